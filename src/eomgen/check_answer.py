"""`check_answer(system, M=..., b=..., g=..., tau=...)`: a student's M, b, g, τ against the derived ones,
entry by entry: equal, or where it differs and the likely cause (see `answer_causes`).

An entry is equal when |s − t| ≤ TOLERANCE · (1 + |t|) at each of STATES random states (seeded; q, u and
the parameters rounded to two decimals, so a printed state is exact); where that holds and the entry is
small, the difference is also brought to its sin/cos normal form, and 0 there makes it equal exactly."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from .answer_causes import likely_cause
from .answer_input import Reader
from .errors import ModelError
from .escaping import markdown_text
from .methods import derive
from .state import random_states
from .textbook import is_zero

TOLERANCE = 1e-9
STATES = 12
EXACT_OPS = 400  # entries up to this size are also compared exactly


@dataclass
class Entry:
    """One entry: `name` ("M[0,1]"), `equal`, `exactly` (by the normal form), and where it differs the
    `state` (symbol name → value), the `student`'s and the `expected` value there and the `cause`."""

    name: str
    equal: bool
    exactly: bool = False
    state: dict = field(default_factory=dict)
    student: float | None = None
    expected: float | None = None
    cause: str | None = None

    def verdict(self) -> str:
        """"equal (exactly)", or "differs at q=...: s instead of t; likely cause: ..."."""
        if self.equal:
            return "equal" + " (exactly)" * self.exactly
        at = ", ".join(f"{k}={v:g}" for k, v in self.state.items())
        return (f"differs at {at}: {self.student:.6g} instead of {self.expected:.6g}; "
                f"likely cause: {self.cause or 'none of the usual ones'}")

    def __str__(self) -> str:
        return f"{self.name}: {self.verdict()}"


@dataclass
class Check:
    """The result: `ok` when every entry is equal; `entries`, one `Entry` each."""

    entries: list

    @property
    def ok(self) -> bool:
        return all(e.equal for e in self.entries)

    def __str__(self) -> str:
        equal = sum(e.equal for e in self.entries)
        return "\n".join([f"{equal} of {len(self.entries)} entries equal ({HOW})", *map(str, self.entries)])

    def markdown(self) -> str:
        rows = [f"| {markdown_text(e.name)} | {markdown_text(e.verdict())} |" for e in self.entries]
        return "\n".join([f"**{'correct' if self.ok else 'not correct'}** ({markdown_text(HOW)})", "",
                          "| entry | verdict |", "|---|---|", *rows])

    def _repr_markdown_(self) -> str:
        return self.markdown()


HOW = (f"numerically at {STATES} random states, |student - derived| <= {TOLERANCE:g} (1 + |derived|); "
       "exactly where marked")


def check_answer(system, M=None, b=None, g=None, tau=None) -> Check:
    """Check a student's M(q), b(q, u), g(q) and τ (the loads' generalized forces; Sᵀ τ_a in the joint
    torques tau_<joint> for a system without loads) against those eomgen derives for `system`."""
    given = {k: v for k, v in (("M", M), ("b", b), ("g", g), ("tau", tau)) if v is not None}
    if not given:
        raise ModelError("check_answer: give at least one of M=, b=, g=, tau=")
    eom = derive(system)
    truth = {"M": eom.M, "b": eom.b, "g": eom.g,
             "tau": eom.tau if eom.load_names else eom.S.T * eom.tau_actuated}
    reader = Reader(system, extra=list(eom.tau_actuated))
    answers = {k: reader.matrix(v, k, truth[k].shape) for k, v in given.items()}
    states = _States(system, list(reader.known.values()))
    entries = []
    for key, answer in answers.items():
        for (i, j), s in np.ndenumerate(np.array(answer, dtype=object)):
            name = f"{key}[{i},{j}]" if truth[key].shape[1] > 1 else f"{key}[{i}]"
            entries.append(states.compare(name, s, truth[key][i, j], system))
    return Check(entries)


class _States:
    """STATES seeded random states of q, u and the parameters, rounded to two decimals."""

    def __init__(self, system, symbols: list) -> None:
        rng = np.random.default_rng(0)
        q, u, _ = random_states(system, STATES, rng)
        if not any(j.group in ("SO3", "SE3") for j in system.joints):  # keep unit quaternions unit
            q = q.round(2)
        values = {**dict(zip(system.q, q.T)), **dict(zip(system.u, u.round(2).T))}
        values.update({s: rng.uniform(0.5, 2.0, STATES).round(2) for s in symbols if s not in values})
        self.symbols, self.columns = list(values), list(values.values())

    def values(self, expr: sp.Expr) -> np.ndarray:
        with np.errstate(all="ignore"):
            out = sp.lambdify(self.symbols, expr, "numpy")(*self.columns)
        return np.broadcast_to(np.asarray(out, dtype=complex), (STATES,))

    @staticmethod
    def same(x: np.ndarray, y: np.ndarray) -> bool:
        return bool(np.all(np.abs(x - y) <= TOLERANCE * (1 + np.abs(y))))

    def compare(self, name: str, student: sp.Expr, truth: sp.Expr, system) -> Entry:
        s, t = self.values(student), self.values(truth)
        if self.same(s, t):
            small = sp.count_ops(student) + sp.count_ops(truth) <= EXACT_OPS
            return Entry(name, True, exactly=small and is_zero(student - truth))
        gap = np.abs(s - t)
        k = int(np.argmax(np.where(np.isfinite(gap), gap, np.inf)))
        used = (student.free_symbols | truth.free_symbols)
        state = {str(sym): float(col[k].real) for sym, col in zip(self.symbols, self.columns) if sym in used}
        cause = likely_cause(student, truth, self.values, self.same, system)
        return Entry(name, False, state=state, student=float(s[k].real), expected=float(t[k].real),
                     cause=cause)

