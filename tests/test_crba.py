"""The composite rigid body algorithm's meetings (`Recursion._meetings`): a column's momentum moves up
the tree, or the ancestors' subspaces come down to meet it. Whichever way a pair meets, M is
Pinocchio's crba; on bushy trees the meetings make M cheaper than moving every column to the root."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import eomgen as eg
import strategies as S
from eomgen.functions import catalogue
from eomgen.printers.walker import writer
from eomgen.methods.recursive import Recursion
from eomgen.model import pinocchio_configuration
from eomgen.verify import mass_matrix, to_pinocchio
from models import close


def hand(free: bool) -> eg.System:
    """An arm (four revolute joints, a spherical wrist) carrying four fingers of three revolute joints, with
    tilted placements, off-axis centres of mass and a mimic joint on the last finger."""
    rng = np.random.default_rng(3)
    system = eg.System(gravity=(0, 0, -9.81))

    def body(name, parent, joint, translation):
        rotation = pin.rpy.rpyToMatrix(*rng.uniform(-1, 1, 3))
        return system.add_body(
            name,
            parent=parent,
            joint=joint,
            mass=rng.uniform(0.2, 2),
            com=tuple(rng.uniform(-0.1, 0.1, 3)),
            inertia=np.diag(rng.uniform(0.02, 0.03, 3)),
            placement=eg.Placement(rotation=rotation, translation=translation),
        )

    root = eg.FreeFlyer("base") if free else eg.Revolute("yaw", axis=(0, 0, 1))
    base = body("base", None, root, (0, 0, 0))
    link = base
    for k, axis in enumerate([(0, 1, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]):
        link = body(f"arm{k}", link, eg.Revolute(f"arm{k}", axis=axis), (0.05, 0, 0.3))
    palm = body("palm", link, eg.Spherical("wrist"), (0.4, 0, 0))
    for f in range(4):
        link = palm
        for k in range(3):
            mimic = ("finger3_0", 0.7, 0.1) if (f, k) == (3, 2) else None
            joint = eg.Revolute(f"finger{f}_{k}", axis=tuple(rng.normal(size=3)), mimic=mimic)
            link = body(f"phalanx{f}_{k}", link, joint, (0.05 + 0.02 * f, 0.03 * k, 0.02))
    return system


def ops(system) -> int:
    eom = eg.derive(system, method="recursive")
    return writer(catalogue(eom)).source("M", eom.compact["M"], True)[2]


def test_meetings_give_pinocchio_crba_with_fewer_operations(monkeypatch):
    system = hand(free=True)
    meetings = Recursion(eg.derive(system, quantities=()).kinematics)._meetings()
    assert meetings[system.body("palm")]  # the arm's subspaces come down to the palm
    f = eg.codegen(eg.derive(system, method="recursive"))
    model = to_pinocchio(system)
    data = model.createData()
    q, _, _ = eg.random_states(system, 5, np.random.default_rng(0))
    for k, q_k in enumerate(q):
        close(f.M(q_k), mass_matrix(model, data, pinocchio_configuration(system, q_k)), 1e-10, f"M {k}")
    met = ops(system)
    monkeypatch.setattr(Recursion, "_meetings", lambda self: dict.fromkeys(self.bodies, False))
    every_column_up = ops(system)
    assert met < 0.92 * every_column_up, (met, every_column_up)


@settings(
    max_examples=12,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(tree=S.trees(max_bodies=10, loads=False, frames=0), up=st.booleans())
def test_random_trees_either_way_equal_pinocchio(tree, up):
    """Bushy random trees of every joint type: M = Pinocchio's crba whether the pairs meet by the rule or
    every column moves to the root."""
    with pytest.MonkeyPatch.context() as mp:
        if up:
            mp.setattr(Recursion, "_meetings", lambda self: dict.fromkeys(self.bodies, False))
        f = eg.codegen(eg.derive(S.eomgen_system(tree), method="recursive"))
    ref = S.PinocchioTree(tree)
    rng = np.random.default_rng(len(tree.bodies))
    for k in range(3):
        q, u = S.random_state(tree, rng)
        close(f.M(q), ref.dynamics(q, u)[0], 1e-9, f"M, state {k}")
