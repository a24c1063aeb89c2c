"""The C extension cache: a damaged entry is rebuilt, the folder is private, an unusable folder is a
clear error naming EOMGEN_CACHE."""
import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import eomgen as eg

SRC = str(Path(eg.__file__).parents[1])


def arm():
    """A 2-link planar arm's equations."""
    system = eg.System()
    a = system.add_body("a", joint=eg.Revolute("q1", axis=(0, 0, 1)), mass=1, com=(0.5, 0, 0),
                        inertia=np.diag([0.01, 0.02, 0.03]))
    system.add_body("b", parent=a, joint=eg.Revolute("q2", axis=(0, 0, 1)), mass=0.5, com=(0.4, 0, 0),
                    inertia=np.diag([0.01, 0.01, 0.02]), placement=eg.Placement(translation=(1, 0, 0)))
    return eg.derive(system)


def difference() -> float:
    """max |C − NumPy| of M and nle (the functions compiled up front: one module) at one state."""
    eom = arm()
    fc, fn = eg.codegen(eom, backend="c"), eg.codegen(eom)
    q, u = np.array([0.3, -0.7]), np.array([0.5, 1.1])
    return max(np.abs(fc.M(q) - fn.M(q)).max(), np.abs(fc.nle(q, u) - fn.nle(q, u)).max())


def _fresh_process(cache: Path) -> float:
    """difference() in a new Python process, with the C module compiled into or loaded from `cache`."""
    env = {**os.environ, "EOMGEN_CACHE": str(cache), "PYTHONPATH": SRC}
    code = f"import sys; sys.path.insert(0, {str(Path(__file__).parent)!r}); import test_cache; " \
           "print(test_cache.difference())"
    result = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return float(result.stdout.split()[-1])


def _entry(cache: Path) -> tuple[Path, Path]:
    (module,) = [p for p in cache.glob("eomgen_*") if not p.name.endswith(".sha256")]
    return module, module.with_name(module.name + ".sha256")


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    """A cache with the arm's module, built once in a fresh process (a module loaded here would be mapped:
    truncating it kills this process) and equal to the NumPy backend there."""
    cache = tmp_path_factory.mktemp("built") / "cache"
    assert _fresh_process(cache) < 1e-12
    return cache


@pytest.mark.parametrize("damage", ["truncated", "garbage, checksum matching", "no checksum",
                                    "wrong checksum", "module is a folder", "checksum is a folder"])
def test_a_damaged_entry_is_rebuilt_in_a_fresh_process(damage, built, tmp_path):
    """A copy of the `built` cache, damaged, then used in another process."""
    cache = tmp_path / "cache"
    shutil.copytree(built, cache)
    module, checksum = _entry(cache)
    assert checksum.read_text().strip() == hashlib.sha256(module.read_bytes()).hexdigest()
    before = module.stat().st_ino
    if damage == "truncated":
        module.write_bytes(module.read_bytes()[:1000])
    if damage == "garbage, checksum matching":  # passes the checksum, does not load (a truncated ELF
        module.write_bytes(b"garbage")         # file would not raise but kill the process: SIGBUS)
        checksum.write_text(hashlib.sha256(b"garbage").hexdigest())
    if damage == "no checksum":
        checksum.unlink()
    if damage == "wrong checksum":
        checksum.write_text("0" * 64)
    if damage.endswith("is a folder"):  # no rename can replace a folder: removed, then rebuilt
        folder = module if damage.startswith("module") else checksum
        folder.unlink()
        (folder / "inside").mkdir(parents=True)
    assert _fresh_process(cache) < 1e-12  # equal to the NumPy backend
    assert checksum.read_text().strip() == hashlib.sha256(module.read_bytes()).hexdigest()
    assert module.stat().st_ino != before  # a new file moved in


@pytest.mark.parametrize("damage", ["truncated", "no checksum", "is a folder"])
def test_a_damaged_shared_glue_is_compiled_again(damage, built, tmp_path):
    """The glue every module links (glue_<hash>.o, one per cache), damaged, with the arm's module gone:
    the next module built compiles the glue again and equals the NumPy backend."""
    cache = tmp_path / "cache"
    shutil.copytree(built, cache)
    (glue,) = cache.glob("glue_*.o")
    checksum = glue.with_name(glue.name + ".sha256")
    assert checksum.read_text().strip() == hashlib.sha256(glue.read_bytes()).hexdigest()
    for path in _entry(cache):
        path.unlink()
    if damage == "truncated":
        glue.write_bytes(glue.read_bytes()[:1000])
    if damage == "no checksum":
        checksum.unlink()
    if damage == "is a folder":
        glue.unlink()
        (glue / "inside").mkdir(parents=True)
    assert _fresh_process(cache) < 1e-12
    assert checksum.read_text().strip() == hashlib.sha256(glue.read_bytes()).hexdigest()


def test_a_module_that_never_loads_is_a_clear_error(tmp_path, monkeypatch):
    """A 'compiler' that writes garbage: rebuilt once, then a ModelError naming the module."""
    fake = tmp_path / "fake-cc"
    fake.write_text('#!/bin/sh\nwhile [ "$1" != "-o" ]; do shift; done\necho garbage > "$2"\n')
    fake.chmod(0o755)
    monkeypatch.setenv("CC", str(fake))
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path / "cache"))
    with pytest.raises(eg.ModelError, match=r"the compiled module .*eomgen_\w+.* does not load"):
        eg.codegen(arm(), backend="c").M(np.zeros(2))


def test_the_cache_folder_is_private(tmp_path, monkeypatch):
    cache = tmp_path / "new" / "cache"
    monkeypatch.setenv("EOMGEN_CACHE", str(cache))
    old = os.umask(0o022)
    try:
        eg.codegen(arm(), backend="c").M(np.zeros(2))
    finally:
        os.umask(old)
    assert cache.stat().st_mode & 0o777 == 0o700


def _unusable(monkeypatch, path: Path, match: str) -> None:
    monkeypatch.setenv("EOMGEN_CACHE", str(path))
    with pytest.raises(eg.ModelError, match=rf"EOMGEN_CACHE={path}, {match}"):
        eg.codegen(arm(), backend="c").M(np.zeros(2))


def test_a_file_as_cache_is_a_clear_error(tmp_path, monkeypatch):
    (tmp_path / "file").write_text("")
    _unusable(monkeypatch, tmp_path / "file", "is a file, not a folder")
    _unusable(monkeypatch, tmp_path / "file" / "cache", "cannot be created: Not a directory")


def test_a_read_only_cache_is_a_clear_error(tmp_path, monkeypatch):
    """A read-only folder, and a folder that cannot be made in one. Root writes into read-only folders
    (and this machine's Python is not reachable by another user), so as root the operating system's
    refusals are stood in for: os.access says no, mkdir raises PermissionError."""
    ro = tmp_path / "ro"
    ro.mkdir(mode=0o500)
    if os.geteuid() == 0:
        from eomgen.printers.build import extension

        access = os.access
        monkeypatch.setattr(extension.os, "access",
                            lambda path, mode: Path(path) != ro and access(path, mode))
        _unusable(monkeypatch, ro, "is not writable")
        monkeypatch.undo()

        mkdir = Path.mkdir

        def refuse(self, *args, **kwargs):
            if self.parent == ro:
                raise PermissionError(13, "Permission denied")
            return mkdir(self, *args, **kwargs)
        monkeypatch.setattr(Path, "mkdir", refuse)
    else:
        _unusable(monkeypatch, ro, "is not writable")
    _unusable(monkeypatch, ro / "cache", "cannot be created: Permission denied")


@pytest.mark.skipif(os.name != "posix", reason="POSIX modes")
def test_a_cache_others_can_write_is_refused(tmp_path, monkeypatch):
    cache = tmp_path / "shared"
    cache.mkdir()
    cache.chmod(0o777)
    _unusable(monkeypatch, cache, "is writable by all users")
    cache.chmod(0o770)
    monkeypatch.setenv("EOMGEN_CACHE", str(cache))
    with pytest.warns(UserWarning, match="is writable by its group"):
        assert eg.codegen(arm(), backend="c").M(np.zeros(2)).shape == (2, 2)
