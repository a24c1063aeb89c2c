"""World placements formed on first reading (`eomgen.placements`), and the recursive method's potential
energy, which reads none of them (the gravity pass in body axes).

- A deep body read first is placed with its ancestors in a loop (no recursion per ancestor), and
  the intermediates are the same whichever body is read first.
- The placements answer like a mapping: None and bodies of other systems are not in it.
- U of the recursive method equals U through the world placements (projected Newton-Euler: −Σ m g⃗ · r_S)
  and U written out by hand for the bodies welded to the world, on what random trees seldom draw: a
  free-flyer base on a rotated placement, a mimic joint, a body welded to the world and a fixed child,
  a massless body, a spring, symbolic gravity and mass, in both engines."""
from __future__ import annotations

import inspect
import sys

import numpy as np
import pytest
import sympy as sp

import eomgen as eg
from eomgen.kinematics import Kinematics


def chain(n: int) -> eg.System:
    system, parent = eg.System(), None
    for i in range(n):
        joint = eg.Revolute(f"q{i}", axis=(0, 0, 1) if i % 2 else (0, 1, 0))
        parent = system.add_body(f"l{i}", parent, joint, mass=1, com=(0.5, 0, 0),
                                 placement=eg.Placement(translation=(1 if i else 0, 0, 0)))
    return system


def test_a_deep_body_read_first_is_placed_with_its_ancestors_in_a_loop():
    """Placing does not recurse per ancestor: 150 links read from the leaf with 100 frames to spare (a
    recursion per ancestor needs two frames each: a 500-link chain hits Python's default limit)."""
    system = chain(150)
    kin, leaf, limit = Kinematics(system), system.bodies[-1], sys.getrecursionlimit()
    sys.setrecursionlimit(len(inspect.stack()) + 100)
    try:
        R = kin.R[leaf]
    finally:
        sys.setrecursionlimit(limit)
    assert R.shape == (3, 3) and len(kin.chain[leaf]) == 150 and kin.J_R(leaf).shape == (3, 150)


def test_the_same_intermediates_whichever_body_is_read_first():
    system = chain(6)
    first_leaf, in_order = Kinematics(system), Kinematics(system)
    first_leaf.R[system.bodies[-1]]
    for body in system.bodies:
        in_order.R[body]
    assert [sp.srepr(x) for x in first_leaf.sub.definitions.values()] == \
        [sp.srepr(x) for x in in_order.sub.definitions.values()]


def test_the_placements_hold_the_systems_bodies_alone():
    system, other = chain(2), chain(2)
    kin = Kinematics(system)
    assert None not in kin.R and kin.chain.get(None, []) == [] and list(kin.p) == list(system.bodies)
    with pytest.raises(KeyError):
        kin.R[other.bodies[0]]


def awkward() -> eg.System:
    gx, gy, gz, m, k = sp.symbols("gx gy gz m k")
    system = eg.System(gravity=(gx, gy, gz))
    base = system.add_body("base", None, eg.FreeFlyer("root"), mass=m, com=(0.1, -0.2, 0.05),
                           inertia=np.diag([1.0, 2.0, 3.0]).tolist(),
                           placement=eg.Placement(rotation=sp.rot_axis1(0.3), translation=(0.2, 0.1, -0.4)))
    arm = system.add_body("arm", base, eg.Revolute("a", axis=(1, 2, 2)), mass=1.5, com=(0.3, 0.1, 0.2),
                          placement=eg.Placement(translation=(0.1, 0.2, 0.3)))
    system.add_body("tool", arm, eg.Fixed("t"), mass=0.7, com=(0.1, 0.0, -0.1),
                    placement=eg.Placement(rotation=sp.rot_axis3(0.4), translation=(0.0, 0.3, 0.0)))
    system.add_body("finger", arm, eg.Revolute("f", axis=(0, 0, 1), mimic=("a", 2.0, 0.3)), mass=0.9,
                    com=(0.2, 0.1, 0.0), placement=eg.Placement(translation=(0.4, 0.0, 0.1)))
    welded = system.add_body("pedestal", None, eg.Fixed("w"), mass=2.0, com=(0.3, 0.4, 0.5),
                             placement=eg.Placement(rotation=sp.rot_axis2(0.7), translation=(1.0, 2.0, 3.0)))
    system.add_body("lamp", welded, eg.Fixed("l"), mass=0.5, com=(0.0, 0.1, 0.0),
                    placement=eg.Placement(translation=(0.0, 0.0, 1.0)))
    system.add_body("slider", arm, eg.Prismatic("s", axis=(0, 1, 0)), mass=0)
    system.add_spring(("finger", (0.1, 0.0, 0.0)), (None, (0.5, 0.5, 0.5)), stiffness=k, rest_length=0.2)
    return system


@pytest.mark.parametrize("engine", ["sympy", "symengine"])
def test_the_recursive_potential_energy_equals_the_world_placements_one(engine):
    system, rng = awkward(), np.random.default_rng(3)
    params = {str(p): rng.uniform(0.5, 1.5) for p in system.parameters}
    g = np.array([params["gx"], params["gy"], params["gz"]])
    R2, R1 = np.array(sp.rot_axis2(0.7), float), np.eye(3)
    welded = -2.0 * g @ (np.array([1.0, 2.0, 3.0]) + R2 @ [0.3, 0.4, 0.5]) \
        - 0.5 * g @ (np.array([1.0, 2.0, 3.0]) + R2 @ ([0.0, 0.0, 1.0] + R1 @ [0.0, 0.1, 0.0]))
    f = {m: eg.codegen(eg.derive(system, method=m, engine=engine))
         for m in ("recursive", "projected_newton_euler")}
    for _ in range(3):
        q = rng.uniform(-1, 1, len(system.q))
        U = float(np.ravel(f["recursive"].U(q, params))[0])
        assert U == pytest.approx(float(np.ravel(f["projected_newton_euler"].U(q, params))[0]), abs=1e-12)
    still = eg.System(gravity=(params["gx"], params["gy"], params["gz"]))  # the welded bodies alone, and
    pedestal = still.add_body("pedestal", None, eg.Fixed("w"), mass=2.0, com=(0.3, 0.4, 0.5),  # one joint
                              placement=eg.Placement(rotation=sp.rot_axis2(0.7), translation=(1.0, 2.0, 3.0)))
    still.add_body("lamp", pedestal, eg.Fixed("l"), mass=0.5, com=(0.0, 0.1, 0.0),
                   placement=eg.Placement(translation=(0.0, 0.0, 1.0)))
    still.add_body("massless", None, eg.Revolute("r", axis=(0, 0, 1)), mass=0)
    U = eg.codegen(eg.derive(still, engine=engine)).U([0.4])
    assert float(np.ravel(U)[0]) == pytest.approx(welded, abs=1e-12)
