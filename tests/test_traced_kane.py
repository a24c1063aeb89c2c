"""Kane's equations in the JAX and CasADi targets equal the NumPy ones: every piece of the Kane catalogue,
the mass matrix, forcing, speeds, rhs and energy, one state and batches (JAX: its own batch and vmap), on
a rolling disk (nonholonomic, a dependent coordinate) and a four-bar (a closed loop: holonomic constraints,
speeds by kinematic equations); JAX's own derivative (jacfwd, under jit) of rhs equals a central finite
difference of the NumPy rhs, as does CasADi's jacobian of its rhs, one casadi.Function. Slow: every catalogue entry of the JAX and CasADi functions of panda and
talos equals NumPy's, with their construction times."""
from __future__ import annotations

import sys
import time
from pathlib import Path

import jax
import numpy as np
import pytest

import eomgen as eg
import kane_systems as K
from eomgen.functions import catalogue, kane_catalogue
from test_catalogue import members, public_call
from test_traced_targets import close

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from rolling_disk import VALUES, rolling_disk  # noqa: E402


def disk():
    """The rolling disk: (Kane's equations, parameter values, consistent states q (z by the contact))."""
    kane = rolling_disk()[1]
    q = np.random.default_rng(3).uniform(-1, 1, (3, 6))
    return kane, VALUES, eg.codegen(kane).assemble(q, VALUES)


def four_bar():
    """The four-bar in the links' absolute rates: (Kane's equations, no parameters, poses by hand)."""
    system, args = K.four_bar("absolute")
    poses = np.array([K.four_bar_pose(x) for x in np.random.default_rng(4).uniform(-np.pi, np.pi, 3)])
    return eg.kane(system, **args), None, poses


SYSTEMS = {"rolling disk": disk, "four-bar": four_bar}
ALGORITHMS = ("mass_matrix", "forcing", "joint_speeds", "dependent_speeds", "qdot", "active_forces")


@pytest.fixture(scope="module", params=list(SYSTEMS))
def system(request):
    """(Kane's equations, params, efforts τ_a, states [q, u, w in the place of u̇, w_ind, x = [q, w_ind]]
    of three states, the NumPy, JAX and CasADi functions)."""
    kane, params, Q = SYSTEMS[request.param]()
    f = eg.codegen(kane)
    rng = np.random.default_rng(5)
    U, WD = rng.normal(size=(2, len(Q), f._nu))
    W = rng.normal(size=(len(Q), f.nv))
    states = [Q, U, WD, W, np.c_[Q, W]]
    tau = np.linspace(0.5, 1.5, len(kane.system.actuated))
    return kane, params, tau, states, f, eg.codegen(kane, backend="jax"), eg.codegen(kane, backend="casadi")


def numbers(f, kane, params, tau, q, u, wd, w, x, algorithms=ALGORITHMS) -> dict:
    """Every piece of the catalogue at (q, u, wd), the `algorithms` at (q, w), rhs at x = [q, w] of target
    f."""
    out = {key: f.call(key, q, u, wd, params) for key in kane_catalogue(kane).functions}
    out.update({name: getattr(f, name)(q, w, params) for name in algorithms})
    return {**out, "rhs": f.rhs(0, x, tau, params)}


def agree(results: dict, expected: dict, what: str) -> None:
    for key, value in expected.items():
        close(results[key], value, 1e-12, f"{key}: {what}")


def test_every_piece_and_algorithm_equals_numpy(system):
    """CasADi: every piece (also as casadi.Function) and every algorithm, one state and three. JAX under
    jit: every piece, mass_matrix, forcing, rhs and energy of one state; rhs of three states, as a batch
    and by vmap."""
    kane, params, tau, states, f, fj, fc = system
    one = [x[0] for x in states]
    for at in (one, states):
        expected = numbers(f, kane, params, tau, *at)
        agree(numbers(fc, kane, params, tau, *at), expected, "CasADi")
        close(fc.energy(at[-1], params), f.energy(at[-1], params), 1e-12, "energy: CasADi")
    p = [[params[str(s)] for s in fc.params]] if fc.params else []  # the vector p, sorted by name
    for key in kane_catalogue(kane).functions:
        close(fc.casadi[key](*one[:3], *p).full(), f.call(key, *one[:3], params), 1e-12, f"{key}: casadi")

    algorithms = ("mass_matrix", "forcing")
    traced = jax.jit(lambda *at: (numbers(fj, kane, params, tau, *at, algorithms), fj.energy(at[-1], params)))
    results, energy = traced(*one)
    agree(results, numbers(f, kane, params, tau, *one, algorithms), "JAX")
    close(energy, f.energy(one[-1], params), 1e-12, "energy: JAX")
    X = states[-1]
    rhs = jax.jit(lambda X: (fj.rhs(0, X, tau, params), jax.vmap(lambda x: fj.rhs(0, x, tau, params))(X)))
    for result, what in zip(rhs(X), ("JAX, three states", "JAX, vmap")):
        close(result, f.rhs(0, X, tau, params), 1e-12, f"rhs: {what}")


@pytest.mark.parametrize("system", ["four-bar", pytest.param("rolling disk", marks=pytest.mark.slow)],
                         indirect=True)  # XLA compiles the disk's Jacobian in seconds
def test_jacfwd_of_rhs_is_the_finite_difference_of_numpy(system):
    """∂ẋ/∂x by jax.jacfwd (under jit) against (ẋ(x + h e_i) − ẋ(x − h e_i)) / 2h of the NumPy rhs,
    h = 1e-6 (truncation ~h², round-off ~ε/h: both below 1e-8)."""
    kane, params, tau, states, f, fj, _ = system
    jacobian = jax.jit(jax.jacfwd(lambda x: fj.rhs(0, x, tau, params)))
    h, x = 1e-6, states[-1][1]
    steps = h * np.eye(len(x))
    difference = (f.rhs(0, x + steps, tau, params) - f.rhs(0, x - steps, tau, params)).T / (2 * h)
    close(jacobian(x), difference, 1e-6, "jacfwd of rhs")


def test_the_casadi_rhs_is_one_function_equal_to_numpys(system):
    """f.casadi["rhs"] (x, tau_a[, p]) → ẋ, one casadi.Function on SX: equal to the NumPy rhs to 1e-12 at
    three states; CasADi's jacobian of it equals a central difference of the NumPy rhs (h = 1e-6) to
    1e-6; a CasADi integrator (CVODES) of it over 0.05 s equals scipy's solve_ivp of the NumPy rhs."""
    import casadi as ca
    from scipy.integrate import solve_ivp

    kane, params, tau, states, f, _, fc = system
    rhs, p = fc.casadi["rhs"], [[params[str(s)] for s in fc.params]] if fc.params else []
    assert rhs.name_in()[:2] == ["x", "tau_a"] and rhs.name_out() == ["xdot"]
    for x in states[-1]:
        close(rhs(x, tau, *p).full()[:, 0], f.rhs(0, x, tau, params), 1e-12, "casadi rhs")
    x = ca.SX.sym("x", f.nx)
    jacobian = ca.Function("J", [x], [ca.jacobian(rhs(x, tau, *p), x)])
    h, x0 = 1e-6, states[-1][1]
    steps = h * np.eye(len(x0))
    difference = (f.rhs(0, x0 + steps, tau, params) - f.rhs(0, x0 - steps, tau, params)).T / (2 * h)
    close(jacobian(x0).full(), difference, 1e-6, "casadi jacobian of rhs")
    ode = {"x": x, "ode": rhs(x, tau, *p)}
    flow = ca.integrator("flow", "cvodes", ode, 0, 0.05, {"abstol": 1e-12, "reltol": 1e-12})
    reference = solve_ivp(lambda t, y: f.rhs(t, y, tau, params), (0, 0.05), x0, rtol=1e-12, atol=1e-12)
    close(flow(x0=x0)["xf"].full()[:, 0], reference.y[:, -1], 1e-8, "casadi integrator of rhs")


def test_a_flat_disk_is_refused_by_both_targets():
    kane = rolling_disk()[1]
    flat = np.array([0, 0, 0, 0, np.pi / 2, 0.0])
    for backend in ("jax", "casadi"):
        with pytest.raises(eg.ModelError, match="rolling disk .* lies flat"):
            eg.codegen(kane, backend=backend).mass_matrix(flat, np.ones(3), VALUES)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["ur5", "panda", "solo12", "talos"])
def test_robots_every_catalogue_entry(name):
    """Every function and every family member (all frames) of JAX and CasADi equals NumPy's; prints the
    construction times (codegen, then every entry printed)."""
    eom = eg.derive(eg.robots.load(name))
    f = eg.codegen(eom)
    q, u, ud = (x[0] for x in eg.random_states(eom.system, 1, np.random.default_rng(7)))
    for backend in ("jax", "casadi"):
        start = time.perf_counter()
        target = eg.codegen(eom, backend=backend)
        built = time.perf_counter() - start
        entries = members(catalogue(eom))
        target.generate([fn.key for fn in entries if not fn.composite])
        printed = time.perf_counter() - start
        for fn in entries:
            if fn.composite:
                if backend == "jax":
                    expected = public_call(f, fn, q, u, ud, None)
                    close(public_call(target, fn, q, u, ud, None), expected, 1e-12, f"{fn.key}: {backend}")
                continue
            close(target.call(fn.key, q, u, ud), f.call(fn.key, q, u, ud), 1e-12, f"{fn.key}: {backend}")
        checked = time.perf_counter() - start
        print(f"{name} {backend}: codegen {built:.1f} s, {len(entries)} entries printed {printed:.1f} s, "
              f"checked {checked:.1f} s")
