"""The runtime of generated code: one text, executed by eomgen for in-memory functions and written
verbatim into generated modules (which need only numpy); and the mpmath functions of the reference."""
import math
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


def runtime_namespace() -> dict:
    """A namespace holding `_Scalar`, `_inputs` and `_call`, as a generated module has them (errors:
    ModelError, where a module raises ValueError)."""
    namespace = {"math": math, "numpy": numpy, "_Error": ModelError}
    exec(RUNTIME, namespace)  # eomgen's own fixed text
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
