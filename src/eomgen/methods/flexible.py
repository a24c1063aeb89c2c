"""Euler-Bernoulli beam elements with Hermite cubic shape functions (`model.beam`), for flexible links
in Lagrange II (after the paper "Dynamic modeling and path planning of flexible-link manipulators").
A point x of the link is at

    r(x) = p + R (f_x(x) e_x + f_y(x) e_y + f_z(x) e_z),   f_x = x + u_x,   f_y = y,   f_z = z,

y = Σ N_k(ξ) d_k on each element of length h (ξ = x − x_e, d its nodal deflections and slopes in the
link's x-y plane; z the same in its x-z plane where the link bends there, else 0) and u_x = −½ ∫₀ˣ (y'² +
z'²) ds the foreshortening of the bent beam (with stiffening; else 0). On an element these are
polynomials in ξ (y, z of degree 3, u_x of degree 5, its constant the foreshortening of the elements
before, `FlexibleLink.shortening`), their coefficients named intermediates, and with A = ṗ, E_a = R e_a
and Ė_a,

    ṙ = A + Σ_a (Ė_a f_a + E_a ḟ_a),    T = ½ ∫ m |ṙ|² dx,    U_g = −∫ m g⃗ · r dx,
    U_e = ½ Σ_e (E I_z d_yᵀ K_e d_y + E I_y d_zᵀ K_e d_z + (GJ / h)(φ_b − φ_a)²),
    K_e = (1 / h³) [[12, 6h, −12, 6h], [6h, 4h², −6h, 2h²], [−12, −6h, 12, −6h], [6h, 2h², −6h, 4h²]],

every integral exact (∫₀ʰ ξ^(i+j) dξ of the coefficients' products), nothing truncated: T is the kinetic
energy of a motion of the centre line, so M stays positive definite at any deflection. Linearized, the
foreshortening gives the geometric stiffness of the axial load, ½ ∫ P(s) (y'² + z'²) ds (for a link
spinning at Ω, P = m Ω² (L² − s²)/2): the centrifugal and gravitational stiffening (Kane, Ryan and
Banerjee 1987). The twist φ (linear on an element) and, with `rotary_inertia` (ρI_x, ρI_y, ρI_z), the
cross-sections' turning: T_rot = ½ Σ_a ρI_a ∫ ω_s,a² dx with ω_s the section's angular velocity in its
own axes (turned from the link frame by R_z(y') R_y(−z') R_x(φ), as the tip), to second order in the
deformation (`_section_rates`): a Rayleigh beam in bending, the twist's inertia, and on a spinning link
the sections' centrifugal and gyroscopic terms (the propeller moment, the flapwise softening). T_rot is
½ wᵀ J w of a vector w linear in the speeds: M stays positive definite."""
from __future__ import annotations

from functools import cache
from itertools import zip_longest

import sympy as sp

from ..kinematics import Kinematics
from ..linalg import dot
from ..model import FlexibleLink
from ..model.beam import coefficients, integrals, quadratic
from ..model.flexible_link import section_turn


def _integral(a: list, b: list, h) -> sp.Expr:
    """∫₀ʰ a(ξ) b(ξ) dξ for polynomials given by their coefficients."""
    return sp.Add(*[x * y * h ** (i + j + 1) / (i + j + 1) for i, x in enumerate(a) for j, y in enumerate(b)
                    if x != 0 and y != 0])


def _product(a: list, b: list) -> list:
    """The coefficients of a(ξ) b(ξ)."""
    return [sp.Add(*[a[i] * b[p - i] for i in range(max(0, p - len(b) + 1), min(p, len(a) - 1) + 1)])
            for p in range(len(a) + len(b) - 1)]


def _slope(y: list) -> list:
    return [(p + 1) * y[p + 1] for p in range(len(y) - 1)]


def _element(kin: Kinematics, joint, e: int, c: list, d: dict, d_dot: dict) -> dict[str, tuple[list, list]]:
    """Per field, (value, rate) on element e as coefficients in ξ: "y", "z" from the shape functions'
    coefficients c and the plane's nodal values and rates d, ḋ; "x" the twist, linear."""
    h, fields = joint.length / joint.elements, {}
    for field, values in d.items():
        if field == "x":
            (a, b), (a_dot, b_dot) = d["x"][e:e + 2], d_dot["x"][e:e + 2]
            fields["x"] = [a, (b - a) / h], [a_dot, (b_dot - a_dot) / h]
            continue
        de, dde = values[2 * e:2 * e + 4], d_dot[field][2 * e:2 * e + 4]
        fields[field] = ([kin.sub.add(sp.Add(*[c[k][p] * de[k] for k in range(4)])) for p in range(4)],
                         [sp.Add(*[c[k][p] * dde[k] for k in range(4)]) for p in range(4)])
    return fields


def _axial(kin: Kinematics, joint, e: int, fields: dict, start) -> tuple[list, list]:
    """(f_x, ḟ_x) on element e: x + u_x with u_x = start − ½ ∫ (y'² + z'²) (start: u_x where it starts)."""
    h = joint.length / joint.elements
    if not joint.stiffening:
        return [e * h, sp.Integer(1)], []
    slopes = [_slope(fields[f][0]) for f in ("y", "z") if f in fields]
    square = [sp.Add(*terms) for terms in zip(*[_product(s, s) for s in slopes])]  # degree 4
    u_x = [start] + [kin.sub.add(-square[p] / (2 * (p + 1))) for p in range(5)]
    u_x_dot = list(kin.time_derivative(sp.Matrix(u_x)))
    return [e * h + u_x[0], 1 + u_x[1], *u_x[2:]], u_x_dot


_angles = sp.symbols("y_s z_s phi y_s_dot z_s_dot phi_dot")  # a section's y', z', φ and rates (placeholders)
_Omega = sp.symbols("Omega_x Omega_y Omega_z")


@cache
def _section_rates() -> list[sp.Poly]:
    """ω_s = Dᵀ Ω + vee(Dᵀ Ḋ), the angular velocity of a cross-section in its own axes, turned from the
    link frame by D = `section_turn`(y', z', φ); to second order in the turn and its rates (the
    centrifugal and gyroscopic terms of the sections' inertia: the propeller moment of a spinning
    twisted link, the flapwise softening), as polynomials in the placeholders."""
    turn, rates, e = _angles[:3], _angles[3:], sp.Symbol("e")
    D = section_turn(*turn)
    W = D.T * sum((D.diff(x) * x_dot for x, x_dot in zip(turn, rates)), sp.zeros(3, 3))
    w = D.T * sp.Matrix(_Omega) + sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
    small = {x: e * x for x in _angles}
    return [sp.Poly(sp.series(x.xreplace(small), e, 0, 3).removeO().subs(e, 1), *_angles) for x in w]


def _turning(fields: dict, Omega) -> list[list[sp.Expr]]:
    """The cross-sections' ω_s (`_section_rates`) as coefficients in ξ, Ω the link frame's angular
    velocity in its axes."""
    empty = ([], [])
    y, z, x = (fields.get(f, empty) for f in ("y", "z", "x"))
    angles = [_slope(y[0]), _slope(z[0]), x[0], _slope(y[1]), _slope(z[1]), x[1]]
    values = dict(zip(_Omega, Omega))
    components = []
    for w in _section_rates():
        total: list = []
        for powers, coefficient in w.terms():
            term = [coefficient.xreplace(values)]
            for polynomial, k in zip(angles, powers):
                for _ in range(k):
                    term = _product(term, polynomial)
            total = [sp.Add(*pair) for pair in zip_longest(total, term, fillvalue=0)]
        components.append(total)
    return components


def _strain(field: str, d: list, e: int, K, h) -> sp.Expr:
    """d_eᵀ K_e d_e of a bending plane's nodal values d on element e (K_e without E I), or (φ_b − φ_a)²/h of
    the twist's."""
    if field == "x":
        return (d[e + 1] - d[e]) ** 2 / h
    return quadratic(K, d[2 * e:2 * e + 4], d[2 * e:2 * e + 4])


def energies(kin: Kinematics, body, Omega=None) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(T, U_gravity, U_elastic) of the flexible link moved by `body`'s FlexibleLink joint (Omega: the link
    frame's angular velocity in its axes, needed with rotary inertia)."""
    joint, sub = body.joint, kin.sub
    h, m = joint.length / joint.elements, joint.mass_per_length
    R, p = kin.R[body], kin.p[body]
    axes = ["x", "y"] + ["z"] * ("z" in joint.fields)
    vectors = {"A": kin.time_derivative(p)}
    for i in range(len(axes)):
        vectors[("E", axes[i])] = R[:, i]
        vectors[("dE", axes[i])] = kin.time_derivative(sp.Matrix(R[:, i]))
    names = list(vectors)

    def known(a, b):  # R orthonormal: E_a · E_b = δ_ab, Ė_a · E_a = 0
        if a == "A" or b == "A" or (a[0] == b[0] == "dE") or (a[0] != b[0] and a[1] != b[1]):
            return None
        return int(a[1] == b[1]) if a[0] == b[0] == "E" else 0
    dots = {(a, b): sub.add(dot(vectors[a], vectors[b])) if known(a, b) is None else known(a, b)
            for i, a in enumerate(names) for b in names[i:]}
    g = {a: dot(kin.system.gravity, vectors[("E", a)]) for a in axes}
    c, K = coefficients(h), integrals(h)["K"]
    d, d_dot = joint.deflections(), joint.deflections(joint.speeds[-len(joint.nodal):])
    T, U_g, U_e, start = [], [], [], sp.Integer(0)
    for e in range(joint.elements):
        fields = _element(kin, joint, e, c, d, d_dot)
        f_x, f_x_dot = _axial(kin, joint, e, fields, start)
        start = sub.add(start + joint.shortening(e))
        value = {"x": f_x, **{a: fields[a][0] for a in ("y", "z") if a in fields}}
        polynomial = {"A": [sp.Integer(1)], ("E", "x"): f_x_dot,
                      **{("dE", a): value[a] for a in axes},
                      **{("E", a): fields[a][1] for a in ("y", "z") if a in fields}}
        kinetic = [(1 if a == b else 2) * w * _integral(polynomial[a], polynomial[b], h)
                   for (a, b), w in dots.items() if w != 0]
        T.append(sub.add(m / 2 * sp.Add(*kinetic)))
        if joint.rotary_inertia is not None:
            turning = zip(joint.rotary_inertia, _turning(fields, Omega))
            T.append(sub.add(sp.Add(*[J * _integral(w, w, h) / 2 for J, w in turning if J != 0])))
        U_g.append(sub.add(-m * (dot(kin.system.gravity, p) * h
                                 + sp.Add(*[g[a] * _integral([1], value[a], h) for a in axes]))))
        U_e.append(sub.add(sp.Add(*[joint.stiffness[f] * _strain(f, d[f], e, K, h)
                                    for f in joint.fields]) / 2))
    return sp.Add(*T), sp.Add(*U_g), sp.Add(*U_e)


def flexible_mass(system) -> sp.Expr:
    """m L summed over the flexible links."""
    return sum((b.joint.mass_per_length * b.joint.length for b in system.bodies
                if isinstance(b.joint, FlexibleLink)), sp.Integer(0))
