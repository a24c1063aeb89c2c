"""The parameters as generated code reads them: p[k] is the k-th parameter sorted by name (a model's free
symbols other than q, u and u̇: masses, lengths, g, ...), each checked against its assumptions."""
from __future__ import annotations

from collections.abc import Iterable

import sympy as sp

from ..errors import ModelError

SIGNS = ("positive", "negative", "nonnegative", "nonpositive", "nonzero")  # the strongest first


def sorted_parameters(symbols: Iterable[sp.Symbol]) -> list[sp.Symbol]:
    """The parameters sorted by name; two symbols of one name (other assumptions) refused."""
    found = sorted(symbols, key=str)
    names = [str(s) for s in found]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ModelError(f"parameters {twice} each name two different symbols (other assumptions): "
                         "parameters are given by name, so their names must differ")
    return found


def assumptions(symbol: sp.Symbol) -> tuple[str, ...]:
    """The assumptions of `symbol` a value is checked against: its strongest sign rule, and integer."""
    sign = next((a for a in SIGNS if getattr(symbol, f"is_{a}")), None)
    return tuple(a for a in (sign, "integer" if symbol.is_integer else None) if a)
