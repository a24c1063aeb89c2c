"""Identification (eomgen.identification) on Pinocchio's regressor `computeJointTorqueRegressor` (independent
of eomgen's), with armature and friction columns added here:
τ_j += I_a,j u̇_j + f_v,j u_j + f_c,j sign(u_j) + f_o,j.

The 2-link arm turns about y (parallel axes), links along x, gravity −z: a planar arm in a vertical
plane. Its base parameters by hand (Khalil's regrouping, inertia about each joint's origin, c = cos, s = sin):
link 1 turns about a fixed axis, so its only inertia in τ is I_yy,1 (τ₁ only, ∝ u̇₁) and its first moments
mc_x,1, mc_z,1 through gravity; link 2's mass regroups into link 1 (m₂ a₁² into I_yy,1, m₂ a₁ into mc_x,1);
link 2 keeps I_yy,2, mc_x,2, mc_z,2. So 6 inertial base parameters: I_yy,1 + m₂a₁², mc_x,1 + a₁m₂, mc_z,1,
I_yy,2, mc_x,2, mc_z,2. Joint 1's armature enters exactly as I_yy,1 does (u̇₁ in τ₁): it regroups too;
joint 2's does not (I_yy,2 enters τ₁ as well); friction adds 3 per joint: 6 + 1 + 6 = 13."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import assume, given, settings
from strategies import PinocchioTree, trees

from eomgen.errors import ModelError
from eomgen.identification import (base_parameters, condition, excite, identify, identify_consistent,
                                   random_fourier, smallest_eigenvalues)

PINOCCHIO = ["m", "mc_x", "mc_y", "mc_z", "I_xx", "I_xy", "I_yy", "I_xz", "I_yz", "I_zz"]
FRICTION = ["viscous", "coulomb", "offset"]
A1 = 0.5


def link(name: str, mass: float, com: float, inertia: float) -> str:
    return (f'<link name="{name}"><inertial><origin xyz="{com} 0 0.01"/><mass value="{mass}"/>'
            f'<inertia ixx="{inertia}" ixy="0" ixz="0" iyy="{inertia}" iyz="0" izz="{inertia}"/>'
            '</inertial></link>')


def joint(name: str, parent: str, child: str, x: float) -> str:
    return (f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{x} 0 0"/><axis xyz="0 1 0"/>'
            '<limit lower="-3" upper="3" effort="100" velocity="5"/>'
            '</joint>')


def arm_urdf(mass2: float = 1.0, inertia2: float = 0.02) -> str:
    """The 2-link arm of the module's text."""
    return ('<robot name="arm"><link name="base"/>' + link("l1", 2.0, 0.25, 0.05)
            + link("l2", mass2, 0.2, inertia2)
            + joint("j1", "base", "l1", 0.0) + joint("j2", "l1", "l2", A1) + "</robot>")


def arm(mass2: float = 1.0, inertia2: float = 0.02) -> pin.Model:
    """The 2-link arm, Pinocchio's model of its URDF."""
    return pin.buildModelFromXML(arm_urdf(mass2, inertia2))


def arm_inverse_dynamics(tmp_path):
    """τ(q, u, u̇) of the 2-link arm's URDF by eomgen (its model, derivation and generated code)."""
    import eomgen as eg

    path = tmp_path / "arm.urdf"
    path.write_text(arm_urdf())
    return eg.codegen(eg.derive(eg.from_urdf(path))).inverse_dynamics


def ur5() -> pin.Model:
    import eomgen as eg

    return pin.buildModelFromUrdf(str(eg.model.robots.paths("ur5")[0]))


class Setup:
    """Pinocchio's regressor with armature and friction columns, the names, the true π and τ = Y π."""

    def __init__(self, model: pin.Model, friction: bool = True, rigid=None):
        self.model, self.data, self.friction = model, model.createData(), friction
        self.rigid = rigid or (lambda q, u, ud: np.array([pin.rnea(model, self.data, *x)
                                                          for x in zip(q, u, ud)]))
        nb, nv = model.nbodies - 1, model.nv
        self.names = [f"{p}_{k}" for k in range(1, nb + 1) for p in PINOCCHIO]
        if friction:
            self.names += [f"armature_{j}" for j in range(1, nv + 1)]
            self.names += [f"{f}_{j}" for j in range(1, nv + 1) for f in FRICTION]
        extra = [0.01 * (j + 1) for j in range(nv)] + [v for j in range(nv) for v in (0.2, 0.5, -0.1)]
        self.pi = np.concatenate([model.inertias[k].toDynamicParameters() for k in range(1, nb + 1)]
                                 + [extra if friction else []])

    def __call__(self, q, u, ud) -> np.ndarray:
        Y = pin.computeJointTorqueRegressor(self.model, self.data, q, u, ud).copy()
        if not self.friction:
            return Y
        F = np.zeros((len(u), 3 * len(u)))
        for j in range(len(u)):
            F[j, 3 * j: 3 * j + 3] = u[j], np.sign(u[j]), 1.0
        return np.hstack([Y, np.diag(ud), F])

    def states(self, rng, n: int):
        nv = self.model.nv
        return rng.uniform(-3, 3, (n, nv)), rng.uniform(-2, 2, (n, nv)), rng.uniform(-4, 4, (n, nv))

    def torques(self, q, u, ud) -> np.ndarray:
        """τ from inverse dynamics (by default Pinocchio's rnea; no regressor) plus armature and friction."""
        nv = self.model.nv
        tau = self.rigid(q, u, ud)
        if self.friction:
            a, f = self.pi[-4 * nv: -3 * nv], self.pi[-3 * nv:].reshape(nv, 3)
            tau += a * ud + f[:, 0] * u + f[:, 1] * np.sign(u) + f[:, 2]
        return tau


def stacked(setup: Setup, q, u, ud) -> np.ndarray:
    return np.concatenate([setup(*x) for x in zip(q, u, ud)])


def svd_rank(W: np.ndarray) -> int | None:
    """The numerical rank from the singular values of the column-normalised W (columns of rounding
    errors, norm below 1e-12 of the largest, zero), at a clear gap; None where a singular value or a
    column's norm (relative) lies in (1e-12, 1e-9], where base_parameters' tolerance decides."""
    norms = np.linalg.norm(W, axis=0)
    relative = norms / norms.max()
    if np.any((relative > 1e-12) & (relative <= 1e-9)):
        return None  # a column that barely acts: not acting for base_parameters (its documented rule)
    norms[relative < 1e-12] = np.inf
    s = np.linalg.svd(W / norms, compute_uv=False)
    s = s / s[0]
    rank = int(np.sum(s > 1e-9))
    return rank if rank == len(s) or s[rank] < 1e-12 else None  # None: a singular value in (1e-12, 1e-9]


@pytest.mark.parametrize("friction", [False, True])
def test_the_base_parameters_of_the_two_link_arm_are_the_hand_derived(friction):
    setup = Setup(arm(), friction)
    rng = np.random.default_rng(1)
    base = base_parameters(setup, *setup.states(rng, 60))
    assert base.rank == (13 if friction else 6) == svd_rank(stacked(setup, *setup.states(rng, 60)))
    # the hand derivation's combinations: link 2's I_yy, mc_x, mc_z stand alone (nothing regroups into them)
    for name in ("I_yy_2", "mc_x_2", "mc_z_2"):
        assert name in base.names
        row = base.map[base.names.index(name)]
        assert np.count_nonzero(np.abs(row) > 1e-9) == 1
    # m₂ regroups with a₁ into mc_x,1 and a₁² into I_yy,1 (whichever column the QR kept of each group)
    m2 = setup.names.index("m_2")
    assert sorted(np.round(base.map[np.abs(base.map[:, m2]) > 1e-9, m2], 9)) == [A1**2, A1]


@pytest.mark.parametrize("model, states", [(arm, 60), (ur5, 40)])
def test_the_rank_is_the_numerical_rank_and_the_base_regressor_reproduces_y_pi(model, states):
    setup = Setup(model())
    rng = np.random.default_rng(2)
    base = base_parameters(setup, *setup.states(rng, states))
    q, u, ud = setup.states(rng, 20)  # fresh states
    W = stacked(setup, q, u, ud)
    assert base.rank == svd_rank(np.concatenate([W, stacked(setup, *setup.states(rng, states))]))
    for pi in (setup.pi, rng.normal(size=len(setup.names))):
        assert np.allclose(base.regressor(W) @ base.of(pi), W @ pi, rtol=0, atol=1e-10 * np.abs(W @ pi).max())
    assert len(base.combinations()) == base.rank and base.tolerance > 0


@pytest.mark.parametrize("robot", ["ur5", "arm"])
def test_noiseless_data_give_the_base_parameters_exactly(robot, tmp_path):
    """ur5's τ by Pinocchio's rnea, the 2-link arm's by eomgen's generated inverse dynamics."""
    setup = Setup(ur5()) if robot == "ur5" else Setup(arm(), rigid=arm_inverse_dynamics(tmp_path))
    rng = np.random.default_rng(3)
    q, u, ud = setup.states(rng, 80)
    result = identify(setup, q, u, ud, setup.torques(q, u, ud))
    truth = result.base.of(setup.pi)
    assert np.allclose(result.beta, truth, rtol=0, atol=1e-8 * max(1, np.abs(truth).max()))
    assert result.rms.max() < 1e-9 and np.isfinite(result.condition)


def test_noisy_estimates_lie_within_their_standard_deviations_and_predict_held_out_torques():
    setup = Setup(arm())
    rng = np.random.default_rng(4)
    noise = np.array([0.3, 0.05])  # per joint: Gautier's weights matter
    base = base_parameters(setup, *setup.states(rng, 60))
    truth = base.of(setup.pi)
    errors = []
    for _ in range(20):
        q, u, ud = setup.states(rng, 100)
        tau = setup.torques(q, u, ud) + rng.normal(size=(100, 2)) * noise
        result = identify(setup, q, u, ud, tau, base=base)
        errors.append((result.beta - truth) / result.std)
        assert np.allclose(result.rms, noise, rtol=0.3)
        q, u, ud = setup.states(rng, 50)  # held out
        error = result.predict(q, u, ud) - setup.torques(q, u, ud)
        assert (np.sqrt((error**2).mean(axis=0)) < 0.5 * noise).all()
    z = np.abs(np.concatenate(errors))  # 20 × 13 standardised errors: N(0, 1) if the std is right
    assert (z < 3).mean() > 0.97 and 0.55 < (z < 1).mean() < 0.8


def test_the_consistent_variant_is_realisable_where_least_squares_is_not():
    """Link 2 light and small (I_yy,2 about its joint: 3e-4 + 0.02·(0.2² + 0.01²)) under noisy torques:
    least squares gives I_yy,2 < 0, which no body has (∫ (x² + z²) dm ≥ 0); I_yy,2 is a base parameter
    alone (the hand derivation), so no physical π has least squares' β."""
    setup = Setup(arm(mass2=0.02, inertia2=3e-4))
    rng = np.random.default_rng(5)
    q, u, ud = setup.states(rng, 15)
    tau = setup.torques(q, u, ud) + rng.normal(size=(15, 2)) * 0.05
    plain = identify(setup, q, u, ud, tau)
    k = plain.base.names.index("I_yy_2")
    assert np.count_nonzero(np.abs(plain.base.map[k]) > 1e-9) == 1 and plain.beta[k] < 0
    nonnegative = [n for n in setup.names if n.split("_")[0] in ("armature", "viscous", "coulomb")]
    result = identify_consistent(setup, q, u, ud, tau, bodies=2, nonnegative=nonnegative)
    J = [np.linalg.eigvalsh(_pseudo_inertia(result.pi[10 * b: 10 * b + 10]))[0] for b in range(2)]
    assert min(J) > -1e-7 and np.allclose(J, result.eigenvalues) and result.beta[k] > -1e-9
    assert all(result.pi[setup.names.index(n)] > -1e-7 for n in nonnegative)
    assert np.allclose(result.beta, result.base.of(result.pi))
    assert (result.rms < 3 * 0.05).all()  # still fits the data, to about the noise
    assert smallest_eigenvalues(setup.pi, 2).min() > 0  # the true arm is realisable


def _pseudo_inertia(p: np.ndarray) -> np.ndarray:
    """J = ∫ [x; 1][x; 1]ᵀ dm from the ten parameters, written out (Wensing et al. 2017, eq. 6)."""
    m, h, (xx, xy, yy, xz, yz, zz) = p[0], p[1:4], p[4:]
    inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    Sigma = 0.5 * np.trace(inertia) * np.eye(3) - inertia
    return np.block([[Sigma, h[:, None]], [h[None, :], np.array([[m]])]])


def test_the_excitation_trajectory_improves_the_condition_number_within_the_limits():
    model = arm()
    setup = Setup(model)
    lower, upper, velocity = model.lowerPositionLimit, model.upperPositionLimit, model.velocityLimit
    rng = np.random.default_rng(6)
    result = excite(setup, lower, upper, velocity, harmonics=3, samples=30, restarts=2,
                    iterations=10, time_limit=60, rng=rng)
    starts = [random_fourier(rng, lower, upper, velocity, 3, 2 * np.pi / 10, result.times) for _ in range(10)]
    randoms = [np.linalg.cond(stacked(setup, *f(result.times))[:, list(result.base.columns)]) for f in starts]
    assert result.condition < min(randoms) and result.condition < 0.7 * np.median(randoms)
    assert result.condition < result.start
    W = stacked(setup, result.q, result.u, result.ud)[:, list(result.base.columns)]
    assert np.isclose(np.linalg.cond(W), result.condition, rtol=1e-6)
    assert np.isclose(condition(setup, result.base, result.q, result.u, result.ud), result.condition)
    assert (result.q >= lower - 1e-9).all() and (result.q <= upper + 1e-9).all()
    assert (np.abs(result.u) <= velocity + 1e-9).all()
    q, u, ud = result.fourier(result.times + result.fourier.period)  # periodic
    assert np.allclose(q, result.q) and np.allclose(ud, result.ud)


def test_an_unclear_rank_gap_is_warned():
    """Columns q₀ and q₀ + 10⁻⁸ q₁: independent, but barely above the tolerance (10⁻⁹)."""
    rng = np.random.default_rng(10)
    q, u = rng.normal(size=(40, 2)), rng.normal(size=(40, 1))
    with pytest.warns(UserWarning, match="no clear rank gap"):
        base = base_parameters(lambda q, u, ud: np.array([[q[0], q[0] + 1e-8 * q[1]]]), q, u, u,
                               names=["a", "b"])
    assert base.rank == 2


@pytest.mark.parametrize("call, message", [
    (lambda s, x: base_parameters(s, *x(2)), "give more states"),
    (lambda s, x: base_parameters(s, *x(40), names=s.names[:-1]), "'regressor' must return"),
    (lambda s, x: base_parameters(s, *x(40), tolerance=2), "'tolerance'"),
    (lambda s, x: identify(s, *x(40), np.zeros((40, 3))), "'tau' must have 2 columns"),
    (lambda s, x: identify(s, *x(40), np.full((40, 2), np.nan)), "'tau' has non-finite"),
    (lambda s, x: identify(s, *x(40), np.zeros((40, 2)), weights=[1, -1]), "'weights'"),
    (lambda s, x: identify_consistent(s, *x(40), np.zeros((40, 2)), bodies=2,
                                      nonnegative=["viscous_3"]), "unknown parameter 'viscous_3'"),
    (lambda s, x: identify_consistent(s, *x(40), np.zeros((40, 2)), bodies=9), "'bodies'"),
    (lambda s, x: identify_consistent(s, *x(40), np.zeros((40, 2)), bodies=2,
                                      prior=np.zeros((2, 28))), "'prior'"),
    (lambda s, x: excite(s, [1, 1], [0, 2], [1, 1]), "lower < upper"),
    (lambda s, x: excite(s, [0, 0], [1, 1], [1, 1], iterations=0), "'iterations'"),
])
def test_bad_input_is_refused_naming_the_argument(call, message):
    setup = Setup(arm())
    rng = np.random.default_rng(7)
    with pytest.raises(ModelError, match=message):
        call(setup, lambda n: setup.states(rng, n))


@settings(max_examples=15, deadline=None)
@given(tree=trees(max_bodies=4, loads=False, frames=0))
def test_base_parameters_of_random_trees_reproduce_y_pi(tree):
    """Random trees (every joint type, unaligned axes, fixed bodies, gravity), Pinocchio's regressor:
    the rank is the SVD's and Y π = Y_b β at fresh states for random π."""
    if not 1 < np.linalg.norm(tree.gravity) < 20:  # not gravity of 1e-300 (columns of subnormal numbers)
        tree.gravity = (0.0, 0.0, -9.81)
    model = PinocchioTree(tree).model
    data = model.createData()
    names = [f"{p}_{k}" for k in range(1, model.njoints) for p in PINOCCHIO]
    rng = np.random.default_rng(8)

    def regressor(q, u, ud):
        # Pinocchio's answer is its data's buffer, the same at every call (the identification copies it)
        return pin.computeJointTorqueRegressor(model, data, q, u, ud).reshape(model.nv, -1)  # (10,): nv = 1

    def states(n):
        return ([pin.randomConfiguration(model, -np.pi * np.ones(model.nq), np.pi * np.ones(model.nq))
                 for _ in range(n)], rng.uniform(-2, 2, (n, model.nv)), rng.uniform(-2, 2, (n, model.nv)))

    n = 4 * len(names) // model.nv + 5
    base = base_parameters(regressor, *states(n), names=names)
    W = np.concatenate([regressor(*x).copy() for x in zip(*states(n))])
    assume(svd_rank(W) is not None)  # a tree whose rank the SVD shows with a clear gap
    assert base.rank == svd_rank(W)
    pi = rng.normal(size=len(names))
    tau = W @ pi
    assert np.allclose(base.regressor(W) @ base.of(pi), tau, rtol=0, atol=1e-9 * max(1, np.abs(tau).max()))


@pytest.mark.slow
def test_ur5_excited_identified_and_consistent():
    """The whole chain on ur5: an excitation trajectory within its URDF's limits, noisy torques on it,
    least squares (β within 4 standard deviations, held-out torques predicted), the consistent fit
    realisable and about as close to the data."""
    model = ur5()
    setup = Setup(model)
    rng = np.random.default_rng(9)
    lower, upper = np.maximum(model.lowerPositionLimit, -3), np.minimum(model.upperPositionLimit, 3)
    result = excite(setup, lower, upper, np.minimum(model.velocityLimit, 2), harmonics=4,
                    samples=60, restarts=2, iterations=10, time_limit=60, rng=rng)
    assert result.condition < result.start
    noise = np.array([0.5, 0.5, 0.3, 0.1, 0.1, 0.05])
    times = np.linspace(0, result.fourier.period, 500, endpoint=False)
    q, u, ud = result.fourier(times)
    tau = setup.torques(q, u, ud) + rng.normal(size=q.shape) * noise
    fit = identify(setup, q, u, ud, tau, base=result.base)
    assert (np.abs(fit.beta - result.base.of(setup.pi)) < 4 * fit.std).all()
    q, u, ud = setup.states(rng, 200)
    error = fit.predict(q, u, ud) - setup.torques(q, u, ud)
    assert (np.sqrt((error**2).mean(axis=0)) < noise).all()
    nonnegative = [n for n in setup.names if n.split("_")[0] in ("armature", "viscous", "coulomb")]
    q, u, ud = result.fourier(times)
    consistent = identify_consistent(setup, q, u, ud, tau, bodies=6, nonnegative=nonnegative,
                                     base=result.base)
    assert consistent.eigenvalues.min() > -1e-7 and (consistent.rms < 1.2 * fit.rms + 1e-3).all()
