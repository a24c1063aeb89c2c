"""Euler-Bernoulli beam elements with Hermite cubic shape functions, for flexible links in Lagrange II
(after the paper "Dynamic modeling and path planning of flexible-link manipulators"). A point x of the
link is at r(x) = p + R (x e_x + y(x) e_y), y = Σ N_k(ξ) d_k on each element of length h
(ξ = x − x_e), d its nodal deflections and slopes. Then

    T = ½ ∫ m |ṙ|² dx,   U_g = −∫ m g⃗ · r dx,   U_e = ½ Σ_e d_eᵀ K_e d_e,
    K_e = (E I / h³) [[12, 6h, −12, 6h], [6h, 4h², −6h, 2h²], [−12, −6h, 12, −6h], [6h, 2h², −6h, 4h²]],

with ṙ = ṗ + Ṙ e_x x + Ṙ e_y y + R e_y ẏ, integrated exactly (the integrands are polynomials in x)."""
from __future__ import annotations

import sympy as sp

from ..kinematics import Kinematics
from ..linalg import dot
from ..model import FlexibleLink
from ..symbols import Generated

_xi, _h, _x0 = (Generated(x, ("element", x), positive=True) for x in ("xi", "h", "x0"))


def shape_functions(h=_h, xi=_xi) -> list[sp.Expr]:
    """Hermite cubics: deflection and slope at ξ = 0, then at ξ = h."""
    s = xi / h
    return [1 - 3 * s**2 + 2 * s**3, h * (s - 2 * s**2 + s**3), 3 * s**2 - 2 * s**3, h * (-s**2 + s**3)]


def element_stiffness(EI, h) -> sp.Matrix:
    """∫ E I N_k'' N_l'' dξ, the classical beam element stiffness."""
    N = shape_functions()
    K = sp.Matrix(4, 4, lambda k, l: sp.integrate(N[k].diff(_xi, 2) * N[l].diff(_xi, 2), (_xi, 0, _h)))
    return (EI * K).xreplace({_h: h})


def _integrals(x0, h) -> dict:
    """∫ over one element of 1, x, x², N_k, x N_k, N_k N_l (x = x0 + ξ)."""
    N, x = shape_functions(), _x0 + _xi

    def integral(e):
        return sp.expand(sp.integrate(sp.expand(e), (_xi, 0, _h))).xreplace({_h: h, _x0: x0})
    return {"1": integral(1), "x": integral(x), "xx": integral(x * x), "N": [integral(n) for n in N],
            "xN": [integral(x * n) for n in N], "NN": [[integral(a * b) for b in N] for a in N]}


def energies(kin: Kinematics, body) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(T, U_gravity, U_elastic) of the flexible link moved by `body`'s FlexibleLink joint."""
    joint, sub = body.joint, kin.sub
    n, L = joint.elements, joint.length
    h = L / n
    m = joint.mass_per_length
    d = [sp.Integer(0), sp.Integer(0)] + list(joint.nodal)  # node 1 clamped
    speeds = dict(zip(joint.coordinates, joint.speeds))
    d_dot = [speeds.get(x, sp.Integer(0)) for x in d]
    R, p = kin.R[body], kin.p[body]
    e_x, e_y = R[:, 0], R[:, 1]
    A = kin.time_derivative(p)
    B, C = kin.time_derivative(sp.Matrix(e_x)), kin.time_derivative(sp.Matrix(e_y))
    AA, AB, AC, AD = dot(A, A), dot(A, B), dot(A, C), dot(A, e_y)
    BB, BC, BD, CC, CD, DD = dot(B, B), dot(B, C), dot(B, e_y), dot(C, C), dot(C, e_y), dot(e_y, e_y)
    gp, gx, gy = (dot(kin.system.gravity, v) for v in (p, e_x, e_y))
    K = element_stiffness(joint.EI, h)
    T, U_g, U_e = [], [], []
    for e in range(n):
        I = _integrals(e * h, h)
        de, dde = d[2 * e:2 * e + 4], d_dot[2 * e:2 * e + 4]
        y_int = sum(I["N"][k] * de[k] for k in range(4))
        yd_int = sum(I["N"][k] * dde[k] for k in range(4))
        xy = sum(I["xN"][k] * de[k] for k in range(4))
        xyd = sum(I["xN"][k] * dde[k] for k in range(4))
        yy = sum(I["NN"][k][l] * de[k] * de[l] for k in range(4) for l in range(4))
        yyd = sum(I["NN"][k][l] * de[k] * dde[l] for k in range(4) for l in range(4))
        ydyd = sum(I["NN"][k][l] * dde[k] * dde[l] for k in range(4) for l in range(4))
        T.append(sub.add(m / 2 * (AA * I["1"] + 2 * AB * I["x"] + 2 * AC * y_int + 2 * AD * yd_int + BB * I["xx"]
                                  + 2 * BC * xy + 2 * BD * xyd + CC * yy + 2 * CD * yyd + DD * ydyd)))
        U_g.append(sub.add(-m * (gp * I["1"] + gx * I["x"] + gy * y_int)))
        U_e.append(sub.add((sp.Matrix(de).T * K * sp.Matrix(de))[0] / 2))
    return sp.Add(*T), sp.Add(*U_g), sp.Add(*U_e)


def flexible_mass(system) -> sp.Expr:
    """m L summed over the flexible links."""
    return sum((b.joint.mass_per_length * b.joint.length for b in system.bodies
                if isinstance(b.joint, FlexibleLink)), sp.Integer(0))
