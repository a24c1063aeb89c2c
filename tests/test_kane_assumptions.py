"""Kane's closed forms under stated assumptions (`assume_nonzero`): the MEAM 535 skate in the notes' own
speeds u1 = ẋ1, u2 = ẋ3, u3 = ẋ2 (dependent: the runner's constraint ẋ2 = tan x3 ẋ1 divides by cos x3)
against the notes' closed forms and sympy's KanesMethod; the refusal without them; the argument checked."""
import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from hypothesis import given, settings, strategies as st

import eomgen as eg
import kane_systems as K
from eomgen.errors import ModelError
from eomgen.methods.nonzero import Nonzero

m, I_z, a, l, F = K.m, K.I_z, K.a, K.l, K.F


def notes_skate():
    """The skate (force F perpendicular to the runner at l) in the notes' speeds; (system, kane args)."""
    system, _ = K.skate(force_at=l)
    x1d, x2d, x3d = system.u
    x3 = system.q[2]
    return system, dict(speeds=[K.u1, K.u2, K.u3], kinematic_equations=[K.u1 - x1d, K.u2 - x3d, K.u3 - x2d],
                        nonholonomic=[-sp.sin(x3) * K.u1 + sp.cos(x3) * K.u3], independent=[K.u1, K.u2])


def notes_closed_forms(x3):
    """The notes' equations (by hand): ẋ2 = tan x3 ẋ1, v_G = (u1 − a sin x3 u2, tan x3 u1 + a cos x3 u2),
    M̃ ẇ = f̃ with M̃ = diag(m sec² x3, I_z + m a²), f̃ = F̃_r − m v_r · (∂v_r/∂t terms)."""
    u1, u2 = K.u1, K.u2
    sec, tan = 1 / sp.cos(x3), sp.tan(x3)
    return {"mass_matrix": sp.Matrix([[m * sec**2, 0], [0, I_z + m * a**2]]),
            "forcing": sp.Matrix([m * a * sec * u2**2 - m * tan * sec**2 * u1 * u2,
                                  F * l - m * a * sec * u1 * u2]),
            "active_forces": sp.Matrix([0, F * l]),
            "dependent_speeds": sp.Matrix([tan * u1]),
            "qdot": sp.Matrix([u1, tan * u1, u2])}


def states(system, count, seed):
    """Random states and parameters with |cos x3| > 0.1 (where the closed forms hold)."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        q = rng.uniform(-np.pi, np.pi, 3)
        if abs(np.cos(q[2])) > 0.1:
            values = {s: rng.uniform(0.5, 1.5) for s in (m, I_z, a, l, F)}
            speeds = dict(zip((K.u1, K.u2), rng.uniform(-2, 2, 2)))
            out.append({**values, **dict(zip(system.q, q)), **speeds})
    return out


def number(expr, values) -> np.ndarray:
    return np.array(sp.Matrix(expr).xreplace(values).evalf(30).tolist(), dtype=float)


@pytest.fixture(scope="module")
def skate():
    system, args = notes_skate()
    return system, eg.kane(system, **args, assume_nonzero=[sp.cos(system.q[2])])


def test_notes_speeds_closed_forms_equal_the_notes(skate):
    """M̃, f̃, F̃_r, the dependent speed and q̇ in closed form equal the notes' at random states."""
    system, k = skate
    assert k.assume_nonzero == [sp.cos(system.q[2])]
    notes = notes_closed_forms(system.q[2])
    for values in states(system, 6, 1):
        for key, expected in notes.items():
            np.testing.assert_allclose(number(getattr(k, key), values), number(expected, values),
                                       rtol=1e-12, atol=1e-12, err_msg=key)


def test_notes_speeds_equal_sympy_kanes_method(skate):
    """F̃_r + F̃*_r = f̃ − M̃ ẇ_ind equals sympy's KanesMethod in the same speeds at random states and
    rates (its last row the constraint's derivative, which gives u̇3)."""
    system, k = skate
    N, x1, x2, x3, body, loads = K._skate_frame(l)
    w = me.dynamicsymbols("u1 u2 u3")
    km = me.KanesMethod(N, q_ind=[x1, x2, x3], u_ind=w[:2], u_dependent=w[2:],
                        kd_eqs=[w[0] - x1.diff(), w[1] - x3.diff(), w[2] - x2.diff()],
                        velocity_constraints=[-sp.sin(x3) * w[0] + sp.cos(x3) * w[2]])
    km.kanes_equations([body], loads)
    rng = np.random.default_rng(5)
    for values in states(system, 4, 2):
        q = [values[s] for s in system.q]
        ours = {s: values[s] for s in (m, I_z, a, l, F)}
        on_sympy = {**ours, **dict(zip([x1, x2, x3], q)), w[0]: values[K.u1], w[1]: values[K.u2],
                    w[2]: np.tan(q[2]) * values[K.u1]}
        M_s = number(me.msubs(km.mass_matrix, on_sympy), {})
        F_s = number(me.msubs(km.forcing, on_sympy), {})[:, 0]
        M_k, f_k = number(k.mass_matrix, values), number(k.forcing, values)[:, 0]
        for wd in rng.uniform(-1, 1, (2, 2)):
            wd_dep = np.linalg.solve(M_s[2:, 2:], F_s[2:] - M_s[2:, :2] @ wd)
            np.testing.assert_allclose(f_k - M_k @ wd, F_s[:2] - M_s[:2] @ np.r_[wd, wd_dep],
                                       rtol=1e-10, atol=1e-10)


def test_without_assumptions_refused_suggesting_them():
    system, args = notes_skate()
    k = eg.kane(system, **args)
    for key in ("mass_matrix", "forcing", "dependent_speeds"):
        with pytest.raises(ModelError, match=r"C_dep: no pivot in column 0 can be proven nonzero "
                           r"\(candidates \[cos\(x_3\)\]\).*assume_nonzero=\[cos\(x_3\)\].*eg.codegen"):
            getattr(k, key)
    with pytest.raises(ModelError, match=r"assume_nonzero=\[cos\(x_3\)\]"):
        eg.solution(k)


def test_solution_shows_where_it_holds(skate):
    system, k = skate
    sol = eg.solution(k)
    text = sol.markdown()
    assert text.count(r"valid where $\cos{\left(x_{3} \right)} \neq 0$") == 2
    x3 = system.q[2]
    v = sol["velocity constraints"]
    assert sp.expand(v[0] - (-sp.sin(x3) * K.u1 + sp.cos(x3) * K.u3)) == 0
    x1d, x2d, x3d = system.u
    kinematic = sp.Matrix([K.u1 - x1d, K.u2 - x3d, K.u3 - x2d])
    assert sp.expand(sol["kinematic equations"] - kinematic) == sp.zeros(3, 1)


def test_runner_speeds_implicit_kinematics_with_assumption():
    """The skate in speeds along and across the runner with w = Wᵀ q̇ (Y's pivots cos x3, then
    −(cos² x3 + sin² x3)/cos x3): with cos x3 ≠ 0 stated, the notes' M̃ = diag(m, I_z + m a²),
    f̃ = [m a u2², F l − m a u1 u2]."""
    system, args = K.skate(force_at=l, solved=False)
    with pytest.raises(ModelError, match="assume_nonzero"):
        eg.kane(system, **args).mass_matrix
    k = eg.kane(system, **args, assume_nonzero=[sp.cos(system.q[2])])
    for values in states(system, 3, 3):
        np.testing.assert_allclose(number(k.mass_matrix, values),
                                   number(sp.diag(m, I_z + m * a**2), values), atol=1e-12)
        forcing = [m * a * K.u2**2, F * l - m * a * K.u1 * K.u2]
        np.testing.assert_allclose(number(k.forcing, values), number(forcing, values), atol=1e-12)


@pytest.mark.parametrize("value,match", [
    (lambda x3: sp.cos(x3), "expected a list"), (lambda x3: "cos(x_3)", "expected a list"),
    (lambda x3: 2, "expected a list"), (lambda x3: [0], "a number states nothing"),
    (lambda x3: [2], "a number states nothing"), (lambda x3: ["cos(x_3)"], "strings are not parsed"),
    (lambda x3: [sp.S.Zero], "a number"),
    (lambda x3: [sp.sin(x3)**2 + sp.cos(x3)**2 - 1], "identically zero"),
    (lambda x3: [sp.cos(sp.Symbol("z"))], r"\[z\] are neither coordinates"),
    (lambda x3: [sp.cos(x3), sp.nan], "must be finite")])
def test_assume_nonzero_refused_where_it_enters(value, match):
    system, args = notes_skate()
    with pytest.raises(ModelError, match=r"kane: assume_nonzero.*" + match):
        eg.kane(system, **args, assume_nonzero=value(system.q[2]))


x, y = sp.symbols("x y")
b, c = sp.symbols("b c", positive=True)


@settings(max_examples=40, deadline=None)
@given(st.integers(-3, 3), st.integers(-3, 3), st.integers(0, 2),
       st.sampled_from([1, -2, sp.Rational(1, 3)]), st.booleans())
def test_products_of_stated_factors_proven(k1, k2, k3, coefficient, flip):
    """c cos(x)^k1 (x − y)^k2 b^k3 (b > 0) is proven nonzero where cos x ≠ 0 and y − x ≠ 0 are stated (in
    either sign); times sin x or c − b, or plus y, it is not (each vanishes somewhere)."""
    nonzero = Nonzero([sp.cos(x), (y - x) if flip else (x - y)])
    e = coefficient * sp.cos(x)**k1 * (x - y)**k2 * b**k3
    assert nonzero.proves(e)
    assert not nonzero.proves(e * sp.sin(x)) and not nonzero.proves(e * (c - b))
    assert not nonzero.proves(e + y)


def test_symbolic_linearization_under_the_same_assumption():
    """linearize(k, symbolic point) solves on the same pivots: refused without the assumption (naming
    the candidate and assume_nonzero), and with it A = ∂ẋ/∂x of the notes' ẋ = [u1, tan x3 u1, u2,
    M̃⁻¹ f̃]."""
    system, args = notes_skate()
    x1, x2, x3 = system.q
    point = {"x_1": x1, "x_2": x2, "x_3": x3, "u1": K.u1, "u2": K.u2}
    with pytest.raises(ModelError, match=r"candidates \[cos\(x_3\)\].*assume_nonzero=\[cos\(x_3\)\]"):
        eg.linearize(eg.kane(system, **args), point, inputs=["F"], symbolic=True)
    k = eg.kane(system, **args, assume_nonzero=[sp.cos(x3)])
    lin = eg.linearize(k, point, inputs=["F"], symbolic=True)
    notes = notes_closed_forms(x3)
    xdot = notes["qdot"].col_join(notes["mass_matrix"].inv() * notes["forcing"])
    state = [x1, x2, x3, K.u1, K.u2]
    A, B = xdot.jacobian(state), xdot.jacobian([F])
    for values in states(system, 3, 4):
        np.testing.assert_allclose(number(lin.A, values), number(A, values), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(number(lin.B, values), number(B, values), rtol=1e-12, atol=1e-12)
