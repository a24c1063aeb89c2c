"""eg.view: the scene of its static page (decoded from the page itself) against Pinocchio's placements of
the UR5's links and visual meshes, and against the cart-pendulum's closed-form positions; the page
self-contained; refusals at the arguments."""
import base64
import html
import re
import sys

import numpy as np
import pinocchio as pin
import pytest
import umsgpack

import eomgen as eg
from eomgen.model.robots import paths
from models import cart_pendulum

Q_UR5 = np.array([0.3, -1.0, 1.2, -0.4, 0.5, 0.7])


def scene(page: str) -> list[dict]:
    """The meshcat commands the page hands to its viewer (base64 msgpack strings)."""
    data = re.search(r"\[(\"[A-Za-z0-9+/=]+\"(?:,\s*\"[A-Za-z0-9+/=]+\")*)\]\.forEach", page).group(1)
    return [umsgpack.unpackb(base64.b64decode(s)) for s in re.findall(r"\"([^\"]+)\"", data)]


def transforms(commands: list[dict]) -> dict[str, np.ndarray]:
    return {c["path"]: np.array(c["matrix"]).reshape(4, 4).T
            for c in commands if c["type"] == "set_transform"}


@pytest.fixture(scope="module")
def ur5_page() -> str:
    return eg.view(eg.robots.load("ur5"), Q_UR5).static_html()


@pytest.fixture(scope="module")
def pendulum():
    system, (m_c, m_p, l, g) = cart_pendulum()
    params = {m_c: 1.0, m_p: 0.5, l: 0.8, g: 9.81}
    sim = eg.simulate(system, ([0.1, 1.0], [0.0, 0.0]), (0.0, 0.5), params=params,
                      t_eval=np.linspace(0.0, 0.5, 11))
    return system, sim


def test_page_fetches_nothing(ur5_page, pendulum, tmp_path):
    for page in (ur5_page, eg.view(pendulum[1]).static_html(tmp_path / "motion.html")):
        assert not re.search(r"<script[^>]*\ssrc\s*=", page, re.I)
        assert not re.search(r"<link[^>]*\shref\s*=\s*[\"']?https?:", page, re.I)
        assert not re.search(r"(fetch|import|url)\s*\(\s*[\"']https?:", page, re.I)
    assert (tmp_path / "motion.html").read_text(encoding="utf-8").startswith("<!DOCTYPE html>")


def test_ur5_links_and_meshes_where_pinocchio_puts_them(ur5_page):
    urdf = str(paths("ur5")[0])
    model = pin.buildModelFromUrdf(urdf)
    visual = pin.buildGeomFromUrdf(model, urdf, pin.GeometryType.VISUAL, package_dirs=[
        str(p) for p in paths("ur5")[0].parents])
    data, gdata = model.createData(), visual.createData()
    pin.forwardKinematics(model, data, Q_UR5)
    pin.updateGeometryPlacements(model, data, visual, gdata)
    commands = scene(ur5_page)
    X = transforms(commands)
    world = X["/eomgen"]
    for i in range(1, model.njoints):  # each link's frame: Pinocchio's joint placement
        body = next(b.name for b in eg.robots.load("ur5").bodies if b.joint.name == model.names[i])
        np.testing.assert_allclose(world @ X[f"/eomgen/{body}"], data.oMi[i].homogeneous, atol=1e-12)
    objects = {c["path"]: c for c in commands if c["type"] == "set_object"}
    meshes = sorted(p for p in objects if "/visual_" in p)
    assert len(meshes) == len(visual.geometryObjects)
    for path in meshes:  # each mesh where Pinocchio places it, from the file it names
        k = int(path.rsplit("_", 1)[1])
        parent = path.rsplit("/", 1)[0]
        np.testing.assert_allclose(world @ X[parent] @ X[path], gdata.oMg[k].homogeneous, atol=1e-12)
        shape = objects[path]["object"]["geometries"][0]
        assert shape["format"] == "dae"
        with open(visual.geometryObjects[k].meshPath) as f:
            assert shape["data"] == f.read()


def test_pendulum_played_back_at_the_simulation_times(pendulum):
    system, sim = pendulum
    commands = scene(eg.view(sim, fps=20.0).static_html())
    X = transforms(commands)
    paths_ = {c["path"] for c in commands}
    assert {"/eomgen/cart/com", "/eomgen/pendulum/com", "/eomgen/pendulum/link_com",
            "/eomgen/pendulum/frames/tip"} <= paths_
    played = next(c for c in commands if c["type"] == "set_animation")
    clips = {a["path"]: a["clip"] for a in played["animations"]}
    assert set(clips) == {"/eomgen/cart", "/eomgen/pendulum"}
    down = X["/eomgen"]  # gravity (0, -g, 0) shown along -z
    np.testing.assert_allclose(down[:3, :3] @ [0, -1, 0], [0, 0, -1], atol=1e-15)
    tracks = {t["name"]: t["keys"] for t in clips["/eomgen/pendulum"]["tracks"]}
    np.testing.assert_allclose([k["time"] for k in tracks[".position"]], 20.0 * sim.t, atol=1e-12)
    com = X["/eomgen/pendulum/com"][:3, 3]
    for key_p, key_q, (x, phi) in zip(tracks[".position"], tracks[".quaternion"], sim.q):
        qx, qy, qz, qw = key_q["value"]
        R = pin.Quaternion(qw, qx, qy, qz).toRotationMatrix()
        closed_form = [x + 0.8 * np.sin(phi), -0.8 * np.cos(phi), 0.0]  # the bob, l from the cart
        np.testing.assert_allclose(R @ com + key_p["value"], closed_form, atol=1e-12)


def test_repr_html_is_the_page_in_an_iframe(pendulum):
    v = eg.view(pendulum[1])
    frame = re.fullmatch(r'<iframe srcdoc="([^"]*)" style="[^"]*"></iframe>', v._repr_html_())
    assert html.unescape(frame.group(1)) == v.static_html()


def test_refusals(pendulum):
    system, sim = pendulum
    params = sim.params
    with pytest.raises(eg.ModelError, match="unknown frame 'tipp' in frames"):
        eg.view(system, params=params, frames=["tipp"])
    other, _ = cart_pendulum()
    other.add_body("extra", parent="pendulum", joint=eg.Revolute("psi"), mass=1)
    with pytest.raises(eg.ModelError, match="simulation is of another system"):
        eg.view(other, simulation=sim)
    with pytest.raises(eg.ModelError, match=r"q must be 2 finite numbers \(x, phi\), got shape \(3,\)"):
        eg.view(system, [0, 0, 0], params=params)
    with pytest.raises(eg.ModelError, match="meshes=True needs a system read from a URDF file"):
        eg.view(system, params=params, meshes=True)
    with pytest.raises(eg.ModelError, match="expected a System or a Simulation"):
        eg.view(sim.functions)
    with pytest.raises(eg.ModelError, match="give q or a simulation, not both"):
        eg.view(system, [0, 0], simulation=sim)
    with pytest.raises(eg.ModelError, match="fps must be positive"):
        eg.view(sim, fps=0)
    with pytest.raises(eg.ModelError, match=r"body 'pendulum': com needs values for \['l'\]"):
        eg.view(system, params={"m_c": 1, "m_p": 1, "g": 1})


def test_missing_meshcat_names_the_extra(pendulum, monkeypatch):
    monkeypatch.setitem(sys.modules, "meshcat", None)
    with pytest.raises(eg.ModelError, match=r"pip install 'eomgen\[view\]'"):
        eg.view(pendulum[1])
