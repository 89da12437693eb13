"""Issue 27: the gridfield Zarr store, the big-input readers, the chunk cache and the follower on a stored field.

References are independent of the code under test: numpy arrays the stores were written from, the in-memory
follower on the same field, the chunks of the cells a bilinear stencil touches computed here by hand, numpy's
flipud for an image's rows.
"""

from __future__ import annotations

import itertools
import json
import math

import dask.array as da
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gridfield.cli import main
from gridfield.core.chunkcache import ChunkCache, LazyArray, LazyGridMap
from gridfield.core.errors import GridfieldError, MapFormatError, SizeLimitError
from gridfield.core.grid import Grid, GridMap
from gridfield.core.limits import override
from gridfield.fields.potential import build_field
from gridfield.following.follower import follow
from gridfield.io import _zarr as zstore
from gridfield.io import read, read_bitmap, write_bitmap, write_store

RES = 0.5


def _map() -> GridMap:
    occ = np.zeros((96, 128), bool)
    occ[30:38, 10:50] = True
    occ[60:80, 80:86] = True
    occ[10:14, 100:120] = True
    return GridMap(Grid((96, 128), RES), occ)


@pytest.fixture(scope="module")
def field():
    return build_field(_map(), (55.0, 42.0), {"model": "khatib"})


def _field_arrays(f):
    return {"occupied": f.map.occupied, "U": f.potential, "dUdx": f.grad_x, "dUdy": f.grad_y,
            "distance": f.distance.distance, "nearest_row": f.distance.nearest_row,
            "nearest_col": f.distance.nearest_col}


def _write_field(path, f, chunks=16, **kw):
    arrays = {k: da.from_array(v, chunks=chunks) for k, v in _field_arrays(f).items()}
    return write_store(path, arrays, f.grid, kind="field", chunks=chunks, scheduler="synchronous",
                       attrs={"goal": f.goal, "params": f.params, "metric": f.distance.metric,
                              "saturate": f.params["saturate"]}, **kw)


@pytest.fixture(scope="module")
def store(field, tmp_path_factory):
    """The field written once in chunks of 16 (the tests below only read it)."""
    return _write_field(tmp_path_factory.mktemp("store") / "f.zarr", field)


# -- the store ------------------------------------------------------------------------------------
def test_field_store_round_trip(store, field):
    p = store
    assert not p.with_name("f.zarr.partial").exists()
    lf = read(p)
    assert isinstance(lf.map, LazyGridMap) and isinstance(lf.grad_x, LazyArray)
    assert lf.grid == field.grid and lf.goal == field.goal
    for name, ref in _field_arrays(field).items():
        got = {"occupied": lf.map.occupied, "U": lf.potential, "dUdx": lf.grad_x, "dUdy": lf.grad_y,
               "distance": lf.distance.distance, "nearest_row": lf.distance.nearest_row,
               "nearest_col": lf.distance.nearest_col}[name]
        np.testing.assert_array_equal(np.asarray(got), ref, err_msg=name)
    assert lf.params["model"] == "khatib" and lf.params["zeta"] == field.params["zeta"]
    meta = json.loads((p / "zarr.json").read_text())["attributes"]["gridfield"]
    assert meta["kind"] == "field" and meta["shape"] == [96, 128] and meta["resolution"] == RES
    assert meta["occupied_cells"] == int(field.map.occupied.sum())
    assert np.count_nonzero(~lf.map.occupied) == int((~field.map.occupied).sum())


def test_map_store_with_numpy_and_odd_chunks(tmp_path):
    occ = np.random.default_rng(3).random((37, 23)) < 0.3
    p = write_store(tmp_path / "m.zarr", {"occupied": occ}, Grid((37, 23), 2.0, (1.0, -4.0), "wall"), kind="map",
                    chunks=(8, 5), scheduler="synchronous")
    m = read(p)
    assert m.grid == Grid((37, 23), 2.0, (1.0, -4.0), "wall") and m.occupied.chunks == (8, 5)
    np.testing.assert_array_equal(np.asarray(m.occupied), occ)
    assert m.occupied_fraction == pytest.approx(occ.mean())


def test_interrupted_write_resumes(tmp_path, field, monkeypatch):
    out = tmp_path / "f.zarr"
    real = zstore._mark_done
    calls = {"n": 0}

    def failing(progress, name, i, j):
        if calls["n"] == 9:
            raise RuntimeError("injected: the machine went away")
        calls["n"] += 1
        real(progress, name, i, j)

    monkeypatch.setattr(zstore, "_mark_done", failing)
    with pytest.raises(RuntimeError, match="injected"):
        _write_field(out, field, chunks=32, resume_key="run-1")
    assert not out.exists() and (tmp_path / "f.zarr.partial").is_dir()
    assert len(list((tmp_path / "f.zarr.partial" / ".progress").iterdir())) == 9
    with pytest.raises(MapFormatError, match="interrupted write"):
        read(out)
    with pytest.raises(GridfieldError, match="other arguments"):
        _write_field(out, field, chunks=32, resume_key="run-2")
    written = []
    monkeypatch.setattr(zstore, "_mark_done", lambda progress, name, i, j: (written.append((name, i, j)),
                                                                              real(progress, name, i, j)))
    _write_field(out, field, chunks=32, resume_key="run-1")
    total = 7 * math.ceil(96 / 32) * math.ceil(128 / 32)
    assert len(written) == total - 9  # only the chunks not yet written
    lf = read(out)
    np.testing.assert_array_equal(np.asarray(lf.grad_y), field.grad_y)
    np.testing.assert_array_equal(np.asarray(lf.potential), field.potential)
    assert not (tmp_path / "f.zarr.partial").exists()


def test_store_without_metadata_is_one_error(tmp_path, capsys):
    import zarr

    g = zarr.open_group(str(tmp_path / "x.zarr"), mode="w")
    g.create_array("distance", shape=(4, 4), chunks=(2, 2), dtype="f8")
    with pytest.raises(MapFormatError, match="without gridfield grid metadata"):
        read(tmp_path / "x.zarr")
    assert main(["plan", str(tmp_path / "x.zarr"), "--start", "1", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "x.zarr" in err[0] and "gridfield grid metadata" in err[0]


def test_write_refuses_an_existing_store(tmp_path):
    occ = np.zeros((4, 4), bool)
    write_store(tmp_path / "m.zarr", {"occupied": occ}, Grid((4, 4), 1.0), kind="map", scheduler="synchronous")
    with pytest.raises(GridfieldError, match="already exists"):
        write_store(tmp_path / "m.zarr", {"occupied": occ}, Grid((4, 4), 1.0), kind="map")


# -- the chunk cache ------------------------------------------------------------------------------
@settings(max_examples=40, deadline=None)
@given(st.integers(1, 9), st.integers(1, 9), st.integers(0, 24), st.integers(0, 24), st.integers(0, 25),
       st.integers(0, 25))
def test_lazy_array_indexing_matches_numpy(r, c, a, b, h, w):
    ref = np.arange(25 * 26, dtype=np.float64).reshape(25, 26)
    lz = LazyArray(ref, chunks=(r, c), cache=ChunkCache(10**6))
    np.testing.assert_array_equal(lz[a:a + h, b:b + w], ref[a:a + h, b:b + w])
    assert lz[a, min(b, 25)] == ref[a, min(b, 25)]
    rows = (np.arange(30) * 7 + a) % 25
    cols = (np.arange(30) * 11 + b) % 26
    np.testing.assert_array_equal(lz.take(rows, cols), ref[rows, cols])


def test_chunk_cache_budget_evicts_least_recently_used():
    ref = np.zeros((40, 40))
    cache = ChunkCache(budget=3 * 10 * 10 * 8)  # three 10 x 10 tiles
    lz = LazyArray(ref, chunks=(10, 10), cache=cache, name="a")
    for ci in range(4):
        lz[ci * 10, 0]
    assert cache.reads == 4 and cache.nbytes <= cache.budget
    lz[30, 0]  # the newest: a hit
    lz[0, 0]   # the oldest was dropped: read again
    assert cache.hits == 1 and cache.reads == 5


# -- the follower on a stored field -------------------------------------------------------------
@pytest.mark.parametrize("sampling", ["bilinear", "nearest"])
def test_follow_on_store_is_the_in_memory_path(store, field, sampling):
    lf = read(store)
    for start in [(3.0, 3.0), (60.0, 5.0), (10.0, 45.0)]:
        a = follow(field, start, params={"sampling": sampling})
        b = follow(lf, start, params={"sampling": sampling})
        assert a.status == b.status and a.iterations == b.iterations
        np.testing.assert_array_equal(a.points, b.points)
        assert a.min_clearance == b.min_clearance


def test_follower_reads_only_the_chunks_it_crosses(store, field):
    chunk = 16
    lf = read(store)
    path = follow(lf, (3.0, 3.0))
    assert path.status == "reached"
    cache = lf.map.occupied.cache
    # the bilinear stencil of every point the follower sampled: cells floor(u), floor(u) + 1 (clamped)
    pts = path.points
    u = np.clip((pts[:, 0] - 0.0) / RES - 0.5, 0, 127)
    v = np.clip((pts[:, 1] - 0.0) / RES - 0.5, 0, 95)
    i0, j0 = u.astype(int), v.astype(int)
    stencil = set()
    for di in (0, 1):
        for dj in (0, 1):
            ii, jj = np.minimum(i0 + di, 127), np.minimum(j0 + dj, 95)
            stencil |= set(zip((jj // chunk).tolist(), (ii // chunk).tolist(), strict=True))
    grad = {(i, j) for name, i, j in cache.read_keys if name == "dUdx"}
    # the path's points are the points sampled, except the last (the goal, reached, not sampled)
    assert grad <= stencil and len(stencil - grad) <= 1
    total = math.ceil(96 / chunk) * math.ceil(128 / chunk)
    assert len(grad) < total / 2
    occ = {(i, j) for name, i, j in cache.read_keys if name == "occupied"}
    near = {((np.clip(j + dj, 0, 95)) // chunk, (np.clip(i + di, 0, 127)) // chunk)
            for j, i in zip(np.floor(pts[:, 1] / RES).astype(int), np.floor(pts[:, 0] / RES).astype(int), strict=True)
            for dj in (-2, -1, 0, 1, 2) for di in (-2, -1, 0, 1, 2)}
    assert occ <= near  # occupancy: the cells around the path (segment checks, one cell of margin)
    assert {n for n, _, _ in cache.read_keys} <= {"occupied", "dUdx", "dUdy", "distance"}


def test_cli_plan_on_a_store(store, field, capsys):
    p = store
    assert main(["plan", str(p), "--start", "3", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    ref = follow(field, (3.0, 3.0))
    assert out["status"] == ref.status == "reached"
    assert out["iterations"] == ref.iterations and 0 < out["chunks_read"] < 4 * 48
    assert main(["plan", str(p), "--start", "3", "3", "--goal", "1", "1"]) == 2
    assert "field of the goal" in capsys.readouterr().err


# -- big inputs ---------------------------------------------------------------------------------
def test_bigtiff_geotiff_reader(tmp_path):
    import tifffile

    walls = np.random.default_rng(5).random((70, 90)) < 0.2
    img = np.where(walls, 0, 255).astype(np.uint8)  # an image: black walls on white
    f = tmp_path / "m.tif"
    tifffile.imwrite(f, img, bigtiff=True, tile=(32, 32),
                     extratags=[(33550, 12, 3, (0.25, 0.25, 0.0)), (33922, 12, 6, (0, 0, 0, 100.0, 50.0, 0))])
    m = read(f)
    assert isinstance(m, LazyGridMap) and m.occupied.chunks == (32, 32)
    assert m.grid.resolution == 0.25 and m.grid.origin == (100.0, 50.0 - 70 * 0.25)
    np.testing.assert_array_equal(np.asarray(m.occupied), np.flipud(walls))
    assert bool(m.occupied[69, 3]) == bool(walls[0, 3])  # the image's top row is the highest y
    m2 = read(f, resolution=1.0, origin=(0, 0))
    assert m2.grid.resolution == 1.0 and m2.grid.origin == (0.0, 0.0)
    del m, m2


def test_npy_and_zarr_array_readers(tmp_path):
    import zarr

    occ = np.random.default_rng(7).random((50, 40)) < 0.25
    np.save(tmp_path / "m.npy", occ.astype(np.uint8))
    m = read(tmp_path / "m.npy", resolution=0.1, chunks=16)
    assert isinstance(m, LazyGridMap) and m.occupied.chunks == (16, 16)
    np.testing.assert_array_equal(m.occupied.window(0, 50, 0, 40), occ)
    z = zarr.open_array(str(tmp_path / "a.zarr"), mode="w", shape=occ.shape, chunks=(10, 10), dtype=bool)
    z[...] = occ
    m = read(tmp_path / "a.zarr", resolution=2.0)
    np.testing.assert_array_equal(np.asarray(m.occupied), occ)
    assert m.is_free([[1.0, 1.0]]).tolist() == [not occ[0, 0]]


def test_lazy_inputs_bypass_the_in_memory_size_guard(tmp_path):
    np.save(tmp_path / "m.npy", np.zeros((200, 300), bool))
    write_bitmap(tmp_path / "m.png", GridMap(Grid((200, 300), 1.0), np.zeros((200, 300), bool)))
    with override(1000):
        m = read(tmp_path / "m.npy")  # read by chunks: nothing is allocated whole
        assert m.shape == (200, 300)
        with pytest.raises(SizeLimitError, match=r"in-memory formats.*BigTIFF.*npy.*Zarr"):
            read_bitmap(tmp_path / "m.png")


# -- the command line ---------------------------------------------------------------------------
def test_cli_chunk_options_need_out(tmp_path, capsys):
    np.save(tmp_path / "m.npy", np.zeros((20, 20), bool))
    assert main(["brushfire", str(tmp_path / "m.npy"), "--chunks", "8"]) == 2
    assert "--out" in capsys.readouterr().err
    assert main(["brushfire", str(tmp_path / "m.npy"), "--out", str(tmp_path / "d.npz")]) == 2
    assert ".zarr" in capsys.readouterr().err


def test_cli_chunks_smaller_than_the_halo(tmp_path, capsys):
    np.save(tmp_path / "m.npy", np.zeros((20, 20), bool))
    code = main(["brushfire", str(tmp_path / "m.npy"), "--chunks", "4", "--saturate", "5", "--metric",
                 "euclidean", "--out", str(tmp_path / "d.zarr")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "saturation halo" in err[0] and "--chunks 6" in err[0]
    assert not (tmp_path / "d.zarr").exists() and not (tmp_path / "d.zarr.partial").exists()


def test_cli_unreachable_scheduler(tmp_path, capsys, monkeypatch):
    import socket

    from gridfield.cli import _chunked

    monkeypatch.setattr(_chunked, "CONNECT_TIMEOUT", 1.0)

    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()  # a port nobody listens on
    np.save(tmp_path / "m.npy", np.zeros((20, 20), bool))
    code = main(["brushfire", str(tmp_path / "m.npy"), "--chunks", "8", "--out", str(tmp_path / "d.zarr"),
                 "--scheduler", f"tcp://127.0.0.1:{port}"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "cannot reach the dask scheduler" in err[0]
    assert not (tmp_path / "d.zarr").exists() and not (tmp_path / "d.zarr.partial").exists()


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["bilinear", "nearest"]), st.integers(1, 7))
def test_lazy_samplers_equal_the_compiled_ones(seed, sampling, chunk):
    from types import SimpleNamespace

    from gridfield.fields.sampling import grid_blocked, grid_potential_sampler, grid_sampler, sample_force

    rng = np.random.default_rng(seed)
    occ = rng.random((9, 11)) < 0.3
    gx, gy, u = rng.normal(size=(3, 9, 11))
    grid = Grid((9, 11), 0.5, (-1.0, 2.0), "wall" if seed % 2 else "open")
    mem = SimpleNamespace(map=GridMap(grid, occ), grad_x=gx, grad_y=gy, potential=u)
    cache = ChunkCache()
    lz = SimpleNamespace(map=LazyGridMap(grid, LazyArray(occ, chunks=(chunk, chunk), cache=cache)),
                         grad_x=LazyArray(gx, chunks=(chunk, chunk), cache=cache),
                         grad_y=LazyArray(gy, chunks=(chunk, chunk), cache=cache),
                         potential=LazyArray(u, chunks=(chunk, chunk), cache=cache))
    pts = rng.uniform([-2.0, 1.0], [5.0, 7.0], size=(40, 2))  # inside and around the grid
    fm, fl = grid_sampler(mem, sampling=sampling), grid_sampler(lz, sampling=sampling)
    um, ul = grid_potential_sampler(mem, sampling=sampling), grid_potential_sampler(lz, sampling=sampling)
    bm, bl = grid_blocked(mem.map), grid_blocked(lz.map)
    for p, q in itertools.pairwise(pts):
        assert fm(tuple(p)) == fl(tuple(p))
        assert um(tuple(p)) == ul(tuple(p))
        assert bm(tuple(p), tuple(p + (q - p) * 0.2)) == bl(tuple(p), tuple(p + (q - p) * 0.2))
    np.testing.assert_array_equal(sample_force(mem, pts, sampling=sampling), sample_force(lz, pts, sampling=sampling))


def test_a_stop_just_before_the_rename_resumes_with_nothing_to_write(tmp_path, monkeypatch):
    occ = np.random.default_rng(2).random((20, 20)) < 0.2
    args = ({"occupied": occ}, Grid((20, 20), 1.0))
    real = zstore._publish

    def stop(*a):
        raise RuntimeError("stopped before the rename")

    monkeypatch.setattr(zstore, "_publish", stop)
    with pytest.raises(RuntimeError, match="before the rename"):
        write_store(tmp_path / "m.zarr", *args, kind="map", chunks=8, resume_key="k", scheduler="synchronous")
    assert not (tmp_path / "m.zarr").exists()
    monkeypatch.setattr(zstore, "_publish", real)
    written = []
    monkeypatch.setattr(zstore, "_mark_done", lambda *a: written.append(a))
    write_store(tmp_path / "m.zarr", *args, kind="map", chunks=8, resume_key="k", scheduler="synchronous")
    assert written == []
    m = read(tmp_path / "m.zarr")
    np.testing.assert_array_equal(np.asarray(m.occupied), occ)
    assert not (tmp_path / "m.zarr" / ".progress").exists() and "gridfield_partial" not in json.loads(
        (tmp_path / "m.zarr" / "zarr.json").read_text())["attributes"]
