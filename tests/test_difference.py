"""eg.difference, the inverse of eg.integrate: against pinocchio.difference on random trees with every
joint type and on a free flyer carrying a ball and a planar joint; the round trip integrate(q0, u, 1) = q1;
near the identity and near a half turn against mpmath's matrix logarithm at 40 digits and closed forms;
the ZYX free flyer (u = q1 − q0); mimic and fixed joints; bad input."""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import eomgen as eg
import strategies as S
from eomgen.model.urdf import pinocchio_configuration
from eomgen.verify import to_pinocchio

SETTINGS = dict(deadline=None, derandomize=True, database=None, print_blob=True,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def floating() -> eg.System:
    """A free flyer carrying a ball joint, a planar joint and a revolute joint in a chain, and a
    finger that mimics the revolute joint (no coordinate of its own)."""
    system = eg.System()
    system.add_body("base", joint=eg.FreeFlyer("ff"), mass=1)
    system.add_body("b", parent="base", joint=eg.Spherical("ball"), mass=1)
    system.add_body("c", parent="b", joint=eg.Planar("pl"), mass=1)
    system.add_body("d", parent="c", joint=eg.Revolute("r", axis=(0.3, 0.4, 1)), mass=1)
    system.add_body("e", parent="d", joint=eg.Revolute("finger", axis=(0, 1, 0), mimic=("r", -1, 0)), mass=1)
    return system


def assert_same_configuration(system: eg.System, q, ref) -> None:
    """q and ref are the same configuration: Pinocchio's q (a planar angle as cos, sin) with each of q's
    quaternions signed like ref's."""
    q = np.array(q, float)
    for b in system.bodies:
        if b.index is not None and b.joint.group in ("SO3", "SE3"):
            k = b.q_index + 3 * (b.joint.group == "SE3")
            q[k:k + 4] *= np.sign(q[k:k + 4] @ ref[k:k + 4])
    np.testing.assert_allclose(pinocchio_configuration(system, q), pinocchio_configuration(system, ref),
                               atol=1e-12)


def check_against_pinocchio(system: eg.System, q0, q1) -> None:
    model = to_pinocchio(system)
    u = eg.difference(system, q0, q1)
    ref = pin.difference(model, pinocchio_configuration(system, q0), pinocchio_configuration(system, q1))
    np.testing.assert_allclose(u, ref, atol=1e-10, rtol=0)
    assert_same_configuration(system, eg.integrate(system, q0, u, 1.0), q1)


@settings(max_examples=30, **SETTINGS)
@given(S.trees(max_bodies=5, loads=False, frames=0), st.integers(0, 2**32 - 1))
def test_random_trees_equal_pinocchio(tree, seed):
    """Every joint type of the random trees (ball, ZYX, planar, universal, cylindrical, helical, ...)."""
    system = S.eomgen_system(tree)
    rng = np.random.default_rng(seed)
    (q0, _), (q1, _) = S.random_state(tree, rng), S.random_state(tree, rng)
    check_against_pinocchio(system, q0, q1)


def test_floating_base_equals_pinocchio():
    """Free flyer (log6), ball, planar and revolute joints at random pairs of states."""
    system = floating()
    q, _, _ = eg.random_states(system, 40, np.random.default_rng(1))
    for q0, q1 in zip(q[:20], q[20:]):
        check_against_pinocchio(system, q0, q1)


def mp_pose(q, k: int, kind: str):
    """The homogeneous transform of a free flyer (4 × 4) or planar joint (3 × 3) at q[k:], in mpmath."""
    if kind == "planar":
        x, y, t = (mp.mpf(float(v)) for v in q[k:k + 3])
        return mp.matrix([[mp.cos(t), -mp.sin(t), x], [mp.sin(t), mp.cos(t), y], [0, 0, 1]])
    px, py, pz, x, y, z, w = (mp.mpf(float(v)) for v in q[k:k + 7])
    n = mp.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return mp.matrix([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), px],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), py],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), pz],
                      [0, 0, 0, 1]])


def mp_twist(q0, q1, k: int, kind: str) -> np.ndarray:
    """(v, ω) of M0⁻¹ M1 from mpmath's matrix logarithm at 40 digits ((v_x, v_y, ω) in the plane)."""
    with mp.workdps(40):
        L = mp.logm(mp.inverse(mp_pose(q0, k, kind)) * mp_pose(q1, k, kind))
        entries = [(0, 2), (1, 2), (1, 0)] if kind == "planar" else \
            [(0, 3), (1, 3), (2, 3), (2, 1), (0, 2), (1, 0)]
        return np.array([float(mp.re(L[i, j])) for i, j in entries])


def test_near_identity_is_accurate():
    """q1 = q0 ⊕ 1e-9 u: the difference is 1e-9 u to 1e-15, where a log through acos or the trace of
    R0ᵀ R1 loses every digit; the free flyer's and planar joint's twists equal mpmath's logarithm."""
    system = floating()
    q, u, _ = eg.random_states(system, 10, np.random.default_rng(2))
    for q0, uk in zip(q, u):
        q1 = eg.integrate(system, q0, 1e-9 * uk, 1.0)
        d = eg.difference(system, q0, q1)
        np.testing.assert_allclose(d, 1e-9 * uk, atol=2e-15, rtol=0)
        np.testing.assert_allclose(d[:6], mp_twist(q0, q1, 0, "free flyer"), atol=2e-15, rtol=0)
        np.testing.assert_allclose(d[9:12], mp_twist(q0, q1, 11, "planar"), atol=2e-15, rtol=0)


def product(p, q) -> list:
    """The quaternion product p ⊗ q, written out (scalar last)."""
    x0, y0, z0, w0 = p
    x1, y1, z1, w1 = q
    return [w0 * x1 + x0 * w1 + y0 * z1 - z0 * y1, w0 * y1 - x0 * z1 + y0 * w1 + z0 * x1,
            w0 * z1 + x0 * y1 - y0 * x1 + z0 * w1, w0 * w1 - x0 * x1 - y0 * y1 - z0 * z1]


def mp_moved(q0, v, w) -> np.ndarray:
    """p0 + R0 V(ω) v, where the free flyer at q0 goes with the twist (v, ω) in unit time, in mpmath
    (V(ω) = 1 + (1 − cos θ)/θ² [ω]× + (θ − sin θ)/θ³ [ω]×², the exponential's closed form)."""
    with mp.workdps(40):
        T0 = mp_pose(q0, 0, "free flyer")
        w = mp.matrix([mp.mpf(float(x)) for x in w])
        t = mp.norm(w)
        W = mp.matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        V = mp.eye(3) + (1 - mp.cos(t)) / t**2 * W + (t - mp.sin(t)) / t**3 * W * W
        p = T0[0:3, 3] + T0[0:3, 0:3] * V * mp.matrix([mp.mpf(float(x)) for x in v])
        return np.array([float(x) for x in p])


@pytest.mark.parametrize("angle", [np.pi - 1e-6, np.pi - 1e-9, np.pi, np.pi + 1e-7, -np.pi + 1e-8,
                                   9e-3, 1.1e-2])
def test_turns_are_accurate(angle):
    """A turn by θ about a unit axis a, near a half turn and either side of V⁻¹'s switch to its series
    at θ = 1e-2 (closed forms): the ball joint's ω = θ a (the shorter path,
    −(2π − θ) a past π); the free flyer moved by the twist (v, θ a) gives it back (θ ≤ π); the planar
    joint turned by θ has ω = θ (θ − 2π past π) and v = 0."""
    system = floating()
    rng = np.random.default_rng(5)
    q0 = eg.random_states(system, 1, rng)[0][0]
    a = rng.normal(size=3)
    a /= np.linalg.norm(a)
    turn = np.r_[np.sin(angle / 2) * a, np.cos(angle / 2)]
    q1 = q0.copy()
    q1[7:11] = product(q0[7:11], turn)
    q1[13] = q0[13] + angle
    expected = angle if abs(angle) <= np.pi else angle - 2 * np.pi * np.sign(angle)
    d = eg.difference(system, q0, q1)
    np.testing.assert_allclose(d[6:9], expected * a, atol=1e-14, rtol=0)
    np.testing.assert_allclose(d[9:12], [0, 0, expected], atol=1e-15, rtol=0)
    if abs(angle) <= np.pi:
        v = rng.uniform(-1, 1, 3)
        q1[0:3] = mp_moved(q0, v, angle * a)
        q1[3:7] = product(q0[3:7], turn)
        d = eg.difference(system, q0, q1)
        np.testing.assert_allclose(d[:6], np.r_[v, angle * a], atol=1e-14, rtol=0)
    assert_same_configuration(system, eg.integrate(system, q0, d, 1.0), q1)


def test_euler_free_flyer_is_the_coordinate_difference():
    """ZYX free flyer and ZYX ball joint: u = q̇, so u = q1 − q0 and the round trip is exact."""
    system = eg.System()
    system.add_body("base", joint=eg.FreeFlyer("ff", parametrization="euler"), mass=1)
    system.add_body("b", parent="base", joint=eg.Spherical("ball", parametrization="zyx"), mass=1)
    system.add_body("c", parent="b", joint=eg.Fixed("weld"), mass=1)
    q, _, _ = eg.random_states(system, 4, np.random.default_rng(3))
    for q0, q1 in zip(q[:2], q[2:]):
        np.testing.assert_array_equal(eg.difference(system, q0, q1), q1 - q0)
        np.testing.assert_allclose(eg.integrate(system, q0, q1 - q0, 1.0), q1, atol=1e-15)


GOOD = np.r_[np.zeros(6), 1.0, 0.0, 0.0, 0.0, 1.0, np.zeros(4)]  # identity quaternions


@pytest.mark.parametrize("q0, q1, name", [
    (np.zeros(14), GOOD, "q0"),
    (GOOD, np.zeros(16), "q1"),
    (np.tile(GOOD, (2, 1)), GOOD, "q0"),
    ("abc", GOOD, "q0"),
    (GOOD, np.r_[GOOD[:7], np.zeros(8)], "q1"),
    (np.r_[GOOD[:14], np.nan], GOOD, "q0"),
])
def test_bad_input_is_refused(q0, q1, name):
    """Wrong length, a batch, not numbers, zero quaternions, NaN."""
    with pytest.raises(eg.ModelError, match=rf"\b{name}\b"):
        eg.difference(floating(), q0, q1)


def test_not_a_system_is_refused():
    with pytest.raises(eg.ModelError, match="System"):
        eg.difference(None, np.zeros(1), np.zeros(1))
