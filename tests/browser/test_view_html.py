"""eg.view's static pages opened in headless Chromium (Debian's /usr/bin/chromium, driven by Playwright):
they load with no console error and no network request, and meshcat's three.js scene holds the nodes
/eomgen/<body> of every body with their meshes (UR5) or primitives (cart-pendulum, played back)."""
import sys
from pathlib import Path

import numpy as np
import pytest

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parents[1]))
from models import cart_pendulum  # noqa: E402

pytestmark = pytest.mark.browser
CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader", "--enable-unsafe-swiftshader",
        "--disable-background-networking", "--disable-component-update", "--no-first-run", "--disable-sync"]
NODES = """() => {  // each node under /eomgen: its path and how many meshes and lines it holds
  const out = {};
  const walk = (o, path) => {
    out[path] = {meshes: 0, lines: 0};
    o.traverse(x => { if (x.isMesh) out[path].meshes++; if (x.isLineSegments) out[path].lines++; });
    o.children.forEach(c => c.name && walk(c, path + "/" + c.name));
  };
  walk(viewer.scene_tree.find(["eomgen"]).object, "/eomgen");
  return out;
}"""


def opened(page_path: Path) -> tuple[dict, list[str], list[str]]:
    """(nodes under /eomgen, console errors and page errors, URLs requested) of a page in Chromium."""
    from playwright.sync_api import sync_playwright

    assert Path(CHROMIUM).is_file(), f"{CHROMIUM} missing: apt-get install -y chromium"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 800, "height": 600})
        errors, requests = [], []
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.on("request", lambda r: requests.append(r.url))
        page.goto(page_path.as_uri(), wait_until="load")
        page.wait_for_function("() => typeof viewer !== 'undefined' && viewer.scene_tree.find(['eomgen'])")
        page.wait_for_timeout(1500)  # the meshes parsed, some frames drawn
        nodes = page.evaluate(NODES)
        browser.close()
    return nodes, errors, [u for u in requests if u != page_path.as_uri()]


def test_ur5_page_shows_its_meshes(tmp_path):
    system = eg.robots.load("ur5")
    eg.view(system, np.array([0.3, -1.0, 1.2, -0.4, 0.5, 0.7])).static_html(tmp_path / "ur5.html")
    nodes, errors, requests = opened(tmp_path / "ur5.html")
    assert errors == [] and requests == []
    for body in system.bodies:  # every link, with the mesh of its URDF visual
        assert nodes[f"/eomgen/{body.name}"]["meshes"] >= 1, body.name


def test_cart_pendulum_page_plays_back(tmp_path):
    system, (m_c, m_p, l, g) = cart_pendulum()
    params = {m_c: 1.0, m_p: 0.5, l: 0.8, g: 9.81}
    sim = eg.simulate(system, ([0.0, 1.0], [0.0, 0.0]), (0.0, 0.5), params=params,
                      t_eval=np.linspace(0.0, 0.5, 11))
    eg.view(sim).static_html(tmp_path / "cart_pendulum.html")
    nodes, errors, requests = opened(tmp_path / "cart_pendulum.html")
    assert errors == [] and requests == []
    assert nodes["/eomgen/cart/com"]["meshes"] == 1 and nodes["/eomgen/pendulum/com"]["meshes"] == 1
    assert nodes["/eomgen/pendulum/link_com"]["meshes"] == 1
    assert nodes["/eomgen/pendulum/frames/tip"]["lines"] == 1
