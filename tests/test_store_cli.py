"""Issue 27 end to end on the command line: ``gridfield brushfire/field BIG --chunks N --out F.zarr`` on inputs
read by chunks (gridfield.chunked computes), checked against scipy's exact transform and the in-memory
field; an interrupted CLI run resumed; a tiny LocalCluster on 127.0.0.1 as ``--scheduler``; and
``gridfield plan`` on the written field."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.ndimage import distance_transform_edt

from gridfield.cli import main
from gridfield.core.grid import Grid, GridMap
from gridfield.fields.potential import build_field
from gridfield.following.follower import follow
from gridfield.io import _zarr as zstore
from gridfield.io import read

RES = 0.5


def _occ() -> np.ndarray:
    occ = np.zeros((48, 64), bool)
    occ[10:14, 5:30] = True
    occ[30:44, 40:43] = True
    occ[25, 55] = True
    return occ


def _edt(occ: np.ndarray) -> np.ndarray:
    return distance_transform_edt(~occ) * RES


def test_brushfire_npy_to_store_is_the_exact_transform(tmp_path, capsys):
    occ = _occ()
    np.save(tmp_path / "m.npy", occ)
    out = tmp_path / "d.zarr"
    code = main(["brushfire", str(tmp_path / "m.npy"), "--resolution", str(RES), "--metric", "euclidean",
                 "--chunks", "16", "--out", str(out)])
    assert code == 0, capsys.readouterr().err
    assert "wrote" in capsys.readouterr().out
    dm = read(out)
    assert dm.metric == "euclidean" and dm.map.occupied.chunks == (16, 16)
    np.testing.assert_allclose(np.asarray(dm.distance), _edt(occ), rtol=0, atol=1e-12)
    # the nearest obstacle is at the distance found
    rr, cc = np.indices(occ.shape)
    nr, nc = np.asarray(dm.nearest_row), np.asarray(dm.nearest_col)
    np.testing.assert_allclose(np.hypot(rr - nr, cc - nc) * RES, _edt(occ), atol=1e-12)
    assert occ[nr, nc].all()


def test_brushfire_bigtiff_resumes_after_an_interruption(tmp_path, monkeypatch, capsys):
    import tifffile

    occ = _occ()
    img = np.where(np.flipud(occ), 0, 255).astype(np.uint8)  # an image, the top row first: black = obstacle
    tifffile.imwrite(tmp_path / "m.tif", img, bigtiff=True, tile=(16, 16),
                     extratags=[(33550, 12, 3, (RES, RES, 0.0))])
    argv = ["brushfire", str(tmp_path / "m.tif"), "--metric", "euclidean", "--chunks", "16",
            "--out", str(tmp_path / "d.zarr")]
    real = zstore._mark_done
    n = {"k": 0}

    def failing(*a):
        if n["k"] == 5:
            raise KeyboardInterrupt
        n["k"] += 1
        real(*a)

    monkeypatch.setattr(zstore, "_mark_done", failing)
    assert main(argv) == 130  # interrupted: one line, no store
    assert "interrupted" in capsys.readouterr().err
    assert not (tmp_path / "d.zarr").exists() and (tmp_path / "d.zarr.partial").is_dir()
    assert not (tmp_path / "d.zarr.scratch").exists()  # the passes' temporary store: gone, also on error
    monkeypatch.setattr(zstore, "_mark_done", real)
    assert main(argv) == 0
    dm = read(tmp_path / "d.zarr")
    np.testing.assert_allclose(np.asarray(dm.distance), _edt(occ), atol=1e-12)
    assert not (tmp_path / "d.zarr.partial").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.zarr", "m.tif"]
    assert not any("column-pass" in str(p) for p in (tmp_path / "d.zarr").rglob("*"))


def test_brushfire_on_a_local_cluster(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")

    occ = _occ()
    np.save(tmp_path / "m.npy", occ)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp",
                                  host="127.0.0.1", dashboard_address=":0") as cluster:
        code = main(["brushfire", str(tmp_path / "m.npy"), "--resolution", str(RES), "--metric", "euclidean",
                     "--saturate", "3", "--chunks", "16", "--out", str(tmp_path / "d.zarr"),
                     "--scheduler", cluster.scheduler_address])
    assert code == 0, capsys.readouterr().err
    d = np.asarray(read(tmp_path / "d.zarr").distance)
    ref = _edt(occ)
    np.testing.assert_allclose(d[ref < 3], ref[ref < 3], atol=1e-12)
    assert np.isinf(d[ref >= 3]).all()


def test_field_to_store_then_plan(tmp_path, capsys):
    occ = _occ()
    np.save(tmp_path / "m.npy", occ)
    out = tmp_path / "f.zarr"
    code = main(["field", str(tmp_path / "m.npy"), "--resolution", str(RES), "--goal", "28", "20",
                 "--chunks", "16", "--out", str(out)])
    assert code == 0, capsys.readouterr().err
    capsys.readouterr()
    lf = read(out)
    assert lf.goal == (28.25, 20.25)  # the centre of the goal's cell
    ref = build_field(GridMap(Grid(occ.shape, RES), occ), (28.25, 20.25), {"model": "khatib"})
    np.testing.assert_array_equal(np.asarray(lf.grad_x), ref.grad_x)
    np.testing.assert_array_equal(np.asarray(lf.grad_y), ref.grad_y)
    np.testing.assert_array_equal(np.asarray(lf.potential), ref.potential)
    assert main(["plan", str(out), "--start", "2", "2", "--goal", "28", "20", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    want = follow(ref, (2.0, 2.0))
    assert got["status"] == want.status and got["iterations"] == want.iterations


def test_complete_nf1_field_to_store_then_plan_on_a_real_map(tmp_path, capsys, test_maps):
    """``--param model=nf1 --param attraction=octile``: the complete field by the chunked wavefront, equal
    bit for bit to the in-memory nf1 (octile) field on a Moving AI map, and ``plan`` on the store reaches the
    goal with the in-memory planner's path, where the chunked classic field's store stalls."""
    from gridfield.fields.navfield import nav_field
    from gridfield.planners import plan

    src = test_maps / "movingai" / "den312d" / "den312d.map.gz"
    gm = read(src)
    out = tmp_path / "nf.zarr"
    assert main(["field", str(src), "--goal", "40.5", "40.5", "--chunks", "32", "--out", str(out),
                 "--param", "model=nf1", "--param", "attraction=octile"]) == 0, capsys.readouterr().err
    assert "a complete model" in capsys.readouterr().out
    lf = read(out)
    ref = nav_field(gm, (40.5, 40.5), {"model": "nf1", "attraction": "octile"})
    for got, want in ((lf.potential, ref.potential), (lf.grad_x, ref.grad_x), (lf.grad_y, ref.grad_y)):
        np.testing.assert_array_equal(np.asarray(got), want)
    assert main(["plan", str(out), "--start", "10.5", "69.5", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    mem = plan("potential", gm, (10.5, 69.5), (40.5, 40.5), {"model": "nf1", "attraction": "octile"})
    assert got["status"] == mem.status == "reached"
    np.testing.assert_allclose(np.array(got["path"]), mem.points, atol=1e-9)
    classic = tmp_path / "k.zarr"
    assert main(["field", str(src), "--goal", "40.5", "40.5", "--chunks", "32", "--out", str(classic)]) == 0
    capsys.readouterr()
    main(["plan", str(classic), "--start", "10.5", "69.5", "--json"])
    assert json.loads(capsys.readouterr().out)["status"] != "reached"  # the classic field's local minimum


def test_chunked_nf1_refuses_what_it_does_not_build(tmp_path, capsys):
    np.save(tmp_path / "m.npy", _occ())
    for extra, why in ((["--param", "model=nf1"], "with its eikonal attraction"),
                       (["--param", "model=nf2"], "not model 'nf2'")):
        code = main(["field", str(tmp_path / "m.npy"), "--resolution", "0.5", "--goal", "28", "20", "--chunks", "16",
                     "--out", str(tmp_path / "x.zarr"), *extra])
        assert code == 2 and why in capsys.readouterr().err
