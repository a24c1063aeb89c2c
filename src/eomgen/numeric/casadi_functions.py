"""The CasADi backend: the catalogue's functions as `casadi.Function`s on SX (`printers.traced`), for
optimal control (`casadi.Opti`, IPOPT) with CasADi's own derivatives; with numbers they return arrays
like the other backends. `f.casadi[key]` takes the function's inputs (q; q, u; q, u, ud) and, unless the
parameters are bound, p (the parameter vector, sorted by name as `f.params`); besides the catalogue's,
"forward_dynamics" (q, u, tau_a[, p]) → u̇ = M⁻¹ (τ + Sᵀ τ_a − b − g), solved by CasADi."""
from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..printers.traced import TRACED, casadi_expression
from ..printers.walker import Generated, writer
from .equations import NumericEoM


class CasadiPrinted:
    """Mixed into a facade: its catalogue's functions printed as CasADi functions of (q, u, ud, p); numbers
    in, arrays out (one state, or N along axis 0, evaluated one by one), so that the NumPy algorithms run
    on them."""

    forward = False  # whether casadi["forward_dynamics"] is made besides the catalogue's functions

    def _print(self, keys: list[str]) -> None:
        import casadi as ca

        traced = writer(self.catalogue, TRACED)
        symbols = [ca.SX.sym(x, n) for x, n in (("q", self.nq), ("u", self._nu), ("ud", self._nu),
                                                 ("p", len(self.params)))]
        for key in keys:
            fn = self.catalogue.printable(key)
            source, shape, ops = traced.function("f", fn)
            expr = casadi_expression(source, shape, key, *symbols)
            function = ca.Function(_name(key), symbols, [expr], ["q", "u", "ud", "p"], [_name(key)])
            self.functions[key] = Generated(source, shape, ops, function)

    @property
    def casadi(self):
        """The CasADi function of each catalogue function by key, of its inputs (and p unless the
        parameters are bound)."""
        return CasadiFunctions(self)

    def call(self, key, q, u=None, ud=None, params=None, out=None) -> np.ndarray:
        from .facade import written

        function = self.generated(key).function
        p = np.asarray(self.parameter_vector(params, key), float)
        q = np.asarray(q, float)
        if q.ndim not in (1, 2) or q.shape[-1] != self.nq:
            raise ModelError(f"q: expected shape ({self.nq},) or (N, {self.nq}), got {q.shape}")
        batch = q.shape[:-1]
        u, ud = (np.zeros(batch + (self._nu,)) if x is None else np.asarray(x, float) for x in (u, ud))
        states = [function(*x, p).full() for x in zip(*(np.atleast_2d(y) for y in (q, u, ud)))]
        result = np.stack(states) if batch else states[0]
        return written(result, out, q=q, u=u, ud=ud)


class CasadiEoM(CasadiPrinted, NumericEoM):
    """`NumericEoM` whose functions are CasADi functions (`CasadiPrinted`); `casadi["forward_dynamics"]`
    besides the catalogue's."""

    forward = True


def _name(key: str) -> str:
    """A CasADi name for a key ("J:tip" → "J_tip"; other characters as their code)."""
    return "".join(c if c.isalnum() or c == "_" else "_" if c == ":" else f"x{ord(c):x}" for c in key)


class CasadiFunctions:
    """f.casadi[key]: the CasADi function of catalogue function `key` of its inputs (and p unless bound)."""

    def __init__(self, f: CasadiPrinted) -> None:
        self.f = f

    def __getitem__(self, key: str):
        import casadi as ca

        f = self.f
        if key == "forward_dynamics" and f.forward:
            return self._forward()
        fn, full = f.catalogue[key], f.generated(key).function
        given = {x: ca.SX.sym(x, n) for x, n in (("q", f.nq), ("u", f._nu), ("ud", f._nu))}
        names = [x.strip() for x in fn.inputs.split(",")]
        args = [given["ud" if x == "tau" else x] if x in names or (x == "ud" and "tau" in names)
                else ca.SX.zeros(f._nu) for x in ("q", "u", "ud")]
        inputs, labels = [given["ud" if x == "tau" else x] for x in names], names
        p = self._p(inputs, labels)
        return ca.Function(_name(key), inputs, [full(*args, p)], labels, [_name(key)])

    def _p(self, inputs: list, labels: list):
        """The parameter vector: none, the bound values, or a symbol p added to the inputs."""
        import casadi as ca

        f = self.f
        if not f.params:
            return ca.DM.zeros(0)
        if f.parameters.values is not None:
            return ca.DM(f.parameters.values)
        p = ca.SX.sym("p", len(f.params))
        inputs.append(p)
        labels.append("p")
        return p

    def _forward(self):
        import casadi as ca

        f = self.f
        q, u, tau_a = ca.SX.sym("q", f.nq), ca.SX.sym("u", f.nv), ca.SX.sym("tau_a", f.S.shape[0])
        inputs, labels = [q, u, tau_a], ["q", "u", "tau_a"]
        p = self._p(inputs, labels)
        zero = ca.SX.zeros(f.nv)
        M = f.generated("M").function(q, zero, zero, p)
        nle = (f.generated("nle").function(q, u, zero, p) if "nle" in f.catalogue
               else f.generated("b").function(q, u, zero, p) + f.generated("g").function(q, zero, zero, p))
        h = f.generated("tau").function(q, u, zero, p) - nle + ca.DM(f.S).T @ tau_a
        return ca.Function("forward_dynamics", inputs, [ca.solve(M, h)], labels, ["ud"])
