"""The layers are a contract: the import-linter contracts of pyproject.toml hold (model → kinematics →
methods → equations → catalogue → printers → numeric → simulate, linearize, verify, ... → CLI), and no
module outside the numeric layer reaches into a private member of the numeric functions (it uses their
public interface). Each check fails on a violation: shown by planting one."""
from __future__ import annotations

import ast
import inspect
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import eomgen
from eomgen import numeric

ROOT = Path(__file__).parents[1]
PACKAGE = Path(eomgen.__file__).parent


def lint(config: Path) -> subprocess.CompletedProcess:
    command = shutil.which("lint-imports") or str(Path(sys.executable).with_name("lint-imports"))
    return subprocess.run([command, "--config", str(config), "--no-cache"], capture_output=True, text=True,
                          cwd=ROOT)


def test_the_layers_hold():
    result = lint(ROOT / "pyproject.toml")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "0 broken" in result.stdout


def test_an_import_against_the_layers_is_found(tmp_path):
    """A contract with the catalogue above the printers (a printer imports the catalogue): broken."""
    text = (ROOT / "pyproject.toml").read_text()
    swapped = text.replace('    "eomgen.printers",\n    "eomgen.functions",\n',
                           '    "eomgen.functions",\n    "eomgen.printers",\n')
    assert swapped != text
    config = tmp_path / "pyproject.toml"
    config.write_text(swapped)
    result = lint(config)
    assert result.returncode != 0 and "BROKEN" in result.stdout


def private_members() -> set[str]:
    """The private names the numeric layer's classes define (a single leading underscore)."""
    names = set()
    for cls in (numeric.NumericEoM, numeric.CompiledEoM, numeric.NumericKane, numeric.CompiledKane):
        for klass in inspect.getmro(cls):
            if klass.__module__.startswith("eomgen.numeric"):
                names |= {n for n in vars(klass) if n.startswith("_") and not n.startswith("__")}
    return names | {"_nu", "_writer", "_python", "_extension", "_dep", "_ind", "_q_dep"}


def reaches_in(source: str, names: set[str]) -> list[str]:
    """`x._name` for a private name, x not self or cls."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Attribute) and node.attr in names:
            if not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")):
                found.append(f"line {node.lineno}: .{node.attr}")
    return found


def test_no_module_outside_the_numeric_layer_calls_its_private_members():
    names = private_members()
    offenders = {}
    for path in PACKAGE.rglob("*.py"):
        if path.relative_to(PACKAGE).parts[0] != "numeric":
            found = reaches_in(path.read_text(), names)
            if found:
                offenders[str(path.relative_to(PACKAGE))] = found
    assert not offenders, offenders


@pytest.mark.parametrize("planted", ["f._print(['M'])", "functions._pvec(None, 'M')"])
def test_a_private_call_is_found(planted):
    assert reaches_in(planted, private_members())


MOVED = {"eomgen.codegen.rhs": "eomgen.numeric.state_equations", "eomgen.codegen.kane": "eomgen.numeric.kane",
         "eomgen.codegen.extension": "eomgen.printers.build.extension",
         "eomgen.assembly": "eomgen.numeric.assembly"}


def test_old_module_names_import_the_new_modules_with_a_warning():
    """In a fresh process (none of the old names imported before): each old name warns once, as an error
    here, naming the new module, then imports the new module itself; eg.codegen stays the function."""
    code = ("import warnings, importlib, sys\nimport eomgen as eg\n"
            f"for old, new in {MOVED!r}.items():\n"
            "    warnings.simplefilter('error')\n"
            "    try:\n        importlib.import_module(old)\n"
            "    except DeprecationWarning as w:\n        print(w)\n"
            "    warnings.simplefilter('ignore')\n"
            "    assert importlib.import_module(old) is sys.modules[new], old\n"
            "import eomgen.codegen\nassert callable(eg.codegen) and eg.codegen.__name__ == 'codegen'\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == [f"{old} is now {new}" for old, new in MOVED.items()]


def test_importing_eomgen_loads_neither_scipy_nor_matplotlib():
    """SciPy (a third of eomgen's import time) and matplotlib are imported where they are used, so that
    `import eomgen` and the command line start quickly; planting a module-level import fails here."""
    code = "import sys, eomgen\n" \
           "print(sorted({m.split('.')[0] for m in sys.modules} & {'scipy', 'matplotlib'}))"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "[]"
