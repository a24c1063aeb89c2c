"""Euler-Bernoulli beam elements with Hermite cubic shape functions (`model.beam`), for flexible links
in Lagrange II (after the paper "Dynamic modeling and path planning of flexible-link manipulators").
A point x of the link is at r(x) = p + R ((x + u_x) e_x + y(x) e_y), y = Σ N_k(ξ) d_k on each element
of length h (ξ = x − x_e), d its nodal deflections and slopes, u_x = −½ ∫₀ˣ y'² ds the foreshortening
(with stiffening; else 0). With A = ṗ, B = d(R e_x)/dt, C = d(R e_y)/dt, D = R e_y, E = R e_x,

    ṙ = A + B x + C y + D ẏ + (B u_x + E u̇_x),
    T = ½ ∫ m |A + B x + C y + D ẏ|² dx + ∫ m [(A·B + x B·B) u_x + A·E u̇_x] dx,
    U_g = −∫ m g⃗ · (p + R (x + u_x) e_x + R y e_y) dx,   U_e = ½ Σ_e d_eᵀ K_e d_e,
    K_e = (E I / h³) [[12, 6h, −12, 6h], [6h, 4h², −6h, 2h²], [−12, −6h, 12, −6h], [6h, 2h², −6h, 4h²]],

the foreshortening terms to second order in the deflection, the consistent order of the linearized
equations (Kane, Ryan and Banerjee 1987; B·E = 0, and |u̇_x|², u_x y are of higher order). Reversing
the order of integration, ∫₀ᴸ f(x) u_x(x) dx = −½ ∫₀ᴸ F(s) y'(s)² ds with F(s) = ∫ₛᴸ f:

    ∫ m (A·B + x B·B) u_x = −½ m ∫ y'² [A·B (L − s) + B·B (L² − s²)/2] ds,
    ∫ m A·E u̇_x = −m A·E ∫ y' ẏ' (L − s) ds,    −∫ m g⃗·E u_x = ½ m g⃗·E ∫ y'² (L − s) ds:

for a link spinning at Ω (B·B = Ω²), the centrifugal axial force P(s) = m Ω² (L² − s²)/2 acting on
the slope, ½ ∫ P y'² ds. Each integral is exact (the integrands are polynomials)."""
from __future__ import annotations

import sympy as sp

from ..kinematics import Kinematics
from ..linalg import dot
from ..model import FlexibleLink
from ..model.beam import integrals, quadratic


def energies(kin: Kinematics, body) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(T, U_gravity, U_elastic) of the flexible link moved by `body`'s FlexibleLink joint."""
    joint, sub = body.joint, kin.sub
    n, L = joint.elements, joint.length
    h = L / n
    m = joint.mass_per_length
    d = joint.nodes()
    d_dot = joint.nodes(joint.speeds[-len(joint.nodal):])  # the nodal rates (θ̇ first unless prescribed)
    R, p = kin.R[body], kin.p[body]
    e_x, e_y = R[:, 0], R[:, 1]
    A = kin.time_derivative(p)
    B, C = kin.time_derivative(sp.Matrix(e_x)), kin.time_derivative(sp.Matrix(e_y))
    AA, AB, AC, AD = dot(A, A), dot(A, B), dot(A, C), dot(A, e_y)
    BB, BC, BD, CC, CD, DD = dot(B, B), dot(B, C), dot(B, e_y), dot(C, C), dot(C, e_y), dot(e_y, e_y)
    AE = dot(A, e_x)
    gp, gx, gy = (dot(kin.system.gravity, v) for v in (p, e_x, e_y))
    T, U_g, U_e = [], [], []
    for e in range(n):
        I = integrals(e * h, h)
        de, dde = d[2 * e:2 * e + 4], d_dot[2 * e:2 * e + 4]
        y_int = sum(I["N"][k] * de[k] for k in range(4))
        yd_int = sum(I["N"][k] * dde[k] for k in range(4))
        xy = sum(I["xN"][k] * de[k] for k in range(4))
        xyd = sum(I["xN"][k] * dde[k] for k in range(4))
        yy, yyd, ydyd = quadratic(I["NN"], de, de), quadratic(I["NN"], de, dde), quadratic(I["NN"], dde, dde)
        T_e = m / 2 * (AA * I["1"] + 2 * AB * I["x"] + 2 * AC * y_int + 2 * AD * yd_int + BB * I["xx"]
                       + 2 * BC * xy + 2 * BD * xyd + CC * yy + 2 * CD * yyd + DD * ydyd)
        U_ge = -m * (gp * I["1"] + gx * I["x"] + gy * y_int)
        if joint.stiffening:  # ∫ y'² (L − s), ∫ y'² (L² − s²), ∫ y' ẏ' (L − s) over the element
            slope2_L = L * quadratic(I["G"], de, de) - quadratic(I["xG"], de, de)
            slope2_LL = L**2 * quadratic(I["G"], de, de) - quadratic(I["xxG"], de, de)
            slope_rate_L = L * quadratic(I["G"], de, dde) - quadratic(I["xG"], de, dde)
            T_e += -m / 2 * (AB * slope2_L + BB * slope2_LL / 2) - m * AE * slope_rate_L
            U_ge += m * gx * slope2_L / 2
        T.append(sub.add(T_e))
        U_g.append(sub.add(U_ge))
        U_e.append(sub.add(joint.EI * quadratic(I["K"], de, de) / 2))
    return sp.Add(*T), sp.Add(*U_g), sp.Add(*U_e)


def flexible_mass(system) -> sp.Expr:
    """m L summed over the flexible links."""
    return sum((b.joint.mass_per_length * b.joint.length for b in system.bodies
                if isinstance(b.joint, FlexibleLink)), sp.Integer(0))
