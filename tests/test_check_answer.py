"""eg.check_answer: the lecture's closed forms (ETH Robot Dynamics cart-pendulum, the bond-graph paper's
two-link arm; SEEDS.md) are equal in any equivalent form, and seeded usual mistakes are found, each with
its entry and cause."""
from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from sympy.physics.mechanics import dynamicsymbols

import eomgen as eg
from models import cart_pendulum, two_link_closed_form

from eomgen import answer_input


def lecture_cart_pendulum():
    """M, b, g as the lecture writes them (φ from the downward vertical)."""
    system, (m_c, m_p, l, g) = cart_pendulum()
    phi, phid = system.q[1], system.u[1]
    M = sp.Matrix([[m_c + m_p, m_p * l * sp.cos(phi)], [m_p * l * sp.cos(phi), m_p * l**2]])
    b = sp.Matrix([-m_p * l * sp.sin(phi) * phid**2, 0])
    return system, M, b, sp.Matrix([0, m_p * g * l * sp.sin(phi)])


def two_link_arm():
    """The paper's arm (angles from the horizontal), each link's inertia diag(I_xx, I_yy, I_zz) about
    its com; M, b = C q̇, G as the paper writes them."""
    g = sp.Symbol("g", positive=True)
    m1, m2, l1, lc1, lc2 = sp.symbols("m_1 m_2 l_1 l_c1 l_c2", positive=True)
    I = [sp.symbols(f"I_{i}xx I_{i}yy I_{i}zz", positive=True) for i in (1, 2)]
    system = eg.System(gravity=(0, -g, 0))
    a = system.add_body("link1", joint=eg.Revolute("q_1", axis=(0, 0, 1)), mass=m1, com=(lc1, 0, 0),
                        inertia=sp.diag(*I[0]))
    system.add_body("link2", parent=a, joint=eg.Revolute("q_2", axis=(0, 0, 1)), mass=m2, com=(lc2, 0, 0),
                    inertia=sp.diag(*I[1]), placement=eg.Placement(translation=(l1, 0, 0)))
    M, b, G = two_link_closed_form(system.q, system.u, m1, m2, l1, lc1, lc2, I[0][2], I[1][2], g)
    return system, M, b, G


CART = lecture_cart_pendulum()
ARM = two_link_arm()


def test_the_lecture_answers_are_equal_exactly():
    for system, M, b, g in (CART, ARM):
        result = eg.check_answer(system, M=M, b=b, g=g)
        assert result.ok and all(e.exactly for e in result.entries), str(result)


def test_equivalent_forms_are_equal():
    system, M, b, g = ARM
    (q1, q2), (m2, lc2) = system.q, sp.symbols("m_2 l_c2", positive=True)
    M = M.copy()
    M[1, 1] = sp.Symbol("I_2zz", positive=True) + m2 * lc2**2 * (1 - sp.sin(q2) ** 2 + sp.sin(q2) ** 2)
    M[0, 1] = sp.factor(sp.expand(M[0, 1]))
    g = g.copy()
    g[1] = g[1].subs(sp.cos(q1 + q2), sp.cos(q1) * sp.cos(q2) - sp.sin(q1) * sp.sin(q2))
    b = sp.expand(b)
    assert eg.check_answer(system, M=M, b=b, g=g).ok
    cart, Mc, bc, gc = CART
    phi = cart.q[1]
    gc = sp.Matrix([0, 2 * gc[1] / sp.sin(phi) * sp.sin(phi / 2) * sp.cos(phi / 2)])  # 2 sin φ/2 cos φ/2
    assert eg.check_answer(cart, M=Mc * (sp.cos(phi) ** 2 + sp.sin(phi) ** 2), g=gc).ok


def test_latex_answers():
    system = CART[0]
    result = eg.check_answer(
        system,
        M=r"\begin{bmatrix} m_c + m_p & m_p l \cos\varphi \\ m_{p} l \cos(\phi) & m_p l^2 \end{bmatrix}",
        b=[r"-m_{p} l \sin{\phi} \dot{\phi}^2", "0"],
        g=["0", r"m_p\, g\, l \sin\left(\phi\right)"])
    assert result.ok, str(result)
    wrong = eg.check_answer(ARM[0], M=[[ARM[1][0, 0], ARM[1][0, 1]],
                                       [ARM[1][1, 0], r"I_{2zz} + m_2 l_{c2}^2 \cos^2 q_2"]])
    assert [str(e.name) for e in wrong.entries if not e.equal] == ["M[1,1]"]


def test_dynamicsymbols_and_solution_check():
    system, M, b, g = CART
    x, phi = dynamicsymbols("x phi")
    m_p, l = sp.symbols("m_p l")  # no assumptions: matched by name
    t = sp.Symbol("t")
    b_student = [-m_p * l * sp.sin(phi) * phi.diff(t) ** 2, 0]
    assert eg.check_answer(system, b=b_student).ok
    solution = eg.solution(system, methods="projected_newton_euler")
    assert solution.check(M=M, b=b, g=g).ok


# each usual mistake once: (system, key, entry, wrong value, words of the cause)
def seeded():
    cart, (m_p, l, g) = CART[0], sp.symbols("m_p l g", positive=True)
    phi, phid = cart.q[1], cart.u[1]
    arm, M, b, G = ARM
    (q1, q2), (_, qd2) = arm.q, arm.u
    m2, l1, lc2 = sp.symbols("m_2 l_1 l_c2", positive=True)
    I_2xx, I_2zz = sp.symbols("I_2xx I_2zz", positive=True)
    return [
        (CART, "b", (0, 0), m_p * l * sp.sin(phi) * phid**2, "sign"),
        (CART, "M", (1, 1), m_p * l**2 / 2, "factor ½"),
        (CART, "M", (0, 1), 2 * m_p * l * sp.cos(phi), "factor 2"),
        (CART, "M", (1, 0), m_p * l * sp.sin(phi), "sin(phi) where cos(phi) belongs"),
        (CART, "g", (1, 0), m_p * g * l * sp.cos(phi), "cos(phi) where sin(phi) belongs"),
        (CART, "b", (0, 0), 0, "missing centrifugal term"),
        (ARM, "M", (1, 1), I_2zz, "missing parallel-axis term l_c2^2*m_2"),
        (ARM, "M", (1, 1), I_2xx + m2 * lc2**2, "wrong axis of inertia: I_2xx where I_2zz belongs"),
        (ARM, "b", (0, 0), -m2 * l1 * lc2 * sp.sin(q2) * qd2**2, "missing Coriolis term"),
        (ARM, "g", (0, 0), G[0] - 2 * m2 * lc2 * g * sp.cos(q1 + q2), "sign of the term"),
        (ARM, "M", (0, 1), M[0, 1].subs(sp.cos(q2), sp.sin(q2)), "sin(q_2) where cos(q_2) belongs"),
    ]


@pytest.mark.parametrize("case", seeded(), ids=lambda c: c[4])
def test_seeded_mistakes_are_named(case):
    (system, M, b, g), key, (i, j), wrong, cause = case
    answer = {"M": M.copy(), "b": b.copy(), "g": g.copy()}
    answer[key][i, j] = wrong
    result = eg.check_answer(system, **answer)
    name = f"{key}[{i},{j}]" if key == "M" else f"{key}[{i}]"
    assert not result.ok and [e.name for e in result.entries if not e.equal] == [name], str(result)
    entry = next(e for e in result.entries if e.name == name)
    assert cause in entry.cause and cause in str(result) and entry.state, str(result)
    assert abs(entry.student - entry.expected) > 1e-6


def test_tau_of_a_motor():
    system, (m_c, m_p, l, g) = cart_pendulum()
    T_a = sp.Symbol("T_a")
    system.add_actuator(system.bodies[1], torque=(0, 0, T_a), reaction=system.bodies[0], name="motor")
    assert eg.check_answer(system, tau=[0, T_a]).ok  # the lecture's τ = [0, T_a]
    assert eg.check_answer(system, tau=[0, -T_a]).entries[1].cause == "sign"


@settings(max_examples=8, deadline=None)
@given(st.sampled_from([("M", (0, 0)), ("M", (0, 1)), ("M", (1, 1)), ("b", (0, 0)), ("b", (1, 0)),
                        ("g", (0, 0)), ("g", (1, 0))]),
       st.sampled_from([(-1, "sign"), (sp.Rational(1, 2), "factor ½"), (2, "factor 2")]))
def test_random_scalings_are_found(where, scaling):
    (key, (i, j)), (factor, cause) = where, scaling
    system, M, b, g = ARM
    answer = {"M": M.copy(), "b": b.copy(), "g": g.copy()}
    answer[key][i, j] *= factor
    bad = [e for e in eg.check_answer(system, **answer).entries if not e.equal]
    assert len(bad) == 1 and bad[0].name.startswith(key) and cause in bad[0].cause


def test_markdown_escapes_names():
    system, M, b, g = CART
    text = eg.check_answer(system, M=M, b=[0, 0], g=g)._repr_markdown_()
    assert "| b\\[0\\] | differs at" in text and "m\\_p" in text and "$" not in text


def test_refusals(monkeypatch):
    system, M, b, g = CART
    with pytest.raises(eg.ModelError, match=r"M\[0,0\] uses unknown symbols \['m_cart'\]; known: .*m_c"):
        eg.check_answer(system, M=[[sp.Symbol("m_cart"), 0], [0, 0]])
    with pytest.raises(eg.ModelError, match="g has 3 rows"):
        eg.check_answer(system, g=[0, 0, 0])
    with pytest.raises(eg.ModelError, match=r"b\[0\]: cannot read the LaTeX"):
        eg.check_answer(system, b=[r"m_p l +", "0"])
    with pytest.raises(eg.ModelError, match=r"reads as sin\(phidot\*\*2\*phi\)"):
        eg.check_answer(system, b=[r"-m_p l \sin\phi \dot\phi^2", "0"])
    with pytest.raises(eg.ModelError, match=r"\\dot\{y\} is not the speed"):
        eg.check_answer(system, b=[r"\dot{y}", "0"])
    with pytest.raises(eg.ModelError, match="at least one"):
        eg.check_answer(system)

    def absent(name):
        raise answer_input.PackageNotFoundError(name)

    monkeypatch.setattr(answer_input, "version", absent)
    with pytest.raises(eg.ModelError, match=r"eomgen\[check\]"):
        eg.check_answer(system, g=["0", "m_p g l"])
