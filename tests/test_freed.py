"""Equations that are dropped are freed by reference counting at once: nothing a derivation builds refers
back to what holds it (a cycle would leave every object of it, hundreds of thousands for a big robot, to
Python's cycle collector, which walks them again at each of its passes until it frees them)."""
from __future__ import annotations

import gc
import weakref
from types import SimpleNamespace

import numpy as np
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


def test_dropped_c_functions_free_their_equations_and_the_kept_ones_still_batch_in_lanes(monkeypatch):
    """Two codegens of one model share its extension module, which stays imported with its first-batch
    hook: dropping one frees its equations (the hook holds their vector printing weakly), and the other's
    first batch still compiles the vector functions, once, and equals its per-state values."""
    from eomgen.printers import c_extension

    made = []
    monkeypatch.setattr(c_extension, "lanes_module",
                        lambda *args, real=c_extension.lanes_module: made.append(args) or real(*args))
    kept, dropped = (eg.codegen(eg.derive(spatial_arm_3dof()), backend="c") for _ in range(2))
    assert dropped.generated("M").function.__self__ is kept.generated("M").function.__self__
    held = [weakref.ref(x) for x in (dropped.eom, dropped.eom.kinematics.sub)]
    del dropped
    gc.collect()
    assert [ref() for ref in held] == [None] * len(held)
    params = {str(p): 1.0 + 0.1 * k for k, p in enumerate(kept.eom.system.parameters)}
    q = np.random.default_rng(5).uniform(-2, 2, (9, 3))
    batch = kept.M(q, params)
    assert len(made) == 1
    np.testing.assert_allclose(batch, [kept.M(qk, params) for qk in q], rtol=1e-14, atol=1e-14)


def test_the_first_batch_hook_survives_a_collection_that_frees_a_queued_printing(monkeypatch):
    """A dropped codegen of the module, left in a reference cycle, may be freed by a collection that the
    hook's own allocations start: the hook still attaches the kept one's vector functions (iterating the
    queue while it shrank raised, and left every later batch one state at a time)."""
    from eomgen.printers import c_extension

    class Module:
        def __init__(self, name: str) -> None:
            self.__name__, self.attached = name, False

        def _attach(self, lanes) -> None:
            self.attached = True

    monkeypatch.setattr(c_extension, "lanes_module", lambda *args: SimpleNamespace(lanes=None))
    threshold, enabled = gc.get_threshold(), gc.isenabled()
    gc.enable()
    try:
        for young in range(60):  # a collection at each point of the hook in turn
            module, kept = Module(f"eomgen_hook_{young}"), (lambda: [])
            gc.collect(0)  # the young generation counted from here
            attach = c_extension.first_batch(module, kept, 1, 1, 0)
            dropped = lambda: []  # noqa: E731
            dropped.cycle = dropped
            c_extension.first_batch(module, dropped, 1, 1, 0)
            del dropped
            gc.set_threshold(young)
            attach()
            gc.set_threshold(*threshold)
            assert module.attached, young
    finally:
        gc.set_threshold(*threshold)
        if not enabled:
            gc.disable()


def test_functions_swept_from_this_process_are_kept_while_their_sweep_is():
    """`eg.sweep` runs a chunk in this process with the functions it was given, not copies, as long as
    its tasks are held (a task copied in this process finds them by their model's token), and keeps
    nothing of them once the tasks are dropped."""
    import pickle

    from eomgen.sweep import model as swept

    f = eg.codegen(eg.derive(spatial_arm_3dof()))
    model = swept(f)
    held = [weakref.ref(x) for x in (f, f.eom)]
    del f
    gc.collect()
    assert model.functions() is held[0]()
    assert pickle.loads(pickle.dumps(model)).functions() is held[0]()
    del model
    gc.collect()
    assert [ref() for ref in held] == [None] * len(held)
