"""URDF fuzzing: small robots of example-robot-data, mutated (adversarial link and joint names, NaN,
infinite, negative, zero and huge masses, inertias and origins, changed joint types, a mimic
joint, dropped attributes). For each mutant `eg.from_urdf` either raises `eomgen.ModelError` (never
another exception) or gives M, b, g equal to Pinocchio's model of the same file; a file Pinocchio
rejects must be a ModelError. Bounded and derandomized; more examples under `pytest -m slow`."""
from __future__ import annotations

import importlib.metadata
import os
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, Phase, example, given, settings
from hypothesis import event
from hypothesis import strategies as st

import eomgen as eg
from eomgen.model.urdf import pinocchio_configuration
from strategies import name_strategy

ROBOTS = Path(str(importlib.metadata.distribution("example-robot-data").locate_file(
    "cmeel.prefix/share/example-robot-data/robots")))
FILES = {"ur5": "ur_description/urdf/ur5_robot.urdf", "panda": "panda_description/urdf/panda.urdf",
         "double_pendulum": "double_pendulum_description/urdf/double_pendulum.urdf",
         "asr_twodof": "asr_twodof_description/urdf/TwoDofs.urdf"}
SHRINK = [Phase.shrink] if os.environ.get("EOMGEN_SHRINK") else []
PHASES = [Phase.explicit, Phase.reuse, Phase.generate] + SHRINK
COMMON = dict(deadline=None, derandomize=True, database=None, print_blob=True, phases=PHASES,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much])

BAD_NUMBERS = ["nan", "NaN", "inf", "-inf", "-1", "-0.5", "0", "1e300", "1e-300", "-1e300", "abc", "", "1 2", "0x10",
               "1_0", "1 ", "1e", ".5", "5."]  # urdfdom drops the first three, reads the last two
JOINT_TYPES = ["revolute", "prismatic", "continuous", "fixed", "planar", "floating", "ball", ""]
ORIGINS = ["nan 0 0", "0 inf 0", "1e300 0 0", "1 2", "1 2 3 4", "a b c", "", "0.1 -0.2 0.3", "3.2 -1.5 7",
           "0.1\t0 0", "1_0 0 0", " 0.1  0 0 "]
AXES = ["0 0 0", "nan 0 1", "1 1 0", "0 0 -1", "1e-20 0 0", "1 0", "0 1 inf", "3 0 0"]
INERTIA_FIELDS = ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]


def source(robot: str) -> Path:
    return ROBOTS / FILES[robot]


# --- mutations: each is (kind, arguments), applied to the parsed XML ----------------------------
def mutations():
    index = st.integers(0, 1000)
    return st.one_of(
        st.tuples(st.just("rename_link"), index, name_strategy()),
        st.tuples(st.just("rename_joint"), index, name_strategy()),
        st.tuples(st.just("mass"), index, st.sampled_from(BAD_NUMBERS)),
        st.tuples(st.just("inertia"), index, st.sampled_from(INERTIA_FIELDS), st.sampled_from(BAD_NUMBERS + ["10", "-10"])),
        st.tuples(st.just("origin"), index, st.sampled_from(["joint", "inertial"]), st.sampled_from(["xyz", "rpy"]),
                  st.sampled_from(ORIGINS)),
        st.tuples(st.just("joint_type"), index, st.sampled_from(JOINT_TYPES)),
        st.tuples(st.just("axis"), index, st.sampled_from(AXES)),
        st.tuples(st.just("mimic"), index, index, st.sampled_from(["2", "-1", "nan", "0"])),
        st.tuples(st.just("drop"), index, st.sampled_from([("joint", "type"), ("joint", "name"), ("link", "name"),
                                                          ("mass", "value"), ("axis", "xyz"), ("parent", "link"),
                                                          ("child", "link"), ("inertia", "ixx"), ("origin", "xyz")])),
    )


def pick(items, i):
    return items[i % len(items)] if items else None


def mutate(root: ET.Element, mutation) -> str:
    """Apply one mutation; returns a description (the names and fields it touched)."""
    kind, i, *rest = mutation
    links, joints = root.findall("link"), root.findall("joint")
    if kind == "rename_link" and links:
        link, new = pick(links, i), rest[0]
        old = link.get("name")
        link.set("name", new)
        for j in joints:
            for tag in ("parent", "child"):
                e = j.find(tag)
                if e is not None and e.get("link") == old:
                    e.set("link", new)
        return f"link {old!r} renamed {new!r}"
    if kind == "rename_joint" and joints:
        joint, new = pick(joints, i), rest[0]
        old = joint.get("name")
        joint.set("name", new)
        for j in joints:
            m = j.find("mimic")
            if m is not None and m.get("joint") == old:
                m.set("joint", new)
        return f"joint {old!r} renamed {new!r}"
    if kind == "mass":
        masses = root.findall("link/inertial/mass")
        if masses:
            pick(masses, i).set("value", rest[0])
            return f"mass {rest[0]!r}"
    if kind == "inertia":
        inertias = root.findall("link/inertial/inertia")
        if inertias:
            pick(inertias, i).set(rest[0], rest[1])
            return f"inertia {rest[0]} = {rest[1]!r}"
    if kind == "origin":
        where, attr, value = rest
        owners = joints if where == "joint" else root.findall("link/inertial")
        if owners:
            owner = pick(owners, i)
            origin = owner.find("origin")
            if origin is None:
                origin = ET.SubElement(owner, "origin")
            origin.set(attr, value)
            return f"{where} origin {attr} = {value!r}"
    if kind == "joint_type" and joints:
        joint = pick(joints, i)
        joint.set("type", rest[0])
        if rest[0] in ("revolute", "prismatic") and joint.find("limit") is None:
            ET.SubElement(joint, "limit", lower="-3", upper="3", effort="10", velocity="1")
        return f"joint {joint.get('name')!r} type {rest[0]!r}"
    if kind == "axis" and joints:
        joint = pick(joints, i)
        axis = joint.find("axis")
        if axis is None:
            axis = ET.SubElement(joint, "axis")
        axis.set("xyz", rest[0])
        return f"joint {joint.get('name')!r} axis {rest[0]!r}"
    if kind == "mimic" and len(joints) > 1:
        joint, other = pick(joints, i), pick(joints, rest[0])
        if joint is not other:
            ET.SubElement(joint, "mimic", joint=other.get("name") or "", multiplier=rest[1], offset="0.1")
            return f"joint {joint.get('name')!r} mimics {other.get('name')!r}"
    if kind == "drop":
        tag, attr = rest[0]
        elements = [e for e in root.iter(tag) if attr in e.attrib]
        if elements:
            e = pick(elements, i)
            del e.attrib[attr]
            return f"dropped {tag} {attr}"
    return "no change"


# --- the property -------------------------------------------------------------------------------
def pinocchio_model(path: Path):
    """Pinocchio's model of the file, or None if Pinocchio rejects it."""
    try:
        return pin.buildModelFromUrdf(str(path), mimic=True)
    except Exception:
        return None


def check_mutant(robot: str, muts, folder: Path) -> str:
    """The outcome of importing a mutant (a ModelError naming the place, or equations equal to
    Pinocchio's); anything else fails."""
    tree = ET.parse(source(robot))
    root = tree.getroot()
    done = [mutate(root, m) for m in muts]
    path = folder / "mutant.urdf"
    tree.write(path, encoding="utf-8", xml_declaration=True)
    model = pinocchio_model(path)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            system = eg.from_urdf(path)
            eom = eg.derive(system, method="recursive")
            f = eg.codegen(eom)
    except eg.ModelError as exc:
        message = str(exc)
        assert any(w in message for w in ("joint", "link", "body", "mass", "inertia", "axis", "origin", "URDF",
                                          "placement", "com", "frame")), \
            f"{done}: the ModelError names no joint, link or field: {message!r}"
        return "ModelError" + (" (Pinocchio rejects the file)" if model is None else "")
    except Exception as exc:  # any other exception type is a failure
        raise AssertionError(f"{done}: {type(exc).__name__} instead of ModelError: {exc}") from exc
    assert model is not None, f"{done}: Pinocchio rejects the file, eomgen accepted it"
    assert system.nv == model.nv, f"{done}: nv {system.nv} != Pinocchio's {model.nv}"
    rng = np.random.default_rng(0)
    for k in range(3):
        q = rng.uniform(-np.pi, np.pi, system.nq)
        u = rng.uniform(-2, 2, system.nv)
        qp = pinocchio_configuration(system, q)
        data = model.createData()  # Pinocchio 4.1's crba is wrong with a reused Data below a mimic joint
        M = pin.crba(model, data, qp).reshape(model.nv, model.nv)
        M = np.triu(M) + np.triu(M, 1).T
        g = pin.computeGeneralizedGravity(model, data, qp).reshape(model.nv)
        b = pin.nonLinearEffects(model, data, qp, u).reshape(model.nv) - g
        for key, ours, ref in (("M", f.M(q), M), ("b", f.b(q, u), b), ("g", f.g(q), g)):
            assert np.all(np.isfinite(ref)), f"{done}: eomgen accepted a model with a non-finite Pinocchio {key}"
            assert np.all(np.isfinite(ours)), f"{done}: {key} not finite: {ours}"
            scale = max(1.0, np.abs(ref).max())
            np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-9 * scale,
                                       err_msg=f"{done}: {key}, state {k}")
    return "loaded, compared with Pinocchio"


@settings(max_examples=40, **COMMON)
@given(robot=st.sampled_from(sorted(FILES)), muts=st.lists(mutations(), min_size=1, max_size=3))
@example(robot="double_pendulum", muts=[("joint_type", 1, "continuous"), ("axis", 1, "0.6 0.8 0")])
@example(robot="ur5", muts=[("joint_type", 2, "continuous")])
@example(robot="panda", muts=[("joint_type", 3, "planar")])
@example(robot="ur5", muts=[("mass", 3, "-1")])
@example(robot="ur5", muts=[("inertia", 3, "ixy", "10")])
def test_mutated_urdf(robot, muts, tmp_path_factory):
    event(check_mutant(robot, muts, tmp_path_factory.mktemp("urdf")))  # counted in hypothesis' statistics


@pytest.mark.slow
@settings(max_examples=2000, **COMMON)
@given(robot=st.sampled_from(sorted(FILES)), muts=st.lists(mutations(), min_size=1, max_size=4))
def test_mutated_urdf_many(robot, muts, tmp_path_factory):
    event(check_mutant(robot, muts, tmp_path_factory.mktemp("urdf")))


@pytest.mark.parametrize("robot", sorted(FILES))
def test_unmutated_files_load(robot, tmp_path):
    """The sources themselves load and equal Pinocchio (the fuzzing starts from working files)."""
    assert check_mutant(robot, [], tmp_path) == "loaded, compared with Pinocchio"
