"""The JAX and CasADi targets (`printers.traced`) equal the NumPy functions for every function of the
catalogue of robots and of the model with every feature (test_catalogue), one state and batches; JAX's
own derivatives (jacfwd) of its forward dynamics equal forward_dynamics_derivatives, CasADi's jacobian of
its inverse dynamics equals inverse_dynamics_derivatives (against Pinocchio in test_derivatives). JAX here
with kernels="xla" (its traced graph: what runs on a GPU, and the derivatives of kernels="c",
test_jax_kernels)."""
from __future__ import annotations

import casadi as ca
import jax
import numpy as np
import pytest

import eomgen as eg
from eomgen.functions import catalogue
from test_catalogue import PARAMS, everything, members, public_call


def close(a, b, tol: float, what: str) -> None:
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert a.shape == b.shape, what
    assert np.abs(a - b).max(initial=0.0) <= tol * max(1.0, float(np.abs(b).max(initial=0.0))), what


@pytest.mark.parametrize("constraints", [True, False])
def test_every_function_equals_numpy(constraints):
    eom = everything(constraints)
    f, fc = eg.codegen(eom), eg.codegen(eom, backend="casadi")
    fj = eg.codegen(eom, backend="jax", kernels="xla")
    q, u, ud = (x[0] for x in eg.random_states(eom.system, 1, np.random.default_rng(5)))
    Q, U, UD = eg.random_states(eom.system, 3, np.random.default_rng(6))
    for fn in members(catalogue(eom)):
        if fn.composite:
            reference = public_call(f, fn, q, u, ud, PARAMS)
            close(public_call(fj, fn, q, u, ud, PARAMS), reference, 1e-12, f"{fn.key}: JAX")
            continue
        reference = f.call(fn.key, q, u, ud, PARAMS)
        close(fj.call(fn.key, q, u, ud, PARAMS), reference, 1e-12, f"{fn.key}: JAX")
        close(fc.call(fn.key, q, u, ud, PARAMS), reference, 1e-12, f"{fn.key}: CasADi")
        if fn.key in ("M", "tau", "T", "J_c", "ID_derivatives", "W:a", "X:tip"):  # each a jit(vmap) compile
            close(fj.call(fn.key, Q, U, UD, PARAMS), f.call(fn.key, Q, U, UD, PARAMS), 1e-12, f"{fn.key}: vmap")
        if fn.public:
            expected = public_call(f, fn, q, u, ud, PARAMS)
            close(public_call(fj, fn, q, u, ud, PARAMS), expected, 1e-12, f"{fn.name}: JAX")
            close(public_call(fc, fn, q, u, ud, PARAMS), expected, 1e-12, f"{fn.name}: CasADi")


@pytest.mark.parametrize("name", ["ur5", "solo12"])
def test_robots_their_dynamics_and_derivatives(name):
    system = eg.robots.load(name)
    eom = eg.derive(system)
    f, fc = eg.codegen(eom), eg.codegen(eom, backend="casadi")
    fj = eg.codegen(eom, backend="jax", kernels="xla")
    q, u, ud = (x[0] for x in eg.random_states(system, 1, np.random.default_rng(9)))
    for key in ("M", "b", "g", "nle", "ID", "ID_derivatives", "com", "A_G"):
        close(fj.call(key, q, u, ud), f.call(key, q, u, ud), 1e-12, f"{name} {key}: JAX")
        close(fc.call(key, q, u, ud), f.call(key, q, u, ud), 1e-12, f"{name} {key}: CasADi")
    derivatives = f.forward_dynamics_derivatives(q, u)
    forward = jax.jit(lambda u: fj.forward_dynamics(q, u))
    close(forward(u), f.forward_dynamics(q, u), 1e-12, "forward dynamics")
    close(jax.jacfwd(lambda u: fj.forward_dynamics(q, u))(u), derivatives[1], 1e-9, "jacfwd: ∂u̇/∂u")
    if system.nq == system.nv:  # ∂/∂q in the tangent space is ∂/∂q here
        close(jax.jacfwd(lambda q: fj.forward_dynamics(q, u))(q), derivatives[0], 1e-9, "jacfwd: ∂u̇/∂q")
        x = ca.SX.sym("x", 2 * system.nv)
        ID = fc.casadi["ID"](x[:system.nq], x[system.nq:], ud)
        D = ca.Function("D", [x], [ca.jacobian(ID, x)])(np.r_[q, u]).full()
        close(D, np.hstack(f.inverse_dynamics_derivatives(q, u, ud)), 1e-10, "CasADi jacobian of ID")
    fd = fc.casadi["forward_dynamics"](q, u, np.zeros(len(system.actuated))).full().ravel()
    close(fd, f.forward_dynamics(q, u), 1e-10, "CasADi forward dynamics (its own symbolic QR solve)")


def test_float32_and_refusals():
    eom = everything(False)
    f32 = eg.codegen(eom, backend="jax", dtype="float32", kernels="xla")
    q, u, _ = (x[0] for x in eg.random_states(eom.system, 1, np.random.default_rng(2)))
    M32 = f32.M(q, PARAMS)
    assert M32.dtype == np.float32
    close(M32, eg.codegen(eom).M(q, PARAMS), 1e-5, "float32 M")
    with pytest.raises(eg.ModelError, match="dtype: only the JAX backend"):
        eg.codegen(eom, backend="c", dtype="float32")
    with pytest.raises(eg.ModelError, match="dtype: expected one of"):
        eg.codegen(eom, backend="jax", dtype="float16")
    with pytest.raises(eg.ModelError, match="out: the JAX backend returns new arrays"):
        f32.M(q, PARAMS, out=np.zeros((f32.nv, f32.nv)))


def test_a_piecewise_is_refused_by_jax_naming_the_function():
    import sympy as sp

    x = sp.Symbol("x")
    system = eg.System()
    system.add_body("a", joint=eg.Revolute("r"), mass=1.0, com=(0.3, 0, 0), inertia=np.eye(3) * 0.1)
    system.add_torque("a", (0, 0, sp.Piecewise((sp.sqrt(x), x > 0), (0, True))), name="spring_like")
    fj = eg.codegen(eg.derive(system), backend="jax")
    with pytest.raises(eg.ModelError, match="tau holds a Piecewise"):
        fj.tau(np.zeros(1), np.zeros(1), params={"x": 1.0})
