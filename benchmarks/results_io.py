"""Where the benchmarks write their JSON: one place for the file, the machine and the versions."""
from __future__ import annotations

import json
import platform
from pathlib import Path

FOLDER = Path(__file__).parent / "results"


def default_path(name: str) -> str:
    return str(FOLDER / f"{name}.json")


def write(path, benchmark: str, rows: list, **meta) -> Path:
    """Write {benchmark, machine, python, **meta, rows} as JSON and print where."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"benchmark": benchmark, "machine": platform.platform(),
                               "python": platform.python_version(), **meta, "rows": rows}, indent=2))
    print(f"written: {out}")
    return out
