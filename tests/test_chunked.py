"""gridfield.chunked on a real Dask cluster: bit-identical to the in-memory brushfire.

The reference is :func:`gridfield.distance.brushfire.brushfire` on the whole array (its own tests check it against
scipy and brute force); here every chunked result is compared with it by ``np.array_equal``. A
``distributed.LocalCluster`` of 2 worker processes (1 thread each) on 127.0.0.1 runs the graphs, with a
memory limit below what the whole map's arrays plus a worker's own footprint need (the workers spill and
hold strips, never the map). Small, exhaustive cases (every metric, border and saturation, odd chunks)
run on the local synchronous scheduler.
"""

from __future__ import annotations

import contextlib
import os
import time

import numpy as np
import pytest

dask = pytest.importorskip("dask")
da = pytest.importorskip("dask.array")
distributed = pytest.importorskip("distributed")

from gridfield.chunked import connect, distance, field, gvd, labels, scratch_dir, wavefront  # noqa: E402
from gridfield.core.errors import ArgumentTypeError, GridfieldError, ParameterError  # noqa: E402
from gridfield.core.grid import Grid, GridMap  # noqa: E402
from gridfield.distance.brushfire import brushfire  # noqa: E402
from gridfield.fields.potential import build_field  # noqa: E402
from gridfield.io import read  # noqa: E402

N = 2048  # map side on the cluster
CHUNK = 256
#: Per worker. The whole map's arrays (occupancy 4 MiB, column pass 16 MiB, distance and nearest cells
#: 64 MiB, the row-pass records 64 MiB: ~150 MiB) and a worker's own ~90-130 MiB do not fit in it.
MEMORY_LIMIT = "256MiB"


@pytest.fixture(scope="module")
def client():
    # dashboard_address=":0": a free port for the scheduler's HTTP routes (None serves them on 8787, which a
    # cluster of another xdist worker may hold: a warning and an unclosed socket; tests/test_ci_warnings.py)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1", dashboard_address=":0",
                                  memory_limit=MEMORY_LIMIT) as cluster, distributed.Client(cluster) as c:
        yield c


def reference(occ: np.ndarray, metric: str = "euclidean", *, border: str = "wall", resolution: float = 1.0,
              saturate: float | None = None):
    gm = GridMap(Grid(occ.shape, resolution, border=border), occ)
    return brushfire(gm, metric=metric, saturate=saturate, compute_labels=False, compute_steps=False)


def random_map(n: int, density: float, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).random((n, n)) < density


def tiled(path, n: int) -> np.ndarray:
    occ = read(path).occupied
    reps = (-(-n // occ.shape[0]), -(-n // occ.shape[1]))
    return np.tile(occ, reps)[:n, :n].copy()


# ------------------------------------------------------------------------------------------------
# exhaustive small cases (synchronous scheduler: no cluster needed for the arithmetic)
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("border", ["wall", "open"])
def test_small_maps_equal_brushfire(border):
    rng = np.random.default_rng(7)
    for shape, chunks in (((37, 53), (8, 11)), ((100, 30), (33, 7)), ((1, 9), 5), ((9, 1), 5)):
        for density in (0.0, 0.01, 0.3):
            occ = rng.random(shape) < density
            x = da.from_array(occ, chunks=chunks)
            cases = [(metric, sat) for metric in ("euclidean", "chessboard", "taxicab") for sat in (None, 1.0)]
            lazy = [distance(x, metric=m, resolution=0.25, saturate=s, border=border) for m, s in cases]
            lazy += [distance(x, resolution=0.25, saturate=s, border=border, return_nearest=True) for s in (None, 1.0)]
            assert all(d.chunks == x.chunks and d.dtype == np.float64 for d in lazy[:len(cases)])
            got = dask.compute(*lazy, scheduler="synchronous")  # one graph for all
            for (metric, sat), d in zip(cases, got, strict=False):
                ref = reference(occ, metric, border=border, resolution=0.25, saturate=sat)
                assert np.array_equal(d, ref.distance), (shape, density, metric, sat)
            for sat, (d, nr, nc) in zip((None, 1.0), got[len(cases):], strict=True):
                ref = reference(occ, border=border, resolution=0.25, saturate=sat)
                assert np.array_equal(d, ref.distance)
                assert np.array_equal(nr, ref.nearest_row) and np.array_equal(nc, ref.nearest_col)
                assert nr.dtype == nc.dtype == np.int32


def test_long_distances_cross_many_chunks():
    """One obstacle in a large open map: every distance spans many chunks, in both passes."""
    occ = np.zeros((300, 280), bool)
    occ[290, 3] = True
    x = da.from_array(occ, chunks=(16, 24))
    with dask.config.set(scheduler="synchronous"):
        for metric in ("euclidean", "chessboard", "taxicab"):
            ref = reference(occ, metric, border="open")
            assert np.array_equal(distance(x, metric=metric, border="open").compute(scheduler="synchronous"), ref.distance)
        d, nr, nc = dask.compute(*distance(x, border="open", return_nearest=True))
    assert (nr == 290).all() and (nc == 3).all()
    rr, cc = np.indices(occ.shape)
    assert np.array_equal(d, np.sqrt((rr - 290) ** 2 + (cc - 3) ** 2.0))  # exact geometry as well


@pytest.mark.parametrize("border", ["wall", "open"])
def test_field_equals_build_field(border):
    """The chunked khatib field against build_field on the whole map (its own arithmetic, bit for bit)."""
    rng = np.random.default_rng(3)
    for params in ({}, {"zeta": 0.5, "eta": 2, "q_star": 3, "d_star": 4}, {"repulsive_power": 3, "saturate": 2.0},
                   {"d_star": 0}):
        occ = rng.random((70, 90)) < 0.03
        gm = GridMap(Grid((70, 90), 0.5, origin=(1.25, -3.0), border=border), occ)
        free = np.argwhere(~occ)
        g = tuple(int(v) for v in free[len(free) // 2])
        ref = build_field(gm, tuple(gm.grid.cell_to_world(np.array(g))[0]), {"model": "khatib", **params})
        d, nr, nc = distance(da.from_array(occ, chunks=(16, 25)), resolution=0.5, border=border, return_nearest=True)
        f = field(d, nr, nc, goal_cell=g, resolution=0.5, origin=(1.25, -3.0), params=params)
        u, gx, gy = dask.compute(f["U"], f["dUdx"], f["dUdy"], scheduler="synchronous")
        assert np.array_equal(u, ref.potential) and np.array_equal(gx, ref.grad_x), params
        assert np.array_equal(gy, ref.grad_y), params
    with pytest.raises(ParameterError, match=r"the chunked field computes repulsion 'nearest' only"):
        field(d, nr, nc, goal_cell=g, params={"repulsion": "sum"})
    with pytest.raises(GridfieldError, match=r"goal_cell \(0, 0\) lies inside an obstacle"):
        occ = np.zeros((8, 8), bool)
        occ[0, 0] = True
        field(*distance(da.from_array(occ, chunks=4), return_nearest=True), goal_cell=(0, 0))


def test_labels_equal_scipy_and_brushfire():
    from scipy import ndimage

    rng = np.random.default_rng(5)
    for shape, chunks in (((37, 53), (8, 11)), ((64, 64), 16), ((100, 30), (33, 7)), ((5, 5), 1), ((16, 16), 4)):
        for density in (0.0, 0.1, 0.3, 0.5, 0.6):  # 0.5-0.6: components that wind across many seams
            occ = rng.random(shape) < density
            ref, _ = ndimage.label(occ, structure=np.ones((3, 3)))
            got = labels(da.from_array(occ, chunks=chunks)).compute(scheduler="synchronous")
            assert got.dtype == np.int32 and np.array_equal(got, ref), (shape, density)
            bf = brushfire(GridMap(Grid(shape, 1.0, border="open"), occ), metric="euclidean").label
            assert np.array_equal(got[occ], bf[occ])


# ------------------------------------------------------------------------------------------------
# the cluster: random, maze and tiled real maps at 2048 x 2048, chunks of 256 x 256
# ------------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_cluster_random_map(client):
    occ = random_map(N, 0.002, 1)  # sparse: distances up to tens of cells, across chunk seams
    x = da.from_array(occ, chunks=CHUNK)
    ref = reference(occ)
    lazy = distance(x, return_nearest=True)
    f = field(*lazy, goal_cell=(1000, 1000))
    d, nr, nc, u = dask.compute(*lazy, f["U"])
    assert np.array_equal(d, ref.distance)
    assert np.array_equal(nr, ref.nearest_row) and np.array_equal(nc, ref.nearest_col)
    gm = GridMap(Grid(occ.shape, 1.0, border="wall"), occ)
    assert np.array_equal(u, build_field(gm, (1000.5, 1000.5), {"model": "khatib"}).potential)
    ref = reference(occ, "taxicab", border="open", saturate=12.0)
    assert np.array_equal(distance(x, metric="taxicab", border="open", saturate=12.0).compute(), ref.distance)


@pytest.mark.slow
def test_cluster_maze_and_real_maps(client, test_maps):
    movingai = test_maps / "movingai"
    for name, metric in (("maze512-32-9", "euclidean"), ("AcrosstheCape", "chessboard")):
        occ = tiled(movingai / name / f"{name}.map.gz", N)
        x = da.from_array(occ, chunks=CHUNK)
        ref = reference(occ, metric, resolution=0.05)
        assert np.array_equal(distance(x, metric=metric, resolution=0.05).compute(), ref.distance), name
    from scipy import ndimage

    assert np.array_equal(labels(x).compute(), ndimage.label(occ, structure=np.ones((3, 3)))[0])


@pytest.mark.parametrize("border", ["wall", "open"])
def test_gvd_and_nearest_labels_equal_brushfire_on_small_maps(border):
    """The label of each cell's nearest obstacle (two gathers along the separable passes) and the GVD (a
    one-cell halo) on odd chunks, against the in-memory brushfire, bit for bit; maps without obstacles and
    maps of one obstacle cell included."""
    rng = np.random.default_rng(5)
    cases = [np.zeros((6, 9), bool), np.eye(7, 11, 3, dtype=bool)]
    cases += [rng.random(tuple(rng.integers(3, 50, 2))) < rng.choice([0.01, 0.05, 0.2, 0.5]) for _ in range(30)]
    for occ in cases:
        chunks = tuple(int(v) for v in rng.integers(2, 17, 2))
        d, lab, g = dask.compute(*gvd(da.from_array(occ, chunks=chunks), border=border, resolution=0.5),
                                 scheduler="synchronous")
        ref = brushfire(GridMap(Grid(occ.shape, 0.5, border=border), occ), metric="euclidean")
        assert np.array_equal(d, ref.distance), (occ.shape, chunks)
        assert np.array_equal(lab, ref.label), (occ.shape, chunks)
        assert np.array_equal(g, ref.gvd), (occ.shape, chunks)
        assert g.dtype == bool and lab.dtype == np.int32


def test_cluster_gvd_on_a_real_map(client, test_maps):
    """The GVD of a tiled Moving AI map on the cluster, chunks of 256 cells, equals the in-memory one."""
    occ = tiled(test_maps / "movingai" / "den312d" / "den312d.map.gz", 1024)
    d, lab, g = dask.compute(*gvd(da.from_array(occ, chunks=CHUNK), resolution=0.05))
    ref = brushfire(GridMap(Grid(occ.shape, 0.05, border="wall"), occ), metric="euclidean")
    assert np.array_equal(d, ref.distance) and np.array_equal(lab, ref.label) and np.array_equal(g, ref.gvd)
    assert 0 < g.sum() < g.size  # a skeleton, not nothing or everything


def test_wavefront_equals_the_in_memory_navigation_function():
    """Tile-wise Dijkstra with boundary exchange ends at the in-memory wavefront's values, bit for bit:
    random maps on odd chunks, octile and unit diagonals, goals anywhere (unreachable cells stay inf)."""
    from gridfield.fields.navigation import wavefront as in_memory

    rng = np.random.default_rng(11)
    for _ in range(10):
        shape = tuple(int(v) for v in rng.integers(3, 45, 2))
        occ = rng.random(shape) < rng.choice([0.0, 0.1, 0.3, 0.45])
        free = np.argwhere(~occ)
        if not len(free):
            continue
        g = tuple(int(v) for v in free[rng.integers(len(free))])
        costs = str(rng.choice(["octile", "unit"]))
        chunks = tuple(int(v) for v in rng.integers(4, 17, 2))
        with dask.config.set(scheduler="synchronous"):
            v, rounds = wavefront(da.from_array(occ, chunks=chunks), g, costs=costs)
            got = v.compute()
        ref = in_memory(GridMap(Grid(shape, 1.0, border="wall"), occ), (g[1] + 0.5, g[0] + 0.5), costs=costs).value
        assert np.array_equal(got, ref), (shape, chunks, costs)
        assert rounds >= 1


def test_cluster_wavefront_on_a_maze(client, test_maps):
    """A Moving AI maze (a 192-cell corner; its corridors cross the 64-cell chunk seams back and forth) on
    the cluster."""
    from gridfield.fields.navigation import wavefront as in_memory

    occ = read(test_maps / "movingai" / "maze512-32-9" / "maze512-32-9.map.gz").occupied[:192, :192].copy()
    g = tuple(int(v) for v in np.argwhere(~occ)[len(np.argwhere(~occ)) // 2])
    v, rounds = wavefront(da.from_array(occ, chunks=64), g)
    ref = in_memory(GridMap(Grid(occ.shape, 1.0, border="wall"), occ), (g[1] + 0.5, g[0] + 0.5), costs="octile").value
    assert np.array_equal(v.compute(), ref)
    assert rounds > 3  # the seams are crossed many times: more rounds than chunks along a side


def test_wavefront_bad_input():
    occ = da.from_array(np.eye(4, dtype=bool), chunks=2)
    with pytest.raises(ParameterError, match="inside an obstacle"):
        wavefront(occ, (1, 1))
    with pytest.raises(ParameterError, match="outside the grid"):
        wavefront(occ, (9, 0))
    with pytest.raises(ParameterError, match="costs must be one of"):
        wavefront(occ, (0, 1), costs="euclid")
    maze = np.zeros((2, 40), bool)
    with pytest.raises(GridfieldError, match="did not settle in 2 rounds"):
        wavefront(da.from_array(maze, chunks=(2, 4)), (0, 0), max_rounds=2)


@pytest.mark.slow
def test_cluster_worker_killed_mid_run(client):
    """A worker process dies while the graph runs: its nanny restarts it, Dask recomputes what it held,
    and the result is complete and equal."""
    occ = random_map(N, 0.001, 2)
    before = set(client.scheduler_info()["workers"])
    future = client.compute(distance(da.from_array(occ, chunks=CHUNK)))
    victim = None
    deadline = time.monotonic() + 60
    while victim is None and time.monotonic() < deadline:
        held = client.has_what()
        victim = next((w for w, keys in held.items() if keys), None)
        if victim is None:
            time.sleep(0.05)
    assert victim is not None and not future.done(), "the graph finished before a worker could be killed"
    with contextlib.suppress(Exception):  # the worker dies before it answers
        client.run(os._exit, 1, workers=[victim])
    d = future.result(timeout=300)
    assert np.array_equal(d, reference(occ).distance)
    client.wait_for_workers(2, timeout=60)
    assert victim not in set(client.scheduler_info()["workers"]) and victim in before


# ------------------------------------------------------------------------------------------------
# the passes through a temporary store (scratch=): equal, and the store gone after the run
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("border", ["wall", "open"])
def test_scratch_store_equals_brushfire_and_is_removed(tmp_path, border):
    rng = np.random.default_rng(5)
    where = tmp_path / "out.zarr.scratch"
    for k, (shape, chunks) in enumerate((((37, 53), (8, 8)), ((15, 34), ((5, 7, 3), (10, 3, 20, 1))),
                                         ((64, 64), (64, 1)), ((1, 9), (1, 4)))):
        occ = rng.random(shape) < (0.01, 0.05, 0.002, 0.3)[k]
        occ[0, 0] = border == "open" or occ[0, 0]  # an open border needs an obstacle for nearest cells
        ref = reference(occ, border=border, resolution=0.25)
        x = da.from_array(occ, chunks=chunks)
        with scratch_dir(where) as s:
            d, nr, nc = dask.compute(*distance(x, resolution=0.25, border=border, return_nearest=True, scratch=s),
                                     scheduler="threads")
            d_only = distance(x, resolution=0.25, border=border, scratch=s).compute(scheduler="synchronous")
            sat = distance(x, resolution=0.25, border=border, saturate=1.0, return_nearest=True, scratch=s)[0]
            sat = sat.compute(scheduler="synchronous")
            assert [p.name.startswith("column-pass-") for p in where.iterdir()] == [True, True]
        assert not where.exists()
        assert np.array_equal(d, ref.distance) and np.array_equal(d_only, ref.distance), (k, border)
        assert np.array_equal(nr, ref.nearest_row) and np.array_equal(nc, ref.nearest_col), (k, border)
        assert np.array_equal(sat, np.where(ref.distance >= 1.0, np.inf, ref.distance)), (k, border)


def test_scratch_store_removed_when_the_run_fails(tmp_path):
    def boom(block):
        raise RuntimeError("a failing input chunk")

    occ = da.from_array(np.zeros((32, 32), bool), chunks=8)
    bad = occ.map_blocks(lambda b, block_info=None: boom(b) if block_info[0]["chunk-location"] == (3, 2) else b,
                         dtype=bool)
    where = tmp_path / "s"
    with pytest.raises(RuntimeError, match="a failing input chunk"), scratch_dir(where) as s:
        distance(bad, return_nearest=True, scratch=s)[0].compute(scheduler="threads")
    assert not where.exists() and list(tmp_path.iterdir()) == []


def test_scratch_dir_removes_a_stale_one_and_refuses_a_foreign_one(tmp_path):
    stale = tmp_path / "stale"
    (stale / "column-pass-0123.zarr").mkdir(parents=True)  # left by a killed run
    with scratch_dir(stale) as s:
        assert list(s.iterdir()) == []
    assert not stale.exists()
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    with pytest.raises(GridfieldError, match=r"holds \['notes.txt'\], not only temporary stores"), scratch_dir(mine):
        pass
    assert (mine / "notes.txt").read_text() == "keep"
    (tmp_path / "file").write_text("")
    with pytest.raises(GridfieldError, match="is not a directory"), scratch_dir(tmp_path / "file"):
        pass
    with scratch_dir(tmp_path / "early") as s:  # the graph built inside, computed after the block
        lazy = distance(da.zeros((8, 8), dtype=bool, chunks=4), scratch=s)
    with pytest.raises(GridfieldError, match="the temporary store between the passes is gone; compute the results "
                                             r"inside the scratch_dir\(\) block"):
        lazy.compute(scheduler="synchronous")
    with pytest.raises(ArgumentTypeError, match="scratch must be a directory path, got int"):
        distance(da.zeros((4, 4), dtype=bool, chunks=2), scratch=3)


@pytest.mark.slow
def test_cluster_scratch_store_worker_killed_mid_run(client, tmp_path):
    """Through the store on the cluster: equal, a worker killed in the row pass changes nothing (its tasks
    are recomputed; the column strips rewritten, if at all, atomically), and the store is gone after."""
    occ = random_map(N, 0.001, 3)
    ref = reference(occ)
    where = tmp_path / "scratch"
    with scratch_dir(where) as s:
        lazy = distance(da.from_array(occ, chunks=CHUNK), return_nearest=True, scratch=s)
        futures = client.compute(list(lazy))
        victim = None
        deadline = time.monotonic() + 60
        while victim is None and time.monotonic() < deadline:
            held = client.has_what()
            victim = next((w for w, keys in held.items() if any("edt-block" in str(k) for k in keys)), None)
            if victim is None:
                time.sleep(0.02)
        assert victim is not None and not all(f.done() for f in futures), "finished before a worker was killed"
        with contextlib.suppress(Exception):
            client.run(os._exit, 1, workers=[victim])
        d, nr, nc = client.gather(futures)
    assert not where.exists()
    assert np.array_equal(d, ref.distance)
    assert np.array_equal(nr, ref.nearest_row) and np.array_equal(nc, ref.nearest_col)
    client.wait_for_workers(2, timeout=60)


# ------------------------------------------------------------------------------------------------
# bad input: one clear error each
# ------------------------------------------------------------------------------------------------
def test_bad_input():
    x = da.zeros((40, 40), dtype=bool, chunks=10)
    with pytest.raises(ArgumentTypeError, match=r"occupied must be a dask.array.Array, got ndarray \(wrap it"):
        distance(np.zeros((4, 4), bool))
    with pytest.raises(ParameterError, match=r"occupied must be boolean \(True = obstacle\), got dtype int64"):
        distance(da.zeros((4, 4), dtype=np.int64, chunks=2))
    with pytest.raises(ParameterError, match=r"occupied must be 2-D"):
        distance(da.zeros((4, 4, 4), dtype=bool, chunks=2))
    with pytest.raises(ParameterError, match=r"metric must be one of"):
        distance(x, metric="octile")
    with pytest.raises(ParameterError, match=r"border must be one of"):
        distance(x, border="closed")
    with pytest.raises(ParameterError, match=r"resolution must be a positive finite number, got 0"):
        distance(x, resolution=0)
    with pytest.raises(ParameterError, match=r"saturate must be a positive finite number"):
        distance(x, saturate=-1)
    with pytest.raises(ParameterError, match=r"chunks of 10 cells are smaller than the saturation halo of 13 cells"):
        distance(x, saturate=12)
    with pytest.raises(ParameterError, match=r"return_nearest=True needs metric='euclidean'"):
        distance(x, metric="chessboard", return_nearest=True)
    with pytest.raises(ParameterError, match=r"far must be a number"):
        distance(x, saturate=2, far="x")


def test_unreachable_scheduler():
    with pytest.raises(GridfieldError, match=r"^cannot connect to the Dask scheduler 'tcp://127.0.0.1:1' within "
                                             r"0.5 s: "):
        connect("tcp://127.0.0.1:1", timeout=0.5)
