"""Common-subexpression elimination on symengine (`eomgen.cse`): the same values as the expressions it
rewrites and as sympy's cse, sympy objects out, and the same output whatever Python's hash order."""
import os
import subprocess
import sys
from pathlib import Path

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import eomgen as eg
from eomgen import cse as engines
from eomgen.cse import cse
from eomgen.simplification import simplified

# atoms with assumptions, a name symengine gives its intermediates, a placeholder's name, floats of
# more than double precision and π: each must come back as it went in
x = sp.Symbol("x", positive=True)
y = sp.Symbol("y", real=True)
ATOMS = [x, y, sp.Symbol("x0"), sp.Symbol("_a0"), sp.Float("0.12345678901234567890123", 25), sp.pi,
         sp.Rational(3, 7)]


def trees(depth: int):
    """Random expressions over ATOMS: sums, products, integer powers, sin, cos, exp, Abs."""
    leaf = st.sampled_from(ATOMS)
    if depth == 0:
        return leaf
    sub = trees(depth - 1)
    return st.one_of(
        leaf,
        st.tuples(sub, sub).map(lambda a: a[0] + a[1]),
        st.tuples(sub, sub).map(lambda a: a[0] * a[1]),
        st.tuples(sub, st.integers(-2, 3)).map(lambda a: a[0] ** a[1]),
        st.sampled_from([sp.sin, sp.cos, sp.exp, sp.Abs]).flatmap(lambda f: sub.map(f)),
    )


def value(expr, at: dict) -> mpmath.mpf:
    with mpmath.workdps(40):
        return sp.N(expr.xreplace(at), 30)


def values(replacements, reduced, at: dict) -> list:
    """The reduced expressions evaluated after their definitions, in order."""
    at = dict(at)
    for s, e in replacements:
        at[s] = sp.Float(value(e, at), 30)
    return [value(e, at) for e in reduced]


@settings(max_examples=40, deadline=None)
@given(st.lists(trees(4), min_size=1, max_size=4), st.floats(0.1, 2), st.floats(-2, -0.1))
def test_same_values_as_the_expressions_and_sympy(exprs, xv, yv):
    """At a random point (40 digits), each reduced expression after its definitions equals the expression
    (the truth) and sympy's cse of it, with symengine and without; atoms come back with their assumptions
    and precision."""
    assume(not any(e.has(sp.zoo, sp.nan, sp.oo, -sp.oo) for e in exprs))
    at = {x: sp.Float(xv, 30), y: sp.Float(yv, 30), sp.Symbol("x0"): sp.Float("0.7", 30),
          sp.Symbol("_a0"): sp.Float("-1.3", 30)}
    truth = [value(e, at) for e in exprs]
    assume(all(t.is_finite and abs(t) < 1e30 for t in truth))  # away from poles
    reference = values(*sp.cse(exprs, symbols=sp.numbered_symbols("c", cls=sp.Dummy)), at)
    for engine in (engines.se, None):  # symengine (the test extra installs it), and sympy where absent
        with pytest.MonkeyPatch.context() as monkeypatch:
            monkeypatch.setattr(engines, "se", engine)
            replacements, reduced = cse(exprs, sp.numbered_symbols("c", cls=sp.Dummy))
        assert all(isinstance(e, sp.Basic) for _, e in replacements) and len(reduced) == len(exprs)
        for got, want, theirs in zip(values(replacements, reduced, at), truth, reference):
            assert abs(got - want) <= 1e-25 * max(1, abs(want))
            assert abs(got - theirs) <= 1e-25 * max(1, abs(want))
        found = set().union(*(e.free_symbols for e in reduced), *(e.free_symbols for _, e in replacements))
        assert found - {s for s, _ in replacements} <= set().union(*(e.free_symbols for e in exprs))
    assert engines.se is not None


def test_cse_level_on_a_robot_equals_pinocchio():
    """ur5's closed forms through the "cse" level (symengine's cse): M, nle equal Pinocchio's crba and
    nonLinearEffects at random states."""
    import pinocchio as pin

    from eomgen.model.urdf import pinocchio_configuration

    robot = eg.robots.load("ur5")
    eom = simplified(eg.derive(robot), "cse")
    f = eg.codegen(eom)
    model = robot.pinocchio_model
    data = model.createData()
    q, u, _ = eg.random_states(robot, 5, np.random.default_rng(3))
    for qk, uk, qp in zip(q, u, pinocchio_configuration(robot, q)):
        np.testing.assert_allclose(f.M(qk), pin.crba(model, data, qp), atol=1e-12)
        np.testing.assert_allclose(f.nle(qk, uk), pin.nonLinearEffects(model, data, qp, uk), atol=1e-11)


SOURCES = """
import eomgen as eg
from eomgen.simplification import simplified
from models import double_pendulum
f = eg.codegen(simplified(eg.derive(double_pendulum()), "cse"))
print(repr(f.sources))
"""


def test_deterministic_across_hash_seeds():
    """The generated code of the "cse" level is the same text under two PYTHONHASHSEEDs."""
    tests = Path(__file__).parent
    path = os.pathsep.join([str(tests), str(tests.parent / "src"), os.environ.get("PYTHONPATH", "")])
    runs = [subprocess.Popen([sys.executable, "-c", SOURCES], stdout=subprocess.PIPE, text=True,
                             env={**os.environ, "PYTHONHASHSEED": seed, "PYTHONPATH": path})
            for seed in ("1", "2")]  # at once
    outputs = [run.communicate()[0] for run in runs]
    assert [run.returncode for run in runs] == [0, 0] and outputs[0] == outputs[1] and len(outputs[0]) > 500
