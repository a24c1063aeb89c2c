"""The URDF pre-check reads numbers exactly as urdfdom does: for each form of a number (single values:
mass, ixx; vectors: inertial and joint origins, axis) urdfdom either keeps it (Pinocchio's model holds
the value, nothing on stderr) and eomgen imports it and verifies against Pinocchio, or urdfdom drops
or refuses it (an error on stderr, a massless link or no model) and eomgen raises a ModelError naming
the file, link or joint, element, attribute and value. The expectation is written out here and also
checked against Pinocchio's parser on every run, so a urdfdom that changes its rule fails the test."""
from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import eomgen as eg
from eomgen.errors import ModelError
from eomgen.verify import verify

TEMPLATE = """<?xml version="1.0"?>
<robot name="r">
 <link name="base"/>
 <link name="arm"><inertial><origin xyz="{cxyz}" rpy="{crpy}"/><mass value="{mass}"/>
  <inertia ixx="{ixx}" ixy="0.01" ixz="0" iyy="1e5" iyz="0" izz="1e5"/></inertial></link>
 <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>
  <origin xyz="{oxyz}" rpy="{orpy}"/><axis xyz="{axis}"/>
  <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
 <link name="hand"><inertial><origin xyz="0 0.1 0"/><mass value="1"/>
  <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.2"/></inertial></link>
 <joint name="elbow" type="revolute"><parent link="arm"/><child link="hand"/><origin xyz="0.5 0 0"/>
  <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""  # two moving joints: verify() wants more than one
CLEAN = dict(cxyz="0.1 0.2 0.3", crpy="0.1 0.2 0.3", mass="2", ixx="0.3", oxyz="0.1 0.2 0.3",
             orpy="0.1 0.2 0.3", axis="0.1 0.2 0.3")
# field → (element, attribute, owner) in the messages
FIELDS = {"mass": ("inertial/mass", "value", "link 'arm'"),
          "ixx": ("inertial/inertia", "ixx", "link 'arm'"),
          "cxyz": ("inertial/origin", "xyz", "link 'arm'"), "crpy": ("inertial/origin", "rpy", "link 'arm'"),
          "oxyz": ("origin", "xyz", "joint 'shoulder'"), "orpy": ("origin", "rpy", "joint 'shoulder'"),
          "axis": ("axis", "xyz", "joint 'shoulder'")}

# single numbers: (text in the file, as urdfdom reads it, or None: dropped); \t \n \r are literal in the file
NUMBERS = [("1e-3", 1e-3), ("+1", 1.0), (".5", 0.5), ("5.", 5.0), (" 1", 1.0), ("\t1", 1.0), ("\n1", 1.0),
           ("&#9;1", 1.0), ("&#10;1", 1.0), ("1E2", 100.0), ("+.5", 0.5), ("00012", 12.0), ("1e+05", 1e5),
           ("5.e1", 50.0), ("0.", 0.0), ("-0", 0.0), ("1e-400", 0.0), ("2.5e-310", 2.5e-310),
           ("1 ", None), (" 1 ", None), ("1&#9;", None), ("1\n", None), ("1&#32;", None), ("0x10", None),
           ("0x1p3", None), ("1,5", None), ("inf", None), ("-inf", None), ("nan", None), ("INF", None),
           ("infinity", None), ("1_0", None), ("1_000", None), ("1e", None), ("1e+", None), (".", None),
           (".e1", None), ("1.5e3.2", None), ("1.2.3", None), ("1d2", None), ("2.0f", None), ("1e400", None),
           ("++1", None), ("+-1", None), ("\u0661", None), ("1 2", None), ("", None), (" ", None)]
# vectors, all meant as 0.1 0.2 0.3: split at spaces only, empty pieces skipped, three numbers
READ = [" 0.1 0.2 0.3 ", "0.1  0.2   0.3", "0.1 \t0.2 0.3", "0.1 \n0.2 0.3", "0.1 &#9;0.2 0.3",
        "\n0.1 0.2 0.3", "0.1 0.2 0.3&#32;", "0.1 \r\n0.2 0.3", "1e-1 +.2 3E-1"]
DROPPED = ["0.1\t0.2 0.3", "0.1\t 0.2 0.3", "0.1\n0.2 0.3", "0.1&#9;0.2 0.3", "0.1 0.2 0.3\n",
           "0.1 0.2 0.3&#10;", "0.1\r\n0.2 0.3", "0.1,0.2,0.3", "0.1 0.2", "0.1 0.2 0.3 0.4", "0.1 0.2 nan",
           "0.1 0.2 inf", "0.1 0.2 1_0", "0.1 0.2 0x1", "0.1\u00a00.2 0.3", "", "   "]
VECTORS = [(t, False) for t in READ] + [(t, True) for t in DROPPED]


def write(tmp_path: Path, name: str = "r.urdf", template: str = TEMPLATE, **fields) -> Path:
    path = tmp_path / name
    path.write_bytes(template.format(**{**CLEAN, **fields}).encode())  # \r and \t stay literal
    return path


def pinocchio_reads(path: Path, capfd) -> pin.Model | None:
    """Pinocchio's model of the file if urdfdom read it without an error on stderr, else None."""
    capfd.readouterr()
    try:
        model = pin.buildModelFromUrdf(str(path))
    except Exception:
        return None
    return None if "Error" in capfd.readouterr().err else model


def same_model(a: pin.Model, b: pin.Model) -> bool:
    """Same inertia, placement and joint (M and b at a state, which see the axis)."""
    q, v = np.array([0.7, -0.4]), np.array([0.3, 0.5])
    return (np.array_equal(a.inertias[1].toDynamicParameters(), b.inertias[1].toDynamicParameters())
            and np.array_equal(a.jointPlacements[1].homogeneous, b.jointPlacements[1].homogeneous)
            and np.array_equal(pin.crba(a, a.createData(), q), pin.crba(b, b.createData(), q))
            and np.array_equal(pin.nonLinearEffects(a, a.createData(), q, v),
                               pin.nonLinearEffects(b, b.createData(), q, v)))


def imports_and_verifies(path: Path) -> None:
    system = eg.from_urdf(path)
    assert verify(system, states=3).ok(1e-10)


def refused(path: Path, field: str, text: str) -> None:
    element, attribute, owner = FIELDS[field]
    text = text.replace("&#9;", "\t").replace("&#10;", "\n").replace("&#32;", " ").replace("\r\n", "\n")
    with pytest.raises(ModelError) as info:
        eg.from_urdf(path)
    message = str(info.value)
    for part in (path.name, owner, element, attribute, repr(text)):
        assert part in message, (part, message)


@pytest.mark.parametrize("field", ["mass", "ixx"])
@pytest.mark.parametrize("text, value", NUMBERS, ids=[repr(t) for t, _ in NUMBERS])
def test_single_number(tmp_path, capfd, field, text, value):
    path = write(tmp_path, **{field: text})
    model = pinocchio_reads(path, capfd)
    if value is None:
        assert model is None, "urdfdom reads this form: the test's rule is out of date"
        refused(path, field, text)
    else:
        reference = pin.buildModelFromUrdf(str(write(tmp_path, "ref.urdf", **{field: repr(value)})))
        assert model is not None and same_model(model, reference), "urdfdom drops or misreads this form"
        imports_and_verifies(path)


@pytest.mark.parametrize("field", ["cxyz", "crpy", "oxyz", "orpy", "axis"])
@pytest.mark.parametrize("text, dropped", VECTORS, ids=[repr(t) for t, _ in VECTORS])
def test_vector(tmp_path, capfd, field, text, dropped):
    path = write(tmp_path, **{field: text})
    model = pinocchio_reads(path, capfd)
    if dropped:
        assert model is None, "urdfdom reads this form: the test's rule is out of date"
        refused(path, field, text)
    else:
        reference = pin.buildModelFromUrdf(str(write(tmp_path, "ref.urdf")))  # "0.1 0.2 0.3"
        assert model is not None and same_model(model, reference), "urdfdom drops or misreads this form"
        imports_and_verifies(path)


INERTIAL = """<robot name="r"><link name="base"/>
 <link name="arm"><inertial>{inner}</inertial></link>
 <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
  <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"""
INERTIA = '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>'
MISSING = {"no <mass>": (INERTIA, "<mass>"),
           "no <inertia>": ('<mass value="2"/>', "<inertia>"),
           "mass without value": ('<mass/>' + INERTIA, "inertial/mass has no value"),
           **{f"no {a}": ('<mass value="2"/>' + re.sub(f'{a}="[^"]*"', "", INERTIA),
                          f"inertial/inertia has no {a}")
              for a in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}}


@pytest.mark.parametrize("case", MISSING)
def test_inertial_needs_mass_and_all_six_inertia_values(tmp_path, capfd, case):
    inner, expected = MISSING[case]
    path = tmp_path / "r.urdf"
    path.write_text(INERTIAL.format(inner=inner))
    assert pinocchio_reads(path, capfd) is None  # urdfdom: "Could not parse inertial element"
    with pytest.raises(ModelError, match=f"r.urdf: link 'arm': .*{expected}"):
        eg.from_urdf(path)


def test_a_link_without_inertial_is_massless(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(INERTIAL.replace("<inertial>{inner}</inertial>", "").replace(
        '<link name="base"/>', '<link name="base"/><link name="tip"><inertial><mass value="1"/>'
        f'{INERTIA}<origin xyz="0 0.5 0"/></inertial></link>').replace(
        "</robot>", '<joint name="wrist" type="continuous"><parent link="arm"/><child link="tip"/>'
        '<origin xyz="0.3 0 0"/><axis xyz="0 1 0"/></joint></robot>'))
    system = eg.from_urdf(path)
    assert system.bodies[1].mass == 0
    assert verify(system, states=3).ok(1e-10)


def test_axis_without_xyz_is_refused_by_name(tmp_path, capfd):
    path = write(tmp_path, template=TEMPLATE.replace('<axis xyz="{axis}"/>', "<axis/>"))
    model = pinocchio_reads(path, capfd)
    assert model is not None  # urdfdom: the zero axis, silently: the joint moves nothing
    assert pin.crba(model, model.createData(), np.zeros(2))[0, 0] == 0
    with pytest.raises(ModelError, match="r.urdf: joint 'shoulder': <axis> has no xyz"):
        eg.from_urdf(path)


def test_axis_of_a_fixed_joint_is_not_read(tmp_path):
    """urdfdom reads the axis of moving joints only: a malformed one on a fixed joint changes nothing."""
    path = write(tmp_path, template=TEMPLATE.replace("</robot>", '<link name="tool"><inertial>'
                 f'<mass value="1"/>{INERTIA}</inertial></link><joint name="flange" type="fixed">'
                 '<parent link="arm"/><child link="tool"/><origin xyz="0 0 0.2"/><axis xyz="0 0"/></joint>'
                 '</robot>'))
    imports_and_verifies(path)


MIMIC = TEMPLATE.replace("</robot>", f'<link name="finger"><inertial><mass value="0.5"/>{INERTIA}</inertial>'
                         '</link><joint name="grip" type="revolute"><parent link="hand"/>'
                         '<child link="finger"/><origin xyz="0 0.2 0"/><axis xyz="1 0 0"/>'
                         '<limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="elbow" '
                         'multiplier="{multiplier}" offset="{offset}"/></joint></robot>')


@pytest.mark.parametrize("field", ["multiplier", "offset"])
@pytest.mark.parametrize("text, value", NUMBERS, ids=[repr(t) for t, _ in NUMBERS])
def test_mimic_number(tmp_path, capfd, field, text, value):
    """A mimic's multiplier and offset are read like the other numbers (urdfdom refuses the file)."""
    path = write(tmp_path, template=MIMIC, **{"multiplier": "2", "offset": "0.1", field: text})
    capfd.readouterr()
    try:
        mimic = pin.buildModelFromUrdf(str(path), mimic=True).joints[3].extract()
    except ValueError:
        mimic = None
    if value is None:
        assert mimic is None and "Error" in capfd.readouterr().err, "urdfdom reads this form"
        text = text.replace("&#9;", "\t").replace("&#10;", "\n").replace("&#32;", " ").replace("\r\n", "\n")
        with pytest.raises(ModelError) as info:
            eg.from_urdf(path)
        for part in (path.name, "joint 'grip'", f"mimic {field}={text!r}"):
            assert part in str(info.value), (part, str(info.value))
    elif field == "multiplier" and abs(value) < 1e-14:  # read as 0, like every URDF number that close
        assert mimic.scaling == value
        with pytest.raises(ModelError, match="'grip' mimics 'elbow' with multiplier .*: it does not move"):
            eg.from_urdf(path)
    else:
        assert {"multiplier": mimic.scaling, "offset": mimic.offset}[field] == value
        finger = eg.from_urdf(path).bodies[-1].joint
        assert float(getattr(finger.mimic, field)) == pytest.approx(value, rel=0, abs=1e-14)


def test_negative_mass_refused_mimic_followed_or_refused_on_request(tmp_path):
    with pytest.raises(ModelError, match="mass must be non-negative"):
        eg.from_urdf(write(tmp_path, mass="-1"))
    path = write(tmp_path, template=MIMIC, multiplier="-2", offset="0.1")
    system = eg.from_urdf(path)
    assert system.nv == 2 and verify(system, states=3).ok(1e-10)
    with pytest.raises(ModelError, match="joint 'grip' mimics joint 'elbow'"):
        eg.from_urdf(path, mimic="refuse")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert eg.from_urdf(path, mimic="independent").nv == 3
    assert any("grip" in str(w.message) for w in caught)


def test_numbers_not_names_are_checked(tmp_path):
    """A quoted '>' and a quote of the other kind in a tag do not confuse the reader of raw attributes."""
    path = write(tmp_path, template=TEMPLATE.replace('<link name="arm">', """<link name='a>"rm'>""")
                 .replace('child link="arm"', """child link='a>"rm'"""), mass="1_0")
    with pytest.raises(ModelError, match="""link 'a>"rm': inertial/mass value='1_0'"""):
        eg.from_urdf(path)


@pytest.mark.parametrize("robot", ["ur5", "panda", "talos_arm", "solo12", "tiago"])
def test_shipped_robots_still_import(robot):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system = eg.robots.load(robot)
    assert len(system.bodies) > 1
