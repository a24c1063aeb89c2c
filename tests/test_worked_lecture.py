"""The worked solution written like the lecture "Robot Dynamics, Dynamics 1" (cart-pendulum): the free
cut's rows as scalar equations lhs = rhs with world-axis reactions, passive joints without an effort,
the loads with their points of action, and the assembled M q̈ + b + g = τ. Every expected form is
written by hand from the lecture; comparisons are exact (trigonometric polynomial identities)."""

from __future__ import annotations

import shutil
import subprocess

import pytest
import sympy as sp

import eomgen as eg
from models import matrices_trig_equal, trig_zero

m_c, m_p, l, g, F_act, k = sp.symbols("m_c m_p l g F_act k", positive=True)


def lecture_cart_pendulum(phi_actuated: bool = False) -> eg.System:
    """The lecture's exercise: passive cart and pendulum (unless phi_actuated), a force F_act on the
    cart, a zero-length spring from the world's origin to the pendulum mass."""
    system = eg.System(gravity=(0, -g, 0))
    cart = system.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0), actuated=False), mass=m_c)
    pendulum = system.add_body("pendulum", parent=cart, mass=m_p, com=(0, -l, 0),
                               joint=eg.Revolute("phi", axis=(0, 0, 1), actuated=phi_actuated))
    system.add_force(cart, (F_act, 0, 0), name="F_act")
    system.add_spring(None, (pendulum, (0, -l, 0)), stiffness=k, name="spring")
    return system


@pytest.fixture(scope="module", params=[False, True], ids=["passive", "phi actuated"])
def solved(request):
    system = lecture_cart_pendulum(request.param)
    return system, eg.solution(system), request.param


def step(sol, title):
    return next(s for s in sol.steps if s.title == title)


def symbol(sol, name):
    return next(s for s in sol["unknowns"] if s.name == name)


def test_free_cut_rows_are_the_lectures_scalar_equations(solved):
    """Kinematic relations, then per body Newton (world x, y) and Euler (z), each lhs = rhs with the mass
    times the acceleration on the left; the rod force F on the pendulum in world axes; τ_φ only where
    the joint is actuated, τ_x never (the cart's joint is passive)."""
    system, sol, phi_actuated = solved
    (x, phi), (_, phid), (xdd, phidd) = system.q, system.u, system.ud
    cut = step(sol, "Cut free")
    F_x, F_y = symbol(sol, "F_pendulum_x"), symbol(sol, "F_pendulum_y")
    F_cy, T_cz = symbol(sol, "F_cart_y"), symbol(sol, "T_cart_z")
    tau = sol["efforts"][0] if phi_actuated else 0  # the joint's effort, as the solution names it
    a_x = xdd + l * sp.cos(phi) * phidd - l * sp.sin(phi) * phid**2  # the lecture's kinematics
    a_y = l * sp.sin(phi) * phidd + l * sp.cos(phi) * phid**2
    kinematic = [xdd, 0, 0, a_x, a_y, phidd]
    rows = [
        (m_c * xdd, F_act - F_x),                    # cart, Newton x
        (0, F_cy - F_y - m_c * g),                   # cart, Newton y (a_cart,y = 0)
        (0, T_cz - tau),                             # cart, Euler z
        (m_p * a_x, F_x - k * (x + l * sp.sin(phi))),           # pendulum, Newton x (spring −k r)
        (m_p * a_y, F_y - m_p * g + k * l * sp.cos(phi)),       # pendulum, Newton y
        (0, -l * (F_x * sp.cos(phi) + F_y * sp.sin(phi)) + tau),  # pendulum, Euler about the mass
    ]
    equations = [e.eq for e in cut.equations]
    assert len(equations) == 12 and all(isinstance(e, sp.Equality) for e in equations)
    assert all(not isinstance(side, sp.MatrixBase) for e in equations for side in e.args)
    for e, hand in zip(equations[:6], kinematic):
        assert e.lhs.name.startswith(("a_", "alpha_")) and trig_zero(e.rhs - hand, system.q), e
    for e, (lhs, rhs) in zip(equations[6:], rows):
        assert trig_zero(e.lhs - lhs, system.q) and trig_zero(e.rhs - rhs, system.q), (e, lhs, rhs)
    efforts = {s.name for e in equations for s in e.free_symbols if s.name.startswith("tau")}
    assert efforts == ({"tau_phi"} if phi_actuated else set())
    assert "They are in world axes." in cut.text
    assert ("Passive joints (no effort): `x`" in cut.text) and (("`phi`" in cut.text) != phi_actuated)


def test_assembled_equations_of_motion_are_the_lectures(solved):
    """The last step: M q̈ + b + g = τ row by row, M, b, g of the lecture, τ = J_Pᵀ F_act of the cart
    force + J_sᵀ F_s of the spring (+ the effort of an actuated joint); each load's τ shown."""
    system, sol, phi_actuated = solved
    (x, phi), (_, phid), (xdd, phidd) = system.q, system.u, system.ud
    last = sol.steps[-1]
    assert last.title == "Equations of motion"
    M = sp.Matrix([[m_c + m_p, m_p * l * sp.cos(phi)], [m_p * l * sp.cos(phi), m_p * l**2]])
    b = sp.Matrix([-m_p * l * sp.sin(phi) * phid**2, 0])
    G = sp.Matrix([0, m_p * g * l * sp.sin(phi)])
    r = sp.Matrix([x + l * sp.sin(phi), -l * sp.cos(phi)])  # the spring's point, from the origin
    tau_spring = r.jacobian([x, phi]).T * (-k * r)
    tau = sp.Matrix([F_act, 0]) + tau_spring + sp.Matrix([0, sol["efforts"][0] if phi_actuated else 0])
    lhs = M * sp.Matrix([xdd, phidd]) + b + G
    equations = [e.eq for e in last.equations]
    assert len(equations) == 2
    for e, left, right in zip(equations, lhs, tau):
        assert trig_zero(e.lhs - left, system.q) and trig_zero(e.rhs - right, system.q), e
    assert matrices_trig_equal(sp.Matrix(last["tau[F_act]"]), sp.Matrix([F_act, 0]), list(system.q))
    assert matrices_trig_equal(sp.Matrix(last["tau[spring]"]), tau_spring, list(system.q))
    assert r"J_P^T F" in last.text and "actuated joints only" in last.text


def test_loads_table_names_the_points_of_action_and_the_actuation(solved):
    _, sol, phi_actuated = solved
    text = sol.markdown()
    assert "between the world at $(0, 0, 0)$ and pendulum at $(0, - l, 0)$" in text
    assert "$\\left[\\begin{matrix}F_{act} & 0 & 0\\end{matrix}\\right]$ on cart at $(0, 0, 0)$" in text
    assert "axis $\\left[\\begin{matrix}1 & 0 & 0\\end{matrix}\\right]$, passive" in text
    assert ("actuated $\\tau_{\\phi}$" in text) == phi_actuated
    numbers = [int(n) for n in __import__("re").findall(r"\\tag\{(\d+)\}", text)]
    assert numbers == list(range(1, 15))  # 12 cut-free rows, then the 2 rows of M q̈ + b + g = τ


def test_pdf_compiles_with_nothing_past_the_margin(solved, tmp_path):
    """pdflatex's own log: no overfull line (nothing runs past the margin)."""
    _, sol, _ = solved
    assert shutil.which("pdflatex"), "pdflatex is needed (.ci/run installs TeX Live)"
    (tmp_path / "sol.tex").write_text(sol.latex(), encoding="utf-8")
    subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "sol.tex"], cwd=tmp_path,
                   check=True, capture_output=True)
    log = (tmp_path / "sol.log").read_text(errors="replace")
    assert "Overfull \\hbox" not in log
    assert (tmp_path / "sol.pdf").stat().st_size > 10_000
