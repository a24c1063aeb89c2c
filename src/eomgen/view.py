"""`eg.view`: a system, or a simulation played back, in 3D (meshcat's three.js viewer) as one
self-contained HTML page: meshcat's JavaScript (from its wheel) and the scene's commands (msgpack,
base64) inline; no server, no browser opened, nothing fetched.

The scene: /eomgen turns the world so that gravity points down the screen (meshcat's −z); under it,
/eomgen/<body> is each body's frame, placed by the generated placements (`f.placement`), holding the
URDF's visual meshes where the system came from a URDF file that has them (`view_meshes`), else
primitives: a sphere at the centre of mass of radius 0.06 L (m / m_max)^⅓ (L the system's size) and a
cylinder from the body's joint to each child's joint (a leaf: to its centre of mass). Named frames are
triads (x red, y green, z blue), contact points red spheres. A simulation has one keyframe per state,
at its times (three.js interpolates between them)."""
from __future__ import annotations

import base64
import html
from pathlib import Path

import numpy as np
import sympy as sp

from .animation import placements, simulation_parameters
from .errors import ModelError
from .model import System
from .simulate import Simulation
from .view_meshes import has_meshes, visuals

COLOURS = {"com": 0xE07020, "link": 0x4477AA, "contact": 0xDD2222, "mesh": 0xC8C8C8}
PAGE = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>{title}</title>
<style>body {{margin: 0}} #meshcat-pane {{width: 100vw; height: 100vh; overflow: hidden}}</style></head>
<body><div id="meshcat-pane"></div>
<script>{viewer}</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
[{commands}].forEach(function (data) {{
  viewer.handle_command_bytearray(Uint8Array.from(atob(data), function (c) {{ return c.charCodeAt(0); }}));
}});
</script></body></html>
"""


class View:
    """A meshcat scene: `commands` (lowered, in order), `paths` of the bodies' nodes; `static_html(path)`
    writes the page, a notebook shows it in an iframe."""

    def __init__(self, commands: list[dict], paths: dict[str, str], title: str, height: int) -> None:
        self.commands, self.paths, self.title, self.height = commands, paths, title, height

    def html(self) -> str:
        """The self-contained page."""
        import umsgpack

        import meshcat

        viewer = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
        data = ",\n".join(f'"{base64.b64encode(umsgpack.packb(c)).decode()}"' for c in self.commands)
        return PAGE.format(title=html.escape(self.title), viewer=viewer.read_text(), commands=data)

    def static_html(self, path=None) -> str:
        """The page, written to `path` when given."""
        page = self.html()
        if path is not None:
            Path(path).write_text(page, encoding="utf-8")
        return page

    def _repr_html_(self) -> str:
        return (f'<iframe srcdoc="{html.escape(self.html(), quote=True)}" style="width: 100%; '
                f'height: {self.height}px; border: none"></iframe>')


def view(source, q=None, *, simulation: Simulation | None = None, params: dict | None = None,
         frames=None, meshes: bool | None = None, fps: float = 30.0, height: int = 480) -> View:
    """The 3D view of a System at q (default: zero, unit quaternions) or of a Simulation played back (also
    `view(system, simulation=sim)`); `frames`: the named frames (or bodies) marked (default all);
    `meshes`: the URDF's visual meshes (default: where the system came from a URDF file), else
    primitives; `params`: values of the symbolic parameters (a simulation's own by default)."""
    if isinstance(source, Simulation):
        if simulation is not None:
            raise ModelError("view: give the simulation as the source or as simulation=, not both")
        source, simulation = source.functions.system, source
    if not isinstance(source, System):
        raise ModelError(f"view: expected a System or a Simulation (eg.simulate), "
                         f"got {type(source).__name__}")
    system = source
    if simulation is not None:
        Q, times = _played(system, simulation, q)
        f = placements(simulation.functions)
        given = simulation_parameters(f, simulation)
        values = {**{str(k): v for k, v in given.items()}, **_names(params)}
    else:
        Q, times, f, values = _pose(system, q), None, placements(system), _names(params)
    marked = _frames(system, frames)
    if meshes and not has_meshes(system):
        raise ModelError("view: meshes=True needs a system read from a URDF file (eg.from_urdf, eg.robots); "
                         f"this one has source {getattr(system, 'source', None)!r}")
    meshcat = _meshcat()
    X = _placements(system, f, Q, {k: v for k, v in values.items() if k in f.parameters.names})
    scene = _Scene(meshcat, system, values, X)
    if has_meshes(system) if meshes is None else meshes:
        scene.meshes()
    else:
        scene.primitives()
    scene.marks(marked)
    if times is not None:
        scene.play(times, fps)
    return View(scene.commands, scene.paths, getattr(system, "name", None) or "eomgen", height)


def _meshcat():
    """The meshcat package, or an error naming the extra that installs it."""
    try:
        import meshcat.animation
        import meshcat.commands
        import meshcat.geometry
    except ImportError:
        raise ModelError("eg.view needs meshcat: pip install 'eomgen[view]'") from None
    return meshcat


def _names(params) -> dict[str, float]:
    """params by symbol name."""
    if params is None:
        return {}
    if not isinstance(params, dict):
        raise ModelError(f"view: params must be a dict of parameter values, got {type(params).__name__}")
    return {str(k): v for k, v in params.items()}


def _played(system: System, simulation: Simulation, q) -> tuple[np.ndarray, np.ndarray]:
    """(q (N, nq), t (N,)) of a simulation of this system."""
    if not isinstance(simulation, Simulation):
        raise ModelError(f"view: simulation must be an eg.simulate result, got {type(simulation).__name__}")
    if q is not None:
        raise ModelError("view: give q or a simulation, not both")
    other = simulation.functions.system
    if other is not system and ([b.name for b in other.bodies] != [b.name for b in system.bodies]
                                or list(other.q) != list(system.q)):
        raise ModelError(f"view: simulation is of another system (bodies {[b.name for b in other.bodies]}, "
                         f"q {list(other.q)}), not of this one (bodies {[b.name for b in system.bodies]})")
    return simulation.q, simulation.t


def _pose(system: System, q) -> np.ndarray:
    """q as one state (1, nq); default zero with unit quaternions (w = 1)."""
    if q is None:
        q = np.zeros(system.nq)
        for b in system.bodies:
            if b.q_index is not None and b.joint.group in ("SO3", "SE3"):
                q[b.q_index + 3 + 3 * (b.joint.group == "SE3")] = 1.0
    q = np.asarray(q, dtype=float)
    if q.shape != (system.nq,) or not np.all(np.isfinite(q)):
        raise ModelError(f"view: q must be {system.nq} finite numbers ({', '.join(map(str, system.q))}), "
                         f"got shape {q.shape}")
    return q[None]


def _frames(system: System, frames) -> list[str]:
    """The frames to mark: all named frames by default, else the given names (frames or bodies)."""
    if frames is None:
        return list(system.frames)
    if isinstance(frames, str):
        frames = [frames]
    bodies = {b.name for b in system.bodies}
    for name in frames:
        if name not in system.frames and name not in bodies:
            raise ModelError(f"view: unknown frame {name!r} in frames; frames are {sorted(system.frames)}, "
                             f"bodies {sorted(bodies)}")
    return list(frames)


def _placements(system: System, f, Q: np.ndarray, params: dict) -> dict[str, np.ndarray]:
    """Each body's placement in the world at the states Q: 4 × 4 matrices (N, 4, 4)."""
    out = {}
    for b in system.bodies:
        R, p = f.placement(b.name, Q, params or None)
        X = np.zeros((len(Q), 4, 4))
        X[:, :3, :3], X[:, :3, 3], X[:, 3, 3] = R, p, 1.0
        out[b.name] = X
    return out


def _numbers(expr, values: dict, what: str) -> np.ndarray:
    """A model quantity as numbers, its symbols given by name in `values`."""
    expr = sp.Matrix(expr) if isinstance(expr, sp.MatrixBase) else sp.sympify(expr)
    missing = sorted(str(s) for s in expr.free_symbols if str(s) not in values)
    if missing:
        raise ModelError(f"view: {what} needs values for {missing}; give them in params")
    return np.array(expr.subs({s: values[str(s)] for s in expr.free_symbols}), dtype=float)


def _homogeneous(R, p) -> np.ndarray:
    X = np.eye(4)
    X[:3, :3], X[:3, 3] = R, np.ravel(p)
    return X


class _Scene:
    """The meshcat commands of a scene, built up in order."""

    def __init__(self, meshcat, system: System, values: dict, X: dict[str, np.ndarray]) -> None:
        self.mc, self.system, self.values, self.X = meshcat, system, values, X
        self.commands: list[dict] = []
        self.paths = {b: f"/eomgen/{b}" for b in X}
        points = [X[b.name][0] @ [*_numbers(b.com, values, f"body '{b.name}': com").ravel(), 1.0]
                  for b in system.bodies]  # the centres of mass in the world, at the first state
        size = float(np.ptp(np.array(points)[:, :3], axis=0).max()) if points else 0.0
        self.L = size if size > 1e-9 else 1.0
        down = _downward(_numbers(system.gravity, values, "gravity"))
        self._set_transform("/eomgen", _homogeneous(down, 0))
        for b, x in X.items():
            self._set_transform(self.paths[b], x[0])
        camera = self._path("/Cameras/default/rotated/<object>")  # three.js axes: y up
        eye = [1.2 * self.L, 0.8 * self.L, 1.2 * self.L]
        self.commands.append(self.mc.commands.SetProperty("position", eye, camera).lower())

    def _path(self, path: str):
        return self.mc.path.Path(tuple(path.strip("/").split("/")))

    def _set_object(self, path: str, geometry, colour: int | None = None) -> None:
        g = self.mc.geometry
        material = None if isinstance(geometry, g.Object) else \
            g.MeshLambertMaterial(color=COLOURS["mesh"] if colour is None else colour)
        command = self.mc.commands.SetObject(geometry, material, path=self._path(path))
        lowered = command.lower()
        for shape in lowered["object"].get("geometries", []):  # the viewer's name for a mesh file's
            shape["type"] = "_meshfile_geometry" if shape["type"] == "_meshfile" else shape["type"]
        self.commands.append(lowered)

    def _set_transform(self, path: str, X: np.ndarray) -> None:
        self.commands.append(self.mc.commands.SetTransform(X, self._path(path)).lower())

    def meshes(self) -> None:
        """The URDF's visual meshes on their bodies."""
        for k, (body, X, shape, colour) in enumerate(visuals(self.system)):
            path = f"{self.paths[body]}/visual_{k}"
            self._set_object(path, shape, colour)
            self._set_transform(path, X)

    def primitives(self) -> None:
        """A sphere at each centre of mass (volume ∝ mass), a cylinder along each link."""
        g, bodies = self.mc.geometry, self.system.bodies
        masses = {b.name: float(_numbers(b.mass, self.values, f"body '{b.name}': mass")) for b in bodies}
        heaviest = max([*masses.values(), 0.0])
        for b in bodies:
            com = _numbers(b.com, self.values, f"body '{b.name}': com").ravel()
            ends = [(c.name, _numbers(c.placement.translation, self.values, f"body '{c.name}': placement"))
                    for c in bodies if c.parent is b]
            for name, end in ends or [("com", com)]:
                self._cylinder(f"{self.paths[b.name]}/link_{name}", end.ravel())
            if masses[b.name] > 0:
                r = 0.06 * self.L * (masses[b.name] / heaviest) ** (1 / 3)
                self._set_object(f"{self.paths[b.name]}/com", g.Sphere(r), COLOURS["com"])
                self._set_transform(f"{self.paths[b.name]}/com", _homogeneous(np.eye(3), com))

    def _cylinder(self, path: str, end: np.ndarray) -> None:
        """A cylinder from the body's origin to `end` (body frame); none where they meet."""
        length = float(np.linalg.norm(end))
        if length < 1e-9 * self.L:
            return
        self._set_object(path, self.mc.geometry.Cylinder(length, 0.015 * self.L), COLOURS["link"])
        self._set_transform(path, _homogeneous(_turning(np.array([0, 1.0, 0]), end / length), end / 2))

    def marks(self, frames: list[str]) -> None:
        """Triads at the named frames, red spheres at the contact points."""
        for name in frames:
            body, X = self._on_body(name)
            path = f"{self.paths[body]}/frames/{name}" if body else f"/eomgen/frames/{name}"
            self._set_object(path, self.mc.geometry.triad(0.08 * self.L))
            self._set_transform(path, X)
        for c in self.system.contacts:
            body, X = self._on_body(c.frame)
            path = f"{self.paths[body]}/contacts/{c.frame}" if body else f"/eomgen/contacts/{c.frame}"
            self._set_object(path, self.mc.geometry.Sphere(0.025 * self.L), COLOURS["contact"])
            self._set_transform(path, X)

    def _on_body(self, name: str) -> tuple[str | None, np.ndarray]:
        """(body or None for the world, placement on it) of a named frame or a body's own frame."""
        if name not in self.system.frames:
            return name, np.eye(4)
        frame = self.system.frames[name]
        R = _numbers(frame.placement.rotation, self.values, f"frame '{name}': placement")
        p = _numbers(frame.placement.translation, self.values, f"frame '{name}': placement")
        return (frame.body.name if frame.body else None), _homogeneous(R, p)

    def play(self, times: np.ndarray, fps: float) -> None:
        """One keyframe per state at (t − t0) · fps frames."""
        if not fps > 0:
            raise ModelError(f"view: fps must be positive, got {fps!r}")
        A = self.mc.animation
        animation = A.Animation(default_framerate=fps)
        for b, X in self.X.items():
            for t, x in zip(times, X):
                A.AnimationFrameVisualizer(animation, self._path(self.paths[b]), float((t - times[0]) * fps)
                                           ).set_transform(x)
        self.commands.append(self.mc.commands.SetAnimation(animation).lower())


def _turning(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The rotation of least angle taking the unit vector a onto the unit vector b (Rodrigues)."""
    v, c = np.cross(a, b), float(a @ b)
    if c < -1 + 1e-12:  # opposite: half a turn about an axis normal to a
        n = np.cross(a, [1.0, 0, 0] if abs(a[0]) < 0.9 else [0, 1.0, 0])
        n /= np.linalg.norm(n)
        return 2 * np.outer(n, n) - np.eye(3)
    V = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + V + V @ V / (1 + c)


def _downward(gravity: np.ndarray) -> np.ndarray:
    """The turn of the world that puts gravity on meshcat's −z (none without gravity)."""
    g = np.ravel(gravity)
    n = np.linalg.norm(g)
    return np.eye(3) if n == 0 else _turning(g / n, np.array([0, 0, -1.0]))
