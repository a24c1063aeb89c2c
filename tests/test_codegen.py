"""NumPy functions: equal to the closed forms evaluated independently, deterministic, and free of
any text taken from the model."""
import ast
import re

import numpy as np
import pytest
import sympy as sp

import eomgen as eg
from models import cart_pendulum, spatial_arm_3dof


def test_functions_equal_closed_forms_by_lambdify():
    system = spatial_arm_3dof()
    eom = eg.derive(system)
    f = eg.codegen(eom)
    rng = np.random.default_rng(5)
    params = {s: rng.uniform(0.2, 1.5) for s in system.parameters}
    q, u = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3)
    subs = {**params, **dict(zip(system.q, q)), **dict(zip(system.u, u))}
    for name, got in [("M", f.M(q, params)), ("b", f.b(q, u, params)), ("g", f.g(q, params))]:
        closed = getattr(eom, name).xreplace({k: sp.Float(v, 30) for k, v in subs.items()}).evalf(30)
        np.testing.assert_allclose(got, np.array(closed.tolist(), float).reshape(got.shape), rtol=1e-12, atol=1e-12)


def test_deterministic_source():
    a = eg.codegen(eg.derive(spatial_arm_3dof()))
    b = eg.codegen(eg.derive(spatial_arm_3dof()))
    assert a.sources == b.sources


def test_the_same_source_is_compiled_once_into_new_functions():
    """Python compiles a text once per process; each function made from it has its own globals."""
    from eomgen.printers.python import compile_function

    source = "def f(x):\n    global calls\n    calls = globals().get('calls', 0) + 1\n    return x + calls\n"
    f, g = compile_function(source, "counter"), compile_function(source, "counter")
    assert f is not g and f.__code__ is g.__code__
    assert (f(1), f(1), g(1)) == (2, 3, 2)


def test_names_never_reach_the_source():
    evil = "q'); import os; os.system('echo pwned') #\n"
    system = eg.System(gravity=(0, -9.81, 0))
    body = system.add_body('arm"""\nimport os', joint=eg.Revolute(evil, axis=(0, 0, 1)), mass=1.0, com=(0.5, 0, 0))
    system.add_frame("tip'\n__import__('os')", body, eg.Placement(translation=(1, 0, 0)))
    system.add_force(body, (sp.Symbol("F'); import os #"), 0, 0), point=(1, 0, 0), name="push\nimport sys")
    f = eg.codegen(eg.derive(system))
    f.jacobian("tip'\n__import__('os')", [0.3])
    for source in f.sources.values():
        tree = ast.parse(source)
        names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
        assert all(re.fullmatch(r"_((sin|cos)_)?(q|u|ud|p|x)\d+|q|u|ud|p|out|sin|cos|sqrt", n) for n in names), names
        assert not any(isinstance(n, (ast.Import, ast.ImportFrom)) for n in ast.walk(tree))
        assert all(isinstance(c.value, (int, float)) for c in ast.walk(tree) if isinstance(c, ast.Constant))
        assert not any(isinstance(n, ast.Attribute) for n in ast.walk(tree))
    np.testing.assert_allclose(f.g([0.3]), [9.81 * 0.5 * np.cos(0.3)])
    np.testing.assert_allclose(f.tau([0.3], [0.0], {"F'); import os #": 2.0}), [-2.0 * np.sin(0.3)])


def test_cart_pendulum_numbers():
    system, _ = cart_pendulum()
    f = eg.codegen(eg.derive(system, method="lagrange"))
    m_c, m_p, l, g = 1.2, 0.4, 0.8, 9.81
    p = {"m_c": m_c, "m_p": m_p, "l": l, "g": g}
    x, phi, xd, phid = 0.3, 0.9, -0.2, 1.7
    np.testing.assert_allclose(f.M([x, phi], p), [[m_c + m_p, m_p * l * np.cos(phi)],
                                                  [m_p * l * np.cos(phi), m_p * l**2]], rtol=1e-14)
    np.testing.assert_allclose(f.b([x, phi], [xd, phid], p), [-m_p * l * np.sin(phi) * phid**2, 0], atol=1e-15)
    np.testing.assert_allclose(f.g([x, phi], p), [0, m_p * g * l * np.sin(phi)], rtol=1e-14)


def test_entry_points_refuse_the_wrong_kind_of_model(tmp_path):
    system, _ = cart_pendulum()
    eom = eg.derive(system)
    for call in (lambda: eg.codegen(system), lambda: eg.codegen(system, backend="c"),
                 lambda: eg.write_module(system, tmp_path / "m.py")):
        with pytest.raises(eg.ModelError, match=r": expected EquationsOfMotion.*, got System \(derive"):
            call()
    with pytest.raises(eg.ModelError, match="verify: expected a System .*, got EquationsOfMotion"):
        eg.verify(eom)
    with pytest.raises(eg.ModelError, match="q: expected real numbers, got dict"):
        eg.codegen(eom).M({"x": 0.1, "phi": 0.2}, {"m_c": 1, "m_p": 0.5, "l": 0.7, "g": 9.81})
