"""eg.sweep on a local cluster of 2 worker processes: the result equals the direct call exactly at every
state (lazy Dask array and Zarr), M agrees with Pinocchio's crba, a worker killed mid-sweep is replaced
with no chunk lost or repeated, and bad arguments are refused by name."""
from __future__ import annotations

import os
import signal
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import eomgen as eg
from eomgen.sweep import RandomChunks

distributed = pytest.importorskip("distributed")
zarr = pytest.importorskip("zarr")


@pytest.fixture(scope="module")
def ur5():
    system = eg.robots.load("ur5")
    eom = eg.derive(system)
    return system, eg.codegen(eom, backend="c"), eg.codegen(eom)


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as local, distributed.Client(local) as client:
        yield client


def made(make, n: int, chunk: int) -> list[np.ndarray]:
    """The states a sweep makes with make(k, n_k), made here: q, u, u̇ of all N rows."""
    parts = [make(k, min(chunk, n - k * chunk)) for k in range(-(-n // chunk))]
    return [np.concatenate(x) for x in zip(*parts)]


@pytest.mark.parametrize("backend", ["c", "numpy"])
def test_a_sweep_equals_the_direct_call_at_every_state(ur5, cluster, backend):
    system, fc, fn = ur5
    f = fc if backend == "c" else fn
    q, u, ud = eg.random_states(system, 2500, np.random.default_rng(1))
    for key, states in [("M", q), ("nle", (q, u)), ("J:tool0", (q, u, ud))]:
        result = eg.sweep(f, key, states, chunk=700, cluster=cluster)
        assert result.chunks[0] == (700, 700, 700, 400)
        assert np.array_equal(result.compute(), f.call(key, q, u, ud))


def test_the_swept_mass_matrix_is_pinocchios(ur5, cluster):
    system, f, _ = ur5
    q = eg.random_states(system, 20, np.random.default_rng(2))[0]
    swept = eg.sweep(f, "M", q, chunk=7, cluster=cluster).compute()
    model = system.pinocchio_model
    data = model.createData()
    for k in range(len(q)):
        crba = pin.crba(model, data, q[k])
        assert np.allclose(swept[k], np.triu(crba) + np.triu(crba, 1).T, atol=1e-10)


def test_states_made_on_the_workers_and_written_to_zarr(ur5, cluster, tmp_path):
    system, f, _ = ur5
    make = RandomChunks(system, seed=7)
    stored = eg.sweep(f, "nle", make, n=2300, chunk=1000, cluster=cluster, out=str(tmp_path / "nle.zarr"))
    q, u, _ = made(make, 2300, 1000)
    assert np.array_equal(zarr.open_array(str(tmp_path / "nle.zarr"))[:], f.call("nle", q, u))
    assert np.array_equal(stored[:], f.call("nle", q, u))


@dataclass(frozen=True)
class Killing:
    """Random chunks that note each chunk made (a file per making: the per-chunk marker) and kill their
    worker's process the first time chunk `victim` is made."""

    make: RandomChunks
    folder: str
    victim: int

    def __call__(self, k: int, n: int):
        marker = Path(self.folder, f"chunk-{k}-{os.getpid()}-{len(os.listdir(self.folder))}")
        marker.write_text(f"{n}")
        if k == self.victim and first_time(Path(self.folder, "killed")):
            os.kill(os.getpid(), signal.SIGKILL)
        return self.make(k, n)


def first_time(path: Path) -> bool:
    """Whether this call made the file `path` (O_EXCL: one process only, however many ask at once)."""
    try:
        os.close(os.open(path, os.O_CREAT | os.O_EXCL))
    except FileExistsError:
        return False
    return True


def test_a_worker_killed_mid_sweep_is_replaced_and_no_chunk_is_lost_or_repeated(ur5, cluster, tmp_path):
    system, f, _ = ur5
    folder = tmp_path / "marks"
    folder.mkdir()
    make = Killing(RandomChunks(system, seed=3), str(folder), victim=3)
    n, chunk = 3000, 500
    before = set(cluster.scheduler_info()["workers"])
    stored = eg.sweep(f, "M", make, n=n, chunk=chunk, cluster=cluster, out=str(tmp_path / "M.zarr"))
    assert (folder / "killed").exists()
    chunks = sorted(int(p.name.split("-")[1]) for p in folder.glob("chunk-*"))
    assert set(chunks) == set(range(6)) and chunks.count(3) >= 2  # chunk 3 made again, on another worker
    assert np.array_equal(stored[:], f.call("M", made(make.make, n, chunk)[0]))  # every row, once
    cluster.wait_for_workers(2, timeout=60)
    assert len(set(cluster.scheduler_info()["workers"]) - before) == 1  # the killed worker replaced


def test_bound_parameters_travel_to_the_workers(cluster):
    from models import cart_pendulum

    system, _ = cart_pendulum()
    f = eg.codegen(eg.derive(system)).bind({"m_c": 2.0, "m_p": 0.5, "l": 0.7, "g": 9.81})
    q = np.random.default_rng(4).uniform(-1, 1, (50, 2))
    m_c, m_p, l, phi = 2.0, 0.5, 0.7, q[:, 1]  # M of the cart-pendulum in closed form
    one, c = np.ones_like(phi), m_p * l * np.cos(phi)
    closed = np.stack([[(m_c + m_p) * one, c], [c, m_p * l**2 * one]])
    assert np.allclose(eg.sweep(f, "M", q, chunk=16, cluster=cluster).compute(),
                       np.moveaxis(closed, (0, 1), (1, 2)), atol=1e-14)


@pytest.mark.parametrize("change, named", [
    ({"key": "Q"}, "key: no function 'Q'"), ({"key": "J:nowhere"}, "key: unknown frame 'nowhere'"),
    ({"key": 3}, "key:"), ({"chunk": 0}, "chunk:"), ({"chunk": 1.5}, "chunk:"), ({"chunk": True}, "chunk:"),
    ({"key": "nle"}, "states: the function reads q, u; u missing"),
    ({"states": np.zeros(6)}, "states: q must have shape (N, 6)"),
    ({"states": np.zeros((4, 5))}, "states: q must have shape (N, 6)"),
    ({"states": (np.zeros((4, 6)), np.zeros((3, 6)))}, "states: u must have shape (N, 6)"),
    ({"states": RandomChunks(None)}, "n:"), ({"n": 5}, "n: 5 given for states of 4 rows"),
    ({"functions": "M"}, "functions:"), ({"cluster": 3.5}, "cluster:")])
def test_bad_arguments_are_refused_by_name(ur5, change, named):
    system, f, _ = ur5
    arguments = {"functions": f, "key": "M", "states": np.zeros((4, 6)), "chunk": 2, **change}
    with pytest.raises(eg.ModelError, match=named.replace("(", r"\(").replace(")", r"\)")):
        eg.sweep(**arguments)
