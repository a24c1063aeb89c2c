"""The joint-torque regressor τ_ID = Y π (`eg.regressor`, `f.regressor`): against Pinocchio's
computeJointTorqueRegressor, rnea and energy regressors (robots, random trees built with Pinocchio's API),
Y π against the inverse dynamics on the robots, the armature and friction columns and π against their
closed forms, and the refusals."""
from __future__ import annotations

import importlib.util
import warnings

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import eomgen as eg
import strategies as S
from eomgen.model.robots import ROBOTS, paths


def close(a, b, tol: float, what: str) -> None:
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert a.shape == b.shape, f"{what}: shape {a.shape} ≠ {b.shape}"
    assert np.abs(a - b).max(initial=0.0) <= tol * max(1.0, float(np.abs(b).max(initial=0.0))), what


def load(name: str) -> eg.System:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # panda's mimic finger, imported independent (as Pinocchio's)
        return eg.robots.load(name)


def numbers(pi: sp.Matrix) -> np.ndarray:
    return np.array([float(x) for x in pi])


def check_inverse_dynamics(name: str, states: int = 3) -> None:
    system = load(name)
    eom = eg.derive(system)
    f, pi = eg.codegen(eom), numbers(eg.regressor(eom).pi)
    for q, u, ud in zip(*eg.random_states(system, states, np.random.default_rng(3))):
        close(f.regressor(q, u, ud) @ pi, f.inverse_dynamics(q, u, ud), 1e-12, f"{name}: Y π ≠ τ_ID")


@pytest.mark.parametrize("name", ["ur5", "panda", "puma560", "stanford"])
def test_y_pi_is_the_inverse_dynamics(name):
    check_inverse_dynamics(name)


FIXED_BASE = [name for name in ROBOTS if not paths(name)[2]]


@pytest.mark.slow
@pytest.mark.parametrize("name", FIXED_BASE)
def test_y_pi_is_the_inverse_dynamics_on_every_fixed_base_robot(name):
    check_inverse_dynamics(name, 2)


@pytest.mark.parametrize("name", ["ur5", "panda", "solo12"])
def test_y_and_the_energy_rows_are_pinocchios(name):
    """Pinocchio's columns (10 per joint, its bodies: fixed links merged into their joint) are Y's first;
    the free flyer's speeds are its too (base twist in the base frame), so no frame change is needed."""
    system = load(name)
    eom = eg.derive(system)
    f, r = eg.codegen(eom), eg.regressor(eom)
    urdf, _, floating = paths(name)
    model = pin.buildModelFromUrdf(str(urdf), *([pin.JointModelFreeFlyer()] if floating else []))
    data = model.createData()
    p = 10 * (model.njoints - 1)
    assert sum(name.startswith("m_") for name in r.names) == model.njoints - 1
    for q, u, ud in zip(*eg.random_states(system, 2, np.random.default_rng(4))):
        close(f.regressor(q, u, ud)[:, :p], pin.computeJointTorqueRegressor(model, data, q, u, ud), 1e-12,
              f"{name}: Y")
        close(f.kinetic_energy_regressor(q, u)[0, :p], pin.computeKineticEnergyRegressor(model, data, q, u),
              1e-12, f"{name}: T row")
        close(f.potential_energy_regressor(q)[0, :p], pin.computePotentialEnergyRegressor(model, data, q),
              1e-12, f"{name}: U row")
        T = f.kinetic_energy_regressor(q, u)[0] @ numbers(r.pi)
        close(T, 0.5 * u @ f.M(q) @ u, 1e-12, "T = ½ uᵀ M u")


@settings(max_examples=15, deadline=None, suppress_health_check=list(HealthCheck))
@given(tree=S.trees(max_bodies=4, loads=False, frames=0), seed=st.integers(0, 2**16))
def test_random_trees_against_pinocchio(tree, seed):
    """Y π = Pinocchio's rnea and Y = its regressor, columns by joint name (fixed bodies welded to the
    joint that carries them, as the tree's Pinocchio model appends them)."""
    system = S.eomgen_system(tree)
    ref = S.PinocchioTree(tree)
    eom = eg.derive(system)
    r, f = eg.regressor(eom), eg.codegen(eom)
    q, u = S.random_state(tree, np.random.default_rng(seed))
    ud = np.random.default_rng(seed + 1).uniform(-2, 2, system.nv)
    Y, perm = f.regressor(q, u, ud), ref.perm
    tau = pin.rnea(ref.model, ref.data, ref.configuration(q), u[perm], ud[perm])
    close((Y @ numbers(r.pi))[perm], tau, 1e-9, "Y π ≠ Pinocchio's rnea")
    links = [b.name for b in system.bodies if b.speed_indices]
    order = [links.index(tree.bodies[int(name[5:])].name) for name in ref.model.names[1:]]
    columns = [10 * k + j for k in order for j in range(10)]
    Y_pin = pin.computeJointTorqueRegressor(ref.model, ref.data, ref.configuration(q), u[perm], ud[perm])
    Y_pin = np.reshape(Y_pin, (system.nv, -1))  # Pinocchio's Python gives one speed's row as a vector
    close(Y[perm][:, columns], Y_pin, 1e-9, "Y ≠ Pinocchio's computeJointTorqueRegressor")


def arm() -> tuple[eg.System, dict]:
    """Two revolute joints with symbolic armature, a fixed tip welded to the second link."""
    m, l, L, m2, Ia, Ixx, Iyy, Izz = sp.symbols("m l L m2 Ia Ixx Iyy Izz", positive=True)
    s = eg.System(gravity=(0, 0, -9.81))
    s.add_body("link1", joint=eg.Revolute("j1", axis=(0, 0, 1), armature=Ia), mass=2.0, com=(0.3, 0, 0))
    s.add_body("link2", parent="link1", joint=eg.Revolute("j2", axis=(0, 1, 0)), mass=m, com=(l, 0, 0),
               inertia=sp.diag(Ixx, Iyy, Izz), placement=eg.Placement(translation=(0.6, 0, 0)))
    s.add_body("tip", parent="link2", joint=eg.Fixed("weld"), mass=m2,
               placement=eg.Placement(translation=(L, 0, 0)))
    return s, dict(m=m, l=l, L=L, m2=m2, Ia=Ia, Ixx=Ixx, Iyy=Iyy, Izz=Izz)


def test_pi_the_armature_and_friction_columns_are_their_closed_forms():
    s, x = arm()
    r = eg.regressor(s)
    assert r.Y.shape == (2, 28)
    pi = dict(zip(r.names, r.pi))
    m, l, L, m2 = x["m"], x["l"], x["L"], x["m2"]
    expected = {"m_link2": m + m2, "mx_link2": m * l + m2 * L, "my_link2": 0, "I_xx_link2": x["Ixx"],
                "I_yy_link2": x["Iyy"] + m * l**2 + m2 * L**2, "I_zz_link2": x["Izz"] + m * l**2 + m2 * L**2,
                "I_xz_link2": 0, "Ia_j1": x["Ia"], "Ia_j2": 0, "Fv_j1": 0, "Fc_j2": 0, "Fo_j1": 0}
    for name, value in expected.items():
        assert sp.expand(pi[name] - value) == 0, name
    u, ud = s.u, s.ud
    for i, joint in enumerate(("j1", "j2")):
        for prefix, column in (("Ia", ud[i]), ("Fv", u[i]), ("Fc", sp.sign(u[i])), ("Fo", 1)):
            k, what = r.names.index(f"{prefix}_{joint}"), f"{prefix}_{joint}"
            assert r.Y[:, k] == sp.Matrix([column if row == i else 0 for row in range(2)]), what
            assert r.U[0, k] == 0 and r.T[0, k] == (u[i] ** 2 / 2 if prefix == "Ia" else 0), what


def test_the_options_select_columns_of_the_full_regressor():
    s, _ = arm()
    full = eg.regressor(s)
    r = eg.regressor(s, friction=("coulomb",), armature=False)
    assert r.names == tuple(n for n in full.names if n[:3] not in ("Ia_", "Fv_", "Fo_"))
    assert [full.names[i] for i in r.columns] == list(r.names)
    assert r.Y == full.Y[:, list(r.columns)] and r.pi == full.pi[list(r.columns), :]
    assert eg.regressor(s, friction=()).names[-2:] == ("Ia_j1", "Ia_j2")


def test_coulomb_is_zero_at_rest_in_every_target(tmp_path, monkeypatch):
    """sign(0) = 0: NumPy, the C extension, the written module, JAX and CasADi."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path / "cache"))
    s, _ = arm()
    eom = eg.derive(s)
    r = eg.regressor(eom)
    params = {"m": 1.0, "l": 0.2, "L": 0.5, "m2": 0.3, "Ia": 0.1, "Ixx": 0.01, "Iyy": 0.02, "Izz": 0.03}
    path = eg.write_module(eom, tmp_path / "arm_module.py")
    spec = importlib.util.spec_from_file_location("arm_module", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    targets = [eg.codegen(eom), eg.codegen(eom, backend="c"), module, eg.codegen(eom, backend="jax"),
               eg.codegen(eom, backend="casadi")]
    coulomb = [k for k, n in enumerate(r.names) if n.startswith("Fc_")]
    q, ud = np.array([0.3, -0.7]), np.array([0.5, 1.5])
    for target in targets:
        Y = np.asarray(target.regressor(q, np.zeros(2), ud, params=params), float)
        assert np.all(Y[:, coulomb] == 0), type(target).__name__
        Y = np.asarray(target.regressor(q, np.array([-0.2, 0.4]), ud, params=params), float)
        close(Y[:, coulomb], np.diag([-1.0, 1.0]), 0, type(target).__name__)


def test_refusals_name_the_argument():
    s, _ = arm()
    with pytest.raises(eg.ModelError, match="friction must be a subset"):
        eg.regressor(s, friction=("dry",))
    with pytest.raises(eg.ModelError, match="friction must be a subset"):
        eg.regressor(s, friction=("viscous", "viscous"))
    with pytest.raises(eg.ModelError, match="armature must be True or False"):
        eg.regressor(s, armature="yes")
    with pytest.raises(eg.ModelError, match="expected a System or EquationsOfMotion"):
        eg.regressor(sp.Matrix([1]))
    flexible = eg.System()
    flexible.add_body("beam", joint=eg.FlexibleLink("beam", 1.0, 1.0, 10.0), mass=0)
    with pytest.raises(eg.ModelError, match="flexible link 'beam'"):
        eg.regressor(flexible)
    f = eg.codegen(eg.derive(flexible))
    with pytest.raises(eg.ModelError, match="flexible link 'beam'"):
        f.regressor(np.zeros(f.nq), np.zeros(f.nv), np.zeros(f.nv))
    assert f.inverse_dynamics(np.zeros(f.nq), np.zeros(f.nv), np.ones(f.nv)).shape == (f.nv,)
