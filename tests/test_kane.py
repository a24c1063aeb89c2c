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
         "particle": (K.particle, K.particle_sympy, {}),
         "rolling_disk": (K.rolling_disk, K.rolling_disk_sympy, dict(torques=True))}


@pytest.mark.parametrize("case", CASES)
def test_equals_sympy_kanes_method(case):
    """F̃_r equal symbolically; F̃*_r equal at random states (with the dependent speeds and their rates
    from the constraints); the accelerations of sympy's full system equal M̃⁻¹ f̃."""
    build, reference, kw = CASES[case]
    system, args = build(**kw)
    k = eg.kane(system, **args)
    km, qs, ws = reference(**kw)
    fr, frstar = km.kanes_equations.__self__._fr, km._frstar
    acc = [sp.Symbol(f"{w.name}_acc") for w in k.independent]
    dep_t = me.dynamicsymbols([w.name for w in k.dependent]) if k.dependent else []
    w_dep = k.dependent_speeds
    # d/dt w_dep = ∂w_dep/∂q q̇ + ∂w_dep/∂w ẇ
    w_dep_dot = w_dep.jacobian(list(system.q)) * k.qdot + w_dep.jacobian(k.independent) * sp.Matrix(acc)
    rep = {}
    for w_t, a in zip(ws, acc):
        rep[w_t.diff()] = a
    for w_t, e in zip(dep_t, w_dep_dot):
        rep[w_t.diff()] = e
    rep.update(dict(zip(qs, system.q)))
    rep.update(dict(zip(ws, k.independent)))
    rep.update(dict(zip(dep_t, w_dep)))
    fr_s, frstar_s = me.msubs(fr, rep), me.msubs(frstar, rep)
    assert sp.simplify(k.active_forces - fr_s) == sp.zeros(len(acc), 1)
    ours = k.inertia_forces().xreplace({sp.Symbol(f"{w.name}dot"): a for w, a in zip(k.independent, acc)})
    rng = np.random.default_rng(12)
    symbols = sorted(ours.free_symbols | frstar_s.free_symbols, key=str)
    for _ in range(5):
        values = {s: sp.Float(rng.uniform(0.3, 1.5), 30) for s in symbols}
        diff = (ours - frstar_s).xreplace(values).evalf(30)
        scale = max(1.0, float(max(abs(x) for x in frstar_s.xreplace(values).evalf(30))))
        assert float(max(abs(x) for x in diff)) < 1e-12 * scale


@pytest.mark.parametrize("build", [lambda: cart_pendulum()[0], double_pendulum, spatial_arm_3dof])
def test_holonomic_equals_projected_newton_euler(build):
    system = build()
    k, e = eg.kane(system), eg.derive(system)
    q = list(system.q)
    assert matrices_trig_equal(k.mass_matrix, e.M, q)
    assert matrices_trig_equal(k.forcing, -(e.b + e.g), q)


def test_skate_equilibrium():
    """A force perpendicular to the runner through C is balanced by the constraint (F̃_r = 0);
    through P at l ≠ 0 it turns the skate (F̃_2 = F l)."""
    system_C, args_C = K.skate(force_at=0)
    system_P, args_P = K.skate(force_at=K.l)
    k_C, k_P = eg.kane(system_C, **args_C), eg.kane(system_P, **args_P)
    assert sp.simplify(k_C.active_forces) == sp.zeros(2, 1)
    assert sp.simplify(k_P.active_forces - sp.Matrix([0, K.F * K.l])) == sp.zeros(2, 1)


@pytest.mark.parametrize("case,backend", [("skate", "numpy"), ("rolling_disk", "numpy"), ("rolling_disk", "c")])
def test_simulation_keeps_constraints_and_energy(case, backend, tmp_path, monkeypatch):
    """10 s unforced: the original velocity constraints hold along the solution to 1e-8 and the
    energy stays constant to 1e-8 relative (compiled: the same functions as NumPy, to 1e-13)."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system, args = (K.skate(force_at=None) if case == "skate" else K.rolling_disk())
    k = eg.kane(system, **args)
    f = eg.codegen(k, backend=backend)
    p = {"m": 1.3, "I_x": 0.05, "I_y": 0.05, "I_z": 0.1, "a": 0.4, "l": 0.7, "R": 0.3, "g": 9.81}
    if case == "skate":
        x0 = np.r_[0.1, -0.2, 0.3, 1.2, 0.8]  # q, then (speed along the runner, turning rate)
    else:
        x0 = np.r_[0.0, 0.0, 0.2, 0.0, 0.5, 4.0]  # q, then (heading rate, spin rate)
    sol = solve_ivp(lambda t, x: f.rhs(t, x, p), (0, 10), x0, method="DOP853", rtol=1e-12, atol=1e-12,
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
        residuals.append(max(abs(c) for c in constraint(q, qd, [p["R"]])))
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


def test_example_runs(capsys):
    import runpy
    from pathlib import Path

    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "nonholonomic.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert "through C: F̃_r = [0, 0]" in out and "through P: F̃_r = [0, F*l]" in out
