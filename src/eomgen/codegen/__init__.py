"""`eg.codegen`, `eg.write_module` and `eg.write_c` and the numeric functions' classes, re-exported from
the layers that hold them: the catalogue (`eomgen.functions`), its printers (`eomgen.printers`) and the
numeric layer (`eomgen.numeric`). The modules this package held before are importable under their old
names for one release (`eomgen.deprecated`)."""
from ..functions import QUANTITIES
from ..numeric import CompiledEoM, CompiledKane, NumericEoM, NumericKane, codegen
from ..printers.module import module_source, write_module
from ..printers.plain_c import write_c
from ..printers.walker import Generated

__all__ = ["QUANTITIES", "CompiledEoM", "CompiledKane", "Generated", "NumericEoM", "NumericKane", "codegen",
           "module_source", "write_c", "write_module"]
