"""The printers: one module per target that turns the function catalogue into code, over one expression
walker (`walker`): Python/NumPy (`python`), the written module (`module`), the C extension
(`c_extension`, per state and vector batches: `vector`) and plain C (`plain_c`); compiling and the cache
in `build`."""
from .module import module_source, write_module
from .plain_c import write_c

__all__ = ["module_source", "write_c", "write_module"]
