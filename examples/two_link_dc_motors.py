"""The planar two-link arm of the paper "Bond Graph Modeling of a Robot Manipulator", each joint
driven by a DC motor through a gear: M, C q̇ and G in closed form, the reflected rotor inertia N² J_m on
M's diagonal, and a simulated voltage step with its power balance
U i = d/dt (T + U_g + ½ L i²) + R i² + f (N q̇)².

Run: python examples/two_link_dc_motors.py"""
import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

import eomgen as eg

m1, m2, l1, lc1, lc2, I1, I2, g = sp.symbols("m1 m2 l1 l_c1 l_c2 I1 I2 g", positive=True)
R, L, k, J_m, f, N = sp.symbols("R L k J_m f N", positive=True)


def two_link_arm(motors: bool = False) -> eg.System:
    """Angles from the horizontal, gravity −g along y; I1, I2 about the centres of mass."""
    system = eg.System(gravity=(0, -g, 0))
    a = system.add_body("link1", joint=eg.Revolute("q_1"), mass=m1, com=(lc1, 0, 0), inertia=sp.diag(0, 0, I1))
    b = system.add_body("link2", parent=a, joint=eg.Revolute("q_2"), mass=m2, com=(lc2, 0, 0),
                        inertia=sp.diag(0, 0, I2), placement=eg.Placement(translation=(l1, 0, 0)))
    if motors:
        for body in (a, b):
            system.add_motor(body, resistance=R, inductance=L, torque_constant=k, rotor_inertia=J_m,
                             friction=f, gear_ratio=N)
    return system


NUMBERS = {"m1": 1.0, "m2": 0.8, "l1": 0.5, "l_c1": 0.25, "l_c2": 0.2, "I1": 0.02, "I2": 0.012, "g": 9.81,
           "R": 2.0, "L": 0.005, "k": 0.05, "J_m": 2e-5, "f": 1e-5, "N": 50.0,
           "U_motor_q_1": 12.0, "U_motor_q_2": 6.0}


def simulate(seconds: float = 1.0):
    """Voltage step at t = 0 from rest (arm hanging down): q, u, currents and the work balance."""
    system = two_link_arm(motors=True)
    eom = eg.derive(system, method="lagrange")
    fn = eg.codegen(eom)
    motors = system.motors

    def rhs(t, x):
        state, i = x[:-1], x[4:6]
        d = fn.rhs(t, state, params=NUMBERS)
        qd = state[2:4]
        p = {k_: NUMBERS[k_] for k_ in ("R", "f", "N")}
        losses = sum(p["R"] * c**2 + p["f"] * (p["N"] * qd[m.body.index]) ** 2 for m, c in zip(motors, i))
        supplied = sum(NUMBERS[str(m.voltage)] * c for m, c in zip(motors, i))
        return np.concatenate([d, [supplied - losses]])

    x0 = np.array([-np.pi / 2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    sol = solve_ivp(rhs, (0, seconds), x0, method="LSODA", rtol=1e-11, atol=1e-12, dense_output=True)

    def energy(x):
        q, u, i = x[:2], x[2:4], x[4:6]
        p = {**NUMBERS, **{str(m.current): c for m, c in zip(motors, i)}}
        return fn.T(q, u, p) + fn.U(q, p) + 0.5 * NUMBERS["L"] * float(i @ i)

    return sol, energy


def main() -> None:
    rigid = eg.derive(two_link_arm(), method="lagrange")
    print("M ="), sp.pprint(sp.simplify(rigid.M))
    print("C q̇ = b ="), sp.pprint(sp.simplify(rigid.b))
    print("G ="), sp.pprint(sp.simplify(rigid.g))
    with_motors = eg.derive(two_link_arm(motors=True), method="lagrange")
    print("M with motors − M =", sp.simplify(with_motors.M - rigid.M).tolist())
    print("motor torques τ =", [sp.simplify(x) for x in with_motors.tau])

    sol, energy = simulate()
    balance = [energy(x) - x[-1] for x in sol.y.T]
    print(f"\nvoltage step 12 V / 6 V for 1 s: q = {np.round(sol.y[:2, -1], 4)}, currents {np.round(sol.y[4:6, -1], 4)} A")
    print(f"energy − supplied work + losses stays at {balance[0]:.6f} J within {np.ptp(balance):.1e} J "
          f"(supplied {sol.y[-1, -1]:.4f} J)")


if __name__ == "__main__":
    main()
