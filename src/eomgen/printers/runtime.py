"""The runtime of generated code: texts executed by eomgen for in-memory functions and written verbatim
into generated modules (which need only numpy); and the mpmath functions of the reference."""
import math
from collections.abc import Mapping
from functools import cache

import numpy

from ..errors import ModelError

RUNTIME = '''
class _Scalar:
    """The functions of generated code at one state but sin, cos, sqrt: math's, with numpy's names."""

    tan, exp, log, sinh, cosh, tanh = math.tan, math.exp, math.log, math.sinh, math.cosh, math.tanh
    arcsin, arccos, arctan, arctan2 = math.asin, math.acos, math.atan, math.atan2
    fabs, power, nan = math.fabs, math.pow, math.nan

    @staticmethod
    def sign(x):
        return 1.0 if x > 0.0 else -1.0 if x < 0.0 else 0.0 * x

    @staticmethod
    def heaviside(x, h):
        return 1.0 if x > 0.0 else 0.0 if x < 0.0 else h + 0.0 * x

    @staticmethod
    def fmin(a, b):  # the other where one is nan
        return b if b < a or a != a else a

    @staticmethod
    def fmax(a, b):
        return b if b > a or a != a else a

    @staticmethod
    def where(c, a, b):
        return a if c else b

    @staticmethod
    def logical_not(c):
        return not c


def _inputs(nq, nv, q, u=None, ud=None):
    """q, u, u̇ as float arrays (one state or N along axis 0), checked; and the batch shape."""
    def numbers(name, x):
        try:
            a = numpy.asarray(x)
            if a.dtype.kind in "fiuO":  # not strings, bools or complex numbers
                return a.astype(float, copy=False)
        except (TypeError, ValueError):
            pass
        raise _Error("%s: expected real numbers, got %s" % (name, type(x).__name__))

    q = numbers("q", q)
    if q.ndim not in (1, 2) or q.shape[-1] != nq:
        raise _Error("q: expected shape (%d,) or (N, %d), got %s" % (nq, nq, q.shape))
    batch = q.shape[:-1]
    args = [q]
    for name, x in (("u", u), ("ud", ud)):
        x = numpy.zeros(batch + (nv,)) if x is None else numbers(name, x)
        if x.shape != batch + (nv,):
            raise _Error("%s: expected shape %s, got %s" % (name, batch + (nv,), x.shape))
        args.append(x)
    for name, x in zip(("q", "u", "ud"), args):
        if not numpy.isfinite(x).all():
            raise _Error(name + ": contains NaN or infinite values")
    return args, batch


def _call(f, shape, nq, nv, q, u=None, ud=None, p=()):
    """Evaluate generated function f at one state (q of shape (nq,), u of shape (nv,)) or N states."""
    args, batch = _inputs(nq, nv, q, u, ud)
    p = [float(x) for x in p]
    if not batch:
        try:
            return f(*[x.tolist() for x in args], p, numpy.zeros(shape), math.sin, math.cos, math.sqrt,
                     _Scalar)
        except (ArithmeticError, ValueError):  # math raises at a pole or off the domain, maybe in a branch
            pass  # of a Piecewise not taken: numpy's float64 scalars give IEEE results (inf, nan) as C does
    p = [numpy.float64(x) for x in p]
    if not batch:
        return f(*[list(x) for x in args], p, numpy.zeros(shape), numpy.sin, numpy.cos, numpy.sqrt, numpy)
    out = f(*[x.T for x in args], p, numpy.zeros(shape + batch), numpy.sin, numpy.cos, numpy.sqrt, numpy)
    return numpy.moveaxis(out, (0, 1), (-2, -1))
'''

# the parameter vector and the actuated joints' term (`numeric.parameters`)
PARAMETERS = '''
_TESTS = {"positive": (lambda x: x > 0.0, "> 0"), "negative": (lambda x: x < 0.0, "< 0"),
          "nonnegative": (lambda x: x >= 0.0, ">= 0"), "nonpositive": (lambda x: x <= 0.0, "<= 0"),
          "nonzero": (lambda x: x != 0.0, "nonzero"),
          "integer": (lambda x: x == math.floor(x), "an integer")}


def _parameter_vector(names, index, used, values, rules):
    """p (p[k]: the value of names[k]; index maps a name or symbol to k) from a mapping {name: value};
    the k outside `used` may be left out (0.0). rules[k]: the assumptions (_TESTS) p[k] must meet."""
    if values is None:
        values = {}
    if not isinstance(values, Mapping):
        raise _Error("params: expected a mapping {name: value} (parameters are given by name only), got %s;"
                     " the parameters are %s" % (type(values).__name__, list(names)))
    p = [0.0] * len(names)
    given, unknown, bad, wrong = set(), [], [], []
    for key, value in values.items():
        k = index.get(key)
        if k is None:
            k = index.get(str(key))
            if k is None:
                unknown.append(str(key))
                continue
        try:
            p[k] = math.nan if isinstance(value, (str, bytes, bool, numpy.bool_)) else float(value)
        except (TypeError, ValueError):
            p[k] = math.nan
        if not math.isfinite(p[k]):
            bad.append(names[k])
        elif k in rules:
            for rule in rules[k]:
                if not _TESTS[rule][0](p[k]):
                    wrong.append("%s = %r (must be %s)" % (names[k], p[k], _TESTS[rule][1]))
        given.add(k)
    if unknown:
        raise _Error("params: unknown parameters %s; the parameters are %s" % (unknown, list(names)))
    if not given.issuperset(used):
        missing = [names[k] for k in sorted(set(used) - given)]
        raise _Error("params: values missing for the parameters %s" % missing)
    if bad:
        raise _Error("params: the values of %s are not finite real numbers (strings and bools are refused)"
                     % bad)
    if wrong:
        raise _Error("params: values contradicting the parameters' assumptions: %s" % "; ".join(wrong))
    return p


def _actuated(h, tau_a, S):
    """h + Sᵀ τ_a, τ_a with one value per actuated joint (per state, or one for all states)."""
    if tau_a is None:
        return h
    tau_a = numpy.asarray(tau_a, dtype=float)
    if tau_a.shape[-1:] != (S.shape[0],) or not numpy.all(numpy.isfinite(tau_a)):
        raise _Error("tau_a: expected %d finite values (one per actuated joint), got shape %s"
                     % (S.shape[0], tau_a.shape))
    return h + tau_a @ S
'''

# the forward dynamics' derivatives from D = ∂(τ_ID − τ_loads)/∂(q, u) (`numeric.forward`)
DERIVATIVES = '''
def _efforts(tau, nv, batch):
    """tau (one effort per speed, for all states or one per state) as floats of shape batch + (nv,)."""
    if tau is None:
        return numpy.zeros(batch + (nv,))
    try:
        t = numpy.asarray(tau, dtype=float)
    except (TypeError, ValueError):
        raise _Error("tau: expected %d real numbers (one per speed), got %s"
                     % (nv, type(tau).__name__)) from None
    if t.shape not in ((nv,), batch + (nv,)) or not numpy.all(numpy.isfinite(t)):
        raise _Error("tau: expected %d finite values (one per speed), shape (%d,) or %s, got shape %s"
                     % (nv, nv, batch + (nv,), t.shape))
    return numpy.broadcast_to(t, batch + (nv,))


def _forward_derivatives(M, h, jacobian, nv):
    """(−M⁻¹ D_q, −M⁻¹ D_u, M⁻¹) with D = jacobian(u̇) at u̇ = M⁻¹ h; M⁻¹ = L⁻ᵀ L⁻¹, M = L Lᵀ."""
    try:
        L_inv = numpy.linalg.inv(numpy.linalg.cholesky(M))
    except numpy.linalg.LinAlgError:
        raise _Error("forward_dynamics_derivatives: M is not positive definite at this state") from None
    M_inv = numpy.swapaxes(L_inv, -1, -2) @ L_inv
    D = -M_inv @ jacobian(numpy.einsum("...ij,...j->...i", M_inv, h))
    return D[..., :nv], D[..., nv:], M_inv
'''


@cache
def runtime_namespace() -> dict:
    """A namespace holding the runtime's functions (`_Scalar`, `_inputs`, `_call`, `_parameter_vector`,
    `_actuated`, `_efforts`, `_forward_derivatives`), as a generated module has them (errors: ModelError,
    where a module raises ValueError)."""
    namespace = {"math": math, "numpy": numpy, "Mapping": Mapping, "_Error": ModelError}
    exec(RUNTIME + PARAMETERS + DERIVATIVES, namespace)  # eomgen's own fixed text
    return namespace


@cache
def mpmath_functions() -> type:
    """The functions of generated code in mpmath at the working precision (sin, cos and sqrt too, passed
    apart): nan where the real function is undefined, as float64 code gives; `_Scalar`'s for the rest."""
    import mpmath

    def real(f):
        def g(*args):
            r = f(*args)
            return r if r.imag == 0 else mpmath.nan
        return staticmethod(g)

    smooth = ("sin", "cos", "tan", "tanh", "exp", "sinh", "cosh", "fabs")
    functions = {k: staticmethod(getattr(mpmath, k)) for k in smooth}
    functions.update(arctan=staticmethod(mpmath.atan), arctan2=staticmethod(mpmath.atan2),
                     sqrt=real(mpmath.sqrt), log=real(mpmath.log), arcsin=real(mpmath.asin),
                     arccos=real(mpmath.acos), power=real(mpmath.power), nan=mpmath.nan)
    return type("_Mpmath", (runtime_namespace()["_Scalar"],), functions)
