"""Numerical extremes (benchmarks/extremes.py has the report): float64 against 50 digits."""
import functools
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
import extremes  # noqa: E402


@functools.cache
def rows() -> dict:
    """The report's rows by case, measured once per worker where a test asks (not while collecting)."""
    return {name: extremes.measure(name, f, q, u) for name, f, q, u in extremes.cases()}


def test_error_bounds():
    """In every case: M, b, g within 1e-14 relative of the 50-digit values; the forward dynamics within
    1e-15 · cond(M) (times a safety factor of 100). Every case is checked; the failures are listed."""
    failed = []
    for case, r in rows().items():
        report = (f"{case}: err M {r['err_M']:.1e}, b {r['err_b']:.1e}, g {r['err_g']:.1e}, "
                  f"u̇ {r['err_forward_dynamics']:.1e}, cond(M) {r['cond_M']:.1e}")
        print("\n" + report)
        if max(r["err_M"], r["err_b"], r["err_g"]) >= 1e-14 or \
                r["err_forward_dynamics"] >= 1e-13 * max(1.0, r["cond_M"]):
            failed.append(report)
    assert not failed, "\n".join(failed)


def test_error_grows_near_gimbal_lock():
    near, nearer = (rows()[f"solo12 Euler base, pitch 90° − {gap}"] for gap in ("0.01", "1e-06"))
    assert nearer["cond_M"] > 1e6 * near["cond_M"] / 100 and nearer["err_forward_dynamics"] > 1e3 * near["err_forward_dynamics"]


def test_quaternion_off_unit_norm_is_a_model_error():
    """Evaluated as accurately, but g (gravity seen in the base frame through R(q)) differs from the
    normalized quaternion's by ~1e-6; M, in base-frame speeds, does not depend on the orientation."""
    import eomgen as eg

    f = eg.codegen(eg.derive(eg.robots.load("solo12"), method="recursive"))
    q, _, _ = eg.random_states(f.eom.system, 1, np.random.default_rng(16))
    off = q[0].copy()
    off[3:7] *= 1 + 1e-6
    model_error = np.abs(f.g(off) - f.g(q[0])).max() / np.abs(f.g(q[0])).max()
    assert 1e-8 < model_error < 1e-5
    assert np.abs(f.M(off) - f.M(q[0])).max() == 0.0


def test_rank_deficient_contacts():
    """A foot held twice: 15 rows of rank 12, u̇ and the minimum-norm F_c to 50 digits' values, and the
    two contacts at the same point share the foot's force equally (a warning names the repeated rows)."""
    import eomgen as eg

    r = rows()["solo12, a foot held twice (15 rows, rank 12)"]
    assert (r["contact_rows"], r["contact_rank"]) == (15, 12)
    assert r["err_F_c"] < 1e-13 and r["err_forward_dynamics"] < 1e-13
    f = eg.codegen(eg.derive(extremes.solo12_foot_held_twice(), method="recursive"))
    q, _, _ = eg.random_states(f.eom.system, 1, np.random.default_rng(23))
    with pytest.warns(UserWarning, match=r"\['FL_FOOT_again.x', 'FL_FOOT_again.y', 'FL_FOOT_again.z'\]"):
        F = f.contact_forces(q[0], np.zeros(18))
    np.testing.assert_allclose(F[:3], F[12:], rtol=1e-10)
    assert np.abs(F[:3]).max() > 0.1
