"""Messages that name what the user must do: swapped arguments, misspelled names, a mass matrix that is
singular because a body carries no mass, all missing parameters at once, the plain C header's names."""
import re

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

import eomgen as eg
from models import cart_pendulum


def test_parent_and_joint_swapped_are_named():
    system, _ = cart_pendulum()
    with pytest.raises(eg.ModelError, match=r"joint 'psi' given as parent and body 'cart' given as joint.*"
                                            r"add_body\(name, parent, joint\)"):
        system.add_body("link", eg.Revolute("psi"), system.body("cart"))
    with pytest.raises(eg.ModelError, match=r"joint 'psi' given as parent; the order"):
        system.add_body("link", eg.Revolute("psi"))
    assert [b.name for b in system.bodies] == ["cart", "pendulum"]


def test_unknown_joint_in_reactions_suggests_the_close_one():
    system, _ = cart_pendulum()
    eom = eg.derive(system, method="free_cut")
    f = eg.codegen(eom)
    params = {"m_c": 1.0, "m_p": 0.5, "l": 0.7, "g": 9.81}
    numeric = f.reactions([0.0, 0.3], [0.0, 0.0], [0.0, 0.0], params=params)
    with pytest.raises(eg.ModelError, match=r"unknown joint 'phy'; did you mean 'phi'\?"):
        f.joint_wrench("phy", [0.0, 0.3], [0.0, 0.0], [0.0, 0.0], params=params)
    for results in (eom.reactions, eom.joint_wrenches, numeric):
        with pytest.raises(eg.ModelError, match=r"unknown joint 'phy'; did you mean 'phi'\? "
                                                r"\(the joints are \['phi', 'x'\]\)"):
            results["phy"]
        with pytest.raises(KeyError):  # still a mapping's error for code that catches KeyError
            results["nothing like it"]


def test_misspelled_load_is_unknown_not_underived():
    system, _ = cart_pendulum()
    system.add_actuator("pendulum", torque=(0, 0, sp.Symbol("T_m")), name="motor")
    system.add_force("cart", (sp.Symbol("F"), 0, 0), name="push")
    eom = eg.derive(system)
    with pytest.raises(eg.ModelError, match=r"unknown load 'motr'; did you mean 'motor'\? "
                                            r"\(the loads are \['motor', 'push'\]\)") as error:
        eom.tau_of("motr")
    assert "quantities" not in str(error.value)
    with pytest.raises(eg.ModelError, match=r"unknown load 'motr'; did you mean 'motor'\?"):
        eg.codegen(eom).tau_of("motr", [0.0, 0.0], [0.0, 0.0], params={"T_m": 1.0})
    assert eom.tau_of("motor") == sp.Matrix([0, sp.Symbol("T_m")])  # the torque on the pendulum's joint
    system.add_torque("cart", (0, 0, 1), name="late")
    with pytest.raises(eg.ModelError, match="load 'late' was added after these equations were derived"):
        eom.tau_of("late")


def leaf_system(n: int, mass_on_axis: bool) -> eg.System:
    """n rods (1 m, 1 kg) turning about z, and a leaf 'hand' on joint 'wrist' that carries no inertia
    about its axis: no mass at all, or a point mass on the axis."""
    system = eg.System(gravity=(0, -9.81, 0))
    parent = None
    for i in range(n):
        parent = system.add_body(f"link{i}", parent=parent, joint=eg.Revolute(f"q_{i}", axis=(0, 0, 1)),
                                 mass=1.0, com=(0.5, 0, 0), inertia=sp.diag(0.001, 0.08, 0.08),
                                 placement=eg.Placement(translation=(1.0 if i else 0.0, 0, 0)))
    system.add_body("hand", parent=parent, joint=eg.Revolute("wrist", axis=(0, 0, 1)),
                    mass=0.5 if mass_on_axis else 0, placement=eg.Placement(translation=(1.0, 0, 0)))
    return system


@settings(max_examples=4, deadline=None)
@given(n=st.integers(1, 3), mass_on_axis=st.booleans(), angles=st.lists(st.floats(-3, 3), min_size=4,
                                                                          max_size=4))
def test_singular_mass_matrix_names_the_leaf(n, mass_on_axis, angles):
    """The wrist's row of M is zero (nothing turns about its axis with inertia): the refusal names the
    wrist and the hand, and no other joint."""
    f = eg.codegen(eg.derive(leaf_system(n, mass_on_axis)))
    q = np.array(angles[:n + 1])
    expected = r"singular: no mass or inertia moves along the speeds of joint 'wrist' \(body 'hand'\)"
    with pytest.raises(eg.ModelError, match=expected) as error:
        f.forward_dynamics(q, np.zeros(n + 1))
    assert not re.search(r"joint 'q_\d'", str(error.value))
    with pytest.raises(eg.ModelError, match=r"at state [01] of the batch.*joint 'wrist'"):
        f.forward_dynamics(np.vstack([q, q]), np.zeros((2, n + 1)))


def test_simulate_names_the_massless_body():
    f = eg.codegen(eg.derive(leaf_system(1, mass_on_axis=False)))
    with pytest.raises(eg.ModelError, match=r"joint 'wrist' \(body 'hand'\)"):
        eg.simulate(f, [0.1, 0.2, 0.0, 0.0], (0.0, 0.1))


def test_linearize_names_every_missing_parameter_at_once():
    system, _ = cart_pendulum()
    eom = eg.derive(system)
    with pytest.raises(eg.ModelError, match=r"values missing for the parameters \['g', 'm_c', 'm_p'\]"):
        eg.linearize(eom, ([0.0, 0.0], [0.0, 0.0]), params={"l": 0.5})
    params = {"l": 0.5, "g": 9.81, "m_c": 1.0, "m_p": 0.3}
    lin = eg.linearize(eom, ([0.0, 0.0], [0.0, 0.0]), params=params)
    # the pendulum hanging down: ẍ and φ̈ from m_c ẍ + m_p l φ̈ = 0, m_p l ẍ + m_p l² φ̈ = −m_p g l φ
    phi_dd = -9.81 * (1.0 + 0.3) / (1.0 * 0.5)
    assert np.isclose(lin.A[3, 1], phi_dd) and np.isclose(lin.A[2, 1], 0.3 * 9.81 / 1.0)


def test_generate_c_frames_speed_names_and_reads(tmp_path, capsys):
    """`eomgen generate --c --frames`: the header names each speed qd_<joint> (the rate of the
    coordinate), writes the frames asked for, and lists each entry a function reads once."""
    from eomgen.__main__ import main

    assert main(["generate", "ur5", "-o", str(tmp_path), "--c", "--name", "ur5", "--frames", "tool0",
                 "wrist_1_link"]) == 0
    header = (tmp_path / "ur5.h").read_text()
    system = eg.robots.load("ur5")
    for k, q in enumerate(system.q):
        assert f" *   u[{k}]: qd_{q} = d/dt q[{k}]" in header
    assert "dot" not in "".join(re.findall(r" \*   u\[\d+\]: .*", header))
    assert "frame tool0" in header and "frame wrist_1_link" in header and "ur5_J_1(" in header
    assert "ur5_J_2(" not in header
    lists = re.findall(r"\b(q|u|ud|p)\[([\d, ]+)\]", " ".join(re.findall(r"reads (.*?)\*/", header, re.S)))
    assert lists
    for arg, ks in lists:
        indices = [int(k) for k in ks.split(",")]
        assert indices == sorted(set(indices)), (arg, indices)
    assert main(["generate", "ur5", "-o", str(tmp_path / "x"), "--c", "--frames", "tool1"]) == 2
    assert "unknown frame 'tool1'" in capsys.readouterr().err
