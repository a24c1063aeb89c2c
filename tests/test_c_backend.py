"""The C backend: the same functions compiled, equal to NumPy and Pinocchio, deterministic source."""
from pathlib import Path

import numpy as np
import pytest

import eomgen as eg
from eomgen.model import pinocchio_configuration
from eomgen.verify import verify
from models import close


@pytest.mark.parametrize("name,method", [("ur5", "recursive"), ("panda", "projected_newton_euler"),
                                         ("solo12", "recursive")])
def test_c_equals_numpy_and_pinocchio(name, method, generated, eomgen_cache):
    system = eg.robots.load(name)
    fc, fn = generated(name, method, "c"), generated(name, method, "numpy")
    q, u, _ = eg.random_states(system, 50, np.random.default_rng(13))
    for key, c, py in [("M", fc.M(q), fn.M(q)), ("b", fc.b(q, u), fn.b(q, u)), ("g", fc.g(q), fn.g(q))]:
        np.testing.assert_allclose(c, py, rtol=1e-12, atol=1e-12, err_msg=key)
    np.testing.assert_allclose(fc.M(q[0]), fn.M(q[0]), rtol=1e-12, atol=1e-12)
    report = verify(system, method=method, backend="c", states=10)
    assert report.ok(1e-10), str(report)
    assert any(Path(eomgen_cache).glob("eomgen_*.so"))  # compiled once, in the run's cache


def test_write_c_is_deterministic_and_compiles(tmp_path):
    import subprocess

    eom = eg.derive(eg.robots.load("ur5"), method="recursive")
    c1, h1 = eg.write_c(eom, tmp_path / "a", name="ur5")
    c2, h2 = eg.write_c(eg.derive(eg.robots.load("ur5"), method="recursive"), tmp_path / "b", name="ur5")
    assert c1.read_bytes() == c2.read_bytes() and h1.read_bytes() == h2.read_bytes()
    main = tmp_path / "a" / "main.c"
    main.write_text('#include <stdio.h>\n#include "ur5.h"\nint main(void) { double q[6] = {0}, u[6] = {0},'
                    ' ud[6] = {0}, p[1] = {0}, M[36] = {0}; ur5_M(q, u, ud, p, M); printf("%.12f\\n", M[0]); return 0; }\n')
    exe = tmp_path / "a" / "main"
    subprocess.run(["cc", str(main), str(c1), "-o", str(exe), "-lm"], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    assert abs(float(out) - eg.codegen(eom).M(np.zeros(6))[0, 0]) < 1e-10
    g_only = eg.derive(eg.robots.load("ur5"), method="recursive", quantities=("g",), frames=["tool0"])
    c3, h3 = eg.write_c(g_only, tmp_path / "c", name="gc")
    header = h3.read_text()
    assert "gc_g(" in header and "gc_M(" not in header and "frame tool0" in header and "gc_J_0(" in header


def test_no_compiler_is_a_clear_error(monkeypatch):
    monkeypatch.setenv("CC", "/nonexistent/cc")
    eom = eg.derive(eg.robots.load("double_pendulum"))
    with pytest.raises(eg.ModelError, match="no C compiler found.*NumPy backend works without one"):
        eg.codegen(eom, backend="c")
    assert eg.codegen(eom).M(np.zeros(2)).shape == (2, 2)


def test_no_python_headers_is_a_clear_error(monkeypatch, tmp_path):
    from eomgen.printers.build import extension

    monkeypatch.setattr(extension.sysconfig, "get_paths", lambda: {"include": str(tmp_path)})
    eom = eg.derive(eg.robots.load("double_pendulum"))
    with pytest.raises(eg.ModelError, match="needs the Python headers.*NumPy backend works without them"):
        eg.codegen(eom, backend="c")


def test_ur5_operation_counts_and_nonlinear_effects(generated):
    """ur5 with numeric parameters: M in at most 250 multiplications, b + g (one pass) in at most 350;
    nle = Pinocchio's nonLinearEffects."""
    import pinocchio as pin

    system = eg.robots.load("ur5")
    f = generated("ur5", "recursive", "numpy")
    assert f.multiplications["M"] <= 250 and f.multiplications["nle"] <= 350, f.multiplications
    model = system.pinocchio_model
    data = model.createData()
    q, u, _ = eg.random_states(system, 10, np.random.default_rng(17))
    for k in range(10):
        np.testing.assert_allclose(f.nle(q[k], u[k]), pin.nonLinearEffects(model, data, q[k], u[k]), rtol=0, atol=1e-10)


def test_extension_inputs_parameters_and_frames(tmp_path, monkeypatch):
    """Symbolic parameters, frame Jacobians (a module built on first use), the NumPy backend's errors,
    and one state = the same state in a batch (vector sin / cos there) to a few ulps."""
    import sympy as sp

    from models import cart_pendulum

    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system, (m_c, m_p, l, g) = cart_pendulum()
    eom = eg.derive(system)
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    params = {"m_c": 2.0, "m_p": 0.5, "l": 0.8, "g": 9.81}
    q, u, _ = eg.random_states(system, 300, np.random.default_rng(3))
    for key in ("M", "b", "g", "tau"):
        args = (q,) if key in ("M", "g") else (q, u)
        np.testing.assert_allclose(getattr(fc, key)(*args, params=params), getattr(fn, key)(*args, params=params),
                                   rtol=1e-13, atol=1e-14, err_msg=key)
    np.testing.assert_allclose(fc.jacobian("tip", q, params), fn.jacobian("tip", q, params), rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(fc.reference("J:tip", q[0], params=params).astype(float), fn.jacobian("tip", q[0], params),
                               rtol=1e-15, atol=1e-15)  # 50-digit reference of a compiled function
    M_closed = sp.lambdify([*system.q, m_c, m_p, l], eom.M.subs(g, 9.81))
    np.testing.assert_allclose(fc.M(q[7], params), M_closed(*q[7], 2.0, 0.5, 0.8), rtol=1e-14)
    one = np.array([fc.b(q[k], u[k], params) for k in range(300)])
    np.testing.assert_allclose(fc.b(q, u, params), one, rtol=1e-14, atol=1e-14)
    with pytest.raises(eg.ModelError, match=r"values missing for the parameters \['l', 'm_p'\]"):
        fc.M(q[0], {"m_c": 1.0})
    with pytest.raises(ValueError, match=r"q: expected shape \(2,\) or \(N, 2\), got \(3,\)"):
        fc.M(np.zeros(3), params)
    with pytest.raises(ValueError, match=r"u: expected shape \(300, 2\), got \(2,\)"):
        fc.b(q, u[0], params)
    with pytest.raises(ValueError, match="u: contains NaN or infinite values"):
        fc.b(q[0], [0.0, np.nan], params)
    for bad in (np.zeros(3), "abc"):  # the NumPy backend says the same
        with pytest.raises(ValueError):
            fn.M(bad, params)


def test_b_and_g_compiled_on_first_use(tmp_path, monkeypatch):
    """The build up front compiles M and nle only (b and g are nle's two parts, 40 % of the C text); the
    first request of b or g compiles both in one more module; each equals Pinocchio."""
    import pinocchio as pin

    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system = eg.robots.load("ur5")
    f = eg.codegen(eg.derive(system, method="recursive"), backend="c")

    def modules() -> dict:
        return {key: fn.function.__self__.__name__ for key, fn in f.functions.items()}

    assert set(modules()) == {"M", "nle"} and len(set(modules().values())) == 1
    model = system.pinocchio_model
    data = model.createData()
    q, u, _ = eg.random_states(system, 3, np.random.default_rng(4))
    for qk, uk, qp in zip(q, u, pinocchio_configuration(system, q)):  # one state at a time: no batch module
        g = pin.computeGeneralizedGravity(model, data, qp)
        close(f.g(qk), g, 1e-12, "g")
        close(f.b(qk, uk), pin.nonLinearEffects(model, data, qp, uk) - g, 1e-12, "b")
        close(f.nle(qk, uk), pin.nonLinearEffects(model, data, qp, uk), 1e-12, "nle")
        close(f.M(qk), pin.crba(model, data, qp), 1e-12, "M")
    up_front, later = modules()["M"], modules()["b"]
    assert modules() == {"M": up_front, "nle": up_front, "b": later, "g": later} and later != up_front


def test_extension_is_cached(tmp_path, monkeypatch):
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    eom = eg.derive(eg.robots.load("double_pendulum"), method="recursive")
    eg.codegen(eom, backend="c")
    built = {p: p.stat().st_mtime_ns for p in tmp_path.iterdir()}
    assert len([p for p in built if p.suffix == ".so"]) == 1
    f = eg.codegen(eom, backend="c")
    assert {p: p.stat().st_mtime_ns for p in tmp_path.iterdir()} == built
    assert f.M(np.zeros(2)).shape == (2, 2)


@pytest.mark.slow
@pytest.mark.parametrize("name", eg.robots.names(floating_base=False) + eg.robots.names(floating_base=True))
def test_every_robot_compiled(name, tmp_path, monkeypatch):
    """Every robot of the earlier tests, compiled: C = NumPy to 1e-12 (batched and one state) and
    = Pinocchio to 1e-10 (M, b, g, end-frame J and J̇u). Run with -m slow."""
    import warnings

    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # files with inertias Pinocchio takes as they are
        system = eg.robots.load(name)
    report = verify(system, method="recursive", backend="c", states=10, seed=3)
    assert report.ok(1e-10), str(report)
    eom = eg.derive(system, method="recursive")
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    q, u, _ = eg.random_states(system, 20, np.random.default_rng(14))
    for key, c, py in [("M", fc.M(q), fn.M(q)), ("b", fc.b(q, u), fn.b(q, u)), ("g", fc.g(q), fn.g(q)),
                       ("M one state", fc.M(q[0]), fn.M(q[0])), ("b one state", fc.b(q[0], u[0]), fn.b(q[0], u[0]))]:
        np.testing.assert_allclose(c, py, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(py).max()), err_msg=key)


def test_example_runs(tmp_path, capsys):
    import runpy
    import sys

    argv = sys.argv
    sys.argv = ["compiled_robot.py", str(tmp_path / "ur5_c")]
    try:
        runpy.run_path(str(Path(__file__).parents[1] / "examples" / "compiled_robot.py"), run_name="__main__")
    finally:
        sys.argv = argv
    out = capsys.readouterr().out
    assert "OK (tolerance 1e-10)" in out and "149 operations for g" in out
    assert (tmp_path / "ur5_c" / "ur5.h").exists()


def test_the_whole_function_set_compiled(tmp_path, monkeypatch):
    """Everything NumericEoM offers runs compiled and equals NumPy: T, U, τ, a load's τ, the free cut's
    joint wrenches and reactions, the forward dynamics, and (solo12) the contact dynamics."""
    from models import cart_pendulum

    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system, _ = cart_pendulum()
    system.add_spring(("pendulum", (0, -1, 0)), (None, (0.5, -2.0, 0)), 20.0, name="spring")
    eom = eg.derive(system, method="free_cut")
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    p = {"m_c": 2.0, "m_p": 0.5, "l": 0.8, "g": 9.81}
    rng = np.random.default_rng(27)
    q, u, ud = rng.uniform(-2, 2, 2), rng.uniform(-2, 2, 2), rng.uniform(-2, 2, 2)
    pairs = [(fc.T(q, u, p), fn.T(q, u, p)), (fc.U(q, p), fn.U(q, p)), (fc.tau(q, u, p), fn.tau(q, u, p)),
             (fc.tau_of("spring", q, u, p), fn.tau_of("spring", q, u, p)),
             (fc.forward_dynamics(q, u, [1.5, -0.3], p), fn.forward_dynamics(q, u, [1.5, -0.3], p)),
             (fc.joint_wrench("phi", q, u, ud, p), fn.joint_wrench("phi", q, u, ud, p)),
             (fc.reactions(q, u, [1.5, -0.3], p)["phi"], fn.reactions(q, u, [1.5, -0.3], p)["phi"])]
    for c, py in pairs:
        np.testing.assert_allclose(c, py, rtol=1e-13, atol=1e-13)
    solo = eg.robots.load("solo12")
    for foot in ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"):
        solo.add_contact(foot, "point")
    eom = eg.derive(solo, method="recursive")
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    q, u, _ = eg.random_states(solo, 1, rng)
    for c, py in zip(fc.constrained_dynamics(q[0], u[0], np.ones(12)), fn.constrained_dynamics(q[0], u[0], np.ones(12))):
        np.testing.assert_allclose(c, py, rtol=1e-10, atol=1e-10)


def test_large_batches_run_over_the_cores(generated):
    """Batches of 16 blocks and more go over the cores (OpenMP): the same numbers as NumPy, last and
    partial block included."""
    system = eg.robots.load("panda")
    fc, fn = generated("panda", "recursive", "c"), generated("panda", "recursive", "numpy")
    q, u, _ = eg.random_states(system, 64 * 40 + 7, np.random.default_rng(28))
    for c, py in [(fc.M(q), fn.M(q)), (fc.b(q, u), fn.b(q, u)), (fc.nle(q, u), fn.nle(q, u))]:
        np.testing.assert_allclose(c, py, rtol=1e-12, atol=1e-12)


def test_write_c_vector_trig_equals_pinocchio(tmp_path):
    """Compiled for this machine, the plain C's sines and cosines come from glibc's vector functions
    (libmvec); M, b + g and the inverse dynamics still equal Pinocchio's crba, nonLinearEffects and rnea.
    Without the derivatives, their functions are not written."""
    import subprocess

    import pinocchio as pin

    system = eg.robots.load("panda")
    eom = eg.derive(system)
    c_path, h_path = eg.write_c(eom, tmp_path, name="panda", derivatives=False)
    header = h_path.read_text()
    assert "panda_ID(" in header and "_derivatives" not in header
    (tmp_path / "main.c").write_text(r"""#include <stdio.h>
#include "panda.h"
int main(void)
{
    double q[PANDA_NQ], u[PANDA_NV], ud[PANDA_NV], p[1] = {0};
    while (1) {
        double M[PANDA_NV * PANDA_NV] = {0}, h[PANDA_NV] = {0}, tau[PANDA_NV] = {0};
        for (int i = 0; i < PANDA_NQ; i++) if (scanf("%lf", &q[i]) != 1) return 0;
        for (int i = 0; i < PANDA_NV; i++) if (scanf("%lf", &u[i]) != 1) return 1;
        for (int i = 0; i < PANDA_NV; i++) if (scanf("%lf", &ud[i]) != 1) return 1;
        panda_M(q, u, ud, p, M), panda_nle(q, u, ud, p, h), panda_ID(q, u, ud, p, tau);
        for (int i = 0; i < PANDA_NV * PANDA_NV; i++) printf("%.17g ", M[i]);
        for (int i = 0; i < PANDA_NV; i++) printf("%.17g %.17g ", h[i], tau[i]);
        printf("\n");
    }
}
""")
    exe = tmp_path / "main"
    subprocess.run(["cc", "-O3", "-march=native", "-Wall", "-Werror", str(tmp_path / "main.c"), str(c_path),
                    "-o", str(exe), "-lm"], check=True)
    symbols = subprocess.run(["nm", str(exe)], capture_output=True, text=True, check=True).stdout
    assert "_ZGV" in symbols  # glibc's vector sin and cos are called
    q, u, ud = eg.random_states(system, 20, np.random.default_rng(1))
    states = "".join(" ".join(repr(float(x)) for x in np.concatenate(s)) + "\n" for s in zip(q, u, ud))
    lines = subprocess.run([str(exe)], input=states,
                           capture_output=True, text=True, check=True).stdout.splitlines()
    model, nv = system.pinocchio_model, system.nv
    data = model.createData()
    for k, line in enumerate(lines):
        values = np.array(line.split(), float)
        qp = pinocchio_configuration(system, q[k])
        M = pin.crba(model, data, qp)
        close(values[:nv * nv].reshape(nv, nv), np.triu(M) + np.triu(M, 1).T, 1e-12, f"M {k}")
        close(values[nv * nv::2], pin.nonLinearEffects(model, data, qp, u[k]), 1e-12, f"nle {k}")
        close(values[nv * nv + 1::2], pin.rnea(model, data, qp, u[k], ud[k]), 1e-12, f"ID {k}")
    assert len(lines) == 20
