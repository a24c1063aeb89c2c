"""The robots of example-robot-data by the names of its loaders (and, for the files that came after
the loaders, pr2, so100, so101, tiago_pro and xarm7, by their file names).

example-robot-data 6 ships only model files (no Python module); they sit in the package's
`cmeel.prefix/share/example-robot-data/robots` folder.

Besides them, the DH robots of `DH_ROBOTS` (puma560, stanford), built from the published tables of
`dh_tables` by `from_dh`."""
from __future__ import annotations

import warnings
from pathlib import Path
from typing import Callable

from ..errors import ModelError
from . import dh_tables
from .dh import DHLink, from_dh
from .system import System
from .urdf import from_urdf

# name: (URDF path under the robots folder, SRDF with rotor parameters or None, floating base)
ROBOTS: dict[str, tuple[str, str | None, bool]] = {
    "a1": ("a1_description/urdf/a1.urdf", None, True),
    "allegro_left_hand": ("allegro_hand_description/urdf/allegro_left_hand.urdf", None, False),
    "allegro_right_hand": ("allegro_hand_description/urdf/allegro_right_hand.urdf", None, False),
    "anymal": ("anymal_b_simple_description/robots/anymal.urdf", None, True),
    "anymal_c": ("anymal_c_simple_description/urdf/anymal.urdf", None, True),
    "anymal_kinova": ("anymal_b_simple_description/robots/anymal-kinova.urdf", None, True),
    "asr_twodof": ("asr_twodof_description/urdf/TwoDofs.urdf", None, False),
    "b1": ("b1_description/urdf/b1.urdf", None, True),
    "b1_z1": ("b1_description/urdf/b1-z1.urdf", None, True),
    "baxter": ("baxter_description/urdf/baxter.urdf", None, False),
    "bolt": ("bolt_description/robots/bolt.urdf", None, True),
    "double_pendulum": ("double_pendulum_description/urdf/double_pendulum.urdf", None, False),
    "double_pendulum_continuous": ("double_pendulum_description/urdf/double_pendulum_continuous.urdf", None, False),
    "double_pendulum_simple": ("double_pendulum_description/urdf/double_pendulum_simple.urdf", None, False),
    "finger_edu": ("finger_edu_description/robots/finger_edu.urdf", None, False),
    "go1": ("go1_description/urdf/go1.urdf", None, True),
    "hector": ("hector_description/robots/quadrotor_base.urdf", None, True),
    "hyq": ("hyq_description/robots/hyq_no_sensors.urdf", None, True),
    "icub": ("icub_description/robots/icub.urdf", None, True),
    "icub_reduced": ("icub_description/robots/icub_reduced.urdf", None, True),
    "iris": ("iris_description/robots/iris_simple.urdf", None, True),
    "kinova": ("kinova_description/robots/kinova.urdf", None, False),
    "laikago": ("laikago_description/urdf/laikago.urdf", None, True),
    "panda": ("panda_description/urdf/panda.urdf", None, False),
    "pr2": ("pr2_description/urdf/pr2.urdf", None, False),
    "romeo": ("romeo_description/urdf/romeo.urdf", None, True),
    "simple_humanoid": ("simple_humanoid_description/urdf/simple_humanoid.urdf", None, True),
    "simple_humanoid_classical": ("simple_humanoid_description/urdf/simple_humanoid_classical.urdf", None, True),
    "so100": ("so_arm_description/urdf/so100.urdf", None, False),
    "so101": ("so_arm_description/urdf/so101.urdf", None, False),
    "solo8": ("solo_description/robots/solo.urdf", None, True),
    "solo12": ("solo_description/robots/solo12.urdf", None, True),
    "talos": ("talos_data/robots/talos_reduced.urdf", "talos_data/srdf/talos.srdf", True),
    "talos_arm": ("talos_data/robots/talos_left_arm.urdf", "talos_data/srdf/talos.srdf", False),
    "talos_box": ("talos_data/robots/talos_reduced_box.urdf", "talos_data/srdf/talos.srdf", True),
    "talos_full": ("talos_data/robots/talos_full_v2.urdf", "talos_data/srdf/talos.srdf", True),
    "talos_full_box": ("talos_data/robots/talos_full_v2_box.urdf", "talos_data/srdf/talos.srdf", True),
    "tiago": ("tiago_description/robots/tiago.urdf", None, False),
    "tiago_dual": ("tiago_description/robots/tiago_dual.urdf", None, False),
    "tiago_no_hand": ("tiago_description/robots/tiago_no_hand.urdf", None, False),
    "tiago_pro": ("tiago_pro_description/robots/tiago_pro.urdf", None, False),
    "ur3": ("ur_description/urdf/ur3_robot.urdf", None, False),
    "ur3_gripper": ("ur_description/urdf/ur3_gripper.urdf", None, False),
    "ur3_limited": ("ur_description/urdf/ur3_joint_limited_robot.urdf", None, False),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, False),
    "ur5_gripper": ("ur_description/urdf/ur5_gripper.urdf", None, False),
    "ur5_limited": ("ur_description/urdf/ur5_joint_limited_robot.urdf", None, False),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", None, False),
    "ur10_limited": ("ur_description/urdf/ur10_joint_limited_robot.urdf", None, False),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None, False),
    "z1": ("z1_description/urdf/z1.urdf", None, False),
}

# name: its DH table (standard convention), built by from_dh
DH_ROBOTS: dict[str, Callable[[], list[DHLink]]] = {"puma560": dh_tables.puma560,
                                                     "stanford": dh_tables.stanford}


def robots_folder() -> Path:
    """Where example-robot-data keeps its model files."""
    from importlib.metadata import PackageNotFoundError, distribution

    try:
        folder = Path(distribution("example-robot-data").locate_file(
            "cmeel.prefix/share/example-robot-data/robots"))
    except PackageNotFoundError:
        raise ModelError("example-robot-data is not installed (pip install example-robot-data)") from None
    if not folder.is_dir():
        raise ModelError(f"example-robot-data has no robots folder at {folder}")
    return folder


def names(floating_base: bool | None = None) -> list[str]:
    """The names of example-robot-data's robots (optionally only the fixed-base or floating-base ones);
    the DH robots are the keys of `DH_ROBOTS`."""
    return sorted(n for n, (_, _, fb) in ROBOTS.items() if floating_base is None or fb == floating_base)


def paths(name: str) -> tuple[Path, Path | None, bool]:
    """(URDF, SRDF or None, floating base) of a robot."""
    if name not in ROBOTS:
        raise ModelError(f"unknown robot {name!r}; robots are {', '.join(names())}, and the DH robots "
                         f"{', '.join(DH_ROBOTS)}")
    urdf, srdf, floating = ROBOTS[name]
    folder = robots_folder()
    return folder / urdf, (folder / srdf if srdf else None), floating


def load(name: str, base: str = "quaternion", mimic: str = "independent") -> System:
    """A robot of example-robot-data as a `System` (armature from its SRDF where it has rotor
    parameters, as example-robot-data's own loader sets it); a floating base in `base`
    parametrization ("quaternion" or "euler"). Mimic joints (panda's second finger, pr2's and
    tiago_pro's grippers, say) are independent joints, as in example-robot-data's own loader, with a
    warning naming them; mimic="mimic" makes them follow their drivers (see `from_urdf`).

    A DH robot ("puma560", "stanford") is built from its table with `from_dh`; its published inertias
    that break the triangle inequality (see `dh_tables`) are taken as they are, without a warning."""
    if name in DH_ROBOTS:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=".*triangle inequality")
            system = from_dh(DH_ROBOTS[name](), strict=False)
        system.name = name
        return system
    urdf, srdf, floating = paths(name)
    system = from_urdf(urdf, floating_base=floating and base, srdf=srdf, mimic=mimic)
    system.name = name
    return system
