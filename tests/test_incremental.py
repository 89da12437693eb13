"""Tests of gridfield.distance.incremental: the distance map and the potential field updated where the map changed.

The reference is a full :func:`gridfield.distance.brushfire.brushfire` (and :func:`build_field`) of the new
occupancy after every update, plus a brute-force nearest obstacle written here (the tie rule the
window updates rely on). Random sequences of insertions and removals (hypothesis) on random maps with
both borders, with and without world obstacle ids.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.distance.brushfire import brushfire
from gridfield.distance.incremental import IncrementalBrushfire
from gridfield.fields.incremental import update_field, update_navigation
from gridfield.fields.potential import build_field


def brute_nearest(occ: np.ndarray, border: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nearest obstacle cell by brute force: smallest squared distance, then column, then row; the wall
    ring (no corners) counts as obstacles. Returns rows, cols, squared distances (-1/-1/-1: none)."""
    rows, cols = occ.shape
    sites = [(int(r), int(c)) for r, c in zip(*np.nonzero(occ), strict=True)]
    if border == "wall":
        sites += [(-1, c) for c in range(cols)] + [(rows, c) for c in range(cols)]
        sites += [(r, -1) for r in range(rows)] + [(r, cols) for r in range(rows)]
    nr, nc, d2 = (np.full((rows, cols), -1) for _ in range(3))
    if not sites:
        return nr, nc, d2
    s = np.array(sites)
    rr, cc = np.mgrid[0:rows, 0:cols]
    dist2 = (rr[..., None] - s[:, 0]) ** 2 + (cc[..., None] - s[:, 1]) ** 2  # rows x cols x sites
    # lexicographic (d2, col, row): one combined integer key
    big = rows + cols + 4
    key = (dist2 * big + (s[:, 1] + 1)) * big + (s[:, 0] + 1)
    k = key.argmin(axis=-1)
    return s[k, 0], s[k, 1], np.take_along_axis(dist2, k[..., None], -1)[..., 0]


def assert_equal_full(ib: IncrementalBrushfire) -> None:
    d = ib.distance_map
    f = brushfire(ib.gridmap, metric="euclidean", compute_steps=False,
                  compute_labels=ib._want_label, compute_gvd=ib._want_gvd)
    np.testing.assert_array_equal(d.distance, f.distance)  # exactly the same floats
    np.testing.assert_array_equal(d.nearest_row, f.nearest_row)  # the same cell, ties included
    np.testing.assert_array_equal(d.nearest_col, f.nearest_col)
    if ib._want_label:
        np.testing.assert_array_equal(d.label, f.label)
    if ib._want_gvd:
        np.testing.assert_array_equal(d.gvd, f.gvd)
    assert d.steps is None and d.metric == "euclidean"


# ----------------------------------------------------------------------------------------------
# the tie rule the windows rely on: the full transform's nearest obstacle is the lexicographic one
# ----------------------------------------------------------------------------------------------
@settings(max_examples=60, deadline=None)
@given(st.integers(1, 14), st.integers(1, 14), st.sampled_from([0.03, 0.1, 0.3]), st.sampled_from(["open", "wall"]),
       st.integers(0, 2**31))
def test_full_transform_nearest_is_the_lexicographic_one(rows, cols, density, border, seed):
    occ = np.random.default_rng(seed).random((rows, cols)) < density
    d = brushfire(GridMap(Grid((rows, cols), 1.0, border=border), occ), metric="euclidean")
    nr, nc, d2 = brute_nearest(occ, border)
    if border == "open" and not occ.any():
        assert (d.nearest_row == -1).all() and np.isinf(d.distance).all()
        return
    np.testing.assert_array_equal(d.nearest_row, nr)
    np.testing.assert_array_equal(d.nearest_col, nc)
    np.testing.assert_array_equal(d.distance, np.sqrt(d2.astype(float)))


# ----------------------------------------------------------------------------------------------
# random sequences of insertions and removals
# ----------------------------------------------------------------------------------------------
@st.composite
def changes(draw, rows, cols):
    """One update: a block, scattered cells or a mask; occupied, freed or both."""
    kind = draw(st.sampled_from(["occupy", "free", "both"]))
    shape = draw(st.sampled_from(["block", "cells", "mask"]))
    if shape == "block":
        r0, c0 = draw(st.integers(0, rows - 1)), draw(st.integers(0, cols - 1))
        h, w = draw(st.integers(1, 6)), draw(st.integers(1, 6))
        cells = np.array([(r, c) for r in range(r0, min(rows, r0 + h)) for c in range(c0, min(cols, c0 + w))])
    elif shape == "cells":
        n = draw(st.integers(1, 8))
        cells = np.array(draw(st.lists(st.tuples(st.integers(0, rows - 1), st.integers(0, cols - 1)),
                                       min_size=n, max_size=n)))
    else:
        seed = draw(st.integers(0, 2**31))
        mask = np.random.default_rng(seed).random((rows, cols)) < draw(st.sampled_from([0.02, 0.1, 0.3]))
        cells = np.argwhere(mask)
    if kind == "occupy":
        return cells, None
    if kind == "free":
        return None, cells
    half = len(cells) // 2
    return cells[:half], cells[half:]


@st.composite
def scenarios(draw):
    rows, cols = draw(st.integers(1, 24)), draw(st.integers(1, 24))
    border = draw(st.sampled_from(["open", "wall"]))
    density = draw(st.sampled_from([0.0, 0.01, 0.05, 0.2, 0.5]))
    seed = draw(st.integers(0, 2**31))
    rng = np.random.default_rng(seed)
    occ = rng.random((rows, cols)) < density
    ids = None
    if draw(st.booleans()):  # world obstacle ids (a few obstacles, not components)
        ids = np.where(occ, rng.integers(1, 5, (rows, cols)), 0).astype(np.int32)
    steps = draw(st.lists(changes(rows, cols), min_size=1, max_size=6))
    return GridMap(Grid((rows, cols), draw(st.sampled_from([1.0, 0.05, 0.3])), border=border), occ, ids), steps


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(scenarios(), st.booleans())
def test_updates_equal_a_full_recompute(scenario, as_mask):
    gridmap, steps = scenario
    ib = IncrementalBrushfire(gridmap)
    assert_equal_full(ib)
    for occupied, freed in steps:
        before_occ = ib.gridmap.occupied.copy()
        before = [a.copy() for a in (ib._dist, ib._nr, ib._nc)]
        if as_mask:  # the same change as boolean masks
            def mask(cells):
                if cells is None:
                    return None
                m = np.zeros(gridmap.shape, bool)
                m[tuple(np.asarray(cells).reshape(-1, 2).T)] = True
                return m
            occupied, freed = mask(occupied), mask(freed)
        if occupied is not None and freed is not None:  # a cell may not be in both
            occ_set = {tuple(x) for x in np.argwhere(occupied)} if as_mask else {tuple(x) for x in occupied}
            fr = np.argwhere(freed) if as_mask else freed
            fr = np.array([x for x in fr if tuple(x) not in occ_set]).reshape(-1, 2)
            freed = fr if not as_mask else (mask(fr) if len(fr) else None)
        window = ib.update(occupied=occupied, freed=freed)
        assert_equal_full(ib)
        # the window holds every cell that changed, and nothing changed when it is None
        changed = ib.gridmap.occupied != before_occ
        for old, new in zip(before, (ib._dist, ib._nr, ib._nc), strict=True):
            changed |= old != new
        if window is None:
            assert not changed.any()
        else:
            r0, r1, c0, c1 = window
            inside = np.zeros_like(changed)
            inside[r0:r1, c0:c1] = True
            assert not (changed & ~inside).any()
            assert changed.any()


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 30), st.integers(2, 30), st.sampled_from([0.1, 0.3, 0.5]), st.sampled_from(["open", "wall"]),
       st.integers(0, 2**31))
def test_components_grown_and_shrunk_keep_the_full_numbering(rows, cols, density, border, seed):
    """Obstacles of a map without ids grow and shrink by a few cells at a time: most such changes keep
    every component's number (updated in place), the others renumber (relabelled on read); either
    way labels and GVD equal the full brushfire's after every step."""
    rng = np.random.default_rng(seed)
    occ = rng.random((rows, cols)) < density
    ib = IncrementalBrushfire(GridMap(Grid((rows, cols), 1.0, border=border), occ))
    for _ in range(8):
        grow = rng.random() < 0.5
        cand = np.argwhere(~ib.gridmap.occupied if grow else ib.gridmap.occupied)
        if not len(cand):
            continue
        cells = cand[rng.integers(0, len(cand), rng.integers(1, 4))]
        ib.update(occupied=cells) if grow else ib.update(freed=cells)
        assert_equal_full(ib)


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 30), st.integers(2, 30), st.sampled_from(["open", "wall"]), st.integers(0, 2**31))
def test_against_brute_force_without_labels(rows, cols, border, seed):
    """Independent of the full transform: the brute-force nearest obstacle after every update."""
    rng = np.random.default_rng(seed)
    occ = rng.random((rows, cols)) < 0.05
    ib = IncrementalBrushfire(GridMap(Grid((rows, cols), 1.0, border=border), occ), compute_labels=False)
    for _ in range(4):
        cells = np.stack([rng.integers(0, rows, 3), rng.integers(0, cols, 3)], 1)
        if rng.random() < 0.5:
            ib.update(occupied=cells)
        else:
            ib.update(freed=np.argwhere(ib.gridmap.occupied)[: rng.integers(0, 6)])
        nr, nc, d2 = brute_nearest(ib.gridmap.occupied, border)
        d = ib.distance_map
        assert d.label is None and d.gvd is None
        np.testing.assert_array_equal(d.nearest_row, nr)
        np.testing.assert_array_equal(d.nearest_col, nc)
        expect = np.where(d2 < 0, np.inf, np.sqrt(np.maximum(d2, 0).astype(float)))
        np.testing.assert_array_equal(d.distance, expect)


def test_moving_obstacle_on_a_larger_map():
    """A block walking across a cluttered 160 x 200 map (large and small windows, merges and splits of
    components), compared with a full recompute after every step."""
    rng = np.random.default_rng(7)
    occ = rng.random((160, 200)) < 0.004
    occ[40:44, 20:180] = True  # a long wall the block touches and leaves
    ib = IncrementalBrushfire(GridMap(Grid((160, 200), 0.1, border="wall"), occ))
    prev = None
    for step in range(12):
        r, c = 30 + 2 * step, 10 + 15 * step
        cells = np.array([(a, b) for a in range(r, r + 6) for b in range(c, c + 6)])
        ib.update(occupied=cells, freed=prev)
        assert_equal_full(ib)
        prev = np.array([x for x in cells if not occ[tuple(x)]])
    ib.update(freed=np.argwhere(ib.gridmap.occupied))  # everything removed: only the wall is left
    assert_equal_full(ib)


def test_emptying_an_open_map_and_filling_it_again():
    occ = np.zeros((5, 6), bool)
    occ[2, 3] = True
    ib = IncrementalBrushfire(GridMap(Grid((5, 6), 1.0), occ))
    ib.update(freed=[[2, 3]])
    d = ib.distance_map
    assert np.isinf(d.distance).all() and (d.nearest_row == -1).all() and (d.label == 0).all() and not d.gvd.any()
    assert_equal_full(ib)
    ib.update(occupied=[[0, 0], [4, 5]])
    assert_equal_full(ib)
    assert ib.update(occupied=[[0, 0]]) is None  # already occupied: nothing changes
    assert ib.update(freed=[[1, 1]]) is None


def test_world_ids_of_new_cells():
    occ = np.zeros((4, 9), bool)
    occ[:, 0] = True
    ids = np.where(occ, 3, 0).astype(np.int32)
    ib = IncrementalBrushfire(GridMap(Grid((4, 9), 1.0), occ, ids))
    ib.update(occupied=[[1, 8], [2, 8]])  # default: a new id, the largest plus one
    assert ib.gridmap.obstacle_id[1, 8] == 4 and ib.distance_map.label[1, 7] == 4
    ib.update(occupied=[[3, 8], [0, 8]], ids=[7, 9])  # one per cell, in the order given
    assert ib.gridmap.obstacle_id[3, 8] == 7 and ib.gridmap.obstacle_id[0, 8] == 9
    assert_equal_full(ib)
    ib.update(freed=[[1, 8]])
    assert ib.gridmap.obstacle_id[1, 8] == 0
    assert_equal_full(ib)


def test_importable_from_its_layer_and_the_top_and_errors():
    import gridfield
    import gridfield.distance
    import gridfield.distance.brushfire as bf

    # the deprecated alias bf.IncrementalBrushfire is gone (CHANGELOG): brushfire never reaches incremental
    assert not hasattr(bf, "IncrementalBrushfire")
    assert gridfield.IncrementalBrushfire is gridfield.distance.IncrementalBrushfire is IncrementalBrushfire
    gm = GridMap(Grid((3, 3), 1.0), np.zeros((3, 3), bool))
    with pytest.raises(ParameterError, match="euclidean"):
        IncrementalBrushfire(gm, metric="chessboard")
    with pytest.raises(ParameterError, match="compute_gvd"):
        IncrementalBrushfire(gm, compute_labels=False, compute_gvd=True)
    ib = IncrementalBrushfire(gm)
    with pytest.raises(ParameterError, match=r"cell \(3, 0\) lies outside"):
        ib.update(occupied=[[3, 0]])
    with pytest.raises(ParameterError, match="shape"):
        ib.update(occupied=np.zeros((2, 2), bool))
    with pytest.raises(ParameterError, match="integer cells"):
        ib.update(occupied=[[0.5, 1.0]])
    with pytest.raises(ParameterError, match=r"\(1, 1\) is both"):
        ib.update(occupied=[[1, 1]], freed=[[1, 1]])
    with pytest.raises(ParameterError, match="ids are only"):
        ib.update(occupied=[[1, 1]], ids=3)
    with pytest.raises(AttributeError):
        bf.NoSuchThing  # noqa: B018


# ----------------------------------------------------------------------------------------------
# fields follow
# ----------------------------------------------------------------------------------------------
@settings(max_examples=25, deadline=None)
@given(st.integers(4, 30), st.integers(4, 30), st.sampled_from(["open", "wall"]), st.integers(0, 2**31),
       st.sampled_from([{"q_star": 2.0}, {"q_star": 0.7, "repulsive_power": 3, "eta": 2.0},
                        {"d_star": 1.0, "zeta": 0.3, "saturate": 0.9}, {"d_star": 0.0, "repulsive_power": 1}]))
def test_update_field_equals_a_full_build(rows, cols, border, seed, params):
    rng = np.random.default_rng(seed)
    occ = rng.random((rows, cols)) < 0.1
    occ[0, 0] = False
    ib = IncrementalBrushfire(GridMap(Grid((rows, cols), 0.5, border=border), occ), compute_labels=False)
    goal = (0.25, 0.25)
    field = build_field(ib.gridmap, goal, params, dmap=ib.distance_map)
    for _ in range(3):
        cells = np.stack([rng.integers(0, rows, 4), rng.integers(0, cols, 4)], 1)
        cells = cells[(cells[:, 0] > 0) | (cells[:, 1] > 0)]  # never the goal cell
        window = ib.update(occupied=cells) if rng.random() < 0.6 else ib.update(freed=cells)
        field = update_field(field, ib, window)
        full = build_field(ib.gridmap, goal, params)
        for name in ("potential", "grad_x", "grad_y"):
            np.testing.assert_array_equal(getattr(field, name), getattr(full, name))
        assert field.map is ib.gridmap and field.distance is ib.distance_map


def test_update_field_refuses_what_it_cannot_reproduce():
    occ = np.zeros((5, 5), bool)
    occ[2, 2] = True
    ib = IncrementalBrushfire(GridMap(Grid((5, 5), 1.0), occ))
    f = build_field(ib.gridmap, (0.5, 0.5), {"repulsion": "sum"}, dmap=ib.distance_map)
    with pytest.raises(ParameterError, match="repulsion='nearest'"):
        update_field(f, ib, (0, 1, 0, 1))
    f = build_field(ib.gridmap, (0.5, 0.5), dmap=ib.distance_map)
    with pytest.raises(ParameterError, match="does not lie in the grid"):
        update_field(f, ib, (0, 9, 0, 1))
    with pytest.raises(ParameterError, match="needs a Field"):
        update_field("field", ib, None)
    with pytest.raises(GridfieldError, match=r"goal .* inside an obstacle"):
        update_field(f, ib, ib.update(occupied=[[0, 0]]))


def test_demo_moving_obstacle_replans_to_the_goal(tmp_path):
    from PIL import Image

    from gridfield.demo import demo

    result = demo(tmp_path, quick=True, parts=["moving"])
    (row,) = result.rows
    assert row["part"] == "moving" and row["status"] == "reached" and row["length"] > 20.0
    gif = tmp_path / "moving_obstacle.gif"
    assert gif in result.files
    with Image.open(gif) as im:
        assert im.n_frames == row["steps"] >= 10


# ----------------------------------------------------------------------------------------------
# navigation functions follow
# ----------------------------------------------------------------------------------------------
@settings(max_examples=40, deadline=None)
@given(st.integers(3, 24), st.integers(3, 24), st.integers(0, 2**31), st.sampled_from([0.0, 1.5]),
       st.sampled_from(["unit", "octile"]), st.sampled_from([4, 8]))
def test_update_navigation_equals_a_new_wavefront(rows, cols, seed, weight, costs, conn):
    from gridfield.fields.navigation import wavefront

    rng = np.random.default_rng(seed)
    occ = rng.random((rows, cols)) < 0.25
    occ[0, 0] = False
    ib = IncrementalBrushfire(GridMap(Grid((rows, cols), 1.0), occ), compute_labels=False)
    nav = wavefront(ib.gridmap, (0.5, 0.5), connectivity=conn, costs=costs, clearance_weight=weight)
    kept = 0
    for _ in range(4):
        cells = np.stack([rng.integers(0, rows, 2), rng.integers(0, cols, 2)], 1)
        cells = cells[(cells[:, 0] > 0) | (cells[:, 1] > 0)]  # never the goal
        window = ib.update(occupied=cells) if rng.random() < 0.5 else ib.update(freed=cells)
        new = update_navigation(nav, ib.gridmap, window)
        kept += new.value is nav.value
        nav = new
        full = wavefront(ib.gridmap, (0.5, 0.5), connectivity=conn, costs=costs, clearance_weight=weight)
        np.testing.assert_array_equal(nav.value, full.value)
        assert nav.map is ib.gridmap


def test_update_navigation_refuses_other_kinds():
    from gridfield.fields.navigation import harmonic

    gm = GridMap(Grid((6, 6), 1.0), np.zeros((6, 6), bool))
    with pytest.raises(ParameterError, match="wavefront"):
        update_navigation(harmonic(gm, (0.5, 0.5)), gm, None)


def test_benchmark_main_tiny(capsys, tmp_path):
    """benchmarks/incremental.py runs on a tiny map and prints its tables (no timing asserted)."""
    import sys
    from pathlib import Path

    bench = Path(__file__).resolve().parent.parent / "benchmarks"
    sys.path.insert(0, str(bench))
    try:
        import incremental as bench_incremental

        assert bench_incremental.main(["--size", "96", "--blocks", "1", "5", "--placements", "2", "--repeat", "1",
                                       "--plot", str(tmp_path / "p.png")]) == 0
    finally:
        sys.path.remove(str(bench))
    out = capsys.readouterr().out
    assert "| 1x1 |" in out and "| 5x5 |" in out and "labels + GVD" in out and "targets" in out
    assert (tmp_path / "p.png").stat().st_size > 0
