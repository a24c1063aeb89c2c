"""Robot files are read once, as Pinocchio's parsers read them, or refused naming the file and what was
found: a DOCTYPE makes expat (eomgen's checks) and tinyxml2 / rapidxml (Pinocchio's parsers) read other
elements, a deep file kills Pinocchio's recursive parsers. Pinocchio and MuJoCo are the truth for what
the C++ parsers read; a deep file is only handed to the checks, never to Pinocchio, except in the slow
test that measures Pinocchio at the limits in a subprocess with a memory limit."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import mujoco
import pinocchio as pin
import pytest

import eomgen as eg
from eomgen.errors import ModelError
from eomgen.model.mjcf_check import check_mjcf
from eomgen.model.urdf_check import MAX_CHAIN, check_urdf
from eomgen.model.xml_read import MAX_DEPTH

JOINT = ("<joint name='j{i}' type='continuous'><parent link='l{i}'/><child link='l{j}'/><axis xyz='0 0 1'/>"
         "</joint>")


def urdf(mass="1", links: int = 2, head: str = "<robot name='r'>") -> str:
    """A chain of `links` links, massless but the last (mass `mass`), on links − 1 continuous joints."""
    inertial = (f"<inertial><mass value='{mass}'/><inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/>"
                "</inertial>")
    body = [f"<link name='l{i}'>{inertial if i == links - 1 else ''}</link>" for i in range(links)]
    return head + "".join(body) + "".join(JOINT.format(i=i, j=i + 1) for i in range(links - 1)) + "</robot>"


def mjcf(mass="1", bodies: int = 1) -> str:
    """A chain of `bodies` nested bodies on hinges; the last geom has mass `mass`."""
    opening = "".join(f"<body name='b{i}' pos='0 0 0.1'><joint name='j{i}' type='hinge'/>"
                      f"<geom type='sphere' size='0.1' mass='{mass if i == bodies - 1 else 1}'/>"
                      for i in range(bodies))
    return "<mujoco><worldbody>" + opening + "</body>" * bodies + "</worldbody></mujoco>"


def write(tmp_path: Path, name: str, text: str) -> Path:
    (tmp_path / name).write_text(text)
    return tmp_path / name


def test_doctype_whose_entity_hides_another_robot_is_refused(tmp_path):
    """Entity text holding '>' (tinyxml2 ends the DOCTYPE there) or ']>' (rapidxml): Pinocchio reads the
    robot of mass 7 hidden in the entity, expat the robot of mass 1 after the DTD."""
    two = (("u.urdf", "robot", ">", urdf("7"), urdf("1"), pin.buildModelFromUrdf, eg.from_urdf),
           ("m.xml", "mujoco", "]>", mjcf("7"), mjcf("1"), pin.buildModelFromMJCF, eg.from_mjcf))
    for name, root, close, hidden, seen, pinocchio_reads, ours in two:
        path = write(tmp_path, name, f'<!DOCTYPE {root} [<!ENTITY e "{close}{hidden}<!--">]>\n{seen}\n'
                                     "<!-- -->\n")
        assert pinocchio_reads(str(path)).inertias[-1].mass == 7  # the two readers disagree
        with pytest.raises(ModelError, match=rf"{name}, line 1: <!DOCTYPE {root} …>: DTDs and entities "
                                             "are refused"):
            ours(path)


@pytest.mark.parametrize("attribute", ["mass='&m;'", "pos='0 0 &m;' mass='1'"])
def test_entity_in_an_mjcf_number_is_refused(tmp_path, attribute):
    """MuJoCo refuses the entity ('bad format'); Pinocchio drops it without a word (the mass of a
    geom of density 1000, a zero offset): eomgen names the DTD."""
    text = '<!DOCTYPE mujoco [<!ENTITY m "2">]>\n' + mjcf().replace("mass='1'", attribute)
    path = write(tmp_path, "e.xml", text)
    with pytest.raises(ValueError, match="bad format"):
        mujoco.MjModel.from_xml_path(str(path))
    with pytest.raises(ModelError, match=r"e.xml, line 1: <!DOCTYPE mujoco …>: DTDs and entities"):
        eg.from_mjcf(path)


def test_doctype_without_subset_entities_and_instructions_are_refused(tmp_path):
    cases = {'<!DOCTYPE robot SYSTEM "r.dtd">\n' + urdf(): r"line 1: <!DOCTYPE robot …>",
             urdf("&m;"): r"undefined entity: line 1, column \d+ \(entities are refused",
             '<?xml version="1.0"?>\n<?xml-stylesheet href="s.xsl"?>\n' + urdf(): r"line 2: processing "
             r"instruction <\?xml-stylesheet …\?>"}
    for text, message in cases.items():
        with pytest.raises(ModelError, match=message):
            eg.from_urdf(write(tmp_path, "r.urdf", text))


def test_predefined_entities_character_references_and_namespaces_read_as_pinocchio_does(tmp_path):
    """&#50; is 2 to both parsers; a default namespace is no namespace to tinyxml2, so the checks read the
    links (eomgen's checks used to see '{ns}link' and skip them: a mass '1 ' urdfdom drops went through)."""
    path = write(tmp_path, "c.urdf", '<?xml version="1.0"?>\n<!-- a &amp; b -->\n' +
                 urdf("&#50;").replace("name='r'", "name='r&amp;&lt;&gt;&quot;&apos;'"))
    assert eg.from_urdf(path).bodies[-1].mass == 2 == pin.buildModelFromUrdf(str(path)).inertias[-1].mass
    spaced = write(tmp_path, "n.urdf", urdf("1 ", head="<robot name='r' xmlns='http://example.org/r'>"))
    assert pin.buildModelFromUrdf(str(spaced)).inertias[-1].mass == 0  # urdfdom dropped the inertial
    with pytest.raises(ModelError, match=r"link 'l1': inertial/mass value='1 ' is not a number urdfdom"):
        eg.from_urdf(spaced)


def calls(check, path: Path, message: str) -> int:
    """Python and C function calls made while `check` refuses `path` with `message`: a count of the work
    done that does not depend on how busy the machine is."""
    count = 0

    def profile(frame, event, arg):
        nonlocal count
        count += event in ("call", "c_call")

    before = sys.getprofile()
    sys.setprofile(profile)
    try:
        with pytest.raises(ModelError, match=message):
            check(path)
    finally:
        sys.setprofile(before)
    return count


def test_ten_thousand_deep_files_are_refused_in_linear_work(tmp_path):
    """Pinocchio's parsers crash on these (segmentation fault): only the checks read them. The nested
    ones stop at level 251, so a 10,010-deep file costs about what a 1,001-deep one does; the flat URDF chain
    is walked in one linear pass, so 10 times the joints cost at most 11 times the calls (a walk
    quadratic in the joints would cost 100 times)."""
    def files(n: int) -> dict:
        return {"chain.xml": (mjcf(bodies=n), check_mjcf, rf"<joint> is nested deeper than {MAX_DEPTH}"),
                "nest.urdf": (urdf().replace("</inertial>", "<x>" * n + "</x>" * n + "</inertial>"),
                              check_urdf, rf"<x> is nested deeper than {MAX_DEPTH}"),
                "chain.urdf": (urdf(links=n + 1), check_urdf, f"joint 'j{n - 1}' is {n} joints below the root")}

    work = {n: {name: calls(check, write(tmp_path, name, text), message)
                for name, (text, check, message) in files(n).items()} for n in (1_001, 10_010)}
    for nested in ("chain.xml", "nest.urdf"):  # the file is read in blocks: a few calls per block
        assert work[10_010][nested] <= 1.2 * work[1_001][nested]
    assert work[10_010]["chain.urdf"] <= 11 * work[1_001]["chain.urdf"]


def test_depth_limits_are_exact(tmp_path):
    """MJCF: <mujoco>, <worldbody>, n bodies and the last body's <joint>: n + 3 levels; URDF: the
    chain's joints."""
    check_mjcf(write(tmp_path, "m.xml", mjcf(bodies=MAX_DEPTH - 3)))
    with pytest.raises(ModelError, match=f"m.xml, line 1: <joint> is nested deeper than {MAX_DEPTH}"):
        check_mjcf(write(tmp_path, "m.xml", mjcf(bodies=MAX_DEPTH - 2)))
    check_urdf(write(tmp_path, "u.urdf", urdf(links=MAX_CHAIN + 1)))
    with pytest.raises(ModelError, match=f"u.urdf: joint 'j{MAX_CHAIN}' is {MAX_CHAIN + 1} joints below "
                                         f"the root link, more than the {MAX_CHAIN} eomgen reads"):
        check_urdf(write(tmp_path, "u.urdf", urdf(links=MAX_CHAIN + 2)))


MEASURE = """
import resource, sys, time
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
import pinocchio as pin
start = time.perf_counter()
model = (pin.buildModelFromMJCF if sys.argv[1].endswith(".xml") else pin.buildModelFromUrdf)(sys.argv[1])
print(model.njoints - 1, time.perf_counter() - start, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


@pytest.mark.slow
def test_pinocchio_reads_files_at_the_limits(tmp_path):
    """The deepest files the checks pass load in Pinocchio (a subprocess with 3 GB of address space)
    in under 5 s and 1.2 GB (the module's measurement)."""
    for name, text, joints in (("m.xml", mjcf(bodies=MAX_DEPTH - 3), MAX_DEPTH - 3),
                               ("u.urdf", urdf(links=MAX_CHAIN + 1), MAX_CHAIN)):
        path = write(tmp_path, name, text)
        check_mjcf(path) if name.endswith(".xml") else check_urdf(path)
        run = subprocess.run([sys.executable, "-c", MEASURE, str(path)], capture_output=True, text=True,
                             timeout=60)
        assert run.returncode == 0, run.stderr
        count, seconds, kilobytes = run.stdout.split()
        assert int(count) == joints and float(seconds) < 5 and int(kilobytes) < 1.2e6


def test_files_that_are_not_utf8_are_refused_naming_the_byte(tmp_path):
    """A UTF-16 file (expat decodes it, the checks' byte offsets and the C++ parsers do not) and a Latin-1
    name are refused before any parser reads them."""
    (tmp_path / "u.urdf").write_bytes(urdf().encode("utf-16"))
    (tmp_path / "l.urdf").write_bytes(urdf().replace("name='r'", "name='r\xe9'").encode("latin-1"))
    for name, byte in (("u.urdf", 0), ("l.urdf", 14)):
        with pytest.raises(ModelError, match=rf"URDF {name}: byte {byte} is not UTF-8"):
            eg.from_urdf(tmp_path / name)
    (tmp_path / "u.xml").write_bytes(mjcf().encode("utf-16"))
    with pytest.raises(ModelError, match=r"MJCF u.xml: byte 0 is not UTF-8"):
        eg.from_mjcf(tmp_path / "u.xml")
