"""Identification of eomgen models (eg.base_parameters, eg.identify, eg.identify_consistent on a System):
the base parameters have the numerical rank of the stacked regressor and the structural grouping gives
them in the model's symbols; torques made by Pinocchio (rnea, with armature) plus friction's closed forms
are identified and predicted."""
import warnings

import numpy as np
import pytest
import sympy as sp

import eomgen as eg
from eomgen.errors import ModelError
from eomgen.identification import numeric_regressor
from eomgen.model import pinocchio_configuration
from eomgen.verify import to_pinocchio

pin = pytest.importorskip("pinocchio")


def load(name: str):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return eg.robots.load(name)


def svd_rank(Y: np.ndarray) -> int:
    """The numerical rank of the stacked regressor by its singular values, columns normalised (columns
    below 1e-9 of the largest dropped), at the base parameters' relative tolerance 1e-9."""
    W = Y.reshape(-1, Y.shape[-1])
    norms = np.linalg.norm(W, axis=0)
    W = W[:, norms > 1e-9 * norms.max()] / norms[norms > 1e-9 * norms.max()]
    s = np.linalg.svd(W, compute_uv=False)
    return int(np.sum(s > 1e-9 * s[0]))


def test_a_models_base_parameters_have_the_rank_and_its_grouping_reproduces_the_torques():
    """ur5 with armature and the three friction kinds: 36 inertial (Gautier/Khalil's count for a 6R
    arm of this geometry, the SVD's here), 4 armatures (two grouped: joints 1 and 2 spin alone), 18
    friction; Y_R β of the grouping in the model's numbers equals Pinocchio's rnea."""
    system = load("ur5")
    base = eg.base_parameters(system, states=80)
    Y = numeric_regressor(system)
    q, u, ud = Y.states(30, seed=5)
    assert base.rank == svd_rank(Y(q, u, ud)) == 36 + 4 + 18
    assert base.grouping is not None and len(base.grouping.names) == base.rank and base.note == ""
    beta = np.array([float(b) for b in base.grouping.expressions])
    model = to_pinocchio(system)
    data = model.createData()
    tau = np.array([pin.rnea(model, data, x, v, a).copy()
                    for x, v, a in zip(pinocchio_configuration(system, q), u, ud)])
    assert np.allclose(Y(q, u, ud)[..., base.grouping.columns] @ beta, tau, rtol=0, atol=1e-10)
    assert np.allclose(base.regressor(Y(q, u, ud)) @ base.of(Y.pi), tau, rtol=0, atol=1e-10)


def test_a_model_is_identified_from_pinocchios_torques_and_friction():
    """τ = rnea (Pinocchio) + F_v u + F_c sign(u), noiseless: the base parameters come back to 1e-8 and
    held-out torques are predicted; the consistent fit of the model keeps its links realisable."""
    system = load("ur5")
    R = eg.regressor(system, friction=("viscous", "coulomb"))
    Y = numeric_regressor(R)
    rng = np.random.default_rng(3)
    Fv, Fc = rng.uniform(0.1, 0.5, 6), rng.uniform(0.2, 1.0, 6)
    model = to_pinocchio(system)
    data = model.createData()

    def torques(q, u, ud):
        configurations = pinocchio_configuration(system, q)
        rnea = [pin.rnea(model, data, x, v, a).copy() for x, v, a in zip(configurations, u, ud)]
        return np.array(rnea) + Fv * u + Fc * np.sign(u)

    q, u, ud = Y.states(120, seed=1)
    pi = Y.pi
    pi[[R.names.index(f"Fv_{j.name}") for j in system.joints if j.dof]] = Fv
    pi[[R.names.index(f"Fc_{j.name}") for j in system.joints if j.dof]] = Fc
    fit = eg.identify(R, q, u, ud, torques(q, u, ud))
    assert np.allclose(fit.beta, fit.base.of(pi), rtol=1e-8, atol=1e-8)
    held_out = Y.states(20, seed=2)
    assert np.allclose(fit.predict(*held_out), torques(*held_out), atol=1e-8)
    consistent = eg.identify_consistent(R, q, u, ud, torques(q, u, ud))
    assert consistent.eigenvalues.min() > -1e-7 and np.max(consistent.rms) < 1e-3


def test_a_symbolic_model_needs_its_values():
    """A model with symbols: eg.base_parameters refuses, naming them; with params its grouping is in the
    user's symbols (the lengths' values bound, the inertial symbols kept)."""
    m, l, g = sp.symbols("m l g", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    a = system.add_body("a", joint=eg.Revolute("q1"), mass=m, com=(l / 2, 0, 0),
                        inertia=sp.diag(0, m * l**2 / 12, m * l**2 / 12))
    system.add_body("b", parent=a, joint=eg.Revolute("q2"), mass=m, com=(l / 2, 0, 0),
                    inertia=sp.diag(0, m * l**2 / 12, m * l**2 / 12),
                    placement=eg.Placement(translation=(l, 0, 0)))
    with pytest.raises(ModelError, match=r"symbols without values: \['g', 'l', 'm'\]"):
        eg.base_parameters(system)
    R = eg.regressor(system, friction=(), armature=False)
    base = eg.base_parameters(numeric_regressor(R, params={"m": 2.0, "l": 0.5, "g": 9.81}))
    assert base.rank == 6 and base.grouping is not None
    hand = {"I_zz_aR": m * l**2 / 3 + m * l**2, "mx_aR": m * l / 2 + m * l, "I_zz_b": m * l**2 / 3,
            "mx_b": m * l / 2, "my_a": 0, "my_b": 0}
    grouped = dict(zip(base.grouping.names, base.grouping.expressions))
    assert grouped == {k: sp.sympify(v) for k, v in hand.items()}


FIXED = ["asr_twodof", "double_pendulum", "finger_edu", "kinova", "panda", "so100", "talos_arm", "ur3",
         "ur5", "ur10", "xarm7", "z1", "allegro_left_hand", "baxter", "tiago_no_hand", "puma560", "stanford"]


@pytest.mark.slow
@pytest.mark.parametrize("name", FIXED)
def test_every_fixed_base_robot_has_its_numerical_rank_and_grouping(name):
    """With and without armature and friction: the base parameters' count is the SVD's rank of the
    stacked regressor, and the structural grouping has as many."""
    system = load(name)
    for options in ({"friction": (), "armature": False}, {}):
        R = eg.regressor(system, **options)
        Y = numeric_regressor(R)
        base = eg.base_parameters(Y, states=max(60, 4 * len(R.names) // system.nv))
        assert base.rank == svd_rank(Y(*Y.states(max(60, 4 * len(R.names) // system.nv), seed=9)))
        assert base.grouping is not None and len(base.grouping.names) == base.rank, base.note


@pytest.mark.slow  # the default run shows the 43 by the grouping on Pinocchio's regressor (test_grouping)
def test_the_panda_arm_has_43_base_inertial_parameters():
    """The Franka Emika Panda, fingers locked (the hand welded to link 7): the 43 base inertial parameters
    of Gaz, Cognetti, Oliva, Robuffo Giordano and De Luca (IEEE RA-L 2019), all given by the grouping."""
    panda = load("panda")
    arm = panda.reduced({j.name: 0.0 for j in panda.joints if "finger" in j.name})
    base = eg.base_parameters(eg.regressor(arm, friction=(), armature=False), states=80)
    assert base.rank == 43 and len(base.grouping.names) == 43
