"""eg.sweep on a local cluster of 2 worker processes: the result equals the direct call exactly at every
state (lazy Dask array and Zarr), reduced per chunk on the workers (np.maximum exactly, np.add to rounding),
M agrees with Pinocchio's crba, a worker killed mid-sweep is replaced
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


def test_a_reduced_sweep_is_the_reduction_of_the_direct_call_per_chunk(ur5, cluster):
    """reduce=np.maximum (exact in any order) equals the direct call's maximum over each chunk's states,
    bit for bit; reduce=np.add its sum to 1e-12 (the additions in another order). States made on the
    workers and given; chunks longer than a slice (1024 states) and a shorter last one."""
    system, f, _ = ur5
    make, n, chunk = RandomChunks(system, seed=5), 10_000, 4500
    q, u, _ = made(make, n, chunk)
    direct = [f.call("nle", q[k:k + chunk], u[k:k + chunk]) for k in range(0, n, chunk)]
    largest = eg.sweep(f, "nle", make, n=n, chunk=chunk, cluster=cluster, reduce=np.maximum)
    assert largest.shape == (3, 6, 1) and largest.chunks[0] == (1, 1, 1)
    assert np.array_equal(largest.compute(), np.stack([d.max(axis=0) for d in direct]))
    given = eg.sweep(f, "nle", (q, u), chunk=chunk, cluster=cluster, reduce=np.maximum)
    assert np.array_equal(given.compute(), largest.compute())
    sums = eg.sweep(f, "M", make, n=n, chunk=chunk, cluster=cluster, reduce=np.add).compute()
    expected = np.stack([f.call("M", q[k:k + chunk]).sum(axis=0) for k in range(0, n, chunk)])
    assert np.allclose(sums, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("name", ["ur5", "solo12"])
def test_random_states_fill_given_arrays_with_numpys_draws(name):
    """random_states(system, n, rng, out=(q, u)) fills q and u with NumPy's draws in the documented order
    (each coordinate's column by rng.uniform, a quaternion by rng.normal normalised, then u by
    rng.uniform(−2, 2)) and returns them; the whole call gives the same q, u."""
    system = eg.robots.load(name)
    n, rng = 1000, np.random.default_rng(9)
    columns = []
    for j in system.joints:
        if j.group == "SE3":
            columns += [rng.uniform(-1, 1, (n, 1)) for _ in range(3)]
            quat = rng.normal(size=(n, 4))
            columns.append(quat / np.linalg.norm(quat, axis=1, keepdims=True))
        else:
            columns.append(rng.uniform(-1, 1, (n, 1)) * np.pi)  # ur5's and solo12's revolute joints
    expected = np.concatenate(columns, axis=1), rng.uniform(-2, 2, (n, system.nv))
    out = np.empty((n, system.nq)), np.empty((n, system.nv))
    filled = eg.random_states(system, n, np.random.default_rng(9), out=out)
    assert all(x is y for x, y in zip(filled, out))
    for result in (filled, eg.random_states(system, n, np.random.default_rng(9))[:2]):
        assert all(np.array_equal(x, y) for x, y in zip(result, expected))
    with pytest.raises(eg.ModelError, match="random_states: out's u must be"):
        eg.random_states(system, n, rng, out=(out[0], np.empty((n, system.nv + 1))))


@pytest.mark.parametrize("change, named", [
    ({"key": "Q"}, "key: no function 'Q'"), ({"key": "J:nowhere"}, "key: unknown frame 'nowhere'"),
    ({"key": 3}, "key:"), ({"chunk": 0}, "chunk:"), ({"chunk": 1.5}, "chunk:"), ({"chunk": True}, "chunk:"),
    ({"key": "nle"}, "states: the function reads q, u; u missing"),
    ({"states": np.zeros(6)}, "states: q must have shape (N, 6)"),
    ({"states": np.zeros((4, 5))}, "states: q must have shape (N, 6)"),
    ({"states": (np.zeros((4, 6)), np.zeros((3, 6)))}, "states: u must have shape (N, 6)"),
    ({"states": RandomChunks(None)}, "n:"), ({"n": 5}, "n: 5 given for states of 4 rows"),
    ({"functions": "M"}, "functions:"), ({"cluster": 3.5}, "cluster:"), ({"reduce": sum}, "reduce:"),
    ({"reduce": np.sin}, "reduce:"), ({"reduce": np.less}, "reduce:"),
    ({"reduce": np.subtract}, "reduce: expected an associative")])
def test_bad_arguments_are_refused_by_name(ur5, change, named):
    system, f, _ = ur5
    arguments = {"functions": f, "key": "M", "states": np.zeros((4, 6)), "chunk": 2, **change}
    with pytest.raises(eg.ModelError, match=named.replace("(", r"\(").replace(")", r"\)")):
        eg.sweep(**arguments)
