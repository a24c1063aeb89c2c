"""Every fixed-base robot of example-robot-data against Pinocchio, generated modules, batching,
and URDF input that must not get through."""
import subprocess
import sys
import textwrap

import numpy as np
import pinocchio as pin
import pytest

import eomgen as eg
from eomgen.model.urdf import pinocchio_configuration
from eomgen.verify import random_states, verify

# Every fixed-base robot of example-robot-data 6 that Pinocchio loads. The floating-base ones
# (a1, anymal*, b1*, bolt, go1, hector, hyq, icub*, iris, laikago, romeo, simple_humanoid*,
# solo8, solo12, talos, talos_box, talos_full*) wait for floating-base support; cassie ships
# an SDF and no URDF.
FIXED_BASE = ["allegro_left_hand", "allegro_right_hand", "asr_twodof", "baxter", "double_pendulum",
              "double_pendulum_continuous", "double_pendulum_simple", "finger_edu", "kinova", "panda", "pr2",
              "so100", "so101", "talos_arm", "tiago", "tiago_dual", "tiago_no_hand", "tiago_pro", "ur10",
              "ur10_limited", "ur3", "ur3_gripper", "ur3_limited", "ur5", "ur5_gripper", "ur5_limited",
              "xarm7", "z1"]


def test_the_list_is_complete():
    assert sorted(FIXED_BASE) == eg.robots.names(floating_base=False)


@pytest.mark.parametrize("name", FIXED_BASE)
def test_projected_newton_euler_equals_pinocchio(name):
    """M, b, g and the Jacobians and J̇u of the end frames at 20 random states (relative 1e-10)."""
    report = verify(eg.robots.load(name), states=20, seed=1)
    assert report.errors["M"] and any(k.startswith("J ") for k in report.errors)
    assert report.ok(1e-10), str(report)


@pytest.mark.parametrize("method,name", [(m, r) for m in ("lagrange", "free_cut") for r in ("ur5", "panda")]
                         + [("recursive", r) for r in ("ur5", "panda", "kinova", "baxter", "talos_arm", "tiago")])
def test_other_methods_equal_pinocchio(name, method):
    report = verify(eg.robots.load(name), method=method, states=20, seed=2)
    assert report.ok(1e-10), str(report)


def test_continuous_joints_map_to_cos_sin():
    """kinova's joints 1, 4 and 6 are continuous: Pinocchio stores (cos θ, sin θ)."""
    system = eg.robots.load("kinova")
    assert system.continuous == [True, False, False, True, False, True]
    assert system.pinocchio_model.nq == 9 and system.nq == 6
    q = np.array([0.3, -1.2, 2.0, 0.1, 0.2, 5.0])
    qp = pinocchio_configuration(system, q)
    np.testing.assert_allclose(qp, [np.cos(0.3), np.sin(0.3), -1.2, 2.0, np.cos(0.1), np.sin(0.1), 0.2,
                                    np.cos(5.0), np.sin(5.0)])


def test_armature_from_srdf():
    """talos_arm gets armature = rotor inertia × gear ratio² from talos.srdf, and crba includes it."""
    system = eg.robots.load("talos_arm")
    model = system.pinocchio_model
    assert np.any(model.armature > 0)
    np.testing.assert_allclose([float(b.joint.armature) for b in system.bodies if b.index is not None], model.armature)
    assert verify(system, states=5).ok(1e-10)


def test_batched_evaluation_equals_single_states():
    system = eg.robots.load("panda")
    f = eg.codegen(eg.derive(system))
    q, u, _ = random_states(system, 7, np.random.default_rng(4))
    M, b, g, J = f.M(q), f.b(q, u), f.g(q), f.jacobian("panda_hand", q)
    assert M.shape == (7, 9, 9) and b.shape == (7, 9) and J.shape == (7, 6, 9)
    for k in range(7):
        np.testing.assert_allclose(M[k], f.M(q[k]), rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(b[k], f.b(q[k], u[k]), rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(g[k], f.g(q[k]), rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(J[k], f.jacobian("panda_hand", q[k]), rtol=1e-14, atol=1e-15)


def _run_isolated(code: str, cwd) -> str:
    """Run code in a fresh interpreter where importing eomgen fails."""
    prelude = "import sys\nsys.modules['eomgen'] = None\n"
    out = subprocess.run([sys.executable, "-c", prelude + textwrap.dedent(code)], cwd=cwd,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_written_module_runs_without_eomgen(tmp_path):
    system = eg.robots.load("ur5")
    eom = eg.derive(system)
    path = eg.write_module(eom, tmp_path / "ur5_eom.py")
    again = eg.write_module(eg.derive(eg.robots.load("ur5")), tmp_path / "again.py")
    assert path.read_bytes() == again.read_bytes()  # deterministic: same model, same bytes
    q, u, _ = random_states(system, 3, np.random.default_rng(5))
    np.save(tmp_path / "q.npy", q)
    np.save(tmp_path / "u.npy", u)
    _run_isolated("""
        import numpy as np
        import ur5_eom
        q, u = np.load("q.npy"), np.load("u.npy")
        np.save("out.npy", np.concatenate([ur5_eom.M(q).reshape(3, -1), ur5_eom.b(q, u), ur5_eom.g(q),
                                           ur5_eom.jacobian("tool0", q).reshape(3, -1)], axis=1))
        """, tmp_path)
    out = np.load(tmp_path / "out.npy")
    model = system.pinocchio_model
    data = model.createData()
    fid = model.getFrameId("tool0")
    for k in range(3):
        M = pin.crba(model, data, q[k])
        g = pin.computeGeneralizedGravity(model, data, q[k])
        b = pin.nonLinearEffects(model, data, q[k], u[k]) - g
        J = pin.computeFrameJacobian(model, data, q[k], fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        ref = np.concatenate([(np.triu(M) + np.triu(M, 1).T).ravel(), b, g, J.ravel()])
        np.testing.assert_allclose(out[k], ref, rtol=0, atol=1e-12 * np.abs(ref).max())


EVIL = ['j1"\'\'\'""" ; import os; os.system("touch PWNED") #', "link\n__import__('os').system('touch PWNED')",
        "tip'); open('PWNED','w'); ('"]


def _evil_urdf(path):
    """A two-link arm whose joint and link names carry quotes, newlines (&#10;) and Python code."""
    esc = [n.replace("&", "&amp;").replace('"', "&quot;").replace("\n", "&#10;").replace("<", "&lt;") for n in EVIL]
    path.write_text(f"""<?xml version="1.0"?>
<robot name="evil&#10;import os">
  <link name="base"/>
  <link name="{esc[1]}">
    <inertial><origin xyz="0.1 0 0"/><mass value="1.5"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>
  </link>
  <link name="{esc[2]}">
    <inertial><origin xyz="0 0.2 0"/><mass value="0.5"/>
      <inertia ixx="0.003" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.003"/></inertial>
  </link>
  <joint name="{esc[0]}" type="revolute">
    <parent link="base"/><child link="{esc[1]}"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="{esc[2]}&#10;x = 1" type="revolute">
    <parent link="{esc[1]}"/><child link="{esc[2]}"/><origin xyz="0.3 0 0" rpy="0.3 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
</robot>
""")
    return path


def test_names_from_urdf_cannot_inject_code(tmp_path):
    system = eg.from_urdf(_evil_urdf(tmp_path / "evil.urdf"))
    assert system.bodies[1].name == EVIL[1] and system.joints[0].name == EVIL[0]
    assert verify(system, states=5).ok(1e-10)
    eg.write_module(eg.derive(system), tmp_path / "evil_eom.py", title="evil\n'''\"\"\"import os")
    out = _run_isolated("""
        import numpy as np
        import evil_eom
        print(evil_eom.FRAMES)
        print(evil_eom.M([0.3, -0.4]).tolist(), evil_eom.jacobian(evil_eom.FRAMES[1], [0.3, -0.4]).shape)
        """, tmp_path)
    assert not (tmp_path / "PWNED").exists()
    assert EVIL[1].replace("\n", "\\n") in out


def test_bad_urdf_files(tmp_path):
    with pytest.raises(eg.ModelError, match="URDF file not found"):
        eg.from_urdf(tmp_path / "missing.urdf")
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='x'><link name='a'></robot")
    with pytest.raises(eg.ModelError, match="cannot read URDF"):
        eg.from_urdf(broken)
    planar = tmp_path / "planar.urdf"
    planar.write_text("""<robot name="p"><link name="a"/><link name="b"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
      <joint name="slider_xy" type="planar"><parent link="a"/><child link="b"/></joint></robot>""")
    with pytest.raises(eg.ModelError, match="joint 'slider_xy': a planar joint moves in the plane normal"):
        eg.from_urdf(planar)
    with pytest.raises(eg.ModelError, match="unknown robot 'ur55'"):
        eg.robots.load("ur55")


def test_command_line(tmp_path):
    from eomgen.__main__ import main

    assert main(["verify", "double_pendulum", "--states", "3"]) == 0
    assert main(["verify", "double_pendulum", "--states", "3", "--backend", "c", "--method", "recursive"]) == 0
    assert main(["generate", "asr_twodof", "-o", str(tmp_path / "two.py")]) == 0
    assert (tmp_path / "two.py").read_text().startswith('"""Equations of motion')
    assert main(["generate", "ur5", "-o", str(tmp_path / "c"), "--c", "--name", "ur5"]) == 0
    header = (tmp_path / "c" / "ur5.h").read_text()
    assert "ur5_M(" in header and "ur5_J_0(" in header and (tmp_path / "c" / "ur5.c").exists()
    assert main(["generate", "ur5", "-o", str(tmp_path / "c"), "--c", "--name", "not a C name"]) == 2
    assert main(["verify", "no_such_robot"]) == 2
