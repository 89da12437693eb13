"""Bad input, second list: each case is a one-line gridfield error (or a bound stated up front), bounded
memory, and unchanged answers on good input. Every test here fails on the code before the fix."""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import threading
import tracemalloc
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from gridfield.core.errors import GridfieldError, MapFormatError
from gridfield.io import bundled_map, read, read_bitmap, read_npz, read_ros_map, read_scen, read_yaml

from mapdata import TEST_MAPS

ROOT = Path(__file__).resolve().parents[1]
ARENA = bundled_map("arena/arena.map")


def cli(*args: str, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gridfield", *args], capture_output=True, text=True,
                          timeout=timeout, cwd=ROOT)


def one_line_error(r: subprocess.CompletedProcess[str]) -> str:
    assert r.returncode == 2, (r.returncode, r.stderr[-2000:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr[-2000:]
    return lines[0]


def peak_bytes(fn, *args, **kw) -> tuple[object, int]:
    """``fn(*args)`` (its result or the GridfieldError it raised) and the peak of traced allocations (numpy too)."""
    tracemalloc.start()
    try:
        try:
            out: object = fn(*args, **kw)
        except GridfieldError as e:
            out = e
        return out, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


# ----------------------------------------------------------------------------------------
# 1. .scen reading: one long field must not widen the whole table
# ----------------------------------------------------------------------------------------
LINE = "0\tarena.map\t49\t49\t1\t11\t1\t12\t1\n"


def test_scen_long_path_field_stays_small(tmp_path):
    # a valid file: every map field is a 3000-character relative path (basename arena.map); the old reader
    # made a 9-column table as wide as the longest field: 5000 x 9 x 3000 x 4 bytes = 540 MB
    f = tmp_path / "long.scen"
    longpath = "d/" * 1495 + "arena.map"
    f.write_text("version 1\n" + "".join(LINE.replace("arena.map", longpath) for _ in range(5000)))
    s, peak = peak_bytes(read_scen, f)
    assert isinstance(s, object) and len(s) == 5000 and str(s.map_name[0]) == "arena.map"  # type: ignore[arg-type, attr-defined]
    assert peak < 20e6, peak


def test_scen_one_long_field_is_refused_naming_the_line(tmp_path):
    f = tmp_path / "m.scen"
    f.write_text("version 1\n" + LINE * 3 + LINE.replace("\t1\n", "\t" + "1" * 20000 + "\n") + LINE)
    e, peak = peak_bytes(read_scen, f)
    assert isinstance(e, MapFormatError)
    assert "m.scen: line 5: the optimal field is 20000 characters long" in str(e)
    assert peak < 5e6, peak


def test_scen_one_huge_line_is_refused_with_bounded_memory(tmp_path):
    f = tmp_path / "m.scen"
    with open(f, "w") as fh:
        fh.write("version 1\n" + LINE)
        fh.write("0\t" + "x" * 30_000_000 + "\t49\t49\t1\t11\t1\t12\t1\n")
    e, peak = peak_bytes(read_scen, f)
    assert isinstance(e, MapFormatError) and "m.scen: line 3: longer than 65536 bytes" in str(e), e
    assert peak < 2e6, peak


def test_scen_many_short_lines_unchanged():
    s = read_scen(ARENA.with_name("arena.map.scen"))
    assert len(s) == 160 and s.map_name.dtype == np.dtype("<U9") and s.digits == 6


# ----------------------------------------------------------------------------------------
# 2. non-regular files are refused before they are opened
# ----------------------------------------------------------------------------------------
@contextlib.contextmanager
def fifo(path: Path) -> Iterator[Path]:
    """A FIFO at ``path``; a helper thread opens it for writing (and closes it) whenever a reader waits, so
    that the old code, which opened it, does not hang the test (it reads an empty file instead)."""
    os.mkfifo(path)
    stop = threading.Event()

    def unblock() -> None:
        while not stop.wait(0.05):
            try:
                fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
            except OSError:
                continue  # no reader yet
            os.close(fd)

    t = threading.Thread(target=unblock, daemon=True)
    t.start()
    try:
        yield path
    finally:
        stop.set()
        t.join()


@pytest.mark.parametrize(("name", "reader"), [("s.scen", read_scen), ("m.map", read), ("w.yaml", read_yaml),
                                              ("w.yaml", read), ("a.npz", read_npz), ("a.png", read_bitmap),
                                              ("r.yaml", read_ros_map)])
def test_fifo_is_refused(tmp_path, name, reader):
    with fifo(tmp_path / name) as f, pytest.raises(MapFormatError, match=rf"{name}: is a FIFO \(named pipe\), "
                                                                         "expected a regular file"):
        reader(f)


def test_fifo_ros_image_is_refused(tmp_path):
    (tmp_path / "m.yaml").write_text("image: img.png\nresolution: 0.05\norigin: [0, 0, 0]\n")
    with fifo(tmp_path / "img.png"), pytest.raises(MapFormatError, match=r"m\.yaml: 'image': .*img\.png: is a FIFO"):
        read_ros_map(tmp_path / "m.yaml")


def test_fifo_sweep_spec_and_rows_file_are_refused(tmp_path):
    from gridfield.sweep import load_spec

    with fifo(tmp_path / "spec.yaml") as f, pytest.raises(MapFormatError, match=r"spec\.yaml: is a FIFO"):
        load_spec(f)
    spec = tmp_path / "ok.yaml"
    spec.write_text(f"maps: [{ARENA}]\nplanners: [wavefront-octile]\noutput: rows.csv\n"
                    "params: {}\n")
    with fifo(tmp_path / "rows.csv"), pytest.raises(GridfieldError, match=r"rows\.csv: the rows file exists and "
                                                                         "is not a regular file"):
        load_spec(spec)


def test_cli_fifo_scenario_is_one_line(tmp_path):
    with fifo(tmp_path / "s.scen") as f:
        line = one_line_error(cli("plan", str(ARENA), "--scenario", str(f), "--index", "0", timeout=30))
    assert "s.scen: is a FIFO (named pipe), expected a regular file" in line


# ----------------------------------------------------------------------------------------
# 4. subnormal (and absurd) resolutions are refused by the one grid rule
# ----------------------------------------------------------------------------------------
def _image(tmp_path: Path) -> Path:
    from PIL import Image

    Image.fromarray(np.full((20, 30), 255, np.uint8)).save(tmp_path / "img.png")
    return tmp_path / "img.png"


@pytest.mark.parametrize("res", ["1e-320", "5e-324", "1e-200", "1e150"])
def test_bad_resolution_ros_npz_bitmap(tmp_path, res):
    img = _image(tmp_path)
    (tmp_path / "m.yaml").write_text(f"image: img.png\nresolution: {res}\norigin: [0, 0, 0]\n")
    np.savez(tmp_path / "a.npz", occupied=np.zeros((20, 30), bool), resolution=np.float64(res),
             origin=np.zeros(2), border=np.array("open"))
    (tmp_path / "w.yaml").write_text(f"bounds: [0, 0, 4, 3]\nresolution: {res}\nborder: wall\n")
    pt = [str(float(res) * 10)] * 2
    for target, extra in ((tmp_path / "m.yaml", []), (tmp_path / "a.npz", []), (img, ["--resolution", res]),
                          (tmp_path / "w.yaml", ["--planner", "wavefront"])):
        line = one_line_error(cli("plan", str(target), *extra, "--start", *pt, "--goal", *pt))
        assert "resolution must be between 1e-75 and 1e+75" in line, line
        if target.suffix != ".png" and target.name != "w.yaml":
            assert target.name in line


def test_resolution_rule_bounds():
    from gridfield.core.errors import ParameterError
    from gridfield.core.grid import RESOLUTION_RANGE, Grid

    lo, hi = RESOLUTION_RANGE
    assert Grid((2, 2), lo).resolution == lo and Grid((2, 2), hi).resolution == hi
    for bad in (lo / 2, hi * 2, 1e-320):
        with pytest.raises(ParameterError, match="resolution must be between"):
            Grid((2, 2), bad)
        with pytest.raises(ParameterError, match="resolution must be between"):
            Grid.covering((0, 0, 1, 1), bad)


# ----------------------------------------------------------------------------------------
# 5. IncrementalBrushfire obstacle ids: 1..2**31-1, never wrapped
# ----------------------------------------------------------------------------------------
def _ids_map(max_id: int = 3):
    from gridfield.core.grid import Grid, GridMap
    from gridfield.distance.incremental import IncrementalBrushfire

    occ = np.zeros((4, 9), bool)
    occ[:, 0] = True
    return IncrementalBrushfire(GridMap(Grid((4, 9), 1.0), occ, np.where(occ, max_id, 0).astype(np.int32)))


@pytest.mark.parametrize("ids", [2**32 + 7, 2**40, 2**31, 0, -1, [5, 2**32], np.array([3, 0], np.int64),
                                 np.uint64(2**63)])
def test_incremental_ids_out_of_range(ids):
    from gridfield.core.errors import ParameterError

    ib = _ids_map()
    before = ib.gridmap.obstacle_id.copy()
    with pytest.raises(ParameterError, match=r"ids must be obstacle ids in 1\.\.2147483647"):
        ib.update(occupied=[[1, 8], [2, 8]], ids=ids)
    np.testing.assert_array_equal(ib.gridmap.obstacle_id, before)  # nothing changed


def test_incremental_default_id_after_the_largest():
    from gridfield.core.errors import ParameterError
    from gridfield.distance.brushfire import brushfire

    ib = _ids_map(2**31 - 2)
    ib.update(occupied=[[1, 8]])  # the last default id
    assert ib.gridmap.obstacle_id[1, 8] == 2**31 - 1
    with pytest.raises(ParameterError, match="no default obstacle id left"):
        ib.update(occupied=[[2, 8]])
    ib.update(occupied=[[2, 8]], ids=2**31 - 1)  # the largest id, given
    d, f = ib.distance_map, brushfire(ib.gridmap, metric="euclidean", compute_steps=False)
    np.testing.assert_array_equal(d.distance, f.distance)
    np.testing.assert_array_equal(d.label, f.label)
    assert ib.gridmap.obstacle_id[2, 8] == 2**31 - 1 and d.label[2, 7] == 2**31 - 1


# ----------------------------------------------------------------------------------------
# 7. a huge robot is refused at once (grid maps: before any footprint; worlds: before shapely fails)
# ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("radius", ["1e4", "1e5", "1e9", "1e300"])
def test_huge_disc_on_a_grid_map_is_refused_at_once(radius):
    line = one_line_error(cli("plan", str(ARENA), "--start", "3.5", "3.5", "--goal", "40.5", "40.5",
                              "--robot-radius", radius, timeout=20))
    assert f"the robot (disc of radius {float(radius):g}) is larger than the map's diagonal (69.3" in line, line


def test_huge_robots_on_grids_through_the_api():
    from gridfield.core.errors import SizeLimitError
    from gridfield.core.grid import Grid, GridMap
    from gridfield.core.limits import override
    from gridfield.geometry.cspace import apply_robot, centre_footprint, conservative_footprint
    from gridfield.geometry.world import Robot

    arena = read(ARENA)
    with pytest.raises(GridfieldError, match="larger than the map's diagonal"):
        apply_robot(arena, [[0, 0], [1e6, 0], [0, 1]])  # a wall: any robot reaching past the diagonal
    open_map = GridMap(Grid((10, 10), 1.0), np.eye(10, dtype=bool))
    assert apply_robot(GridMap(Grid((10, 10), 1.0), np.zeros((10, 10), bool)), 1e9).occupied.sum() == 0
    with override(10**6), pytest.raises(SizeLimitError, match="the footprint of the robot"):
        apply_robot(open_map, [[0, 0], [5e3, 0], [0, 1]])  # open border: sized by the guard, not built
    with override(10**6), pytest.raises(SizeLimitError, match="the footprint of a disc robot of radius 1e\\+06"):
        centre_footprint(1e6, 1.0)
    with override(10**6), pytest.raises(SizeLimitError, match="the footprint of the robot"):
        conservative_footprint(Robot(radius=1e6), 1.0)


@pytest.mark.parametrize("robot", [["--robot-radius", "1e300"], ["--robot-radius", "1e20"]])
def test_huge_disc_on_a_vector_world_is_one_line(robot):
    line = one_line_error(cli("plan", str(bundled_map("seed000.yaml")), "--resolution", "0.1", *robot))
    assert "is larger than the world's diagonal" in line and "GEOS" not in line, line


def test_huge_robot_in_a_world_file_is_one_line(tmp_path):
    text = bundled_map("seed000.yaml").read_text()
    f = tmp_path / "w.yaml"
    f.write_text(text + "\nrobot: {radius: 1.0e+300}\n" if "robot:" not in text else text)
    line = one_line_error(cli("plan", str(f), "--resolution", "0.1"))
    assert "larger than the world's diagonal" in line, line


# ----------------------------------------------------------------------------------------
# 9. the grid configuration space of a disc is decided at cell centres: tight, and every move safe
# ----------------------------------------------------------------------------------------
def _centre_distance_reference(gm) -> np.ndarray:
    """Independent reference: the exact distance from each cell centre to the nearest occupied closed cell square
    (or the wall), by scipy's EDT on the doubled lattice (half-cell steps), where the nearest point of a square to
    a centre is a lattice point."""
    from scipy import ndimage

    occ = gm.occupied
    if gm.grid.border == "wall":
        occ = np.pad(occ, 1, constant_values=True)
    rows, cols = occ.shape
    fine = np.zeros((2 * rows + 1, 2 * cols + 1), bool)
    r, c = np.nonzero(occ)
    for dr in (0, 1, 2):
        for dc in (0, 1, 2):
            fine[2 * r + dr, 2 * c + dc] = True  # the square of cell (r, c): lattice points 2r..2r+2
    d = ndimage.distance_transform_edt(~fine)[1::2, 1::2] * (gm.grid.resolution / 2)
    return d[1:-1, 1:-1] if gm.grid.border == "wall" else d


def _data(rel: str) -> Path:
    """A file of the suite's copy of external maps (tests/data/maps)."""
    return TEST_MAPS / rel


@pytest.mark.parametrize("name", ["movingai/den312d/den312d.map.gz", "movingai/lak303d/lak303d.map.gz",
                                  "movingai/16room_000/16room_000.map.gz", "movingai/AcrosstheCape/AcrosstheCape.map.gz",
                                  "ros_maps/mdr_wrs20-arena/map.yaml", "arena"])
def test_disc_cspace_on_real_maps_is_exact_at_cell_centres(name):
    from gridfield.geometry.cspace import apply_robot

    gm = read(ARENA if name == "arena" else _data(name))
    ref = _centre_distance_reference(gm)
    h = gm.grid.resolution
    for r_cells in (0.01, 0.1, 0.49, 0.5, 0.75, 1.0, 1.3, 2.5):
        r = r_cells * h
        out = apply_robot(gm, r).occupied
        assert not np.any(~out & (ref <= r)), (name, r_cells)  # safe: the disc at a free centre touches nothing
        tie = np.isclose(ref, r, rtol=1e-7)
        assert np.array_equal(out[~tie], (ref <= r)[~tie]), (name, r_cells)  # tight: blocked only if it touches
        if r_cells < 0.5:
            assert np.array_equal(out, gm.occupied)  # below half a cell: a point


def test_den312d_scenarios_are_free_for_a_tenth_of_a_cell():
    from gridfield.geometry.cspace import apply_robot

    m = _data("movingai/den312d/den312d.map.gz")
    gm, sc = read(m), read_scen(m.with_name("den312d.map.scen.gz"))
    c = apply_robot(gm, 0.1).occupied
    assert not c[tuple(sc.start_cell.T)].any() and not c[tuple(sc.goal_cell.T)].any()  # was 68 % blocked


def test_one_cell_robot_on_the_mdr_map_finds_the_point_path():
    from gridfield.planners import plan

    ros = _data("ros_maps/mdr_wrs20-arena/map.yaml")
    out = cli("plan", str(ros), "--start", "0.575", "1.125", "--goal", "2.825", "-0.325", "--planner",
              "wavefront-octile", "--robot-radius", "0.05", "--json")
    assert out.returncode == 0, out.stderr
    import json

    res = json.loads(out.stdout)
    assert res["status"] == "reached", res  # no_path with the old conservative C-space
    point = plan("wavefront-octile", read(ros), (0.575, 1.125), (2.825, -0.325))
    assert point.status == "reached" and res["workspace_clearance"] > 0.05


@pytest.mark.parametrize("seed", range(40))
def test_property_every_allowed_move_keeps_the_disc_clear(seed):
    """Exact geometry (shapely): the disc at every free centre, and swept along every move the grid planners may
    take between free centres (axis moves; diagonals whose two side cells are free: no corner cutting), is
    disjoint from every occupied closed square and the wall; from half a cell on, every diagonal between free
    centres is safe."""
    import shapely

    from gridfield.core.grid import Grid, GridMap
    from gridfield.geometry.cspace import apply_robot

    rng = np.random.default_rng(seed)
    h = float(rng.choice([0.25, 1.0]))
    border = "wall" if seed % 2 else "open"
    grid = Grid((9, 11), h, origin=(0.5, -1.0), border=border)
    occ = rng.random(grid.shape) < rng.uniform(0.05, 0.25)
    r = float(rng.uniform(0.0, 2.5)) * h
    free = ~apply_robot(GridMap(grid, occ), r).occupied
    cells = np.argwhere(occ)
    x0, y0 = grid.origin
    union = shapely.union_all(shapely.box(x0 + cells[:, 1] * h, y0 + cells[:, 0] * h, x0 + (cells[:, 1] + 1) * h,
                                          y0 + (cells[:, 0] + 1) * h)) if len(cells) else shapely.Polygon()
    if border == "wall":
        xmin, ymin, xmax, ymax = grid.bounds
        union = union.union(shapely.box(xmin - 9, ymin - 9, xmax + 9, ymax + 9).difference(shapely.box(*grid.bounds)))
    if union.is_empty:
        return
    fc = np.argwhere(free)
    centres = grid.cell_to_world(fc)
    assert np.all(shapely.distance(shapely.points(centres), union) > r)
    segs, any_diag = [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        b = fc + np.array([dr, dc])
        ok = (b[:, 0] >= 0) & (b[:, 0] < grid.rows) & (b[:, 1] >= 0) & (b[:, 1] < grid.cols)
        a, b = fc[ok], b[ok]
        ok = free[b[:, 0], b[:, 1]]
        a, b = a[ok], b[ok]
        if dr and dc:
            sides = free[a[:, 0] + dr, a[:, 1]] & free[a[:, 0], a[:, 1] + dc]
            any_diag.append(np.stack([grid.cell_to_world(a), grid.cell_to_world(b)], axis=1))
            a, b = a[sides], b[sides]
        segs.append(np.stack([grid.cell_to_world(a), grid.cell_to_world(b)], axis=1))
    allowed = np.concatenate(segs)
    if len(allowed):
        assert np.all(shapely.distance(shapely.linestrings(allowed), union) > r)
    diags = np.concatenate(any_diag)
    if r >= h / 2 and len(diags):
        assert np.all(shapely.distance(shapely.linestrings(diags), union) > r)


# ----------------------------------------------------------------------------------------
# 3. sweep specs: the runs are counted before anything is expanded or validated
# ----------------------------------------------------------------------------------------
def _spec(tmp_path: Path, body: str) -> Path:
    f = tmp_path / "spec.yaml"
    f.write_text(f"output: {tmp_path / 'rows.csv'}\n" + body)
    return f


def test_sweep_huge_random_pairs_refused_with_the_count(tmp_path):
    import time

    from gridfield.sweep import load_spec

    f = _spec(tmp_path, f"planners: [wavefront-octile]\nmaps:\n  - path: {ARENA}\n    random_pairs: {{n: 100000000}}\n")
    t = time.perf_counter()
    e, peak = peak_bytes(load_spec, f)
    assert isinstance(e, MapFormatError) and "the spec expands to 1e+08 runs" in str(e), e
    assert time.perf_counter() - t < 10 and peak < 50e6, peak


def test_sweep_huge_parameter_product_refused_before_validating(tmp_path, monkeypatch):
    import gridfield.sweep._spec as spec_mod
    from gridfield.sweep import load_spec

    calls = []
    monkeypatch.setattr(spec_mod, "_validate_params", lambda *a: calls.append(a))
    params = "".join(f"  {n}: [{', '.join(str(0.1 * (i + 1)) for i in range(10))}]\n"
                      for n in ("eta", "zeta", "q_star", "d_star", "step", "tolerance", "repulsive_power", "attractive_power"))
    f = _spec(tmp_path, f"planners: [potential]\nmaps: [{ARENA}]\nparams:\n{params}")
    with pytest.raises(MapFormatError, match=r"the spec expands to 1e\+08 runs \(1 planners x 1e\+08 parameter "):
        load_spec(f)
    assert not calls  # refused before a single combination was validated


def test_sweep_run_count_follows_the_memory_limit(tmp_path):
    from gridfield.core.limits import override
    from gridfield.sweep import load_spec

    f = _spec(tmp_path, f"planners: [wavefront-octile]\nmaps:\n  - path: {ARENA}\n    random_pairs: {{n: 100}}\n")
    assert len(load_spec(f)[0]) == 100
    with override(1000), pytest.raises(MapFormatError, match=r"expands to 100 runs .* more than 62 \(what 1024 "
                                                              r"bytes per run allow"):
        load_spec(f)


def _sweep_runs():
    from gridfield.sweep import Run

    return [Run(str(ARENA), None, "wavefront-octile", (), (1.5, 37.5), (1.5, 38.5 + k)) for k in range(8)]


def test_dask_killed_worker_is_one_error_and_the_rows_are_kept(tmp_path, monkeypatch):
    import distributed
    from distributed.scheduler import KilledWorker

    import gridfield.sweep._backends as backends
    from gridfield.sweep import run_sweep

    real = backends.run_batch

    def dies_on_the_last(batch, target=None):
        if any(r.goal[1] == 38.5 + 7 for r in batch):
            raise KilledWorker("run_batch-xyz", SimpleNamespace(address="tcp://127.0.0.1:1"), allowed_failures=3)
        return real(batch, target)

    runs = _sweep_runs()
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        monkeypatch.setattr(backends, "run_batch", dies_on_the_last)
        with pytest.raises(GridfieldError, match=r"the Dask cluster failed \(KilledWorker: .*\); the rows written "
                                                 r"so far are kept: run the sweep again to resume$"):
            run_sweep(runs, tmp_path / "rows.csv", scheduler=client, progress=False, batch_size=1)
        kept = (tmp_path / "rows.csv").read_text().splitlines()
        assert 1 <= len(kept) - 1 < len(runs)
        monkeypatch.setattr(backends, "run_batch", real)
        rows = run_sweep(runs, tmp_path / "rows.csv", scheduler=client, progress=False, batch_size=1)
    assert len(rows) == len(runs) and (tmp_path / "rows.csv").read_text().splitlines()[:len(kept)] == kept


def test_dask_scheduler_gone_is_one_error_and_the_rows_are_kept(tmp_path, monkeypatch):
    import distributed

    import gridfield.sweep as sweep_module
    from gridfield.sweep import run_sweep

    runs = _sweep_runs()
    real_append = sweep_module._Journal.append
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                       dashboard_address=":0")
    client = distributed.Client(cluster)

    def append_then_stop(self, row):
        written = real_append(self, row)
        if len(self.rows) == 2:
            cluster.close()
        return written

    monkeypatch.setattr(sweep_module._Journal, "append", append_then_stop)
    try:
        with pytest.raises(GridfieldError, match=r"the Dask cluster failed .* the rows written so far are kept"):
            run_sweep(runs, tmp_path / "rows.csv", scheduler=client, progress=False, batch_size=1)
    finally:
        client.close()
        cluster.close()
    assert len((tmp_path / "rows.csv").read_text().splitlines()) >= 3


# ----------------------------------------------------------------------------------------
# 8. the Minkowski union of a non-convex obstacle leaves no zero-area hole
# ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("robot", [[[-0.3, -0.1], [0.3, -0.1], [0.3, 0.1], [-0.3, 0.1]],
                                   [[0.001, -0.317], [-0.251, 0.434], [0.333, 0.152]],
                                   [[0.222, -0.353], [-0.219, 0.231], [0.068, 0.4], [0.368, -0.184]]])
def test_polygon_robot_on_star_two_leaves_no_sliver_hole(robot):
    import shapely

    from gridfield.fields.navigation import star_world
    from gridfield.geometry.cspace import cspace_world
    from gridfield.io import read_world

    w = read_world(bundled_map("star_two.yaml"))
    c = cspace_world(w, robot)
    star = c.obstacles[0].geometry
    assert star.geom_type == "Polygon" and not star.interiors
    # the exact C-obstacle of the star (a union of convex pieces, computed independently) has the same area
    ref = shapely.union_all([shapely.convex_hull(shapely.multipoints(
        np.concatenate([e[:, None, :] - np.asarray(robot)[None]]).reshape(-1, 2)))
        for e in np.stack([np.asarray(w.obstacles[0].geometry.exterior.coords)[:-1],
                           np.roll(np.asarray(w.obstacles[0].geometry.exterior.coords)[:-1], -1, axis=0)], axis=1)]
        + [shapely.affinity.translate(w.obstacles[0].geometry, *(-np.asarray(robot[0])))])
    assert star.area == pytest.approx(ref.area, rel=1e-12)
    star_world(c, c.goal)  # was: ParameterError "obstacle 1 (polygon) has holes"


def test_real_holes_are_kept():
    import shapely

    from gridfield.geometry.cspace._vector import _drop_slivers

    outer = [(0, 0), (10, 0), (10, 10), (0, 10)]
    real, sliver = [(2, 2), (4, 2), (4, 4), (2, 4)], [(6, 6), (7, 6), (6.5, 6 + 1e-15)]
    out = _drop_slivers(shapely.Polygon(outer, [real, sliver]))
    assert len(out.interiors) == 1 and out.area == pytest.approx(96.0)


def test_point_clear_but_its_cell_centre_blocked_is_named():
    from gridfield.core.grid import Grid, GridMap
    from gridfield.geometry.cspace import apply_robot, check_robot_point

    occ = np.zeros((5, 5), bool)
    occ[2, 2] = True
    gm = GridMap(Grid((5, 5), 1.0), occ)
    c = apply_robot(gm, 0.6)
    check_robot_point(gm, 0.6, "start", (0.5, 0.5), cspace=c)
    with pytest.raises(GridfieldError, match=r"start \(1\.1, 2\.5\) is 0\.9 from the nearest occupied cell, enough "
                                             r"for the robot \(disc of radius 0\.6\), but the centre of its cell "
                                             r"\(1\.5, 2\.5\) is 0\.5 from it"):
        check_robot_point(gm, 0.6, "start", (1.1, 2.5), cspace=c)


def test_polygon_robot_with_absurd_coordinates_is_refused_without_warnings():
    r = cli("plan", str(bundled_map("seed000.yaml")), "--resolution", "0.1", "--robot", "0,0 1e300,0 0,1")
    line = one_line_error(r)  # was: two numpy overflow warnings, then a verdict from overflowed products
    assert "--robot must hold coordinates within ±1e+100" in line, line


def test_dask_cluster_without_workers_ends_the_sweep(tmp_path, monkeypatch):
    import distributed

    import gridfield.sweep._backends as backends
    from gridfield.sweep import run_sweep

    monkeypatch.setattr(backends, "NO_WORKER_TIMEOUT", 2.0)
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        monkeypatch.setattr(client, "scatter", lambda target, **kw: target)  # no worker to scatter to: embed it
        with pytest.raises(GridfieldError, match=r"the Dask cluster failed \(TimeoutError: no worker for 2 s "
                                                 r"\(all died, none restarted\)\); the rows written so far are kept"):
            run_sweep(_sweep_runs(), tmp_path / "rows.csv", scheduler=client, progress=False, batch_size=4)



@pytest.mark.parametrize("how", ["sweep", "connect"])
def test_an_unreachable_scheduler_leaves_no_default_client(tmp_path, how):
    """A ``distributed.Client`` that fails to connect makes itself the default all the same (and points dask's
    scheduler at it): a later ``compute()`` in the same process then waits on the dead address. A fresh run
    hung so in a doctest. Neither the sweep nor ``chunked.connect`` may leave one behind."""
    import dask
    import distributed

    from gridfield.chunked import connect
    from gridfield.sweep import run_sweep

    with pytest.raises(GridfieldError, match="cannot connect to the Dask scheduler 'nonsense://x'"):
        if how == "sweep":
            run_sweep(_sweep_runs(), tmp_path / "rows.csv", scheduler="nonsense://x", progress=False)
        else:
            connect("nonsense://x", timeout=1)
    with pytest.raises(ValueError, match="No clients found"):
        distributed.default_client()
    assert dask.config.get("scheduler", None) != "dask.distributed"
