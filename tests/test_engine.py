"""The hot core's two engines (`eomgen.engine`): sympy, the reference, and symengine, the default.

- A sympy expression taken into symengine and back is the same function of the same symbols: symbols of
  one name but other assumptions, eomgen's own names and the engine's token names stay apart (hypothesis,
  40-digit evaluation).
- Both engines' partial derivatives (the chain rule's ∂e/∂y) are the same sympy expression and equal sympy's
  `diff` (hypothesis, 40 digits); sin of a sum, which symengine writes otherwise, is differentiated the
  same from both; a name whose terms cancel in sympy leaves the symbols apart; pickles drop the caches.
- Both engines' sources are byte for byte the same and their numbers equal Pinocchio's and each other's
  (1e-13) on robots of example-robot-data (every robot under `slow`; allegro's hand once printed an unused
  intermediate from symengine, whose symbols had cancelled in sympy), and the sympy engine equals
  Pinocchio on random trees (symengine is every other test's engine).
- Golden source per engine: the module of a symbolic arm printed from each engine's derivation is the
  text in tests/golden (one text: the engines' sources are byte-identical there; regenerate it with
  EOMGEN_GOLDEN=1 after a change meant to change it), and the same text under two PYTHONHASHSEEDs; every
  robot's module source (sha256) the same under two PYTHONHASHSEEDs from each engine (`slow`).
- An unknown engine, or symengine where it is not installed, is refused by name."""
from __future__ import annotations

import os
import subprocess
import sys
import warnings
from pathlib import Path

import mpmath
import numpy as np
import pytest
import sympy as sp
import symengine as se
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

import eomgen as eg
from eomgen import engine
from eomgen.errors import ModelError
from eomgen.model.urdf import pinocchio_configuration
from eomgen.printers.module import module_source
from eomgen.subexpressions import Subexpressions
from eomgen.symbols import Generated

ENGINES = ("sympy", "symengine")
GOLDEN = Path(__file__).parent / "golden"

# --- conversions ----------------------------------------------------------------------------------
x_real, x_plain = sp.Symbol("x", real=True), sp.Symbol("x")
LEAVES = [x_real, x_plain, sp.Symbol("_ε0"), sp.Symbol("_ε1", positive=True), Generated("_ξ0", ("_ξ", 0)),
          sp.Symbol("_ξ0"), sp.Symbol("q_1"), sp.Integer(3), sp.Rational(-2, 7), sp.Float(0.1), sp.pi]


def expressions():
    leaf = st.sampled_from(LEAVES)
    return st.recursive(leaf, lambda inner: st.one_of(
        st.tuples(inner, inner).map(lambda a: a[0] + a[1]),
        st.tuples(inner, inner).map(lambda a: a[0] * a[1]),
        st.tuples(inner, st.integers(-3, 3)).map(lambda a: a[0] ** a[1] if a[0] != 0 or a[1] > 0 else a[0]),
        inner.map(sp.sin), inner.map(sp.cos), inner.map(lambda a: sp.sqrt(a ** 2 + 1)),
        inner.map(sp.Abs), inner.map(sp.atan)), max_leaves=12)


def at(expr, values: dict) -> mpmath.mpc:
    return mpmath.mpmathify(complex(expr.xreplace(values).evalf(40)))


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(expr=expressions())
def test_a_round_trip_is_the_same_function_of_the_same_symbols(expr):
    """Every symbol is told apart from the others by its object (two symbols named x, eomgen's _ξ0 and a
    user's, a user's symbol named like a token): each gets its own value, so mixing any two up changes the
    number."""
    eng = engine.make_engine("symengine")
    back = eng.to_sympy(eng.scalar(expr))
    assert back.free_symbols <= expr.free_symbols  # the very objects, assumptions and all
    values = {s: sp.Float(0.3 + 0.17 * k, 40) for k, s in enumerate(LEAVES) if isinstance(s, sp.Symbol)}
    a, b = at(expr, values), at(back, values)
    assert abs(a - b) <= 1e-25 * max(1, abs(a)), (expr, back)


def test_sums_and_products_come_back_in_sympys_order():
    """Sums and products rebuilt without collecting again are the objects sympy builds itself (equal,
    same hash), so a name given in one engine is found from the other."""
    eng = engine.make_engine("symengine")
    a, b, c = sp.symbols("a b c", real=True)
    for expr in (a + 2 * b + c ** 2, 3 * a * b * sp.sin(c), a * b - c / 5 + 1, sp.cos(a) * sp.sin(b)):
        back = eng.to_sympy(eng.scalar(expr))
        assert back == expr and hash(back) == hash(expr) and back.args == expr.args


NUMBERS = [sp.Integer(2), sp.Integer(-1), sp.Integer(-2), sp.Rational(1, 2), sp.Rational(-2, 7),
           sp.Float(0.5), sp.Float(-1.25)]
a_, b_, c_ = sp.symbols("a b c", real=True)
FACTORS = [a_, b_, c_, sp.sin(a_), sp.cos(b_), a_ ** 2, 1 / c_, sp.sqrt(2),
           sp.Integer(2) ** sp.Rational(1, 3)]


@settings(max_examples=400, deadline=None, derandomize=True, database=None)
@given(c=st.sampled_from(NUMBERS), terms=st.lists(st.tuples(st.sampled_from(NUMBERS + [sp.Integer(1)]),
                                                              st.lists(st.sampled_from(FACTORS), max_size=3)),
                                                    min_size=2, max_size=5),
       rest=st.sampled_from([None, a_, -2 * a_ * b_, sp.sin(a_) / 2]))
def test_a_number_times_a_sum_comes_back_as_sympy_forms_it(c, terms, rest):
    """symengine keeps c (t_1 + ... + t_n) as a product, sympy distributes a rational c (and keeps a float
    one outside): the conversion gives the very object sympy builds from the same operations, also inside a
    sum, where the distributed terms may cancel others."""
    eng = engine.make_engine("symengine")
    total = sp.Add(*[k * sp.Mul(*f) for k, f in terms])
    expr, made = c * total, eng.scalar(c) * eng.scalar(total)
    if rest is not None:
        expr, made = expr + rest, made + eng.scalar(rest)
    back = eng.to_sympy(made)
    assert back == expr and back.args == expr.args and hash(back) == hash(expr), (back, expr)


def engine_products(eng):
    """Products built in symengine from its own leaves: symbols, sin, numbers, radicals it keeps as they are
    written (√8, √3 √6, 4^(1/3)), which sympy simplifies where it multiplies them, and a number times a
    sum, which sympy distributes (2 (b − a/2) + a = 2 b)."""
    root = se.Integer
    a, b = eng.scalar(a_), eng.scalar(b_)
    leaves = [a, b, se.sin(a), se.sqrt(root(2)), se.sqrt(root(3)), se.sqrt(root(6)), se.sqrt(root(8)),
              root(4) ** se.Rational(1, 3), root(2) ** se.Rational(2, 3), 2 * (b - a / 2)]
    numbers = st.sampled_from([root(1), root(2), root(-1), se.Rational(1, 2), se.Rational(-2, 3),
                               se.RealDouble(0.5), se.RealDouble(-1.25)])
    return st.tuples(numbers, st.lists(st.sampled_from(leaves), max_size=3)).map(
        lambda kf: kf[0] * sp.prod(kf[1], start=root(1)))


SYMENGINE = engine.make_engine("symengine") if engine.se is not None else None


def _cancelling() -> list:
    """Terms whose sum sympy collects (a + 2 (b − a/2) + sin b = 2 b + sin b)."""
    a, b = SYMENGINE.scalar(a_), SYMENGINE.scalar(b_)
    return [a, 2 * (b - a / 2), se.sin(b)]


@settings(max_examples=400, deadline=None, derandomize=True, database=None)
@example(c=2, terms=_cancelling(), rest=None)
@given(c=st.sampled_from([2, -1, -2, sp.Rational(1, 2), sp.Rational(-2, 7), 0.5, -1.25]),
       terms=st.lists(engine_products(SYMENGINE), min_size=2, max_size=5),
       rest=st.sampled_from([None, a_, -2 * a_ * b_, sp.sin(a_) / 2]))
def test_a_number_times_a_sum_built_in_symengine_is_what_sympys_mul_makes_of_it(c, terms, rest):
    """The same for sums symengine built, where a term may be a radical it keeps (√8) or a product of
    radicals (√3 √6) that sympy simplifies when it multiplies: c (t_1 + ... + t_n) converted is sympy's
    `Mul` of c and the converted sum (whose terms may then collect: 2 (√8 + √2) = 6 √2), and a definition's
    symbols are those of its sympy form (or None where terms collected)."""
    eng = SYMENGINE
    total = terms[0]
    for term in terms[1:]:
        total = total + term
    assume(type(total) is se.Add)  # terms that collected into one are no sum
    made = eng.scalar(sp.sympify(c)) * total
    expr = sp.Mul(eng.to_sympy(eng.scalar(sp.sympify(c))), eng.to_sympy(total))
    if rest is not None:
        made, expr = made + eng.scalar(rest), sp.Add(expr, rest)
    back, symbols = eng.definition(made)
    assert back == expr and back.args == expr.args and hash(back) == hash(expr), (back, expr)
    assert symbols is None or set(symbols) == back.free_symbols


def plain_expressions():
    """Sums, products, integer powers and square roots of the leaves and of their sin and cos (what the
    engines' `diff` takes: the hot core's sin and cos are of coordinates; symengine writes sin(x − 2/7) as
    −sin(2/7 − x), another expression of the same function)."""
    leaf = st.one_of(st.sampled_from(LEAVES), st.sampled_from(LEAVES).map(sp.sin),
                     st.sampled_from(LEAVES).map(sp.cos))
    return st.recursive(leaf, lambda inner: st.one_of(
        st.tuples(inner, inner).map(lambda a: a[0] + a[1]),
        st.tuples(inner, inner).map(lambda a: a[0] * a[1]),
        st.tuples(inner, st.integers(-3, 3)).map(lambda a: a[0] ** a[1] if a[0] != 0 or a[1] > 0 else a[0]),
        inner.map(lambda a: sp.sqrt(a ** 2 + 1))), max_leaves=12)


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(expr=plain_expressions())
def test_both_engines_differentiate_to_the_same_expression_as_sympy_diff(expr):
    """∂e/∂y from each engine's `diff` (the chain rule's partials) is the same sympy expression, object
    for object (so the derivatives' sources match), and equals sympy's own `diff` (40 digits)."""
    reference, fast = engine.make_engine("sympy"), engine.make_engine("symengine")
    values = {s: sp.Float(0.3 + 0.17 * k, 40) for k, s in enumerate(LEAVES) if isinstance(s, sp.Symbol)}
    for y in sorted(expr.free_symbols, key=str):
        ours = reference.to_sympy(reference.diff(expr, y))
        assert sp.srepr(fast.to_sympy(fast.diff(fast.scalar(expr), fast.scalar(y)))) == sp.srepr(ours)
        a, b = at(ours, values), at(sp.diff(expr, y), values)
        assert abs(a - b) <= 1e-25 * max(1, abs(b)), (expr, y, ours)


def test_a_name_whose_terms_cancel_in_sympy_keeps_the_symbols_apart():
    """symengine keeps 2 (a/2 + b) − 2 b, whose sympy form is the symbol a: naming it must not make `a`
    stand for that engine expression (the derivatives of a would be lost)."""
    a, b, c = sp.symbols("a b c")
    sub = Subexpressions(engine="symengine")
    sub.scalar(sp.sin(a) + b * c)  # a and b met inside an expression only
    A, B = sub.engine.token(a), sub.engine.token(b)
    sub.add(2 * (A / 2 + B) - 2 * B)
    assert sub.derivative(a * c, {a: 1}, "a") == c and sub.scalar(a) == A


def test_a_definition_reads_the_symbols_of_its_sympy_form():
    """A node symengine converts itself (Abs) may collect a sum inside, 2 (a/2 + b) − 2 b → a: the
    symbols a definition reads (which inputs the printers read) are those of its sympy form."""
    a, b, c = sp.symbols("a b c")
    sub = Subexpressions(engine="symengine")
    sub.scalar(sp.sin(a) + b * c)
    A, B, C = (sub.engine.token(s) for s in (a, b, c))
    for e in (engine.se.Abs(2 * (A / 2 + B) - 2 * B) * C, engine.se.sin(2 * (A / 2 + B) - 2 * B) * C):
        name = sub.engine.to_sympy(sub.add(e))
        assert sub.reads(name) == sub.definitions[name].free_symbols == {a, c}


def test_sin_of_a_sum_differentiates_to_one_expression_in_both_engines():
    """Expressions that do not come from the hot core (loads, sympy's own terms) may hold sin and cos of
    sums, which symengine writes otherwise (sin(a − b) as −sin(b − a)): their derivative is the same
    object from both engines, and sympy's diff."""
    a, b, x, y = sp.symbols("a b x y")
    expr, seeds = x * sp.sin(a - b) + sp.cos(2 * a) * b, {a: 1, x: y, b: 1}
    results = [Subexpressions(engine=e).derivative(expr, seeds, "t") for e in ENGINES]
    assert sp.srepr(results[0]) == sp.srepr(results[1])
    direct = sum(sp.diff(expr, s) * v for s, v in seeds.items())
    assert sp.expand(results[0] - direct) == 0


def test_equations_pickle_without_the_engines_caches():
    """The partials, dependency lists and conversions are dropped from a pickle (sweep sends and hashes
    it) and rebuilt after: the derivatives come out the same."""
    import pickle

    from models import spatial_arm_3dof
    eom = eg.derive(spatial_arm_3dof(), method="lagrange")
    sub = eom.kinematics.sub
    q = list(eom.system.q)
    before = sub.derivative(eom.M[0, 1], {q[1]: 1}, ("test", 1))
    assert sub._gradients and sub.engine._out
    loaded = pickle.loads(pickle.dumps(eom))
    again = loaded.kinematics.sub
    assert not again._gradients and not again._needs and not again.engine._out
    assert again.derivative(loaded.M[0, 1], {q[1]: 1}, ("test", 2)) == before


# --- both engines on robots -----------------------------------------------------------------------
def check_robot(name: str, states: int = 3) -> None:
    """Both engines' module sources byte for byte the same; their numbers equal each other (1e-13) and
    Pinocchio's crba, nonLinearEffects and computeGeneralizedGravity (1e-10 relative)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # files with inertias Pinocchio takes as they are
        system = eg.robots.load(name)
    eoms = {e: eg.derive(system, engine=e) for e in ENGINES}
    assert module_source(eoms["sympy"]) == module_source(eoms["symengine"]), f"{name}: the sources differ"
    f = {e: eg.codegen(eom) for e, eom in eoms.items()}
    model = system.pinocchio_model
    data = model.createData()
    q, u, _ = eg.random_states(system, states, np.random.default_rng(5))
    for qk, uk, qp in zip(q, u, pinocchio_configuration(system, q)):
        ours = {e: (f[e].M(qk), f[e].nle(qk, uk), f[e].g(qk)) for e in ENGINES}
        pin_M = np.triu(pin.crba(model, data, qp))
        pin_M = pin_M + np.triu(pin_M, 1).T
        ref = (pin_M, pin.nonLinearEffects(model, data, qp, uk), pin.computeGeneralizedGravity(model, data, qp))
        for key, a, b, r in zip("M nle g".split(), ours["sympy"], ours["symengine"], ref):
            scale = max(1.0, float(np.abs(r).max()))
            assert np.abs(a - b).max() <= 1e-13 * scale, f"{name} {key}: the engines differ"
            assert np.abs(b - r).max() <= 1e-10 * scale, f"{name} {key}: Pinocchio"


import pinocchio as pin  # noqa: E402

EVERY = eg.robots.names()
SOME = ["ur5", "solo12", "kinova", "talos_arm", "double_pendulum", "allegro_left_hand"]


@pytest.mark.parametrize("name", SOME)
def test_both_engines_equal_pinocchio(name):
    check_robot(name)


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n in EVERY if n not in SOME])
def test_both_engines_equal_pinocchio_on_every_robot(name):
    check_robot(name)


def test_the_reference_engine_on_random_trees():
    """The sympy engine (every other test derives with symengine) against Pinocchio built with its own
    API, on random trees with adversarial names and every method."""
    import strategies as S
    from test_properties import COMMON, METHODS, check_pinocchio

    @settings(max_examples=16, **COMMON)
    @given(tree=S.trees(), method=st.sampled_from(METHODS))
    def run(tree, method):
        check_pinocchio(tree, eg.derive(S.eomgen_system(tree), method=method, engine="sympy"))

    run()


# --- golden sources, hash seeds ------------------------------------------------------------------
SOURCE = """
import sys
import eomgen as eg
from eomgen.printers.module import module_source
from models import spatial_arm_3dof
print(module_source(eg.derive(spatial_arm_3dof(), engine=sys.argv[1]), title="arm"), end="")
"""


ROBOT_DIGESTS = """
import hashlib, sys, warnings
import eomgen as eg
from eomgen.printers.module import module_source
warnings.simplefilter("ignore")
system = eg.robots.load(sys.argv[1])
for engine in ("sympy", "symengine"):
    print(engine, hashlib.sha256(module_source(eg.derive(system, engine=engine)).encode()).hexdigest())
"""


def sources(argument: str, seed: str, script: str = SOURCE) -> subprocess.Popen:
    """`script` (the golden arm's source by default) run with `argument` under PYTHONHASHSEED=`seed`."""
    tests = Path(__file__).parent
    path = os.pathsep.join([str(tests), str(tests.parent / "src"), os.environ.get("PYTHONPATH", "")])
    return subprocess.Popen([sys.executable, "-c", script, argument], stdout=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONHASHSEED": seed, "PYTHONPATH": path})


@pytest.mark.slow
@pytest.mark.parametrize("name", EVERY)
def test_every_robots_sources_under_two_hash_seeds(name):
    """Each robot's module source (sha256) from each engine is the same under PYTHONHASHSEED 1 and 2, and
    the same from both engines."""
    runs = [sources(name, seed, ROBOT_DIGESTS) for seed in ("1", "2")]  # at once
    outputs = [run.communicate()[0] for run in runs]
    assert [run.returncode for run in runs] == [0, 0] and outputs[0] == outputs[1], outputs
    digests = dict(line.split() for line in outputs[0].splitlines())
    assert digests["sympy"] == digests["symengine"], f"{name}: the engines' sources differ"


@pytest.mark.parametrize("engine_name", ENGINES)
def test_golden_source_and_hash_seeds(engine_name):
    runs = [sources(engine_name, seed) for seed in ("1", "2")]  # at once
    outputs = [run.communicate()[0] for run in runs]
    assert [run.returncode for run in runs] == [0, 0] and outputs[0] == outputs[1]
    golden = GOLDEN / "spatial_arm_3dof.txt"
    if os.environ.get("EOMGEN_GOLDEN") and engine_name == "sympy":  # the reference writes it
        golden.write_text(outputs[0])
    assert outputs[0] == golden.read_text(), f"the {engine_name} engine's source changed: see {golden}"


def test_the_golden_sources_compute_the_same_equations():
    """The two engines' modules of the symbolic arm (their own text) give the same M, b, g."""
    from models import spatial_arm_3dof

    system, rng = spatial_arm_3dof(), np.random.default_rng(2)
    params = {str(p): rng.uniform(0.5, 1.5) for p in sorted(system.parameters, key=str)}
    f = {e: eg.codegen(eg.derive(system, engine=e), params=params) for e in ENGINES}
    for _ in range(3):
        q, u = rng.uniform(-3, 3, 3), rng.uniform(-2, 2, 3)
        for ours in (lambda g: g.M(q), lambda g: g.b(q, u), lambda g: g.g(q)):
            np.testing.assert_allclose(ours(f["sympy"]), ours(f["symengine"]), rtol=1e-13, atol=1e-13)


# --- refusals -------------------------------------------------------------------------------------
def test_unknown_engine_is_refused():
    from models import spatial_arm_3dof

    with pytest.raises(ModelError, match="engine: 'cas' is not one of"):
        eg.derive(spatial_arm_3dof(), engine="cas")


def test_symengine_missing_is_refused(monkeypatch):
    from models import spatial_arm_3dof

    monkeypatch.setattr(engine, "se", None)
    assert engine.default_engine() == "sympy"
    with pytest.raises(ModelError, match="engine 'symengine' is not installed"):
        eg.derive(spatial_arm_3dof(), engine="symengine")
