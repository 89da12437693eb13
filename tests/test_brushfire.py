"""Tests of gridfield.brushfire (compiled wavefront distance maps) and ``gridfield brushfire``.

The fast transforms are checked against slow references: a breadth-first wavefront and brute-force
distances written plainly here (small grids), and scipy.ndimage's distance transforms (random grids
and real maps). Then the nearest obstacle, the labels, the GVD, borders, saturation, edge cases,
the options and the command line.
"""

from __future__ import annotations

import math
from collections import deque
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy import ndimage

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.distance.brushfire import BORDER_LABEL, DistanceMap, brushfire

from mapdata import TEST_MAPS, image, raw

REPO = Path(__file__).resolve().parent.parent
EIGHT = [(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if (dr, dc) != (0, 0)]
FOUR = [(-1, 0), (1, 0), (0, -1), (0, 1)]
COMBOS = [(8, "chessboard"), (4, "taxicab"), (8, "euclidean"), (4, "euclidean"), (8, "taxicab"), (4, "chessboard")]


# ----------------------------------------------------------------------------------------------
# references
# ----------------------------------------------------------------------------------------------
def bfs_steps(occ: np.ndarray, border: str, connectivity: int) -> np.ndarray:
    """The textbook brushfire, plainly: a breadth-first wavefront from every obstacle cell (and from the
    wall ring outside the grid), numbered from 0 on the obstacles. -1 where nothing is reachable."""
    rows, cols = occ.shape
    steps = np.full((rows, cols), -1, dtype=int)
    queue: deque[tuple[int, int]] = deque()
    for r in range(rows):
        for c in range(cols):
            if occ[r, c]:
                steps[r, c] = 0
                queue.append((r, c))
    nbrs = EIGHT if connectivity == 8 else FOUR
    if border == "wall":  # every cell next to the ring is 1 step from it
        for r in range(rows):
            for c in range(cols):
                near_wall = any(not (0 <= r + dr < rows and 0 <= c + dc < cols) for dr, dc in nbrs)
                if near_wall and steps[r, c] == -1:
                    steps[r, c] = 1
                    queue.append((r, c))
        queue = deque(sorted(queue, key=lambda rc: steps[rc]))
    while queue:
        r, c = queue.popleft()
        for dr, dc in nbrs:
            rr, cc = r + dr, c + dc
            if 0 <= rr < rows and 0 <= cc < cols and steps[rr, cc] == -1:
                steps[rr, cc] = steps[r, c] + 1
                queue.append((rr, cc))
    return steps


def metric_length(metric: str, dr, dc):
    dr, dc = np.abs(dr), np.abs(dc)
    if metric == "chessboard":
        return np.maximum(dr, dc)
    if metric == "taxicab":
        return dr + dc
    return np.hypot(dr, dc)


def obstacle_cells(occ: np.ndarray, border: str) -> np.ndarray:
    """(row, col) of every obstacle cell, with the wall ring (without its corners) for a wall border."""
    rows, cols = occ.shape
    cells = [np.argwhere(occ)]
    if border == "wall":
        r, c = np.arange(rows), np.arange(cols)
        cells += [np.c_[np.full(cols, -1), c], np.c_[np.full(cols, rows), c],
                  np.c_[r, np.full(rows, -1)], np.c_[r, np.full(rows, cols)]]
    return np.concatenate(cells).reshape(-1, 2)


def brute_distance(occ: np.ndarray, border: str, metric: str, cells: np.ndarray | None = None) -> np.ndarray:
    """Distance in cells from every cell to the nearest of ``cells`` (default: all obstacles), by brute force."""
    cells = obstacle_cells(occ, border) if cells is None else cells
    rr, cc = np.indices(occ.shape)
    if len(cells) == 0:
        return np.full(occ.shape, np.inf)
    d = metric_length(metric, rr[..., None] - cells[:, 0], cc[..., None] - cells[:, 1])
    return d.min(axis=-1).astype(float)


def scipy_reference(occ: np.ndarray, border: str, metric: str) -> np.ndarray:
    """scipy.ndimage's transform (wall border: pad with obstacles and crop)."""
    o = np.pad(occ, 1, constant_values=True) if border == "wall" else occ
    if metric == "euclidean":
        d = ndimage.distance_transform_edt(~o)
    else:
        d = ndimage.distance_transform_cdt(~o, metric=metric)
    return d[1:-1, 1:-1] if border == "wall" else d


def components(occ: np.ndarray) -> np.ndarray:
    return ndimage.label(occ, structure=np.ones((3, 3), bool))[0]


def check_nearest(dm: DistanceMap) -> None:
    """The nearest cell is an obstacle cell (or the wall ring, no corner) at exactly ``distance``, and the
    label is that obstacle's label."""
    occ = dm.map.occupied
    rows, cols = occ.shape
    res = dm.grid.resolution
    nr, nc = dm.nearest_row, dm.nearest_col
    rr, cc = np.indices(occ.shape)
    inside = (nr >= 0) & (nr < rows) & (nc >= 0) & (nc < cols)
    if dm.grid.border == "wall":
        ring = ~inside
        assert np.all(((nr[ring] == -1) | (nr[ring] == rows)) ^ ((nc[ring] == -1) | (nc[ring] == cols)))
        assert np.all(dm.label[ring] == BORDER_LABEL)
    else:
        assert inside.all()
    assert occ[nr[inside], nc[inside]].all()
    d = metric_length(dm.metric, rr - nr, cc - nc) * res
    np.testing.assert_allclose(dm.distance, d, rtol=1e-12, atol=1e-12)
    own = dm.map.obstacle_id if dm.map.obstacle_id is not None else components(occ)
    assert np.array_equal(dm.label[inside], own[nr[inside], nc[inside]])
    assert np.array_equal(dm.label[occ], own[occ])


def check_gvd(dm: DistanceMap) -> None:
    """The GVD separates the labels' regions, and every GVD cell lies within one cell (one
    8-neighbour step, measured in the metric) of equidistant from two obstacles of different labels."""
    occ, lab, gvd = dm.map.occupied, dm.label, dm.gvd
    rows, cols = occ.shape
    assert not (gvd & occ).any()
    keep = ~occ & ~gvd
    for dr, dc in EIGHT:  # once the GVD is removed, no two neighbouring free cells differ in label
        a = (slice(max(0, -dr), rows - max(0, dr)), slice(max(0, -dc), cols - max(0, dc)))
        b = (slice(max(0, dr), rows + min(0, dr) or None), slice(max(0, dc), cols + min(0, dc) or None))
        assert not (keep[a] & keep[b] & (lab[a] != lab[b])).any()
    if not gvd.any():
        return
    cells = obstacle_cells(occ, dm.grid.border)
    own = components(occ) if dm.map.obstacle_id is None else dm.map.obstacle_id
    cell_label = np.where((cells[:, 0] >= 0) & (cells[:, 0] < rows) & (cells[:, 1] >= 0) & (cells[:, 1] < cols),
                          own[np.clip(cells[:, 0], 0, rows - 1), np.clip(cells[:, 1], 0, cols - 1)], BORDER_LABEL)
    per_label = {int(v): brute_distance(occ, dm.grid.border, dm.metric, cells[cell_label == v])
                 for v in np.unique(lab)}
    step = {"chessboard": 1.0, "taxicab": 2.0, "euclidean": math.sqrt(2)}[dm.metric]
    d = dm.distance / dm.grid.resolution
    for r, c in np.argwhere(gvd):
        mine = per_label[int(lab[r, c])][r, c]
        assert math.isclose(mine, d[r, c], abs_tol=1e-9)
        others = {int(lab[r + dr, c + dc]) for dr, dc in EIGHT
                  if 0 <= r + dr < rows and 0 <= c + dc < cols and not occ[r + dr, c + dc]
                  and lab[r + dr, c + dc] != lab[r, c]}
        assert others, (r, c)
        other = min(per_label[v][r, c] for v in others)
        assert mine - 1e-9 <= other <= mine + step + 1e-9


def random_occupancy(seed: int, shape: tuple[int, int], density: float) -> np.ndarray:
    return np.random.default_rng(seed).random(shape) < density


def load_movingai(path: Path) -> np.ndarray:
    """Minimal Moving AI .map reader: '.', 'G', 'S' free, anything else blocked; first map row = top."""
    lines = raw(path).decode().splitlines()
    start = next(i for i, line in enumerate(lines) if line.strip() == "map") + 1
    rows = [line.rstrip("\n") for line in lines[start:] if line.strip()]
    chars = np.array([list(r) for r in rows])
    return ~np.isin(chars, [".", "G", "S"])[::-1]


def load_pgm(path: Path) -> np.ndarray:
    """Minimal ROS map image reader: occupied where the grey level is below 0.35 * 255 (dark)."""
    with image(path) as im:
        grey = np.asarray(im.convert("L"))
    return (grey < 0.35 * 255)[::-1]


# ----------------------------------------------------------------------------------------------
# the numbering and the references
# ----------------------------------------------------------------------------------------------
def test_numbering_obstacles_zero_neighbours_one():
    occ = np.zeros((5, 5), bool)
    occ[2, 2] = True
    d8 = brushfire(GridMap(Grid((5, 5), 1.0), occ))
    assert d8.steps[2, 2] == 0
    assert (d8.steps[1:4, 1:4][~occ[1:4, 1:4]] == 1).all()
    assert d8.steps.max() == 2 and d8.steps.dtype == np.int32 and d8.distance.dtype == np.float64
    d4 = brushfire(GridMap(Grid((5, 5), 1.0), occ), connectivity=4)
    assert d4.steps[1, 1] == 2 and d4.steps[1, 2] == 1 and d4.steps[0, 0] == 4
    assert d4.metric == "taxicab" and d8.metric == "chessboard"


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    occ=st.integers(1, 9).flatmap(lambda r: st.integers(1, 9).flatmap(
        lambda c: arrays(bool, (r, c), elements=st.booleans()))),
    border=st.sampled_from(["open", "wall"]),
    combo=st.sampled_from(COMBOS),
)
def test_small_grids_equal_plain_wavefront_and_brute_force(occ, border, combo):
    connectivity, metric = combo
    res = 0.25
    dm = brushfire(GridMap(Grid(occ.shape, res, border=border), occ), connectivity=connectivity, metric=metric)
    assert np.array_equal(dm.steps, bfs_steps(occ, border, connectivity))
    if not occ.any() and border == "open":
        assert np.isinf(dm.distance).all() and (dm.label == 0).all() and not dm.gvd.any()
        return
    np.testing.assert_allclose(dm.distance, brute_distance(occ, border, metric) * res, rtol=1e-12)
    check_nearest(dm)
    check_gvd(dm)


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    rows=st.integers(1, 40),
    cols=st.integers(1, 320),
    transpose=st.booleans(),
    density=st.sampled_from([0.0005, 0.003, 0.02, 0.2, 0.6, 0.95]),
    border=st.sampled_from(["open", "wall"]),
)
def test_random_grids_equal_scipy(seed, rows, cols, transpose, density, border):
    shape = (cols, rows) if transpose else (rows, cols)
    occ = random_occupancy(seed, shape, density)
    gm = GridMap(Grid(shape, 1.0, border=border), occ)
    if not occ.any() and border == "open":
        return
    for connectivity, metric in COMBOS:
        dm = brushfire(gm, connectivity=connectivity, metric=metric)
        step_metric = "chessboard" if connectivity == 8 else "taxicab"
        assert np.array_equal(dm.steps, scipy_reference(occ, border, step_metric))
        ref = scipy_reference(occ, border, metric)
        if metric == "euclidean":
            np.testing.assert_allclose(dm.distance, ref, rtol=1e-12, atol=1e-12)
        else:
            assert np.array_equal(dm.distance, ref.astype(float))
        check_nearest(dm)


def _real_maps() -> list:
    bundled = [REPO / "maps/arena/arena.map", REPO / "maps/turtlebot3_world/map.pgm",
               REPO / "maps/nav2_depot/depot.pgm"]
    external = [TEST_MAPS / p for p in (
        "movingai/maze512-32-9/maze512-32-9.map.gz", "movingai/random512-10-0/random512-10-0.map.gz",
        "movingai/Berlin_0_256/Berlin_0_256.map.gz", "movingai/den312d/den312d.map.gz",
        "movingai/mapf_maze-32-32-2/maze-32-32-2.map.gz", "ros_maps/nav2_smoothers_world/smoothers_world.pgm.gz",
        "ros_maps/mdr_wrs20-arena/map.pgm.gz")]
    return [pytest.param(p, id=p.name) for p in bundled + external]


@pytest.mark.parametrize("path", _real_maps())
def test_real_maps_equal_scipy(path):
    occ = load_movingai(path) if path.name.endswith((".map", ".map.gz")) else load_pgm(path)
    for border in ("open", "wall"):
        gm = GridMap(Grid(occ.shape, 0.05, border=border), occ)
        cdt = {m: scipy_reference(occ, border, m) for m in ("chessboard", "taxicab")}
        edt = scipy_reference(occ, border, "euclidean")
        for connectivity, metric in ((8, "chessboard"), (4, "taxicab"), (8, "euclidean")):
            dm = brushfire(gm, connectivity=connectivity, metric=metric)
            assert np.array_equal(dm.steps, cdt["chessboard" if connectivity == 8 else "taxicab"])
            ref = edt if metric == "euclidean" else cdt[metric]
            np.testing.assert_allclose(dm.distance, ref * 0.05, rtol=1e-12, atol=1e-12)
            check_nearest(dm)


def test_labels_number_components_like_scipy():
    occ = random_occupancy(7, (60, 90), 0.3)
    dm = brushfire(GridMap(Grid(occ.shape, 1.0), occ))
    lab, n = ndimage.label(occ, structure=np.ones((3, 3), bool))
    assert np.array_equal(dm.label[occ], lab[occ])
    assert set(np.unique(dm.label)) == set(range(1, n + 1))


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 50), cols=st.integers(1, 50),
       density=st.sampled_from([0.1, 0.3, 0.5, 0.7]), strips=st.integers(1, 60))
def test_components_labelled_in_strips_equal_scipy(seed, rows, cols, density, strips):
    """The threads label horizontal strips, joined afterwards: same numbering as scipy.ndimage.label."""
    from gridfield.distance import _brushfire as k

    occ = random_occupancy(seed, (rows, cols), density)
    comp = np.empty(occ.shape, np.int32)
    count = k.label_components(occ.view(np.uint8), comp, strips)
    ref, n = ndimage.label(occ, structure=np.ones((3, 3), bool))
    assert count == n and np.array_equal(comp, ref)


def test_labels_from_rasterized_world_obstacle_ids():
    occ = np.zeros((6, 9), bool)
    occ[1:3, 1] = occ[4, 6:8] = occ[0, 8] = True
    ids = np.zeros(occ.shape, np.int32)
    ids[1:3, 1], ids[4, 6:8], ids[0, 8] = 7, 3, 3  # two pieces of obstacle 3, one of obstacle 7
    for metric in ("chessboard", "euclidean"):
        dm = brushfire(GridMap(Grid(occ.shape, 1.0), occ, obstacle_id=ids), metric=metric)
        check_nearest(dm)
        assert set(np.unique(dm.label)) == {3, 7}
        check_gvd(dm)


# ----------------------------------------------------------------------------------------------
# GVD
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("gap", [9, 10])
@pytest.mark.parametrize("combo", COMBOS[:3])
def test_gvd_of_two_walls_is_their_bisector(gap, combo):
    connectivity, metric = combo
    occ = np.zeros((7, gap + 2), bool)
    occ[:, 0] = occ[:, -1] = True
    dm = brushfire(GridMap(Grid(occ.shape, 1.0), occ), connectivity=connectivity, metric=metric)
    middle = (gap + 1) // 2  # the one column halfway (an even gap: the left one of the two middle columns)
    expected = np.zeros(occ.shape, bool)
    expected[:, middle] = True
    assert np.array_equal(dm.gvd, expected)
    check_gvd(dm)


def test_gvd_of_two_points_follows_the_perpendicular_bisector():
    occ = np.zeros((41, 41), bool)
    occ[10, 8] = occ[14, 32] = True  # the bisector runs through every row, 1 column per 6 rows
    dm = brushfire(GridMap(Grid(occ.shape, 1.0), occ), metric="euclidean")
    check_gvd(dm)
    rr, cc = np.nonzero(dm.gvd)
    d1, d2 = np.hypot(rr - 10, cc - 8), np.hypot(rr - 14, cc - 32)
    assert set(rr) == set(range(41)) and np.all(np.abs(d1 - d2) <= 2 * math.sqrt(2))
    assert np.bincount(rr).max() <= 2  # one cell thick (two where the digital line steps sideways)


def test_gvd_includes_the_wall_border():
    occ = np.zeros((9, 9), bool)
    occ[4, 4] = True
    wall = brushfire(GridMap(Grid(occ.shape, 1.0, border="wall"), occ))
    opened = brushfire(GridMap(Grid(occ.shape, 1.0, border="open"), occ))
    assert not opened.gvd.any() and (opened.label[~occ] == 1).all()
    assert wall.gvd.any() and (wall.label == BORDER_LABEL).any()
    check_gvd(wall)
    # along row and column 4: the cell 2 steps from the wall next to the one 2 steps from the obstacle
    # (a tie: the smaller label, the wall's, is marked)
    assert wall.gvd[4, 1] and wall.gvd[1, 4] and wall.gvd[4, 7] and wall.gvd[7, 4]
    assert not wall.gvd[4, 2] and not wall.gvd[4, 3] and not wall.gvd[2, 4]


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), border=st.sampled_from(["open", "wall"]), combo=st.sampled_from(COMBOS))
def test_gvd_properties_on_random_grids(seed, border, combo):
    occ = random_occupancy(seed, (18, 23), 0.06)
    dm = brushfire(GridMap(Grid(occ.shape, 1.0, border=border), occ), connectivity=combo[0], metric=combo[1])
    if occ.any() or border == "wall":
        check_gvd(dm)


# ----------------------------------------------------------------------------------------------
# borders, saturation, edge cases
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("combo", COMBOS)
def test_wall_border_is_an_obstacle_open_border_is_not(combo):
    connectivity, metric = combo
    shape = (5, 8)
    empty = np.zeros(shape, bool)
    wall = brushfire(GridMap(Grid(shape, 0.5, border="wall"), empty), connectivity=connectivity, metric=metric)
    rr, cc = np.indices(shape)
    to_wall = np.minimum.reduce([rr + 1, shape[0] - rr, cc + 1, shape[1] - cc])
    assert np.array_equal(wall.steps, to_wall)
    np.testing.assert_allclose(wall.distance, to_wall * 0.5)
    assert (wall.label == BORDER_LABEL).all() and not wall.gvd.any()
    check_nearest(wall)
    opened = brushfire(GridMap(Grid(shape, 0.5, border="open"), empty), connectivity=connectivity, metric=metric)
    assert (opened.steps == -1).all() and np.isinf(opened.distance).all()
    occ = empty.copy()
    occ[2, 0] = True
    opened = brushfire(GridMap(Grid(shape, 0.5, border="open"), occ), connectivity=connectivity, metric=metric)
    assert opened.steps[2, 7] == 7 and wall.steps[2, 7] == 1


def test_saturation_clips_distance_only():
    occ = random_occupancy(3, (30, 40), 0.02)
    for border in ("open", "wall"):
        gm = GridMap(Grid(occ.shape, 0.1, border=border), occ)
        full = brushfire(gm, metric="euclidean")
        for far in (math.inf, 9.0):
            sat = brushfire(gm, metric="euclidean", saturate=0.35, far=far)
            clipped = full.distance >= 0.35
            assert clipped.any() and (~clipped).any()
            assert np.all(sat.distance[clipped] == far)
            assert np.array_equal(sat.distance[~clipped], full.distance[~clipped])
            assert sat.saturate == 0.35 and sat.far == far
            for name in ("steps", "nearest_row", "nearest_col", "label", "gvd"):
                assert np.array_equal(getattr(sat, name), getattr(full, name)), name


@pytest.mark.parametrize("border", ["open", "wall"])
@pytest.mark.parametrize("combo", COMBOS)
def test_empty_and_all_obstacle_maps(border, combo):
    connectivity, metric = combo
    shape = (4, 6)
    full = brushfire(GridMap(Grid(shape, 1.0, border=border), np.ones(shape, bool)),
                     connectivity=connectivity, metric=metric)
    assert (full.steps == 0).all() and (full.distance == 0).all() and (full.label == 1).all()
    assert not full.gvd.any()
    rr, cc = np.indices(shape)
    assert np.array_equal(full.nearest_row, rr) and np.array_equal(full.nearest_col, cc)
    empty = brushfire(GridMap(Grid(shape, 1.0, border=border), np.zeros(shape, bool)),
                      connectivity=connectivity, metric=metric)
    if border == "open":
        assert (empty.steps == -1).all() and np.isinf(empty.distance).all()
        assert (empty.nearest_row == -1).all() and (empty.nearest_col == -1).all()
        assert (empty.label == 0).all() and not empty.gvd.any()
        x, y = empty.nearest_point()
        assert np.isnan(x).all() and np.isnan(y).all()
        sat = brushfire(GridMap(Grid(shape, 1.0, border=border), np.zeros(shape, bool)), saturate=2.0, far=7.0)
        assert (sat.distance == 7.0).all()  # nothing within the radius: every distance is "far"
    else:
        check_nearest(empty)
        x, _ = empty.nearest_point()
        assert np.isfinite(x).all()


@pytest.mark.parametrize("shape", [(1, 1), (1, 2), (1, 13), (1, 300), (13, 1), (300, 1)])
@pytest.mark.parametrize("border", ["open", "wall"])
def test_single_row_and_column_maps(shape, border):
    for occ in (np.zeros(shape, bool), np.ones(shape, bool), random_occupancy(1, shape, 0.1)):
        if occ.size > 1:
            occ.flat[occ.size // 3] = True
        gm = GridMap(Grid(shape, 1.0, border=border), occ)
        for connectivity, metric in COMBOS:
            dm = brushfire(gm, connectivity=connectivity, metric=metric)
            assert np.array_equal(dm.steps, bfs_steps(occ, border, connectivity))
            if occ.any() or border == "wall":
                np.testing.assert_allclose(dm.distance, brute_distance(occ, border, metric))
                check_nearest(dm)
                check_gvd(dm)


def test_world_units_and_nearest_point():
    occ = np.zeros((3, 4), bool)
    occ[0, 3] = True
    dm = brushfire(GridMap(Grid((3, 4), 0.5, origin=(10.0, -2.0)), occ), metric="euclidean")
    assert dm.distance[2, 0] == pytest.approx(0.5 * math.hypot(2, 3))
    x, y = dm.nearest_point()
    assert np.all(x == 10.0 + 3.5 * 0.5) and np.all(y == -2.0 + 0.5 * 0.5)
    assert dm.grid is dm.map.grid


def test_occupancy_of_any_layout_and_dtype():
    occ = random_occupancy(11, (40, 30), 0.1)
    ref = brushfire(GridMap(Grid((30, 40), 1.0), np.ascontiguousarray(occ.T)))
    for variant in (occ.T, np.asfortranarray(occ.T), occ.T.astype(np.uint8), occ.T.astype(np.int64)):
        dm = brushfire(GridMap(Grid((30, 40), 1.0), variant))
        for name in ("steps", "distance", "nearest_row", "nearest_col", "label", "gvd"):
            assert np.array_equal(getattr(dm, name), getattr(ref, name)), name
    with pytest.raises(TypeError, match="dtype float64"):  # issue 17: only booleans or the integers 0/1
        GridMap(Grid((30, 40), 1.0), occ.T.astype(float))


# ----------------------------------------------------------------------------------------------
# options
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("combo", COMBOS)
def test_optional_outputs_and_threads_give_the_same_arrays(combo):
    connectivity, metric = combo
    occ = random_occupancy(5, (70, 130), 0.1)
    gm = GridMap(Grid(occ.shape, 0.1, border="wall"), occ)
    full = brushfire(gm, connectivity=connectivity, metric=metric)
    one = brushfire(gm, connectivity=connectivity, metric=metric, threads=1)
    variants = {
        "nearest only": dict(compute_labels=False),
        "labels only": dict(compute_nearest=False, compute_gvd=False),
        "labels and gvd": dict(compute_nearest=False),
        "distance only": dict(compute_nearest=False, compute_labels=False),
        "no gvd": dict(compute_gvd=False),
        "no steps": dict(compute_steps=False),
        "distance and nearest, no steps (what a potential reads)": dict(compute_steps=False, compute_labels=False),
        "distance only, no steps": dict(compute_steps=False, compute_nearest=False, compute_labels=False),
    }
    for name in ("steps", "distance", "nearest_row", "nearest_col", "label", "gvd"):
        assert np.array_equal(getattr(one, name), getattr(full, name)), name
    for what, kw in variants.items():
        dm = brushfire(gm, connectivity=connectivity, metric=metric, **kw)
        assert np.array_equal(dm.distance, full.distance), what
        if kw.get("compute_steps", True):
            assert np.array_equal(dm.steps, full.steps), what
        else:
            assert dm.steps is None, what
        for name, wanted in (("nearest_row", kw.get("compute_nearest", True)),
                             ("label", kw.get("compute_labels", True)),
                             ("gvd", kw.get("compute_gvd", kw.get("compute_labels", True)))):
            value = getattr(dm, name)
            assert (value is None) != wanted, (what, name)
            if wanted:
                assert np.array_equal(value, getattr(full, name)), (what, name)


def test_nearest_point_needs_the_nearest_obstacle():
    dm = brushfire(GridMap(Grid((2, 2), 1.0), np.eye(2, dtype=bool)), compute_nearest=False)
    with pytest.raises(GridfieldError, match="compute_nearest=False"):
        dm.nearest_point()


@pytest.mark.parametrize(("kw", "match"), [
    (dict(connectivity=6), "connectivity must be 4 or 8, got 6"),
    (dict(connectivity=True), "connectivity must be 4 or 8"),
    (dict(metric="manhattan"), "metric must be one of .*'manhattan'"),
    (dict(saturate=0), "saturate must be a positive finite distance, got 0"),
    (dict(saturate=math.inf), "saturate must be a positive finite distance"),
    (dict(saturate="x"), "saturate must be a positive finite distance"),
    (dict(far="near"), "far must be a number"),
    (dict(threads=0), "threads must be a positive integer"),
    (dict(threads=1.5), "threads must be a positive integer"),
    (dict(compute_nearest="yes"), "compute_nearest must be True or False"),
    (dict(compute_steps=None), "compute_steps must be True or False"),
    (dict(compute_labels=False, compute_gvd=True), "compute_gvd=True needs the labels"),
])
def test_bad_parameters_are_named(kw, match):
    with pytest.raises(ParameterError, match=match):
        brushfire(GridMap(Grid((2, 2), 1.0), np.eye(2, dtype=bool)), **kw)


def test_threads_above_the_maximum_are_clipped_and_large_grids_use_them():
    occ = random_occupancy(2, (1024, 1100), 0.1)  # above PARALLEL_MIN_CELLS: all cores by default
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    ref = brushfire(gm, threads=1, metric="euclidean")
    for threads in (None, 2, 10_000):
        dm = brushfire(gm, threads=threads, metric="euclidean")
        for name in ("steps", "distance", "nearest_row", "nearest_col", "label", "gvd"):
            assert np.array_equal(getattr(dm, name), getattr(ref, name)), name


def test_packed_nearest_index_in_int64_as_for_huge_grids():
    """Grids of 2**31 padded cells or more carry the nearest cell in int64: same kernel, other dtype."""
    from gridfield.distance import _chamfer as k

    occ = random_occupancy(4, (25, 90), 0.05)
    o8 = occ.view(np.uint8)
    out = {}
    for dtype in (np.int32, np.int64):
        steps, nidx, dist = np.empty(occ.shape, np.int32), np.empty(occ.shape, dtype), np.empty(occ.shape)
        k.chamfer_nearest(o8, True, True, True, 0, True, steps, nidx, dist, 1.0, True)
        rows_, cols_ = np.empty(occ.shape, np.int32), np.empty(occ.shape, np.int32)
        k.decode_rows(0, occ.shape[0], nidx, rows_, cols_)
        out[dtype] = (steps, rows_, cols_)
    ref = brushfire(GridMap(Grid(occ.shape, 1.0, border="wall"), occ))
    for a, b, name in zip(out[np.int32], out[np.int64], ("steps", "nearest_row", "nearest_col"), strict=True):
        assert np.array_equal(a, b) and np.array_equal(a, getattr(ref, name))


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 90), cols=st.integers(1, 70),
       density=st.sampled_from([0.003, 0.02, 0.1, 0.4]), border=st.sampled_from(["open", "wall"]),
       strip=st.integers(2, 12), margin=st.integers(1, 8))
def test_chamfer_in_strips_is_exact_and_thread_independent(seed, rows, cols, density, border, strip, margin):
    """Large grids run the chamfer passes in strips on windows with margins (here made tiny so that
    small grids use them, and sparse ones fall back to one pass): same values as scipy, exact nearest
    obstacles, and the same arrays with 1 or 2 threads."""
    import gridfield.distance.brushfire as bf

    occ = random_occupancy(seed, (rows, cols), density)
    if not occ.any() and border == "open":
        return
    gm = GridMap(Grid(occ.shape, 1.0, border=border), occ)
    for connectivity, metric in ((8, "chessboard"), (4, "taxicab"), (8, "taxicab"), (8, "euclidean")):
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(bf, "STRIP_ROWS", strip)
            mp.setattr(bf, "MARGIN", margin)
            one, two = (brushfire(gm, connectivity=connectivity, metric=metric, threads=t) for t in (1, 2))
        assert np.array_equal(one.steps, scipy_reference(occ, border, "chessboard" if connectivity == 8 else "taxicab"))
        np.testing.assert_allclose(one.distance, scipy_reference(occ, border, metric), rtol=1e-12)
        check_nearest(one)
        for name in ("steps", "distance", "nearest_row", "nearest_col", "label", "gvd"):
            assert np.array_equal(getattr(one, name), getattr(two, name)), name


def test_import_gridfield_does_not_load_numba_kernels():
    import subprocess
    import sys

    code = "import sys, gridfield, gridfield.distance.brushfire; print('numba' in sys.modules, " \
           "any('gridfield.distance.' + m in sys.modules for m in ('_brushfire', '_chamfer', '_edt')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO)
    assert out.stdout.split() == ["False", "False"]


# ----------------------------------------------------------------------------------------------
# command line
# ----------------------------------------------------------------------------------------------
def _write_pgm(path: Path, occ: np.ndarray) -> None:
    from PIL import Image

    Image.fromarray(np.where(occ[::-1], 0, 254).astype(np.uint8)).save(path)


def test_cli_on_a_pgm(tmp_path, capsys):
    from gridfield.cli import main

    occ = np.zeros((30, 50), bool)
    occ[10:14, 5:9] = occ[20, 30:45] = True
    pgm = tmp_path / "room.pgm"
    _write_pgm(pgm, occ)
    npz, png = tmp_path / "out.npz", tmp_path / "out.png"
    rc = main(["brushfire", str(pgm), "--connectivity", "4", "--metric", "euclidean", "--saturate", "6",
               "--resolution", "0.5", "--npz", str(npz), "--plot", str(png)])
    assert rc == 0
    out = capsys.readouterr().out
    assert "brushfire 30x50 cells of 0.5" in out and "euclidean distance" in out and "GVD cells" in out
    assert "2 obstacle labels" in out and "ms" in out
    with np.load(npz) as z:
        assert {"occupied", "steps", "distance", "label", "gvd", "resolution", "origin", "border"} <= set(z.files)
        assert np.array_equal(z["occupied"], occ)
        gm = GridMap(Grid(occ.shape, 0.5, border=str(z["border"])), occ)
        ref = brushfire(gm, connectivity=4, metric="euclidean", saturate=6)
        assert np.array_equal(z["steps"], ref.steps) and np.array_equal(z["distance"], ref.distance)
        assert np.array_equal(z["gvd"], ref.gvd) and float(z["resolution"]) == 0.5
    assert png.stat().st_size > 1000


def test_cli_on_the_bundled_arena_map(tmp_path, capsys):
    from gridfield.cli import main

    assert main(["brushfire", str(REPO / "maps/arena/arena.map"), "--npz", str(tmp_path / "a.npz")]) == 0
    out = capsys.readouterr().out
    assert "brushfire 49x49 cells of 1 (8-connected steps, chessboard distance, wall border)" in out
    with np.load(tmp_path / "a.npz") as z:
        occ = z["occupied"]
        assert np.array_equal(z["steps"], scipy_reference(occ, "wall", "chessboard"))


def test_cli_rasterizes_a_world(capsys):
    from gridfield.cli import main

    assert main(["brushfire", str(REPO / "maps/seed000.yaml"), "--resolution", "0.25", "--metric", "taxicab"]) == 0
    out = capsys.readouterr().out
    assert "cells of 0.25" in out and "taxicab distance" in out and "3 obstacle labels" in out


@pytest.mark.parametrize(("argv", "message"), [
    (["brushfire", "no/such/map.pgm"], "no such file"),
    (["brushfire", "MAP", "--npz", "no/such/dir/out.npz"], "does not exist"),
    (["brushfire", "MAP", "--resolution", "0.5"], "resampling a grid is not supported"),
])
def test_cli_errors_are_one_line_exit_2(argv, message, capsys):
    from gridfield.cli import main

    argv = [str(REPO / "maps/arena/arena.map") if a == "MAP" else a for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err and err.startswith("gridfield brushfire: error:")


def test_cli_rejects_a_bad_saturation_radius(capsys):
    from gridfield.cli import main

    assert main(["brushfire", str(REPO / "maps/arena/arena.map"), "--saturate", "-1"]) == 2
    assert "--saturate: expected a positive finite number" in capsys.readouterr().err


def test_result_memory_is_reused_and_released():
    """The grid-sized arrays reuse a freed result's block; what the block held does not leak into the
    next result (checked against scipy); pool_limit(0) unmaps every kept block."""
    import gridfield.distance.brushfire as gb

    k = gb._kernel_brushfire()
    old = k.pool_limit()
    try:
        k.pool_limit(0)  # an empty pool to start from: blocks earlier tests of this process left are gone
        k.pool_limit(old)
        assert k.pool_bytes() == (0, 0)
        a = k.empty((700, 700), np.float64)  # 3.9 MB: pooled
        ptr = a.__array_interface__["data"][0]
        a[:] = -7.0
        del a
        b = k.empty((700, 700), np.float64)
        assert b.__array_interface__["data"][0] == ptr
        assert not b.flags.owndata and b.flags.c_contiguous and b.flags.writeable
        del b
        rng = np.random.default_rng(5)
        for p in (0.3, 0.01):  # the second map's results land in the first one's blocks
            occ = rng.random((700, 700)) < p
            d = brushfire(GridMap(Grid(occ.shape, 1.0), occ), metric="euclidean", compute_labels=False)
            np.testing.assert_array_equal(d.distance, ndimage.distance_transform_edt(~occ))
            c = brushfire(GridMap(Grid(occ.shape, 1.0), occ), compute_nearest=False, compute_labels=False)
            np.testing.assert_array_equal(c.steps, ndimage.distance_transform_cdt(~occ, metric="chessboard"))
            del d, c
        assert k.pool_bytes()[1] > 0
        k.pool_limit(0)
        assert k.pool_bytes() == (0, 0)
    finally:
        k.pool_limit(old)
