"""The C backend's batches in vector registers (W states at once) and out=: the same numbers as Pinocchio
per state, as the scalar per-call path and as the NumPy backend, for every batch size (partial blocks);
out= reused and refused; functions with branches keep the scalar batch loop."""

import warnings

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import eomgen as eg
from eomgen.printers.vector import branches
from eomgen.model.urdf import pinocchio_configuration
from eomgen.verify import mass_matrix, to_pinocchio
from models import cart_pendulum, close

SIZES = [1, 3, 5, 7, 9, 17, 1000]  # W - 1 and W + 1 for W = 2, 4, 8; a partial last block


@pytest.fixture(scope="module")
def ur5(generated):
    system = eg.robots.load("ur5")
    fc = generated("ur5", "recursive", "c")  # shared by the worker's tests, in the run's cache
    fc.M(np.zeros((2, 6)))  # the first batch builds the vector functions
    return system, fc, generated("ur5", "recursive", "numpy")


def pinocchio(system, q, u) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(M, nle, g) per state: crba (upper triangle mirrored), nonLinearEffects, computeGeneralizedGravity."""
    model = system.pinocchio_model
    data, qp = model.createData(), pinocchio_configuration(system, q)
    M, nle, g = [], [], []
    for k in range(len(q)):
        Mk = pin.crba(model, data, qp[k])
        M.append(np.triu(Mk) + np.triu(Mk, 1).T)
        nle.append(pin.nonLinearEffects(model, data, qp[k], u[k]))
        g.append(pin.computeGeneralizedGravity(model, data, qp[k]))
    return np.array(M), np.array(nle), np.array(g)


@pytest.mark.parametrize("name", ["ur5", "solo12"])
def test_batches_equal_pinocchio_and_the_per_call_path(name, ur5, generated):
    """Every batch size: M, nle, g = Pinocchio per state (1e-10), = the scalar one-state call (1e-12
    relative), b = nle - g."""
    system = ur5[0] if name == "ur5" else eg.robots.load(name)
    fc = ur5[1] if name == "ur5" else generated(name, "recursive", "c")
    q, u, _ = eg.random_states(system, max(SIZES), np.random.default_rng(31))
    M, nle, g = pinocchio(system, q, u)
    for n in SIZES:
        batch = {"M": fc.M(q[:n]), "nle": fc.nle(q[:n], u[:n]), "g": fc.g(q[:n]), "b": fc.b(q[:n], u[:n])}
        for key, want in (("M", M), ("nle", nle), ("g", g), ("b", nle - g)):
            np.testing.assert_allclose(
                batch[key], want[:n], rtol=0, atol=1e-10, err_msg=f"{key}, {n} states"
            )
        for k in range(min(n, 20)):
            for key, one in (("M", fc.M(q[k])), ("nle", fc.nle(q[k], u[k])), ("g", fc.g(q[k]))):
                np.testing.assert_allclose(
                    batch[key][k],
                    one,
                    rtol=1e-12,
                    atol=1e-12 * np.abs(one).max(),
                    err_msg=f"{key}, state {k} of {n}",
                )


@settings(max_examples=25, deadline=None)
@given(n=st.integers(1, 40), seed=st.integers(0, 2**32 - 1), scale=st.sampled_from([1.0, 1e3, 3e5]))
def test_any_batch_equals_the_states_one_by_one(ur5, n, seed, scale):
    """Any batch size and angles (past 1e5 sin and cos are libm's, lane by lane): the batch = each state
    alone to 1e-12 relative."""
    _, fc, _ = ur5
    rng = np.random.default_rng(seed)
    q, u = rng.uniform(-scale, scale, (n, 6)), rng.uniform(-3, 3, (n, 6))
    q[rng.random(n) < 0.3] *= 1e-3  # small and large angles in one block
    for batch, one in (
        (fc.M(q), [fc.M(x) for x in q]),
        (fc.nle(q, u), [fc.nle(x, v) for x, v in zip(q, u)]),
    ):
        one = np.array(one)
        np.testing.assert_allclose(batch, one, rtol=1e-12, atol=1e-12 * np.abs(one).max())


def test_out_is_written_and_returned(ur5):
    """out= on both backends: the result written into out (every entry, stale ones included) and out
    returned; the same numbers as without out."""
    system, fc, fn = ur5
    q, u, _ = eg.random_states(system, 2 * 9 + 1, np.random.default_rng(32))
    for f in (fc, fn):
        for n in (1, 9, 19):
            calls = {
                "M": lambda **o: f.M(q[:n], **o),
                "b": lambda **o: f.b(q[:n], u[:n], **o),
                "g": lambda **o: f.g(q[:n], **o),
                "nle": lambda **o: f.nle(q[:n], u[:n], **o),
                "call": lambda **o: f.call("M", q[:n], **o),
            }
            for key, call in calls.items():
                want = call()
                out = np.full(want.shape, np.nan)
                for _ in range(2):  # reused
                    assert call(out=out) is out
                    np.testing.assert_array_equal(out, want, err_msg=f"{key}, {n} states")
        one = fc.M(q[0], out=np.full((6, 6), np.nan))
        np.testing.assert_array_equal(one, fc.M(q[0]))


def test_bad_out_is_refused(ur5):
    system, fc, fn = ur5
    q, u, _ = eg.random_states(system, 5, np.random.default_rng(33))
    bad = [
        np.zeros((5, 6)),
        np.zeros((4, 6, 6)),
        np.zeros((5, 6, 6), dtype=np.float32),
        np.zeros((5, 6, 6), order="F"),
        np.zeros((5, 6, 12))[..., ::2],
        [[0.0] * 6] * 5,
    ]
    readonly = np.zeros((5, 6, 6))
    readonly.flags.writeable = False
    for f in (fc, fn):
        for out in bad + [readonly]:
            with pytest.raises(
                ValueError,
                match=r"out: expected a writeable C-contiguous float64 array of " r"shape \(5, 6, 6\), got",
            ):
                f.M(q, out=out)
        with pytest.raises(ValueError, match=r"out: .* of shape \(5, 6\), got .*\(5, 6, 6\)"):
            f.nle(q, u, out=np.zeros((5, 6, 6)))
        with pytest.raises(ValueError, match=r"out: .* of shape \(6,\), got"):
            f.g(q[0], out=np.zeros((1, 6)))


def test_lane_functions_and_long_functions_in_parts(tmp_path, monkeypatch):
    """The elementary functions, Min, Max, |x| and general powers lane by lane, and functions split in
    parts (a small SEGMENT): the batch = the NumPy backend and the per-call path."""
    from eomgen.printers import walker

    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    monkeypatch.setattr(walker, "SEGMENT", 1)
    system = eg.System(gravity=(0, 0, -9.81))
    a = system.add_body("a", joint=eg.Revolute("x", axis=(0, 0, 1)), mass=1, com=(0.5, 0, 0))
    b = system.add_body(
        "b",
        parent=a,
        joint=eg.Prismatic("y", axis=(1, 0, 0)),
        mass=2,
        placement=eg.Placement(translation=(1, 0, 0)),
    )
    x, y = system.q
    v = system.u[0]
    system.add_torque(
        a, (0, 0, sp.tan(x / 3) + sp.exp(-(y**2)) * v + sp.log(2 + sp.sin(x)) + sp.atan2(y, x + 3))
    )
    system.add_torque(
        b,
        (
            sp.asin(x / 3) * sp.acos(y / 3) + sp.sinh(x / 2) - sp.cosh(y) * sp.tanh(v),
            sp.Abs(x - y) + sp.Min(x, y, sp.Rational(3, 10)) * sp.Max(x, -y, v),
            (2 + sp.cos(x)) ** 1.5 + sp.atan(v) + sp.sqrt(3 + y),
        ),
    )
    eom = eg.derive(system)
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    rng = np.random.default_rng(34)
    q, u = rng.uniform(-2, 2, (37, 2)), rng.uniform(-2, 2, (37, 2))
    for key, args in (("tau", (q, u)), ("M", (q,)), ("nle", (q, u))):
        batch = getattr(fc, key)(*args)
        np.testing.assert_allclose(batch, getattr(fn, key)(*args), rtol=1e-12, atol=1e-12, err_msg=key)
        one = np.array([getattr(fc, key)(*(a[k] for a in args)) for k in range(37)])
        np.testing.assert_allclose(batch, one, rtol=1e-12, atol=1e-12, err_msg=key)
    assert "e0_1(" in fc.functions["tau"].source  # in parts
    assert not branches(eom.subexpressions, eom.tau_compact)  # in vector registers


def test_branches_keep_the_scalar_batch_loop(tmp_path, monkeypatch):
    """A Piecewise load: no vector function; the scalar batch loop = the NumPy backend, out= zeroed."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system = eg.System(gravity=(0, -9.81, 0))
    a = system.add_body("a", joint=eg.Revolute("x", axis=(0, 0, 1)), mass=1, com=(0.5, 0, 0))
    x, v = system.q[0], system.u[0]
    system.add_torque(a, (0, 0, sp.Piecewise((-x, x > 0), (x**2, True)) + sp.sign(v)))
    eom = eg.derive(system)
    assert branches(eom.subexpressions, eom.tau_compact)
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    q, u = np.linspace(-1, 1, 21)[:, None], np.linspace(1, -1, 21)[:, None]
    out = np.full((21, 1, 1), np.nan)
    assert fc.call("tau", q, u, out=out) is out
    np.testing.assert_allclose(out, fn.call("tau", q, u), rtol=1e-14, atol=1e-14)


def test_vector_functions_are_built_on_the_first_batch_for_this_machine(tmp_path, monkeypatch):
    """codegen and calls of one state build one module, the first batch the module of the vector
    functions; on another CPU (machine() in the cache key) both are built again."""
    from eomgen.printers.build import extension

    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system = eg.System(gravity=(0, -9.81, 0))  # a model of this test only: no module of it loaded yet
    a = system.add_body("a", joint=eg.Revolute("x", axis=(0, 0, 1)), mass=1.2345, com=(0.321, 0, 0))
    system.add_body(
        "b",
        parent=a,
        joint=eg.Revolute("y", axis=(0, 0, 1)),
        mass=0.5432,
        com=(0.123, 0, 0),
        placement=eg.Placement(translation=(0.9, 0, 0)),
    )
    eom = eg.derive(system, method="recursive")
    modules = lambda: len(list(tmp_path.glob("eomgen_*.so")))  # noqa: E731
    f = eg.codegen(eom, backend="c")
    np.testing.assert_allclose(f.M(np.ones(2)), eg.codegen(eom).M(np.ones(2)), rtol=1e-14)
    assert modules() == 1
    M = f.M(np.ones((3, 2)))
    assert modules() == 2
    assert extension.machine()
    monkeypatch.setattr(extension, "machine", lambda: "another CPU")
    np.testing.assert_array_equal(eg.codegen(eom, backend="c").M(np.ones((3, 2))), M)
    assert modules() == 4


def test_inverse_dynamics_derivatives_in_batches(ur5):
    """∂τ/∂q, ∂τ/∂u of 17 states at once (vector registers) = Pinocchio's computeRNEADerivatives
    per state (1e-9) and = each state alone (1e-12 relative)."""
    system, fc, _ = ur5
    q, u, ud = eg.random_states(system, 17, np.random.default_rng(35))
    dq, du = fc.inverse_dynamics_derivatives(q, u, ud)
    model = system.pinocchio_model
    data = model.createData()
    for k in range(17):
        want = pin.computeRNEADerivatives(model, data, q[k], u[k], ud[k])[:2]
        for ours, theirs, one in zip(
            (dq[k], du[k]), want, fc.inverse_dynamics_derivatives(q[k], u[k], ud[k])
        ):
            np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-9)
            np.testing.assert_allclose(ours, one, rtol=1e-12, atol=1e-12 * np.abs(one).max())


def test_vector_functions_that_do_not_compile_leave_the_scalar_loop(tmp_path, monkeypatch):
    """A compiler that refuses the vector module: a warning, and batches one state at a time (= NumPy)."""
    from eomgen.printers import c_extension

    def refused(*args):
        raise eg.ModelError("the C compiler failed: vector types")

    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    monkeypatch.setattr(c_extension, "lanes_module", refused)
    system, _ = cart_pendulum()
    eom = eg.derive(system)
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    params = {"m_c": 1.5, "m_p": 0.25, "l": 0.6, "g": 9.81}
    q, u, _ = eg.random_states(system, 11, np.random.default_rng(36))
    with pytest.warns(UserWarning, match="batches run one state at a time: the C compiler failed"):
        M = fc.M(q, params)
    np.testing.assert_allclose(M, fn.M(q, params), rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(fc.nle(q, u, params), fn.nle(q, u, params), rtol=1e-13, atol=1e-13)


def test_a_first_batch_interrupted_while_printing_tries_again_on_the_next(monkeypatch):
    """Ctrl-C while the first batch prints the vector functions: the batch raises KeyboardInterrupt, and
    the next batch prints them (once) and runs in lanes (it ran one state at a time for good before)."""
    from eomgen.printers import c_extension

    calls = []

    def interrupted_once(*args, real=c_extension.lanes_module):
        calls.append(args)
        if len(calls) == 1:
            raise KeyboardInterrupt
        return real(*args)

    monkeypatch.setattr(c_extension, "lanes_module", interrupted_once)
    system, _ = cart_pendulum()
    fc = eg.codegen(eg.derive(system), backend="c")
    params = {"m_c": 1.5, "m_p": 0.25, "l": 0.6, "g": 9.81}
    q, _, _ = eg.random_states(system, 11, np.random.default_rng(37))
    with pytest.raises(KeyboardInterrupt):
        fc.M(q, params)
    M = fc.M(q, params)
    fc.M(q, params)
    assert len(calls) == 2
    np.testing.assert_allclose(M, [fc.M(qk, params) for qk in q], rtol=1e-14, atol=1e-14)


def test_sin_and_cos_of_a_parameter_in_vector_registers(tmp_path, monkeypatch):
    """A placement turned by a symbolic angle φ: the vector functions read sin φ and cos φ of the
    parameter lanes; they compile (no fallback warning) and the batch equals Pinocchio's crba with
    the rotation by φ in numbers."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    phi = sp.Symbol("phi")

    def arm(angle):
        c, s = sp.cos(angle), sp.sin(angle)
        system = eg.System(gravity=(0, 0, -9.81))
        a = system.add_body("a", joint=eg.Revolute("j0", axis=(0, 1, 0)), mass=1.0, com=(0.1, 0, -0.3),
                            inertia=np.diag([0.01, 0.02, 0.015]))
        system.add_body("b", parent=a, joint=eg.Revolute("j1", axis=(1, 0, 0)), mass=2.0,
                        com=(0.1, 0.05, -0.3), inertia=np.diag([0.01, 0.02, 0.015]),
                        placement=eg.Placement(rotation=sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]]),
                                               translation=(0, 0, -0.5)))
        return system

    fc = eg.codegen(eg.derive(arm(phi)), backend="c")
    q = np.random.default_rng(5).uniform(-2, 2, (11, 2))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the vector module's fallback is a warning
        batch = fc.M(q, params={"phi": 0.3})
    model = to_pinocchio(arm(sp.Float(0.3)))
    data = model.createData()
    for k in range(len(q)):
        close(batch[k], mass_matrix(model, data, q[k]), 1e-12, f"M {k}")


@pytest.mark.parametrize("n", [1, 8, 17])
def test_out_sharing_memory_with_an_input_is_refused(ur5, n):
    """A work buffer whose views are q and out (the C batches wrote M over states not read yet: errors ~3
    for N ≥ 8) is refused on both backends, naming out and the input; views of one buffer that do not
    overlap give Pinocchio's M and nle."""
    system, fc, fn = ur5
    q, u, _ = eg.random_states(system, n, np.random.default_rng(34))
    M, nle, _ = pinocchio(system, q, u)
    for f in (fc, fn):
        buffer = np.zeros(n * 36 + n * 12)
        out, qs = buffer[:n * 36].reshape(n, 6, 6), buffer[:n * 6].reshape(n, 6)
        us = buffer[-n * 6:].reshape(n, 6)
        qs[...] = q
        with pytest.raises(ValueError, match="out: shares memory with the input q"):
            f.M(qs, out=out)
        us[...] = u
        with pytest.raises(ValueError, match="out: shares memory with the input u"):
            f.nle(q, us, out=us)
        apart = buffer[n * 36:n * 42].reshape(n, 6)
        apart[...] = q
        np.testing.assert_allclose(f.M(apart, out=out), M, atol=1e-12)
        np.testing.assert_allclose(f.nle(apart, us, out=buffer[:n * 6].reshape(n, 6)), nle, atol=1e-10)
