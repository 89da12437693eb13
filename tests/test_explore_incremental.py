"""The explorer's incremental hook: a drawn obstacle is rasterized alone and the brushfire is an
:class:`gridfield.distance.incremental.IncrementalBrushfire` updated where the map changed (draw, remove,
undo, clear); checked against an independent re-rasterization (``as_gridmap``) and a full
``brushfire`` of the resulting map, with the full brushfire patched to count its calls."""

from __future__ import annotations

import os

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.backend_bases import KeyEvent, MouseEvent
from shapely.geometry import Point, Polygon, box

import gridfield.distance.incremental as incremental
import gridfield.fields.potential as potential
from gridfield.core.errors import ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.distance.brushfire import brushfire
from gridfield.explore import Explorer
from gridfield.fields.potential import build_field
from gridfield.geometry.rasterize import as_gridmap
from gridfield.io import bundled_map, read_world

RES = 0.25


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture
def ex():
    e = Explorer(read_world(bundled_map("seed000.yaml")), resolution=RES)
    yield e
    e.close()


@pytest.fixture
def calls(monkeypatch):
    """Every full brushfire run from now on (the field's, the planner's, a new IncrementalBrushfire's)."""
    out: list[str] = []
    for mod in (potential, incremental):
        real = mod.brushfire
        monkeypatch.setattr(mod, "brushfire", lambda *a, _r=real, _m=mod.__name__, **k: out.append(_m) or _r(*a, **k))
    return out


def _same_as_full(ex, truth):
    """The explorer's map equals ``truth`` (an independent rasterization) and its field's distance
    map equals a full brushfire of it, nearest obstacle cells included."""
    np.testing.assert_array_equal(ex.gridmap.occupied, truth.occupied)
    if truth.obstacle_id is not None:
        np.testing.assert_array_equal(ex.gridmap.obstacle_id, truth.obstacle_id)
    full = brushfire(truth, metric="euclidean")
    d = ex.field.distance
    np.testing.assert_array_equal(d.distance, full.distance)
    np.testing.assert_array_equal(d.nearest_row, full.nearest_row)
    np.testing.assert_array_equal(d.nearest_col, full.nearest_col)
    np.testing.assert_array_equal(ex.field.potential, build_field(truth, ex.goal, ex.params).potential)


def _key(ex, key):
    ex.figure.canvas.callbacks.process("key_press_event", KeyEvent("key_press_event", ex.figure.canvas, key))


def _click(ex, x, y, button=1):
    px, py = ex.ax.transData.transform((x, y))
    ex.figure.canvas.callbacks.process("button_press_event",
                                       MouseEvent("button_press_event", ex.figure.canvas, px, py, button))


def test_drawing_an_obstacle_and_undo_run_no_full_brushfire(ex, calls):
    loaded = as_gridmap(read_world(bundled_map("seed000.yaml")), RES)
    n = len(ex.world.obstacles)
    _key(ex, "d")  # draw obstacle with the mouse, as a user does
    for x, y in [(14, 2), (17, 2), (17, 5), (14, 5)]:
        _click(ex, x, y)
    _click(ex, 15, 3, button=3)
    assert len(ex.world.obstacles) == n + 1
    assert ex.gridmap.world is ex.world
    _same_as_full(ex, as_gridmap(ex.world, RES))  # what the explorer computed before the hook
    assert ex.field.distance is ex._incremental.distance_map
    assert ex.path is not None and ex.path.status == "reached"
    assert ex.path.params["zeta"] == ex.field.params["zeta"]
    calls.clear()  # _same_as_full ran build_field without dmap
    _key(ex, "u")  # undo: the obstacle goes, freed incrementally
    assert len(ex.world.obstacles) == n
    assert not calls
    _same_as_full(ex, loaded)
    calls.clear()
    ex.add_polygon([(14, 2), (17, 2), (17, 5), (14, 5)])
    ex.clear()  # back to the loaded map: incremental too
    assert not calls
    _same_as_full(ex, loaded)


def test_the_planner_reuses_the_incremental_brushfire(ex, calls):
    ex.add_polygon([(14, 2), (17, 2), (17, 5), (14, 5)])
    assert not calls
    ex.set_planner("wavefront-octile")
    ex.set_planner("potential")
    assert not calls
    assert ex.path is not None and ex.path.status == "reached"
    again = Explorer(ex.world, resolution=RES)  # the same world, planned from scratch
    try:
        np.testing.assert_allclose(again.path.points, ex.path.points)
    finally:
        again.close()


def test_removing_an_overlapped_obstacle_hands_its_cells_to_the_other(ex, calls):
    ex.add_polygon([(14, 2), (17, 2), (17, 5), (14, 5)])
    ex.add_polygon([(16, 3), (19, 3), (19, 6), (16, 6)])  # overlaps the first: the lower id wins there
    first = max(o.id for o in ex.world.obstacles) - 1
    both = as_gridmap(ex.world, RES)
    assert (both.obstacle_id == first).sum() > 0
    calls.clear()
    ex.remove_obstacle(first)  # its cells under the second polygon now belong to the second
    assert not calls
    assert all(o.id != first for o in ex.world.obstacles)
    _same_as_full(ex, as_gridmap(ex.world, RES))
    calls.clear()
    ex.undo()
    assert not calls
    _same_as_full(ex, both)
    with pytest.raises(ParameterError, match="no obstacle 999"):
        ex.remove_obstacle(999)
    assert ex.remove_last_obstacle()
    _same_as_full(ex, as_gridmap(ex.world, RES))


def test_a_random_sequence_of_draws_removals_and_undos():
    world = read_world(bundled_map("seed000.yaml"))
    ex = Explorer(world, resolution=0.5)
    rng = np.random.default_rng(20)
    xmin, ymin, xmax, ymax = world.bounds
    try:
        seen = set()
        for _ in range(12):
            op = rng.choice(["draw", "draw", "remove", "undo"])
            if op == "draw":
                c = rng.uniform((xmin + 2, ymin + 2), (xmax - 2, ymax - 2))
                h = rng.uniform(0.3, 2.0, 2)
                box = c + h * np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]])
                if min(Polygon(box).distance(Point(p)) for p in (ex.start, ex.goal)) < 1.0:
                    continue  # keep start and goal free
                ex.add_polygon(box)
            elif op == "remove":
                ids = sorted(o.id for o in ex.world.obstacles)
                ex.remove_obstacle(int(rng.choice(ids)))
            else:
                ex.undo()
            seen.add(op)
            _same_as_full(ex, as_gridmap(ex.world, 0.5))
        assert seen == {"draw", "remove", "undo"}
    finally:
        ex.close()


def test_a_grid_map_without_a_world_is_burnt_and_undone_incrementally(calls):
    occ = np.zeros((40, 60), bool)
    occ[10:30, 20:24] = True
    gm = GridMap(Grid((40, 60), 0.5), occ)
    # the classic field (model khatib) is the one the incremental brushfire serves; a map without
    # params would get the potential planner's default, nf1
    ex = Explorer(gm, params={"model": "khatib"}, start=(2.0, 2.0), goal=(28.0, 18.0))
    try:
        calls.clear()
        ex.add_polygon([(15, 5), (18, 5), (18, 9), (15, 9)])
        assert not calls
        from gridfield.geometry.rasterize import rasterize_geometry

        truth = GridMap(gm.grid, occ | rasterize_geometry(box(15, 5, 18, 9), gm.grid))
        _same_as_full(ex, truth)
        calls.clear()
        ex.undo()
        assert not calls
        _same_as_full(ex, gm)
    finally:
        ex.close()


def test_cspace_rasterizes_in_full_but_keeps_the_brushfire_incremental(ex, calls):
    ex.set_robot(0.3)
    assert ex.compute_cspace()
    calls.clear()
    ex.add_polygon([(14, 2), (17, 2), (17, 5), (14, 5)])
    assert not calls  # the C-space is re-rasterized, its brushfire updated where it changed
    from gridfield.geometry.cspace import apply_robot

    truth = as_gridmap(apply_robot(ex.world, ex.robot), RES)
    np.testing.assert_array_equal(ex.cgridmap.occupied, truth.occupied)
    full = brushfire(truth, metric="euclidean")
    np.testing.assert_array_equal(ex.field.distance.distance, full.distance)
    np.testing.assert_array_equal(ex.field.potential, build_field(truth, ex.goal, ex.params).potential)
    assert ex.path is not None and ex.path.status == "reached"


def test_saturated_or_other_metrics_fall_back_to_the_full_brushfire(ex, calls):
    ex.set_param("saturate", 1.0)
    calls.clear()
    ex.add_polygon([(14, 2), (17, 2), (17, 5), (14, 5)])
    assert "gridfield.fields.potential" in calls  # no incremental saturated map: the full one
    full = potential.field_distance_map(ex.gridmap, ex.params)
    np.testing.assert_array_equal(ex.field.distance.distance, full.distance)
    ex.set_param("saturate", None)
    ex.set_param("metric", "taxicab")
    assert ex.field.distance.metric == "taxicab"
    np.testing.assert_array_equal(ex.field.distance.distance, brushfire(ex.gridmap, metric="taxicab",
                                                                         connectivity=4).distance)
