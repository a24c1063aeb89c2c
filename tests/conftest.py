"""What the tests of one run share: one C extension cache for every worker (each module compiled once per
run), and the robots' equations and generated functions, derived once per worker."""
from __future__ import annotations

import functools
import gc
import os
import warnings

import pytest

import eomgen as eg


@pytest.fixture(scope="session", autouse=True)
def eomgen_cache(tmp_path_factory) -> str:
    """$EOMGEN_CACHE where it is set; else a folder of this run beside the workers' temp folders (pytest-xdist
    gives each worker basetemp/popen-gw<i>), so a module built by one worker is loaded by the others.
    Tests of the cache itself set their own."""
    if os.environ.get("EOMGEN_CACHE"):
        yield os.environ["EOMGEN_CACHE"]
        return
    base = tmp_path_factory.getbasetemp()
    folder = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "eomgen_cache"
    folder.mkdir(mode=0o700, exist_ok=True)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("EOMGEN_CACHE", str(folder))
        yield str(folder)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_teardown(item, nextitem):
    """After the last test of a module (its fixtures gone): its cyclic garbage collected, then what is
    left (the robots derived once per worker, sympy's caches: millions of objects) frozen out of the
    cycle collector's later passes (`gc.freeze`). A full pass walks every object; without this, a worker
    spent about 45 s in 28 of them. Objects made in a test are collected as usual."""
    yield
    if nextitem is None or getattr(nextitem, "module", None) is not getattr(item, "module", None):
        gc.collect()
        gc.freeze()


def load(name: str, **options) -> eg.System:
    """eg.robots.load, quiet about files with inertias Pinocchio takes as they are."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return eg.robots.load(name, **options)


@functools.cache
def _derived(name: str, method: str) -> eg.EquationsOfMotion:
    return eg.derive(load(name), method=method)


@functools.cache
def _generated(name: str, method: str, backend: str):
    return eg.codegen(_derived(name, method), backend=backend)


@pytest.fixture(scope="session")
def derived():
    """derived(name, method): eg.derive(eg.robots.load(name), method=method), once per worker (read only)."""
    return _derived


@pytest.fixture(scope="session")
def generated():
    """generated(name, method, backend): eg.codegen of `derived(name, method)`, once per worker; its lazily
    built members (derivatives, frame Jacobians) are built once too (read only)."""
    return _generated
