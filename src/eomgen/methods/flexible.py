"""Euler-Bernoulli beam elements with Hermite cubic shape functions (`model.beam`), for flexible links
in Lagrange II (after the paper "Dynamic modeling and path planning of flexible-link manipulators").
A point x of the link is at

    r(x) = p + R (f_x(x) e_x + f_y(x) e_y),   f_x = x + u_x,   f_y = y,

y = Σ N_k(ξ) d_k on each element of length h (ξ = x − x_e, d its nodal deflections and slopes) and
u_x = −½ ∫₀ˣ y'² ds the foreshortening of the bent beam (with stiffening; else 0). On an element both
are polynomials in ξ (y of degree 3, u_x of degree 5, its constant the foreshortening of the elements
before, `FlexibleLink.shortening`), their coefficients named intermediates, and with A = ṗ,
B = d(R e_x)/dt, E = R e_x,
C = d(R e_y)/dt, D = R e_y,

    ṙ = A + B f_x + E ḟ_x + C f_y + D ḟ_y,    T = ½ ∫ m |ṙ|² dx,    U_g = −∫ m g⃗ · r dx,
    U_e = ½ Σ_e d_eᵀ K_e d_e,  K_e = (E I / h³) [[12, 6h, −12, 6h], [6h, 4h², −6h, 2h²], [−12, −6h, 12, −6h],
                                                 [6h, 2h², −6h, 4h²]],

every integral exact (∫₀ʰ ξ^(i+j) dξ of the coefficients' products), nothing truncated: T is the kinetic
energy of a motion of the centre line, so M stays positive definite at any deflection. Linearized, the
foreshortening gives the geometric stiffness of the axial load, ½ ∫ P(s) y'² ds (for a link spinning at
Ω, P = m Ω² (L² − s²)/2): the centrifugal and gravitational stiffening (Kane, Ryan and Banerjee 1987)."""
from __future__ import annotations

import sympy as sp

from ..kinematics import Kinematics
from ..linalg import dot
from ..model import FlexibleLink
from ..model.beam import coefficients, integrals, quadratic


def _integral(a: list, b: list, h) -> sp.Expr:
    """∫₀ʰ a(ξ) b(ξ) dξ for polynomials given by their coefficients."""
    return sp.Add(*[x * y * h ** (i + j + 1) / (i + j + 1) for i, x in enumerate(a) for j, y in enumerate(b)
                    if x != 0 and y != 0])


def _fields(kin: Kinematics, joint, e: int, c: list, d: list, d_dot: list, start) -> tuple[list, ...]:
    """(f_x, ḟ_x, f_y, ḟ_y) on element e as coefficients in ξ (c: the shape functions' coefficients; d,
    ḋ: the nodal values and rates; start: u_x where the element starts)."""
    sub, h = kin.sub, joint.length / joint.elements
    de, dde = d[2 * e:2 * e + 4], d_dot[2 * e:2 * e + 4]
    y = [sub.add(sp.Add(*[c[k][p] * de[k] for k in range(4)])) for p in range(4)]
    y_dot = [sp.Add(*[c[k][p] * dde[k] for k in range(4)]) for p in range(4)]
    f_x = [e * h, sp.Integer(1)]
    if not joint.stiffening:
        return f_x, [], y, y_dot
    slope = [(p + 1) * y[p + 1] for p in range(3)]
    square = [sp.Add(*[slope[i] * slope[p - i] for i in range(max(0, p - 2), min(p, 2) + 1)])
              for p in range(5)]  # y'² (degree 4)
    u_x = [start] + [sub.add(-square[p] / (2 * (p + 1))) for p in range(5)]
    u_x_dot = list(kin.time_derivative(sp.Matrix(u_x)))
    return [f_x[0] + u_x[0], f_x[1] + u_x[1], *u_x[2:]], u_x_dot, y, y_dot


def energies(kin: Kinematics, body) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(T, U_gravity, U_elastic) of the flexible link moved by `body`'s FlexibleLink joint."""
    joint, sub = body.joint, kin.sub
    h, m = joint.length / joint.elements, joint.mass_per_length
    R, p = kin.R[body], kin.p[body]
    E, D = R[:, 0], R[:, 1]
    A, B, C = kin.time_derivative(p), kin.time_derivative(sp.Matrix(E)), kin.time_derivative(sp.Matrix(D))
    vectors = {"A": A, "B": B, "E": E, "C": C, "D": D}
    known = {("B", "E"): 0, ("E", "E"): 1, ("E", "D"): 0, ("C", "D"): 0, ("D", "D"): 1}  # R orthonormal
    names = list(vectors)
    dots = {(a, b): known[a, b] if (a, b) in known else sub.add(dot(vectors[a], vectors[b]))
            for i, a in enumerate(names) for b in names[i:]}
    gp, gx, gy = (dot(kin.system.gravity, v) for v in (p, E, D))
    c, K = coefficients(h), integrals(h)["K"]
    d, d_dot = joint.nodes(), joint.nodes(joint.speeds[-len(joint.nodal):])
    T, U_g, U_e, start = [], [], [], sp.Integer(0)
    for e in range(joint.elements):
        f_x, f_x_dot, f_y, f_y_dot = _fields(kin, joint, e, c, d, d_dot, start)
        start = sub.add(start + joint.shortening(e))
        fields = {"A": [sp.Integer(1)], "B": f_x, "E": f_x_dot, "C": f_y, "D": f_y_dot}
        T.append(sub.add(m / 2 * sp.Add(*[(1 if a == b else 2) * w * _integral(fields[a], fields[b], h)
                                          for (a, b), w in dots.items() if w != 0])))
        U_g.append(sub.add(-m * (gp * h + gx * _integral([1], f_x, h) + gy * _integral([1], f_y, h))))
        de = d[2 * e:2 * e + 4]
        U_e.append(sub.add(joint.EI * quadratic(K, de, de) / 2))
    return sp.Add(*T), sp.Add(*U_g), sp.Add(*U_e)


def flexible_mass(system) -> sp.Expr:
    """m L summed over the flexible links."""
    return sum((b.joint.mass_per_length * b.joint.length for b in system.bodies
                if isinstance(b.joint, FlexibleLink)), sp.Integer(0))
