"""The lecture's cart-pendulum (SEEDS.md §1): a cart (mass m_c, coordinate x) carrying a pendulum
(point mass m_p at distance l, angle φ from the downward vertical), derived by projected Newton-Euler
and Lagrange II, then the generalized forces of a motor, a cart force and a spring.

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
    for method in ("projected_newton_euler", "lagrange"):
        eom = eg.derive(system, method=method)
        print(f"\n{method}:")
        for name in ("M", "b", "g"):
            print(f"{name} =")
            sp.pprint(sp.simplify(getattr(eom, name)), use_unicode=True)

    system.add_actuator(pendulum, torque=(0, 0, T_a), reaction=cart, name="motor")
    system.add_force(cart, (F, 0, 0), name="cart_force")
    system.add_spring((None, (P_x, P_y, 0)), "tip", stiffness=k, name="spring")
    print("\nGeneralized forces τ of the loads (projected Newton-Euler | Lagrange II):")
    eoms = [eg.derive(system, method=m) for m in ("projected_newton_euler", "lagrange")]
    for name in eoms[0].load_names:
        ne, la = (sp.simplify(e.tau_of(name)) for e in eoms)
        print(f"  {name:10s} {list(ne)}   |   {list(la)}")


if __name__ == "__main__":
    main()
