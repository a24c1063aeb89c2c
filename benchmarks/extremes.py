"""Numerical extremes: the generated float64 code against the same expressions evaluated with mpmath
at 50 digits, and the forward dynamics against an mpmath LU solve, with the condition number of M.

Where error grows and why: evaluating M, b, g costs a few ulps even at 10³ rad/s, 10⁴ rad or mass
ratios of 10⁶ (every entry is a short sum of products of bounded trigonometric terms and constants;
large speeds only scale b by u²; an angle of 10⁴ rad is exact in float64 and libm's sin and cos are
correct to an ulp there, so the digits an angle that large lacks were lost before, in whatever
produced it). The forward dynamics u̇ = M⁻¹(τ − b − g) loses about log10 cond(M) digits:
near kinematic singularities (a stretched arm), for mass ratios of 10⁶ and for Euler-angle bases near
pitch 90° cond(M) grows, and so does the error of u̇. A quaternion 1e-6 off unit norm is evaluated
just as accurately, but the model itself is then wrong by ~1e-6 (R is not orthonormal): normalize.
A rank-deficient contact set (a foot held twice) leaves the contact forces undetermined along the
redundant rows; the minimum-norm forces and the accelerations are computed to about
cond(J M⁻¹ Jᵀ restricted to its range) · 1e-16, like a full-rank set.

Run: python benchmarks/extremes.py [--out benchmarks/results/extremes.json]"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import mpmath
import numpy as np

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parent))
import derive_chain  # noqa: E402
import results_io  # noqa: E402


def numeric_chain(n: int, masses=None) -> eg.System:
    system, parent = eg.System(gravity=(0, 0, -9.81)), None
    for i in range(n):
        m = 1.0 if masses is None else masses[i % len(masses)]
        parent = system.add_body(f"link{i}", parent=parent, joint=eg.Revolute(f"q_{i}", axis=derive_chain.axis(i)),
                                 mass=m, com=(0.15, 0.01, 0.0), inertia=np.diag([0.001, 0.01, 0.01]).dot(m).tolist(),
                                 placement=eg.Placement(translation=(0.3 if i else 0.0, 0.0, 0.0)))
    return system


def _rel(a, ref) -> float:
    ref = np.asarray(ref, dtype=float)
    return float(np.abs(np.asarray(a, float) - ref).max() / max(np.abs(ref).max(), 1e-300))


def measure(name: str, f, q, u) -> dict:
    """Relative errors of M, b, g and u̇ = M⁻¹(−b − g) against 50 digits, and cond(M); with contacts,
    u̇ and F_c of the constrained dynamics against the minimum-norm solution at 50 digits."""
    M, b, g = f.M(q), f.b(q, u), f.g(q)
    Mr, br, gr = (f.reference(k, q, u) for k in ("M", "b", "g"))
    row = {"case": name, "err_M": _rel(M, Mr), "err_b": _rel(b, br[:, 0]), "err_g": _rel(g, gr[:, 0]),
           "cond_M": float(np.linalg.cond(M))}
    with mpmath.workdps(50):
        M_mp, h_mp = mpmath.matrix(Mr.tolist()), mpmath.matrix((-(br + gr))[:, 0].tolist())
        if not f.eom.system.contacts:
            row["err_forward_dynamics"] = _rel(np.linalg.solve(M, -(b + g)), _floats(mpmath.lu_solve(M_mp, h_mp)))
            return row
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the redundant rows are the point here
            ud, F = f.constrained_dynamics(q, u)
        J = mpmath.matrix(f.reference("J_c", q).tolist())
        Jdot_u = mpmath.matrix(f.reference("Jdot_c_u", q, u)[:, 0].tolist())
        Minv = mpmath.inverse(M_mp)  # numbers at 50 digits (LU)
        Minv_JT, Minv_h = Minv * J.T, Minv * h_mp
        F_ref = -_pinv(J * Minv_JT) * (J * Minv_h + Jdot_u)
        row.update(err_forward_dynamics=_rel(ud, _floats(Minv_h + Minv_JT * F_ref)), err_F_c=_rel(F, _floats(F_ref)),
                   contact_rows=J.rows, contact_rank=int(np.linalg.matrix_rank(_floats(J).reshape(J.rows, J.cols))))
    return row


def _floats(x) -> np.ndarray:
    return np.array([float(v) for v in x])


def _pinv(A):
    """Moore-Penrose pseudo-inverse in mpmath (singular values below 1e-30 of the largest dropped)."""
    U, S, V = mpmath.svd_r(A)
    keep = [k for k in range(len(S)) if S[k] > S[0] * mpmath.mpf("1e-30")]
    return sum((V[k, :].T * U[:, k].T / S[k] for k in keep), mpmath.zeros(A.cols, A.rows))


def solo12_foot_held_twice():
    """solo12 on its four feet (3D points) plus a second contact frame at the front left foot:
    15 constraint rows of rank 12."""
    system = eg.robots.load("solo12")
    foot = system.frames["FL_FOOT"]
    system.add_frame("FL_FOOT_again", foot.body, foot.placement)
    for name in ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT", "FL_FOOT_again"):
        system.add_contact(name, "point")
    return system


def cases():
    rng = np.random.default_rng(0)
    ur5 = eg.codegen(eg.derive(eg.robots.load("ur5"), method="recursive"))
    yield "ur5 random", ur5, rng.uniform(-3, 3, 6), rng.uniform(-2, 2, 6)
    yield "ur5 stretched, wrist aligned", ur5, np.array([0.3, 0.0, 0.0, 0.0, 0.0, 0.7]), rng.uniform(-2, 2, 6)
    yield "ur5 at 1e3 rad/s", ur5, rng.uniform(-3, 3, 6), np.full(6, 1e3)
    yield "ur5 at angles of 1e4 rad", ur5, 1e4 + rng.uniform(-3, 3, 6), rng.uniform(-2, 2, 6)
    ratio = eg.codegen(eg.derive(numeric_chain(6, masses=[1e3, 1e-3]), method="recursive"))
    yield "6 links, mass ratio 1e6", ratio, rng.uniform(-3, 3, 6), rng.uniform(-2, 2, 6)
    for n in (20, 50):
        chain = eg.codegen(eg.derive(numeric_chain(n), method="recursive"))
        yield f"chain of {n} links", chain, rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
    euler = eg.robots.load("solo12", base="euler")
    fe = eg.codegen(eg.derive(euler))
    for gap in (1e-2, 1e-6):
        q = np.r_[0.0, 0.0, 0.3, 0.2, np.pi / 2 - gap, 0.1, np.tile([0.0, 0.8, -1.6], 4)]
        yield f"solo12 Euler base, pitch 90° − {gap:g}", fe, q, rng.uniform(-1, 1, 18)
    quat = eg.codegen(eg.derive(eg.robots.load("solo12"), method="recursive"))
    q, u, _ = eg.random_states(quat.eom.system, 1, rng)
    q = q[0]
    q[3:7] *= 1 + 1e-6
    yield "solo12 quaternion 1e-6 off unit norm", quat, q, u[0]
    held = eg.codegen(eg.derive(solo12_foot_held_twice(), method="recursive"))
    q, u, _ = eg.random_states(held.eom.system, 1, rng)
    J = held.contact_jacobian(q[0])
    u = u[0] - np.linalg.pinv(J) @ (J @ u[0])  # speeds the contacts allow
    yield "solo12, a foot held twice (15 rows, rank 12)", held, q[0], u


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=results_io.default_path("extremes"))
    args = ap.parse_args()
    rows = [measure(*c) for c in cases()]
    print(f"{'case':46s} {'err M':>9s} {'err b':>9s} {'err g':>9s} {'err u̇':>9s} {'err F_c':>9s} {'cond M':>9s}")
    for r in rows:
        F = f"{r['err_F_c']:9.1e}" if "err_F_c" in r else f"{'-':>9s}"
        print(f"{r['case']:46s} {r['err_M']:9.1e} {r['err_b']:9.1e} {r['err_g']:9.1e} "
              f"{r['err_forward_dynamics']:9.1e} {F} {r['cond_M']:9.1e}")
    print("\n" + __doc__.split("\n\n")[1])
    results_io.write(args.out, "extremes", rows)


if __name__ == "__main__":
    main()
