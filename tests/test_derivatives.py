"""The inverse dynamics and the derivatives of the dynamics as generated functions: equal to Pinocchio's
rnea, computeRNEADerivatives and computeABADerivatives on robots of example-robot-data and on random trees
with every joint type built with Pinocchio's own API (1e-10 relative to each matrix's size), to central
finite differences along `eg.integrate` of eomgen's own forward dynamics (loads: springs and dampers; a ZYX
Euler base, which Pinocchio does not have; a flexible link), the same numbers from every output path
(NumPy, C extension, written module, plain C), and bad calls refused."""
from __future__ import annotations

import importlib.util
import subprocess
import warnings

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import eomgen as eg
from test_outputs import load as load_module
import strategies as S
from models import JOINTS, close, joint_chain
from eomgen.model import pinocchio_configuration
from eomgen.verify import to_pinocchio

SETTINGS = dict(
    deadline=None,
    derandomize=True,
    database=None,
    phases=[Phase.generate],
    suppress_health_check=list(HealthCheck),
)


def pinocchio_values(model, qp, u, ud, tau, data=None) -> list[np.ndarray]:
    """[rnea, ∂τ/∂q, ∂τ/∂u, ∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ] (copies: Pinocchio returns views of `data`)."""
    data = model.createData() if data is None else data
    values = [pin.rnea(model, data, qp, u, ud)]
    values += pin.computeRNEADerivatives(model, data, qp, u, ud)[:2]
    values = [np.array(x) for x in values]
    return values + [np.array(x) for x in pin.computeABADerivatives(model, data, qp, u, tau)]


def ours(f, q, u, ud, tau) -> list[np.ndarray]:
    return [
        f.inverse_dynamics(q, u, ud),
        *f.inverse_dynamics_derivatives(q, u, ud),
        *f.forward_dynamics_derivatives(q, u, tau),
    ]


NAMES = ["inverse dynamics", "∂τ/∂q", "∂τ/∂u", "∂u̇/∂q", "∂u̇/∂u", "∂u̇/∂τ"]


def load(name: str) -> eg.System:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # files with inertias Pinocchio takes as they are
        return eg.robots.load(name)


@pytest.mark.parametrize(
    "name, method, backend",
    [
        ("ur5", "recursive", "numpy"),
        ("ur5", "recursive", "c"),
        ("panda", "projected_newton_euler", "numpy"),
        ("solo12", "recursive", "numpy"),
        pytest.param("talos", "recursive", "numpy", marks=pytest.mark.slow),
    ],
)
def test_robots_equal_pinocchio(name, method, backend, generated):
    """At 3 random states and efforts (talos: armature; solo12: a quaternion free flyer; panda: the inverse
    dynamics by the recursion on the kinematics of another method); batched states equal single ones."""
    system = load(name)
    f = generated(name, method, backend)
    model = to_pinocchio(system)
    data = model.createData()
    rng = np.random.default_rng(7)
    q, u, ud = eg.random_states(system, 3, rng)
    tau = rng.uniform(-5, 5, u.shape)
    for k in range(3):
        expected = pinocchio_values(model, pinocchio_configuration(system, q[k]), u[k], ud[k], tau[k], data)
        for what, x, y in zip(NAMES, ours(f, q[k], u[k], ud[k], tau[k]), expected):
            close(x, y, 1e-10, f"{name}: {what}, state {k}")
    for what, batch, one in zip(NAMES, ours(f, q, u, ud, tau), ours(f, q[1], u[1], ud[1], tau[1])):
        close(batch[1], one, 1e-13, f"{name}: batched {what}")
    close(
        f.forward_dynamics_derivatives(q, u, tau[0])[1][2],
        ours(f, q[2], u[2], ud[2], tau[0])[4],
        1e-13,
        f"{name}: one τ for every state",
    )


def pinocchio_order(tree, ref, matrices) -> list[np.ndarray]:
    """eomgen's vectors and matrices in Pinocchio's order of the speeds."""
    p = ref.perm
    return [x[p] if x.ndim == 1 else x[np.ix_(p, p)] for x in matrices]


# Pinocchio 4.1's derivative algorithms miss the rate of a motion subspace that turns with the joint's own
# coordinates (SphericalZYX, Universal): they differ from differences of its own rnea and aba by O(1)
QUIRKS = {"zyx", "universal"}


def differences(fn, n: int, h: float = 1e-4) -> np.ndarray:
    """The columns (−fn(2h e_j) + 8 fn(h e_j) − 8 fn(−h e_j) + fn(−2h e_j)) / 12h (fourth order)."""
    return np.array(
        [(-fn(2 * h * e) + 8 * fn(h * e) - 8 * fn(-h * e) + fn(-2 * h * e)) / (12 * h) for e in np.eye(n)]
    ).T


def pinocchio_differences(model, qp, u, ud, tau, mimic: bool = False) -> list[np.ndarray]:
    """As `pinocchio_values`, from Pinocchio's rnea and forward dynamics alone (q moved along
    pinocchio.integrate): aba, or with a mimic joint (which aba refuses) CRBA's M⁻¹ (τ − b − g), on fresh
    data
    (Pinocchio 4.1's crba on used data is wrong there)."""
    n = model.nv

    def rnea(dq, du):
        return pin.rnea(model, model.createData(), pin.integrate(model, qp, dq), u + du, ud)

    def forward(dq, du, dt):
        q, data = pin.integrate(model, qp, dq), model.createData()
        if not mimic:
            return pin.aba(model, data, q, u + du, tau + dt)
        M = np.triu(pin.crba(model, data, q))
        return np.linalg.solve(M + np.triu(M, 1).T, tau + dt - pin.nonLinearEffects(model, data, q, u + du))

    zero = np.zeros(n)
    return [
        rnea(zero, zero),
        differences(lambda d: rnea(d, zero), n),
        differences(lambda d: rnea(zero, d), n),
        differences(lambda d: forward(d, zero, zero), n),
        differences(lambda d: forward(zero, d, zero), n),
        differences(lambda d: forward(zero, zero, d), n),
    ]


@pytest.mark.parametrize("name", [*JOINTS, "armature"])
def test_joint_types_equal_pinocchio(name):
    """Every joint type in a chain of three bodies (`models.joint_chain`, Pinocchio's by `to_pinocchio`;
    "armature": a revolute with rotor inertia) at 2 random states: against Pinocchio's derivative algorithms
    (1e-10), or for a ZYX or universal joint (`QUIRKS`) and a mimic joint (which they refuse) against
    fourth-order differences of Pinocchio's rnea and forward dynamics (1e-8)."""
    joint = JOINTS[name]() if name in JOINTS else eg.Revolute("r1", axis=(1, 0, 0), armature=0.05)
    system = joint_chain(joint)
    f = eg.codegen(eg.derive(system, method="recursive"))
    model = to_pinocchio(system)
    rng = np.random.default_rng(5)
    q, u, ud = eg.random_states(system, 2, rng)
    tau = rng.uniform(-3, 3, u.shape)
    analytic = name not in ("universal", "spherical_zyx", "mimic")
    for k in range(2):
        qp = pinocchio_configuration(system, q[k])
        expected = (
            pinocchio_values(model, qp, u[k], ud[k], tau[k])
            if analytic
            else pinocchio_differences(model, qp, u[k], ud[k], tau[k], mimic=name == "mimic")
        )
        for what, x, y in zip(NAMES, ours(f, q[k], u[k], ud[k], tau[k]), expected):
            close(x, y, 1e-10 if analytic else 1e-8, f"{name}: {what}, state {k}")


def massive(tree) -> None:
    """Every body with mass (a massless body on a joint makes M singular: no forward dynamics), and helical
    pitches below 1e-300 set to 0 (Pinocchio 4.1's rnea and crba disagree for denormal pitches)."""
    for b in tree.bodies:
        b.pitch = 0.0 if abs(b.pitch) < 1e-300 else b.pitch
        if b.mass == 0:
            b.mass, b.inertia = 0.5, ((0.01, 0, 0), (0, 0.02, 0), (0, 0, 0.025))


@settings(max_examples=20, **SETTINGS)
@given(
    tree=S.trees(max_bodies=5, loads=False), method=st.sampled_from(["recursive", "projected_newton_euler"])
)
def test_random_trees_equal_pinocchio(tree, method):
    """Every joint type (speeds permuted into Pinocchio's depth-first order): against Pinocchio's derivative
    algorithms (1e-10), or with a ZYX or universal joint (`QUIRKS`) against fourth-order differences of its
    rnea and aba (1e-8), the trees made `massive`; the forward dynamics' derivatives are compared where M is
    well conditioned (cond < 1e6), as both sides solve with it."""
    massive(tree)
    f = eg.codegen(eg.derive(S.eomgen_system(tree), method=method))
    ref = S.PinocchioTree(tree)
    rng = np.random.default_rng(len(tree.bodies))
    q, u = S.random_state(tree, rng)
    ud, tau = rng.uniform(-2, 2, u.shape), rng.uniform(-2, 2, u.shape)
    p = ref.perm
    quirks = any(b.kind in QUIRKS for b in tree.bodies)
    reference = pinocchio_differences if quirks else pinocchio_values
    expected = reference(ref.model, ref.configuration(q), u[p], ud[p], tau[p])
    values = pinocchio_order(
        tree, ref, [f.inverse_dynamics(q, u, ud), *f.inverse_dynamics_derivatives(q, u, ud)]
    )
    if np.linalg.cond(f.M(q)) < 1e6:
        values += pinocchio_order(tree, ref, f.forward_dynamics_derivatives(q, u, tau))
    for what, x, y in zip(NAMES, values, expected):
        close(x, y, 1e-8 if quirks else 1e-10, what)


# --- finite differences of eomgen's own functions ----------------------------------------------------------
def spring_damper_system() -> eg.System:
    """A quaternion free flyer, a hinge and a ball joint, with a spring to the world, a damper between the
    bodies and a force in body axes."""
    system = eg.System()
    inertia = np.diag([0.02, 0.03, 0.04])
    system.add_body("base", joint=eg.FreeFlyer("base"), mass=2.0, com=(0.05, 0.0, 0.01), inertia=inertia)
    system.add_body(
        "arm",
        parent="base",
        joint=eg.Revolute("hinge", axis=(0, 1, 0)),
        mass=1.0,
        com=(0.2, 0, 0),
        inertia=inertia,
        placement=eg.Placement(translation=(0.1, 0.0, 0.05)),
    )
    system.add_body(
        "hand",
        parent="arm",
        joint=eg.Spherical("wrist"),
        mass=0.5,
        com=(0.05, 0.02, 0),
        inertia=inertia / 2,
        placement=eg.Placement(translation=(0.4, 0.0, 0.0)),
    )
    system.add_spring(("hand", (0.1, 0.0, 0.0)), (None, (0.3, -0.2, 1.0)), 40.0, 0.3, name="spring")
    system.add_damper(("hand", (0.0, 0.1, 0.0)), ("base", (0.0, 0.0, 0.2)), 2.5, name="damper")
    system.add_force("arm", (0.0, 1.0, 3.0), (0.2, 0.0, 0.0), in_body_frame=True, name="push")
    return system


def central(system, fn, q, u) -> tuple[np.ndarray, np.ndarray]:
    """(∂fn/∂q, ∂fn/∂u) by fourth-order central differences, q moved along `eg.integrate` (the tangent
    space)."""
    n = len(u)
    return (
        differences(lambda d: fn(eg.integrate(system, q, d, 1.0), u), n),
        differences(lambda d: fn(q, u + d), n),
    )


@pytest.mark.parametrize(
    "build",
    [spring_damper_system, lambda: eg.robots.load("solo12", base="euler")],
    ids=["spring_damper", "solo12_euler"],
)
def test_finite_differences(build):
    """The derivatives equal central differences (to 1e-8 of each matrix's size) of
    M u̇ + b + g and of u̇ = forward_dynamics + M⁻¹ τ: loads (spring, damper, force) enter ∂u̇/∂q and ∂u̇/∂u;
    a ZYX Euler base (no Pinocchio counterpart) is differentiated in its angles."""
    system = build()
    f = eg.codegen(eg.derive(system, method="recursive"))
    rng = np.random.default_rng(3)
    q, u, ud = (x[0] for x in eg.random_states(system, 1, rng))
    tau = rng.uniform(-3, 3, len(u))

    def inverse(q, u):
        return f.M(q) @ ud + f.nle(q, u)

    def forward(q, u):
        return f.forward_dynamics(q, u) + np.linalg.solve(f.M(q), tau)

    close(f.inverse_dynamics(q, u, ud), inverse(q, u), 1e-12, "inverse dynamics = M u̇ + b + g")
    for what, x, y in zip(
        ["∂τ/∂q", "∂τ/∂u"], f.inverse_dynamics_derivatives(q, u, ud), central(system, inverse, q, u)
    ):
        close(x, y, 1e-8, what)
    Fq, Fu, Ft = f.forward_dynamics_derivatives(q, u, tau)
    for what, x, y in zip(["∂u̇/∂q", "∂u̇/∂u"], (Fq, Fu), central(system, forward, q, u)):
        close(x, y, 1e-8, what)
    close(Ft, np.linalg.inv(f.M(q)), 1e-10, "∂u̇/∂τ = M⁻¹")


# --- every output path ------------------------------------------------------------------------------------
DRIVER = r"""#include <stdio.h>
#include <string.h>
#include "eom.h"

int main(void)
{
    double q[EOM_NQ], u[EOM_NV], ud[EOM_NV], tau[EOM_NV], p[EOM_NP + 1];
    double ID[EOM_NV], D[2 * EOM_NV * EOM_NV], F[3 * EOM_NV * EOM_NV];
    for (;;) {
        for (int i = 0; i < EOM_NQ; i++) if (scanf("%lf", &q[i]) != 1) return 0;
        for (int i = 0; i < EOM_NV; i++) if (scanf("%lf", &u[i]) != 1) return 1;
        for (int i = 0; i < EOM_NV; i++) if (scanf("%lf", &ud[i]) != 1) return 1;
        for (int i = 0; i < EOM_NV; i++) if (scanf("%lf", &tau[i]) != 1) return 1;
        memset(ID, 0, sizeof ID); memset(D, 0, sizeof D);
        eom_ID(q, u, ud, p, ID);
        eom_ID_derivatives(q, u, ud, p, D);
        eom_FD_derivatives(q, u, tau, p, F);
        for (int i = 0; i < EOM_NV; i++) printf("%.17g ", ID[i]);
        for (int i = 0; i < 2 * EOM_NV * EOM_NV; i++) printf("%.17g ", D[i]);
        for (int i = 0; i < 3 * EOM_NV * EOM_NV; i++) printf("%.17g ", F[i]);
        printf("\n");
    }
}
"""


def plain_c(eom, folder, states) -> list[list[np.ndarray]]:
    """ID, (∂τ/∂q, ∂τ/∂u), (∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ) per state from write_c's C (cc -Wall -Werror)."""
    c_path, _ = eg.write_c(eom, folder, name="eom")
    (folder / "driver.c").write_text(DRIVER)
    exe = folder / "driver"
    build = subprocess.run(
        [
            "cc",
            "-O1",
            "-std=c99",
            "-Wall",
            "-Werror",
            f"-I{folder}",
            str(folder / "driver.c"),
            str(c_path),
            "-o",
            str(exe),
            "-lm",
        ],
        capture_output=True,
        text=True,
    )
    assert build.returncode == 0, build.stderr[-3000:]
    text = "".join(" ".join(repr(float(x)) for x in np.concatenate(state)) + "\n" for state in states)
    run = subprocess.run([str(exe)], input=text, capture_output=True, text=True, timeout=60)
    n = len(eom.u)
    out = []
    for line in run.stdout.splitlines():
        x = np.array([float(v) for v in line.split()])
        ID, D, F = np.split(x, [n, n + 2 * n * n])
        D, F = D.reshape(n, 2 * n), F.reshape(n, 3 * n)
        out.append([ID, D[:, :n], D[:, n:], F[:, :n], F[:, n : 2 * n], F[:, 2 * n :]])
    return out


def check_outputs(system, folder) -> None:
    """The C extension (one state and batched), the written module and plain C equal NumPy (1e-12)."""
    eom = eg.derive(system, method="recursive")
    f, fc = eg.codegen(eom), eg.codegen(eom, backend="c")
    spec = importlib.util.spec_from_file_location("written", eg.write_module(eom, folder / "written.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    rng = np.random.default_rng(11)
    q, u, ud = eg.random_states(system, 3, rng)
    tau = rng.uniform(-3, 3, u.shape)
    expected = [ours(f, q[k], u[k], ud[k], tau[k]) for k in range(3)]
    paths = {
        "C": [ours(fc, q[k], u[k], ud[k], tau[k]) for k in range(3)],
        "C batched": [[x[k] for x in ours(fc, q, u, ud, tau)] for k in range(3)],
        "module": [ours(module, q[k], u[k], ud[k], tau[k]) for k in range(3)],
        "plain C": plain_c(eom, folder, list(zip(q, u, ud, tau))),
    }
    for path, values in paths.items():
        assert len(values) == 3, path
        for k in range(3):
            for what, x, y in zip(NAMES, values[k], expected[k]):
                close(x, y, 1e-12, f"{path}: {what}, state {k}")


def test_outputs_agree(tmp_path):
    """A free flyer with a spring, a damper and a force (∂τ_loads in the forward dynamics' derivatives)."""
    check_outputs(spring_damper_system(), tmp_path)


@settings(max_examples=2, **SETTINGS)
@given(tree=S.trees(max_bodies=4))
def test_random_tree_outputs_agree(tree, tmp_path_factory):
    """Random trees with every joint type and loads."""
    massive(tree)
    check_outputs(S.eomgen_system(tree), tmp_path_factory.mktemp("tree"))


def test_flexible_link_from_the_compact_forms():
    """A flexible link: τ_ID = M u̇ + b + g of Lagrange's compact forms; its derivatives (bending in τ_loads)
    equal central differences."""
    beam = eg.System(gravity=(0, -9.81, 0))
    beam.add_body(
        "link", joint=eg.FlexibleLink("theta", length=1.0, mass_per_length=2.0, EI=3.0, elements=2)
    )
    f = eg.codegen(eg.derive(beam, method="lagrange"))
    rng = np.random.default_rng(4)
    q, u, ud = (x[0] for x in eg.random_states(beam, 1, rng))
    tau = rng.uniform(-1, 1, len(u))
    close(f.inverse_dynamics(q, u, ud), f.M(q) @ ud + f.nle(q, u), 1e-13, "M u̇ + b + g")

    def forward(q, u):
        return f.forward_dynamics(q, u) + np.linalg.solve(f.M(q), tau)

    for what, x, y in zip(
        ["∂u̇/∂q", "∂u̇/∂u"], f.forward_dynamics_derivatives(q, u, tau), central(beam, forward, q, u)
    ):
        close(x, y, 1e-8, what)


def test_bad_calls_are_refused(generated):
    system = eg.robots.load("ur5")
    f = generated("ur5", "recursive", "numpy")  # its derivatives built once per worker
    q, u, ud = (x[0] for x in eg.random_states(system, 1, np.random.default_rng(0)))
    with pytest.raises(eg.ModelError, match=r"u: expected shape \(6,\), got \(5,\)"):
        f.inverse_dynamics(q, u[:5], ud)
    with pytest.raises(eg.ModelError, match=r"ud: expected shape \(6,\), got \(7,\)"):
        f.inverse_dynamics_derivatives(q, u, np.r_[ud, 0.0])
    with pytest.raises(eg.ModelError, match=r"tau: expected 6 finite values \(one per speed\)"):
        f.forward_dynamics_derivatives(q, u, np.ones(5))
    with pytest.raises(eg.ModelError, match=r"tau: expected 6 finite values"):
        f.forward_dynamics_derivatives(q, u, [np.nan] * 6)
    with pytest.raises(eg.ModelError, match=r"tau: expected 6 real numbers \(one per speed\), got str"):
        f.forward_dynamics_derivatives(q, u, "ones")
    g_only = eg.codegen(eg.derive(system, method="recursive", quantities=("g",)))
    close(g_only.inverse_dynamics(q, u, ud), f.inverse_dynamics(q, u, ud), 1e-13, "ID of g-only equations")
    with pytest.raises(
        eg.ModelError, match=r"forward_dynamics_derivatives needs M, b and g; derived: \['g'\]"
    ):
        g_only.forward_dynamics_derivatives(q, u)
    kane = eg.codegen(eg.kane(joint_chain(eg.Revolute("r1", axis=(1, 0, 0)))))
    for call in (
        kane.inverse_dynamics,
        kane.inverse_dynamics_derivatives,
        kane.forward_dynamics_derivatives,
    ):
        with pytest.raises(
            eg.ModelError, match="generated for EquationsOfMotion .*not for Kane's equations"
        ):
            call(q[:3], u[:3], ud[:3])
    looped = load_module(Path(__file__).parents[1] / "examples" / "four_bar.py").four_bar()
    for backend in ("numpy", "c"):  # u̇ of a loop is the constrained dynamics': refused, not unconstrained
        h = eg.codegen(eg.derive(looped, method="recursive"), backend=backend)
        with pytest.raises(eg.ModelError, match=r"constraint rows \['.*'\].*eg.linearize"):
            h.forward_dynamics_derivatives(np.zeros(h.nq), np.zeros(h.nv))
    limp = eg.System()  # a massless link on a joint: M is singular
    limp.add_body("a", joint=eg.Revolute("r0"), mass=1.0, com=(0.3, 0, 0), inertia=np.eye(3) * 0.1)
    limp.add_body("b", parent="a", joint=eg.Revolute("r1", axis=(1, 0, 0)), mass=0.0)
    for backend in ("numpy", "c"):
        h = eg.codegen(eg.derive(limp, method="recursive"), backend=backend)
        with pytest.raises(eg.ModelError, match="M is not positive definite at this state"):
            h.forward_dynamics_derivatives(np.zeros(2), np.zeros(2))
    beam = eg.System(gravity=(0, -9.81, 0))  # a flexible link, which the recursion does not cover
    beam.add_body(
        "link", joint=eg.FlexibleLink("theta", length=1.0, mass_per_length=2.0, EI=3.0, elements=1)
    )
    with pytest.raises(eg.ModelError, match=r"prescribed motion is M u̇ \+ b \+ g: derive \['M', 'b'\] too"):
        eg.codegen(eg.derive(beam, method="lagrange", quantities=("g",))).inverse_dynamics(
            np.zeros(3), np.zeros(3), np.zeros(3)
        )
    fc = generated("ur5", "recursive", "c")
    with pytest.raises(eg.ModelError, match=r"tau: expected shape \(6,\)"):
        fc.forward_dynamics_derivatives(q, u, np.ones(5))
    with pytest.raises(ValueError, match=r"u: expected shape \(6,\)"):
        fc.inverse_dynamics_derivatives(q, u[:5], ud)
