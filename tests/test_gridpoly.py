"""Grid maps as exact polygons (gridfield.geometry.gridpoly) and the exact planners / compare on grid maps."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given
from hypothesis import strategies as st
from scipy import ndimage

from gridfield.compare import batch_compare, collides, convergence_study
from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.gridpoly import block_downsample, grid_world, source_grid
from gridfield.planners import plan


@st.composite
def gridmaps(draw):
    rows, cols = draw(st.integers(1, 12)), draw(st.integers(1, 12))
    occ = np.random.default_rng(draw(st.integers(0, 2**32 - 1))).random((rows, cols)) < draw(
        st.sampled_from([0.1, 0.3, 0.5, 0.8]))
    res = draw(st.sampled_from([1.0, 0.5, 0.25, 0.1]))
    origin = (draw(st.sampled_from([0.0, -3.5, 12.25])), draw(st.sampled_from([0.0, 7.75, -1.0])))
    return GridMap(Grid((rows, cols), res, origin, draw(st.sampled_from(["open", "wall"]))), occ)


@given(gridmaps())
def test_polygons_are_exactly_the_blocked_cells(gm):
    w = grid_world(gm)
    assert w.bounds == gm.grid.bounds and w.border == gm.grid.border and w.resolution == gm.grid.resolution
    polys = [ob.geometry for ob in w.obstacles]
    assert all(p.is_valid for p in polys)
    h = gm.grid.resolution
    assert sum(p.area for p in polys) == pytest.approx(gm.occupied.sum() * h * h, rel=1e-12, abs=1e-12)
    # every cell centre is inside the polygons iff the cell is blocked
    xs, ys = gm.grid.cell_centers()
    X, Y = np.meshgrid(xs, ys)
    union = shapely.union_all(polys) if polys else shapely.GeometryCollection()
    inside = shapely.contains_xy(union, X, Y) if polys else np.zeros(gm.shape, bool)
    assert (inside == gm.occupied).all()
    # one polygon per 4-connected piece: cells touching only at a corner stay apart
    _, n4 = ndimage.label(gm.occupied)
    assert len(polys) == n4
    # two pieces meet at most in points (the corner rule), never along an edge
    for i in range(len(polys)):
        for j in range(i + 1, len(polys)):
            assert shapely.intersection(polys[i], polys[j]).length == 0.0


@given(gridmaps(), st.integers(1, 5))
def test_block_downsample_is_conservative(gm, k):
    c = block_downsample(gm, k)
    assert c.grid.resolution == gm.grid.resolution * k and c.grid.origin == gm.grid.origin
    fine_x, fine_y = gm.grid.cell_centers()
    X, Y = np.meshgrid(fine_x, fine_y)
    pts = np.column_stack([X.ravel(), Y.ravel()])
    # a free coarse cell holds only free fine cells; a blocked one holds a blocked fine cell or the outside
    coarse_free = c.is_free(pts).reshape(gm.shape)
    assert not (coarse_free & gm.occupied).any()
    cells, inside = c.grid.world_to_cell(pts)
    assert inside.all()
    for r, col in np.argwhere(c.occupied):
        mine = (cells[:, 0] == r) & (cells[:, 1] == col)
        outside = (r + 1) * k > gm.shape[0] or (col + 1) * k > gm.shape[1]
        assert gm.occupied.ravel()[mine].any() or (outside and gm.grid.border == "wall")
    with pytest.raises(ParameterError):
        block_downsample(gm, 0)


def _rooms() -> GridMap:
    occ = np.zeros((24, 24), bool)
    occ[12, :] = True
    occ[12, 4:7] = False                 # a door
    occ[4:9, 14:18] = True               # a block
    occ[16, 16] = occ[17, 17] = True     # a pinch pair
    return GridMap(Grid((24, 24), 0.5, origin=(1.0, 2.0), border="wall"), occ, source="rooms")


def test_exact_planners_run_on_grid_maps():
    gm = _rooms()
    s, g = (11.0, 3.0), (11.0, 13.0)
    vis = plan("visibility", gm, s, g)
    world = grid_world(gm)
    assert source_grid(world) is gm
    # the same optimum through the polygon world (plan_visibility hands it to the grid graph) ...
    assert plan("visibility", world, s, g).length == pytest.approx(vis.length, abs=1e-12)
    # ... and through the general polygon visibility graph of gridfield.exact.visibility
    from gridfield.exact.visibility import visibility_graph

    assert visibility_graph(world).shortest_path(s, g)[1] == pytest.approx(vis.length, abs=1e-9)
    assert not collides(world, vis.points)
    ep = plan("exact-potential", gm, s, g, {"step": 0.1, "max_iterations": 4000})
    assert ep.status in ("reached", "local_minimum")
    assert not collides(world, ep.points) and ep.min_clearance > 0
    assert ep.length >= vis.length - 1e-9 or ep.status != "reached"
    with pytest.raises(GridfieldError, match="inside an obstacle"):
        plan("exact-potential", gm, (5.0, 8.25), g)


def test_convergence_study_on_a_grid_map():
    gm = _rooms()
    s, g = (11.25, 3.25), (11.25, 13.25)
    rows = convergence_study(gm, s, g, [2.0, 1.0, 0.5], grid_planner="wavefront-octile",
                             exact_planner="visibility")
    assert [r["resolution"] for r in rows] == [2.0, 1.0, 0.5]
    opt = plan("visibility", gm, s, g).length
    for r in rows:
        assert r["optimal_length"] == pytest.approx(opt, abs=1e-12)
        if r["status"] == "reached":
            assert r["length_ratio_optimal"] >= 1.0 - 1e-12
            assert not r["collides"]
    assert rows[-1]["status"] == "reached"
    # the x4 grid closes the one-cell door: the coarse grid finds no path or a start in a wall
    assert rows[0]["status"] != "reached"
    with pytest.raises(ParameterError, match="multiples of the map's resolution"):
        convergence_study(gm, s, g, [0.75], grid_planner="wavefront-octile", exact_planner="visibility")


def test_batch_compare_on_a_grid_map():
    gm = _rooms()
    r = batch_compare(gm, 4, resolution=0.5, planners=("visibility", "wavefront-octile"), progress=False)
    assert r["planners"]["visibility"]["success_rate"] == 1.0
    assert r["planners"]["visibility"]["length_ratio"]["max"] == pytest.approx(1.0, abs=1e-12)
    ratios = [row["wavefront-octile"]["length_ratio"] for row in r["rows"]]
    assert all(x >= 1.0 - 1e-12 for x in ratios if not math.isnan(x))


@given(gridmaps(), st.integers(0, 2**32 - 1))
def test_exact_potential_distance_is_the_distance_to_the_blocked_squares(gm, seed):
    """The exact field's nearest-obstacle distance on a grid world equals a brute force over every
    blocked square (and the border wall): the distance to a union of squares is the smallest one."""
    from gridfield.exact.continuous import ExactField

    if not gm.occupied.any():
        return
    w = grid_world(gm)
    xmin, ymin, xmax, ymax = gm.grid.bounds
    rng = np.random.default_rng(seed)
    pts = rng.uniform([xmin, ymin], [xmax, ymax], size=(20, 2))
    pts = pts[gm.is_free(pts)]
    if len(pts) == 0:
        return
    field = ExactField(w, pts[0], {"repulsion": "nearest"})
    h = gm.grid.resolution
    r, c = np.nonzero(gm.occupied)
    x0 = xmin + c * h
    y0 = ymin + r * h
    for x, y in pts:
        dx = np.maximum.reduce([x0 - x, np.zeros_like(x0), x - (x0 + h)])
        dy = np.maximum.reduce([y0 - y, np.zeros_like(y0), y - (y0 + h)])
        ref = float(np.hypot(dx, dy).min())
        if gm.grid.border == "wall":
            ref = min(ref, x - xmin, xmax - x, y - ymin, ymax - y)
        got = min(d for d, _, _ in field.closest((float(x), float(y))))
        assert got == pytest.approx(ref, abs=1e-9)


def test_cli_plan_and_compare_on_a_moving_ai_map(capsys):
    import json

    from gridfield.cli import main
    from gridfield.io import bundled_map, read_movingai_map

    arena = str(bundled_map("arena/arena.map"))
    rc = main(["plan", arena, "--planner", "visibility", "--start", "1.5", "37.5", "--goal", "45.5", "3.5", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and out["status"] == "reached" and out["planner"] == "visibility"
    m = read_movingai_map(arena)
    world = grid_world(m)
    assert not collides(world, np.asarray(out["path"]))
    rc = main(["compare", arena, "--start", "1.5", "37.5", "--goal", "45.5", "3.5", "--planner", "wavefront-octile",
               "--exact-planner", "visibility", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert rc == 0
    assert [r["resolution"] for r in data["rows"]] == [4.0, 2.0, 1.0, 0.5, 0.25]
    (last,) = [r for r in data["rows"] if r["resolution"] == 1.0]
    assert last["status"] == "reached" and last["exact_length"] == pytest.approx(out["length"], abs=1e-9)
    assert last["length_ratio_optimal"] >= 1.0 and not last["collides"]
    rc = main(["compare", arena, "--start", "1.5", "37.5", "--goal", "45.5", "3.5", "--resolutions", "1.5"])
    assert rc == 2 and "multiples of the map's resolution" in capsys.readouterr().err
    rc = main(["compare", arena, "--start", "1.5", "37.5", "--goal", "45.5", "3.5", "--resolutions", "0.4"])
    assert rc == 2 and "integer fractions" in capsys.readouterr().err


def test_exact_potential_clearance_through_the_tree_equals_the_world_clearance():
    """plan('exact-potential') on a grid world with many pieces measures its clearance through the
    cached STRtree; the world's own obstacle-by-obstacle clearance is the reference."""
    rng = np.random.default_rng(3)
    occ = rng.random((30, 30)) < 0.12
    occ[2, 2] = occ[27, 27] = False
    gm = GridMap(Grid((30, 30), 1.0, border="wall"), occ)
    world = grid_world(gm)
    assert len(world.obstacles) > 8
    p = plan("exact-potential", gm, (2.5, 2.5), (27.5, 27.5), {"step": 0.2, "q_star": 1.5, "max_iterations": 3000})
    assert p.min_clearance == pytest.approx(world.clearance(p.points), abs=1e-12)
    from gridfield.exact.continuous import _clearance

    free_line = np.array([[2.5, 2.5], [2.6, 2.6]])
    assert _clearance(world, free_line) == pytest.approx(world.clearance(free_line), abs=1e-12)
