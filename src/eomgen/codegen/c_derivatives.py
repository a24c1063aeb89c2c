"""The forward dynamics' derivatives in C (formulas in `derivative_functions`), one function

    f(q, u, tau, p, out),   out = [∂u̇/∂q | ∂u̇/∂u | ∂u̇/∂τ = M⁻¹]   (nv × 3 nv, row-major),

that evaluates [M | τ_loads − b − g] (`derivative_functions.forward_parts`), factors M = Lᵀ L (L lower
triangular, from the last speed up: Featherstone's LTL factorisation, no fill-in when every speed's
ancestors come before it; the zeros of a tree are skipped), solves for u̇ = M⁻¹ (τ + τ_loads − b − g),
evaluates D = ∂(τ_ID − τ_loads)/∂(q, u) at u̇ and solves M X = [−D | 1]. Where M is not positive definite
every output is NaN. The same text serves the extension (with the arrays sinq, cosq) and `write_c`."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import ModelError
from . import listed, reads
from .numpy_backend import C, C_TRIG, Syntax
from .derivative_functions import efforts, forward_dynamics, forward_key, forward_parts, jacobians
from .vector import vector_sources

TEMPLATE = r"""/* A = Lᵀ L in place on A's lower triangle (row-major, @lda@ columns), L lower triangular;
   0 unless A is positive definite */
static int @name@_factor(double *A)
{
    for (int k = @nv@ - 1; k >= 0; --k) {
        double *Ak = A + k * @lda@;
        if (!(Ak[k] > 0.0))
            return 0;
        double d = sqrt(Ak[k]), r = 1.0 / d;
        Ak[k] = d;
        for (int i = 0; i < k; ++i)
            Ak[i] *= r;
        for (int i = 0; i < k; ++i) {
            double a = Ak[i], *Ai = A + i * @lda@;
            if (a != 0.0)
                for (int j = 0; j <= i; ++j)
                    Ai[j] -= a * Ak[j];
        }
    }
    return 1;
}

/* X := (Lᵀ L)⁻¹ X, X row-major with m columns */
static void @name@_solve(const double *A, double *X, int m)
{
    for (int k = @nv@ - 1; k >= 0; --k) {
        const double *Ak = A + k * @lda@;
        double r = 1.0 / Ak[k], *Xk = X + k * m;
        for (int c = 0; c < m; ++c)
            Xk[c] *= r;
        for (int i = 0; i < k; ++i) {
            double a = Ak[i], *Xi = X + i * m;
            if (a != 0.0)
                for (int c = 0; c < m; ++c)
                    Xi[c] -= a * Xk[c];
        }
    }
    for (int k = 0; k < @nv@; ++k) {
        const double *Ak = A + k * @lda@;
        double r = 1.0 / Ak[k], *Xk = X + k * m;
        for (int j = 0; j < k; ++j) {
            double a = Ak[j];
            const double *Xj = X + j * m;
            if (a != 0.0)
                for (int c = 0; c < m; ++c)
                    Xk[c] -= a * Xj[c];
        }
        for (int c = 0; c < m; ++c)
            Xk[c] *= r;
    }
}

@header@
    double A[@nv@ * @lda@] = {0}, D[@nv@ * 2 * @nv@] = {0}, ud[@nv@];
    @parts@(q, u, u, p, @trig@A);
    if (!@name@_factor(A)) {
        for (int k = 0; k < 3 * @nv@ * @nv@; ++k)
            out[k] = NAN;
        return;
    }
    for (int i = 0; i < @nv@; ++i)
        ud[i] = A[i * @lda@ + @nv@] + tau[i];
    @name@_solve(A, ud, 1);
    @jacobian@(q, u, ud, p, @trig@D);
    for (int i = 0; i < @nv@; ++i) {
        for (int j = 0; j < 2 * @nv@; ++j)
            out[i * 3 * @nv@ + j] = -D[i * 2 * @nv@ + j];
        for (int j = 0; j < @nv@; ++j)
            out[i * 3 * @nv@ + 2 * @nv@ + j] = i == j;
    }
    @name@_solve(A, out, 3 * @nv@);
}
"""


def forward_derivatives_source(name: str, parts: str, jacobian: str, nv: int, syntax: Syntax) -> str:
    """The C text of `name`(q, u, tau, p, out) (`syntax`: with the arrays sinq, cosq for the extension),
    calling the generated functions `parts` ([M | h]) and `jacobian` (D)."""
    text = TEMPLATE
    for key, value in {
        "header": syntax.header.format(name=name).replace("*ud", "*tau"),
        "name": name,
        "parts": parts,
        "jacobian": jacobian,
        "nv": str(nv),
        "lda": str(nv + 1),
        "trig": "sinq, cosq, " if "sinq" in syntax.header else "",
    }.items():
        text = text.replace(f"@{key}@", value)
    return text


def plain_parts(eom) -> list[tuple]:
    """For `write_c` (with M, b, g): the entry of [M | h], which <name>_FD_derivatives calls."""
    if not forward_dynamics(eom):
        return []
    return [
        (
            "FD_parts",
            forward_parts(eom),
            False,
            "[M | τ_loads − b − g] (M's lower triangle), for FD_derivatives",
            [],
        )
    ]


def plain_function(eom, name: str, sources: dict[str, str]) -> tuple[str, str] | None:
    """For `write_c` (with M, b, g): the text and the declaration of <name>_FD_derivatives, given the
    written sources by key."""
    if not forward_dynamics(eom):
        return None
    key, nv = forward_key(eom), len(eom.u)
    text = forward_derivatives_source(f"{name}_FD_derivatives", f"{name}_FD_parts", f"{name}_{key}", nv, C)
    used = reads(sources["FD_parts"] + sources[key])
    read = listed({arg: ks for arg, ks in used.items() if arg != "ud"})
    declaration = (
        "/* [∂u̇/∂q | ∂u̇/∂u | ∂u̇/∂τ] of the forward dynamics M u̇ = τ + τ_loads − b − g at q, u, τ (NV "
        "joint efforts,\n * in the place of ud); out: NV x 3 NV, row-major, every entry written (NaN "
        "where M is not positive definite);\n * reads "
        f"{read}, tau */\n"
        + C.header.format(name=f"{name}_FD_derivatives").split("\n")[0].replace("*ud", "*tau")
        + ";"
    )
    return text, declaration


class CompiledDerivatives:
    """Mixed into `CompiledEoM`: the Jacobians of the dynamics and (with M, b, g) the forward dynamics'
    derivatives built in one extension module on first use, the latter one compiled call; batches of the
    Jacobians in vector registers (`vector`)."""

    def _dynamics_jacobian(self, key: str, q, u, ud, params) -> np.ndarray:
        self._build_derivatives()
        return self.call(key, q, u, ud, params)

    def forward_dynamics_derivatives(self, q, u, tau=None, params=None) -> tuple[np.ndarray, ...]:
        if "FD_derivatives" not in self.functions:
            self._forward_checks(q, params)
            self._build_derivatives()
        elif self._euler:
            self._forward_checks(q, params)
        function, p = self.functions["FD_derivatives"].function, self._pvec(params, "FD_derivatives")
        try:
            try:
                out = function(q, u, tau, p)
            except ValueError:
                if tau is None or np.ndim(tau) != 1 or np.ndim(q) != 2:
                    raise
                out = function(q, u, np.ascontiguousarray(efforts(tau, self.nv, np.shape(q)[:-1])), p)
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

    def _build_derivatives(self) -> None:
        """ID_derivatives, and with M, b, g: FD_jacobian (with loads), FD_parts ([M | h]) and FD_derivatives,
        the C function that combines them."""
        if "ID_derivatives" in self.functions:
            return
        from .c_backend import extension_functions  # which imports this module

        eom, build = self.eom, jacobians(self.eom)
        keys = ["ID_derivatives"]
        if forward_dynamics(eom):
            keys += ["FD_jacobian"] * bool(eom.load_names) + ["FD_parts"]
            build["FD_parts"] = lambda: forward_parts(eom)
        written, exprs = [], []
        for i, key in enumerate(keys):
            self._built.setdefault(key, (build[key], False))  # for `reference`
            exprs.append((build[key](), False))
            source, shape, ops = self._c.source(f"e{i}", *exprs[-1])
            written.append((key, source, shape, ops, self._c.trig_indices))
        if forward_dynamics(eom):
            parts, jacobian = written[-1], written[keys.index(forward_key(eom))]
            trig = sorted(set(parts[4]) | set(jacobian[4]))
            source = forward_derivatives_source(
                f"e{len(keys)}", f"e{len(keys) - 1}", f"e{keys.index(forward_key(eom))}", self.nv, C_TRIG
            )
            written.append(("FD_derivatives", source, (self.nv, 3 * self.nv), parts[3] + jacobian[3], trig))
        def lanes() -> list[str | None]:  # on the first batch; FD_derivatives's loop stays scalar
            return vector_sources(self._lanes, exprs, len(written))

        functions = extension_functions(written, self.nq, self.nv, len(self.params), lanes)
        if forward_dynamics(eom):  # the parameters it reads are those of its parts
            functions["FD_derivatives"] = dataclasses.replace(
                functions["FD_derivatives"], source=parts[1] + jacobian[1] + source
            )
        self.functions.update(functions)
