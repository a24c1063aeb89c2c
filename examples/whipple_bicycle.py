"""The Whipple bicycle built from its parts: a rear frame on a free-flying base, the rear wheel, the front
frame on the tilted steer axis, the front wheel, and two rolling contacts; the benchmark parameters of
Meijaard, Papadopoulos, Ruina and Schwab (2007). Linearized about upright running at speed v by finite
differences of the generated right-hand side: the eigenvalues at v = 0 … 10 m/s and the weave and
capsize speeds.

Run: python examples/whipple_bicycle.py"""
from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.optimize import brentq

import eomgen as eg

# Meijaard et al. 2007, Table 1: axes x forward, y right, z down, origin at the rear contact;
# the inertia matrices of the rear body B and the front handlebar assembly H about their mass centres.
BENCHMARK = {"w": 1.02, "c": 0.08, "lam": np.pi / 10, "g": 9.81,
             "r_R": 0.3, "m_R": 2.0, "I_Rxx": 0.0603, "I_Ryy": 0.12,
             "x_B": 0.3, "z_B": -0.9, "m_B": 85.0, "I_Bxx": 9.2, "I_Byy": 11.0, "I_Bzz": 2.8, "I_Bxz": 2.4,
             "x_H": 0.9, "z_H": -0.7, "m_H": 4.0, "I_Hxx": 0.05892, "I_Hyy": 0.06, "I_Hzz": 0.00708,
             "I_Hxz": -0.00756,
             "r_F": 0.35, "m_F": 3.0, "I_Fxx": 0.1405, "I_Fyy": 0.28}
P = {name: sp.Symbol(name, real=True) for name in BENCHMARK}


def derivative(f, x0, h: float = 0.05, levels: int = 5) -> np.ndarray:
    """J = ∂f/∂x at x0: central differences D(h) = (f(x0 + h e_k) − f(x0 − h e_k)) / 2h at h, h/2, …,
    Richardson-extrapolated (D(h) = J + a h² + b h⁴ + …)."""
    x0 = np.asarray(x0, dtype=float)
    columns = []
    for k in range(len(x0)):
        e = np.eye(len(x0))[k]
        table: list[list[np.ndarray]] = []
        for i in range(levels):
            step = h / 2**i
            row = [(np.asarray(f(x0 + step * e)) - np.asarray(f(x0 - step * e))) / (2 * step)]
            for j in range(1, i + 1):
                row.append(row[j - 1] + (row[j - 1] - table[i - 1][j - 1]) / (4**j - 1))
            table.append(row)
        columns.append(table[-1][-1])
    return np.column_stack(columns)


def state_matrix(accelerations, v: float) -> np.ndarray:
    """A of ẋ = A x, x = (roll φ, steer δ, φ̇, δ̇), about upright running at speed v: accelerations(x, v)
    gives (φ̈, δ̈) at the state x."""
    return np.vstack([np.eye(4)[2:], derivative(lambda x: accelerations(x, v), np.zeros(4))])


def stable_speeds(eigenvalues) -> tuple[float, float]:
    """The weave and capsize speeds: where the largest real part of eigenvalues(v) crosses zero, downwards
    (weave, between 4 and 5 m/s) and upwards (capsize, between 5 and 7 m/s)."""
    def abscissa(v):
        return eigenvalues(v).real.max()
    return brentq(abscissa, 4.0, 5.0, xtol=1e-14), brentq(abscissa, 5.0, 7.0, xtol=1e-14)
