"""Builds in translation units: functions cut into many parts spread over many units give Pinocchio's
and the NumPy backend's numbers; the cache key covers every unit; a unit the compiler refuses is named in
the error; the progress bar counts the units."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import eomgen as eg
from eomgen import progress as bars
from eomgen.printers import syntax, walker
from eomgen.printers.build import compile as units
from eomgen.printers.build import extension
from eomgen.printers.syntax import C_TRIG
from eomgen.verify import verify
from models import double_pendulum


def cut(monkeypatch, tmp_path, segment: int, unit: int) -> None:
    """Parts of about `segment` operations, units of about `unit` characters, a fresh cache."""
    monkeypatch.setattr(walker, "SEGMENT", segment)
    monkeypatch.setattr(units, "UNIT", unit)
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))


# panda (the longest build of the run) under -m slow: ur5 here and test_any_cut_gives_the_numpy_numbers
# prove the split build in the default run
@pytest.mark.parametrize("name,method", [("ur5", "recursive"),
                                         pytest.param("panda", "projected_newton_euler", marks=pytest.mark.slow)])
def test_split_build_equals_pinocchio_and_numpy(name, method, tmp_path, monkeypatch):
    cut(monkeypatch, tmp_path, segment=40, unit=4000)
    system = eg.robots.load(name)
    eom = eg.derive(system, method=method)
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    sources = [f.source for f in fc.functions.values()]
    header, layout = units.translation_units(sources)
    assert "e0_5(" in sources[0] and len(layout) >= 4  # many parts, many units
    q, u, _ = eg.random_states(system, 20, np.random.default_rng(5))
    for key, c, py in [
        ("M", fc.M(q), fn.M(q)),
        ("b", fc.b(q, u), fn.b(q, u)),
        ("g", fc.g(q), fn.g(q)),
        ("nle", fc.nle(q, u), fn.nle(q, u)),
        ("M, one state", fc.M(q[3]), fn.M(q[3])),
    ]:
        np.testing.assert_allclose(c, py, rtol=1e-12, atol=1e-12, err_msg=key)
    report = verify(system, method=method, backend="c", states=5)
    assert report.ok(1e-10), str(report)


@settings(max_examples=6, deadline=None)
@given(segment=st.integers(3, 300), unit=st.integers(200, 30_000))
def test_any_cut_gives_the_numpy_numbers(tmp_path_factory, segment, unit):
    with pytest.MonkeyPatch.context() as monkeypatch:
        cut(monkeypatch, tmp_path_factory.mktemp("cache"), segment, unit)
        eom = eg.derive(double_pendulum())
        fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
        q, u, _ = eg.random_states(eom.system, 7, np.random.default_rng(segment))
        p = {name: 0.5 + 0.1 * k for k, name in enumerate(fc.parameters.names)}  # symbolic parameters
        np.testing.assert_allclose(fc.M(q, p), fn.M(q, p), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(fc.nle(q, u, p), fn.nle(q, u, p), rtol=1e-12, atol=1e-12)


def constant(i: int, body: str) -> tuple[str, tuple, list]:
    """Function e<i> writing out[0] = `body`, as the extension's functions are written."""
    return C_TRIG.header.format(name=f"e{i}") + f"\n    out[0] = {body};\n}}\n", (1, 1), []


def test_cache_key_covers_every_unit(tmp_path, monkeypatch):
    cut(monkeypatch, tmp_path, segment=2500, unit=10)  # one function per unit
    first = extension.build([constant(0, "1.5"), constant(1, "2.5"), constant(2, "3.5")], 1, 1, 0)
    assert [first.m0([0.0])[0, 0], first.m1([0.0])[0, 0], first.m2([0.0])[0, 0]] == [1.5, 2.5, 3.5]
    assert len(units.translation_units([constant(i, "0.0")[0] for i in range(3)])[1]) == 3
    built = {p: p.stat().st_mtime_ns for p in tmp_path.iterdir()}
    again = extension.build([constant(0, "1.5"), constant(1, "2.5"), constant(2, "3.5")], 1, 1, 0)
    assert again is first and {p: p.stat().st_mtime_ns for p in tmp_path.iterdir()} == built
    changed = extension.build([constant(0, "1.5"), constant(1, "2.5"), constant(2, "-3.5")], 1, 1, 0)
    assert changed.__name__ != first.__name__ and changed.m2([0.0])[0, 0] == -3.5
    monkeypatch.setattr(units, "LARGE", 1)  # the same text, another optimisation level: another module
    other = extension.build([constant(0, "1.5"), constant(1, "2.5"), constant(2, "3.5")], 1, 1, 0)
    assert other.__name__ not in (first.__name__, changed.__name__) and other.m1([0.0])[0, 0] == 2.5
    assert len(list(tmp_path.glob("eomgen_*.so"))) == 3


def test_a_failing_unit_is_named_with_the_compiler_message(tmp_path, monkeypatch):
    cut(monkeypatch, tmp_path, segment=2500, unit=10)
    with pytest.raises(
        eg.ModelError, match=r"(?s)the C compiler failed on unit \d \(functions e1\).*undeclared"
    ):
        extension.build(
            [constant(0, "1.0"), constant(1, "not_declared_anywhere"), constant(2, "3.0")], 1, 1, 0
        )
    assert not list(tmp_path.glob("eomgen_*.so"))


def test_progress_bar_over_the_units(tmp_path, monkeypatch, capsys):
    cut(monkeypatch, tmp_path, segment=2500, unit=10)
    monkeypatch.setattr(bars, "DELAY", 0)
    monkeypatch.setenv("EOMGEN_PROGRESS", "1")
    with eg.quiet(False):
        extension.build([constant(0, "1.0"), constant(1, "2.0")], 1, 1, 0)
    err = capsys.readouterr().err
    assert "compiling C" in err and "/3" in err and "unit" in err  # two units and the module


def test_definitions_lose_static_and_keep_their_text():
    part = constant(0, "1.0")[0].replace("void e0", "EOMGEN_NOINLINE void e0_0")
    text = syntax.NOINLINE + "\n\n" + part + "\n" + constant(0, "2.0")[0]
    blocks, found = units.definitions(text)
    assert blocks == [syntax.NOINLINE]
    assert [units.name(d) for d in found] == ["e0_0", "e0"] and not any(
        d.startswith("static") for d in found
    )
    assert [d.split("\n")[-2] for d in found] == ["    out[0] = 1.0;", "    out[0] = 2.0;"]


def test_the_glue_compiles_no_vector_code(tmp_path, monkeypatch):
    """The module built up front holds neither the vector types nor the batched vector loop (the
    intrinsics' headers alone were half its compile time): the module of vector functions, built on the
    first batch, hands its loop over with them; a batch then equals the states one at a time."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    glue = extension.module_source("m", [constant(0, "1.0")], 1, 1, 0)
    assert "immintrin" not in glue and "vector_size" not in glue and "batch_vector(eomgen_vfn" not in glue
    eom = eg.derive(double_pendulum(numeric=True))
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    q, u, _ = eg.random_states(eom.system, 9, np.random.default_rng(2))
    np.testing.assert_allclose(fc.nle(q, u), fn.nle(q, u), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fc.M(q), [fn.M(x) for x in q], rtol=1e-12, atol=1e-12)
