"""solo12 standing on its four feet (floating base and contacts).

1. Joint torques that hold it still, the contact forces under gravity (they carry its weight).
2. The support-consistent dynamics: N_cᵀ (M u̇ + b + g) = N_cᵀ Sᵀ τ, and J_c N_c = 0.
3. The base in ZYX Euler angles beside the quaternion base near pitch 90°: the same physics, but the
   Euler mass matrix becomes singular there (the warning reports its condition number).

Run: python examples/quadruped_contact.py"""
import warnings

import numpy as np

import eomgen as eg


def main() -> None:
    system = eg.robots.load("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    for foot in feet:
        system.add_contact(foot, "point")
    f = eg.codegen(eg.derive(system, method="recursive"))
    q = np.r_[0.0, 0.0, 0.3, 0.0, 0.0, 0.0, 1.0, np.tile([0.0, 0.8, -1.6], 4)]
    u = np.zeros(system.nv)

    N = f.support_projector(q)
    S = np.array(system.S.tolist(), float)
    tau = np.linalg.lstsq(N.T @ S.T, N.T @ f.g(q), rcond=None)[0]  # holds it still: N_cᵀ (g − Sᵀ τ) = 0
    ud, F = f.constrained_dynamics(q, u, tau)
    mass = sum(float(b.mass) for b in system.bodies)
    print(f"solo12: nq = {system.nq}, nv = {system.nv}, mass {mass:.3f} kg, weight {mass * 9.81:.3f} N")
    print("holding torques [N m]:", np.round(tau, 4))
    for foot, force in zip(feet, F.reshape(4, 3)):
        print(f"  contact force {foot}: {np.round(force, 4)} N")
    print(f"sum of contact forces: {np.round(F.reshape(4, 3).sum(axis=0), 6)} N, max |u̇| = {np.abs(ud).max():.1e}")
    print(f"|J_c N_c| = {np.abs(f.contact_jacobian(q) @ N).max():.1e}, |N_c² − N_c| = {np.abs(N @ N - N).max():.1e}")
    residual = f.support_consistent_residual(q, u, ud, tau)
    print(f"support-consistent dynamics, |N_cᵀ (M u̇ + b + g − Sᵀ τ)| = {np.abs(residual).max():.1e}")

    euler = eg.robots.load("solo12", base="euler")
    fe = eg.codegen(eg.derive(euler))
    print("\nZYX Euler base near pitch 90° (quaternion M is regular everywhere):")
    for pitch in (0.0, 1.0, 1.5, 1.57, np.pi / 2 - 1e-5):
        qe = np.r_[0.0, 0.0, 0.3, 0.2, pitch, 0.1, np.tile([0.0, 0.8, -1.6], 4)]
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fe.forward_dynamics(qe, np.zeros(18))
        note = f"  warning: {caught[0].message}" if caught else ""
        print(f"  pitch {pitch:.6f}: cond(M_euler) = {np.linalg.cond(fe.M(qe)):.2e}{note}")


if __name__ == "__main__":
    main()
