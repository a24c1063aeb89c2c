"""MJCF files read as MuJoCo reads them (MuJoCo the oracle, see `mujoco_oracle` for the coordinate
mapping), or refused with the element named."""
from __future__ import annotations

import re
from importlib.resources import files
from pathlib import Path

import mujoco
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import eomgen as eg
from eomgen.errors import ModelError
from mujoco_oracle import assert_equals_mujoco

DATA = files("eomgen") / "data" / "mjcf"


@pytest.mark.parametrize("name", ["tree.xml", "spatial_loop.xml", "cassie_leg.xml"])
def test_data_files_equal_mujoco(name):
    """tree.xml's free root has pos and euler: MuJoCo's q is the body's pose (was p0 + (p0 − R0 p0))."""
    assert_equals_mujoco(Path(str(DATA / name)))


def write(tmp_path: Path, inside: str, top: str = "", world: str = "", name: str = "m.xml") -> Path:
    """A file with a root body 'r' (contents `inside`) in <worldbody>, `top` before it, `world` beside."""
    path = tmp_path / name
    path.write_text(f"<mujoco>{top}<worldbody>{world}<body name='r'>{inside}</body></worldbody></mujoco>")
    return path


INERTIAL = '<inertial pos="0.01 0.02 0.1" mass="1.3" diaginertia="0.01 0.02 0.03"/>'
READ = {
    "joint pos": f"""<joint name="j0" axis="1 0 0"/>{INERTIAL}<body name="b" pos="0 0.1 0.3">
        <joint name="j1" axis="0 1 0" pos="0.02 0.03 -0.01"/>{INERTIAL}<site name="s" pos="0.1 0 0"/>
        </body>""",
    "rotated free root": f"""<freejoint name="f"/>{INERTIAL}<site name="s" pos="0.1 0 0" euler="10 0 0"/>
        <body name="b" pos="0 0.1 0.3"><joint name="j1" type="ball" pos="0.02 0 0"/>{INERTIAL}</body>""",
    "sites on the fixed root": f"""{INERTIAL}<site name="s" pos="0.1 0.2 0.3" euler="10 20 30"/>
        <site pos="0 0 1" zaxis="0 -1 0"/><site name="x" xyaxes="0 1 0 -1 0.1 0"/>
        <body name="b" pos="0 0.1 0.3"><joint name="j1" axis="0 1 0"/>{INERTIAL}</body>""",
    "unnamed joints and sites": f"""<joint axis="1 0 0"/>{INERTIAL}<body name="b" pos="0 0.1 0.3"><joint
        axis="0 1 0"/>{INERTIAL}<site/><body name="c"><joint axis="0 0 1" pos="0 0.1 0"/>{INERTIAL}<site/>
        </body></body>""",
    "visual geoms beside an inertial": f"""<joint axis="1 0 0"/>{INERTIAL}
        <geom type="mesh" mesh="none" contype="0" conaffinity="0"/>""",
}
READ_TOP = {"sites on the fixed root": ('<compiler angle="radian"/>', '<site name="w" pos="1 2 3" '
                                        'quat="0.5 0.5 0.5 0.5"/><site pos="0 1 0"/>'),
            "visual geoms beside an inertial": ('<asset><mesh name="none" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/>'
                                                '</asset>', "")}


@pytest.mark.parametrize("case", READ, ids=list(READ))
def test_read_as_mujoco(tmp_path, case):
    """Item 1 (a joint's pos: the body's name is its origin; a free root with pos and a rotation; sites
    on the root welded to the world and on <worldbody>) and unnamed bodies, joints and sites."""
    top, world = READ_TOP.get(case, ("", ""))
    assert_equals_mujoco(write(tmp_path, READ[case], top, world))


def test_gravity_disabled(tmp_path):
    """<flag gravity="disable"/>: g = 0 as in MuJoCo (was the gravity of <option>)."""
    path = write(tmp_path, f'<joint axis="1 0 0"/>{INERTIAL}',
                 '<option gravity="0 0 -9.81"><flag gravity="disable"/></option>')
    assert_equals_mujoco(path)
    assert tuple(eg.from_mjcf(path).gravity) == (0, 0, 0)


GEOM = '<geom type="sphere" size="0.1" mass="2"/>'
REFUSED = {
    "unnamed bodies": (f'<joint name="a" axis="1 0 0"/>{INERTIAL}<body><joint axis="0 1 0"/>{INERTIAL}'
                       f'</body><body><joint axis="1 0 0"/>{INERTIAL}</body>', "",
                       "body 1 inside body 'r' has no name"),
    "mesh inertia": ('<joint axis="1 0 0"/><geom name="g" type="mesh" mesh="m"/>',
                     '<asset><mesh name="m" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/></asset>',
                     "geom 'g': a mesh's"),
    "visual geom": (f'<joint axis="1 0 0"/>{GEOM}<geom name="v" class="visual" type="box" size="1 1 1"/>',
                    '<default><default class="visual"><geom contype="0" conaffinity="0"/></default>'
                    '</default>',
                    "body 'r': geom 'v': contype=0 and conaffinity=0"),
    "inertiagrouprange": (f'<joint axis="1 0 0"/>{GEOM}', '<compiler inertiagrouprange="0 2"/>',
                          "inertiagrouprange='0 2'"),
    "inertiafromgeom": (f'<joint axis="1 0 0"/>{INERTIAL}{GEOM}', '<compiler inertiafromgeom="true"/>',
                        "inertiafromgeom='true'> with body 'r'"),
    "settotalmass": (f'<joint axis="1 0 0"/>{GEOM}', '<compiler settotalmass="5"/>', "settotalmass='5'"),
    "springdamper": (f'<joint name="k" axis="1 0 0" springdamper="0.1 1"/>{GEOM}', "",
                     "joint 'k': springdamper='0.1 1'"),
    "default joint pos": (f'<joint axis="1 0 0"/>{GEOM}', '<default><joint pos="0 0 0.1"/></default>',
                          "a joint pos in a default class"),
    "free joint pos": (f'<joint type="free" pos="0 0 0.1"/>{GEOM}', "", "body 'r': free joint pos"),
    "site named like a body": (f'<joint axis="1 0 0"/>{GEOM}<site name="r"/>', "",
                               "site 'r' has the name of a body"),
    "two sites of one name": (f'<joint axis="1 0 0"/>{GEOM}<site name="s"/><site name="s" pos="1 0 0"/>', "",
                              "two sites are named 's'"),
    "site named like a joint": (f'<joint name="j" axis="1 0 0"/>{GEOM}<site name="j"/>', "",
                                "site 'j' has the name of a joint"),
    "joint with pos named like its body": (f'<joint name="r" axis="1 0 0" pos="0.1 0 0"/>{GEOM}', "",
                                           "joint 'r' has a pos and the name of a body"),
    "welded site with three numbers in quat": (f'{INERTIAL}<site name="s" quat="1 0 0"/><body name="b"><joint '
                                              f'name="j1" axis="0 1 0"/>{INERTIAL}</body>', "",
                                              r"quat='1 0 0' must be 4 finite numbers"),
}


@pytest.mark.parametrize("case", REFUSED, ids=list(REFUSED))
def test_refused_with_the_element(tmp_path, case):
    """Items 2 and 11: what Pinocchio's parser reads otherwise than MuJoCo (each imported silently with
    other numbers before) is refused, naming the element and attribute."""
    inside, top, message = REFUSED[case]
    with pytest.raises(ModelError, match=message):
        eg.from_mjcf(write(tmp_path, inside, top))


def names(own: str) -> st.SearchStrategy:
    """Mostly a name of its own, else none or one that other elements may have."""
    return st.sampled_from([own, own, own, None, "a"])


TURNS = st.sampled_from(["", ' euler="10 -20 30"', ' quat="0.9 0.1 -0.2 0.3"', ' axisangle="0 0.6 0.8 40"',
                         ' xyaxes="0 1 0 -1 0 0.2"', ' zaxis="0 -1 0.1"'])
POS = st.sampled_from(["", ' pos="0.1 -0.2 0.3"', ' pos="0 0 -0.25"'])
INERTIAS = st.sampled_from([INERTIAL, '<geom type="capsule" fromto="0 0 0 0 0.1 -0.2" size="0.03"/>',
                            '<geom type="box" size="0.1 0.05 0.02" pos="0 0 -0.1" mass="0.7"/>',
                            '<geom class="heavy" type="sphere" size="0.05" pos="0.1 0 0"/>',
                            '<geom class="visual" type="box" size="0.1 0.1 0.1"/><geom size="0.1"/>'])
JOINTS = st.sampled_from(['type="hinge" axis="0.3 1 0.2"', 'type="slide" axis="0 0 1"', 'type="ball"', None])
DEFAULTS = ('<default><joint armature="0.02"/><default class="heavy"><geom density="3000"/></default>'
            '<default class="visual"><geom contype="0" conaffinity="0"/></default></default>')


def name(value) -> str:
    return f' name="{value}"' if value else ""


@st.composite
def mjcf_files(draw) -> str:
    """A tree of 1 to 4 bodies: a free root (pos and a rotation) or a fixed one, named and unnamed bodies,
    joints and sites, joints with pos, a site on every body, inertias given or from geoms of classes."""
    free = draw(st.booleans())
    pose = ' pos="0 0 1"' + draw(TURNS) if free else ""
    bodies = [f'<body{name(draw(names("r")))}{pose}>' + ("<freejoint/>" if free else "") + INERTIAL
              + f"<site{name(draw(names('s')))}{draw(POS)}{draw(TURNS)}/>"]
    for i in range(draw(st.integers(1, 3))):
        joint = draw(JOINTS)
        joint = f"<joint{name(draw(names(f'j{i}')))} {joint}{draw(POS)}/>" if joint else ""
        bodies.append(f"<body{name(draw(names(f'b{i}')))}{draw(POS)}{draw(TURNS)}>{joint}{draw(INERTIAS)}"
                      f"<site{name(draw(names(f's{i}')))}{draw(POS)}{draw(TURNS)}/>")
    nested = draw(st.booleans())
    text = bodies[0] + ("".join(bodies[1:]) + "</body>" * len(bodies[1:]) if nested else
                        "</body>".join(bodies[1:]) + "</body>")
    world = f'<site{name(draw(names("w")))} pos="1 0 0"{draw(TURNS)}/>'
    return f"<mujoco>{DEFAULTS}<worldbody>{world}{text}</body></worldbody></mujoco>"


@settings(max_examples=30, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=mjcf_files())
def test_random_files_equal_mujoco_or_are_refused(tmp_path, text):
    """Each file MuJoCo reads either equals MuJoCo or is refused with a ModelError that names an element
    of the file; a file MuJoCo refuses is refused."""
    path = tmp_path / "random.xml"
    path.write_text(text)
    try:
        mujoco.MjModel.from_xml_path(str(path))
    except ValueError:
        with pytest.raises(ModelError):
            eg.from_mjcf(path)
        return
    try:
        eg.from_mjcf(path)
    except ModelError as exc:
        assert re.search(r"(body|joint|site|geom) '[^']+'|<default|the root body", str(exc)), str(exc)
        return
    assert_equals_mujoco(path, states=2)
