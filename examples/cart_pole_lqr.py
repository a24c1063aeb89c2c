"""Balancing a cart-pole with LQR: derive, linearize about the upright, design the gains, simulate the
nonlinear system under the controller, plot it and animate it.

The cart (mass m_c, coordinate x, pushed by the force F = τ_a) carries a pole (point mass m_p at distance l,
angle φ from the upward vertical, not actuated). T = ½ (m_c + m_p) ẋ² − m_p l cos φ ẋ φ̇ + ½ m_p l² φ̇² and
U = m_p g l cos φ; about the upright, M = [[m_c + m_p, −m_p l], [−m_p l, m_p l²]] and ∂²U/∂φ² = −m_p g l, so
x = [x, φ, ẋ, φ̇] moves by ẋ = A x + B F with (by hand)

    A = [[0, 0, 1, 0], [0, 0, 0, 1], [0, m_p g / m_c, 0, 0], [0, (m_c + m_p) g / (m_c l), 0, 0]],
    B = [0, 0, 1 / m_c, 1 / (m_c l)]ᵀ;

the LQR gain K = R⁻¹ Bᵀ P (P from the continuous algebraic Riccati equation) and F = −K (x − x_0) bring the
pole back from a tilt the linearization never saw.

Run: python examples/cart_pole_lqr.py [output folder]   (writes cart_pole.png and cart_pole.gif)"""
import sys
from pathlib import Path

import numpy as np
import scipy.linalg

import eomgen as eg

VALUES = {"m_c": 1.0, "m_p": 0.3, "l": 0.6, "g": 9.81}


def cart_pole(m_c: float = VALUES["m_c"], m_p: float = VALUES["m_p"], l: float = VALUES["l"],
              g: float = VALUES["g"]) -> eg.System:
    """The cart on a rail along x, the pole about z, upright at φ = 0 (its tip at (x − l sin φ, l cos φ))."""
    system = eg.System(gravity=(0, -g, 0))
    cart = system.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=m_c)
    pole = system.add_body("pole", parent=cart, joint=eg.Revolute("phi", axis=(0, 0, 1), actuated=False),
                           mass=m_p, com=(0, l, 0))
    system.add_frame("tip", body=pole, placement=eg.Placement(translation=(0, l, 0)))
    return system


def by_hand(m_c: float = VALUES["m_c"], m_p: float = VALUES["m_p"], l: float = VALUES["l"],
            g: float = VALUES["g"]) -> tuple[np.ndarray, np.ndarray]:
    """A, B of the module's docstring."""
    A = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, m_p * g / m_c, 0, 0],
                  [0, (m_c + m_p) * g / (m_c * l), 0, 0]])
    return A, np.array([[0], [0], [1 / m_c], [1 / (m_c * l)]])


def lqr(A: np.ndarray, B: np.ndarray, Q: np.ndarray, R: np.ndarray) -> np.ndarray:
    """K = R⁻¹ Bᵀ P with Aᵀ P + P A − P B R⁻¹ Bᵀ P + Q = 0."""
    P = scipy.linalg.solve_continuous_are(A, B, Q, R)
    return np.linalg.solve(R, B.T @ P)


def balance(tilt: float = 0.3, duration: float = 6.0):
    """(functions, linearization, K, simulation) of the pole released at `tilt` rad, the cart at rest."""
    system = cart_pole()
    f = eg.codegen(eg.derive(system, method="recursive"))
    L = eg.linearize(f.eom, (np.zeros(2), np.zeros(2)))
    K = lqr(L.A, L.B, Q=np.diag([10.0, 10.0, 1.0, 1.0]), R=np.eye(1))

    def controller(t, q, u):
        return -K @ np.concatenate([q, u])

    sim = eg.simulate(f, (np.array([0.0, tilt]), np.zeros(2)), (0.0, duration), controller=controller,
                      t_eval=np.linspace(0.0, duration, 121))
    return f, L, K, sim


def main(folder: Path) -> None:
    f, L, K, sim = balance()
    print("A =\n", L.A, "\nB =\n", L.B, "\nstates:", L.states, "inputs:", L.inputs)
    A, B = by_hand()
    print(f"|A − A_hand| = {np.abs(L.A - A).max():.1e}, |B − B_hand| = {np.abs(L.B - B).max():.1e}")
    print("K =", K, " closed-loop eigenvalues:", np.linalg.eigvals(L.A - L.B @ K))
    print(f"after {sim.t[-1]} s: x = {sim.q[-1, 0]:.2e} m, φ = {sim.q[-1, 1]:.2e} rad; "
          f"energy balance |E − E0 − W| ≤ {np.abs(sim.balance).max():.1e} J")
    folder.mkdir(parents=True, exist_ok=True)
    eg.plot(sim).savefig(folder / "cart_pole.png")
    eg.animate(sim, f, path=folder / "cart_pole.gif", fps=20)
    print("wrote", folder / "cart_pole.png", "and", folder / "cart_pole.gif")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("."))
