"""The Whipple bicycle built from its parts (examples/whipple_bicycle.py), in both formulations (the rear
frame on a free-flying base; on rails, yaw and roll about the rear contact line, sympy's and Moore's),
against the published benchmark of Meijaard, Papadopoulos, Ruina and Schwab, "Linearized dynamics
equations for the balance and steer of a bicycle: a benchmark and review", Proc. R. Soc. A 463 (2007)
1955–1982.

Sources of the numbers (none computed by eomgen):
- M, C1, K0, K2: the paper's benchmark matrices (14 digits), as printed there and reproduced in
  BicycleParameters (moorepants/BicycleParameters, `benchmark_matrices`).
- TABLE_2: the eigenvalues at v = 0 … 10 m/s of the paper's Table 2 (p. 1971), as transcribed in the
  Whipple model tests of Dale L. Peterson (gyrostat formulation, 2011); v = 1 … 5 also in sympy's bicycle
  tutorial (doc/src/tutorials/physics/mechanics/bicycle_example.rst), to the digits printed there.
- WEAVE, CAPSIZE: Table 2 (a) of the paper (the same digits in the BicycleParameters-based tools and
  Peterson's tests).
The reference eigenvalues are those of the 4 × 4 first-order form of the published matrices; the test
first checks that they are the published table's."""
import functools
import runpy
import sys
from pathlib import Path

import numpy as np
import pytest

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
import whipple_bicycle as bike  # noqa: E402

G = 9.81
M = np.array([[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]])
C1 = np.array([[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]])
K0 = np.array([[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]])
K2 = np.array([[0.0, 76.59734589573222], [0.0, 2.65431523794604]])
WEAVE, CAPSIZE = 4.29238253634111, 6.02426201538837

# Table 2: per speed, the real eigenvalues and the weave pair's real part ± imaginary part
TABLE_2 = {0: ([-5.53094371765393, -3.13164324790656, 3.13164324790656, 5.53094371765393], None),
           1: ([-7.11008014637442, -3.13423125066578], (3.52696170990070, 0.80774027519930)),
           2: ([-8.67387984831735, -3.07158645641514], (2.68234517512745, 1.68066296590675)),
           3: ([-10.35101467245920, -2.63366137253667], (1.70675605663975, 2.31582447384325)),
           4: ([-12.15861426576450, -1.42944427361326], (0.41325331521125, 3.07910818603206)),
           5: ([-14.07838969279820, -0.32286642900409], (-0.77534188219585, 4.46486771378823)),
           6: ([-16.08537123098030, -0.00406690076970], (-1.52644486584142, 5.87673060598709)),
           7: ([-18.15788466125262, 0.10268170574766], (-2.13875644258362, 7.19525913329805)),
           8: ([-20.27940894394569, 0.14327879765713], (-2.69348683581097, 8.46037971396931)),
           9: ([-22.43788559040858, 0.15790184030917], (-3.21675402252485, 9.69377351531791)),
           10: ([-24.62459635017404, 0.16105338653172], (-3.72016840437287, 10.90681139476287))}
SPEEDS = list(TABLE_2)
TOL = 1e-11  # the finite differences' accuracy (observed: 4e-13)


def published_eigenvalues(v: float) -> np.ndarray:
    """Eigenvalues of ẋ = [[0, 1], [−M⁻¹(g K0 + v² K2), −v M⁻¹ C1]] x, the published matrices."""
    A = np.block([[np.zeros((2, 2)), np.eye(2)],
                  [-np.linalg.solve(M, G * K0 + v**2 * K2), -np.linalg.solve(M, v * C1)]])
    return np.sort_complex(np.linalg.eigvals(A))


def table_2(v: int) -> np.ndarray:
    real, pair = TABLE_2[v]
    pairs = [] if pair is None else [complex(pair[0], -pair[1]), complex(pair[0], pair[1])]
    return np.sort_complex(np.array(real + pairs, dtype=complex))


BUILDERS = {"free-flying base": bike.bicycle, "rails": bike.bicycle_on_rails}


@functools.cache
def generated(formulation: str):
    """Kane's equations of the bicycle built as `formulation` (a key of BUILDERS), and their code."""
    k = BUILDERS[formulation]()[1]
    return k, eg.codegen(k)


@pytest.fixture(scope="module", params=list(BUILDERS))
def f(request):
    return generated(request.param)[1]


@pytest.mark.parametrize("v", SPEEDS)
def test_published_matrices_give_the_published_table(v):
    assert np.abs(published_eigenvalues(v) - table_2(v)).max() < 1e-12


def test_published_matrices_give_the_published_speeds():
    weave, capsize = bike.stable_speeds(published_eigenvalues)
    assert abs(weave - WEAVE) < 1e-13 and abs(capsize - CAPSIZE) < 1e-13


def test_upright_running():
    """Assembled upright: the rear wheel's centre at height r_R, no pitch; rolling at v = 5 m/s the rear
    frame moves forward at v, the front wheel spins at −v/r_F; the roll–steer block of Kane's mass matrix
    is the published M."""
    f = generated("free-flying base")[1]
    q = f.assemble(np.zeros(9), bike.BENCHMARK)
    assert np.allclose(q, np.eye(9)[2] * -0.3, atol=1e-14)
    w = np.array([0.0, 0.0, -5.0 / 0.3])
    dependent = f.dependent_speeds(q, w, bike.BENCHMARK)  # ẋ, ẏ, ż, yaw rate, pitch rate, front spin
    assert np.allclose(dependent, [5.0, 0, 0, 0, 0, -5.0 / 0.35], atol=1e-13)
    assert np.abs(f.mass_matrix(q, w, bike.BENCHMARK)[:2, :2] - M).max() < 1e-13


def test_on_rails_the_rear_wheel_is_grounded_and_upright_running():
    """On rails the tree keeps the rear wheel on the ground: its disk is grounded, the pitch is the one
    dependent coordinate (the front wheel's height); assembled upright the benchmark's rear frame is level
    (pitch 0, Table 1's geometry); rolling at 5 m/s the rear contact moves forward at v, the front wheel
    spins at −v/r_F; the roll–steer block of Kane's mass matrix is the published M."""
    k, f = generated("rails")
    x, y, yaw, roll, pitch, spin_R, steer, spin_F = k.system.q
    assert k.grounded == ["rear_wheel_rolling"] and k.dependent_coordinates == [pitch]
    guess = np.r_[0.1, 0.2, 0.3, 0.0, 0.05, 0.4, 0.0, 0.5]  # x, y, yaw, roll 0, pitch, spin, steer 0, spin
    expected = np.where(np.arange(8) == 4, 0.0, guess)
    assert np.allclose(f.assemble(guess, bike.BENCHMARK), expected, atol=1e-14)
    w = np.array([0.0, 0.0, -5.0 / 0.3])
    dependent = f.dependent_speeds(np.zeros(8), w, bike.BENCHMARK)  # ẋ, ẏ, yaw, pitch rates, front spin
    assert np.allclose(dependent, [5.0, 0, 0, 0, -5.0 / 0.35], atol=1e-13)
    assert np.abs(f.mass_matrix(np.zeros(8), w, bike.BENCHMARK)[:2, :2] - M).max() < 1e-13


def test_eigenvalues_at_0_to_10_m_per_s(f):
    for v in SPEEDS:
        ours = bike.eigenvalues(f, float(v))
        assert np.abs(ours - published_eigenvalues(v)).max() < TOL, v
        assert np.abs(ours - table_2(v)).max() < TOL, v


def test_weave_and_capsize_speeds(f):
    weave, capsize = bike.stable_speeds(lambda v: bike.eigenvalues(f, v))
    assert abs(weave - WEAVE) < 1e-12 and abs(capsize - CAPSIZE) < 1e-12
    for v, stable in ((4.2, False), (4.4, True), (6.0, True), (6.1, False)):
        assert (bike.eigenvalues(f, v).real.max() < 0) == stable, v


@pytest.mark.slow
def test_sympy_kanes_method_bicycle_of_the_benchmark():
    """The benchmark's twin, sympy's KanesMethod on the same bicycle, gives the published table too."""
    import bicycle
    accelerations = bicycle.sympy_accelerations(*bicycle.sympy_bicycle())
    for v in (0, 3, 5, 7, 10):
        eig = np.sort_complex(np.linalg.eigvals(bike.state_matrix(accelerations, float(v))))
        assert np.abs(eig - table_2(v)).max() < TOL, v


def test_example_runs():
    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "whipple_bicycle.py"), run_name="__main__")
