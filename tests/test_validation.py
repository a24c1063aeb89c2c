"""Bad input gets a clear error naming the body, joint, frame or field."""
import numpy as np
import pytest
import sympy as sp

import eomgen as eg
from eomgen import ModelError
from models import cart_pendulum


def _system():
    return eg.System(gravity=(0, 0, -9.81))


def test_negative_mass():
    with pytest.raises(ModelError, match="body 'arm'.*mass"):
        _system().add_body("arm", joint=eg.Revolute("q"), mass=-1)


def test_noncommutative_symbol():
    """The engines take every symbol as commuting (symengine has no other kind): one that does not is
    refused where it enters."""
    m = sp.Symbol("m", commutative=False)
    with pytest.raises(ModelError, match="body 'arm'.*mass.*does not commute"):
        _system().add_body("arm", joint=eg.Revolute("q"), mass=m)


def test_inertia_not_symmetric():
    with pytest.raises(ModelError, match="body 'arm'.*symmetric"):
        _system().add_body("arm", joint=eg.Revolute("q"), mass=1, inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])
    a, b = sp.symbols("a b")
    with pytest.raises(ModelError, match="body 'arm'.*symmetric"):
        _system().add_body("arm", joint=eg.Revolute("q"), mass=1, inertia=[[1, a, 0], [b, 1, 0], [0, 0, 1]])


def test_inertia_not_positive_semidefinite():
    with pytest.raises(ModelError, match="body 'arm'.*positive semidefinite"):
        _system().add_body("arm", joint=eg.Revolute("q"), mass=1, inertia=np.diag([1.0, -0.1, 1.0]).tolist())


def test_inertia_triangle_inequality():
    with pytest.raises(ModelError, match="body 'arm'.*triangle"):
        _system().add_body("arm", joint=eg.Revolute("q"), mass=1, inertia=np.diag([1.0, 1.0, 3.0]).tolist())


def test_unknown_parent():
    with pytest.raises(ModelError, match="body 'arm'.*unknown parent 'base'"):
        _system().add_body("arm", parent="base", joint=eg.Revolute("q"), mass=1)


def test_parent_from_another_system():
    other = _system().add_body("base", joint=eg.Revolute("q0"), mass=1)
    with pytest.raises(ModelError, match="body 'arm'.*unknown parent 'base'"):
        _system().add_body("arm", parent=other, joint=eg.Revolute("q"), mass=1)


def test_loop_in_tree():
    with pytest.raises(ModelError, match="body 'arm'.*own parent"):
        _system().add_body("arm", parent="arm", joint=eg.Revolute("q"), mass=1)


def test_duplicate_names():
    s = _system()
    s.add_body("arm", joint=eg.Revolute("q1"), mass=1)
    with pytest.raises(ModelError, match="duplicate name 'arm'"):
        s.add_body("arm", joint=eg.Revolute("q2"), mass=1)
    with pytest.raises(ModelError, match="duplicate name 'arm'"):
        s.add_frame("arm", body="arm")
    s.add_force("arm", (1, 0, 0), name="push")
    with pytest.raises(ModelError, match="duplicate load name 'push'"):
        s.add_force("arm", (1, 0, 0), name="push")


def test_coordinate_used_twice():
    s = _system()
    s.add_body("a", joint=eg.Revolute("q"), mass=1)
    with pytest.raises(ModelError, match="body 'b'.*coordinate 'q'"):
        s.add_body("b", parent="a", joint=eg.Prismatic(sp.Symbol("q")), mass=1)


def test_unsupported_joint_type():
    with pytest.raises(ModelError, match="body 'arm'.*unsupported joint type str"):
        _system().add_body("arm", joint="ball", mass=1)


def test_bad_axis_and_placement():
    with pytest.raises(ModelError, match="joint 'q'.*axis must not be zero"):
        eg.Revolute("q", axis=(0, 0, 0))
    with pytest.raises(ModelError, match="joint 'q'.*axis.*3-vector"):
        eg.Revolute("q", axis=(0, 1))
    with pytest.raises(ModelError, match="placement.rotation is not a proper rotation"):
        eg.Placement(rotation=[[1, 0, 0], [0, 1, 0], [0, 0, -1]])
    with pytest.raises(ModelError, match="placement.translation"):
        eg.Placement(translation=(1, 2))


def test_non_finite_and_bad_shapes():
    with pytest.raises(ModelError, match="body 'arm': com.*finite"):
        _system().add_body("arm", joint=eg.Revolute("q"), mass=1, com=(float("nan"), 0, 0))
    with pytest.raises(ModelError, match="body 'arm': inertia.*3×3"):
        _system().add_body("arm", joint=eg.Revolute("q"), mass=1, inertia=[[1, 0], [0, 1]])
    with pytest.raises(ModelError, match="gravity"):
        eg.System(gravity=(0, -9.81))


def test_unknown_body_in_load_and_frame():
    s, _ = cart_pendulum()
    with pytest.raises(ModelError, match="unknown body 'wheel'"):
        s.add_force("wheel", (1, 0, 0))
    with pytest.raises(ModelError, match="unknown body 'wheel'"):
        s.add_frame("rim", body="wheel")
    with pytest.raises(ModelError, match="cannot read a point"):
        s.add_spring(42, "tip", stiffness=1)


def test_negative_spring_constants():
    s, _ = cart_pendulum()
    with pytest.raises(ModelError, match="spring .spring0.: stiffness must be non-negative"):
        s.add_spring(None, "tip", stiffness=-3)
    with pytest.raises(ModelError, match="damper .damper0.: damping must be non-negative"):
        s.add_damper(None, "tip", damping=-1)


def test_derive_errors():
    with pytest.raises(ModelError, match="no bodies"):
        eg.derive(_system())
    s = _system()
    s.add_body("arm", joint=eg.Revolute("q"), mass=0)
    with pytest.raises(ModelError, match="total mass"):
        eg.derive(s)
    s, _ = cart_pendulum()
    with pytest.raises(ModelError, match="unknown method 'kane2'"):
        eg.derive(s, method="kane2")
    with pytest.raises(ModelError, match="unknown backend 'fortran'"):
        eg.codegen(eg.derive(s), backend="fortran")


def test_generated_functions_check_their_input():
    s, _ = cart_pendulum()
    f = eg.codegen(eg.derive(s))
    p = {"m_c": 1.0, "m_p": 0.5, "l": 0.7, "g": 9.81}
    with pytest.raises(ValueError, match=r"q: expected shape \(2,\)"):
        f.M([0.0, 0.1, 0.2], p)
    with pytest.raises(ValueError, match="u: contains NaN"):
        f.b([0.0, 0.1], [np.nan, 0.0], p)
    with pytest.raises(ModelError, match="values missing for the parameters.*'m_p'"):
        f.M([0.0, 0.1], {"m_c": 1.0, "l": 0.7, "g": 9.81})
    with pytest.raises(ModelError, match="unknown frame 'hand'"):
        f.jacobian("hand", [0.0, 0.1], p)
    with pytest.raises(ModelError, match="unknown load 'motor'"):
        f.tau_of("motor", [0.0, 0.1], [0.0, 0.0], p)
