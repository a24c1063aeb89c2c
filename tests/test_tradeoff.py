"""The speed-accuracy table: each variant's error is what its approximation implies."""
import json

import eomgen as eg
from eomgen.__main__ import main


def test_tradeoff_ur5(tmp_path):
    variants = {v.name.split(":")[0].split(" below")[0]: v
                for v in eg.tradeoff(eg.robots.load("ur5"), states=50, levels=("closed", "cse"))}
    full = variants["full model (recursive, float64)"]
    assert full.errors["M"][0] == 0 and full.ops < variants["projected Newton-Euler code"].ops
    assert max(variants["projected Newton-Euler code"].errors[k][0] for k in ("M", "b", "g")) < 1e-13
    assert 1e-9 < variants["float32"].errors["M"][0] < 1e-5  # single precision: ~1e-7
    coriolis = variants["Coriolis and centrifugal neglected"]
    assert coriolis.errors["b"][0] == 1.0 and coriolis.errors["M"][0] == 0 and coriolis.errors["ud"][0] > 1e-3
    locked = variants["joints locked"]
    assert max(locked.errors[k][0] for k in ("M", "b", "g")) < 1e-13 and locked.errors["ud"][0] > 1e-6
    assert variants["links as point masses"].errors["M"][0] > 1e-3
    closed, cse = variants["closed forms, nothing shared"], variants["closed forms + CSE"]
    assert max(max(v.errors[k][0] for k in ("M", "b", "g")) for v in (closed, cse)) < 1e-13  # exact rewrites
    assert closed.ops > 50 * full.ops and full.ops < cse.ops < 2 * full.ops
    png, table = tmp_path / "pareto.png", tmp_path / "table.json"
    assert main(["tradeoff", "ur5", "--states", "20", "--levels", "cse", "--png", str(png), "--json", str(table)]) == 0
    assert png.stat().st_size > 10_000 and len(json.loads(table.read_text())) == 9


def test_trigonometric_simplification_level():
    """The double pendulum: trigsimp of every closed-form entry, then CSE, gives the same numbers
    and fewer operations than the closed forms; unknown levels are an error."""
    import pytest

    from eomgen.simplification import simplified
    from models import double_pendulum

    system = double_pendulum(numeric=True)
    variants = {v.name: v for v in eg.tradeoff(system, states=30, trig_max_ops=10_000)}
    trig = variants["trigsimp (8/8 entries) + CSE"]  # M (4), b (2), g (2)
    assert max(trig.errors[k][0] for k in ("M", "b", "g", "ud")) < 1e-13
    assert trig.ops < variants["closed forms, nothing shared"].ops and trig.ops < variants["full model (recursive, float64)"].ops
    with pytest.raises(eg.ModelError, match="unknown simplification level 'full'"):
        simplified(eg.derive(system), "full")


def test_tradeoff_of_a_flexible_arm_has_its_modes_and_stiffening_rows():
    """A flexible link (one element) carrying a rigid link: "no stiffening" differs from the full model
    where the link bends; its modal reductions are exact projections (M, b, g = Tᵀ M T, Tᵀ b, Tᵀ g), one mode
    changes the accelerations, and both modes are the full model in other coordinates (u̇ equal to
    round-off); the locked hand's rows are the full model's."""
    import numpy as np

    arm = eg.System(gravity=(0, -9.81, 0))
    link = arm.add_body("link", joint=eg.FlexibleLink("q1", length=1.0, mass_per_length=2.0, EI=20.0,
                                                       elements=1), mass=0)
    arm.add_body("hand", parent=link, joint=eg.Revolute("q2"), mass=0.5, com=(0.2, 0, 0),
                 inertia=np.diag([0.001, 0.002, 0.003]).tolist())
    variants = {v.name: v for v in eg.tradeoff(arm, states=20, levels=(), modes=(1, 2))}
    assert variants["full model (lagrange, float64)"].errors["ud"][0] < 1e-12
    assert variants["no stiffening"].errors["ud"][0] > 1e-4
    errors = [variants[name].errors for name in ("1 mode of each field", "2 modes of each field")]
    assert max(e[key][0] for e in errors for key in ("M", "b", "g")) < 1e-12
    assert errors[0]["ud"][0] > 1e-6 > 1e-10 > errors[1]["ud"][0]
    locked = variants["joints locked: q2"]
    assert max(locked.errors[k][0] for k in ("M", "b", "g")) < 1e-13 and locked.errors["ud"][0] > 1e-6


def test_tradeoff_locks_a_joint_of_a_floating_robot_and_keeps_a_modal_link():
    """A free-flying base (7 coordinates, 6 speeds) with a locked arm joint: the locked row indexes q and u
    apart, its M, b, g rows equal the full model's; a link already modal gets no further modal rows."""
    import numpy as np

    s = eg.System(gravity=(0, 0, -9.81))
    base = s.add_body("base", joint=eg.FreeFlyer("base"), mass=2.0, inertia=np.diag([0.1, 0.2, 0.3]).tolist())
    a = s.add_body("a", parent=base, joint=eg.Revolute("qa"), mass=1.0, com=(0.3, 0, 0),
                   inertia=np.diag([0.01, 0.02, 0.03]).tolist())
    s.add_body("b", parent=a, joint=eg.Revolute("qb", axis=(0, 1, 0)), mass=0.5, com=(0.2, 0, 0.1),
               inertia=np.diag([0.01, 0.02, 0.03]).tolist(), placement=eg.Placement(translation=(0.5, 0, 0)))
    locked = {v.name: v for v in eg.tradeoff(s, states=5, levels=(), lock={"qa": 0.3})}["joints locked: qa"]
    assert max(locked.errors[k][0] for k in ("M", "b", "g")) < 1e-13 and locked.errors["ud"][0] > 1e-6
    modal = eg.System(gravity=(0, -9.81, 0))
    modal.add_body("link", joint=eg.FlexibleLink("q1", length=1.0, mass_per_length=2.0, EI=20.0, elements=1,
                                                  modes=1), mass=0)
    names = [v.name for v in eg.tradeoff(modal, states=5, levels=(), modes=(1, 2))]
    assert "no stiffening" in names and not any(name.endswith("of each field") for name in names)
