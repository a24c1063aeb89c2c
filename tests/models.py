"""Systems the tests share, built the way a user would build them."""
from __future__ import annotations

import numpy as np
import sympy as sp

import eomgen as eg


def trig_zero(expr, q) -> bool:
    """True if expr ≡ 0 as a polynomial identity in sin q_i, cos q_i and the parameters, using only
    sin² + cos² = 1 (a normal form: sin q_i appears with degree ≤ 1 after the substitution)."""
    expr = sp.sympify(expr)
    c = {qi: sp.Symbol(f"_c{i}") for i, qi in enumerate(q)}
    s = {qi: sp.Symbol(f"_s{i}") for i, qi in enumerate(q)}
    expr = expr.xreplace({sp.cos(qi): c[qi] for qi in q}).xreplace({sp.sin(qi): s[qi] for qi in q})
    expr = sp.expand(expr)
    for qi in q:
        si, ci = s[qi], c[qi]
        expr = sp.expand(expr.replace(lambda e: e.is_Pow and e.base == si and e.exp.is_Integer and e.exp > 1,
                                      lambda e: si ** (e.exp % 2) * (1 - ci**2) ** (e.exp // 2)))
    return expr == 0


def matrices_trig_equal(A, B, q) -> bool:
    return all(trig_zero(a - b, q) for a, b in zip(A, B))


def assert_methods_agree(system, method: str, reference: str = "projected_newton_euler") -> None:
    """M, b, g of two derivations are identical as trigonometric polynomials."""
    a, b = eg.derive(system, method=reference), eg.derive(system, method=method)
    for name in ("M", "b", "g"):
        assert matrices_trig_equal(getattr(a, name), getattr(b, name), list(system.q)), f"{name}: {method}"


def cart_pendulum():
    m_c, m_p, l, g = sp.symbols("m_c m_p l g", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    cart = system.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=m_c)
    pend = system.add_body("pendulum", parent=cart, joint=eg.Revolute("phi", axis=(0, 0, 1)),
                           mass=m_p, com=(0, -l, 0))
    system.add_frame("tip", body=pend, placement=eg.Placement(translation=(0, -l, 0)))
    return system, (m_c, m_p, l, g)


def planar_arm(n: int) -> eg.System:
    """n links turning about z, link i of length l_i, centre of mass at l_ci, inertia I_i about z."""
    g = sp.Symbol("g", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    parent, length = None, 0
    for i in range(1, n + 1):
        m, l, lc, inertia = sp.symbols(f"m_{i} l_{i} l_c{i} I_{i}", positive=True)
        parent = system.add_body(f"link{i}", parent=parent, joint=eg.Revolute(f"q_{i}", axis=(0, 0, 1)),
                                 mass=m, com=(lc, 0, 0), inertia=sp.diag(0, 0, inertia),
                                 placement=eg.Placement(translation=(length, 0, 0)))
        length = l
    return system


def double_pendulum(numeric: bool = False):
    """Planar double pendulum, physical rods: com at the middle, inertia about z."""
    if numeric:
        m1, m2, l1, l2, I1, I2, g = 1.3, 0.7, 0.9, 0.6, 0.08, 0.03, 9.81
    else:
        m1, m2, l1, l2, I1, I2, g = sp.symbols("m1 m2 l1 l2 I1 I2 g", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    a = system.add_body("upper", joint=eg.Revolute("q_1", axis=(0, 0, 1)), mass=m1,
                        com=(l1 / 2, 0, 0), inertia=sp.diag(0, I1, I1))
    b = system.add_body("lower", parent=a, joint=eg.Revolute("q_2", axis=(0, 0, 1)), mass=m2,
                        com=(l2 / 2, 0, 0), inertia=sp.diag(0, I2, I2),
                        placement=eg.Placement(translation=(l1, 0, 0)))
    system.add_frame("tip", body=b, placement=eg.Placement(translation=(l2, 0, 0)))
    return system


def symbolic_inertia(tag: str) -> sp.Matrix:
    xx, yy, zz, xy, xz, yz = sp.symbols(f"I{tag}_xx I{tag}_yy I{tag}_zz I{tag}_xy I{tag}_xz I{tag}_yz")
    return sp.Matrix([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def spatial_arm_3dof():
    """Revolute on a skew axis, prismatic on a skew axis, revolute about x; offset and rotated
    placements; full symbolic inertia tensors and com offsets."""
    g = sp.Symbol("g")
    system = eg.System(gravity=(0, 0, -g))
    R_tilt = sp.Matrix([[1, 0, 0], [0, 0, -1], [0, 1, 0]])  # 90° about x
    b1 = system.add_body("link1", joint=eg.Revolute("q_1", axis=(1, 1, 0)), mass=sp.Symbol("m1"),
                         com=sp.symbols("c1x c1y c1z"), inertia=symbolic_inertia("1"))
    b2 = system.add_body("link2", parent=b1, joint=eg.Prismatic("q_2", axis=(0, 1, 1)), mass=sp.Symbol("m2"),
                         com=sp.symbols("c2x c2y c2z"), inertia=symbolic_inertia("2"),
                         placement=eg.Placement(rotation=R_tilt, translation=(sp.Symbol("a1"), 0, sp.Symbol("d1"))))
    system.add_body("link3", parent=b2, joint=eg.Revolute("q_3", axis=(1, 0, 0)), mass=sp.Symbol("m3"),
                    com=sp.symbols("c3x c3y c3z"), inertia=symbolic_inertia("3"),
                    placement=eg.Placement(translation=(0, sp.Symbol("a2"), 0)))
    return system


def random_rotation(rng) -> np.ndarray:
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q @ np.diag(np.sign(np.diag(R)))
    return Q if np.linalg.det(Q) > 0 else -Q


def random_inertia(rng) -> np.ndarray:
    """A physical inertia: principal moments from a random solid box, randomly rotated."""
    a, b, c = rng.uniform(0.05, 0.5, size=3)
    m = rng.uniform(0.5, 3.0)
    D = np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * m / 12
    R = random_rotation(rng)
    return R @ D @ R.T


# joint kinds of the numeric arm: (eomgen joint class, axis)
ARM6 = [(eg.Revolute, (0, 0, 1)), (eg.Revolute, (0, 1, 0)), (eg.Prismatic, (1, 0, 0)),
        (eg.Revolute, (0.3, -0.5, 0.8)), (eg.Revolute, (1, 0, 0)), (eg.Prismatic, (0.2, 0.9, -0.4))]


def numeric_arm(rng, joints=ARM6, branch_at: int | None = None):
    """A numeric spatial arm with random placements, masses, coms and inertias; returns the system and
    the raw numbers (for building the same robot in Pinocchio). With branch_at, the last joint hangs
    from body `branch_at` instead of the previous one (a tree)."""
    system = eg.System(gravity=(0, 0, -9.81))
    spec, parent = [], None
    for i, (kind, axis) in enumerate(joints):
        if branch_at is not None and i == len(joints) - 1:
            parent = system.bodies[branch_at]
        R = random_rotation(rng)
        p = rng.uniform(-0.4, 0.4, size=3)
        m = rng.uniform(0.5, 3.0)
        c = rng.uniform(-0.2, 0.2, size=3)
        I = random_inertia(rng)
        parent = system.add_body(f"link{i}", parent=parent, joint=kind(f"q_{i}", axis=axis), mass=m,
                                 com=tuple(c), inertia=I.tolist(),
                                 placement=eg.Placement(rotation=R.tolist(), translation=tuple(p)))
        spec.append(dict(kind=kind, axis=np.array(axis, float) / np.linalg.norm(axis), R=R, p=p, m=m, c=c, I=I,
                         parent=system.bodies.index(parent.parent) if parent.parent else -1))
    return system, spec


def close(actual, expected, rtol: float, what: str) -> None:
    """|actual − expected| ≤ rtol · max(1, max |expected|) (relative to the size of the array), finite."""
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    assert np.all(np.isfinite(actual)), f"{what}: not finite: {actual}"
    atol = rtol * max(1.0, np.abs(expected).max())
    np.testing.assert_allclose(actual, expected, rtol=0, atol=atol, err_msg=what)


# every joint type but the free flyer, for a chain of three bodies (`joint_chain`)
JOINTS = {
    "helical": lambda: eg.Helical("h", axis=(0, 1, 0), pitch=0.2),
    "universal": lambda: eg.Universal("uj", axis1=(1, 0, 0), axis2=(0, 0, 1)),
    "cylindrical": lambda: eg.Cylindrical("c", axis=(0, 1, 1)),
    "translation": lambda: eg.Translation("t"),
    "spherical_zyx": lambda: eg.Spherical("s", "zyx"),
    "spherical_quaternion": lambda: eg.Spherical("s"),
    "planar": lambda: eg.Planar("p"),
    "mimic": lambda: eg.Revolute("r1", axis=(1, 0, 0), mimic=("r0", -1.5, 0.3)),
}


def joint_chain(joint) -> eg.System:
    """Three bodies: a revolute about z at the root, `joint` off its axis and turned, a revolute about x."""
    s = eg.System(gravity=(0, 0, -9.81))
    a = s.add_body("a", joint=eg.Revolute("r0", axis=(0, 0, 1)), mass=0.9, com=(0.1, 0, 0.05),
                   inertia=sp.diag(0.02, 0.03, 0.04))
    b = s.add_body("b", parent=a, joint=joint, mass=1.3, com=(0.1, 0.2, -0.3),
                   inertia=sp.Matrix([[0.3, 0.01, 0.02], [0.01, 0.4, 0.03], [0.02, 0.03, 0.5]]),
                   placement=eg.Placement(rotation=sp.Matrix([[1, 0, 0], [0, 0, -1], [0, 1, 0]]),
                                          translation=(0.3, 0.1, 0.2)))
    s.add_body("c", parent=b, joint=eg.Revolute("r2", axis=(1, 0, 0)), mass=0.7, com=(0.2, 0, 0.1),
               inertia=sp.diag(0.1, 0.2, 0.15), placement=eg.Placement(translation=(0.3, -0.1, 0.2)))
    return s


def two_link_closed_form(q, u, m1, m2, l1, lc1, lc2, I1, I2, g):
    """M, C q̇ and G of the two-link arm of the bond-graph paper (angles from the horizontal, links along
    their x axes, I_i about the com and the joint axis z), as the paper writes them."""
    (q1, q2), (qd1, qd2) = q, u
    M11 = I1 + I2 + m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * sp.cos(q2))
    M12 = I2 + m2 * (lc2**2 + l1 * lc2 * sp.cos(q2))
    M = sp.Matrix([[M11, M12], [M12, I2 + m2 * lc2**2]])
    h = -m2 * l1 * lc2 * sp.sin(q2)
    Cqd = sp.Matrix([h * qd2 * (2 * qd1 + qd2), -h * qd1**2])
    G = sp.Matrix([(m1 * lc1 + m2 * l1) * g * sp.cos(q1) + m2 * lc2 * g * sp.cos(q1 + q2),
                   m2 * lc2 * g * sp.cos(q1 + q2)])
    return M, Cqd, G
