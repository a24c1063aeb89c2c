"""The pose of an MJCF element from its attributes, as MuJoCo reads it: `pos`, and one of `quat` (w x y z,
normalized), `axisangle` (axis, angle), `euler` (angles about the axes of `<compiler eulerseq>`, lower
case: rotating with the frame), `xyaxes` (x, then y made orthogonal to it), `zaxis` (the shortest turn
of e_z onto it); angles in `<compiler angle>` units (degrees unless "radian"). For the sites that
Pinocchio's parser drops: those on `<worldbody>` and on a root body welded to the world."""
from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..errors import ModelError


def _unit(v, where: str) -> np.ndarray:
    n = np.linalg.norm(v)
    if not n > 1e-12:
        raise ModelError(f"{where}: a zero vector where MuJoCo needs a direction")
    return np.asarray(v, float) / n


COUNTS = {"pos": 3, "quat": 4, "axisangle": 4, "euler": 3, "xyaxes": 6, "zaxis": 3}


def _values(attribute: Callable, name: str, where: str) -> list[float] | None:
    """Attribute `name` as its COUNTS[name] finite numbers (None if absent)."""
    text = attribute(name)
    if text is None:
        return None
    try:
        values = [float(x) for x in text.split()]
    except ValueError:
        values = []
    if len(values) != COUNTS[name] or not np.isfinite(values).all():
        raise ModelError(f"{where}: {name}={text!r} must be {COUNTS[name]} finite numbers")
    return values


def pose(attribute: Callable[[str], str | None], compiler: dict[str, str], where: str
         ) -> tuple[np.ndarray, np.ndarray]:
    """(R, p) in its body's frame of an element with these attributes (`attribute(name)`: its text or
    None)."""
    from scipy.spatial.transform import Rotation

    if attribute("fromto") is not None:
        raise ModelError(f"{where}: fromto on a site welded to the world is not read (give pos and an "
                         "orientation)")
    degree = np.pi / 180 if compiler.get("angle", "degree") == "degree" else 1.0
    p = np.array(_values(attribute, "pos", where) or [0.0] * 3)
    R = np.eye(3)
    if (q := _values(attribute, "quat", where)) is not None:
        w, x, y, z = _unit(q, where)
        R = Rotation.from_quat([x, y, z, w]).as_matrix()
    elif (a := _values(attribute, "axisangle", where)) is not None:
        R = Rotation.from_rotvec(_unit(a[:3], where) * a[3] * degree).as_matrix()
    elif (e := _values(attribute, "euler", where)) is not None:
        R = Rotation.from_euler(compiler.get("eulerseq", "xyz").upper(), np.multiply(e, degree)).as_matrix()
    elif (xy := _values(attribute, "xyaxes", where)) is not None:
        x = _unit(xy[:3], where)
        y = _unit(np.subtract(xy[3:], x * np.dot(x, xy[3:])), where)
        R = np.column_stack([x, y, np.cross(x, y)])
    elif (z := _values(attribute, "zaxis", where)) is not None:
        z = _unit(z, where)
        turn = np.cross([0, 0, 1], z)
        if np.linalg.norm(turn) < 1e-12:  # e_z or −e_z: MuJoCo turns by π about x for the latter
            R = np.diag([1.0, np.sign(z[2]), np.sign(z[2])])
        else:
            R = Rotation.from_rotvec(_unit(turn, where) * np.arctan2(np.linalg.norm(turn), z[2])).as_matrix()
    return R, p
