"""Direct collocation by Hermite–Simpson (Betts 2010, §4.6; Kelly 2017, SIAM Review 59(4)), the piece the two
trajectory-optimisation examples share (cart_pole_swing_up.py, panda_point_to_point.py).

On N intervals of length h = T / N the states x = [q, u] and the efforts τ_a are unknowns at the knots t_k
and the midpoints t_k + h/2, and so are the accelerations u̇, held to the equations of motion there by
eomgen's CasADi inverse dynamics (the implicit form, one recursive Newton–Euler pass, cheaper than M⁻¹):

    ID(q, u, u̇) = M u̇ + b + g = τ(q, u) + Sᵀ τ_a ;

with ẋ = f = [u, u̇] (q̇ = u for revolute and prismatic joints) each interval holds

    x_m = (x_k + x_k+1) / 2 + h / 8 (f_k − f_k+1)          (the Hermite cubic's midpoint)
    x_k+1 − x_k = h / 6 (f_k + 4 f_m + f_k+1)              (Simpson's rule),

and the effort ∫ τ_aᵀ W τ_a dt is Simpson's h / 6 Σ (ℓ_k + 4 ℓ_m + ℓ_k+1). Between the points τ_a is the
quadratic through τ_k, τ_m, τ_k+1 (`effort`), what the re-simulation with the C backend replays."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import casadi as ca
import numpy as np

import eomgen as eg
from eomgen.numeric.casadi_functions import CasadiEoM
from eomgen.simulate import Simulation

SUCCESS = ("Solve_Succeeded", "Solved_To_Acceptable_Level")


@dataclass
class Trajectory:
    """The optimum at the 2N + 1 points t (knots and midpoints): states x (2N+1, nx), efforts tau
    (2N+1, n_a); IPOPT's `status` ("Solve_Succeeded" is its "Optimal Solution Found") and iterations."""

    t: np.ndarray
    x: np.ndarray
    tau: np.ndarray
    status: str
    iterations: int

    @property
    def success(self) -> bool:
        return self.status in SUCCESS

    def effort(self, t: float) -> np.ndarray:
        """τ_a(t): the quadratic through the interval's knots and midpoint (Lagrange, s = (t − t_k) / h)."""
        N = (len(self.t) - 1) // 2
        h = self.t[2] - self.t[0]
        k = int(np.clip((t - self.t[0]) // h, 0, N - 1))
        s = (t - self.t[2 * k]) / h
        a, m, b = self.tau[2 * k:2 * k + 3]
        return a * (2 * s - 1) * (s - 1) + m * 4 * s * (1 - s) + b * s * (2 * s - 1)


class Collocation:
    """An `Opti` problem over [0, T] on N Hermite–Simpson intervals of the equations of `f` (eomgen's CasADi
    functions, parameters bound), |τ_a| ≤ tau_max; `X` (nx, 2N+1), `A` (u̇) and `tau` (n_a, 2N+1) are its
    variables, to which the example adds its boundary conditions."""

    def __init__(self, f: CasadiEoM, T: float, N: int, tau_max, weights=None) -> None:
        nq, n_a = f.nq, f.S.shape[0]
        self.opti, self.T, self.N, self.nq = ca.Opti(), T, N, nq
        self.X = self.opti.variable(nq + f.nv, 2 * N + 1)
        self.A = self.opti.variable(f.nv, 2 * N + 1)
        self.tau = self.opti.variable(n_a, 2 * N + 1)
        q, u = self.X[:nq, :], self.X[nq:, :]
        points = 2 * N + 1
        self.opti.subject_to(f.casadi["ID"].map(points)(q, u, self.A)
                             == f.casadi["tau"].map(points)(q, u) + ca.DM(f.S).T @ self.tau)
        f, h, X = ca.vertcat(u, self.A), T / N, self.X
        a, m, b = (slice(i, 2 * N - 1 + i, 2) for i in (0, 1, 2))  # knots k, midpoints, knots k + 1
        self.opti.subject_to(X[:, m] == (X[:, a] + X[:, b]) / 2 + h / 8 * (f[:, a] - f[:, b]))
        self.opti.subject_to(X[:, b] - X[:, a] == h / 6 * (f[:, a] + 4 * f[:, m] + f[:, b]))
        limit = np.broadcast_to(np.asarray(tau_max, float), (n_a,))[:, None]
        self.opti.subject_to(self.opti.bounded(-limit, self.tau, limit))
        W = ca.DM(np.diag(np.ones(n_a) if weights is None else weights))
        running = ca.sum1(self.tau * (W @ self.tau))
        self.opti.minimize(h / 6 * (ca.sum2(running[:, a]) + 4 * ca.sum2(running[:, m])
                                    + ca.sum2(running[:, b])))

    def at_rest(self, column: int, q=None) -> None:
        """u(t) = 0 (and q(t) = q when given) at the point `column` (0: the start, -1: the end)."""
        self.opti.subject_to(self.X[self.nq:, column] == 0)
        if q is not None:
            self.opti.subject_to(self.X[:self.nq, column] == np.asarray(q, float))

    def guess(self, q0, q1) -> None:
        """The straight line from q0 to q1 at rest as IPOPT's starting point."""
        s = np.linspace(0.0, 1.0, 2 * self.N + 1)
        q = np.outer(q0, 1 - s) + np.outer(q1, s)
        self.opti.set_initial(self.X, np.vstack([q, np.zeros_like(q)]))

    def solve(self, max_iter: int = 500) -> Trajectory:
        """IPOPT (quiet); the trajectory whether or not it converged, with its status."""
        self.opti.solver("ipopt", {"print_time": False},
                         {"print_level": 0, "sb": "yes", "max_iter": max_iter})
        try:
            solution = self.opti.solve()
        except RuntimeError:  # not converged: the last iterate, its status says why
            solution = self.opti.debug
        stats = solution.stats()
        t = np.linspace(0.0, self.T, 2 * self.N + 1)
        return Trajectory(t, np.asarray(solution.value(self.X)).T.reshape(len(t), -1),
                          np.asarray(solution.value(self.tau)).T.reshape(len(t), -1),
                          stats["return_status"], stats["iter_count"])


def figure(trajectory: Trajectory, sim: Simulation, title: str, path: Path | None = None):
    """eg.plot of the re-simulation (lines) with the collocation points (dots) over q, u and τ_a; saved to
    `path` when given."""
    fig = eg.plot(sim)
    nq = sim.q.shape[1]
    columns = (trajectory.x[:, :nq], trajectory.x[:, nq:], trajectory.tau)
    for ax, values in zip(fig.axes, columns):
        for line, column in zip(ax.get_lines(), values.T):
            ax.plot(trajectory.t, column, ".", color=line.get_color())
    fig.suptitle(f"{title}: collocation points (dots), C re-simulation (lines); IPOPT: {trajectory.status}")
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path)
        print("wrote", path)
    return fig
