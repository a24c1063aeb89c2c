"""Worked solutions: the lecture's intermediate results, textbook form, and documents that compile.

Every expected expression is written by hand from the lecture "Robot Dynamics, Dynamics 1", the
lecture on Kane's method for nonholonomic systems and the paper "Bond Graph Modeling of a Robot
Manipulator"; comparisons are exact (trigonometric polynomial identities)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

import eomgen as eg
from eomgen.__main__ import main
from eomgen.printing import latex
from eomgen.worked.compile import compile_pdf as safe_compile
from models import cart_pendulum, matrices_trig_equal, planar_arm, trig_zero

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import nonholonomic  # noqa: E402

LECTURE = ("free_cut", "projected_newton_euler", "lagrange")


def same(A, B, q) -> bool:
    return matrices_trig_equal(sp.Matrix(A), sp.Matrix(B), list(q))


@pytest.fixture(scope="module")
def cart():
    system, (m_c, m_p, l, g) = cart_pendulum()
    F, T_a, k = sp.symbols("F T_a k", positive=True)
    cart_body, pendulum = system.bodies
    system.add_force(cart_body, (F, 0, 0), name="cart force")
    system.add_actuator(pendulum, torque=(0, 0, T_a), reaction=cart_body, name="motor")
    system.add_spring(None, (pendulum, (0, -l, 0)), stiffness=k, name="spring")
    return system, eg.solution(system), (m_c, m_p, l, g, F, T_a, k)


def test_cart_pendulum_kinematics(cart):
    system, sol, (m_c, m_p, l, g, *_) = cart
    x, phi = system.q
    assert same(sol["r_S[pendulum]"], [x + l * sp.sin(phi), -l * sp.cos(phi), 0], system.q)
    assert same(sol["J_P[pendulum]"], [[1, l * sp.cos(phi)], [0, l * sp.sin(phi)], [0, 0]], system.q)
    assert same(sol["J_R[pendulum]"], [[0, 0], [0, 0], [0, 1]], system.q)
    assert same(sol["Omega[pendulum]"], [0, 0, system.u[1]], system.q)
    assert same(sol["J_P[cart]"], [[1, 0], [0, 0], [0, 0]], system.q)
    assert same(sol["J_R[cart]"], sp.zeros(3, 2), system.q)
    assert same(sol["Omega[cart]"], [0, 0, 0], system.q)


def test_cart_pendulum_energies_and_lagrange_steps(cart):
    system, sol, (m_c, m_p, l, g, *_) = cart
    (x, phi), (xd, phid), (xdd, phidd) = system.q, system.u, system.ud
    T = (m_c + m_p) * xd**2 / 2 + m_p * l * sp.cos(phi) * xd * phid + m_p * l**2 * phid**2 / 2
    assert trig_zero(sol.find("T", "lagrange") - T, system.q)
    U_gravity = -m_p * g * l * sp.cos(phi)
    U = sol.find("U", "lagrange")
    k = sp.Symbol("k", positive=True)
    spring = k * ((x + l * sp.sin(phi)) ** 2 + (l * sp.cos(phi)) ** 2) / 2  # zero-length, from the origin
    difference = U - U_gravity - spring
    assert all(
        trig_zero(sp.diff(difference, v), system.q) for v in system.q
    ), difference  # up to a constant
    p = [(m_c + m_p) * xd + m_p * l * sp.cos(phi) * phid, m_p * l * sp.cos(phi) * xd + m_p * l**2 * phid]
    assert same(sol["dT/du"], p, system.q)
    dp = [
        (m_c + m_p) * xdd + m_p * l * (sp.cos(phi) * phidd - sp.sin(phi) * phid**2),
        m_p * l * (sp.cos(phi) * xdd - sp.sin(phi) * phid * xd) + m_p * l**2 * phidd,
    ]
    assert same(sol["d/dt dT/du"], dp, system.q)
    assert same(sol["dT/dq"], [0, -m_p * l * sp.sin(phi) * xd * phid], system.q)
    assert same(sol["dU/dq"], [sp.diff(U_gravity + spring, v) for v in system.q], system.q)


def test_cart_pendulum_M_b_g_by_each_method(cart):
    """SEEDS' M, b, g exactly, from each method's own step; τ of the motor and the cart force."""
    system, sol, (m_c, m_p, l, g, F, T_a, k) = cart
    phi, phid = system.q[1], system.u[1]
    M = [[m_c + m_p, m_p * l * sp.cos(phi)], [m_p * l * sp.cos(phi), m_p * l**2]]
    for method in LECTURE:
        assert same(sol.find("M", method), M, system.q), method
        assert same(sol.find("b", method), [-m_p * l * sp.sin(phi) * phid**2, 0], system.q), method
        assert same(sol.find("g", method), [0, m_p * g * l * sp.sin(phi)], system.q), method
        assert same(sol.find("tau[motor]", method), [0, T_a], system.q)
        assert same(sol.find("tau[cart force]", method), [F, 0], system.q)
        # the spring from the origin to the mass: τ = J_sᵀ F_s, F_s = −k r
        r = sp.Matrix([system.q[0] + l * sp.sin(phi), -l * sp.cos(phi), 0])
        J_s = r.jacobian(system.q)
        assert same(sol.find("tau[spring]", method), J_s.T * (-k * r), system.q)
    comparison = next(s for s in sol.steps if s.title == "Comparison of the methods")
    assert (
        all(e.is_zero_matrix for e in comparison.expressions.values()) and len(comparison.expressions) == 6
    )


def test_cart_pendulum_free_cut(cart):
    """6 equations, 6 unknowns (12 with the kinematics); the rod force m_p (a_S − g⃗)."""
    system, sol, (m_c, m_p, l, g, *_) = cart
    (x, phi), (xd, phid), (xdd, phidd) = system.q, system.u, system.ud
    assert sol["equations"] == 6 and len(sol["unknowns"]) == 6
    assert sol["equations with kinematics"] == 12 and sol["unknowns with kinematics"] == 12
    cut = next(s for s in sol.steps if s.title == "Cut free")
    assert len(cut.equations) == 12  # 6 kinematic relations, then Newton (2) and Euler (1) per body
    r_S = sp.Matrix([x + l * sp.sin(phi), -l * sp.cos(phi)])
    a_S = r_S.jacobian([x, phi]) * sp.Matrix([xdd, phidd]) + (
        r_S.jacobian([x, phi]) * sp.Matrix([xd, phid])
    ).jacobian([x, phi]) * sp.Matrix([xd, phid])
    rod = m_p * (a_S - sp.Matrix([0, -g]))  # Newton on the point mass: the rod's force, all there is
    spring_force = -sp.Symbol("k", positive=True) * sp.Matrix([x + l * sp.sin(phi), -l * sp.cos(phi)])
    assert same(sol["reaction[phi]"][:2, :], rod - spring_force, system.q)
    assert "6 dynamic equations in 6 unknowns" in cut.text and "12 equations in 12 unknowns" in cut.text


def test_skate_kane_steps():
    """The skate: F̃_r of a force F perpendicular to the runner at distance l; M̃ and f̃ by hand."""
    l = sp.Symbol("l", positive=True)
    system, args = nonholonomic.skate(force_at=l)
    sol = eg.solution(eg.kane(system, **args))
    m, a, I_z, F = (
        sp.Symbol("m", positive=True),
        sp.Symbol("a", positive=True),
        sp.Symbol("I_z", positive=True),
        sp.Symbol("F"),
    )
    u1, u2 = sp.symbols("u1 u2")
    q = list(system.q)
    assert same(sol["F_r"], [0, F * l], q)
    assert same(sol["M~"], [[m, 0], [0, I_z + m * a**2]], q)
    assert same(sol["f~"], [m * a * u2**2, F * l - m * a * u1 * u2], q)
    x3 = q[2]
    assert same(sol["v_r[skate]"], [[sp.cos(x3), -a * sp.sin(x3)], [sp.sin(x3), a * sp.cos(x3)], [0, 0]], q)
    assert same(sol["omega_r[skate]"], [[0, 0], [0, 0], [0, 1]], q)
    F_star = sol["F*_r"]
    wdot = [s for s in F_star.free_symbols if s.name in ("u1dot", "u2dot")]
    assert len(wdot) == 2 and same(sol["F_r + F*_r"], sol["F_r"] + F_star, q)
    assert same(sol["dependent speeds solved"], [0], q)


def two_link_arm():
    """The bond-graph paper's arm, angles from the horizontal, gravity −y."""
    m1, m2, l1, lc1, lc2, I1, I2, g = sp.symbols("m_1 m_2 l_1 l_c1 l_c2 I_1 I_2 g", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    a = system.add_body(
        "link1",
        joint=eg.Revolute("q_1", axis=(0, 0, 1)),
        mass=m1,
        com=(lc1, 0, 0),
        inertia=sp.diag(0, 0, I1),
    )
    system.add_body(
        "link2",
        parent=a,
        joint=eg.Revolute("q_2", axis=(0, 0, 1)),
        mass=m2,
        com=(lc2, 0, 0),
        inertia=sp.diag(0, 0, I2),
        placement=eg.Placement(translation=(l1, 0, 0)),
    )
    return system, (m1, m2, l1, lc1, lc2, I1, I2, g)


def test_two_link_arm_textbook():
    system, (m1, m2, l1, lc1, lc2, I1, I2, g) = two_link_arm()
    sol = eg.solution(system)
    (q1, q2), (qd1, qd2) = system.q, system.u
    M11 = I1 + I2 + m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * sp.cos(q2))
    M12 = I2 + m2 * (lc2**2 + l1 * lc2 * sp.cos(q2))
    M = [[M11, M12], [M12, I2 + m2 * lc2**2]]
    h = -m2 * l1 * lc2 * sp.sin(q2)
    Cqd = [h * qd2 * (2 * qd1 + qd2), -h * qd1**2]
    G = [
        (m1 * lc1 + m2 * l1) * g * sp.cos(q1) + m2 * lc2 * g * sp.cos(q1 + q2),
        m2 * lc2 * g * sp.cos(q1 + q2),
    ]
    for method in LECTURE:
        assert same(sol.find("M", method), M, system.q)
        assert same(sol.find("b", method), Cqd, system.q)
        assert same(sol.find("g", method), G, system.q)
    for got, hand in zip(list(sol["M"]) + list(sol["b"]) + list(sol["g"]), sum(M, []) + Cqd + G):
        assert sp.count_ops(got) <= sp.count_ops(sp.expand(hand)), (got, hand)  # textbook, not swollen


def test_three_link_arm_every_entry_in_textbook_form():
    """Every entry of M, b, g no larger than a hand-written closed form (and equal to it)."""
    system = planar_arm(3)
    m1, l1, lc1, I1, m2, l2, lc2, I2, m3, lc3, I3, g = sp.symbols(
        "m_1 l_1 l_c1 I_1 m_2 l_2 l_c2 I_2 m_3 l_c3 I_3 g", positive=True)
    sol = eg.solution(system)
    q1, q2, q3 = system.q
    d1, d2, d3 = system.u
    c2, c3, c23 = sp.cos(q2), sp.cos(q3), sp.cos(q2 + q3)
    s2, s3, s23 = sp.sin(q2), sp.sin(q3), sp.sin(q2 + q3)
    M33 = I3 + m3 * lc3**2
    M23 = M33 + m3 * l2 * lc3 * c3
    M22 = I2 + m2 * lc2**2 + I3 + m3 * (l2**2 + lc3**2 + 2 * l2 * lc3 * c3)
    M13 = M23 + m3 * l1 * lc3 * c23
    M12 = M22 + m2 * l1 * lc2 * c2 + m3 * (l1 * l2 * c2 + l1 * lc3 * c23)
    M11 = (
        I1
        + m1 * lc1**2
        + I2
        + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2)
        + I3
        + m3 * (l1**2 + l2**2 + lc3**2 + 2 * l1 * l2 * c2 + 2 * l1 * lc3 * c23 + 2 * l2 * lc3 * c3)
    )
    M = sp.Matrix([[M11, M12, M13], [M12, M22, M23], [M13, M23, M33]])
    # b = C q̇ from the Christoffel symbols of the hand M (an independent route to b)
    q, u = list(system.q), list(system.u)
    b = sp.Matrix(
        [
            sum(
                (sp.diff(M[i, j], q[k]) - sp.diff(M[j, k], q[i]) / 2) * u[j] * u[k]
                for j in range(3)
                for k in range(3)
            )
            for i in range(3)
        ]
    )
    b_hand = [
        -m2 * l1 * lc2 * s2 * (2 * d1 * d2 + d2**2)
        - m3 * l1 * l2 * s2 * (2 * d1 * d2 + d2**2)
        - m3 * l1 * lc3 * s23 * (d2 + d3) * (2 * d1 + d2 + d3)
        - m3 * l2 * lc3 * s3 * d3 * (2 * d1 + 2 * d2 + d3),
        (m2 * l1 * lc2 * s2 + m3 * l1 * l2 * s2 + m3 * l1 * lc3 * s23) * d1**2
        - m3 * l2 * lc3 * s3 * d3 * (2 * d1 + 2 * d2 + d3),
        m3 * l1 * lc3 * s23 * d1**2 + m3 * l2 * lc3 * s3 * (d1 + d2) ** 2,
    ]
    assert same(b, b_hand, q)
    G3 = m3 * g * lc3 * sp.cos(q1 + q2 + q3)
    G2 = G3 + (m2 * lc2 + m3 * l2) * g * sp.cos(q1 + q2)
    G = [G2 + (m1 * lc1 + m2 * l1 + m3 * l1) * g * sp.cos(q1), G2, G3]
    for method in LECTURE:
        assert (
            same(sol.find("M", method), M, q)
            and same(sol.find("b", method), b_hand, q)
            and same(sol.find("g", method), G, q)
        ), method
    hands = list(M) + b_hand + G
    for got, hand in zip(list(sol["M"]) + list(sol["b"]) + list(sol["g"]), hands):
        assert sp.count_ops(got) <= 1.2 * sp.count_ops(hand), (got, hand)
    assert sol.unsimplified == 0
    assert "chi" not in str(sol.latex())


def test_no_intermediate_symbols_and_readable_names(cart):
    _, sol, _ = cart
    document = sol.latex()
    assert "ξ" not in document and "xi_" not in document
    assert r"\dot{\phi}" in document and r"\ddot{x}" in document and "m_{p}" in document
    assert not any(
        "_ξ" in str(s)
        for step in sol.steps
        for e in step.expressions.values()
        for s in sp.sympify(e).free_symbols
    )


def test_numbers_from_a_file_print_as_decimals():
    assert latex(sp.Rational(44105, 9007199254740992), digits=4) == latex(
        sp.Float(4.896722e-12, 6), digits=4
    )
    assert "4.897" in latex(sp.Rational(44105, 9007199254740992), digits=4)
    assert latex(sp.Rational(1, 2)) == r"\frac{1}{2}"
    assert latex(sp.Float(0.123456789), digits=3) == "0.123"
    robot = eg.robots.load("ur5")
    assert latex(robot.u[0]) == r"\dot{q}_{\mathrm{shoulder\_pan\_joint}}"  # a visible dot on a long name
    text = eg.solution(robot, methods=("recursive",)).markdown(digits=3)
    assert "9007199254740992" not in text and r"\frac{" not in text.split("## Kinematics")[0]


def test_jupyter_display():
    system, (m_c, m_p, l, g) = cart_pendulum()
    eom = eg.derive(system, method="lagrange")
    md = eom._repr_markdown_()
    assert "lagrange" in md and r"\ddot q" in md and "2×2" in md and r"l^{2} m_{p}" in md
    assert eom._repr_latex_().startswith("$$")
    system, args = nonholonomic.rolling_disk(torques=True)
    md = eg.kane(system, **args)._repr_markdown_()
    assert "2 velocity constraints" in md and r"\tilde M" in md
    assert eg.solution(cart_pendulum()[0])._repr_markdown_().startswith("# ")


def compile_pdf(tex: str, folder: Path) -> Path:
    """pdflatex on the document (as solution.pdf runs it): it must compile without an error (a LaTeX
    engine is required: .ci/run installs TeX Live)."""
    assert shutil.which("pdflatex"), "pdflatex is needed (.ci/run installs TeX Live)"
    return safe_compile(tex, folder / "s.pdf")


@pytest.mark.parametrize("which", ["cart_pendulum", "rolling_disk", "ur5"])
def test_latex_documents_compile(which, tmp_path, cart):
    if which == "cart_pendulum":
        sol = cart[1]
    elif which == "rolling_disk":
        system, args = nonholonomic.rolling_disk(torques=True)
        sol = eg.solution(eg.kane(system, **args))
    else:
        sol = eg.solution(eg.robots.load("ur5"), methods=("recursive", "projected_newton_euler"))
        assert sol.form == "shared" and any(step.shared for step in sol.steps)
    pdf = compile_pdf(sol.latex(), tmp_path)
    assert pdf.stat().st_size > 10_000
    png = shutil.which("pdftoppm")
    assert png, "pdftoppm is needed (poppler-utils)"
    subprocess.run(
        [png, "-r", "40", "-png", "-f", "1", "-l", "1", str(pdf), str(tmp_path / "page")], check=True
    )
    assert any(tmp_path.glob("page*.png"))


def test_markdown_document(cart):
    text = cart[1].markdown()
    assert text.startswith("# Equations of motion") and "## Newton-Euler with a free cut" in text
    assert "$$" in text and "| body | parent |" in text and "## Comparison" in text


def test_command_line_solve(tmp_path):
    source = tmp_path / "model.py"
    source.write_text(
        "import sympy as sp\nimport eomgen as eg\nm, l, g = sp.symbols('m l g', positive=True)\n"
        "system = eg.System(gravity=(0, -g, 0))\n"
        "system.add_body('rod', joint=eg.Revolute('theta', axis=(0, 0, 1)), mass=m, com=(l, 0, 0))\n"
    )
    for suffix in (".tex", ".md", ".pdf"):
        assert main(["solve", str(source), "-o", str(tmp_path / f"s{suffix}")]) == 0
        assert (tmp_path / f"s{suffix}").stat().st_size > 500
    assert r"\documentclass" in (tmp_path / "s.tex").read_text()
    assert main(["solve", str(source), "-o", str(tmp_path / "s.docx")]) == 2
    (tmp_path / "empty.py").write_text("x = 1\n")
    assert main(["solve", str(tmp_path / "empty.py"), "-o", str(tmp_path / "e.tex")]) == 2


def test_errors_name_the_problem():
    system, _ = cart_pendulum()
    with pytest.raises(eg.ModelError, match="unknown methods"):
        eg.solution(system, methods=("newton",))
    with pytest.raises(eg.ModelError, match="form"):
        eg.solution(system, form="pretty")
    with pytest.raises(eg.ModelError, match="System"):
        eg.solution(eg.derive(system))
    with pytest.raises(eg.ModelError, match="expected"):
        eg.solution("system")


def test_floating_base_step_against_pinocchio():
    """A free-flyer body with a leg standing on a point contact: S = [0 I] by hand, the printed J_c
    (through its shared definitions) equals Pinocchio's frame Jacobian built with its own API."""
    import numpy as np
    import pinocchio as pin

    system = eg.System(gravity=(0, 0, -9.81))
    base = system.add_body("base", joint=eg.FreeFlyer("root"), mass=2.0, inertia=sp.diag(0.1, 0.2, 0.3))
    leg = system.add_body(
        "leg",
        parent=base,
        joint=eg.Revolute("knee", axis=(0, 1, 0)),
        mass=0.5,
        com=(0, 0, -0.2),
        inertia=sp.diag(0.01, 0.01, 0.001),
        placement=eg.Placement(translation=(0.1, 0, 0)),
    )
    system.add_frame("foot", body=leg, placement=eg.Placement(translation=(0, 0, -0.4)))
    system.add_contact("foot", "point")
    sol = eg.solution(system, methods=("projected_newton_euler", "recursive"))
    step = next(s for s in sol.steps if s.title == "Floating base and contacts")
    assert step["S"] == sp.Matrix([[0] * 6 + [1]])
    assert {"F_c", "N_c"} <= set(step.expressions)
    comparison = next(s for s in sol.steps if s.title == "Comparison of the methods")
    assert all(float(v) < 1e-10 for v in comparison.expressions.values())

    model = pin.Model()
    root = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "root")
    model.appendBodyToJoint(
        root, pin.Inertia(2.0, np.zeros(3), np.diag([0.1, 0.2, 0.3])), pin.SE3.Identity()
    )
    knee = model.addJoint(root, pin.JointModelRY(), pin.SE3(np.eye(3), np.array([0.1, 0, 0])), "knee")
    model.appendBodyToJoint(
        knee, pin.Inertia(0.5, np.array([0, 0, -0.2]), np.diag([0.01, 0.01, 0.001])), pin.SE3.Identity()
    )
    foot = model.addFrame(
        pin.Frame("foot", knee, 0, pin.SE3(np.eye(3), np.array([0, 0, -0.4])), pin.FrameType.OP_FRAME)
    )
    data = model.createData()
    q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    J = pin.getFrameJacobian(model, data, foot, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)[:3]
    values = dict(zip(system.q, q))
    for symbol, definition in step.shared:
        values[symbol] = definition.xreplace(values).evalf()
    J_c = np.array(step["J_c"].xreplace(values).evalf(), dtype=float)
    assert np.allclose(J_c, J, atol=1e-12), (J_c, J)


def test_names_numbers_and_symbolic_axes_found_in_review(tmp_path):
    """Names with LaTeX's specials and non-ASCII letters compile; numbers from a file (decimals) are
    compared at random states, not exactly (round-off); a symbolic axis skips only the cut-free balances."""
    g, alpha = sp.Symbol("g", positive=True), sp.Symbol("alpha")
    system = eg.System(gravity=(0, -g, 0))
    a = system.add_body("Wägen #1 & {x}", joint=eg.Prismatic("x % 1", axis=(1, 0, 0)), mass=1.3)
    system.add_body(
        "arm_φ",
        parent=a,
        joint=eg.Revolute("φ joint_a", axis=(0, 0, 1)),
        mass=0.7,
        com=(0, -0.45, 0),
        inertia=sp.diag(0.01, 0.01, 0.01),
    )
    sol = eg.solution(system)
    comparison = next(s for s in sol.steps if s.title == "Comparison of the methods")
    assert "random states" in comparison.text
    assert all(float(v) < 1e-10 for v in comparison.expressions.values())
    compile_pdf(sol.latex(), tmp_path)
    tilted = eg.System(gravity=(0, -g, 0))
    tilted.add_body(
        "rod",
        joint=eg.Revolute("phi", axis=(sp.sin(alpha), 0, sp.cos(alpha))),
        mass=sp.Symbol("m", positive=True),
        com=(0, -sp.Symbol("l", positive=True), 0),
    )
    sol = eg.solution(tilted)
    assert not any(step.title == "Cut free" for step in sol.steps)
    assert any(step.title == "Elimination of the reactions" for step in sol.steps)
