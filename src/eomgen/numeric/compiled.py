"""The C backend's numeric functions: the same as NumPy's, each catalogue function compiled from C
(`printers.c_extension`; per call and batched). M, nle (else b and g) and the frames derived with them are
built in one extension module up front; where nle is, b and g (its two parts, 40 % of the text: measured
in benchmarks/builds.py) together in one module on the first request of either, the inverse dynamics'
derivatives with the forward dynamics' in one module on first use, any other function in a module of its
own on first use."""
from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..functions import DERIVATIVES
from ..printers.build.extension import compiler, python_headers
from ..printers.c_extension import ExtensionPrinter
from .equations import NumericEoM
from .facade import written
from .forward import euler, forward_checks, joint_efforts
from .lines import check_ends

PARTS = ("b", "g")  # of nle: compiled together on first use


class Compiled:
    """Mixed into a facade: its functions printed by an `ExtensionPrinter` (`batches`: with vector
    functions), called directly."""

    batches = True

    def _print(self, keys: list[str]) -> None:
        if not hasattr(self, "_extension"):
            compiler(), python_headers()  # a clear error before any work (the first print: construction)
            self._extension = ExtensionPrinter(self.catalogue, self.batches)
        if "nle" in keys:  # up front: nle stands for b + g until either is asked for
            keys = [k for k in keys if k not in PARTS]
        elif set(keys) & set(PARTS):
            keys = keys + [k for k in PARTS if k not in keys and k not in self.functions
                           and k in self.catalogue]
        if set(keys) & set(DERIVATIVES):  # the derivatives' group last: a composite after its parts
            keys = [k for k in keys if k not in DERIVATIVES] + [k for k in DERIVATIVES
                                                                 if k in self.catalogue.functions]
        self.functions.update(self._extension.print(keys))

    def _pvec(self, params, key) -> list[float] | np.ndarray | None:
        """p as the extension reads it: the bound values, else those `key` uses (the others 0.0)."""
        if params is None and self.parameters.values is not None:
            return self.parameters.values
        return self.parameter_vector(params, key) if self.params else None

    def call(self, key, q, u=None, ud=None, params=None, out=None) -> np.ndarray:
        result = self.generated(key).function(q, u, ud, self._pvec(params, key), out)
        return check_ends(self, result, q, params)


class CompiledEoM(Compiled, NumericEoM):
    """`NumericEoM` with every function compiled from C (per call and batched)."""

    # the common entry points call the compiled function directly (vector outputs as vectors)
    def M(self, q, params=None, out=None) -> np.ndarray:
        return self.generated("M").function(q, None, None, self._pvec(params, "M"), out)

    def b(self, q, u, params=None, out=None) -> np.ndarray:
        return self.generated("b").vector(q, u, None, self._pvec(params, "b"), out)

    def g(self, q, params=None, out=None) -> np.ndarray:
        return self.generated("g").vector(q, None, None, self._pvec(params, "g"), out)

    def nle(self, q, u, params=None, out=None) -> np.ndarray:
        if "nle" not in self.catalogue:
            return written(self.b(q, u, params) + self.g(q, params), out, q=q, u=u)
        return self.generated("nle").vector(q, u, None, self._pvec(params, "nle"), out)

    def forward_dynamics_derivatives(self, q, u, tau=None, params=None) -> tuple[np.ndarray, ...]:
        if "FD_derivatives" not in self.functions or euler(self.system):
            forward_checks(self, q, params)
        function, p = self.generated("FD_derivatives").function, self._pvec(params, "FD_derivatives")
        try:
            try:
                out = function(q, u, tau, p)
            except ValueError:
                if tau is None or np.ndim(tau) != 1 or np.ndim(q) != 2:
                    raise
                out = function(q, u, np.ascontiguousarray(joint_efforts(tau, self.nv, np.shape(q)[:-1])), p)
        except ValueError as error:  # one τ for all states, else as the extension reads u̇ (named ud)
            text = str(error)
            raise ModelError("tau" + text[2:] if text.startswith("ud:") else text) from None
        nv = self.nv
        if out.ndim == 2:  # one state (sliced without an ellipsis: the common call, kept cheap)
            if out[0, 2 * nv] != out[0, 2 * nv]:  # NaN, as every output, where M is not positive definite
                raise ModelError("forward_dynamics_derivatives: M is not positive definite at this state")
            return out[:, :nv], out[:, nv:2 * nv], out[:, 2 * nv:]
        if np.isnan(out[:, 0, 2 * nv]).any():
            raise ModelError("forward_dynamics_derivatives: M is not positive definite at this state")
        return out[..., :nv], out[..., nv:2 * nv], out[..., 2 * nv:]
