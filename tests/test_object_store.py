"""The chunked commands on an object store, end to end (issue 47).

A real S3 API server (moto's server mode) listens on 127.0.0.1, and a Dask ``LocalCluster`` of two worker
processes (one thread each) computes; each worker works in its own directory with its own temporary
directory, all under one watched folder. The map is uploaded to the bucket, ``gridfield brushfire`` /
``field`` read it from there and write their store there, and ``gridfield plan`` follows the stored field
from there. The references are independent: ``scipy.ndimage.distance_transform_edt`` and the in-memory
field and follower. Skipped (with the reason) only where s3fs or moto's server is not installed.
"""

from __future__ import annotations

import contextlib
import io
import json
import logging
import os
import socket
import tempfile
import threading
from pathlib import Path

import numpy as np
import pytest

s3fs = pytest.importorskip("s3fs", reason="the object-store tests need s3fs: pip install 'gridfield[s3]'")
moto_server = pytest.importorskip("moto.server", reason="the object-store tests need moto's server: "
                                  "pip install 'moto[server]' (in the [test] extra)")
distributed = pytest.importorskip("distributed", reason="the cluster tests need dask.distributed (the [dask] extra)")

from scipy.ndimage import distance_transform_edt  # noqa: E402

from gridfield.cli import main  # noqa: E402
from gridfield.core.errors import MapFormatError  # noqa: E402
from gridfield.core.grid import Grid, GridMap  # noqa: E402
from gridfield.fields.potential import build_field  # noqa: E402
from gridfield.following import follow  # noqa: E402
from gridfield.io import read  # noqa: E402

SECRET = "gridfield-test-secret-d41d8cd9"  # the key the environment holds: never shown
RES = 0.5
CHUNK = 32


def _occ() -> np.ndarray:
    """Blocks beside the diagonal from the start (2, 2) to the goal (45, 35), and a few single cells in the
    corners away from it (the classic field has no local minimum on the way)."""
    occ = np.zeros((90, 110), bool)
    occ[60:85, 5:30] = True
    occ[5:25, 70:100] = True
    occ[40:44, 0:12] = True
    rng = np.random.default_rng(47)
    occ[rng.integers(60, 90, 12), rng.integers(0, 40, 12)] = True
    occ[rng.integers(0, 30, 12), rng.integers(60, 110, 12)] = True
    return occ


def _clear_s3_cache() -> None:
    """A new environment (credentials, endpoint) for the next file system: they are read when an instance
    is made, and fsspec keeps instances. The old ones' sessions are collected here, quietly."""
    import gc
    import warnings

    s3fs.S3FileSystem.clear_instance_cache()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResourceWarning)
        gc.collect()


def _fs():
    fs = s3fs.S3FileSystem()
    fs.invalidate_cache()
    return fs


@pytest.fixture(scope="module")
def s3():
    """The S3 server on 127.0.0.1 (a free port) and the usual environment naming it: AWS variables only."""
    logging.getLogger("werkzeug").setLevel(logging.ERROR)  # the server's request log
    server = moto_server.ThreadedMotoServer(ip_address="127.0.0.1", port=0, verbose=False)
    server.start()
    host, port = server.get_host_and_port()
    with pytest.MonkeyPatch.context() as mp:
        for k, v in {"AWS_ACCESS_KEY_ID": "AKIAGRIDFIELDTEST", "AWS_SECRET_ACCESS_KEY": SECRET,
                     "AWS_DEFAULT_REGION": "us-east-1", "AWS_ENDPOINT_URL": f"http://{host}:{port}",
                     "AWS_EC2_METADATA_DISABLED": "true", "AWS_MAX_ATTEMPTS": "2"}.items():
            mp.setenv(k, v)
        mp.delenv("AWS_PROFILE", raising=False)
        _clear_s3_cache()
        fs = s3fs.S3FileSystem()
        fs.mkdir("maps")
        fs.mkdir("fields")
        yield {"endpoint": f"http://{host}:{port}", "host": host, "port": port}
        _clear_s3_cache()
    server.stop()


def _own_dirs(root: str) -> str:
    """On a worker: its own working directory and temporary directory under ``root``."""
    pid = os.getpid()
    work, tmp = Path(root, f"work-{pid}"), Path(root, f"tmp-{pid}")
    work.mkdir(exist_ok=True)
    tmp.mkdir(exist_ok=True)
    os.chdir(work)
    os.environ["TMPDIR"] = str(tmp)
    tempfile.tempdir = str(tmp)
    return str(tmp)


@pytest.fixture(scope="module")
def cluster(s3, tmp_path_factory):
    """Two worker processes, each with its own working and temporary directory under one watched folder
    (the cluster's ``local_directory`` too); the workers inherit the S3 variables of the environment."""
    watched = tmp_path_factory.mktemp("workers")
    with distributed.LocalCluster(processes=True, n_workers=2, threads_per_worker=1, host="127.0.0.1",
                                  dashboard_address=":0", local_directory=str(watched / "dask")) as lc, \
            distributed.Client(lc) as client:
        tmps = client.run(_own_dirs, str(watched))
        assert len(set(tmps.values())) == 2
        yield {"address": lc.scheduler_address, "watched": watched, "client": client}


def _chunk_files(root: Path) -> list[str]:
    """Files under ``root`` that hold data (Dask's lock files are empty): none may come of the computation."""
    return sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file() and p.stat().st_size > 0
                  and not p.name.endswith(".lock"))


@pytest.fixture
def watched_here(tmp_path, monkeypatch):
    """The test process's working and temporary directory: an empty folder checked afterwards."""
    here = tmp_path / "client"
    here.mkdir()
    monkeypatch.chdir(here)
    monkeypatch.setattr(tempfile, "tempdir", str(here))
    return here


def _put_npy(fs, url: str, occ: np.ndarray) -> None:
    buf = io.BytesIO()
    np.save(buf, occ)
    fs.pipe_file(url, buf.getvalue())


def _put_tiff(fs, url: str, occ: np.ndarray) -> None:
    import tifffile

    buf = io.BytesIO()
    img = np.where(occ, 0, 255).astype(np.uint8)[::-1]  # an image: dark = obstacle, first row the top
    tifffile.imwrite(buf, img, bigtiff=True, tile=(32, 32), extratags=[(33550, 12, 3, (RES, RES, 0.0))])
    fs.pipe_file(url, buf.getvalue())


def test_brushfire_and_field_on_s3_with_a_cluster_equal_the_references_and_plan_reaches(
        s3, cluster, watched_here, capsys):
    """``brushfire s3://maps/m.npy --out s3://fields/d.zarr --scheduler`` on two worker processes: the store
    read back from S3 equals scipy's exact transform bit for bit (and its nearest cells are at that
    distance); ``field`` from a BigTIFF in the bucket equals the in-memory field, and ``plan
    s3://fields/f.zarr`` reaches the goal as the in-memory follower does. No file with data lands in the
    workers' or the client's directories, and the temporary store's prefix is gone from the bucket."""
    fs = _fs()
    occ = _occ()
    _put_npy(fs, "maps/m.npy", occ)
    _put_tiff(fs, "maps/m.tif", occ)
    code = main(["brushfire", "s3://maps/m.npy", "--resolution", str(RES), "--metric", "euclidean",
                 "--chunks", str(CHUNK), "--out", "s3://fields/d.zarr", "--scheduler", cluster["address"]])
    assert code == 0, capsys.readouterr().err
    assert "wrote s3://fields/d.zarr" in capsys.readouterr().out
    dm = read("s3://fields/d.zarr")
    assert dm.metric == "euclidean" and dm.map.occupied.chunks == (CHUNK, CHUNK)
    edt = distance_transform_edt(~occ) * RES
    np.testing.assert_array_equal(np.asarray(dm.distance), edt)
    rr, cc = np.indices(occ.shape)
    dr, dc = rr - np.asarray(dm.nearest_row), cc - np.asarray(dm.nearest_col)
    np.testing.assert_array_equal(np.sqrt(dr * dr + dc * dc) * RES, edt)  # the nearest cell is at that distance

    code = main(["field", "s3://maps/m.tif", "--goal", "45", "35", "--chunks", str(CHUNK),
                 "--out", "s3://fields/f.zarr", "--scheduler", cluster["address"]])
    assert code == 0, capsys.readouterr().err
    capsys.readouterr()
    lf = read("s3://fields/f.zarr")
    ref = build_field(GridMap(Grid(occ.shape, RES), occ), lf.goal, {"model": "khatib"})
    np.testing.assert_array_equal(np.asarray(lf.potential), ref.potential)
    np.testing.assert_array_equal(np.asarray(lf.grad_x), ref.grad_x)
    assert main(["plan", "s3://fields/f.zarr", "--start", "2", "2", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    want = follow(ref, (2.0, 2.0))
    assert got["status"] == want.status == "reached" and got["iterations"] == want.iterations

    fs = _fs()
    assert not fs.exists("fields/d.zarr.scratch") and not fs.exists("fields/f.zarr.scratch")
    assert not fs.exists("fields/d.zarr/.progress")
    assert _chunk_files(cluster["watched"]) == []
    assert _chunk_files(watched_here) == []


def test_gvd_through_s3_on_the_cluster_equals_brushfire(s3, cluster):
    """``gvd(..., scratch="s3://...")`` on the two worker processes: the passes (and the gathered labels)
    meet in the bucket; distance, labels and GVD equal the in-memory brushfire, and the prefix is removed."""
    import dask.array as da

    from gridfield.chunked import gvd, scratch_dir
    from gridfield.distance.brushfire import brushfire

    occ = _occ()
    ref = brushfire(GridMap(Grid(occ.shape, RES, border="wall"), occ), metric="euclidean")
    with scratch_dir("s3://fields/gvd.scratch") as s:
        lazy = gvd(da.from_array(occ, chunks=CHUNK), resolution=RES, border="wall", scratch=s)
        d, lab, g = cluster["client"].compute(list(lazy), sync=True)
    np.testing.assert_array_equal(d, ref.distance)
    np.testing.assert_array_equal(lab, ref.label)
    np.testing.assert_array_equal(g, ref.gvd)
    assert not _fs().exists("fields/gvd.scratch")
    assert _chunk_files(cluster["watched"]) == []


def test_an_interrupted_store_resumes_in_place(s3, watched_here, capsys, monkeypatch):
    """A run stopped after some chunks leaves the store at its URL marked as interrupted: ``read`` refuses
    it naming the resume, and the same command writes only the chunks not yet written."""
    from gridfield.io import _zarr

    fs = _fs()
    occ = _occ()
    _put_npy(fs, "maps/r.npy", occ)
    cmd = ["brushfire", "s3://maps/r.npy", "--resolution", str(RES), "--metric", "euclidean", "--chunks",
           str(CHUNK), "--out", "s3://fields/r.zarr"]
    marked = []
    real = _zarr._RemoteMarks.mark

    def stop_after_five(self, name, i, j):
        if len(marked) >= 5:
            raise KeyboardInterrupt  # the run is killed
        real(self, name, i, j)
        marked.append((name, i, j))

    monkeypatch.setattr(_zarr._RemoteMarks, "mark", stop_after_five)
    assert main(cmd) == 130  # "interrupted"
    capsys.readouterr()
    with pytest.raises(MapFormatError, match=r"an interrupted write.*re-run"):
        read("s3://fields/r.zarr")
    first = len(marked)
    monkeypatch.setattr(_zarr._RemoteMarks, "mark", lambda self, name, i, j: (real(self, name, i, j),
                                                                            marked.append((name, i, j))))
    assert main(cmd) == 0, capsys.readouterr().err
    n_chunks = 4 * 3 * 4  # four arrays of 3 x 4 chunks
    assert 5 <= first < n_chunks and len(marked) == n_chunks  # the second run wrote only the chunks not yet written
    assert len(set(marked)) == n_chunks
    np.testing.assert_array_equal(np.asarray(read("s3://fields/r.zarr").distance), distance_transform_edt(~occ) * RES)
    assert _chunk_files(watched_here) == []


class _Proxy:
    """A TCP relay on 127.0.0.1 to the S3 server whose connections can be cut (and let through again)."""

    def __init__(self, host: str, port: int) -> None:
        self.target = (host, port)
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.up = True
        self.live: list[socket.socket] = []
        self.lock = threading.Lock()
        self.thread = threading.Thread(target=self._accept, daemon=True)
        self.thread.start()

    def _accept(self) -> None:
        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            if not self.up:
                conn.close()
                continue
            upstream = socket.create_connection(self.target)
            with self.lock:
                self.live += [conn, upstream]
            for a, b in ((conn, upstream), (upstream, conn)):
                threading.Thread(target=self._pump, args=(a, b), daemon=True).start()

    @staticmethod
    def _pump(a: socket.socket, b: socket.socket) -> None:
        try:
            while data := a.recv(65536):
                b.sendall(data)
        except OSError:
            pass
        finally:
            for s in (a, b):
                with contextlib.suppress(OSError):
                    s.shutdown(socket.SHUT_RDWR)

    def drop(self) -> None:
        self.up = False
        with self.lock:
            for s in self.live:
                with contextlib.suppress(OSError):
                    s.shutdown(socket.SHUT_RDWR)
                s.close()
            self.live.clear()

    def close(self) -> None:
        self.drop()
        self.sock.close()


def test_a_dropped_connection_is_one_line_and_the_run_resumes(s3, watched_here, capsys, monkeypatch):
    """The connection to the store drops mid-run: one line on stderr naming the store (no key), exit 2; once
    the store is reachable again the same command resumes and the store equals scipy's transform."""
    from gridfield.io import _zarr

    fs = _fs()
    occ = _occ()
    _put_npy(fs, "maps/c.npy", occ)
    proxy = _Proxy(s3["host"], s3["port"])
    try:
        monkeypatch.setenv("AWS_ENDPOINT_URL", f"http://127.0.0.1:{proxy.port}")
        _clear_s3_cache()
        real = _zarr._RemoteMarks.mark
        marked = []

        def drop_after_four(self, name, i, j):
            real(self, name, i, j)
            marked.append(1)
            if len(marked) == 4:
                proxy.drop()

        monkeypatch.setattr(_zarr._RemoteMarks, "mark", drop_after_four)
        cmd = ["brushfire", "s3://maps/c.npy", "--resolution", str(RES), "--metric", "euclidean", "--chunks",
               str(CHUNK), "--out", "s3://fields/c.zarr"]
        assert main(cmd) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("gridfield brushfire: error: s3://"), err  # the map or the store
        assert "the connection to the object store failed" in err and "run the same command again to resume" in err
        assert 4 <= len(marked) < 4 * 3 * 4  # some chunks were written before the drop, not all
        assert SECRET not in err
        proxy.up = True
        _clear_s3_cache()
        monkeypatch.setattr(_zarr._RemoteMarks, "mark", real)
        assert main(cmd) == 0, capsys.readouterr().err
    finally:
        proxy.close()
    monkeypatch.setenv("AWS_ENDPOINT_URL", s3["endpoint"])
    _clear_s3_cache()
    np.testing.assert_array_equal(np.asarray(read("s3://fields/c.zarr").distance), distance_transform_edt(~occ) * RES)
    assert _chunk_files(watched_here) == []


def test_a_missing_bucket_or_map_is_one_line_without_credentials(s3, watched_here, capsys):
    fs = _fs()
    _put_npy(fs, "maps/b.npy", _occ())
    assert main(["brushfire", "s3://maps/b.npy", "--metric", "euclidean", "--chunks", "16",
                 "--out", "s3://no-such-bucket/d.zarr"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "s3://no-such-bucket/d.zarr: no such bucket or object" in err, err
    assert main(["brushfire", "s3://maps/none.npy", "--metric", "euclidean", "--chunks", "16", "--out", "s3://fields/n.zarr"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "s3://maps/none.npy: no such bucket or object" in err, err
    # a URL carrying a key: the message names the place, never the key
    assert main(["brushfire", f"s3://AKIAGRIDFIELDTEST:{SECRET}@maps/b.npy", "--metric", "euclidean", "--chunks", "16",
                 "--out", "s3://fields/k.zarr"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and SECRET not in err and "AKIAGRIDFIELDTEST" not in err, err
    assert "s3://***@maps/b.npy" in err
    assert _chunk_files(watched_here) == []


def test_a_denied_write_is_one_line_without_credentials(s3, watched_here, capsys, monkeypatch):
    """With the server enforcing IAM, a user who may only read the buckets is refused the write: one line
    naming the store, not the key."""
    import urllib.request

    import boto3

    iam = boto3.client("iam", endpoint_url=s3["endpoint"])
    iam.create_user(UserName="reader")
    iam.put_user_policy(UserName="reader", PolicyName="read", PolicyDocument=json.dumps({
        "Version": "2012-10-17", "Statement": [{"Effect": "Allow", "Action": ["s3:GetObject", "s3:ListBucket",
                                                                              "s3:HeadObject"],
                                                 "Resource": "*"}]}))
    key = iam.create_access_key(UserName="reader")["AccessKey"]
    fs = _fs()
    _put_npy(fs, "maps/p.npy", _occ())

    def auth(count: str) -> None:
        req = urllib.request.Request(f"{s3['endpoint']}/moto-api/reset-auth", data=count.encode(), method="POST",
                                     headers={"Content-Type": "text/plain"})  # (a form's body is parsed away)
        urllib.request.urlopen(req, timeout=10).close()

    monkeypatch.setenv("AWS_ACCESS_KEY_ID", key["AccessKeyId"])
    monkeypatch.setenv("AWS_SECRET_ACCESS_KEY", key["SecretAccessKey"])
    _clear_s3_cache()
    auth("0")  # every request from now on is authorized
    try:
        code = main(["brushfire", "s3://maps/p.npy", "--metric", "euclidean", "--chunks", "16", "--out", "s3://fields/p.zarr"])
    finally:
        auth("inf")
        _clear_s3_cache()
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "s3://fields/p.zarr: access denied" in err and key["SecretAccessKey"] not in err, err
    assert _chunk_files(watched_here) == []
