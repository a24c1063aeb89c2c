"""The functions of an `EquationsOfMotion` beyond its quantities, each with its inputs, shape and the
expression it is built from: the centre of mass and centroidal momentum (`eomgen.centroidal`), the
constraint rows and closure residual (`Kinematics`), the inverse dynamics and the derivatives of the
dynamics (`eomgen.inverse_dynamics`), q̇(q, u), the building blocks of the numeric algorithms
(`expressions`) and the families per frame, load and joint. Each that the model lacks gets its reason in
`missing`."""
from __future__ import annotations

import sympy as sp

from .. import centroidal as momentum
from ..constraint_rows import tilts
from ..eom import EquationsOfMotion
from ..errors import ModelError, unknown
from ..inverse_dynamics import available, dynamics_jacobian, inverse_dynamics, unavailable
from ..regressor import full_regressor, links, missing_reason, speeds
from .catalogue import Family, Function
from .expressions import (centres, closure_frames, forward_parts, lengths, line_loads, nonconservative,
                          placement)


# the derivatives of the dynamics: printed together in C (a composite after its parts), left out by
# write_c(derivatives=False)
DERIVATIVES = ("ID_derivatives", "FD_jacobian", "FD_parts", "FD_derivatives")


def forward_dynamics(eom: EquationsOfMotion) -> bool:
    """Whether the forward dynamics (and its derivatives) are there: M, b, g derived."""
    return {"M", "b", "g"} <= set(eom.compact)


def forward_key(eom: EquationsOfMotion) -> str:
    """The key of D = ∂(τ_ID − τ_loads)/∂(q, u): the inverse dynamics' own Jacobian without loads."""
    return "FD_jacobian" if eom.load_names else "ID_derivatives"


def centroidal(eom: EquationsOfMotion, missing: dict) -> list[Function]:
    """c, J_com and A_G where the system has moving mass and no flexible link."""
    kin, nv = eom.kinematics, len(eom.u)
    try:
        momentum.total_mass(kin)
    except ModelError as error:
        missing.update(dict.fromkeys(("com", "J_com", "A_G"), str(error)))
        return []
    moving = [j.name for j in eom.system.prescribed]
    if moving:
        missing["A_G"] = (f"A_G: the momentum of joint '{moving[0]}''s prescribed motion is no column of A_G "
                          "(A_G u misses it)")
    return [Function("com", "com", "centre of mass c (world)", "q", (3, 1), lambda: momentum.com(kin),
                     "vector"),
            Function("J_com", "com_jacobian", "J_com (3 x NV), the Jacobian of the centre of mass", "q",
                     (3, nv), lambda: momentum.com_jacobian(kin)),
            Function("A_G", "centroidal_momentum_matrix", "A_G (6 x NV): [linear momentum; angular momentum "
                     "about c] per unit speed, world axes", "q", (6, nv),
                     lambda: momentum.centroidal_momentum_matrix(kin))][:2 if moving else 3]


def constraints(eom: EquationsOfMotion, missing: dict) -> list[Function]:
    """J_c and J̇_c u with contacts, loops or rolling disks; the closure residual with loops or disks."""
    system, kin, nv = eom.system, eom.kinematics, len(eom.u)
    rows, closure = tuple(system.constraint_rows()), tuple(system.closure_rows())
    found = []
    if rows:
        found += [Function("J_c", "contact_jacobian", "J_c: the stacked rows of every contact, loop and "
                           "rolling disk, world-aligned axes", "q", (len(rows), nv),
                           lambda: kin.constraint_jacobian()[0], rows=rows),
                  Function("Jdot_c_u", "contact_jacobian_dot_u", "J̇_c u, stacked like J_c's rows", "q, u",
                           (len(rows), 1), lambda: kin.constraint_jacobian()[1], "vector", rows=rows)]
    else:
        missing.update(dict.fromkeys(("J_c", "Jdot_c_u"), "the system has no contacts, loops or rolling "
                                     "disks: add them with System.add_contact, add_loop or add_rolling"))
    if closure:
        found.append(Function("closure", "closure_residual", "the loops' and rolling disks' position "
                              "residuals, zero when closed", "q", (len(closure), 1), kin.closure_residual,
                              "vector", rows=closure))
    else:
        missing["closure"] = ("the system has no loops or rolling disks: add them with System.add_loop or "
                              "System.add_rolling")
    return found


def dynamics(eom: EquationsOfMotion, missing: dict) -> list[Function]:
    """The inverse dynamics, D (where it can be formed) and, with M, b, g and no constraints, the forward
    dynamics' derivatives (a composite of [M | h] and D)."""
    nv, rows = len(eom.u), eom.system.constraint_rows()
    if not available(eom):
        missing.update(dict.fromkeys(("ID", "ID_derivatives", "FD_derivatives"), unavailable(eom)))
        return []
    found = [Function("ID", "inverse_dynamics", "τ = M u̇ + b + g, one recursive Newton-Euler pass",
                      "q, u, ud", (nv, 1), lambda: inverse_dynamics(eom), "vector"),
             Function("ID_derivatives", "inverse_dynamics_derivatives", "[∂τ/∂q | ∂τ/∂u] (NV x 2 NV) of the "
                      "inverse dynamics, ∂/∂q in the tangent space", "q, u, ud", (nv, 2 * nv),
                      lambda: dynamics_jacobian(eom), "columns")]
    if not forward_dynamics(eom):
        missing["FD_derivatives"] = ("forward_dynamics_derivatives needs M, b and g; derived: "
                                     f"{list(eom.quantities)} (derive with quantities=None)")
        return found
    if rows:
        missing["FD_derivatives"] = (f"forward_dynamics_derivatives: the system has constraint rows "
                                     f"{rows[:6]}, whose forces these derivatives of M⁻¹ (τ − b − g) leave "
                                     "out; linearize the constrained dynamics with "
                                     "eg.linearize(eom, op_point, independent=[...])")
        return found
    if eom.load_names:
        found.append(Function("FD_jacobian", "_forward_dynamics_jacobian", "[∂/∂q | ∂/∂u] (NV x 2 NV) of "
                              "τ_ID − τ_loads, ∂/∂q in the tangent space", "q, u, ud", (nv, 2 * nv),
                              lambda: dynamics_jacobian(eom, True), public=False))
    return found + [
        Function("FD_parts", "_forward_parts", "[M | τ_loads − b − g] (M's lower triangle), for "
                 "FD_derivatives", "q, u", (nv, nv + 1), lambda: forward_parts(eom), public=False),
        Function("FD_derivatives", "forward_dynamics_derivatives", "[∂u̇/∂q | ∂u̇/∂u | ∂u̇/∂τ] of the "
                 "forward dynamics M u̇ = τ + τ_loads − b − g at q, u, τ (NV joint efforts)", "q, u, tau",
                 (nv, 3 * nv), None, "columns", parts=("FD_parts", forward_key(eom)))]


def regressor(eom: EquationsOfMotion, missing: dict) -> list[Function]:
    """The full joint-torque regressor Y (τ_ID = Y π; columns: `eg.regressor(eom).names` with the
    default options) and the energies' rows, where every joint is rigid."""
    system, nv = eom.system, len(eom.u)
    if missing_reason(system):
        missing.update(dict.fromkeys(("Y", "Y_T", "Y_U"), missing_reason(system)))
        return []
    p = 10 * len(links(system)) + 4 * len(speeds(system))
    return [Function("Y", "regressor", "the joint-torque regressor Y(q, u, u̇) (NV x P): τ_ID = Y π, π as "
                     "eg.regressor(eom).pi", "q, u, ud", (nv, p), lambda: full_regressor(eom).Y),
            Function("Y_T", "kinetic_energy_regressor", "the kinetic energy's row (1 x P): T = Y_T π", "q, u",
                     (1, p), lambda: full_regressor(eom).T),
            Function("Y_U", "potential_energy_regressor", "gravity's potential energy's row (1 x P): "
                     "U = Y_U π", "q", (1, p), lambda: full_regressor(eom).U)]


def qdot(eom: EquationsOfMotion) -> Function:
    """q̇(q, u) (`System.qdot`)."""
    return Function("qdot", "qdot", "the coordinate rates q̇(q, u) (u but for quaternions)", "q, u",
                    (len(eom.q), 1), lambda: eom.system.qdot, "vector")


def blocks(eom: EquationsOfMotion) -> list[Function]:
    """The building blocks of the numeric algorithms (not public)."""
    system, nv = eom.system, len(eom.u)
    lines, disks = line_loads(system), len(system.rolling)
    found = [Function("tau_nc", "_tau_nc", "τ of the loads but springs and bending", "q, u", (nv, 1),
                      lambda: nonconservative(eom), "vector", public=False),
             Function("centres", "_centres", "the bodies' centres of mass (world)", "q",
                      (3, len(system.bodies)), lambda: centres(eom), public=False)]
    if system.motors:
        circuits = lambda: sp.Matrix([m.circuit(eom.u) for m in system.motors])  # noqa: E731
        found.append(Function("motor", "_motor", "per DC motor [U − k N q̇, R, L]", "q, u",
                              (len(system.motors), 3), circuits, public=False))
    if disks:
        found.append(Function("tilt", "_tilt", "‖e × n‖ of every rolling disk", "q", (disks, 1),
                              lambda: tilts(eom.kinematics), "vector", public=False))
    if system.loops or disks:
        found.append(Function("closure_frames", "_closure_frames", "the loop frames' origins and the disks' "
                              "centres", "q", (3, 2 * len(system.loops) + disks),
                              lambda: closure_frames(eom), public=False))
    if lines:
        found.append(Function("line_lengths", "_line_lengths", "‖r_a − r_b‖ of the loads along a line", "q",
                              (len(lines), 1), lambda: lengths(eom), "vector", public=False))
    return found


def families(eom: EquationsOfMotion, missing: dict) -> list[Family]:
    """Per frame or body J, J̇ u and [R | p]; per load its τ; per joint (free cut) its wrench and
    reaction."""
    system, kin, nv = eom.system, eom.kinematics, len(eom.u)
    frames = tuple([b.name for b in system.bodies if b.index is not None] + list(system.frames))
    beyond = {b.name for b in kin.on_tip} | {name for name, f in system.frames.items()
                                              if f.body in kin.on_tip}
    rigid = tuple(name for name in frames if name not in beyond)  # Jacobians beyond a flexible link: refused
    loads = tuple(eom.load_names)

    def load(name: str) -> None:
        if name not in loads:
            raise unknown("load", name, list(loads))

    moving = [j.name for j in system.prescribed]
    if moving:
        missing["Jdot_u"] = (f"Jdot_u: J̇ u, the bias of a frame's velocity J u, misses joint "
                             f"'{moving[0]}''s prescribed motion (its rate is no column of J)")
    found = [Family("J", "frame", "jacobian", "6 x NV Jacobian [J_P; J_R] of frame {item}, world-aligned "
                    "axes", "q", (6, nv), kin.jacobian, rigid),
             Family("Jdot_u", "frame", "jacobian_dot_u", "J̇ u of frame {item} ([linear; angular])", "q, u",
                    (6, 1), kin.jacobian_dot_u, rigid, "vector"),
             Family("X", "frame", "placement", "placement [R | p] (3 x 4) of frame {item} in the world", "q",
                    (3, 4), lambda frame: placement(kin, frame), frames, "pose"),
             Family("tau", "load", "tau_of", "generalized force τ(q, u) of load {item}", "q, u", (nv, 1),
                    lambda name: eom.compact[f"tau:{name}"], loads, "vector", load)]
    found = [family for family in found if family.prefix not in missing]
    drives = tuple(name for name in (j.name for j in system.prescribed) if f"drive:{name}" in eom.compact)
    if drives:
        def driven(name: str) -> None:
            if name not in drives:
                raise unknown("joint of prescribed motion", name, list(drives))
        found.append(Family("drive", "drive", "driving_effort", "the effort (torque or force) joint {item}'s "
                            "prescribed motion takes", "q, u, ud", (1, 1),
                            lambda name: eom.compact[f"drive:{name}"], drives, "number", driven))
    else:
        missing["drive"] = ("driving_effort: no joint of prescribed motion (or M, b and g not all derived: "
                            "derive with quantities=None)")
    try:
        wrenches, reactions = eom.free_cut_result("joint_wrenches"), eom.free_cut_result("reactions")
    except ModelError as error:
        missing["W"] = missing["R"] = str(error)
        return found

    def joint(name: str) -> None:
        if name not in wrenches:
            raise unknown("joint", name, list(wrenches))

    return found + [
        Family("W", "joint", "joint_wrench", "(F, T) the parent exerts on the body of joint {item} at the "
               "joint origin, world axes", "q, u, ud", (6, 1), wrenches.__getitem__, tuple(wrenches),
               "wrench", joint),
        Family("R", "joint", "joint_reaction", "the reaction force and torque of joint {item} at its "
               "origin, world axes", "q, u, ud", (6, 1), reactions.__getitem__, tuple(reactions), "wrench",
               joint)]
