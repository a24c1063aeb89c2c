"""A build that scales: the generated C functions as translation units compiled at once, one compiler
per core, then linked into one shared library.

Each function's text is cut into its definitions (a long function is already written as parts, see
`numpy_backend.FunctionWriter._parts`); the definitions lose their `static` (the library exports only
its entry point: -fvisibility=hidden) and are packed into units of about `UNIT` characters, each unit
with the prototypes of the functions it calls from the others. The number of units depends on the text
only, not on the machine, so the same functions give the same library everywhere. A unit is optimised
by its size (`optimisation`): the big ones at -O1, which compiles in less time for the same speed
(measured: benchmarks/builds.py --levels)."""

from __future__ import annotations

import math
import os
import re
import subprocess
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

from ...errors import ModelError
from ...progress import progress

UNIT = 60_000  # characters of definitions per translation unit
LARGE = 20_000  # characters from which a unit is compiled at -O1
CALL = re.compile(r"\b(\w+)\(")
# for the machine it runs on (the vector width of batches, `vector`): the cache key holds the machine
COMPILE = ["-march=native", "-fno-math-errno", "-ftree-vectorize", "-fPIC", "-fvisibility=hidden"]


def definitions(source: str) -> tuple[list[str], list[str]]:
    """The preprocessor blocks and the function definitions of generated C text (a definition runs from
    its first line at column 0 to its closing brace at column 0; its signature is the line before its
    opening brace), each without `static`."""
    blocks, found, lines = [], [], []
    for line in source.splitlines():
        if not lines and line.startswith("#"):
            if blocks and blocks[-1][-1] != "":
                blocks[-1].append(line)
            else:
                blocks.append([line])
        elif lines or line.strip():
            lines.append(line)
            if line == "}":
                at = lines.index("{") - 1
                lines[at] = lines[at].removeprefix("static ")
                found.append("\n".join(lines))
                lines = []
        elif blocks:
            blocks[-1].append("")  # a blank line ends a preprocessor block
    return ["\n".join(b).strip() for b in blocks], found


def prototype(definition: str) -> str:
    lines = definition.split("\n")
    return lines[lines.index("{") - 1] + ";"


def name(definition: str) -> str:
    """The name of the function a definition defines."""
    signature = prototype(definition)
    return signature[: signature.index("(")].split()[-1]


@dataclass(frozen=True)
class Unit:
    """One translation unit: the functions it defines and its C text."""

    names: tuple[str, ...]
    text: str


def translation_units(sources: list[str]) -> tuple[str, list[Unit]]:
    """The declarations for the module's entry points (math.h, the macros, a prototype of every
    definition) and the definitions of `sources` packed into ⌈characters / UNIT⌉ units (at most one per
    definition) of about equal size (the largest first, each into the smallest unit so far), each with
    the prototypes of the functions it calls from other units."""
    blocks, found = [], []
    for source in sources:
        b, d = definitions(source)
        blocks += [x for x in b if x not in blocks]
        found += d
    prototypes = {name(d): prototype(d) for d in found}
    packed: list[list[str]] = [[] for _ in range(min(math.ceil(sum(map(len, found)) / UNIT), len(found)))]
    sizes = [0] * len(packed)
    for d in sorted(found, key=len, reverse=True):
        k = sizes.index(min(sizes))
        packed[k].append(d)
        sizes[k] += len(d)
    head = ["#include <math.h>", *blocks]
    units = []
    for definitions_ in packed:
        names = tuple(map(name, definitions_))
        calls = sorted(set(CALL.findall("\n".join(definitions_))) & prototypes.keys() - set(names))
        units.append(Unit(names, "\n".join(head + [prototypes[c] for c in calls] + ["", *definitions_])))
    return "\n".join(head + list(prototypes.values())) + "\n", units


def optimisation(unit: Unit) -> str:
    """-O2, or -O1 for a unit of `LARGE` characters or more."""
    return "-O1" if len(unit.text) >= LARGE else "-O2"


def jobs() -> int:
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def compile_objects(compiler: str, commands: dict[str, list[str]]) -> dict[str, str]:
    """Run the compiler once per {label: arguments}, `jobs()` at once, with a progress bar over them;
    the compiler's messages of those that fail, by label."""

    def run(arguments):
        return subprocess.run([compiler, *arguments], capture_output=True, text=True)

    with ThreadPoolExecutor(jobs()) as pool:
        futures = {pool.submit(run, arguments): label for label, arguments in commands.items()}
        done = progress(as_completed(futures), "compiling C", total=len(futures), unit="unit")
        return {futures[f]: f.result().stderr for f in list(done) if f.result().returncode != 0}


def build_library(
    compiler: str,
    glue: str,
    units: list[Unit],
    includes: list[str],
    attempts: tuple[list[str], ...],
    folder: Path,
    library: Path,
    shared: Callable[[list[str]], str] | None = None,
) -> None:
    """Compile `glue` (the module's entry points) and the `units` in `folder` and link them into
    `library`, with `shared(options)` (an object compiled apart, for those options) where given: with the
    first of `attempts` (options for the glue and the link) that builds here; a ModelError with the
    compiler's message naming the unit that fails."""
    objects, commands = [], {}
    for k, unit in enumerate(units):
        c_file = folder / f"unit{k}.c"
        c_file.write_text(unit.text)
        objects.append(str(c_file.with_suffix(".o")))
        label = f"unit {k} (functions {', '.join(unit.names)})"
        commands[label] = [optimisation(unit), *COMPILE, "-c", str(c_file), "-o", objects[-1]]
    glue_file, glue_object = folder / "module.c", str(folder / "module.o")
    glue_file.write_text(glue)
    for options in attempts:
        glue_command = ["-O2", *COMPILE, *includes, *options, "-c", str(glue_file), "-o", glue_object]
        failed = compile_objects(compiler, {"the module": glue_command, **commands})
        if units_failed := [
            f"{label}: {error}" for label, error in failed.items() if label != "the module"
        ]:
            raise ModelError(f"the C compiler failed on {units_failed[0][:2000]}")
        commands = {}  # compiled
        if "the module" not in failed:
            try:
                linked = [glue_object, *objects, *([shared(options)] if shared else [])]
            except ModelError as error:
                failed["the module"] = str(error)
                continue
            link = subprocess.run([compiler, "-shared", *linked, *options, "-o", str(library)],
                                  capture_output=True, text=True)
            if link.returncode == 0:
                return
            failed["the module"] = link.stderr
    raise ModelError(f"the C compiler failed on the module: {failed['the module'][:2000]}")
