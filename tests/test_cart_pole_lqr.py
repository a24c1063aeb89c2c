"""examples/cart_pole_lqr.py: the linearization about the upright equals the hand derivation of the example's
docstring (Lagrange's equations written out), and the LQR designed on it brings the nonlinear cart-pole back
upright from a 0.3 rad tilt with the energy balance E − E0 − W held; the plot and the GIF are written."""
import sys
from pathlib import Path

import numpy as np
from PIL import Image

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
import cart_pole_lqr as example  # noqa: E402


def test_lqr_balances_the_cart_pole(tmp_path):
    f, L, K, sim = example.balance(tilt=0.3, duration=6.0)
    A, B = example.by_hand()
    np.testing.assert_allclose(L.A, A, atol=1e-13)
    np.testing.assert_allclose(L.B, B, atol=1e-13)
    assert L.states == ("x", "phi", "xdot", "phidot") and L.inputs == ("tau_x",)
    assert np.all(np.linalg.eigvals(A - B @ K).real < 0)
    assert abs(sim.q[0, 1] - 0.3) < 1e-12
    assert np.abs(sim.q[-1]).max() < 5e-3 and np.abs(sim.u[-1]).max() < 5e-3
    m_p, g, l = (example.VALUES[k] for k in ("m_p", "g", "l"))
    lifted = m_p * g * l * (1 - np.cos(0.3))  # the pole's potential energy regained, by hand
    assert abs(sim.energy[-1] - sim.energy[0] - lifted) < 1e-3 * lifted + np.abs(sim.u[-1]).max()
    assert np.abs(sim.balance).max() < 1e-8
    eg.plot(sim).savefig(tmp_path / "cart_pole.png")
    eg.animate(sim, f, path=tmp_path / "cart_pole.gif", frames=6)
    assert Image.open(tmp_path / "cart_pole.gif").n_frames == 6
    assert (tmp_path / "cart_pole.png").stat().st_size > 0
