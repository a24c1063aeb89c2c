"""The visual meshes of a URDF, for `eg.view`: Pinocchio's visual geometry model of the file the system
came from (`system.source`), each geometry on the body its joint moves, placed on the body's frame (the
Pinocchio joint frame, as `from_urdf` builds the bodies); `package://` paths are looked for in the
file's parent folders and in example-robot-data's share folder."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .errors import ModelError
from .model import System

LOADERS = {".stl": "StlMeshGeometry", ".obj": "ObjMeshGeometry", ".dae": "DaeMeshGeometry"}
TURN = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])  # meshcat's y axis onto z


def has_meshes(system: System) -> bool:
    """Whether the system was read from a URDF file (whose visual geometry `visuals` reads)."""
    source = getattr(system, "source", None)
    return source is not None and Path(source).suffix.lower() == ".urdf" and Path(source).is_file()


def visuals(system: System) -> list[tuple[str, np.ndarray, object, int | None]]:
    """(body name, 4 × 4 placement on the body's frame with the mesh scale, meshcat geometry, colour or
    None) of each visual geometry of the system's URDF."""
    import meshcat.geometry as mg
    import pinocchio as pin

    source = Path(system.source)
    model = pin.buildModelFromUrdf(str(source))
    try:
        geometry = pin.buildGeomFromUrdf(model, str(source), pin.GeometryType.VISUAL,
                                         package_dirs=_package_dirs(source))
    except Exception as exc:  # Pinocchio's RuntimeError / ValueError with the missing file's name
        raise ModelError(f"view: cannot read the visual meshes of {source}: {exc}; "
                         "view it with meshes=False") from None
    bodies = {b.joint.name: b.name for b in system.bodies}
    root = system.bodies[0].name  # the file's root link: fixed on the world, or on a free flyer
    out = []
    for g in geometry.geometryObjects:
        joint = model.names[g.parentJoint]
        body = root if g.parentJoint == 0 else bodies.get(joint)
        if body is None:
            raise ModelError(f"view: visual '{g.name}' of {source} moves with joint '{joint}', which the "
                             "system does not have; view it with meshes=False")
        shape, turn = _mesh(mg, g, source)
        X = g.placement.homogeneous @ np.diag([*np.asarray(g.meshScale, float), 1.0]) @ turn
        out.append((body, X, shape, _colour(g)))
    return out


def _package_dirs(source: Path) -> list[str]:
    """Where `package://name/...` may be: the file's parent folders, example-robot-data's share folder."""
    from .model.robots import robots_folder

    dirs = [str(p) for p in source.parents]
    try:
        dirs.append(str(robots_folder().parent.parent))
    except ModelError:  # example-robot-data not installed: the file's own folders only
        pass
    return dirs


def _mesh(mg, g, source: Path) -> tuple[object, np.ndarray]:
    """(meshcat geometry, transform onto the URDF's shape) of a Pinocchio geometry object: its mesh file,
    or its box, sphere or cylinder (hpp-fcl's along z, meshcat's along y: turned y → z)."""
    shape, path = g.geometry, Path(g.meshPath) if g.meshPath else None
    kind = type(shape).__name__
    if kind == "Box":
        return mg.Box(2 * np.asarray(shape.halfSide, float)), np.eye(4)
    if kind == "Sphere":
        return mg.Sphere(shape.radius), np.eye(4)
    if kind == "Cylinder":
        return mg.Cylinder(2 * shape.halfLength, shape.radius), TURN
    if path is None or path.suffix.lower() not in LOADERS:
        raise ModelError(f"view: visual '{g.name}' of {source} is a {kind} "
                         f"{'' if path is None else str(path)!r}; eomgen shows {sorted(LOADERS)} meshes, "
                         "boxes, spheres and cylinders (view it with meshes=False)")
    return getattr(mg, LOADERS[path.suffix.lower()]).from_file(str(path)), np.eye(4)


def _colour(g) -> int | None:
    """The URDF material's colour as 0xRRGGBB where the file gives one (a mesh's own colours else)."""
    if not g.overrideMaterial:
        return None
    r, gr, b = (int(round(255 * float(c))) for c in np.asarray(g.meshColor)[:3])
    return (r << 16) | (gr << 8) | b
