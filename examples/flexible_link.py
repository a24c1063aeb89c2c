"""The single flexible link of the finite-element paper "Dynamic modeling and path planning of flexible-link
manipulators": one Euler-Bernoulli element,
q = [θ, u₃, u₄] (joint angle, tip deflection and slope), m = 5 kg over L = 1 m, gravity 9.81, derived
by Lagrange II without linearization; then a free swing from the horizontal, plotted to PNG.

Run: python examples/flexible_link.py [--out PNG, default examples/output/flexible_link.png]"""
import argparse
from pathlib import Path

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

import eomgen as eg

EI = sp.Symbol("EI", positive=True)


def flexible_link(elements: int = 1, EI_value=EI) -> eg.System:
    system = eg.System(gravity=(0, -9.81, 0))
    system.add_body("link", joint=eg.FlexibleLink("theta", length=1, mass_per_length=5, EI=EI_value,
                                                  elements=elements))
    return system


def simulate(EI_value: float = 50.0, seconds: float = 3.0, elements: int = 1, backend: str = "numpy"):
    """Released at rest from the horizontal, undeformed; returns the solution and the energy T + U
    (backend: eg.codegen's, "c" for the compiled functions)."""
    system = flexible_link(elements, EI_value)
    f = eg.codegen(eg.derive(system, method="lagrange"), backend=backend)
    n = system.nv

    def rhs(t, x):
        return np.concatenate([x[n:], f.forward_dynamics(x[:n], x[n:])])

    sol = solve_ivp(rhs, (0, seconds), np.zeros(2 * n), method="DOP853", rtol=1e-11, atol=1e-12,
                    t_eval=np.linspace(0, seconds, 601))
    energy = np.array([f.T(x[:n], x[n:]) + f.U(x[:n]) for x in sol.y.T])
    return sol, energy


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=str(Path(__file__).parent / "output" / "flexible_link.png"))
    args = ap.parse_args()
    eom = eg.derive(flexible_link(), method="lagrange")
    print("q =", list(eom.q))
    print("M(q) ="), sp.pprint(sp.simplify(eom.M))
    print("b ="), sp.pprint(sp.simplify(eom.b))
    print("g ="), sp.pprint(sp.simplify(eom.g))
    print("elastic forces τ_e = −K d ="), sp.pprint(sp.simplify(eom.tau_of("elastic")))
    sol, energy = simulate()
    print(f"free swing, EI = 50 N m²: energy {energy[0]:.6f} J, drift {np.ptp(energy):.1e} J over 3 s")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    ax1.plot(sol.t, sol.y[0], label="joint angle θ [rad]")
    ax1.legend()
    ax2.plot(sol.t, 1e3 * sol.y[1], color="C1", label="tip deflection u₃ [mm]")
    ax2.set_xlabel("t [s]")
    ax2.legend()
    fig.suptitle("Flexible link, one element, m = 5 kg, L = 1 m, EI = 50 N m²")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=100)
    print(f"plot: {args.out}")


if __name__ == "__main__":
    main()
