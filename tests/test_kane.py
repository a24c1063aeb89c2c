"""Kane's equations against sympy.physics.mechanics.KanesMethod on the lecture's nonholonomic systems,
against projected Newton-Euler on holonomic ones, and in simulation."""
import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from scipy.integrate import solve_ivp

import eomgen as eg
import kane_systems as K
from models import cart_pendulum, double_pendulum, matrices_trig_equal, spatial_arm_3dof

CASES = {"skate": (K.skate, K.skate_sympy, dict(force_at=K.l)),
         "skate_implicit": (lambda **kw: K.skate(solved=False, **kw), K.skate_sympy, dict(force_at=K.l)),
         "particle": (K.particle, K.particle_sympy, {}),
         "rolling_disk": (K.rolling_disk, K.rolling_disk_sympy, dict(torques=True)),
         "pythagoras": (lambda **kw: K.constrained_skate(K.pythagoras, **kw),
                        lambda **kw: K.constrained_skate_sympy(K.pythagoras_sympy_form, **kw),
                        dict(force_at=K.l)),
         "rotation": (lambda **kw: K.constrained_skate(K.rotation, **kw),
                      lambda **kw: K.constrained_skate_sympy(K.rotation, **kw), dict(force_at=K.l)),
         "elementary": (lambda **kw: K.constrained_skate(K.elementary, **kw),
                        lambda **kw: K.constrained_skate_sympy(K.elementary, **kw), dict(force_at=K.l))}
P = {"m": 1.3, "I_x": 0.05, "I_y": 0.05, "I_z": 0.1, "a": 0.4, "l": 0.7, "R": 0.3, "g": 9.81, "F": 0.6,
     "tau_d": 0.3, "tau_s": -0.2, "b": 0.8}


def given(f, values=P) -> dict:
    """The values of the parameters of numeric functions `f` (unknown names are refused)."""
    return {str(s): values[str(s)] for s in f.params}


def _number(expr, values) -> np.ndarray:
    return np.array(me.msubs(expr, values).evalf(30).tolist(), dtype=float)


@pytest.mark.parametrize("case", CASES)
def test_equals_sympy_kanes_method(case):
    """At random states, with sympy's own KanesMethod (its mass matrix and forcing over all speeds, the
    last rows the constraints' derivatives): the dependent speeds satisfy its constraints, F̃_r equal, and
    F̃_r + F̃*_r = f̃ − M̃ ẇ_ind equal for random ẇ_ind (the dependent rates from sympy's rows)."""
    build, reference, kw = CASES[case]
    system, args = build(**kw)
    k = eg.kane(system, **args)
    f = eg.codegen(k)
    km, qs, ws = reference(**kw)
    p, o = len(ws), len(km.u)
    MM, F = km.mass_matrix, km.forcing
    params = {s: P[s.name] for s in MM.free_symbols | F.free_symbols | km._fr.free_symbols if s.name in P}
    rng = np.random.default_rng(12)
    for _ in range(4):
        q, w = rng.uniform(-1.5, 1.5, system.nq), rng.uniform(-1.5, 1.5, p)
        w_dep = f.dependent_speeds(q, w, given(f))
        values = {**params, **dict(zip(qs, q)), **dict(zip(km.u, [*w, *w_dep]))}
        np.testing.assert_allclose(_number(km._f_nh, values) if len(w_dep) else [], 0, atol=1e-12)
        np.testing.assert_allclose(f.active_forces(q, w, given(f)), _number(km._fr, values)[:, 0], atol=1e-12)
        M_s, F_s = _number(MM, values), _number(F, values)[:, 0]
        for wd in rng.uniform(-1, 1, (2, p)):
            wd_dep = np.linalg.solve(M_s[p:, p:], F_s[p:] - M_s[p:, :p] @ wd) if o > p else []
            sympy_residual = F_s[:p] - M_s[:p] @ np.r_[wd, wd_dep]
            ours = f.forcing(q, w, given(f)) - f.mass_matrix(q, w, given(f)) @ wd
            np.testing.assert_allclose(ours, sympy_residual, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("case", ["skate", "particle", "rolling_disk", "pythagoras"])
def test_closed_forms_equal_generated_code(case):
    """Where every pivot is provably nonzero, the closed forms equal the numeric solves."""
    build, _, kw = CASES[case]
    system, args = build(**kw)
    k = eg.kane(system, **args)
    f = eg.codegen(k)
    rng = np.random.default_rng(3)
    q, w = rng.uniform(-1.5, 1.5, system.nq), rng.uniform(-1.5, 1.5, len(k.independent))
    values = {**{s: P[s.name] for s in k.parameters}, **dict(zip(system.q, q)), **dict(zip(k.independent, w))}
    for key in ("mass_matrix", "forcing", "qdot", "dependent_speeds", "active_forces"):
        closed = np.array(getattr(k, key).xreplace(values).evalf(30).tolist(), dtype=float)
        ours = getattr(f, key)(q, w, given(f))
        np.testing.assert_allclose(ours, closed.reshape(ours.shape), rtol=1e-12, atol=1e-12)


def test_no_closed_form_without_provable_pivot():
    """w = Wᵀ q̇ with W a rotation: Y's pivots cos x3, sin x3 are not provably nonzero."""
    system, args = K.skate(solved=False)
    k = eg.kane(system, **args)
    with pytest.raises(eg.ModelError,
                       match=r"speed map .* no pivot in column 0 can be proven nonzero.*eg.codegen"):
        k.mass_matrix
    assert k.dependent_speeds == sp.Matrix([0])  # C_dep = [1]: still closed


def test_pythagoras_dependent_speeds():
    """(cos² + sin² − 1) ẋ1 + ẋ2 − ẋ3 = 0, a ẋ1 − cos x3 ẋ3 = 0: ẋ1 = cos x3 ẋ3 / a, ẋ2 = ẋ3 (by hand)."""
    system, args = K.constrained_skate(K.pythagoras)
    f = eg.codegen(eg.kane(system, **args))
    for x3 in (0.0, 0.7, np.pi / 2, -2.1):
        q = np.array([0.3, -0.2, x3])
        np.testing.assert_allclose(f.dependent_speeds(q, [1.7], given(f)), [np.cos(x3) * 1.7 / P["a"], 1.7],
                                   rtol=1e-14, atol=1e-14)


def test_rotation_block_finite_at_zero():
    """C_dep = [[sin x3, cos x3], [cos x3, −sin x3]]: the code is finite and right at x3 = 0, π/2 and random
    x3 (by hand: [ẋ1, ẋ2] = C_dep [0, b ẋ3] = b ẋ3 [cos x3, −sin x3]); batched as well."""
    system, args = K.constrained_skate(K.rotation, force_at=K.l)
    k = eg.kane(system, **args)
    for backend in ("numpy", "c"):
        f = eg.codegen(k, backend=backend)
        x3 = np.r_[0.0, np.pi / 2, np.pi, np.random.default_rng(5).uniform(-3, 3, 5)]
        q = np.c_[np.zeros((len(x3), 2)), x3]
        w = np.full((len(x3), 1), 1.3)
        expected = P["b"] * 1.3 * np.c_[np.cos(x3), -np.sin(x3)]
        np.testing.assert_allclose(f.dependent_speeds(q, w, given(f)), expected, rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(f.dependent_speeds(q[0], w[0], given(f)), expected[0],
                                   rtol=1e-14, atol=1e-14)
        x = np.c_[q, w]
        p = given(f)
        assert np.all(np.isfinite(f.rhs(0, x, params=p))) and np.all(np.isfinite(f.rhs(0, x[0], params=p)))
        np.testing.assert_allclose(f.rhs(0, x, params=p)[3], f.rhs(0, x[3], params=p), rtol=1e-13)


def test_elementary_functions_in_constraints():
    """tan, exp, atan2 in the constraints: generated (NumPy and C, one state and batched) and equal to
    the hand solution of K.elementary."""
    system, args = K.constrained_skate(K.elementary, force_at=K.l)
    k = eg.kane(system, **args)
    rng = np.random.default_rng(3)
    q = rng.uniform(-1.2, 1.2, (6, 3))
    w = rng.uniform(-2, 2, (6, 1))
    x1, x2, x3 = q.T
    expected = w * np.c_[P["b"] * np.cos(x3), P["b"] * np.sin(x3) + np.exp(-x1**2) * np.arctan2(x2, 2)]
    for backend in ("numpy", "c"):
        f = eg.codegen(k, backend=backend)
        np.testing.assert_allclose(f.dependent_speeds(q, w, given(f)), expected, rtol=1e-13, atol=1e-13)
        np.testing.assert_allclose(f.dependent_speeds(q[2], w[2], given(f)), expected[2], rtol=1e-13, atol=1e-13)


def test_parameter_only_in_a_constraint():
    """b appears only in a constraint: it is a parameter of the equations and of the generated code."""
    system, args = K.constrained_skate(K.rotation)
    assert K.b not in system.parameters
    k = eg.kane(system, **args)
    f = eg.codegen(k)
    assert K.b in k.parameters and "b" in [str(s) for s in f.params]
    q, w = np.array([0.1, 0.2, 0.4]), np.array([0.9])
    with pytest.raises(eg.ModelError, match=r"values missing for the parameters \['b'\]"):
        f.dependent_speeds(q, w, {k: v for k, v in given(f).items() if k != "b"})
    bound = eg.codegen(k, params={**given(f), "b": 1.6})
    np.testing.assert_array_equal(bound.rhs(0, np.r_[q, w]),
                                  f.rhs(0, np.r_[q, w], params={**given(f), "b": 1.6}))
    one, two = (f.rhs(0, np.r_[q, w], params={**given(f), "b": b}) for b in (0.8, 1.6))
    np.testing.assert_allclose(f.dependent_speeds(q, w, {**given(f), "b": 1.6}),
                               2 * f.dependent_speeds(q, w, given(f)))
    assert not np.allclose(one, two)


def test_bicycle_five_constraints():
    """A Whipple-like bicycle, C_dep a dense trigonometric 5 × 5: derived without symbolic solves, finite
    upright, and over 1 s unforced at 4.5 m/s the constraints hold (the front contact's height, the holonomic
    one, stays 0 to 1e-8) and the energy is conserved to 1e-8 relative."""
    system, args, height = K.bicycle()
    k = eg.kane(system, **args)
    f = eg.codegen(k)
    p = {"m_b": 85.0, "g": 9.81}
    x0 = np.r_[np.zeros(system.nq), 0.05, 15.0, 0.02]  # upright; roll rate, rear spin, steer rate
    assert np.all(np.isfinite(f.rhs(0, x0, params=p)))
    np.testing.assert_allclose(f.qdot(x0[:8], x0[8:], p)[[0, 1, 4]], [4.5, 0, 0], atol=1e-12)
    sol = solve_ivp(lambda t, x: f.rhs(t, x, params=p), (0, 1.0), x0, method="DOP853", rtol=1e-12,
                    atol=1e-12, t_eval=np.linspace(0, 1.0, 11))
    assert sol.success
    eom = eg.codegen(k.eom)
    constraint = sp.lambdify([list(system.q), list(system.u), [K.m_b, K.g_b]], args["nonholonomic"])
    z = sp.lambdify([list(system.q)], height)
    energies = []
    for x in sol.y.T:
        q, qd = x[:8], f.qdot(x[:8], x[8:], p)
        energies.append(eom.T(q, qd, p) + eom.U(q, p))
        assert max(abs(np.array(constraint(q, qd, [85.0, 9.81])))) < 1e-8 and abs(z(q)) < 1e-8
    assert sol.y[0, -1] > 4 and abs(sol.y[3, -1]) > 1e-3  # it rode on and rolled
    assert np.ptp(energies) < 1e-8 * max(1.0, abs(energies[0]))


@pytest.mark.parametrize("build", [lambda: cart_pendulum()[0], double_pendulum, spatial_arm_3dof])
def test_holonomic_equals_projected_newton_euler(build):
    system = build()
    k, e = eg.kane(system), eg.derive(system)
    q = list(system.q)
    assert matrices_trig_equal(k.mass_matrix, e.M, q)
    assert matrices_trig_equal(k.forcing, -(e.b + e.g), q)


def test_skate_equilibrium():
    """A force perpendicular to the runner through C is balanced by the constraint (F̃_r = 0);
    through P at l ≠ 0 it turns the skate (F̃_2 = F l): closed forms, and the generated code of the
    implicit kinematic equations."""
    system_C, args_C = K.skate(force_at=0)
    system_P, args_P = K.skate(force_at=K.l)
    k_C, k_P = eg.kane(system_C, **args_C), eg.kane(system_P, **args_P)
    assert sp.simplify(k_C.active_forces) == sp.zeros(2, 1)
    assert sp.simplify(k_P.active_forces - sp.Matrix([0, K.F * K.l])) == sp.zeros(2, 1)
    x = np.random.default_rng(4).uniform(-1, 1, (6, 5))
    for at, expected in ((0, [0, 0]), (K.l, [0, P["F"] * P["l"]])):
        system, args = K.skate(force_at=at, solved=False)
        f = eg.codegen(eg.kane(system, **args))
        np.testing.assert_allclose(f.active_forces(x[:, :3], x[:, 3:], given(f)), np.tile(expected, (6, 1)),
                                   atol=1e-14)


@pytest.mark.parametrize("case,backend", [("skate", "numpy"), ("rolling_disk", "numpy"), ("rolling_disk", "c")])
def test_simulation_keeps_constraints_and_energy(case, backend, tmp_path, monkeypatch):
    """10 s unforced: the original velocity constraints hold along the solution to 1e-8 and the
    energy stays constant to 1e-8 relative (compiled: the same functions as NumPy, to 1e-13)."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system, args = (K.skate(force_at=None, solved=False) if case == "skate" else K.rolling_disk())
    k = eg.kane(system, **args)
    f = eg.codegen(k, backend=backend)
    p = given(f)
    if case == "skate":
        x0 = np.r_[0.1, -0.2, 0.3, 1.2, 0.8]  # q, then (speed along the runner, turning rate)
    else:
        x0 = np.r_[0.0, 0.0, 0.2, 0.0, 0.5, 4.0]  # q, then (heading rate, spin rate)
    sol = solve_ivp(lambda t, x: f.rhs(t, x, params=p), (0, 10), x0, method="DOP853", rtol=1e-12, atol=1e-12,
                    t_eval=np.linspace(0, 10, 101))
    if backend == "c":
        fn, x = eg.codegen(k), np.random.default_rng(26).uniform(-1, 1, (20, len(x0)))
        for key in ("mass_matrix", "forcing", "qdot", "dependent_speeds", "active_forces"):
            np.testing.assert_allclose(getattr(f, key)(x[:, :system.nq], x[:, system.nq:], p),
                                       getattr(fn, key)(x[:, :system.nq], x[:, system.nq:], p), rtol=1e-13, atol=1e-13)
    assert sol.success
    eom = eg.codegen(eg.derive(system))
    nq = system.nq
    energies, residuals = [], []
    # the constraints as the user states them, in q and q̇ (the skate: C moves along the runner)
    stated = (args["nonholonomic"] if case == "rolling_disk" else
              [-sp.sin(system.q[2]) * system.u[0] + sp.cos(system.q[2]) * system.u[1]])
    constraint = sp.lambdify([list(system.q), list(system.u), [K.R]], stated)
    for x in sol.y.T:
        q, w = x[:nq], x[nq:]
        qd = f.qdot(q, w, p)  # q̇ = u of the joints
        energies.append(eom.T(q, qd, p) + eom.U(q, p))
        residuals.append(max(abs(c) for c in constraint(q, qd, [P["R"]])))
    assert max(residuals) < 1e-8
    assert np.ptp(energies) < 1e-8 * max(1.0, abs(energies[0]))


def test_bad_input():
    system, args = K.skate()
    with pytest.raises(eg.ModelError, match="nonholonomic constraint 0 is not linear"):
        eg.kane(system, **{**args, "nonholonomic": [K.u3**2]})
    x1d, x2d, x3d = system.u
    singular = [K.u1 - x1d - x2d, K.u2 - x3d, K.u3 - 2 * x1d - 2 * x2d]
    with pytest.raises(eg.ModelError, match="speed map .* is not invertible"):
        eg.kane(system, **{**args, "kinematic_equations": singular})
    with pytest.raises(eg.ModelError, match=r"independent speeds \[v\] are not among the speeds"):
        eg.kane(system, **{**args, "independent": [K.u1, sp.Symbol("v")]})
    with pytest.raises(eg.ModelError, match="kinematic equation 0 is not linear"):
        eg.kane(system, **{**args, "kinematic_equations": [K.u1 - x1d**2, K.u2 - x3d, K.u3 - x2d]})
    with pytest.raises(eg.ModelError, match="constraint 0 depends on q̇"):
        eg.kane(system, **{**args, "nonholonomic": [K.u3 - x1d]})
    plane, _ = K.skate()
    with pytest.raises(eg.ModelError, match="matrix of the dependent speeds C_dep is not invertible"):
        eg.kane(plane, nonholonomic=[plane.u[0] + plane.u[1], 2 * plane.u[0] + 2 * plane.u[1]],
                independent=[plane.u[2]])


def test_example_runs(capsys):
    import runpy
    from pathlib import Path

    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "nonholonomic.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert "through C: F̃_r = [0, 0]" in out and "through P: F̃_r = [0, F*l]" in out


def test_inputs_are_checked_where_they_enter(tmp_path):
    """Strings are never evaluated, non-finite values and look-alike symbols are refused, naming the
    argument; speeds must be sympy Symbols."""
    system, args = K.particle()
    marker = tmp_path / "PWNED"
    with pytest.raises(eg.ModelError, match="kane: nonholonomic constraint 0: expected a number or a sympy"):
        eg.kane(system, **{**args, "nonholonomic": [f"0*__import__('os').system('touch {marker}')"]})
    assert not marker.exists()
    with pytest.raises(eg.ModelError, match="kane: nonholonomic constraint 0: must be finite"):
        eg.kane(system, **{**args, "nonholonomic": [sp.nan * system.u[2]]})
    zdot = sp.Symbol(str(system.u[2]))  # labelled like the speed, but another symbol
    with pytest.raises(eg.ModelError, match=f"parameter '{zdot}' has the name of the speed of joint"):
        eg.kane(system, **{**args, "nonholonomic": [zdot - system.q[0] * system.u[1]]})
    with pytest.raises(eg.ModelError, match="kane: speeds: expected sympy Symbols"):
        eg.kane(system, speeds=["a", "b", "c"])
    with pytest.raises(eg.ModelError, match="kane: independent: expected a list of sympy Symbols"):
        eg.kane(system, **{**args, "independent": system.u[0]})
    with pytest.raises(eg.ModelError, match="kane: expected an eomgen.System"):
        eg.kane(eg.derive(system))
