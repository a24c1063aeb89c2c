"""The structural grouping of the inertial parameters (eomgen.identification.grouping) against hand
derivations (a planar 2R arm, a spatial 3R arm) and against Pinocchio's joint-torque regressor: Y = Y_R K at
random states, and the grouped columns that move have the rank of Y (ur5, panda, puma560, stanford)."""
import warnings

import numpy as np
import pytest
import sympy as sp

import eomgen as eg
from eomgen.identification.grouping import group
from eomgen.verify import to_pinocchio

pin = pytest.importorskip("pinocchio")


def regressor(system, states: int = 40, seed: int = 0) -> np.ndarray:
    """Pinocchio's joint-torque regressor of the numeric system, stacked over random states."""
    model = to_pinocchio(system)
    data, rng = model.createData(), np.random.default_rng(seed)
    return np.vstack([pin.computeJointTorqueRegressor(model, data, rng.uniform(-3, 3, model.nq),
                                                      rng.standard_normal(model.nv),
                                                      rng.standard_normal(model.nv)).copy()
                      for _ in range(states)])


def grouped(system, armature: bool = False):
    return group(eg.regressor(system, friction=(), armature=armature))


def base(grouping, Y: np.ndarray, values: dict | None = None):
    """The grouping restricted to the columns that move, after checking Y = Y_R K (K at `values`)."""
    K = np.array(grouping.K.xreplace(values or {}).tolist(), dtype=float)
    Y_R = Y[:, grouping.columns]
    assert np.abs(Y - Y_R @ K).max() < 1e-10 * max(1.0, np.abs(Y).max())
    return grouping.restrict(np.linalg.norm(Y_R, axis=0) > 1e-9 * np.linalg.norm(Y))


def I_O(m, c, I):
    """The inertia about the body origin from the one about the com (parallel axes)."""
    c = sp.Matrix(c)
    return I + m * ((c.T * c)[0] * sp.eye(3) - c * c.T)


def inertia(name):
    xx, xy, xz, yy, yz, zz = sp.symbols(f"{name}xx {name}xy {name}xz {name}yy {name}yz {name}zz")
    return sp.Matrix([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def equal(ours, theirs) -> bool:
    return sp.expand(ours - theirs) == 0


def numeric(system_of, values):
    return system_of(lambda x: sp.sympify(x).xreplace(values))


def planar_2r(v=lambda x: x):
    """Two links turning about parallel z axes, the second at (l1, 0, 0); gravity in the plane."""
    m1, m2, l1, g = sp.symbols("m1 m2 l1 g", positive=True)
    c1, c2 = sp.symbols("c1x c1y c1z"), sp.symbols("c2x c2y c2z")
    s = eg.System(gravity=(0, v(-g), 0), strict=False)
    a = s.add_body("a", joint=eg.Revolute("q1", axis=(0, 0, 1)), mass=v(m1), com=[v(x) for x in c1],
                   inertia=inertia("A").applyfunc(v))
    s.add_body("b", parent=a, joint=eg.Revolute("q2", axis=(0, 0, 1)), mass=v(m2),
               com=[v(x) for x in c2], inertia=inertia("B").applyfunc(v),
               placement=eg.Placement(translation=(v(l1), 0, 0)))
    return s


def spatial_3r(v=lambda x: x):
    """A vertical first axis (z), then two parallel horizontal axes (y), the second link of length l2."""
    m = sp.symbols("m1:4", positive=True)
    d1, l2, g = sp.symbols("d1 l2 g", positive=True)
    c = [sp.symbols(f"c{k}x c{k}y c{k}z") for k in (1, 2, 3)]
    s = eg.System(gravity=(0, 0, v(-g)), strict=False)
    args = [dict(mass=v(m[k]), com=[v(x) for x in c[k]], inertia=inertia("ABC"[k]).applyfunc(v))
            for k in range(3)]
    b1 = s.add_body("one", joint=eg.Revolute("q1", axis=(0, 0, 1)), **args[0])
    b2 = s.add_body("two", parent=b1, joint=eg.Revolute("q2", axis=(0, 1, 0)),
                    placement=eg.Placement(translation=(0, 0, v(d1))), **args[1])
    s.add_body("three", parent=b2, joint=eg.Revolute("q3", axis=(0, 1, 0)),
               placement=eg.Placement(translation=(v(l2), 0, 0)), **args[2])
    return s


VALUES = dict(m1=1.3, m2=0.9, m3=0.7, l1=0.45, l2=0.38, d1=0.3, g=9.81)


def values_for(system) -> dict:
    """Random numbers for every symbol of `system` (physical inertias: diagonal dominant)."""
    rng, out = np.random.default_rng(1), {}
    for x in sorted(system.parameters, key=str):
        name = str(x)
        diagonal = name[-2:] in ("xx", "yy", "zz")
        out[x] = VALUES.get(name, rng.uniform(0.5, 1.0) if diagonal else rng.uniform(-0.1, 0.1))
    return out


def test_planar_2r_grouping_equals_the_hand_derivation():
    """Six base parameters: ZZ1 + m2 l1² (about joint 1), MX1 + m2 l1, MY1, ZZ2, MX2, MY2."""
    symbolic = planar_2r()
    values = values_for(symbolic)
    G = base(grouped(symbolic), regressor(numeric(planar_2r, values)), values)
    m1, m2, l1 = sp.symbols("m1 m2 l1", positive=True)
    (c1x, c1y, c1z), (c2x, c2y, c2z) = sp.symbols("c1x c1y c1z"), sp.symbols("c2x c2y c2z")
    IO1, IO2 = I_O(m1, (c1x, c1y, c1z), inertia("A")), I_O(m2, (c2x, c2y, c2z), inertia("B"))
    hand = {"I_zz_aR": IO1[2, 2] + m2 * l1**2, "mx_aR": m1 * c1x + m2 * l1, "my_a": m1 * c1y,
            "I_zz_b": IO2[2, 2], "mx_b": m2 * c2x, "my_b": m2 * c2y}
    assert sorted(G.names) == sorted(hand)
    for name, expr in zip(G.names, G.expressions):
        assert equal(expr, hand[name]), name
    assert np.linalg.matrix_rank(regressor(numeric(planar_2r, values))) == 6


def test_spatial_3r_grouping_equals_the_hand_derivation():
    """Fifteen: seven of link 3 (Izz − Ixx, Iyy, Ixy, Ixz, Iyz, MZ, MX), seven of link 2 with link 3's
    mass and MY moved in, and ZZ1 with the x inertias of links 2 and 3."""
    symbolic = spatial_3r()
    values = values_for(symbolic)
    Y = regressor(numeric(spatial_3r, values))
    G = base(grouped(symbolic), Y, values)
    m1, m2, m3 = sp.symbols("m1:4", positive=True)
    l2 = sp.Symbol("l2", positive=True)
    c = [sp.symbols(f"c{k}x c{k}y c{k}z") for k in (1, 2, 3)]
    I1, I2, I3 = (I_O(m, ck, inertia(n)) for m, ck, n in zip((m1, m2, m3), c, "ABC"))
    h2, h3 = sp.Matrix(c[1]) * m2, sp.Matrix(c[2]) * m3
    hand = {"I_zz_threeR": I3[2, 2] - I3[0, 0], "I_yy_three": I3[1, 1], "I_xy_three": I3[0, 1],
            "I_xz_three": I3[0, 2], "I_yz_three": I3[1, 2], "mz_three": h3[2], "mx_three": h3[0],
            "I_zz_twoR": I2[2, 2] + m3 * l2**2 - I2[0, 0], "I_yy_twoR": I2[1, 1] + m3 * l2**2,
            "I_xy_twoR": I2[0, 1] - l2 * h3[1], "I_xz_two": I2[0, 2], "I_yz_two": I2[1, 2],
            "mz_two": h2[2], "mx_twoR": h2[0] + m3 * l2,
            "I_zz_oneR": I1[2, 2] + I2[0, 0] + I3[0, 0]}
    assert sorted(G.names) == sorted(hand)
    for name, expr in zip(G.names, G.expressions):
        assert equal(expr, hand[name]), name
    assert np.linalg.matrix_rank(Y) == 15


@pytest.mark.parametrize("name, rank", [("ur5", 36), ("puma560", 36), ("stanford", 33)])
def test_robots_grouping_has_the_numerical_rank(name, rank):
    """The grouped columns that move are as many as the rank of Pinocchio's regressor, and independent
    (the counts are Pinocchio's numerical ranks, computed in the test)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system = eg.robots.load(name)
    Y = regressor(system, states=60)
    G = base(grouped(system), Y)
    assert len(G.names) == np.linalg.matrix_rank(Y) == np.linalg.matrix_rank(Y[:, G.columns])


def test_armatures_of_joints_that_spin_alone_are_grouped_with_their_link_inertia():
    """ur5 with armatures: each joint's column u̇_i at row i joins Y. The first joint turns about a fixed
    vertical axis, so its armature adds to Izz of the first link; the second joint's axis is horizontal,
    perpendicular to the only rotation of its parent, so a·ω₂ = q̇₂ and its armature adds to Iyy of the
    second link: two fewer base parameters than the 36 + 6 columns."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system = eg.robots.load("ur5")
    model = to_pinocchio(system)
    data, rng, rows = model.createData(), np.random.default_rng(2), []
    for _ in range(60):
        ud = rng.standard_normal(model.nv)
        Y = pin.computeJointTorqueRegressor(model, data, rng.uniform(-3, 3, model.nq),
                                            rng.standard_normal(model.nv), ud)
        rows.append(np.hstack([Y, np.diag(ud)]))
    Y = np.vstack(rows)
    G = base(grouped(system, armature=True), Y)
    first, second = [b for b in system.bodies if b.speed_indices][:2]
    assert len(G.names) == np.linalg.matrix_rank(Y) == 36 + 4
    assert {f"I_zz_{first.name}R", f"I_yy_{second.name}R"} <= set(G.names)
    assert not {f"Ia_{first.joint.name}", f"Ia_{second.joint.name}"} & set(G.names)


def test_panda_arm_has_the_43_base_parameters_of_gaz_et_al():
    """The Franka Emika Panda with its fingers locked (the hand on link 7): 43 base inertial parameters
    (Gaz, Cognetti, Oliva, Robuffo Giordano, De Luca, IEEE RA-L 2019), by Pinocchio's regressor's rank and
    by the grouping."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        panda = eg.robots.load("panda")
    fingers = {j.name: 0.0 for j in panda.joints if "finger" in j.name}
    arm = panda.reduced(fingers)
    Y = regressor(arm, states=80)
    G = base(grouped(arm), Y)
    assert len(fingers) == 2 and len(G.names) == np.linalg.matrix_rank(Y) == 43
