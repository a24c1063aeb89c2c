"""Every output path computes the same equations, with the parameters given by name everywhere and
bound once: NumPy functions, the written module, the C extension and plain C (write_c)."""
from __future__ import annotations

import importlib.util
import re
import subprocess

import numpy as np
import pytest
import sympy as sp

import eomgen as eg
from models import double_pendulum

P = {"m_c": 1.3, "m_p": 0.6, "l": 0.8, "g": 9.81, "k": 25.0, "F": 2.5}


def spring_cart_pendulum(frame: str = "tip"):
    """The getting-started cart-pendulum (only the cart actuated) with a spring from the world origin to the
    pendulum's tip and a horizontal force F on the cart."""
    m_c, m_p, l, g, k, F = sp.symbols("m_c m_p l g k F", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    cart = system.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=m_c)
    pend = system.add_body("pendulum", parent=cart, joint=eg.Revolute("phi", axis=(0, 0, 1), actuated=False),
                           mass=m_p, com=(0, -l, 0))
    system.add_frame(frame, body=pend, placement=eg.Placement(translation=(0, -l, 0)))
    system.add_spring(None, frame, stiffness=k, name="spring")
    system.add_force(cart, (F, 0, 0), name="push")
    return system


def by_hand(q, u, tau_a):
    """M, b, g, τ and u̇ of `spring_cart_pendulum` written out: tip r = (x + l sin φ, −l cos φ),
    spring force −k r through J = ∂r/∂q, push F on x; u̇ = M⁻¹ (τ + Sᵀ τ_a − b − g), S = [1, 0]."""
    m_c, m_p, l, g, k, F = (P[n] for n in ("m_c", "m_p", "l", "g", "k", "F"))
    (x, phi), (_, phid) = q, u
    M = np.array([[m_c + m_p, m_p * l * np.cos(phi)], [m_p * l * np.cos(phi), m_p * l**2]])
    b = np.array([-m_p * l * np.sin(phi) * phid**2, 0.0])
    G = np.array([0.0, m_p * g * l * np.sin(phi)])
    r = np.array([x + l * np.sin(phi), -l * np.cos(phi)])
    J = np.array([[1.0, l * np.cos(phi)], [0.0, l * np.sin(phi)]])
    tau = J.T @ (-k * r) + np.array([F, 0.0])
    return M, b, G, tau, np.linalg.solve(M, tau + np.array([tau_a, 0.0]) - b - G)


def load(path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path / "cache"))


def states(n, seed=3):
    rng = np.random.default_rng(seed)
    return rng.uniform(-2, 2, (n, 2)), rng.uniform(-2, 2, (n, 2)), rng.uniform(-5, 5, n)


def test_module_forward_dynamics_has_the_loads(tmp_path):
    eom = eg.derive(spring_cart_pendulum())
    f = eg.codegen(eom)
    m = load(eg.write_module(eom, tmp_path / "cp_eom.py"))
    assert m.ACTUATED == ("x",) and m.S.tolist() == [[1.0, 0.0]]
    q, u, tau_a = states(20)
    for k in range(20):
        M, b, G, tau, ud = by_hand(q[k], u[k], tau_a[k])
        for got in (m.forward_dynamics(q[k], u[k], [tau_a[k]], P),
                    f.forward_dynamics(q[k], u[k], [tau_a[k]], P)):
            np.testing.assert_allclose(got, ud, rtol=1e-12, atol=1e-12)
        for got in (m.tau(q[k], u[k], P), f.tau(q[k], u[k], P)):
            np.testing.assert_allclose(got, tau, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(m.M(q[k], P), M, rtol=1e-13)
        np.testing.assert_allclose(m.b(q[k], u[k], P) + m.g(q[k], P), b + G, rtol=1e-12, atol=1e-12)
    batch = m.forward_dynamics(q, u, tau_a[:, None], P)
    np.testing.assert_allclose(batch, f.forward_dynamics(q, u, tau_a[:, None], P), rtol=1e-13, atol=1e-13)
    with pytest.raises(ValueError, match="tau_a: expected 1 finite values"):
        m.forward_dynamics(q[0], u[0], [1.0, 2.0], P)


def c_driver(directory, name: str, header: str, keys: list[tuple[str, int]], q, u) -> np.ndarray:
    """Evaluate <name>_<key> (out of `size` doubles) of plain C at the states, p filled in the
    header's index order from the comments `p[k]: name`; one row of outputs per state."""
    order = re.findall(r"^ \*   p\[(\d+)\]: (\S+)$", header, re.M)
    assert [int(k) for k, _ in order] == list(range(len(P)))
    p = ", ".join(repr(P[n]) for _, n in order)
    lines = ["#include <stdio.h>", f'#include "{name}.h"', "int main(void) {",
             f"    const double p[] = {{{p}}};", "    double ud[2] = {0};"]
    for qk, uk in zip(q, u):
        qs, us = (", ".join(repr(float(x)) for x in v) for v in (qk, uk))
        lines += ["    {", f"        const double q[] = {{{qs}}}, u[] = {{{us}}};"]
        for key, size in keys:
            lines += [f"        {{ double out[{size}] = {{0}}; {name}_{key}(q, u, ud, p, out);",
                      f'          for (int i = 0; i < {size}; ++i) printf("%.17g ", out[i]); }}']
        lines += ['        printf("\\n");', "    }"]
    (directory / "main.c").write_text("\n".join(lines + ["    return 0;", "}"]) + "\n")
    exe = directory / "main"
    subprocess.run(["cc", "-Wall", "-Werror", str(directory / "main.c"), str(directory / f"{name}.c"), "-o",
                    str(exe), "-lm"], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    return np.array([[float(x) for x in line.split()] for line in out.strip().split("\n")])


def placement_and_com(q):
    """The tip's [R | p] (rotation about z by φ, position (x + l sin φ, −l cos φ, 0)), the centre of mass
    c = (m_c (x, 0, 0) + m_p (x + l sin φ, −l cos φ, 0)) / (m_c + m_p) and its Jacobian ∂c/∂q, by hand."""
    m_c, m_p, l = P["m_c"], P["m_p"], P["l"]
    x, phi = q
    s, c = np.sin(phi), np.cos(phi)
    X = np.array([[c, -s, 0, x + l * s], [s, c, 0, -l * c], [0, 0, 1, 0]])
    com = np.array([x + m_p * l * s / (m_c + m_p), -m_p * l * c / (m_c + m_p), 0])
    J_com = np.array([[1, m_p * l * c / (m_c + m_p)], [0, m_p * l * s / (m_c + m_p)], [0, 0]])
    return np.concatenate([X.ravel(), com, J_com.ravel()])


def placed(R, p):
    return np.column_stack([R, p]).ravel()


def test_every_output_path_agrees(tmp_path, cache):
    eom = eg.derive(spring_cart_pendulum())
    q, u, _ = states(6)
    fn, fc = eg.codegen(eom), eg.codegen(eom, backend="c")
    m = load(eg.write_module(eom, tmp_path / "cp_eom.py"))
    _, h = eg.write_c(eom, tmp_path / "c", name="cp", frames=["tip"])
    keys = [("M", 4), ("b", 2), ("g", 2), ("tau", 2), ("J_0", 12), ("X_0", 12), ("com", 3), ("J_com", 6),
            ("A_G", 12)]
    plain = c_driver(tmp_path / "c", "cp", h.read_text(), keys, q, u)

    def outputs(f):
        return [np.concatenate([f.M(q[k], P).ravel(), f.b(q[k], u[k], P), f.g(q[k], P), f.tau(q[k], u[k], P),
                                f.jacobian("tip", q[k], P).ravel(), placed(*f.placement("tip", q[k], P)),
                                f.com(q[k], P), f.com_jacobian(q[k], P).ravel(),
                                f.centroidal_momentum_matrix(q[k], P).ravel()]) for k in range(len(q))]

    expected = np.array([np.concatenate([x.ravel() for x in by_hand(q[k], u[k], 0.0)[:4]])
                         for k in range(len(q))])
    kinematics = np.array([placement_and_com(q[k]) for k in range(len(q))])
    for label, got in [("numpy", outputs(fn)), ("module", outputs(m)), ("c extension", outputs(fc)),
                       ("write_c", plain)]:
        np.testing.assert_allclose(np.asarray(got)[:, :10], expected, rtol=1e-12, atol=1e-12, err_msg=label)
        np.testing.assert_allclose(np.asarray(got)[:, 22:43], kinematics, atol=1e-14, err_msg=label)
        np.testing.assert_allclose(got, plain, rtol=1e-13, atol=1e-13, err_msg=label)
    h_G = m.centroidal_momentum(q, u, P)  # A_G u, batched
    expected = [fn.centroidal_momentum(q[k], u[k], P) for k in range(len(q))]
    np.testing.assert_allclose(h_G, expected, atol=1e-14)


def test_parameters_by_name_only(tmp_path):
    eom = eg.derive(spring_cart_pendulum())
    m, f = load(eg.write_module(eom, tmp_path / "cp_eom.py")), eg.codegen(eom)
    q = np.array([0.1, 0.7])
    readme_order = (P["m_c"], P["m_p"], P["l"], P["g"])
    for module in (m, f):  # no positions, not even in the order of PARAMETERS
        for values in (readme_order, [P[n] for n in m.PARAMETERS], np.array([P[n] for n in m.PARAMETERS])):
            with pytest.raises(ValueError, match=r"given by name only\), got (tuple|list|ndarray); "
                                                 r"the parameters are \['F', 'g', 'k', 'l', 'm_c', 'm_p'\]"):
                module.M(q, values)
    np.testing.assert_allclose(m.M(q, P), by_hand(q, q, 0.0)[0], rtol=1e-14)
    symbols = {sp.Symbol(n, positive=True): v for n, v in P.items()}  # the symbols themselves name them too
    np.testing.assert_allclose(f.M(q, symbols), m.M(q, P), rtol=0)
    for module in (m, f):
        with pytest.raises(ValueError, match=r"unknown parameters \['mass'\]"):
            module.g(q, {**P, "mass": 1.0})
        with pytest.raises(ValueError, match=r"values missing for the parameters \['l', 'm_p'\]"):
            module.M(q, {"m_c": 1.0})
        with pytest.raises(ValueError, match=r"the values of \['m_p'\] are not finite"):
            module.M(q, {**P, "m_p": np.inf})


def checked_model() -> eg.System:
    """One body whose g(q) uses a parameter of each assumption the values are checked against."""
    m, h = sp.Symbol("m", positive=True), sp.Symbol("h", negative=True)
    c, d, n = sp.Symbol("c", nonzero=True), sp.Symbol("d", nonnegative=True), sp.Symbol("n", integer=True)
    system = eg.System(gravity=(0, h, 0))
    system.add_body("a", joint=eg.Revolute("q1"), mass=m, com=(c + d, n, 0))
    return system


def test_parameter_values_checked_like_model_values(tmp_path, cache):
    eom = eg.derive(checked_model())
    m = load(eg.write_module(eom, tmp_path / "checked.py"))
    assert m.ASSUMPTIONS == {"c": ("nonzero",), "d": ("nonnegative",), "h": ("negative",),
                             "m": ("positive",), "n": ("integer",)}
    good = {"m": 2.0, "h": -9.81, "c": -0.5, "d": 0.0, "n": 2}
    q = [0.4]
    expected = -2.0 * -9.81 * (-0.5 * np.cos(0.4) - 2 * np.sin(0.4))  # −m g_y ∂(y_com)/∂q with g_y = h
    f = eg.codegen(eom)
    for module in (m, f, eg.codegen(eom, backend="c")):
        np.testing.assert_allclose(module.g(q, good), [expected], rtol=1e-14)
        for name, value, rule in [("m", 0.0, "> 0"), ("h", 0.5, "< 0"), ("c", 0.0, "nonzero"),
                                  ("d", -1e-9, ">= 0"), ("n", 1.5, "an integer")]:
            with pytest.raises(ValueError, match=rf"assumptions: {name} = {value!r} \(must be {rule}\)"):
                module.g(q, {**good, name: value})
        for value in ("0.7", b"1", True, np.bool_(False), 1j, [0.7]):
            with pytest.raises(ValueError, match=r"the values of \['c'\] are not finite real numbers"):
                module.g(q, {**good, "c": value})
    with pytest.raises(eg.ModelError, match=r"m = -1.0 \(must be > 0\)"):
        f.bind({**good, "m": -1})


def test_bind(cache):
    eom = eg.derive(spring_cart_pendulum())
    q, u, tau_a = states(8)
    for backend in ("numpy", "c"):
        f = eg.codegen(eom, backend=backend)
        for bound in (f.bind(P), eg.codegen(eom, backend=backend, params=P)):
            np.testing.assert_array_equal(bound.M(q), f.M(q, P))
            np.testing.assert_array_equal(bound.g(q[0]), f.g(q[0], P))
            np.testing.assert_array_equal(bound.jacobian("tip", q), f.jacobian("tip", q, P))
            np.testing.assert_allclose(bound.forward_dynamics(q[1], u[1], tau_a[1:2]),
                                       by_hand(q[1], u[1], tau_a[1])[4], rtol=1e-12)
            with pytest.raises(eg.ModelError, match="bound"):
                bound.M(q, P)
        with pytest.raises(eg.ModelError, match=r"unknown parameters \['mass'\]"):
            f.bind({**P, "mass": 1.0})
        with pytest.raises(eg.ModelError, match=r"values missing for the parameters \['k'\]"):
            f.bind({n: v for n, v in P.items() if n != "k"})
        with pytest.raises(eg.ModelError, match=r"the values of \['l'\] are not finite"):
            f.bind({**P, "l": np.nan})


def test_c_asks_only_for_the_parameters_used(cache):
    eom = eg.derive(double_pendulum())
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    gravity = {"m1": 1.3, "m2": 0.7, "l1": 0.9, "l2": 0.6, "g": 9.81}  # no inertias I1, I2
    q = np.random.default_rng(1).uniform(-3, 3, (5, 2))
    np.testing.assert_allclose(fc.g(q, gravity), fn.g(q, gravity), rtol=1e-14)
    np.testing.assert_allclose(fc.g(q[0], gravity), fn.g(q[0], gravity), rtol=1e-14)
    with pytest.raises(eg.ModelError, match=r"values missing for the parameters \['I1', 'I2'\]"):
        fc.M(q, gravity)


def test_header_documents_and_cannot_be_injected(tmp_path):
    evil = "tip */ int injected; /*\nx"
    eom = eg.derive(spring_cart_pendulum(frame=evil))
    c, h = eg.write_c(eom, tmp_path, name="cp", frames=[evil])
    header = h.read_text()
    code = re.sub(r"/\*.*?\*/", "", header, flags=re.S)  # what the compiler sees
    assert "injected" not in code and header.count("*/") == header.count("/*")
    for line in ["q[1]: phi", "u[0]: qd_x = d/dt q[0]", "p[0]: F", "p[5]: m_p",
                 "tau_a[0]: joint x, adds to tau[0]",
                 "#define CP_NP 6", "zeroed by the caller"]:
        assert line in header, line
    g_doc = header[header.index("gravity terms"):header.index("void cp_g(")]
    assert "out: 2 x 1, row-major; reads q[1]; p[1, 3, 5]" in g_doc  # g, l, m_p; not the cart's x
    subprocess.run(["cc", "-Wall", "-Werror", "-c", str(c), "-o", str(tmp_path / "cp.o")], check=True)


def test_wrong_inputs_are_value_errors(tmp_path):
    """ModelError in eomgen, ValueError in a written module (which needs no eomgen)."""
    eom = eg.derive(spring_cart_pendulum())
    m = load(eg.write_module(eom, tmp_path / "cp_eom.py"))
    for module, error in ((m, ValueError), (eg.codegen(eom), eg.ModelError)):
        shape = r"expected shape \(2,\) or \(N, 2\), got "
        numbers = "expected real numbers, got "
        for q, message in [({"x": 0.1, "phi": 0.2}, numbers + "dict"), (["0", "0.3"], numbers + "list"),
                           ([True, False], numbers + "list"), (None, shape + r"\(\)"),
                           ([0.1, 0.2, 0.3], shape + r"\(3,\)"), ([np.nan, 0.1], "contains NaN")]:
            with pytest.raises(error, match=f"q: {message}"):
                module.M(q, P)
        with pytest.raises(error, match=r"u: expected shape \(2,\), got \(1,\)"):
            module.b([0.1, 0.2], [0.1], P)


def test_number_symbols_print_as_their_values(tmp_path, cache):
    """pi, E (also as exp(1)), GoldenRatio and EulerGamma are written as their float values."""
    system = eg.System(gravity=(0, -sp.GoldenRatio, 0))
    system.add_body("a", joint=eg.Revolute("q1"), mass=sp.exp(1), com=(sp.pi / 4, 0, 0),
                    inertia=sp.eye(3) * sp.EulerGamma)
    eom = eg.derive(system)
    q = [0.3]
    M = [[np.e * np.pi**2 / 16 + float(sp.EulerGamma)]]
    g = [np.e * float(sp.GoldenRatio) * np.pi / 4 * np.cos(0.3)]
    module = load(eg.write_module(eom, tmp_path / "consts.py"))
    for f in (eg.codegen(eom), eg.codegen(eom, backend="c"), module):
        np.testing.assert_allclose(f.M(q), M, rtol=1e-15)
        np.testing.assert_allclose(f.g(q), g, rtol=1e-15)
    c, _ = eg.write_c(eom, tmp_path / "c", name="consts")
    assert repr(np.pi) in c.read_text() and repr(np.e) in c.read_text()
    subprocess.run(["cc", "-Wall", "-Werror", "-c", str(c), "-o", str(tmp_path / "consts.o")], check=True)
