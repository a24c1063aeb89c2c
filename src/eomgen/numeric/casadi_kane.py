"""Kane's equations in CasADi: the pieces of `kane_catalogue` as `casadi.Function`s on SX
(`f.casadi[key]`, `casadi_functions.CasadiPrinted`); with numbers they return arrays, on which the NumPy
algorithms of `numeric.kane` compute mass_matrix, forcing, the speeds, rhs and energy. Besides the
pieces, `f.casadi["rhs"]` (x, tau_a[, p]) → ẋ: the state equations of `NumericKane.rhs` as one function
on SX, every linear system solved by CasADi's `solve` (no inverse written out):

    w_dep = −C_dep⁻¹ (C_ind w_ind + c0),  [P | u] = −Y⁻¹ [K T | K w + k0],  ẇ_dep,0 = −C_dep⁻¹ ċ,
    u̇₀ = −Y⁻¹ (K ẇ₀ + ẏ),  ẋ = [q̇(q, u); (Pᵀ M P)⁻¹ Pᵀ (h + Sᵀ τ_a − M u̇₀)]."""
from __future__ import annotations

from .casadi_functions import CasadiFunctions, CasadiPrinted
from .kane import NumericKane


class CasadiKane(CasadiPrinted, NumericKane):
    """`NumericKane` whose pieces are CasADi functions of (q, u, ud = w, p); `casadi["rhs"]` besides."""

    @property
    def casadi(self):
        """The CasADi function of each piece by key, and "rhs" (x, tau_a[, p]) → ẋ."""
        return KaneFunctions(self)


class KaneFunctions(CasadiFunctions):
    """f.casadi[key] of Kane's equations: the pieces', and "rhs"."""

    def __getitem__(self, key: str):
        return self._rhs() if key == "rhs" else super().__getitem__(key)

    def _rhs(self):
        import casadi as ca

        f = self.f
        f._without_motors()
        x, tau_a = ca.SX.sym("x", f.nx), ca.SX.sym("tau_a", f.S.shape[0])
        inputs, labels = [x, tau_a], ["x", "tau_a"]
        p = self._p(inputs, labels)
        q, w_ind, n, nv = x[:f.nq], x[f.nq:], f.n, f.nv

        def piece(key: str, u=None, w=None):
            zero = ca.SX.zeros(f._nu)
            return f.generated(key).function(q, zero if u is None else u, zero if w is None else w, p)

        def merged(independent, dependent):
            """The rows of the independent and dependent speeds, in the speeds' order."""
            rows = independent if dependent is None else ca.vertcat(independent, dependent)
            return rows[[int(i) for i in f._order], :]

        T_dep = w_dep = C_dep = None
        if f._dep:
            Cc = piece("C")
            C_dep, C_ind = Cc[:, f._dep], Cc[:, f._ind]
            X = ca.solve(C_dep, ca.horzcat(C_ind, C_ind @ w_ind + Cc[:, n:]))
            T_dep, w_dep = -X[:, :nv], -X[:, nv]
        w, T = merged(w_ind, w_dep), merged(ca.SX.eye(nv), T_dep)
        Yk = piece("Y")
        Y, K = Yk[:, :n], Yk[:, n:2 * n]
        X = ca.solve(Y, ca.horzcat(K @ T, K @ w + Yk[:, 2 * n:]))
        P, u = -X[:, :nv], -X[:, nv]
        rates = piece("rates", u, None if f.kane.speeds_are_qdot else w)
        wd0 = merged(ca.SX.zeros(nv), -ca.solve(C_dep, rates[n:]) if f._dep else None)
        ud0 = -ca.solve(Y, K @ wd0 + rates[:n])
        M = piece("M")
        h = piece("h", u)[:, 0] + ca.DM(f.S).T @ tau_a
        qdot = piece("qdot", u) if "qdot" in f.catalogue.functions else u
        wdot = ca.solve(P.T @ M @ P, P.T @ (h - M @ ud0))
        return ca.Function("rhs", inputs, [ca.vertcat(qdot, wdot)], labels, ["xdot"])
