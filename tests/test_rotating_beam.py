"""A cantilever on a hub spinning at constant Ω (uniform, no hub radius): its frequencies from the
equations linearized about the undeflected beam, with the hub's speed held (its row dropped, u_hub = Ω).

Nondimensional: L = m = EI = 1, so γ = Ω √(m L⁴/EI) = Ω and ω̄ = ω. The first flapwise (out of the plane
of rotation) frequency of the centrifugally stiffened beam: 3.5160, 3.6816, 4.1373, 4.7973, 5.5850 at
γ = 0 … 4 (Wright, Smith, Thompson and Worley, "Vibration modes of centrifugally stiffened beams",
J. Appl. Mech. 49 (1982) 197–202, table 1; Hodges and Rutkowski, "Free-vibration analysis of rotating
beams by a variable-order finite-element method", AIAA J. 19 (1981) 1459–1466). In the plane of rotation
(chordwise) the inextensible beam's frequency is ω² = ω_flap² − Ω². Without stiffening the flapwise
frequency stays ω₀ and the chordwise one follows ω² = ω₀² − Ω², unstable (a real eigenvalue) past ω₀.
Gravity along the link: Greenhill's buckling load of a column under its own weight; and Kane, Ryan and
Banerjee's spin-up."""
from __future__ import annotations

import functools
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq

import eomgen as eg

PUBLISHED = [3.5160, 3.6816, 4.1373, 4.7973, 5.5850]  # γ = 0, 1, 2, 3, 4
FLAP = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]  # the link's deflection axis y along the hub's axis z


@functools.cache
def beam_on_hub(elements: int, flap: bool, stiffening: bool = True):
    """The numeric functions and nv of a hub (revolute about z, massless) carrying a flexible link,
    deflecting out of the plane of rotation (flap) or in it; derived once per worker (read only)."""
    system = eg.System(gravity=(0, 0, 0))
    hub = system.add_body("hub", joint=eg.Revolute("theta_h"), mass=0)
    link = eg.FlexibleLink("beam", length=1, mass_per_length=1, EI=1, elements=elements, stiffening=stiffening)
    system.add_body("beam", parent=hub, joint=link, mass=0,
                    placement=eg.Placement(rotation=FLAP if flap else np.eye(3).tolist()))
    return eg.codegen(eg.derive(system, method="lagrange")), system.nv


def eigenvalues(f, n: int, Omega: float, h: float = 1e-6) -> np.ndarray:
    """λ of M ẍ + C ẋ + K x = 0 for the nodal coordinates x (the hub at speed Ω, the link's own angle
    held at 0): K, C by central differences of nle − τ_elastic at x = ẋ = 0."""
    r = list(range(2, n))

    def force(x, v):
        q, u = np.zeros(n), np.r_[Omega, 0.0, np.zeros(n - 2)]
        q[r], u[r] = x, v
        return (f.nle(q, u) - f.tau_of("elastic", q, u))[r]

    k, zero = len(r), np.zeros(len(r))
    K = np.column_stack([(force(h * e, zero) - force(-h * e, zero)) / (2 * h) for e in np.eye(k)])
    C = np.column_stack([(force(zero, h * e) - force(zero, -h * e)) / (2 * h) for e in np.eye(k)])
    M = f.M(np.zeros(n))[np.ix_(r, r)]
    A = np.block([[np.zeros((k, k)), np.eye(k)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    return np.linalg.eigvals(A)


def first(f, n: int, Omega: float) -> float:
    """The first frequency, or −√λ for a real eigenvalue λ > 0 (divergence)."""
    lam = eigenvalues(f, n, Omega)
    if lam.real.max() > 1e-6:
        return -lam.real.max()
    return np.sort(np.abs(lam.imag))[::2][0]  # ± pairs


def test_flapwise_frequencies_equal_the_published_values():
    """8 elements: each of the five equals the published four decimals (±0.5 in the last, plus 3e-5 for
    the discretisation: 8 and 12 elements differ by less, `test_flapwise_frequencies_converge`)."""
    coarse = beam_on_hub(8, True)
    for gamma, published in enumerate(PUBLISHED):
        w8 = first(*coarse, gamma)
        print(f"γ = {gamma}: ω̄ = {w8:.6f} (8 elements); published {published}")
        assert abs(w8 - published) < 8e-5


@pytest.mark.slow
def test_flapwise_frequencies_converge():
    """12 elements: each of the five equals the published four decimals (±0.5 in the last, plus 1e-5),
    and 8 and 12 elements differ by < 3e-5."""
    fine, coarse = beam_on_hub(12, True), beam_on_hub(8, True)
    for gamma, published in enumerate(PUBLISHED):
        w12, w8 = first(*fine, gamma), first(*coarse, gamma)
        print(f"γ = {gamma}: ω̄ = {w12:.6f} (12 elements), {w8:.6f} (8); published {published}")
        assert abs(w12 - published) < 6e-5 and abs(w8 - w12) < 3e-5


def test_chordwise_frequency_is_the_flapwise_one_less_the_spin():
    for gamma in (1.0, 2.5, 4.0):
        flap, chord = first(*beam_on_hub(8, True), gamma), first(*beam_on_hub(8, False), gamma)
        assert chord**2 == pytest.approx(flap**2 - gamma**2, rel=1e-8)


def test_without_stiffening_the_link_softens_and_diverges():
    """stiffening=False: the flapwise frequency stays ω₀; the chordwise one follows ω² = ω₀² − Ω² and
    diverges past Ω = ω₀ (a real eigenvalue), where the stiffened link stays stable."""
    flap, chord = beam_on_hub(8, True, False), beam_on_hub(8, False, False)
    w0 = first(*flap, 0.0)
    assert w0 == pytest.approx(first(*beam_on_hub(8, True), 0.0), rel=1e-12)
    for gamma in (1.0, 2.0, 3.0):
        assert first(*flap, gamma) == pytest.approx(w0, rel=1e-8)
        assert first(*chord, gamma) ** 2 == pytest.approx(w0**2 - gamma**2, rel=1e-8)
    assert first(*chord, 4.0) < 0 < first(*beam_on_hub(8, False), 4.0)


def test_spin_up_stays_bounded_with_stiffening_and_diverges_without():
    """Kane, Ryan and Banerjee's spin-up (benchmarks/spin_up.py, 2 elements; its table converges with
    the element count): the stiffened link's tip deflection peaks below 1 m during the 15 s ramp to
    6 rad/s and dies out in the steady spin; without stiffening it exceeds the link's length within 12 s."""
    sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
    from spin_up import L, spin_up

    t, w = spin_up(2, True, 30.0)
    assert 0.3 < np.abs(w).max() < 1.0 and np.abs(w[t > 25]).max() < 0.05
    try:
        t, w = spin_up(2, False, 12.0)  # past L at 9.2 s, 1e41 m at 30 s
        assert np.abs(w).max() > L
    except eg.ModelError as failure:  # the integrator gave up as the deflection grew
        assert "integrator" in str(failure)


def test_a_column_buckles_under_its_own_weight_at_greenhills_load():
    """A uniform column clamped upright (the link's angle prescribed 0) under its own weight buckles at
    m g L³/EI = 7.8373 (Greenhill 1881; Timoshenko and Gere, Theory of Elastic Stability, §2.13): the
    lowest eigenvalue of the stiffness, bending plus gravity's foreshortening term, crosses zero there.
    Without stiffening gravity along the link does not enter the bending stiffness: no buckling."""
    G = sp.Symbol("G", positive=True)

    def column(stiffening: bool):
        system = eg.System(gravity=(-G, 0, 0))
        link = eg.FlexibleLink("beam", length=1, mass_per_length=1, EI=1, elements=8, stiffening=stiffening,
                               motion=0)
        system.add_body("beam", joint=link, mass=0)
        return eg.codegen(eg.derive(system)), system.nv

    def lowest(functions, g: float, h: float = 1e-6) -> float:
        f, n = functions
        zero = np.zeros(n)

        def force(x):
            return f.nle(x, zero, {"G": g}) - f.tau_of("elastic", x, zero, {"G": g})
        K = np.column_stack([(force(h * e) - force(-h * e)) / (2 * h) for e in np.eye(n)])
        return np.linalg.eigvalsh((K + K.T) / 2)[0]

    stiffened = column(True)
    assert brentq(lambda g: lowest(stiffened, g), 5, 10) == pytest.approx(7.8373, abs=3e-4)
    plain = column(False)
    assert lowest(plain, 20.0) == pytest.approx(lowest(plain, 1e-3), rel=1e-9)
    assert lowest(plain, 20.0) > 0
