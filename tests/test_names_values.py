"""Names are labels, never identities or code; values are refused where they enter.

The reference for the name tests is Pinocchio (built with its own API, or from the same URDF), which
knows nothing of eomgen's symbol names."""
import numpy as np
import pinocchio as pin
import pytest
import sympy as sp

import eomgen as eg
from eomgen.verify import to_pinocchio, verify


def _arm(names, base=None):
    """A spatial 3-link arm (numeric) with joints named `names`, optionally on a free-flyer base."""
    s = eg.System(gravity=(0, 0, -9.81))
    parent = (s.add_body("base", joint=eg.FreeFlyer(base), mass=2, inertia=np.diag([0.3, 0.4, 0.5]))
              if base else None)
    for k, (name, axis) in enumerate(zip(names, [(0, 0, 1), (0, 1, 0), (1, 0, 1)])):
        parent = s.add_body(f"link {k}, left", parent=parent, joint=eg.Revolute(name, axis=axis), mass=1 + k,
                            com=(0.3, 0.1 * k, 0), inertia=np.diag([0.1, 0.2, 0.25]),
                            placement=eg.Placement(translation=(0.5, 0, 0.1 * k)))
    return s


@pytest.mark.parametrize("names", [("a", "adot", "b"), ("q_1", "qdot_1", "q_2"), ("a", "addot", "adot"),
                                   ("_ξ0", "_ξ1", "tau_a"), ("sin", "lambda", "upper arm, left"),
                                   ("a", "ad", "add")])
def test_names_that_look_generated_give_pinocchio_equations(names):
    s = _arm(names)
    model = to_pinocchio(s)
    data = model.createData()
    f = eg.codegen(eg.derive(s))
    rng = np.random.default_rng(1)
    for _ in range(5):
        q, u = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3)
        g = pin.computeGeneralizedGravity(model, data, q)
        np.testing.assert_allclose(f.g(q), g, atol=1e-12)
        np.testing.assert_allclose(f.b(q, u), pin.nonLinearEffects(model, data, q, u) - g, atol=1e-12)
        np.testing.assert_allclose(f.M(q), pin.crba(model, data, q), atol=1e-12)


def _euler_and_beam(base_joint: str, beam_joint: str):
    s = eg.System(gravity=(0, 0, -9.81))
    base = s.add_body("base", joint=eg.FreeFlyer("root", parametrization="euler"), mass=2,
                      inertia=np.diag([0.3, 0.4, 0.5]))
    arm = s.add_body("arm", parent=base, joint=eg.Revolute(base_joint, axis=(0, 1, 0)), mass=1, com=(0.3, 0, 0),
                     inertia=np.diag([0.1, 0.2, 0.25]))
    s.add_body("beam", parent=arm, joint=eg.FlexibleLink("beam", length=1, mass_per_length=0.5, EI=2.0),
               placement=eg.Placement(translation=(0.6, 0, 0)))
    s.add_body("tip", parent="beam", joint=eg.Revolute(beam_joint, axis=(0, 0, 1)), mass=0.5, com=(0.1, 0, 0),
               inertia=np.diag([0.01, 0.01, 0.01]))
    return eg.codegen(eg.derive(s, method="lagrange"))


def test_labels_of_generated_symbols_never_collide():
    """An Euler base 'root' beside a joint 'root_yaw' (whose speed is labelled like the base's yaw rate), a
    flexible link 'beam' beside a joint 'w2_beam' (labelled like its nodal deflection): the same equations
    as with plain names."""
    plain, tricky = _euler_and_beam("j1", "j2"), _euler_and_beam("root_yaw", "w2_beam")
    rng = np.random.default_rng(2)
    q, u = rng.uniform(-1, 1, plain.nq), rng.uniform(-1, 1, plain.nv)
    np.testing.assert_allclose(tricky.M(q), plain.M(q), atol=1e-13)
    np.testing.assert_allclose(tricky.b(q, u), plain.b(q, u), atol=1e-12)
    assert np.linalg.cond(tricky.M(q)) < 1e8


def test_a_parameter_never_becomes_a_coordinate_or_a_speed():
    g, phidot = sp.symbols("g phidot")
    s = eg.System(gravity=(0, -g, 0))
    with pytest.raises(eg.ModelError, match="joint 'g': its coordinate 'g' is a parameter of gravity already"):
        s.add_body("a", joint=eg.Revolute("g"), mass=1, com=(1, 0, 0))
    s.add_body("a", joint=eg.Revolute("phi"), mass=1, com=(1, 0, 0))
    with pytest.raises(eg.ModelError, match="load 'drag': parameter 'phidot' has the name of the speed of joint "
                                            "'phi'"):
        s.add_torque("a", (0, 0, -0.1 * phidot), name="drag")
    s.add_torque("a", (0, 0, -0.1 * s.u[0]), name="drag")  # the speed itself
    s2 = eg.System()
    s2.add_body("a", joint=eg.Revolute("x"), mass=sp.Symbol("ydot"), com=(1, 0, 0))
    with pytest.raises(eg.ModelError, match="joint 'y': its speed is labelled 'ydot', the name of a parameter"):
        s2.add_body("b", parent="a", joint=eg.Revolute("y"), mass=1)
    s2.add_body("b", parent="a", joint=eg.Revolute("z"), mass=1)  # the refused change left nothing behind


def test_equations_of_a_changed_system_are_refused():
    s = eg.System()
    a = s.add_body("a", joint=eg.Revolute("q1"), mass=1, com=(1, 0, 0))
    eom = eg.derive(s)
    s.add_force(a, (1, 0, 0), point=(1, 0, 0))
    with pytest.raises(eg.ModelError, match="the system changed after these equations were derived"):
        eg.codegen(eom)
    with pytest.raises(eg.ModelError, match="the system changed"):
        eom.tau
    np.testing.assert_allclose(eg.codegen(eg.derive(s)).tau([0.0], [0.0]), [0.0])
    np.testing.assert_allclose(eg.codegen(eg.derive(s)).tau([np.pi / 2], [0.0]), [-1.0])


def test_free_flyer_beside_a_joint_named_like_its_components():
    s = _arm(("root_joint_vx", "root_joint_qw", "root_joint_vxdot"), base="root_joint")
    assert verify(s, states=5).ok(1e-10)


def test_c_backend_with_generated_looking_joint_names(tmp_path, monkeypatch):
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    eom = eg.derive(_arm(("_ξ0", "_x0", "_q0")), method="recursive")
    c, py = eg.codegen(eom, backend="c"), eg.codegen(eom)
    q = np.array([0.3, -0.2, 0.9])
    np.testing.assert_allclose(c.M(q), py.M(q), atol=1e-13)


def test_urdf_joints_j_and_jdot_verify(tmp_path):
    path = tmp_path / "jj.urdf"
    inertial = ('<inertial><origin xyz="0.4 0.05 0"/><mass value="1.5"/>'
                '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.25"/></inertial>')
    path.write_text(f"""<robot name="jj"><link name="base"/><link name="l1">{inertial}</link>
      <link name="l2">{inertial}</link>
      <joint name="j" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
        <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="jdot" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="1 0 0"/>
        <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>""")
    assert verify(eg.from_urdf(path), states=5).ok(1e-10)


def test_body_names_with_spaces_and_commas_in_the_free_cut():
    s = _arm(("q1", "q2", "q3"))
    cut = eg.derive(s, method="free_cut").cut_equations
    assert (len(cut.equations), len(cut.unknowns)) == (18, 18)
    assert len(set(cut.unknowns)) == 18


def test_one_joint_name_per_joint():
    s = eg.System()
    s.add_body("a", joint=eg.Revolute("q1"), mass=1)
    with pytest.raises(eg.ModelError, match="body 'b': joint name 'q1' is used by another joint"):
        s.add_body("b", parent="a", joint=eg.Fixed("q1"), mass=1)


def test_one_symbol_per_name():
    s = eg.System()
    s.add_body("a", joint=eg.Revolute("q1"), mass=sp.Symbol("l"), com=(1, 0, 0))
    with pytest.raises(eg.ModelError, match="body 'b': com.*Symbol\\('l', positive=True\\).*body 'a': mass"):
        s.add_body("b", parent="a", joint=eg.Revolute("q2"), mass=1,
                   com=(sp.Symbol("l", positive=True), 0, 0))
    with pytest.raises(eg.ModelError, match="body 'c': mass depends on the coordinates"):
        s.add_body("c", parent="a", joint=eg.Revolute("q3"), mass=sp.Symbol("q1") + 1)


def test_a_parameter_named_like_an_internal_symbol():
    """Element integrals use an element length 'h' of their own: a user's h must stay the user's."""
    h = sp.Symbol("h", positive=True)

    def link(EI):
        s = eg.System(gravity=(0, 0, 0))
        s.add_body("beam", joint=eg.FlexibleLink("theta", length=1, mass_per_length=2, EI=EI, elements=1))
        return eg.derive(s, method="lagrange")
    K = sp.Matrix(link(h).tau_of("elastic")).xreplace({h: 3})
    assert sp.simplify(K - sp.Matrix(link(3).tau_of("elastic"))) == sp.zeros(3, 1)


def test_strings_are_never_evaluated(tmp_path):
    marker = tmp_path / "PWNED"
    evil = f"__import__('os').system('touch {marker}')"
    s = eg.System()
    with pytest.raises(eg.ModelError, match="body 'x': mass: expected a number or a sympy expression"):
        s.add_body("x", joint=eg.Revolute("q"), mass=evil)
    with pytest.raises(eg.ModelError, match=r"body 'x': com\[1\]: expected a number"):
        s.add_body("x", joint=eg.Revolute("q"), mass=1, com=(0, evil, 0))
    with pytest.raises(eg.ModelError, match=r"joint 'q': armature"):
        eg.Revolute("q", armature=evil)
    assert not marker.exists()


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf, sp.nan, sp.zoo, 1j, np.float32("nan")])
def test_non_finite_values_refused_where_they_enter(bad):
    with pytest.raises(eg.ModelError, match="joint 'q': armature"):
        eg.Revolute("q", armature=bad)
    with pytest.raises(eg.ModelError, match=r"placement.translation\[0\]"):
        eg.Placement(translation=(bad, 0, 0))
    with pytest.raises(eg.ModelError, match="joint 'q': length"):
        eg.FlexibleLink("q", length=bad, mass_per_length=1, EI=1)
    s = eg.System()
    with pytest.raises(eg.ModelError, match=r"body 'a': com\[2\]"):
        s.add_body("a", joint=eg.Revolute("q"), mass=1, com=(0, 0, bad))
    with pytest.raises(eg.ModelError, match="body 'a': mass"):
        s.add_body("a", joint=eg.Revolute("q"), mass=bad)
    s.add_body("a", joint=eg.Revolute("q"), mass=1, com=(1, 0, 0))
    with pytest.raises(eg.ModelError, match="spring 'k': stiffness"):
        s.add_spring(("a", (1, 0, 0)), None, bad, name="k")
    with pytest.raises(eg.ModelError, match="motor 'm': resistance"):
        s.add_motor("a", resistance=bad, inductance=1, torque_constant=1, rotor_inertia=1, name="m")
    with pytest.raises(eg.ModelError, match="motor 'm': inductance must be positive"):
        s.add_motor("a", resistance=1, inductance=0, torque_constant=1, rotor_inertia=1, name="m")


def test_damper_with_coinciding_ends_is_refused():
    s = eg.System()
    a = s.add_body("a", joint=eg.Revolute("q1"), mass=1, com=(1, 0, 0))
    s.add_body("b", parent=a, joint=eg.Revolute("q2"), mass=1, com=(1, 0, 0),
               placement=eg.Placement(translation=(1, 0, 0)))
    s.add_damper(("a", (1, 0, 0)), ("b", (0, 0, 0)), 2.0, name="hinge damper")
    with pytest.raises(eg.ModelError, match="load 'hinge damper': its two points coincide at every state"):
        eg.derive(s)


def _urdf(tmp_path, mass="1", izz="0.1", mimic=""):
    path = tmp_path / "two.urdf"
    path.write_text(f"""<robot name="two"><link name="base"/>
      <link name="l1"><inertial><origin xyz="0.5 0 0"/><mass value="{mass}"/>
        <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="{izz}"/></inertial></link>
      <link name="l2"><inertial><mass value="1"/>
        <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
      <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
        <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="1 0 0"/>
        <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>{mimic}</joint></robot>""")
    return path


@pytest.mark.parametrize("mass, izz, message", [
    ("nan", "0.1", "link 'l1': inertial/mass value='nan' must be finite"),
    ("-1", "0.1", "link 'l1': mass must be non-negative"),
    ("1", "nan", "link 'l1': inertial/inertia izz='nan' must be finite"),
    ("heavy", "0.1", "link 'l1': inertial/mass value='heavy' is not a number")])
def test_urdf_bad_numbers_refused(tmp_path, mass, izz, message):
    path = _urdf(tmp_path, mass, izz)
    pin.buildModelFromUrdf(str(path))  # Pinocchio's parser goes on (a massless link): we must not
    with pytest.raises(eg.ModelError, match=message):
        eg.from_urdf(path)


def test_urdf_mimic_refused_or_imported_on_request(tmp_path):
    path = _urdf(tmp_path, mimic='<mimic joint="j1" multiplier="2" offset="0.1"/>')
    with pytest.raises(eg.ModelError, match="joint 'j2' mimics joint 'j1'.*mimic='independent'"):
        eg.from_urdf(path, mimic="refuse")
    with pytest.warns(UserWarning, match=r"mimic joints \['j2'\] imported as independent joints"):
        s = eg.from_urdf(path, mimic="independent")
    assert verify(s, states=3).ok(1e-10)


def test_values_too_large_for_float64_products():
    """1e300 kg is finite, but m l² overflows float64: refused where it enters (also from a URDF)."""
    with pytest.raises(eg.ModelError, match="body 'a': mass: 1e\\+300 is too large"):
        eg.System().add_body("a", joint=eg.Revolute("q"), mass=1e300)
    eg.System().add_body("a", joint=eg.Revolute("q"), mass=1e150)


def test_entry_points_name_their_arguments():
    s = _arm(("q1", "q2", "q3"))
    with pytest.raises(eg.ModelError, match="reduced: lock must be a dict"):
        s.reduced(lock=["q1"])
    with pytest.raises(eg.ModelError, match="random_states: n must be a non-negative integer"):
        eg.random_states(s, -1, np.random.default_rng(0))
    with pytest.raises(eg.ModelError, match="write_c: expected EquationsOfMotion"):
        eg.write_c(s, "/tmp/never")


def test_verify_a_one_joint_robot():
    s = eg.System()
    s.add_body("a", joint=eg.Revolute("q1", axis=(0, 1, 0)), mass=1, com=(0.3, 0, 0.1), inertia=np.eye(3) * 0.1)
    assert verify(s, states=3).ok(1e-10)


def test_spring_rest_length_zero_as_a_float():
    """rest_length=0.0 is sympy's Float(0), which is not == 0: it must still be the zero-length spring
    (F = −k d, no 0/0 when its ends meet), found by the property run."""
    s = eg.System(gravity=(0, 0, 0))
    s.add_body("a", joint=eg.Revolute("q1"), mass=1, com=(1, 0, 0))
    s.add_spring(("a", (0.5, 0.2, 0)), ("a", (0.5, 0.2, 0)), 1.1, rest_length=0.0)
    s.add_spring(("a", (1, 0, 0)), (None, (0, 1, 0)), 2.0, rest_length=0.0, name="to world")
    f = eg.codegen(eg.derive(s))
    for q in (0.0, 0.7, np.pi / 2):  # tip r = (cos q, sin q), F = −k (r − e_y): τ = (r × F)_z = k cos q
        np.testing.assert_allclose(f.tau([q], [0.0]), [2.0 * np.cos(q)], atol=1e-15)
