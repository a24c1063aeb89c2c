"""kernels="c" (`numeric.jax_kernels`): the JAX functions' values on CPU come from the C backend's compiled
kernels, one C call per vmapped batch, their derivatives from the traced graph. The same checks as
test_traced_targets for the traced graph: every catalogue entry equals NumPy to 1e-12 (one state, jit,
vmap), jacfwd of the forward dynamics equals forward_dynamics_derivatives to 1e-9; grad of M against a
central difference of NumPy's M; on any other platform the traced graph (lowered for CUDA: no callback),
where JAX sees another platform than CPU (`only_cpu` false)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import jax
import numpy as np
import pytest

import eomgen as eg
from eomgen.functions import catalogue
from eomgen.numeric import jax_kernels
from test_catalogue import PARAMS, everything, members, public_call
from test_traced_targets import close


@pytest.fixture(scope="module")
def features():
    """(the every-feature model without constraints, its NumPy functions, its JAX functions with the C
    kernels, every entry printed: one C module)."""
    eom = everything(False)
    fj = eg.codegen(eom, backend="jax", kernels="c")
    fj.generate([fn.key for fn in members(catalogue(eom)) if not fn.composite])
    return eom, eg.codegen(eom), fj


def test_every_entry_equals_numpy_one_state_jit_and_vmap(features):
    eom, f, fj = features
    q, u, ud = (x[0] for x in eg.random_states(eom.system, 1, np.random.default_rng(5)))
    Q, U, UD = eg.random_states(eom.system, 3, np.random.default_rng(6))
    for fn in members(catalogue(eom)):
        if fn.composite:
            close(public_call(fj, fn, q, u, ud, PARAMS), public_call(f, fn, q, u, ud, PARAMS), 1e-12, fn.key)
            continue
        reference = f.call(fn.key, q, u, ud, PARAMS)
        close(fj.call(fn.key, q, u, ud, PARAMS), reference, 1e-12, f"{fn.key}: one state (jitted)")
        close(fj.call(fn.key, Q, U, UD, PARAMS), f.call(fn.key, Q, U, UD, PARAMS), 1e-12, f"{fn.key}: vmap")
    assert set(fj._c.compiled) == {fn.key for fn in members(catalogue(eom)) if not fn.composite}


def c_calls(function, *args) -> int:
    """The calls of the C kernels (the XLA FFI targets "eomgen_<module>_m<i>") in the program that jit of
    `function` lowers for CPU."""
    return jax.jit(function).trace(*args).lower(lowering_platforms=("cpu",)).as_text().count("call @eomgen_")


def test_a_vmapped_batch_is_one_c_call(features):
    """vmap and nested vmaps reach the C function as one batch (one FFI call over the batch axes), a
    shared p once; parameters mapped per state: the batch too, each state with its own."""
    eom, f, fj = features
    Q, U, UD = eg.random_states(eom.system, 12, np.random.default_rng(3))
    p = np.asarray(fj.parameter_vector(PARAMS, "M"))
    M = fj.jax["M"]
    nested = jax.vmap(jax.vmap(M, in_axes=(0, 0, None, None)), in_axes=(0, 0, None, None))
    args = Q.reshape(3, 4, -1), U.reshape(3, 4, -1), UD[0], p
    close(jax.jit(nested)(*args), f.M(Q, PARAMS).reshape(3, 4, fj.nv, fj.nv), 1e-12, "nested vmap")
    assert c_calls(nested, *args) == 1
    broadcast = jax.vmap(jax.vmap(M, in_axes=(0, None, None, None)), in_axes=(None, 0, None, None))
    expected = np.broadcast_to(f.M(Q[:3], PARAMS), (2, 3, fj.nv, fj.nv))
    close(jax.jit(broadcast)(Q[:3], U[:2], UD[0], p), expected, 1e-12, "q and u broadcast")
    heavier = {**PARAMS, "g": 3.0}
    p = fj.parameter_vector(PARAMS, "g")
    P = np.array([p, fj.parameter_vector(heavier, "g"), p, p])
    G = np.asarray(jax.vmap(fj.jax["g"])(Q[:4], U[:4], UD[:4], P))
    close(G[[0, 2, 3]], f.call("g", Q[[0, 2, 3]], params=PARAMS), 1e-12, "vmap over p")
    close(G[1], f.call("g", Q[1], params=heavier), 1e-12, "vmap over p")
    assert c_calls(jax.vmap(fj.jax["g"]), Q[:4], U[:4], UD[:4], P) == 1


def test_derivatives_are_the_traced_graphs(features):
    eom, f, fj = features
    q, u, _ = (x[0] for x in eg.random_states(eom.system, 1, np.random.default_rng(9)))
    forward = jax.jit(lambda u: fj.forward_dynamics(q, u, params=PARAMS))
    close(forward(u), f.forward_dynamics(q, u, params=PARAMS), 1e-12, "forward dynamics")
    dud_du = jax.jit(jax.jacfwd(forward))(u)
    close(dud_du, f.forward_dynamics_derivatives(q, u, params=PARAMS)[1], 1e-9, "jacfwd: ∂u̇/∂u")
    grad = jax.jit(jax.grad(lambda q: fj.M(q, PARAMS)[0, 1]))(q)
    h = 1e-6
    central = [(f.M(q + h * e, PARAMS)[0, 1] - f.M(q - h * e, PARAMS)[0, 1]) / (2 * h)
               for e in np.eye(len(q))]
    close(grad, central, 1e-6, "grad of M[0, 1]")


def test_bound_params_float32_nan_and_other_platforms(features, monkeypatch):
    eom, f, fj = features
    Q, U, _ = eg.random_states(eom.system, 4, np.random.default_rng(1))
    bound = {k: v for k, v in PARAMS.items() if k != "i_m"}  # the motor current is state
    close(fj.bind(bound).M(Q), f.M(Q, PARAMS), 1e-12, "bind")
    close(eg.codegen(eom, backend="jax", params=bound).M(Q[0]), f.M(Q[0], PARAMS), 1e-12, "params=")
    f32 = eg.codegen(eom, backend="jax", dtype="float32", params=bound)
    assert f32.kernels == "c" and f32.M(Q).dtype == np.float32  # computed in float64, rounded
    close(f32.M(Q), f.M(Q, PARAMS), 1e-6, "float32")
    with pytest.raises((jax.errors.JaxRuntimeError, ValueError), match="q: contains NaN or infinite"):
        np.asarray(fj.M(np.full(fj.nq, np.nan), PARAMS))  # the C kernel checks its inputs
    with pytest.raises((jax.errors.JaxRuntimeError, ValueError), match="ud: contains NaN or infinite"):
        np.asarray(fj.call("ID", Q, U, np.full((4, fj.nv), np.inf), PARAMS))
    p = np.asarray(fj.parameter_vector(PARAMS, "M"))
    batch = jax.vmap(fj.jax["M"], in_axes=(0, 0, 0, None))
    assert c_calls(batch, Q, U, U, p) == 1
    monkeypatch.setattr(jax_kernels, "only_cpu", lambda: False)  # as where JAX sees a GPU too
    jax.clear_caches()  # traced again: the choice between C and graph is made when tracing
    close(jax.jit(batch)(Q, U, U, p), f.M(Q, PARAMS), 1e-12, "platform_dependent, on CPU")
    assert c_calls(batch, Q, U, U, p) == 1
    lowered = jax.jit(batch).trace(Q, U, U, p).lower(lowering_platforms=("cuda",)).as_text()
    assert "custom_call" not in lowered and "callback" not in lowered
    jax.clear_caches()


def test_no_host_callback_one_c_call_per_jitted_call(features):
    """One state and a batch (jit, jit of vmap): one C call (an XLA FFI call), no host callback (a
    Python call per jitted call: 0.3 ms); jacfwd, grad, vmap of jacfwd: the traced graph's tangents."""
    eom, f, fj = features
    Q, U, UD = eg.random_states(eom.system, 6, np.random.default_rng(11))
    p = np.asarray(fj.parameter_vector(PARAMS, "M"))
    M = fj.jax["M"]
    one, batch = (Q[0], U[0], UD[0], p), (Q, U, UD, p)
    vmapped = jax.vmap(M, in_axes=(0, 0, 0, None))
    for function, args in ((M, one), (vmapped, batch)):
        assert "callback" not in jax.jit(function).trace(*args).lower().as_text()
        assert c_calls(function, *args) == 1
    assert c_calls(jax.jacfwd(M), *one) == 0
    assert c_calls(jax.grad(lambda q, *rest: M(q, *rest)[0, 0]), *one) == 0
    assert c_calls(jax.vmap(jax.jacfwd(M), in_axes=(0, 0, 0, None)), *batch) == 0
    close(jax.jit(M)(*one), f.M(Q[0], PARAMS), 1e-12, "one state, jit")
    close(jax.jit(vmapped)(*batch), f.M(Q, PARAMS), 1e-12, "jit of vmap")
    jacobian = jax.jit(jax.jacfwd(M))(*one)
    close(jax.vmap(jax.jacfwd(M), in_axes=(0, 0, 0, None))(*batch)[0], jacobian, 1e-12, "vmap of jacfwd")
    h, e = 1e-6, np.eye(fj.nq)[0]
    central = (f.M(Q[0] + h * e, PARAMS) - f.M(Q[0] - h * e, PARAMS)) / (2 * h)
    close(jacobian[..., 0], central, 1e-6, "jacfwd of M against a central difference of NumPy's M")


def test_the_default_and_refusals(monkeypatch):
    eom = everything(False)
    assert eg.codegen(eom, backend="jax").kernels == "c"  # a C compiler here
    with pytest.raises(eg.ModelError, match="kernels: expected one of"):
        eg.codegen(eom, backend="jax", kernels="cuda")
    with pytest.raises(eg.ModelError, match="kernels: only the JAX backend"):
        eg.codegen(eom, backend="c", kernels="c")
    monkeypatch.setenv("CC", "no-such-compiler")
    assert eg.codegen(eom, backend="jax").kernels == "xla"
    with pytest.raises(eg.ModelError, match="kernels='c': no C compiler found"):
        eg.codegen(eom, backend="jax", kernels="c")


def test_c_kernels_that_do_not_build_fall_back_with_a_warning_or_refuse(monkeypatch, tmp_path):
    """An XLA FFI header the glue cannot use (here: none at all): by default a warning naming the cause
    and the traced graph on CPU (the values still NumPy's); kernels="c" asked for: a ModelError."""
    system = eg.System()  # a model of this test alone: no module of it built or loaded before
    link = system.add_body("link", joint=eg.Revolute("swing", axis=(1, 0, 0)), mass=1.2345, com=(0, 0, -0.3))
    system.add_body("tip", parent=link, joint=eg.Revolute("bend", axis=(0, 1, 0)), mass=0.5,
                    com=(0, 0, -0.2), placement=eg.Placement(translation=(0, 0, -0.6)))
    eom = eg.derive(system)
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    monkeypatch.setattr(jax.ffi, "include_dir", lambda: str(tmp_path / "no-headers"))
    q = np.array([0.3, -0.7])
    with pytest.warns(UserWarning, match="(?s)the C kernels do not build with JAX .* graph on CPU too"):
        M = eg.codegen(eom, backend="jax").M(q)
    close(M, eg.codegen(eom).M(q), 1e-12, "M")
    with pytest.raises(eg.ModelError, match="kernels='c': the C kernels do not build with JAX"):
        eg.codegen(eom, backend="jax", kernels="c").M(q)


FLOAT32 = """
import numpy as np, jax, eomgen as eg
from test_catalogue import PARAMS, everything
eom = everything(False)
f32 = eg.codegen(eom, backend="jax", dtype="float32", params={k: v for k, v in PARAMS.items() if k != "i_m"})
Q = eg.random_states(eom.system, 4, np.random.default_rng(1))[0]
M, reference = [np.asarray(f32.M(Q)), np.asarray(f32.M(Q[0]))], eg.codegen(eom).M(Q, PARAMS)
print(jax.config.jax_enable_x64, M[0].dtype, M[1].dtype,
      max(np.abs(M[0] - reference).max(), np.abs(M[1] - reference[0]).max()) / np.abs(reference).max())
"""


def test_float32_without_64_bit_mode():
    """dtype="float32" in a process where JAX's 64-bit mode is off: the C kernels get float32 buffers,
    compute in float64 and round (a float32 buffer read as float64 would give wrong values)."""
    tests = str(Path(__file__).parent)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([tests, os.environ.get("PYTHONPATH", "")])}
    result = subprocess.run([sys.executable, "-c", FLOAT32], env=env, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    x64, one, batch, error = result.stdout.split()
    assert (x64, one, batch) == ("False", "float32", "float32") and float(error) < 1e-6
