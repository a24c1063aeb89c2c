"""eg.plot and eg.animate, headless: the figure's curves are the simulation's; the animation's first frame
is drawn at the placements of the bodies and frames (2D in the plane of a planar motion, 3D otherwise);
a GIF has the frames asked for, an MP4 is written; Kane's equations are animated from their system."""

import numpy as np
import pytest
import sympy as sp
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d import Axes3D
from PIL import Image

import eomgen as eg
import kane_systems as K
from eomgen.animation import plane
from models import double_pendulum


@pytest.fixture(scope="module")
def swing():
    f = eg.codegen(eg.derive(double_pendulum(numeric=True)))
    return f, eg.simulate(
        f,
        ([0.3, -0.5], [0.0, 1.0]),
        (0, 1),
        controller=lambda t, q, u: [0.2, -0.1 * u[1]],
        t_eval=np.linspace(0, 1, 41),
    )


def test_plot(swing, tmp_path):
    """Rows q, u, τ_a and the energy: their curves are the simulation's, the balance on the right axis."""
    _, sim = swing
    fig = eg.plot(sim, tmp_path / "swing.png")
    assert isinstance(fig, Figure) and (tmp_path / "swing.png").stat().st_size > 10_000
    q_axes, u_axes, tau_axes, energy, balance = fig.axes
    for ax, values in ((q_axes, sim.q), (u_axes, sim.u), (tau_axes, sim.tau)):
        for line, column in zip(ax.lines, values.T):
            np.testing.assert_array_equal(line.get_ydata(), column)
    assert [line.get_label() for line in q_axes.lines] == ["q_1", "q_2"]
    np.testing.assert_array_equal(energy.lines[1].get_ydata(), sim.work)
    np.testing.assert_array_equal(balance.lines[0].get_ydata(), sim.balance)


def test_gif_of_a_planar_motion(swing, tmp_path):
    """2D (the plane x, y); the first frame's lines run from the upper link's origin to the lower's and on to
    the tip, at the placements f.placement("lower"), f.placement("tip") of q(t0); 8 GIF frames."""
    f, sim = swing
    anim = eg.animate(sim, path=tmp_path / "swing.gif", frames=8)
    ax = anim._fig.axes[0]
    assert not isinstance(ax, Axes3D) and (ax.get_xlabel(), ax.get_ylabel()) == ("x", "y")
    lower, tip = (f.placement(name, sim.q[0])[1] for name in ("lower", "tip"))
    segments = {tuple(np.round(np.ravel(line.get_xydata()), 12)) for line in ax.lines[:2]}
    assert segments == {
        tuple(np.round([0, 0, *lower[:2]], 12)),
        tuple(np.round([*lower[:2], *tip[:2]], 12)),
    }
    with Image.open(tmp_path / "swing.gif") as gif:
        assert gif.n_frames == 8


def spherical_pendulum() -> eg.System:
    system = eg.System(gravity=(0, 0, -9.81))
    bob = system.add_body(
        "bob", joint=eg.Spherical("s"), mass=1.0, com=(0, 0, -0.5), inertia=sp.eye(3) * 0.01
    )
    system.add_frame("tip", body=bob, placement=eg.Placement(translation=(0, 0, -0.6)))
    return system


def test_mp4_of_a_spatial_motion(tmp_path):
    """A spherical pendulum swinging around: 3D, the first frame's line from the pivot to the tip frame at
    its placement; the MP4 written."""
    system = spherical_pendulum()
    f = eg.codegen(eg.derive(system))
    q0 = np.r_[np.sin(0.3), 0, 0, np.cos(0.3)]  # tilted 0.6 rad about x
    sim = eg.simulate(f, (q0, [0, 2.0, 0]), (0, 1))
    anim = eg.animate(sim, system, path=tmp_path / "bob.mp4", frames=6)
    ax = anim._fig.axes[0]
    assert isinstance(ax, Axes3D)
    np.testing.assert_allclose(
        np.array(ax.lines[0].get_data_3d()).T, [[0, 0, 0], f.placement("tip", q0)[1]], atol=1e-13
    )
    assert (tmp_path / "bob.mp4").stat().st_size > 1000


def test_kane_rolling_disk(tmp_path):
    """Kane's equations have no placements: the system's are generated; the disk's dot is at (x, y, R);
    for a notebook, the animation as HTML with its 3 frames."""
    system, args = K.rolling_disk()
    values = {"m": 1.3, "R": 0.3, "g": 9.81}
    sim = eg.simulate(eg.kane(system, **args), ([0, 0, 0, 0], [0.5, 3.0]), (0, 0.5), params=values)
    anim = eg.animate(sim, frames=3)
    dots = anim._fig.axes[0].lines[-2].get_data_3d()
    np.testing.assert_allclose(np.array(dots)[:, -1], [0, 0, 0.3], atol=1e-14)
    assert anim.to_jshtml().count("data:image/png;base64") == 3


def test_plane():
    """A world plane where the points lie in one, else the two principal directions; None in 3D."""
    rng = np.random.default_rng(9)
    B, labels = plane(np.c_[rng.normal(size=(20, 2)), np.full(20, 0.4)][:, [0, 2, 1]])
    assert labels == ["x", "z"] and np.array_equal(B, np.eye(3)[:, [0, 2]])
    tilted = rng.normal(size=(20, 2)) @ np.array([[1, 0, 0], [0, 0.6, 0.8]])
    B, labels = plane(tilted)
    assert (
        labels == ["e1", "e2"] and np.allclose(B.T @ B, np.eye(2)) and np.allclose(B.T @ [0, 0.8, -0.6], 0)
    )
    assert plane(rng.normal(size=(20, 3))) is None


def test_refused(swing, tmp_path):
    _, sim = swing
    with pytest.raises(eg.ModelError, match=r"path must end in \['.gif', '.mp4'\]"):
        eg.animate(sim, path=tmp_path / "swing.avi")
    with pytest.raises(eg.ModelError, match="frames must be a positive integer"):
        eg.animate(sim, frames=0)
    with pytest.raises(eg.ModelError, match="the functions have 4 coordinates, the simulation 2"):
        eg.animate(sim, spherical_pendulum())
    with pytest.raises(eg.ModelError, match="plot: expected a Simulation"):
        eg.plot(sim.q)
