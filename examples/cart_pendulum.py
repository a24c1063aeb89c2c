"""The textbook cart-pendulum: a cart (mass m_c, coordinate x) carrying a pendulum
(point mass m_p at distance l, angle φ from the downward vertical), derived by the three methods
(Newton-Euler with a free cut, projected Newton-Euler, Lagrange II), the free cut's equation count
and rod force, then the generalized forces of a motor, a cart force and a spring.

Run: python examples/cart_pendulum.py"""
import sympy as sp

import eomgen as eg

m_c, m_p, l, g = sp.symbols("m_c m_p l g", positive=True)
T_a, F, k, P_x, P_y = sp.symbols("T_a F k P_x P_y")


def cart_pendulum() -> tuple[eg.System, object, object]:
    system = eg.System(gravity=(0, -g, 0))
    cart = system.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=m_c)
    pendulum = system.add_body("pendulum", parent=cart, joint=eg.Revolute("phi", axis=(0, 0, 1)),
                               mass=m_p, com=(0, -l, 0))
    system.add_frame("tip", body=pendulum, placement=eg.Placement(translation=(0, -l, 0)))
    return system, cart, pendulum


def main() -> None:
    system, cart, pendulum = cart_pendulum()
    print(f"q = {list(system.q)}, u = {list(system.u)}")
    for method in ("free_cut", "projected_newton_euler", "lagrange"):
        eom = eg.derive(system, method=method)
        print(f"\n{method}:")
        for name in ("M", "b", "g"):
            print(f"{name} =")
            sp.pprint(sp.simplify(getattr(eom, name)), use_unicode=True)

    cut = eg.derive(system, method="free_cut")
    print(f"\nFree cut (planar: 3 equations per body): {cut.cut_equations}")
    print("unknowns:", cut.cut_equations.unknowns)
    for equation in cut.cut_equations.equations:
        print("  0 =", equation)
    F_rod, _ = cut.reactions["phi"]
    towards_pivot = sp.Matrix([-sp.sin(system.q[1]), sp.cos(system.q[1]), 0])
    print("rod force (towards the pivot):", sp.simplify((towards_pivot.T * F_rod)[0]))

    system.add_actuator(pendulum, torque=(0, 0, T_a), reaction=cart, name="motor")
    system.add_force(cart, (F, 0, 0), name="cart_force")
    system.add_spring((None, (P_x, P_y, 0)), "tip", stiffness=k, name="spring")
    methods = ("free_cut", "projected_newton_euler", "lagrange")
    eoms = [eg.derive(system, method=m) for m in methods]
    for name in eoms[0].load_names:
        print(f"\nτ of {name}:")
        for method, eom in zip(methods, eoms):
            print(f"  {method:24s} {list(sp.simplify(eom.tau_of(name)))}")


if __name__ == "__main__":
    main()
