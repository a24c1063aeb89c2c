"""Floating-base robots: a free-flyer base (Pinocchio's q layout, u = base twist in the base frame)."""
import numpy as np
import pytest

import eomgen as eg
from eomgen.verify import verify

# Every floating-base robot of example-robot-data 6 that Pinocchio loads (cassie ships an SDF only).
FLOATING = ["a1", "anymal", "anymal_c", "anymal_kinova", "b1", "b1_z1", "bolt", "go1", "hector", "hyq", "icub",
            "icub_reduced", "iris", "laikago", "romeo", "simple_humanoid", "simple_humanoid_classical", "solo12",
            "solo8", "talos", "talos_box", "talos_full", "talos_full_box"]


def test_the_list_is_complete():
    assert sorted(FLOATING) == eg.robots.names(floating_base=True)


@pytest.mark.filterwarnings("ignore:body")  # some files carry inertias Pinocchio takes as they are
@pytest.mark.parametrize("name", FLOATING)
def test_recursive_equals_pinocchio(name):
    """M, b, g, foot / hand Jacobians and J̇u at 20 random states with random base orientations and
    twists, relative 1e-10."""
    report = verify(eg.robots.load(name), method="recursive", states=20, seed=3)
    assert report.ok(1e-10), str(report)


@pytest.mark.parametrize("name", ["solo12", "talos"])
def test_projected_newton_euler_equals_pinocchio(name):
    report = verify(eg.robots.load(name), states=20, seed=4)
    assert report.ok(1e-10), str(report)


def test_free_flyer_model_and_errors():
    system = eg.robots.load("solo12")
    assert (system.nq, system.nv) == (19, 18)
    S = np.array(system.S.tolist(), float)
    assert S.shape == (12, 18) and not S[:, :6].any() and (S[:, 6:] == np.eye(12)).all()
    for method in ("lagrange", "free_cut"):
        with pytest.raises(eg.ModelError, match="free-flyer base"):
            eg.derive(system, method=method)
    s = eg.System()
    base = s.add_body("base", joint=eg.Revolute("q0"), mass=1)
    with pytest.raises(eg.ModelError, match="FreeFlyer joint must attach the root body"):
        s.add_body("second", parent=base, joint=eg.FreeFlyer("ff"), mass=1)
