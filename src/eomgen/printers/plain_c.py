"""The plain C target: the catalogue as C source and a header for a controller (no Python): every public
function and the parts of the forward dynamics' derivatives, per frame, load and joint its family's
functions, each <name>_<key>(q, u, ud, p, out); the header documents the inputs index by index and per
function its output and the entries it reads."""
from __future__ import annotations

import re
from pathlib import Path

from ..version import __version__
from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..functions import DERIVATIVES, QUANTITIES, Catalogue, Function, catalogue, expect_equations
from ..progress import progress
from .forward_c import forward_derivatives_source
from .syntax import C, VECTOR_TRIG
from .walker import listed, reads, writer



def comment(text: str) -> str:
    """`text` safe inside a C comment: no comment delimiters, no line breaks or other unprintables."""
    text = "".join(c if c.isprintable() else "?" for c in str(text))
    return text.replace("*/", "*?").replace("/*", "/?")


def printed(cat: Catalogue, fn: Function, derivatives: bool) -> bool:
    """Whether write_c prints `fn`: every public function and the parts of a composite (those of the
    derivatives only with `derivatives`)."""
    return (fn.public or fn.key in cat.parts()) and (derivatives or fn.key not in DERIVATIVES)


def write_c(eom: EquationsOfMotion, directory, name: str = "eom",
            frames: list[str] | None = None, derivatives: bool = True) -> tuple[Path, Path]:
    """Plain C (no Python) for a controller: <name>.c and <name>.h with <name>_<quantity> for M, b, g,
    nle, T, U (those derived) and tau, per frame <name>_J_<k>, <name>_Jdot_u_<k>, <name>_X_<k> (default:
    the frames of derive(frames=...), else all), <name>_com, <name>_J_com, <name>_A_G (moving mass, no
    flexible link) and with contacts, loops or rolling disks <name>_J_c,
    <name>_Jdot_c_u and (loops, disks) <name>_closure, the inverse dynamics <name>_ID and its
    derivatives <name>_ID_derivatives, <name>_FD_derivatives (`derivatives=False` leaves those two out:
    the largest functions of a big robot), <name>_qdot, per load <name>_tau_<k> and (free cut) per joint
    <name>_W_<k> and <name>_R_<k>, each f(q, u, ud, p, out). The header documents the inputs
    index by index (p[k]: the parameters sorted by name), and per function its output (row-major,
    zeroed by the caller; the constraint rows by name) and the entries of q, u, ud, p it reads."""
    expect_equations(eom, "write_c")
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", name):
        raise ModelError(f"write_c: name must be a C identifier, got {name!r}")
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    cat = catalogue(eom)
    frames = list(eom.frames or eom.system.frames) if frames is None else list(frames)
    parts = [fn for fn in cat if fn.key in QUANTITIES]
    parts += [cat[f"{prefix}:{frame}"] for frame in frames for prefix in cat.frames()]
    parts += [fn for fn in cat if printed(cat, fn, derivatives) and fn not in parts]
    parts += [family.of(item) for prefix, family in cat.families.items() if prefix not in cat.frames()
              for item in family.items]
    c = writer(cat, C)
    body, decls, sources = ["#include <math.h>", VECTOR_TRIG, f'#include "{name}.h"', ""], [], {}
    for fn in progress(parts, "writing C", unit="function"):
        key = c_name(cat, fn, frames)
        if fn.composite:
            text, declaration = composite(fn, name, key, [sources[k] for k in fn.parts])
        else:
            text, (rows, cols), _ = c.function(f"{name}_{key}", fn)
            named = "".join(f"\n *   row {r}: {comment(row)}" for r, row in enumerate(fn.rows))
            prototype = C.header.format(name=f"{name}_{key}").split("\n")[0]
            declaration = (f"/* {comment(fn.what)}{named}\n * out: {rows} x {cols}, row-major; reads "
                           f"{listed(reads(text))} */\n{prototype};")
        sources[key] = text
        body.append(text)
        decls.append(declaration)
    c_path, h_path = directory / f"{name}.c", directory / f"{name}.h"
    c_path.write_text("\n".join(body))
    h_path.write_text(header(eom, name) + "\n\n".join(decls) + "\n\n#endif\n")
    return c_path, h_path


def c_name(cat, fn: Function, frames: list[str]) -> str:
    """The C name of `fn` after <name>_: its key, a family member's <prefix>_<k> (k: the item's index among
    the frames written, or its family's items)."""
    if fn.item is None:
        return fn.key
    prefix = fn.key.split(":")[0]
    items = frames if prefix in cat.frames() else list(cat.families[prefix].items)
    return f"{prefix}_{items.index(fn.item)}"


def composite(fn: Function, name: str, key: str, parts: list[str]) -> tuple[str, str]:
    """The text and declaration of <name>_FD_derivatives, given its parts' texts ([M | h], then D)."""
    text = forward_derivatives_source(f"{name}_{key}", *(f"{name}_{k}" for k in fn.parts), fn.shape[0], C)
    read = listed({arg: ks for arg, ks in reads("".join(parts)).items() if arg != "ud"})
    declaration = (
        "/* [∂u̇/∂q | ∂u̇/∂u | ∂u̇/∂τ] of the forward dynamics M u̇ = τ + τ_loads − b − g at q, u, τ (NV "
        "joint efforts,\n * in the place of ud); out: NV x 3 NV, row-major, every entry written (NaN "
        "where M is not positive definite);\n * reads "
        f"{read}, tau */\n"
        + C.header.format(name=f"{name}_{key}").split("\n")[0].replace("*ud", "*tau")
        + ";"
    )
    return text, declaration


def speed_labels(system) -> list[str]:
    """The speeds as a header names them: qd_<coordinate> where u_k is a coordinate's rate q̇_i, else their
    own names (the twist of a free flyer or ball joint: base_vx, ..., ball_wz)."""
    u = list(system.u)
    labels = [str(x) for x in u]
    for i, (q, rate) in enumerate(zip(system.q, system.qdot)):
        if rate in u:
            labels[u.index(rate)] = f"qd_{q} = d/dt q[{i}]"
    return labels


def header(eom: EquationsOfMotion, name: str) -> str:
    """The header's guard, sizes and the inputs' documentation, index by index."""
    params = catalogue(eom).inputs["p"]
    actuated = eom.system.actuated
    N = name.upper()
    lines = [f"#ifndef EOMGEN_{N}_H", f"#define EOMGEN_{N}_H",
             f"/* Generated by eomgen {__version__} ({eom.method}):",
             " * M(q) u̇ + b(q, u) + g(q) = τ(q, u) + Sᵀ τ_a.",
             " *",
             f" * Every function is {name}_<f>(q, u, ud, p, out), all arrays of double:",
             f" *   q:  {N}_NQ coordinates;  u: {N}_NV speeds;  ud: {N}_NV accelerations (same order as u);",
             f" *   p:  {N}_NP parameters, sorted by name; a function reads only the entries listed with it",
             " *       (the others may hold anything, e.g. 0.0);",
             " *   out: the output, row-major (out[i * cols + j]); only its nonzero entries are written,",
             " *       so out must be zeroed by the caller.",
             " * Entries:"]
    lines += [f" *   q[{k}]: {comment(x)}" for k, x in enumerate(eom.q)]
    lines += [f" *   u[{k}]: {comment(x)}" for k, x in enumerate(speed_labels(eom.system))]
    lines += [f" *   p[{k}]: {comment(x)}" for k, x in enumerate(params)]
    lines += [f" *   tau_a[{r}]: joint {comment(label)}, adds to tau[{list(eom.S.row(r)).index(1)}] "
              "(S^T tau_a)" for r, label in enumerate(actuated)]
    sizes = {"NQ": len(eom.q), "NV": len(eom.u), "NP": len(params), "NA": len(actuated)}
    lines += [" */", *(f"#define {N}_{k} {n}" for k, n in sizes.items()), "", ""]
    return "\n".join(lines)
