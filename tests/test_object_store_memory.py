"""The passes' temporary store and the stores at a URL, in memory (``memory://``, fsspec's in-process file
system: no server, so the local schedulers only), against the in-memory brushfire and scipy.

The S3 server and the cluster are tests/test_object_store.py's; these run where fsspec alone is there."""

from __future__ import annotations

import numpy as np
import pytest

fsspec = pytest.importorskip("fsspec", reason="URLs need fsspec (the [s3] extra)")
da = pytest.importorskip("dask.array", reason="the chunked computation needs Dask (the [dask] extra)")

from scipy.ndimage import distance_transform_edt  # noqa: E402

from gridfield.chunked import distance, gvd, scratch_dir  # noqa: E402
from gridfield.cli import main  # noqa: E402
from gridfield.core.errors import GridfieldError, MapFormatError  # noqa: E402
from gridfield.core.grid import Grid, GridMap  # noqa: E402
from gridfield.distance.brushfire import brushfire  # noqa: E402
from gridfield.io import read, read_store, write_store  # noqa: E402
from gridfield.io._common import redact  # noqa: E402


def _maps():
    rng = np.random.default_rng(470)
    for shape, density in (((23, 31), 0.05), ((40, 17), 0.01), ((9, 50), 0.2), ((30, 30), 0.0)):
        occ = rng.random(shape) < density
        if density == 0.0:
            occ[15, 3] = True  # one obstacle
        yield occ


@pytest.mark.parametrize("border", ["wall", "open"])
def test_gvd_through_a_store_equals_brushfire(border, tmp_path):
    """``gvd(..., scratch=)``: the labels gathered in the column pass's strips and read back by each output
    chunk give the in-memory brushfire's distance, labels and GVD bit for bit, with the store in memory
    and in a directory, for chunkings that cut the strips anywhere."""
    for k, occ in enumerate(_maps()):
        ref = brushfire(GridMap(Grid(occ.shape, 0.5, border=border), occ), metric="euclidean")
        for chunks in ((7, 5), (16, 16)):
            for place in (f"memory://gvd{k}/{chunks[0]}x{chunks[1]}.scratch", tmp_path / f"s{k}-{chunks[0]}"):
                with scratch_dir(place) as s:
                    d, lab, g = gvd(da.from_array(occ, chunks=chunks), resolution=0.5, border=border, scratch=s)
                    d, lab, g = da.compute(d, lab, g, scheduler="threads")
                np.testing.assert_array_equal(d, ref.distance)
                np.testing.assert_array_equal(lab, ref.label)
                np.testing.assert_array_equal(g, ref.gvd)
    assert not fsspec.filesystem("memory").find("/gvd0")  # every temporary store removed


def test_distance_through_a_memory_store_equals_scipy():
    occ = np.random.default_rng(1).random((37, 45)) < 0.03
    with scratch_dir("memory://edt/a.scratch") as s:
        d, nr, nc = distance(da.from_array(occ, chunks=(8, 13)), return_nearest=True, border="open", scratch=s)
        d, nr, nc = da.compute(d, nr, nc, scheduler="threads")
    np.testing.assert_array_equal(d, distance_transform_edt(~occ))
    rr, cc = np.indices(occ.shape)
    assert occ[nr, nc].all() and np.array_equal(np.sqrt((rr - nr) ** 2.0 + (cc - nc) ** 2.0), d)


def test_scratch_prefix_with_foreign_objects_is_refused():
    fs = fsspec.filesystem("memory")
    fs.pipe_file("/busy/s.scratch/keep.txt", b"mine")
    with pytest.raises(GridfieldError, match=r"holds \['keep.txt'\], not only temporary stores"), \
            scratch_dir("memory://busy/s.scratch"):
        pass
    assert fs.cat_file("/busy/s.scratch/keep.txt") == b"mine"


def test_store_at_a_url_round_trips_and_an_interrupted_one_is_refused():
    occ = np.zeros((6, 5), bool)
    occ[2, 3] = True
    url = write_store("memory://st/m.zarr", {"occupied": occ}, Grid((6, 5), 0.5), kind="map", chunks=4)
    assert url == "memory://st/m.zarr" and bool(read_store(url).occupied[2, 3])
    with pytest.raises(GridfieldError, match="already exists"):
        write_store(url, {"occupied": occ}, Grid((6, 5), 0.5), kind="map", chunks=4)
    fs = fsspec.filesystem("memory")
    assert not fs.exists("/st/m.zarr/.progress")  # the marks are removed once complete
    import zarr

    g = zarr.open_group("memory://st/half.zarr", mode="w")
    g.attrs["gridfield_partial"] = {"resume_key": "k"}
    with pytest.raises(MapFormatError, match="an interrupted write"):
        read_store("memory://st/half.zarr")
    with pytest.raises(GridfieldError, match="holds an interrupted run with other arguments"):
        write_store("memory://st/half.zarr", {"occupied": occ}, Grid((6, 5), 0.5), kind="map", chunks=4,
                    resume_key="other")


def test_cli_brushfire_on_memory_urls_tiff_and_npy(capsys):
    """``gridfield brushfire memory://...tif --out memory://...zarr`` (threads): a BigTIFF and a ``.npy`` read
    by ranges from the URL give scipy's transform."""
    import io

    import tifffile

    occ = np.random.default_rng(5).random((50, 70)) < 0.02
    fs = fsspec.filesystem("memory")
    buf = io.BytesIO()
    tifffile.imwrite(buf, np.where(occ, 0, 255).astype(np.uint8)[::-1], bigtiff=True, tile=(16, 16))
    fs.pipe_file("/in/m.tif", buf.getvalue())
    buf = io.BytesIO()
    np.save(buf, occ)
    fs.pipe_file("/in/m.npy", buf.getvalue())
    for src in ("memory://in/m.tif", "memory://in/m.npy"):
        out = f"memory://out/{src.rsplit('.', 1)[1]}.zarr"
        assert main(["brushfire", src, "--metric", "euclidean", "--chunks", "16", "--out", out]) == 0, \
            capsys.readouterr().err
        capsys.readouterr()
        np.testing.assert_array_equal(np.asarray(read(out).distance), distance_transform_edt(~occ))
    assert main(["brushfire", "memory://in/m.npy", "--metric", "euclidean", "--chunks", "16", "--out",
                 "memory://out/npy.zarr"]) == 2
    assert "memory://out/npy.zarr: already exists" in capsys.readouterr().err


def test_redact_hides_keys_in_urls_and_the_environment(monkeypatch):
    monkeypatch.setenv("AWS_SECRET_ACCESS_KEY", "very-secret-value")
    text = redact("s3://AKIAXYZ:pw@b/f.zarr?X-Amz-Credential=abc&x=1 failed with very-secret-value")
    assert "AKIAXYZ" not in text and "pw@" not in text and "abc" not in text and "very-secret-value" not in text
    assert text == "s3://***@b/f.zarr?X-Amz-Credential=***&x=1 failed with ***"


@pytest.mark.parametrize("metric", ["chessboard", "taxicab"])
def test_cli_brushfire_default_metric_to_a_url_writes_the_distance(metric, capsys):
    """``gridfield brushfire MAP --out URL`` without ``--metric`` (chessboard) or with taxicab: the distance alone
    (their nearest cells follow the in-memory raster order, which the chunks do not reproduce), equal to the
    in-memory brushfire; before, the command refused its own default."""
    import io

    occ = np.random.default_rng(9).random((33, 41)) < 0.03
    buf = io.BytesIO()
    np.save(buf, occ)
    fsspec.filesystem("memory").pipe_file(f"/in/{metric}.npy", buf.getvalue())
    cmd = ["brushfire", f"memory://in/{metric}.npy", "--chunks", "16", "--out", f"memory://out/{metric}.zarr"]
    assert main(cmd if metric == "chessboard" else [*cmd, "--metric", metric]) == 0, capsys.readouterr().err
    assert "(occupied, distance)" in capsys.readouterr().out
    dm = read(f"memory://out/{metric}.zarr")
    ref = brushfire(GridMap(Grid(occ.shape, 1.0, border="open"), occ), metric=metric)
    assert dm.metric == metric and dm.nearest_row is None
    np.testing.assert_array_equal(np.asarray(dm.distance), ref.distance)
