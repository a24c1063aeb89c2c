"""The forward dynamics' derivatives in C (formulas in `numeric.forward`), one function

    f(q, u, tau, p, out),   out = [∂u̇/∂q | ∂u̇/∂u | ∂u̇/∂τ = M⁻¹]   (nv × 3 nv, row-major),

that evaluates [M | τ_loads − b − g] (`functions.expressions.forward_parts`), factors M = Lᵀ L (L lower
triangular, from the last speed up: Featherstone's LTL factorisation, no fill-in when every speed's
ancestors come before it; the zeros of a tree are skipped), solves for u̇ = M⁻¹ (τ + τ_loads − b − g),
evaluates D = ∂(τ_ID − τ_loads)/∂(q, u) at u̇ and solves M X = [−D | 1]. Where M is not positive definite
every output is NaN. The same text serves the extension (with the arrays sinq, cosq) and `write_c`."""

from __future__ import annotations

from .syntax import Syntax

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
