"""The speed-accuracy table: each variant's error is what its approximation implies."""
import json

import eomgen as eg
from eomgen.__main__ import main


def test_tradeoff_ur5(tmp_path):
    variants = {v.name.split(":")[0].split(" below")[0]: v for v in eg.tradeoff(eg.robots.load("ur5"), states=50)}
    full = variants["full model (recursive, float64)"]
    assert full.errors["M"][0] == 0 and full.ops < variants["projected Newton-Euler code"].ops
    assert max(variants["projected Newton-Euler code"].errors[k][0] for k in ("M", "b", "g")) < 1e-13
    assert 1e-9 < variants["float32"].errors["M"][0] < 1e-5  # single precision: ~1e-7
    coriolis = variants["Coriolis and centrifugal neglected"]
    assert coriolis.errors["b"][0] == 1.0 and coriolis.errors["M"][0] == 0 and coriolis.errors["ud"][0] > 1e-3
    locked = variants["joints locked"]
    assert max(locked.errors[k][0] for k in ("M", "b", "g")) < 1e-13 and locked.errors["ud"][0] > 1e-6
    assert variants["links as point masses"].errors["M"][0] > 1e-3
    png, table = tmp_path / "pareto.png", tmp_path / "table.json"
    assert main(["tradeoff", "ur5", "--states", "20", "--png", str(png), "--json", str(table)]) == 0
    assert png.stat().st_size > 10_000 and len(json.loads(table.read_text())) == 8
