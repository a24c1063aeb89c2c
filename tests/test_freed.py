"""Equations that are dropped are freed by reference counting at once: nothing a derivation builds refers
back to what holds it (a cycle would leave every object of it, hundreds of thousands for a big robot, to
Python's cycle collector, which walks them again at each of its passes until it frees them)."""
from __future__ import annotations

import gc
import weakref

import pytest

import eomgen as eg
from models import spatial_arm_3dof

METHODS = ["recursive", "lagrange", "projected_newton_euler", "free_cut"]


@pytest.mark.parametrize("method", METHODS)
def test_a_dropped_derivation_is_freed_at_once(method):
    """The equations, their kinematics and intermediates are gone when the last name of them is dropped,
    after the world placements, a frame's Jacobian and J̇ u and the closed forms were formed."""
    eom = eg.derive(spatial_arm_3dof(), method=method, frames=["link3"])
    kin = eom.kinematics
    kin.R[kin.system.bodies[-1]], kin.columns[kin.system.bodies[0]], eom.M, eom.U
    held = [weakref.ref(x) for x in (eom, kin, kin.sub, kin.sub.engine)]
    del eom, kin
    assert [ref() for ref in held] == [None] * len(held)


def test_dropped_generated_functions_free_their_equations():
    """Generated functions hold their equations, whose function catalogue refers back to them: the cycle
    collector frees them all once the functions are dropped (a catalogue kept aside, keyed weakly by the
    equations, kept every equations ever generated)."""
    f = eg.codegen(eg.derive(spatial_arm_3dof()))
    f.M([0.1, 0.2, 0.3], params={str(p): 1.0 for p in f.eom.system.parameters})
    held = [weakref.ref(x) for x in (f.eom, f.eom.kinematics.sub)]
    del f
    gc.collect()
    assert [ref() for ref in held] == [None] * len(held)
