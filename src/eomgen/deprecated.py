"""Modules under their names before the layers (`eomgen.functions`, `eomgen.printers`, `eomgen.numeric`)
existed, importable for one release: `import eomgen.codegen.rhs` gives `eomgen.numeric.state_equations`
with a DeprecationWarning naming the new module."""
from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import warnings

MOVED = {f"eomgen.codegen.{old}": f"eomgen.{new}" for old, new in {
    "numpy_backend": "printers.walker", "c_backend": "numeric.compiled", "kane": "numeric.kane",
    "rhs": "numeric.state_equations", "parameters": "numeric.parameters",
    "derivative_functions": "numeric.forward", "kinematic_functions": "numeric.evaluations",
    "extension": "printers.build.extension", "compile": "printers.build.compile", "vector": "printers.vector",
    "contacts": "numeric.contacts", "lines": "numeric.lines", "singular": "numeric.singular",
    "module": "printers.module", "runtime": "printers.runtime",
    "c_derivatives": "printers.forward_c"}.items()}
MOVED.update({"eomgen.assembly": "eomgen.numeric.assembly", "eomgen.reduction": "eomgen.numeric.reduction"})


class Moved(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Imports a moved module's old name as the module that now holds it."""

    def find_spec(self, fullname, path=None, target=None):
        return importlib.util.spec_from_loader(fullname, self) if fullname in MOVED else None

    def create_module(self, spec):
        warnings.warn(f"{spec.name} is now {MOVED[spec.name]}", DeprecationWarning, stacklevel=3)
        return importlib.import_module(MOVED[spec.name])

    def exec_module(self, module) -> None:
        pass


if not any(isinstance(finder, Moved) for finder in sys.meta_path):
    sys.meta_path.append(Moved())
