"""The Whipple bicycle (benchmark of Meijaard et al. 2007): eomgen's Kane from the parts
(examples/whipple_bicycle.py) beside sympy.physics.mechanics.KanesMethod on the same bicycle with the
same symbolic parameters: derivation time, operation count of the generated code, and both models'
eigenvalues against the published ones. Prints a table and writes JSON.

Run: python benchmarks/bicycle.py [--out benchmarks/results/bicycle.json]"""
from __future__ import annotations

import argparse
import ast
import sys
import time
from pathlib import Path

import numpy as np
import sympy as sp
import sympy.physics.mechanics as me
from scipy.optimize import newton

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))
import results_io  # noqa: E402
import test_bicycle as published  # noqa: E402
import whipple_bicycle as bike  # noqa: E402

t = me.dynamicsymbols._t


def sympy_bicycle() -> tuple[me.KanesMethod, dict]:
    """KanesMethod on the bicycle: yaw q1, roll q2, pitch q3 (dependent), steer q4; speeds u1 … u4 their
    rates, u5 and u6 the wheels' spin rates on their frames; independent roll, steer and rear spin rates.
    The rear contact P has zero velocity (no slip), so every velocity follows from P by the two-point
    theorem; the front contact's velocity = 0 gives the three velocity constraints (two no-slip, one the
    rate of the front contact's height, the holonomic constraint)."""
    p = bike.P
    q1, q2, q3, q4 = q = me.dynamicsymbols("q1:5")
    u1, u2, u3, u4, u5, u6 = u = me.dynamicsymbols("u1:7")
    N = me.ReferenceFrame("N")  # z down
    A = N.orientnew("A", "Axis", (q1, N.z))  # yaw
    B = A.orientnew("B", "Axis", (q2, A.x))  # roll
    C = B.orientnew("C", "Axis", (q3, B.y))  # rear frame: pitch
    D = C.orientnew("D", "Axis", (p["lam"], C.y))  # D.z along the steer axis, tilted back by λ
    steered = D.orientnew("D_E", "Axis", (q4, D.z))
    E = steered.orientnew("E", "Axis", (-p["lam"], steered.y))  # front frame, = C when δ = 0
    WR, WF = me.ReferenceFrame("WR"), me.ReferenceFrame("WF")  # the wheels (axisymmetric: spin only)
    A.set_ang_vel(N, u1 * N.z)
    B.set_ang_vel(A, u2 * A.x)
    C.set_ang_vel(B, u3 * B.y)
    E.set_ang_vel(C, u4 * D.z)
    WR.set_ang_vel(C, u5 * C.y)
    WF.set_ang_vel(E, u6 * E.y)

    contact_R = me.Point("P")
    contact_R.set_vel(N, 0)
    centre_R = contact_R.locatenew("R_o", -p["r_R"] * B.z)
    centre_R.v2pt_theory(contact_R, N, WR)
    mass_B = centre_R.locatenew("B_o", p["x_B"] * C.x + (p["z_B"] + p["r_R"]) * C.z)
    steer = centre_R.locatenew("S", (p["w"] + p["c"]) * C.x + p["r_R"] * C.z)  # steer axis meets the ground
    mass_H = steer.locatenew("H_o", (p["x_H"] - p["w"] - p["c"]) * E.x + p["z_H"] * E.z)
    centre_F = steer.locatenew("F_o", -p["c"] * E.x - p["r_F"] * E.z)
    for point in (mass_B, steer):
        point.v2pt_theory(centre_R, N, C)
    for point in (mass_H, centre_F):
        point.v2pt_theory(steer, N, E)
    down = A.z - (A.z & E.y) * E.y  # towards the ground in the front wheel's plane
    contact_F = centre_F.locatenew("Q", p["r_F"] * down / sp.sqrt(down & down))
    contact_F.v2pt_theory(centre_F, N, WF)

    bodies = [me.RigidBody("B", mass_B, C, p["m_B"],
                           (me.inertia(C, p["I_Bxx"], p["I_Byy"], p["I_Bzz"], 0, 0, p["I_Bxz"]), mass_B)),
              me.RigidBody("H", mass_H, E, p["m_H"],
                           (me.inertia(E, p["I_Hxx"], p["I_Hyy"], p["I_Hzz"], 0, 0, p["I_Hxz"]), mass_H)),
              me.RigidBody("R", centre_R, WR, p["m_R"],
                           (me.inertia(C, p["I_Rxx"], p["I_Ryy"], p["I_Rxx"]), centre_R)),
              me.RigidBody("F", centre_F, WF, p["m_F"],
                           (me.inertia(E, p["I_Fxx"], p["I_Fyy"], p["I_Fxx"]), centre_F))]
    loads = [(body.masscenter, body.mass * p["g"] * N.z) for body in bodies]
    v_Q = contact_F.vel(N)
    km = me.KanesMethod(N, q_ind=[q1, q2, q4], u_ind=[u2, u4, u5],
                        kd_eqs=[qi.diff(t) - ui for qi, ui in zip(q, u)],
                        q_dependent=[q3], configuration_constraints=[contact_F.pos_from(contact_R) & N.z],
                        u_dependent=[u6, u1, u3],  # pivots nonzero upright: x by spin, y by yaw, z by pitch
                        velocity_constraints=[v_Q & A.x, v_Q & A.y, v_Q & A.z])
    km.kanes_equations(bodies, loads)
    return km, {"q": q, "u": u, "height": contact_F.pos_from(contact_R) & N.z,
                "constraints": sp.Matrix([v_Q & A.x, v_Q & A.y, v_Q & A.z])}


def plain_symbols(extra: dict) -> dict:
    """q(t), u(t) → plain symbols (to lambdify and print)."""
    return {s: sp.Symbol(f"_{s.func.__name__}") for s in [*extra["q"], *extra["u"]]}


def sympy_accelerations(km: me.KanesMethod, extra: dict):
    """(φ̈, δ̈)(x, v) of the KanesMethod bicycle at x = (φ, δ, φ̇, δ̇), rolling at speed v (rear spin
    −v/r_R): pitch from the front contact's height = 0 (secant iteration), the dependent speeds from the
    velocity constraints, u̇ from the mass matrix and forcing of all six speeds."""
    q, u = extra["q"], extra["u"]
    plain = plain_symbols(extra) | {bike.P[name]: value for name, value in bike.BENCHMARK.items()}
    args = [[plain[s] for s in q], [plain[s] for s in u]]
    height = sp.lambdify(args[0], extra["height"].xreplace(plain))
    C_u = sp.lambdify(args, extra["constraints"].jacobian(u).xreplace(plain), cse=True)
    M, F = (sp.lambdify(args, m.xreplace(plain), cse=True) for m in (km.mass_matrix, km.forcing))
    ind, dep = [1, 3, 4], [0, 2, 5]
    rows = [list(km.u).index(u[1]), list(km.u).index(u[3])]  # u̇ in the order of km.u: roll, steer

    def accelerations(x, v):
        phi, delta, phid, deltad = x
        pitch = newton(lambda th: height(0.0, phi, th, delta), 0.0, tol=1e-15)
        qs = [0.0, phi, pitch, delta]
        us = np.zeros(6)
        us[ind] = phid, deltad, -v / bike.BENCHMARK["r_R"]
        Cu = np.array(C_u(qs, us), dtype=float)
        us[dep] = -np.linalg.solve(Cu[:, dep], Cu[:, ind] @ us[ind])
        ud = np.linalg.solve(np.array(M(qs, us), dtype=float), np.array(F(qs, us), dtype=float))
        return ud[rows, 0]
    return accelerations


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def eigenvalue_error(accelerations) -> float:
    """The largest distance of the linearized eigenvalues from the published ones, v = 0 … 10 m/s."""
    return max(np.abs(np.sort_complex(np.linalg.eigvals(bike.state_matrix(accelerations, float(v))))
                      - published.published_eigenvalues(v)).max() for v in range(11))


def code_ops(source: str) -> int:
    """Operations in Python source, counted alike for both: arithmetic (binary), negations, calls."""
    return sum(isinstance(node, (ast.BinOp, ast.UnaryOp, ast.Call)) for node in ast.walk(ast.parse(source)))


def eomgen_row() -> dict:
    """eg.kane on the bicycle from its parts, then eg.codegen: the generated functions (M, h, Y, C, rates,
    holonomic; the linear solves are numeric), their operations."""
    t_derive, (_, k) = timed(bike.bicycle)
    t_code, f = timed(lambda: eg.codegen(k))
    ops = {key: code_ops(g.source) for key, g in f.functions.items()}
    return {"method": "eomgen kane", "derive_s": t_derive, "codegen_s": t_code, "ops": sum(ops.values()),
            "ops_by_function": ops, "max_eigenvalue_error": eigenvalue_error(bike.accelerations(f))}


def sympy_row() -> dict:
    """KanesMethod (the constraints solved symbolically, LU), then sympy.cse of its mass matrix and
    forcing (all six speeds) printed as Python (sympy.pycode), its operations."""
    t_derive, (km, extra) = timed(sympy_bicycle)
    equations = [e.xreplace(plain_symbols(extra)) for e in [*km.mass_matrix, *km.forcing]]
    t_code, (common, outputs) = timed(lambda: sp.cse(equations))
    source = "\n".join([f"{s} = {sp.pycode(e)}" for s, e in [*common, *(("_", e) for e in outputs)]])
    return {"method": "sympy KanesMethod", "derive_s": t_derive, "codegen_s": t_code,
            "ops": code_ops(source),
            "max_eigenvalue_error": eigenvalue_error(sympy_accelerations(km, extra))}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=results_io.default_path("bicycle"))
    args = ap.parse_args()
    rows = [eomgen_row(), sympy_row()]
    print(f"{'Whipple bicycle':20s} {'derive [s]':>10s} {'code [s]':>9s} {'operations':>11s} "
          f"{'eigenvalues vs published':>25s}")
    for r in rows:
        print(f"{r['method']:20s} {r['derive_s']:10.2f} {r['codegen_s']:9.2f} {r['ops']:11d} "
              f"{r['max_eigenvalue_error']:25.1e}")
    print("code: eg.codegen, or sympy.cse of KanesMethod's mass matrix and forcing; operations: of the "
          "generated Python, counted alike")
    results_io.write(args.out, "bicycle", rows, sympy=sp.__version__)


if __name__ == "__main__":
    main()
