"""Voxel map readers (issue 44): Moving AI 3-D ``.3dmap``/``.3dscen``, ``.binvox``, 3-D ``.npy``/``.npz`` and
point clouds (PLY, ``.xyz``).

Every file is written here by the test's own plain writer (the format's rules written out again), read back
and compared voxel by voxel; the bundled scenarios' optimal costs are checked against scipy's Dijkstra on a
graph built here; the point clouds against the geometry of their voxels.
"""

from __future__ import annotations

import gzip
import itertools
import json
import math
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from gridfield.cli import main
from gridfield.core.errors import MapFormatError, ParameterError, SizeLimitError
from gridfield.core.limits import override
from gridfield.io import (
    Scenarios,
    Scenarios3D,
    read,
    read_3dmap,
    read_binvox,
    read_npz,
    read_pointcloud,
    read_scen,
    read_scen3d,
    read_voxel_npy,
    write_npz,
)

from mapdata import TEST_MAPS

VOXEL = TEST_MAPS / "voxel"
SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


# ----------------------------------------------------------------------------------------------
# the test's own writers
# ----------------------------------------------------------------------------------------------
def write_3dmap(path: Path, occ: np.ndarray, *, shuffle: int | None = None, duplicate: bool = False) -> Path:
    """``voxel W H D`` and one ``x y z`` line per blocked voxel ``occ[z, y, x]``."""
    d, h, w = occ.shape
    lines = [f"{x} {y} {z}" for z in range(d) for y in range(h) for x in range(w) if occ[z, y, x]]
    if duplicate:
        lines += lines[: len(lines) // 2]
    if shuffle is not None:
        np.random.default_rng(shuffle).shuffle(lines)
    path.write_text(f"voxel {w} {h} {d}\n" + "".join(ln + "\n" for ln in lines))
    return path


def write_binvox(path: Path, occ: np.ndarray, translate=(0.0, 0.0, 0.0), scale=1.0, value=1) -> Path:
    """binvox: runs of (value, count <= 255) over the voxels in x, z, y order (y fastest)."""
    d = occ.shape[0]
    flat = [bool(occ[k, j, i]) for i in range(d) for k in range(d) for j in range(d)]
    out = bytearray()
    for v, group in itertools.groupby(flat):
        n = len(list(group))
        while n:
            c = min(n, 255)
            out += bytes([value if v else 0, c])
            n -= c
    head = f"#binvox 1\ndim {d} {d} {d}\ntranslate {translate[0]} {translate[1]} {translate[2]}\nscale {scale}\ndata\n"
    path.write_bytes(head.encode() + bytes(out))
    return path


def write_ply(path: Path, pts: np.ndarray, fmt: str, *, dtype: str = "f4", faces: bool = False) -> Path:
    """A PLY with vertex x y z (and a uchar property between y and z), optionally a face element after."""
    order = {"ascii": "", "binary_little_endian": "<", "binary_big_endian": ">"}[fmt]
    kind = {"f4": "float", "f8": "double"}[dtype]
    n = len(pts)
    head = (f"ply\nformat {fmt} 1.0\ncomment written by the test\nelement vertex {n}\nproperty {kind} x\n"
            f"property {kind} y\nproperty uchar red\nproperty {kind} z\n")
    if faces:
        head += "element face 1\nproperty list uchar int vertex_indices\n"
    head += "end_header\n"
    if fmt == "ascii":
        body = "".join(f"{float(p[0])!r} {float(p[1])!r} 7 {float(p[2])!r}\n" for p in pts)
        if faces:
            body += "3 0 1 2\n"
        path.write_bytes(head.encode() + body.encode())
    else:
        rec = np.zeros(n, dtype=[("x", order + dtype), ("y", order + dtype), ("red", "u1"), ("z", order + dtype)])
        rec["x"], rec["y"], rec["z"], rec["red"] = pts[:, 0], pts[:, 1], pts[:, 2], 7
        tail = b"\x03" + np.array([0, 1, 2], dtype=order + "i4").tobytes() if faces else b""
        path.write_bytes(head.encode() + rec.tobytes() + tail)
    return path


voxels = st.tuples(st.integers(1, 6), st.integers(1, 6), st.integers(1, 6)).flatmap(
    lambda s: st.lists(st.booleans(), min_size=math.prod(s), max_size=math.prod(s)).map(
        lambda v, s=s: np.array(v, dtype=bool).reshape(s)))


# ----------------------------------------------------------------------------------------------
# .3dmap
# ----------------------------------------------------------------------------------------------
@SETTINGS
@given(occ=voxels, seed=st.integers(0, 100), dup=st.booleans())
def test_3dmap_round_trip_voxel_by_voxel(tmp_path, occ, seed, dup):
    f = write_3dmap(tmp_path / "m.3dmap", occ, shuffle=seed, duplicate=dup)
    m = read_3dmap(f)
    assert m.shape == occ.shape and m.grid.resolution == 1.0 and m.grid.origin == (0.0, 0.0, 0.0)
    assert m.grid.border == "wall" and m.meta["format"] == "movingai3d" and m.source == str(f)
    np.testing.assert_array_equal(m.occupied, occ)
    np.testing.assert_array_equal(read(f).occupied, occ)  # read() picks the reader by suffix


def test_3dmap_axes_are_not_flipped(tmp_path):
    f = tmp_path / "m.3dmap"
    f.write_text("voxel 5 4 3\r\n4 0 2\r\n\r\n0 3 1\r\n")  # CRLF and a blank line
    m = read_3dmap(f)
    assert m.shape == (3, 4, 5)
    assert np.argwhere(m.occupied).tolist() == [[1, 3, 0], [2, 0, 4]]  # (z, y, x)
    assert m.is_free([[4.5, 0.5, 2.5], [0.5, 3.5, 1.5], [4.5, 0.5, 1.5]]).tolist() == [False, False, True]
    assert m.grid.bounds == (0.0, 0.0, 0.0, 5.0, 4.0, 3.0)
    assert m.meta["occupancy_rule"] and m.meta["blocked_lines"] == 2


def test_3dmap_gzip_reads_as_the_plain_file(tmp_path):
    occ = np.random.default_rng(0).random((4, 5, 6)) < 0.3
    f = write_3dmap(tmp_path / "m.3dmap", occ)
    g = tmp_path / "m.3dmap.gz"
    g.write_bytes(gzip.compress(f.read_bytes()))
    np.testing.assert_array_equal(read_3dmap(g).occupied, occ)
    np.testing.assert_array_equal(read(g).occupied, occ)
    (tmp_path / "bad.3dmap.gz").write_bytes(b"not gzip")
    with pytest.raises(MapFormatError, match="not a gzip file"):
        read_3dmap(tmp_path / "bad.3dmap.gz")


def test_3dmap_empty_body_is_an_empty_map(tmp_path):
    f = tmp_path / "e.3dmap"
    f.write_text("voxel 2 2 2\n")
    assert not read_3dmap(f).occupied.any()


@pytest.mark.parametrize(("text", "match"), [
    ("", r"empty file"),
    ("\n\n", r"empty file"),
    ("voxel 4 3\n", r"line 1: expected the header 'voxel W H D'"),
    ("type octile\n", r"line 1: expected the header 'voxel W H D'"),
    ("voxel 4 x 2\n", r"line 1: the header's height must be a positive integer, got 'x'"),
    ("voxel 4 3 0\n", r"line 1: the header's depth must be a positive integer, got '0'"),
    ("voxel 4 3 2\n1 1 1\n4 0 0\n", r"line 3: voxel \(4, 0, 0\) lies outside the map's 4 x 3 x 2 voxels"),
    ("voxel 4 3 2\n0 3 0\n", r"line 2: voxel \(0, 3, 0\) lies outside"),
    ("voxel 4 3 2\n\n0 0 2\n", r"line 3: voxel \(0, 0, 2\) lies outside .* z < 2"),
    ("voxel 4 3 2\n1.5 0 0\n", r"line 2: coordinates must be non-negative integers, got '1.5'"),
    ("voxel 4 3 2\n0 0 0\n-1 0 0\n", r"line 3: coordinates must be non-negative integers, got '-1'"),
    ("voxel 4 3 2\n0 0 0\n1 2\n", r"line 3: expected 3 fields \(x y z\), got 2"),
    ("voxel 4 3 2\n0 0 0 0\n", r"line 2: expected 3 fields \(x y z\), got 4"),
    ("voxel 4 3 2\n0 0 " + "9" * 30 + "\n", r"line 2: coordinate .* too large"),
])
def test_3dmap_errors_name_the_file_and_line(tmp_path, text, match):
    f = tmp_path / "bad.3dmap"
    f.write_text(text)
    with pytest.raises(MapFormatError, match=match) as e:
        read_3dmap(f)
    assert str(f) in str(e.value)


def test_3dmap_not_utf8_is_a_format_error(tmp_path):
    f = tmp_path / "bin.3dmap"
    f.write_bytes(b"voxel 2 2 2\n\xff\xfe 0 0\n")
    with pytest.raises(MapFormatError, match="line 2: coordinates must be non-negative integers"):
        read_3dmap(f)


def test_huge_header_is_refused_before_allocating(tmp_path):
    f = tmp_path / "huge.3dmap"
    f.write_text("voxel 1000000000 1000000000 1000000000\n0 0 0\n")
    tracemalloc.start()
    try:
        with pytest.raises(SizeLimitError, match=r"huge.3dmap \(.3dmap header .*1000000000 x 1000000000 x 1000000000"):
            read_3dmap(f)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1_000_000


def test_header_beyond_a_set_limit_names_its_byte_estimate(tmp_path):
    f = write_3dmap(tmp_path / "m.3dmap", np.zeros((10, 10, 11), bool))
    with override(1000), pytest.raises(SizeLimitError, match=r"10 x 10 x 11 = 1100 cells would need about"):
        read_3dmap(f)


@SETTINGS
@given(data=st.binary(max_size=200) | st.lists(st.sampled_from(
    ["voxel 3 3 3", "voxel 0 1 1", "voxel 99999999999 9 9", "1 1 1", "2 0 1", "3 3 3", "a b c", "1 1", "",
     " ", "\t", "1e3 0 0", "0x1 0 0", "voxel", "#", "1 1 1 1", "00000000000000000002 0 0"]),
    max_size=8).map(lambda ls: "\n".join(ls).encode()))
def test_3dmap_fuzz_never_a_traceback(tmp_path, data):
    f = tmp_path / "fuzz.3dmap"
    f.write_bytes(data)
    with override(100_000):
        try:
            m = read_3dmap(f)
        except (MapFormatError, SizeLimitError):
            return
    assert m.ndim == 3 and m.occupied.dtype == bool


@SETTINGS
@given(lines=st.lists(st.lists(st.sampled_from(["0", "7", "12", "+3", "-1", "1.5", "x", "", "00", "+", "1+2"]),
                               max_size=4).map(" ".join), max_size=6),
       sep=st.sampled_from(["\n", "\r\n", "\n\n"]))
def test_3dmap_fast_parser_and_byte_parser_agree(tmp_path, lines, sep):
    """np.loadtxt (the fast path) and the byte parser (the one naming the line) read the same bodies alike."""
    from gridfield.io._voxel import _int_table, _loadtxt_block

    body = sep.join(lines).encode()
    f = tmp_path / "b.3dmap"
    fast = _loadtxt_block(body)
    try:
        table, line_no = _int_table(f, body, 2, ("x", "y", "z"))
    except MapFormatError:
        assert fast is None or (fast < 0).any()  # the byte parser refuses what loadtxt refuses (and negatives)
        return
    assert fast is not None and np.array_equal(fast, table)
    assert len(line_no) == len(table) and (np.diff(line_no) > 0).all()


# ----------------------------------------------------------------------------------------------
# .3dscen and the bundled (generated) maps
# ----------------------------------------------------------------------------------------------
def bbox_costs(occ: np.ndarray, start_zyx: tuple[int, int, int]) -> np.ndarray:
    """Optimal 26-neighbour costs from a voxel (moves 1, sqrt 2, sqrt 3; a move's bounding box must be
    free), by scipy's Dijkstra on a graph built here with numpy."""
    index = np.arange(occ.size).reshape(occ.shape)
    src, dst, cost = [], [], []
    for m in itertools.product((-1, 0, 1), repeat=3):
        if m == (0, 0, 0):
            continue
        ok = np.ones(occ.shape, dtype=bool)  # from voxel v: every voxel v + b (b in the move's box) free, inside
        for b in itertools.product(*[(0, v) if v else (0,) for v in m]):
            shifted = np.ones(occ.shape, dtype=bool)  # blocked outside the map
            sl_dst = tuple(slice(max(-o, 0), n - max(o, 0)) for o, n in zip(b, occ.shape, strict=True))
            sl_src = tuple(slice(max(o, 0), n - max(-o, 0)) for o, n in zip(b, occ.shape, strict=True))
            shifted[sl_dst] = occ[sl_src]
            ok &= ~shifted
        ok &= ~occ
        v = np.argwhere(ok)
        src.append(index[tuple(v.T)])
        dst.append(index[tuple((v + np.array(m)).T)])
        cost.append(np.full(len(v), math.sqrt(sum(map(abs, m)))))
    g = coo_matrix((np.concatenate(cost), (np.concatenate(src), np.concatenate(dst))), shape=(occ.size, occ.size))
    return dijkstra(g.tocsr(), indices=int(index[start_zyx])).reshape(occ.shape)


@pytest.mark.parametrize("name", ["building", "random20", "cave"])
def test_bundled_voxel_maps_and_their_optimal_costs(name):
    m = read(VOXEL / f"{name}.3dmap.gz")
    s = read_scen(VOXEL / f"{name}.3dmap.3dscen.gz")
    assert isinstance(s, Scenarios3D) and isinstance(s, Scenarios) and len(s) == 12
    assert str(s.map_name[0]) == f"{name}.3dmap" and s.version == "1" and max(m.shape) <= 64
    tol = s.tolerance()
    for k in range(0, len(s), 4):  # a third of them: each a Dijkstra over the whole map
        start = tuple(int(v) for v in s.start_cell[k])
        assert not m.occupied[start] and not m.occupied[tuple(s.goal_cell[k])]
        costs = bbox_costs(m.occupied, start)
        assert abs(costs[tuple(s.goal_cell[k])] - s.optimal[k]) <= tol[k]
    assert (s.ratio >= 1 - 1e-9).all()


def test_scen3d_coordinates(tmp_path):
    f = tmp_path / "t.3dmap.3dscen"
    f.write_text("version 1\nmaps/t.3dmap\n1 2 3 4 5 6 5.19615242 1.00000000\n0 0 0 0 0 0 0 1\n")
    s = read_scen3d(f, shape=(7, 6, 5))
    assert s.start_voxel.tolist() == [[1, 2, 3], [0, 0, 0]] and s.goal_voxel[0].tolist() == [4, 5, 6]
    assert s.start_xy[0].tolist() == [1.5, 2.5, 3.5] and s.goal_xy[0].tolist() == [4.5, 5.5, 6.5]
    assert s.start_cell[0].tolist() == [3, 2, 1] and s.goal_cell[0].tolist() == [6, 5, 4]
    assert s.optimal.tolist() == [5.19615242, 0.0] and s.ratio.tolist() == [1.0, 1.0]
    assert str(s.map_name[0]) == "t.3dmap" and s.precision == "decimals" and s.digits == 8
    assert s.width.tolist() == [5, 5] and s.height.tolist() == [6, 6] and s.depth.tolist() == [7, 7]
    assert not s.no_path.any()
    g = tmp_path / "t.3dmap.3dscen.gz"
    g.write_bytes(gzip.compress(f.read_bytes()))
    assert read_scen(g).start_voxel.tolist() == s.start_voxel.tolist()


@pytest.mark.parametrize(("text", "match"), [
    ("", r"expected 'version 1' first"),
    ("t.3dmap\n0 0 0 1 1 1 1.7 1\n", r"line 1: expected 'version 1' first"),
    ("version 1\n", r"line 2: expected the map's file name"),
    ("version 1\n0 0 0 1 1 1 1.7 1\n", r"line 2: expected the map's file name"),
    ("version 1\nt.3dmap\n", r"no scenarios"),
    ("version 1\nt.3dmap\n0 0 0 1 1 1 1.7\n", r"line 3: expected 8 fields"),
    ("version 1\nt.3dmap\n0 0 0 1 1 1 1.7 1\n0 0 0.5 1 1 1 1.7 1\n", r"line 4: sz must be an integer, got '0.5'"),
    ("version 1\nt.3dmap\n0 0 0 1 1 x 1.7 1\n", r"line 3: gz must be an integer"),
    ("version 1\nt.3dmap\n0 0 0 1 1 1 abc 1\n", r"line 3: optimal_cost must be a number"),
    ("version 1\nt.3dmap\n0 0 0 1 1 1 -2 1\n", r"line 3: optimal_cost and ratio must be finite numbers >= 0"),
    ("version 1\nt.3dmap\n0 0 0 1 1 1 nan 1\n", r"line 3: optimal_cost and ratio must be finite"),
    ("version 1\nt.3dmap\n0 -1 0 1 1 1 1 1\n", r"line 3: start \(0, -1, 0\) or goal \(1, 1, 1\) lies outside"),
    ("version 1\nt.3dmap\n0 0 0 1 1 " + "9" * 5000 + " 1 1\n", r"line 3: gz must be an integer"),
])
def test_scen3d_errors(tmp_path, text, match):
    f = tmp_path / "bad.3dscen"
    f.write_text(text)
    with pytest.raises(MapFormatError, match=match):
        read_scen3d(f)


def test_scen3d_outside_the_given_shape(tmp_path):
    f = tmp_path / "t.3dscen"
    f.write_text("version 1\nt.3dmap\n0 0 0 4 1 1 1 1\n")
    with pytest.raises(MapFormatError, match=r"line 3: .* lies outside the 4 x 3 x 2 map"):
        read_scen3d(f, shape=(2, 3, 4))
    with pytest.raises(ParameterError, match="shape must be three positive integers"):
        read_scen3d(f, shape=(2, 3))


# ----------------------------------------------------------------------------------------------
# binvox
# ----------------------------------------------------------------------------------------------
@SETTINGS
@given(d=st.integers(1, 7), seed=st.integers(0, 1000), value=st.sampled_from([1, 200]))
def test_binvox_round_trip(tmp_path, d, seed, value):
    occ = np.random.default_rng(seed).random((d, d, d)) < 0.4
    f = write_binvox(tmp_path / "m.binvox", occ, translate=(-1.5, 2.0, 0.25), scale=3.0, value=value)
    m = read_binvox(f)
    np.testing.assert_array_equal(m.occupied, occ)
    assert m.grid.resolution == pytest.approx(3.0 / d) and m.grid.origin == (-1.5, 2.0, 0.25)
    assert m.meta["format"] == "binvox"
    np.testing.assert_array_equal(read(f).occupied, occ)


def test_binvox_voxel_order_and_world_coordinates(tmp_path):
    """The spec: y runs fastest, then z, then x; voxel (i, j, k) has its centre at t + s * ((i, j, k) + 0.5) / d."""
    d, t, s = 4, np.array([10.0, -2.0, 1.0]), 2.0
    i, j, k = 3, 1, 2  # x, y, z
    index = i * d * d + k * d + j
    runs = bytes([0, index, 1, 1, 0, d**3 - index - 1])
    f = tmp_path / "one.binvox"
    f.write_bytes(f"#binvox 1\ndim {d} {d} {d}\ntranslate {t[0]} {t[1]} {t[2]}\nscale {s}\ndata\n".encode() + runs)
    m = read_binvox(f)
    assert np.argwhere(m.occupied).tolist() == [[k, j, i]]
    centre = t + s * (np.array([i, j, k]) + 0.5) / d
    assert m.is_free([centre]).tolist() == [False]
    assert m.grid.cell_to_world([[k, j, i]])[0].tolist() == pytest.approx(centre.tolist())


def test_binvox_without_translate_and_scale_is_the_unit_cube(tmp_path):
    f = tmp_path / "u.binvox"
    f.write_bytes(b"#binvox 1\ndim 2 2 2\ndata\n" + bytes([1, 8]))
    m = read_binvox(f)
    assert m.grid.resolution == 0.5 and m.grid.origin == (0.0, 0.0, 0.0) and m.occupied.all()


@pytest.mark.parametrize(("data", "match", "error"), [
    (b"#binvox 1\ndim 2 2 2\ndata\n" + bytes([1, 7]), r"truncated binvox data: the run lengths add up to 7 voxels, "
     r"but 'dim 2 2 2' has 8", MapFormatError),
    (b"#binvox 1\ndim 2 2 2\ndata\n" + bytes([1, 8, 0]), r"truncated binvox data: 3 bytes", MapFormatError),
    (b"#binvox 1\ndim 2 2 2\ndata\n" + bytes([1, 8, 0, 1]), r"add up to 9 voxels", MapFormatError),
    (b"#binvox 1\ndim 2 2 2\n", r"ends before its 'data' line", MapFormatError),
    (b"binvox 1\ndim 2 2 2\ndata\n", r"line 1: expected '#binvox 1'", MapFormatError),
    (b"#binvox 1\ndata\n\x01\x08", r"no 'dim' line", MapFormatError),
    (b"#binvox 1\ndim 2 x 2\ndata\n", r"line 2: 'dim' needs three positive integers", MapFormatError),
    (b"#binvox 1\ndim 2 2 2\nscale -1\ndata\n", r"line 3: 'scale' needs a positive number", MapFormatError),
    (b"#binvox 1\ndim 2 2 2\ntranslate 0 nan 0\ndata\n", r"'translate' needs three finite", MapFormatError),
    (b"#binvox 1\ndim 2 2 2\ncolour red\ndata\n", r"line 3: expected a binvox header line", MapFormatError),
    (b"#binvox 1\ndim 2 3 2\ndata\n" + bytes([0, 12]), r"dims 2 3 2 are not equal", MapFormatError),
    (b"#binvox 1\ndim 100000 100000 100000\ndata\n" + bytes([0, 255]), r"binvox header 'dim 100000 100000 "
     r"100000'.*100000 x 100000 x 100000", SizeLimitError),
])
def test_binvox_errors(tmp_path, data, match, error):
    f = tmp_path / "bad.binvox"
    f.write_bytes(data)
    tracemalloc.start()
    try:
        with pytest.raises(error, match=match):
            read_binvox(f)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1_000_000


# ----------------------------------------------------------------------------------------------
# point clouds
# ----------------------------------------------------------------------------------------------
def check_voxelized(m, pts: np.ndarray) -> None:
    """Geometry: every point's voxel (its closed box) is occupied, every occupied voxel's closed box holds a
    point, and the grid covers the points' box with one free voxel around it."""
    res = m.grid.resolution
    lo = np.array(m.grid.origin)
    centres = m.grid.cell_to_world(np.argwhere(m.occupied))  # (x, y, z) of each occupied voxel
    inside = (np.abs(pts[None, :, :] - centres[:, None, :]) <= res / 2 + 1e-9).all(axis=2)  # voxel x point
    assert inside.any(axis=1).all()  # each occupied voxel holds a point
    assert inside.any(axis=0).all()  # each point lies in an occupied voxel
    assert np.allclose(lo, pts.min(axis=0) - res)
    top = np.array(m.grid.bounds[3:])
    assert (top - pts.max(axis=0) > res - 1e-9).all() and (top - pts.max(axis=0) <= 2 * res + 1e-9).all()


@pytest.mark.parametrize("fmt", ["ascii", "binary_little_endian", "binary_big_endian"])
@pytest.mark.parametrize("dtype", ["f4", "f8"])
@pytest.mark.parametrize("faces", [False, True])
def test_ply_voxelized(tmp_path, fmt, dtype, faces):
    pts = np.random.default_rng(5).uniform(-2, 3, (60, 3)).astype(dtype).astype(np.float64)
    f = write_ply(tmp_path / "c.ply", pts, fmt, dtype=dtype, faces=faces)
    m = read(f, resolution=0.4)
    assert m.ndim == 3 and m.meta["format"] == "ply" and m.meta["points"] == 60
    check_voxelized(m, pts)


def test_xyz_voxelized_with_comments_and_extra_columns(tmp_path):
    pts = np.random.default_rng(6).uniform(0, 5, (40, 3))
    lines = ["# a scan", ""] + [f"{float(x)!r} {float(y)!r} {float(z)!r} 0.5 128  # point {i}" for i, (x, y, z) in enumerate(pts)]
    f = tmp_path / "c.xyz"
    f.write_text("\n".join(lines) + "\n")
    m = read_pointcloud(f, resolution=0.7)
    assert m.meta["format"] == "xyz" and m.grid.border == "open"
    check_voxelized(m, pts)


def test_one_point_and_margin_zero(tmp_path):
    f = tmp_path / "p.xyz"
    f.write_text("1 2 3\n")
    m = read_pointcloud(f, resolution=0.5, margin=0)
    assert m.shape == (1, 1, 1) and m.occupied.all() and m.grid.origin == (1.0, 2.0, 3.0)


@pytest.mark.parametrize(("name", "data", "match"), [
    ("a.xyz", "0 0 0\n1 1\n", r"line 2: expected x y z \(three numbers\), got 2 fields"),
    ("a.xyz", "0 0 0\n1 b 1\n", r"line 2: .xyz coordinates must be numbers, got 'b'"),
    ("a.xyz", "0 0 0\n1 nan 1\n", r"line 2: point \(1, nan, 1\) is not finite"),
    ("a.xyz", "# nothing\n", r"no points"),
    ("a.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
              "end_header\n0 0 0\n", r"truncated PLY file: the header says 2 vertices, the file holds 1"),
    ("a.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
     r"has no property z"),
    ("a.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
              "end_header\n0 0\n", r"line 8: expected 3 vertex values"),
    ("a.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nend_header\n" + "\0" * 20, r"truncated PLY file: 3 vertices of 12 bytes need"),
    ("a.ply", "ply\nformat weird 1.0\nend_header\n", r"line 2: expected 'format ascii"),
    ("a.ply", "plyx\nhello\n", r"not a PLY file"),
    ("a.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n3 0 1 2\n",
     r"no 'element vertex'"),
])
def test_pointcloud_errors(tmp_path, name, data, match):
    f = tmp_path / name
    f.write_text(data)
    with pytest.raises(MapFormatError, match=match) as e:
        read_pointcloud(f, resolution=1.0)
    assert str(f) in str(e.value)


def test_pointcloud_needs_a_resolution_and_the_guard(tmp_path):
    f = tmp_path / "c.xyz"
    f.write_text("0 0 0\n1 1 1\n")
    with pytest.raises(ParameterError, match="needs a resolution"):
        read(f)
    tracemalloc.start()
    try:
        with pytest.raises(SizeLimitError, match=r"c.xyz at resolution 1e-06"):
            read(f, resolution=1e-6)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1_000_000


# ----------------------------------------------------------------------------------------------
# 3-D arrays
# ----------------------------------------------------------------------------------------------
def test_3d_npy_as_a_voxel_map(tmp_path):
    occ = np.random.default_rng(1).random((3, 4, 5)) < 0.3
    f = tmp_path / "v.npy"
    np.save(f, occ)
    m = read(f, resolution=0.5, origin=(1.0, 2.0, 3.0))
    np.testing.assert_array_equal(m.occupied, occ)
    assert m.grid.resolution == 0.5 and m.grid.origin == (1.0, 2.0, 3.0) and m.meta["format"] == "npy"
    labels = np.where(occ, 3, 0).astype(np.int16)  # numbers: non-zero = obstacle
    np.save(f, labels)
    np.testing.assert_array_equal(read_voxel_npy(f).occupied, occ)
    grey = np.where(occ, 0, 255).astype(np.uint8)  # grey levels: 0 = black = obstacle
    np.save(f, grey)
    np.testing.assert_array_equal(read(f, occupancy="dark").occupied, occ)
    np.save(tmp_path / "s.npy", labels)
    with pytest.raises(MapFormatError, match="no grey-level convention"):
        read(tmp_path / "s.npy", occupancy="dark")  # signed integers are no grey levels
    with pytest.raises(ParameterError, match="chunks"):
        read(f, chunks=16)  # a voxel map is read whole
    with override(10), pytest.raises(SizeLimitError, match=r"v.npy \(.npy header\)"):
        read(f)


def test_2d_npy_is_still_read_by_chunks(tmp_path):
    from gridfield.core.chunkcache import LazyGridMap

    f = tmp_path / "m.npy"
    np.save(f, np.eye(3, dtype=bool))
    assert isinstance(read(f), LazyGridMap)


def test_3d_npz_round_trip(tmp_path):
    from gridfield.core.grid import Grid

    occ = np.random.default_rng(2).random((2, 3, 4)) < 0.5
    grid = Grid((2, 3, 4), 0.25, (0.0, 1.0, 2.0), "wall")
    f = write_npz(tmp_path / "v.npz", {"occupied": occ, "distance": np.ones((2, 3, 4))}, grid)
    m = read_npz(f)
    np.testing.assert_array_equal(m.occupied, occ)
    assert m.grid == grid and m.meta["format"] == "npz"
    assert read(f).grid == grid
    np.savez(tmp_path / "bad.npz", occupied=occ, distance=np.ones((2, 3, 5)), resolution=1.0, origin=[0, 0, 0])
    with pytest.raises(MapFormatError, match="different shapes"):
        read_npz(tmp_path / "bad.npz")


# ----------------------------------------------------------------------------------------------
# gridfield info
# ----------------------------------------------------------------------------------------------
def test_info_on_a_voxel_map(tmp_path, capsys):
    occ = np.zeros((3, 4, 5), dtype=bool)
    occ[0, 0, 0] = occ[1, 1, 1] = occ[2, 3, 4] = True  # two 26-connected regions
    f = write_3dmap(tmp_path / "m.3dmap", occ)
    assert main(["info", str(f), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["shape"] == [3, 4, 5] and info["bounds"] == [0, 0, 0, 5, 4, 3] and info["origin"] == [0, 0, 0]
    assert info["occupied_cells"] == 3 and info["occupied_fraction"] == pytest.approx(3 / 60)
    assert info["obstacles"] == 2 and info["format"] == "movingai3d" and info["occupancy_rule"]
    assert main(["info", str(f)]) == 0
    out = capsys.readouterr().out
    assert "3 layers x 4 rows x 5 cols" in out and "x [0, 5], y [0, 4], z [0, 3]" in out
    assert "occupied cells:    3 of 60" in out and "26-connected" in out


def test_info_on_a_point_cloud_takes_resolution(tmp_path, capsys):
    f = tmp_path / "c.xyz"
    f.write_text("0 0 0\n1 1 1\n")
    assert main(["info", str(f), "--resolution", "0.5", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["shape"] == [5, 5, 5] and info["resolution"] == 0.5 and info["format"] == "xyz"
    assert main(["info", str(f)]) != 0
    assert "needs a resolution" in capsys.readouterr().err


def test_voxel_io_benchmark_runs_tiny(capsys):
    """benchmarks/voxel_io.py's main on a tiny map (no timing asserted: its readers agree, its table prints)."""
    import sys

    bench = str(Path(__file__).resolve().parents[1] / "benchmarks")
    sys.path.insert(0, bench)
    try:
        import voxel_io
    finally:
        sys.path.remove(bench)
    assert voxel_io.main(["--size", "12", "--repeat", "1"]) == 0
    assert "| read_3dmap |" in capsys.readouterr().out


def test_the_commands_pass_resolution_to_a_point_cloud(tmp_path):
    """The commands' map loader (gridfield.cli._common.load_target) gives a cloud its --resolution."""
    import argparse

    from gridfield.cli._common import load_target

    f = tmp_path / "c.xyz"
    f.write_text("0 0 0\n1 1 1\n")
    m = load_target(argparse.Namespace(map=str(f), resolution=0.5, command="field"))
    assert m.ndim == 3 and m.grid.resolution == 0.5 and int(m.occupied.sum()) == 2


def test_3dmap_gzip_bomb_is_refused_by_its_decompressed_size(tmp_path):
    f = tmp_path / "bomb.3dmap.gz"
    f.write_bytes(gzip.compress(b"voxel 4 4 4\n" + b"0 0 0\n" * 400_000))  # 2.4 MB of lines, 4 x 4 x 4 voxels
    with override(100), pytest.raises(SizeLimitError, match="decompresses to more than"):
        read_3dmap(f)
    assert int(read_3dmap(f).occupied.sum()) == 1  # within the default limit: duplicates are fine


_HEADS = {
    "f.binvox": [b"#binvox 1\n", b"dim 2 2 2\n", b"dim 3 3 3\n", b"translate 0 0 0\n", b"scale 2\n", b"data\n",
                 b"\x01\x08", b"\x00\xff", b"\n"],
    "f.ply": [b"ply\n", b"format ascii 1.0\n", b"format binary_big_endian 1.0\n", b"element vertex 2\n",
              b"property float x\n", b"property double y\n", b"property uchar z\n", b"end_header\n", b"0 1 2\n",
              b"\x00\x01\x02\x03\x04\x05\x06\x07", b"element face 1\n", b"property list uchar int vertex_indices\n"],
    "f.xyz": [b"0 0 0\n", b"1 2\n", b"# c\n", b"1e400 0 0\n", b"nan 0 0\n", b"\xff\n", b"-1 -2 -3 4\n"],
    "f.3dscen": [b"version 1\n", b"m.3dmap\n", b"0 0 0 1 1 1 1.7 1.0\n", b"0 0 0 1 1\n", b"x y z 1 1 1 1 1\n", b"\n"],
}


@SETTINGS
@given(name=st.sampled_from(sorted(_HEADS)), data=st.data())
def test_voxel_readers_fuzz_never_a_traceback(tmp_path, name, data):
    parts = data.draw(st.lists(st.sampled_from(_HEADS[name]) | st.binary(max_size=12), max_size=10))
    f = tmp_path / name
    f.write_bytes(b"".join(parts))
    with override(100_000):
        try:
            out = read_scen(f) if name.endswith("3dscen") else read(f, resolution=0.5) if name.endswith(
                ("ply", "xyz")) else read(f)
        except (MapFormatError, SizeLimitError):
            return
    assert len(out) if isinstance(out, Scenarios3D) else out.ndim == 3


@pytest.mark.parametrize("count", ["9" * 5000, "\u00b2", "-1"])
def test_ply_element_count_that_is_no_number(tmp_path, count):
    f = tmp_path / "c.ply"
    f.write_text(f"ply\nformat ascii 1.0\nelement vertex {count}\nproperty float x\nend_header\n", encoding="utf-8")
    with pytest.raises(MapFormatError, match="line 3: not a PLY header line"):
        read_pointcloud(f, resolution=1.0)


def test_3dmap_is_parsed_in_blocks_with_the_right_line_numbers(tmp_path, monkeypatch):
    """Blocks of whole lines (a tiny block size here): the same map, and an error names the file's line."""
    from gridfield.io import _voxel

    occ = np.random.default_rng(3).random((5, 6, 7)) < 0.4
    f = write_3dmap(tmp_path / "m.3dmap", occ, shuffle=1)
    g = tmp_path / "m.3dmap.gz"
    g.write_bytes(gzip.compress(f.read_bytes()))
    monkeypatch.setattr(_voxel, "BLOCK_BYTES", 16)
    np.testing.assert_array_equal(read_3dmap(f).occupied, occ)
    np.testing.assert_array_equal(read_3dmap(g).occupied, occ)
    lines = f.read_text().splitlines()
    lines[40] = "1 1 99"
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(MapFormatError, match=r"line 41: voxel \(1, 1, 99\) lies outside"):
        read_3dmap(f)
    lines[40] = "1 1 x"
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(MapFormatError, match=r"line 41: coordinates must be non-negative integers, got 'x'"):
        read_3dmap(f)
    f.write_text("voxel 2 2 2\n" + "1" * 40)
    with pytest.raises(MapFormatError, match=r"line 2: longer than 16 bytes"):
        read_3dmap(f)


@pytest.mark.parametrize("name", ["building", "random20", "cave"])
def test_plan_on_the_bundled_voxel_scenarios_reaches_their_optimal_costs(tmp_path, capsys, name):
    """The readers end to end: ``gridfield plan MAP.3dmap.gz --scenario F.3dscen`` (the 26-connected wavefront,
    the benchmark's bounding-box rule) finds each scenario's published optimal cost."""
    scen = tmp_path / f"{name}.3dmap.3dscen"
    scen.write_bytes(gzip.decompress((VOXEL / f"{name}.3dmap.3dscen.gz").read_bytes()))
    s = read_scen3d(scen)
    tol = s.tolerance()
    for i in range(len(s)):
        assert main(["plan", str(VOXEL / f"{name}.3dmap.gz"), "--scenario", str(scen), "--index", str(i),
                     "--planner", "wavefront-octile", "--json"]) == 0
        out = json.loads(capsys.readouterr().out)
        assert out["status"] == "reached" and abs(out["length"] - s.optimal[i]) <= tol[i], (i, out["length"])
