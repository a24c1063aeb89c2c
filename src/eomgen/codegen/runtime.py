"""The runtime of generated code: one text, executed by eomgen for in-memory functions and written
verbatim into generated modules (which need only numpy)."""

RUNTIME = '''
def _inputs(nq, nv, q, u=None, ud=None):
    """q, u, u̇ as float arrays (one state or N along axis 0), checked; and the batch shape."""
    q = numpy.asarray(q, dtype=float)
    if q.ndim not in (1, 2) or q.shape[-1] != nq:
        raise ValueError("q: expected shape (%d,) or (N, %d), got %s" % (nq, nq, q.shape))
    batch = q.shape[:-1]
    args = [q]
    for name, x in (("u", u), ("ud", ud)):
        x = numpy.zeros(batch + (nv,)) if x is None else numpy.asarray(x, dtype=float)
        if x.shape != batch + (nv,):
            raise ValueError("%s: expected shape %s, got %s" % (name, batch + (nv,), x.shape))
        args.append(x)
    for name, x in zip(("q", "u", "ud"), args):
        if not numpy.all(numpy.isfinite(x)):
            raise ValueError(name + ": contains NaN or infinite values")
    return args, batch


def _call(f, shape, nq, nv, q, u=None, ud=None, p=()):
    """Evaluate generated function f at one state (q of shape (nq,), u of shape (nv,)) or N states."""
    args, batch = _inputs(nq, nv, q, u, ud)
    p = [float(x) for x in p]
    if not batch:
        return f(*[x.tolist() for x in args], p, numpy.zeros(shape), math.sin, math.cos, math.sqrt)
    out = f(*[x.T for x in args], p, numpy.zeros(shape + batch), numpy.sin, numpy.cos, numpy.sqrt)
    return numpy.moveaxis(out, (0, 1), (-2, -1))
'''


def runtime_namespace() -> dict:
    """A namespace holding `_inputs` and `_call`, as a generated module has them."""
    import math

    import numpy

    namespace = {"math": math, "numpy": numpy}
    exec(RUNTIME, namespace)  # eomgen's own fixed text
    return namespace
