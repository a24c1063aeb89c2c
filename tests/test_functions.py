"""The elementary functions, Min, Max, sign, Heaviside, Piecewise and general powers in loads and
placements: every output path equals sympy's own evaluation, on every branch; their derivative rules
equal sympy's diff; anything else is a clear error."""
import subprocess

import numpy as np
import pytest
import sympy as sp

import eomgen as eg
from eomgen.subexpressions import Subexpressions


def functions_of(x: sp.Expr, y: sp.Expr, v: sp.Expr) -> list[sp.Expr]:
    """Every covered function of x, y in [-2, 2] and v (branches at 0, x = y, y = 0.2, ...)."""
    return [sp.tan(x / 3) + sp.exp(-y**2) * v, sp.log(2 + sp.sin(x)) + sp.atan2(y, x) - sp.atan(v),
            sp.asin(x / 3) * sp.acos(y / 3) + sp.sinh(x / 2) - sp.cosh(y) * sp.tanh(v),
            sp.Abs(x - y) + sp.sign(v) + sp.Heaviside(y - sp.Rational(1, 5)) + sp.Heaviside(x, 0),
            sp.Min(x, y, sp.Rational(3, 10)) * sp.Max(x, -y, v) + sp.Max(x, 0) + (2 + sp.cos(x))**1.5,
            sp.Piecewise((7 * (-x)**1.5, x < 0), (x * y, sp.And(x <= 1, y > 0)),
                         (v, sp.Or(sp.Eq(x, y), y >= 1)), (x + 2, sp.Not(sp.And(y < -1, v < 0))), (-3, True))
            + sp.Piecewise((sp.sqrt(x) + sp.log(x), x > 0), (y**3, sp.Ne(x, y)), (1 - y, True))
            + sp.Piecewise((sp.asin(x), sp.Abs(x) <= 1), (sp.acos(1 / x), True)) + (3 + y)**-3]


def model() -> tuple[eg.System, list[sp.Symbol]]:
    x, y = sp.symbols("x y")
    system = eg.System(gravity=(0, 0, 0))
    a = system.add_body("a", joint=eg.Revolute("x", axis=(0, 0, 1)), mass=1, com=(0.5, 0, 0))
    b = system.add_body("b", parent=a, joint=eg.Prismatic("y", axis=(1, 0, 0)), mass=2,
                        placement=eg.Placement(translation=(1, 0, 0)))
    q0, q1 = system.q
    u0, u1 = system.u
    f = functions_of(q0, q1, u0)
    system.add_torque(a, (0, 0, f[0] + f[1]))
    system.add_torque(b, (f[2], f[3], f[4]))
    system.add_force(b, (f[5], f[3] * u1, 0), point=(0.3, 0.1, 0))
    return system, [q0, q1, u0, u1]


def states() -> np.ndarray:
    """[q0, q1, u0, u1]: random states and states on the boundaries of the branches."""
    rng = np.random.default_rng(5)
    special = [[0.5, 0.5, 0.0, 1.0], [-0.7, 0.2, -1.0, 0.0], [0.0, -1.5, -0.5, 2.0], [1.5, 1.5, 0.3, -1.0],
               [0.8, -0.3, 0.0, 0.0], [1.2, -1.5, -0.4, 0.5], [-1.0, 1.2, 1.0, 1.0], [0.3, 0.0, 2.0, -2.0],
               [1.7, -1.2, 0.5, 0.2], [0.9, 1.0, -0.2, 0.1], [-0.4, 0.9, 0.0, 0.0]]
    return np.vstack([special, rng.uniform(-2, 2, (30, 4))])


def exact(expr: sp.Expr, symbols: list[sp.Symbol], values) -> float:
    """sympy's own value at exact inputs (the conditions decided exactly)."""
    return float(expr.xreplace({s: sp.Float(float(v), 40) for s, v in zip(symbols, values)}).evalf(30))


@pytest.fixture(scope="module")
def derived():
    system, symbols = model()
    eom = eg.derive(system)
    X = states()
    tau = [[exact(t, symbols, x) for t in eom.tau] for x in X]
    return eom, symbols, X, np.array(tau)


def test_tau_every_path(derived, tmp_path, monkeypatch):
    """NumPy one state and a batch, C one state and a batch, mpmath: sympy's values."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    eom, _, X, tau = derived
    q, u = X[:, :2], X[:, 2:]
    fn, fc = eg.codegen(eom), eg.codegen(eom, backend="c")
    for k, row in enumerate(tau):
        np.testing.assert_allclose(fn.tau(q[k], u[k]), row, rtol=1e-12, atol=1e-12, err_msg=str(X[k]))
        np.testing.assert_allclose(fc.tau(q[k], u[k]), row, rtol=1e-12, atol=1e-12, err_msg=str(X[k]))
        if q[k, 0] == 0:  # mpmath divides exactly: the pole of acos(1/x) in the branch not taken raises
            with pytest.raises(ZeroDivisionError):
                fn.reference("tau", q[k], u[k])
            continue
        reference = np.array(fn.reference("tau", q[k], u[k])[:, 0], dtype=float)
        np.testing.assert_allclose(reference, row, rtol=1e-14, atol=1e-14, err_msg=str(X[k]))
    with np.errstate(invalid="ignore"):  # the branches not taken: (-x)**1.5 at x > 0, ...
        np.testing.assert_allclose(fn.tau(q, u), tau, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fc.tau(q, u), tau, rtol=1e-12, atol=1e-12)
    python = fn.functions["tau"].source
    assert all(f"m.{g}(" in python for g in ("arctan2", "arcsin", "fmin", "where", "heaviside"))
    assert all(g in fc.functions["tau"].source for g in ("atan2(", "asin(", "fmin(", " ? ", "pow("))


def placed_model() -> tuple[eg.System, sp.Symbol, list[str]]:
    """The functions of a parameter s in frame placements: in J, so in write_c and write_module."""
    s = sp.Symbol("s")
    system = eg.System()
    a = system.add_body("a", joint=eg.Revolute("x", axis=(0, 0, 1)), mass=1, com=(0.5, 0, 0))
    f = functions_of(s, s / 2 - sp.Rational(1, 2), 2 * s)
    frames = []
    for k in range(0, len(f), 2):
        frames.append(f"f{k}")
        system.add_frame(f"f{k}", a, eg.Placement(translation=(f[k], f[k + 1] if k + 1 < len(f) else s, 0)))
    return system, s, frames


def test_write_c_and_module(tmp_path):
    """Plain C compiled with a driver, and the numpy-only module, at parameters on each branch."""
    import importlib.util

    system, s, frames = placed_model()
    eom = eg.derive(system)
    c_path, _ = eg.write_c(eom, tmp_path, name="fn", frames=frames)
    calls = "".join(f"fn_J_{k}(q, u, ud, p, J); for (int i = 0; i < 6; ++i) printf(\"%.17g\\n\", J[i]);"
                    for k in range(len(frames)))
    main = tmp_path / "main.c"
    main.write_text('#include <stdio.h>\n#include <stdlib.h>\n#include "fn.h"\n'
                    'int main(int argc, char **argv) {'
                    ' double q[1] = {atof(argv[1])}, u[1] = {0}, ud[1] = {0},'
                    ' p[1] = {atof(argv[2])}, J[6];'
                    f" {calls} return 0; }}\n")
    subprocess.run(["cc", str(main), str(c_path), "-o", str(tmp_path / "main"), "-lm"], check=True)
    module_path = eg.write_module(eom, tmp_path / "fn_eom.py", frames=frames)
    spec = importlib.util.spec_from_file_location("fn_eom", module_path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    q0 = system.q[0]
    jacobians = [eom.subexpressions.inline(eom.kinematics.jacobian(f)) for f in frames]
    for x, value in [(0.4, -0.8), (1.1, 0.0), (-0.3, 0.7), (2.0, 1.0), (0.9, 1.5), (-1.2, 2.3)]:
        expected = np.array([[exact(e, [q0, s], [x, value]) for e in J[:, 0]] for J in jacobians])
        out = subprocess.run([str(tmp_path / "main"), repr(x), repr(value)], capture_output=True, text=True,
                             check=True).stdout
        close = dict(rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(np.array(out.split(), float).reshape(-1, 6), expected, **close)
        for k, f in enumerate(frames):
            np.testing.assert_allclose(module.jacobian(f, [x], {"s": value})[:, 0], expected[k], **close)
            batch = module.jacobian(f, [[x], [x]], {"s": value})
            np.testing.assert_allclose(batch[1, :, 0], expected[k], **close)


def test_derivative_rules_equal_sympy():
    """The forward-mode rules, directly and through intermediates, against sympy's diff on real symbols."""
    x, y, v = sp.symbols("x y v", real=True)
    dx, dy, dv = sp.symbols("dx dy dv", real=True)
    rng = np.random.default_rng(9)
    points = [*rng.uniform(-2, 2, (16, 3)), [-0.7, 1.3, -0.2], [1.5, -1.6, -0.3]]  # no kinks: sympy's diff
    # takes the mean there (Heaviside(0) = 1/2), the rules one side
    for f in functions_of(x, y, v):
        sub = Subexpressions()
        named = sub.add(sp.sin(x) + y)  # an intermediate inside the function
        g = f.xreplace({y: named - sp.sin(x)})
        direct = sub.derivative(f, {x: dx, y: dy, v: dv}, "d")
        chained = sub.inline(sub.derivative(sub.add(g * 1), {x: dx, y: dy, v: dv}, "d"))
        expected = sum(sp.diff(f, s) * ds for s, ds in ((x, dx), (y, dy), (v, dv)))
        for p in points:
            at = {x: p[0], y: p[1], v: p[2], dx: 0.3, dy: -1.1, dv: 0.7}
            want = complex(expected.subs(at).evalf())
            for got in (direct, chained):
                assert abs(complex(sp.sympify(got).subs(at).evalf()) - want) < 1e-9 * (1 + abs(want)), (f, p)


X, T = sp.symbols("x t")


@pytest.mark.parametrize("load,name", [(sp.Function("friction")(X), "friction"),
                                       (sp.Derivative(sp.Function("h")(X), X), "Derivative"),
                                       (sp.Integral(T**2, T), "Integral"), (sp.I * X, "ImaginaryUnit"),
                                       (sp.zeta(X), "zeta")])
def test_unsupported_is_a_clear_error(load, name):
    """Refused where the load enters (functions of time, derivatives, integrals), or where its code is
    written."""
    system = eg.System()
    a = system.add_body("a", joint=eg.Revolute("x", axis=(0, 0, 1)), mass=1, com=(0.5, 0, 0))
    x = system.q[0]
    with pytest.raises(eg.ModelError, match=name):
        system.add_torque(a, (0, 0, sp.sympify(load).xreplace({X: x})))
        eg.codegen(eg.derive(system)).tau([0.1], [0.2], params={"t": 1.0})


def test_no_value_or_no_number_is_a_clear_error():
    """What the model's checks let through no longer: a symbol that is no input, infinity, a condition."""
    from eomgen.printers.syntax import C
    from eomgen.printers.walker import Printer

    x = sp.Symbol("x")
    for expr, name in [(sp.Piecewise((1, sp.Symbol("w") > 0), (0, True)), "symbol w: it is no coordinate"),
                       (sp.oo * x, "Infinity"),
                       (sp.Piecewise((1, sp.Xor(x > 0, x < 1)), (0, True)), "condition Xor")]:
        for syntax in ({}, {"syntax": C}):
            with pytest.raises(eg.ModelError, match=name):
                Printer({x: "_q0"}, **syntax)(expr)
