"""Pivots proven nonzero, with stated assumptions (`eg.kane(..., assume_nonzero=[...])`).

A product vanishes only where one of its factors does. So an entry e = c ∏ fᵢ^kᵢ (`sp.factor_terms`;
small entries first brought over one denominator, `sp.together`) is nonzero wherever the stated
expressions are not zero, if its coefficient c ≠ 0 and every base fᵢ is proven nonzero by sympy
(`is_zero is False`: numbers, positive symbols, ...) or is, up to its sign, a base of a stated
expression (compared as it is and, when small, expanded); small bases are also expanded with
sin² = 1 − cos² (cos² + sin² is 1). No entry is simplified."""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp

SMALL = 60  # entries with more operations than this are compared as they are (neither together nor expand)


class Nonzero:
    """The stated expressions s_k ≠ 0 and what they prove nonzero."""

    def __init__(self, stated: Iterable[sp.Expr] = ()) -> None:
        self.stated = list(stated)
        self._bases = {g for s in self.stated for f in bases(s) for g in forms(f)}

    def proves(self, e: sp.Expr) -> bool:
        """e ≠ 0 wherever every stated expression is ≠ 0 (sympy's proof, or the product rule above)."""
        if e.is_zero is False:
            return True
        if not self._bases or e.is_zero:
            return False
        return all(f.is_zero is False or pythagoras(f).is_zero is False
                   or not forms(f).isdisjoint(self._bases) for f in bases(e))

    def condition(self) -> str:
        """'s_1 ≠ 0, s_2 ≠ 0' in LaTeX ('' when nothing is stated)."""
        return ", ".join(rf"{sp.latex(s)} \neq 0" for s in self.stated)


NOTHING = Nonzero()  # nothing stated: only sympy's proofs


def bases(e: sp.Expr) -> list[sp.Expr]:
    """The bases fᵢ of e = c ∏ fᵢ^kᵢ that are not numbers ([0] for e = 0)."""
    e = sp.sympify(e)
    small = sp.count_ops(e) <= SMALL
    coefficient, rest = sp.factor_terms(sp.together(e) if small else e).as_coeff_Mul()
    if coefficient == 0:
        return [sp.S.Zero]
    found = []
    for f in sp.Mul.make_args(rest):
        base = f.base if f.is_Pow else f
        if not (base.is_number and base.is_zero is False):
            found.append(base)
    return found


def pythagoras(f: sp.Expr) -> sp.Expr:
    """Small f expanded with sin²x = 1 − cos²x (so that cos²x + sin²x is 1); large f as it is."""
    if sp.count_ops(f) > SMALL:
        return f
    return sp.expand(sp.expand(f).subs({sp.sin(x) ** 2: 1 - sp.cos(x) ** 2
                                        for x in (s.args[0] for s in f.atoms(sp.sin))}))


def forms(f: sp.Expr) -> set[sp.Expr]:
    """f and −f, and their expansions when f is small."""
    out = {f, -f}
    if sp.count_ops(f) <= SMALL:
        out |= {sp.expand(f), -sp.expand(f)}
    return out
