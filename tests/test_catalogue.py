"""The function catalogue walked on a model with every feature (loads of each kind, a DC motor, a
contact, a loop, a rolling disk on a free flyer, frames, the free cut): every function it offers exists
in every target — the NumPy functions, the C extension, the written module and plain C — under its
public name, and all targets compute the same numbers. A function added to the catalogue without a
target fails here, naming the target."""
from __future__ import annotations

import ctypes
import functools
import importlib.util
import shutil
import subprocess

import numpy as np
import pytest
import sympy as sp

import eomgen as eg
from eomgen.functions import catalogue
from eomgen.printers.plain_c import c_name

PARAMS = {"g": 9.81, "k": 40.0, "i_m": 0.3, "U_m": 2.0}


@functools.cache
def everything(constraints: bool = True) -> eg.EquationsOfMotion:
    """The model; without `constraints` no contact, loop or rolling disk (the forward dynamics' derivatives
    are offered only then)."""
    g, k = sp.symbols("g k", positive=True)
    s = eg.System(gravity=(0, 0, -g))
    cart = s.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=2.0)
    arm = s.add_body("arm", parent=cart, joint=eg.Revolute("a", axis=(0, 1, 0)), mass=1.0, com=(0.4, 0, 0),
                     inertia=np.diag([0.01, 0.02, 0.03]))
    fore = s.add_body("fore", parent=arm, joint=eg.Revolute("b", axis=(0, 1, 0)), mass=0.5, com=(0.3, 0, 0),
                      placement=eg.Placement(translation=(0.8, 0, 0)), inertia=np.diag([0.01, 0.01, 0.02]))
    s.add_frame("tip", fore, eg.Placement(translation=(0.6, 0, 0)))
    s.add_frame("anchor", None, eg.Placement(translation=(1.0, 0, 0.2)))
    s.add_body("wheel", joint=eg.FreeFlyer("w"), mass=1.5, inertia=np.diag([0.03, 0.06, 0.03]))
    s.add_frame("foot", fore, eg.Placement(translation=(0.2, 0, -0.1)))
    if constraints:
        s.add_loop("tip", "anchor", kind="point", name="closure")
        s.add_rolling("wheel", 0.3, axis=(0, 1, 0), name="roll")
        s.add_contact("foot")
    s.add_force("fore", (0, 0, 1.5), point=(0.1, 0, 0), name="push")
    s.add_torque("arm", (0, 0.3, 0), name="twist")
    s.add_spring("arm", "fore", k, rest_length=0.2, name="spring")
    s.add_damper("cart", "fore", 0.7, name="damper")
    s.add_motor("arm", resistance=1.2, inductance=0.1, torque_constant=0.05, rotor_inertia=0.01,
                gear_ratio=10, name="m")
    return eg.derive(s, method="free_cut")


def members(cat):
    """Every function of the catalogue, each family's for every item."""
    return [*cat, *(family.of(item) for family in cat.families.values() for item in family.items)]


def raw(fn, value) -> np.ndarray:
    """A public function's result as the (rows, cols) output of the catalogue (`Function.form`)."""
    if fn.form == "columns":
        return np.hstack(value)
    if fn.form == "pose":
        return np.hstack([value[0], value[1][:, None]])
    if fn.form == "wrench":
        return np.concatenate(value)[:, None]
    return np.reshape(value, fn.shape)


def arguments(fn, q, u, ud) -> list:
    """The inputs of `fn` (a composite's tau in the place of u̇)."""
    given = {"q": q, "u": u, "ud": ud, "tau": ud}
    return [given[x.strip()] for x in fn.inputs.split(",")]


def public_call(target, fn, q, u, ud, params):
    """fn by its public name in a target (NumPy, C or a written module)."""
    args = ([fn.item] if fn.item is not None else []) + arguments(fn, q, u, ud)
    return raw(fn, getattr(target, fn.name)(*args, params=params))


def close(a, b, what: str) -> None:
    scale = max(1.0, float(np.abs(b).max()))
    assert np.abs(np.asarray(a, float) - b).max() <= 1e-11 * scale, what


def plain_c(eom, tmp_path):
    """write_c of every frame, compiled and loaded: (library, C name of a function)."""
    cat = catalogue(eom)
    frames = list(cat.families["J"].items)
    c_path, _ = eg.write_c(eom, tmp_path, name="every", frames=frames)
    library = tmp_path / "libevery.so"
    compiler = shutil.which("cc") or "cc"
    subprocess.run([compiler, "-O1", "-shared", "-fPIC", str(c_path), "-o", str(library), "-lm"], check=True)
    return ctypes.CDLL(str(library)), lambda fn: f"every_{c_name(cat, fn, frames)}"


def c_call(lib, name: str, fn, q, u, ud, p) -> np.ndarray:
    out = np.zeros(fn.shape)
    arrays = [np.ascontiguousarray(x, dtype=float) for x in (q, u, ud, p)]
    pointers = [x.ctypes.data_as(ctypes.c_void_p) for x in (*arrays, out)]
    getattr(lib, name)(*pointers)
    return out


EXPECTED = {"M", "b", "g", "tau", "T", "U", "qdot", "com", "J_com", "A_G", "ID", "ID_derivatives", "Y", "Y_T",
            "Y_U", "J", "Jdot_u", "X", "W", "R"}


@pytest.mark.parametrize("constraints, offered", [(True, {"J_c", "Jdot_c_u", "closure"}),
                                                  (False, {"FD_derivatives"})])
def test_every_function_is_in_every_target_and_agrees(constraints, offered, tmp_path, monkeypatch):
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path / "cache"))
    eom = everything(constraints)
    cat = catalogue(eom)
    f, fc = eg.codegen(eom), eg.codegen(eom, backend="c")
    fc.generate([fn.key for fn in members(cat) if not fn.composite])  # one module, one compile
    path = eg.write_module(eom, tmp_path / "every_module.py")
    spec = importlib.util.spec_from_file_location("every_module", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    lib, c_names = plain_c(eom, tmp_path)
    q, u, ud = (x[0] for x in eg.random_states(eom.system, 1, np.random.default_rng(7)))
    p = np.array(f.parameters.vector(PARAMS, range(len(f.params))))
    public = [fn for fn in members(cat) if fn.public]
    assert {fn.key.split(":")[0] for fn in public} == EXPECTED | offered
    for fn in public:
        for target, name in ((f, "NumPy"), (fc, "the C extension"), (module, "the written module")):
            assert hasattr(target, fn.name), f"{name} lacks {fn.name} ({fn.key})"
        reference = public_call(f, fn, q, u, ud, PARAMS)
        if not fn.composite:
            close(reference, f.call(fn.key, q, u, ud, PARAMS), f"{fn.key}: the public function ≠ its output")
        close(public_call(fc, fn, q, u, ud, PARAMS), reference, f"{fn.key}: C extension ≠ NumPy")
        close(public_call(module, fn, q, u, ud, PARAMS), reference, f"{fn.key}: written module ≠ NumPy")
        assert hasattr(lib, c_names(fn)), f"plain C lacks {c_names(fn)} ({fn.key})"
        close(c_call(lib, c_names(fn), fn, q, u, ud, p), reference, f"{fn.key}: plain C ≠ NumPy")
    for fn in members(cat):  # the building blocks: the same in the extension
        if not fn.public and not fn.composite:
            expected = f.call(fn.key, q, u, ud, PARAMS)
            close(fc.call(fn.key, q, u, ud, PARAMS), expected, f"{fn.key}: C ≠ NumPy")


def test_the_numbers_are_the_equations():
    """Independent checks of the catalogue's meaning at one state: τ_ID = M u̇ + b + g, the reactions'
    wrench of the free cut is the joint wrench less its motion part, J_c's loop rows are d/dt of the closure
    residual (finite differences), q̇ integrates the quaternion."""
    eom = everything()
    f = eg.codegen(eom)
    q, u, ud = (x[0] for x in eg.random_states(eom.system, 1, np.random.default_rng(8)))
    M, nle = f.M(q, PARAMS), f.nle(q, u, PARAMS)
    close(f.inverse_dynamics(q, u, ud, PARAMS), M @ ud + nle, "ID ≠ M u̇ + b + g")
    h = 1e-6
    dr = (f.closure_residual(eg.integrate(eom.system, q, u, h), PARAMS)
          - f.closure_residual(eg.integrate(eom.system, q, u, -h), PARAMS)) / (2 * h)
    rows = f.closure_index
    np.testing.assert_allclose(f.contact_jacobian(q, PARAMS)[rows] @ u, dr, atol=1e-6)
    dq = (eg.integrate(eom.system, q, u, h) - eg.integrate(eom.system, q, u, -h)) / (2 * h)
    np.testing.assert_allclose(f.qdot(q, u, PARAMS), dq, atol=1e-6)


def test_a_function_the_model_lacks_is_refused_with_the_reason():
    f = eg.codegen(eg.derive(everything(False).system, method="recursive", quantities=("g",)))
    with pytest.raises(eg.ModelError, match="M was not derived"):
        f.M(np.zeros(f.nq))
    with pytest.raises(eg.ModelError, match="free cut"):
        f.joint_wrench("a", np.zeros(f.nq), np.zeros(f.nv), np.zeros(f.nv))
    with pytest.raises(eg.ModelError, match="needs M, b and g"):
        f.forward_dynamics_derivatives(np.zeros(f.nq), np.zeros(f.nv))
    with pytest.raises(eg.ModelError, match="the system has no contacts, loops or rolling disks"):
        f.contact_jacobian(np.zeros(f.nq))
    constrained = eg.codegen(everything())
    with pytest.raises(eg.ModelError, match="constraint rows"):
        constrained.forward_dynamics_derivatives(np.zeros(constrained.nq), np.zeros(constrained.nv))
