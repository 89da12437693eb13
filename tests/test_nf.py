"""The complete potential models (gridfield.fields.navfield: nf1, nf2, nf-blend) and the planner's default.

Oracles: scikit-fmm's fast marching and the exact Euclidean distance (nf1's eikonal values), the
binary-heap march (the bucket queue's values), the octile wavefront of ``wavefront-octile`` (nf1's
octile option), :func:`gridfield.following.basins.basins` (one sink per free component, the goal's, on every
Moving AI and ROS map of tests/data/maps), scipy's 4-connected labelling (reachability), shapely's
exact geometry (no segment enters an occupied cell) and a bisection for the bottleneck clearance.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from gridfield.core.errors import ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.core.params import REGISTRY
from gridfield.distance.brushfire import brushfire
from gridfield.fields.navfield import (
    BUCKET_CELLS,
    NF_MODELS,
    _kernels,
    band_cost,
    eikonal,
    nav_field,
    nf_potential,
    nf_skeleton,
    skeleton,
    work_maps,
)
from gridfield.fields.navigation import wavefront
from gridfield.fields.potential import build_field
from gridfield.following.basins import basins
from gridfield.following.escapes import navigation_map
from gridfield.io import read, read_movingai_map
from gridfield.planners import PLANNERS, plan

REPO = Path(__file__).resolve().parent.parent


def wall_map(occ: np.ndarray, res: float = 1.0) -> GridMap:
    return GridMap(Grid(occ.shape, res, border="wall"), occ)


def rooms(n: int = 40) -> np.ndarray:
    """Four rooms joined by one-cell doors, inside a wall."""
    occ = np.zeros((n, n), bool)
    occ[n // 2, :] = occ[:, n // 2] = True
    for r, c in ((n // 2, n // 4), (n // 2, 3 * n // 4), (n // 4, n // 2)):
        occ[r, c] = False
    return occ


# ------------------------------------------------------------------------------------------------
# nf1's values
# ------------------------------------------------------------------------------------------------
def test_eikonal_is_the_euclidean_distance_on_an_empty_map():
    gm = wall_map(np.zeros((60, 80), bool), 0.5)
    goal = (10.25, 7.25)
    t = eikonal(gm, goal)
    xs, ys = gm.grid.cell_centers()
    exact = np.hypot(*np.meshgrid(xs - goal[0], ys - goal[1]))
    err = t - exact
    # first-order fast marching overestimates (upwind: never below the distance), by about 1 % of
    # the distance (median), 3 % at most beyond half a cell
    far = exact > 2.5
    assert err.min() > -1e-9 and (err <= 0.03 * exact + 0.25).all()
    assert np.median(err[far] / exact[far]) < 0.015


def test_eikonal_against_scikit_fmm_with_obstacles():
    skfmm = pytest.importorskip("skfmm")
    rng = np.random.default_rng(3)
    occ = np.zeros((70, 90), bool)
    for _ in range(12):
        r, c = rng.integers(0, 60), rng.integers(0, 80)
        occ[r:r + rng.integers(2, 12), c:c + rng.integers(2, 12)] = True
    occ[5, 5] = False
    gm = wall_map(occ)
    t = eikonal(gm, (5.5, 5.5))
    phi = np.ones(occ.shape)
    phi[5, 5] = 0.0
    ref = np.ma.filled(skfmm.distance(np.ma.MaskedArray(phi, occ), dx=1.0, order=2), np.inf)
    ref[occ] = np.inf
    fin = np.isfinite(ref) & (~occ)
    # the same cells are reached: the diagonal stencil needs both side cells free, as corners block
    lab = ndimage.label(~occ)[0]
    assert np.array_equal(np.isfinite(t), lab == lab[5, 5])
    assert np.isfinite(t[fin]).all()
    # beyond 8 cells: near the goal the references differ most (skfmm's 4-neighbour stencil gives
    # 3.16 for the exact 2 sqrt 2 two diagonal steps away, the rotated stencil here gives 2.83)
    far = fin & (ref > 8.0)
    rel = np.abs(t[far] - ref[far]) / ref[far]
    assert np.median(rel) < 0.01 and rel.max() < 0.05, (np.median(rel), rel.max())


def test_bucket_queue_agrees_with_the_binary_heap_march():
    rng = np.random.default_rng(0)
    free = (rng.random((120, 150)) >= 0.2).astype(np.uint8)
    free[60, 75] = 1
    k = _kernels()
    src = (np.array([60]), np.array([75]), np.array([0.0]))
    cost = 1.0 + 3.0 * rng.random(free.shape)
    for c, top in ((np.empty((0, 0)), 1.0), (cost, 4.0)):
        exact, _ = k.march(free, c, *src, True, -1, -1, 0.0)
        fast, _ = k.march_buckets(free, c, *src, True, -1, -1, 0.0, BUCKET_CELLS, top)
        fin = np.isfinite(exact)
        assert np.array_equal(fin, np.isfinite(fast))
        assert np.abs(fast[fin] - exact[fin]).max() <= BUCKET_CELLS * top


def test_stop_at_settles_the_cells_up_to_the_start(monkeypatch):
    # the plain (Dijkstra-ordered) truncation; the A*-ordered one is tests/test_nf_astar.py's
    monkeypatch.setattr("gridfield.fields.navfield.ASTAR_WEIGHT", 0.0)
    gm = wall_map(rooms())
    full = eikonal(gm, (5.5, 5.5))
    part = eikonal(gm, (5.5, 5.5), stop_at=(30.5, 30.5), margin=4.0)
    v = full[30, 30]
    near = full <= v + 3.9
    assert np.array_equal(part[near], full[near])
    assert np.isinf(part[full > v + 4.0 + BUCKET_CELLS]).all()


def test_octile_option_is_the_octile_wavefront():
    rng = np.random.default_rng(5)
    occ = rng.random((30, 40)) < 0.25
    occ[3, 3] = False
    for border in ("wall", "open"):
        gm = GridMap(Grid(occ.shape, 0.5, border=border), occ)
        f = build_field(gm, (1.75, 1.75), {"model": "nf1", "attraction": "octile"})
        ref = wavefront(navigation_map(gm), (1.75, 1.75), costs="octile").value
        assert f.map.grid.shape == ref.shape
        assert np.array_equal(f.potential, ref)


def test_open_border_fronts_pass_round_the_grid():
    occ = np.zeros((10, 10), bool)
    occ[4:6, 0:7] = True
    gm = GridMap(Grid((10, 10), 1.0), occ)  # open border: the way round the left end is outside the grid
    f = build_field(gm, (2.5, 8.5), {"model": "nf1"})
    work, around = work_maps(gm)
    assert f.map.grid.shape == (12, 12) and f.map.grid.border == "wall" and around.grid.border == "open"
    assert np.isfinite(f.potential[~work.occupied]).all()
    p = plan("potential", gm, (2.5, 1.5), (2.5, 8.5))
    assert p.status == "reached" and p.extra.get("left_map") is True
    walled = GridMap(Grid((10, 10), 1.0, border="wall"), occ)
    q = plan("potential", walled, (2.5, 1.5), (2.5, 8.5))
    assert q.status == "reached" and (q.points[:, 0] >= 0).all() and "left_map" not in q.extra


# ------------------------------------------------------------------------------------------------
# one minimum per free component: basins on every Moving AI and ROS map
# ------------------------------------------------------------------------------------------------
def _one_goal_per_component(gm: GridMap) -> tuple[np.ndarray, np.ndarray, int]:
    lab, n = ndimage.label(~np.asarray(gm.occupied, bool))
    flat = lab.ravel()
    _, first = np.unique(flat, return_index=True)
    cells = np.column_stack(np.unravel_index(first[1:] if flat[first[0]] == 0 else first, lab.shape))
    return gm.grid.cell_to_world(cells), cells, n


#: The complete models' parameter sets the basins tests check: each model's defaults (nf1's with its
#: clearance band, the potential planner's default) and nf1 without the band.
NF_PARAMS = [{"model": m} for m in NF_MODELS] + [{"model": "nf1", "clearance_band": 0}]


def _assert_one_sink_per_component(gm: GridMap, params: dict, cache: dict) -> None:
    model = params["model"]
    goals, cells, n = _one_goal_per_component(gm)
    dmap = None
    skel = None
    if model == "nf2":
        dmap, sk, cost = cache.setdefault("nf2", nf_skeleton(gm))
        skel = (sk, cost)
    else:
        dmap = cache.setdefault("d", brushfire(gm, metric="euclidean", compute_labels=False, compute_gvd=False))
    U, _, work, _ = nf_potential(gm, goals, params, dmap=dmap, skel=skel)
    assert work is gm
    assert np.isfinite(U[~gm.occupied]).all(), params  # every free cell is reached from its component's goal
    b = basins(SimpleNamespace(map=gm, potential=U, goal=tuple(goals[0])))
    assert len(b.minima) == n, (params, len(b.minima), n)
    sinks = np.unique(b.sink[~gm.occupied])
    assert np.array_equal(np.sort(sinks), np.sort(np.ravel_multi_index(cells.T, gm.shape)))


def _test_map_files(root: Path) -> list[Path]:
    mai = sorted(p for p in (root / "movingai").glob("*/*.map.gz"))
    ros = sorted((root / "ros_maps").glob("*/*.yaml"))
    return mai + ros


def test_one_sink_per_component_on_small_maps(test_maps):
    for name in ("arena", "mapf_room-64-64-8", "rmtst01", "den312d"):
        gm = read_movingai_map(next((test_maps / "movingai" / name).glob("*.map.gz")))
        cache: dict = {}
        for params in NF_PARAMS:
            _assert_one_sink_per_component(gm, params, cache)


@pytest.mark.slow
def test_one_sink_per_component_on_every_moving_ai_and_ros_map(test_maps):
    files = _test_map_files(test_maps)
    assert len(files) >= 25
    for f in files:
        gm = read_movingai_map(f) if f.name.endswith(".map.gz") else read(f)
        assert gm.grid.border == "wall"
        cache: dict = {}
        for params in NF_PARAMS:
            _assert_one_sink_per_component(gm, params, cache)


# ------------------------------------------------------------------------------------------------
# the planner: every reachable goal reached, no collision
# ------------------------------------------------------------------------------------------------
def assert_path_free(gm: GridMap, points: np.ndarray) -> None:
    g = gm.grid
    eps = 1e-9 * g.resolution
    r, c = np.nonzero(gm.occupied)
    x0, y0 = g.origin[0] + c * g.resolution, g.origin[1] + r * g.resolution
    tree = shapely.STRtree(shapely.box(x0 + eps, y0 + eps, x0 + g.resolution - eps, y0 + g.resolution - eps))
    pts = np.asarray(points, float)
    if len(pts) >= 2:
        seg, _ = tree.query(shapely.linestrings(np.stack([pts[:-1], pts[1:]], axis=1)), predicate="intersects")
        assert not len(seg), "a path segment enters an occupied cell"


@st.composite
def random_maps(draw):
    rows, cols = draw(st.integers(6, 24)), draw(st.integers(6, 24))
    rng = np.random.default_rng(draw(st.integers(0, 2**31 - 1)))
    occ = rng.random((rows, cols)) < draw(st.sampled_from([0.1, 0.25, 0.4]))
    free = np.flatnonzero(~occ)
    if len(free) < 2:
        occ[0, 0] = occ[-1, -1] = False
        free = np.flatnonzero(~occ)
    i, j = rng.choice(free, 2, replace=False)
    g = Grid((rows, cols), draw(st.sampled_from([1.0, 0.05])), border=draw(st.sampled_from(["open", "wall"])))
    centres = g.cell_to_world(np.array([divmod(int(i), cols), divmod(int(j), cols)]))
    jitter = rng.uniform(-0.4, 0.4, (2, 2)) * g.resolution
    return GridMap(g, occ), centres[0] + jitter[0], centres[1] + jitter[1]


@settings(max_examples=60)
@given(case=random_maps(), model=st.sampled_from([None, "nf1", "nf2", "nf-blend"]))
def test_every_reachable_goal_is_reached_without_collision(case, model):
    gm, start, goal = case
    nm = navigation_map(gm)
    lab = ndimage.label(~nm.occupied)[0]
    a, b = nm.grid.cell_of(*start), nm.grid.cell_of(*goal)
    reachable = lab[a] == lab[b]
    p = plan("potential", gm, start, goal, {} if model is None else {"model": model})
    assert p.params["model"] == (model or "nf1")
    if not reachable:
        assert p.status == "no_path"
        return
    assert p.status == "reached", (p.status, p.extra.get("stop_reason"), p.extra.get("stall_point"))
    assert np.allclose(p.points[-1], goal)
    assert_path_free(gm, p.points)
    assert p.extra.get("escapes_tried", 0) == 0
    assert p.extra["median_clearance"] >= p.min_clearance


def test_default_is_nf1_and_khatib_is_one_parameter_away():
    occ = np.zeros((10, 10), bool)
    occ[4:6, 0:7] = True
    gm = wall_map(occ)
    d = plan("potential", gm, (2.5, 1.5), (2.5, 8.5))
    k = plan("potential", gm, (2.5, 1.5), (2.5, 8.5), {"model": "khatib"})
    assert (d.status, d.params["model"]) == ("reached", "nf1")
    assert (k.status, k.params["model"]) == ("local_minimum", "khatib")
    assert "median_clearance" not in k.extra  # the key is the complete models'
    # build_field itself keeps the classic field when model is unset
    assert build_field(gm, (2.5, 8.5)).params["model"] == "khatib"


def test_registry_names_the_models_and_their_parameters():
    assert set(NF_MODELS) <= set(REGISTRY["model"].choices)
    for name in ("attraction", "clearance_gain"):
        assert name in PLANNERS["potential"].reads and REGISTRY[name].meaning
        assert REGISTRY[name].planners == ("potential",)
    assert REGISTRY["model"].default is None and "nf1" in REGISTRY["model"].scale


def test_seed_worlds_ask_for_the_classic_field():
    from gridfield.io import read as read_any

    for name in ("seed000.yaml", "seed000_segment.yaml", "seed001.yaml", "star_two.yaml"):
        w = read_any(REPO / "maps" / name)
        assert w.params["model"] == "khatib", name


def test_plan_json_names_the_model(capsys):
    from gridfield.cli import main

    rc = main(["plan", str(REPO / "maps" / "arena" / "arena.map"), "--start", "2.5", "2.5", "--goal", "40.5", "40.5",
               "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    assert out["params"]["model"] == "nf1" and out["status"] == "reached"
    assert out["median_clearance"] >= out["min_clearance"]


# ------------------------------------------------------------------------------------------------
# clearance: nf2 keeps the bottleneck clearance, nf-blend keeps off the walls
# ------------------------------------------------------------------------------------------------
def bottleneck(dist: np.ndarray, free: np.ndarray, s: tuple[int, int], g: tuple[int, int]) -> float:
    """The largest t such that s and g are 4-connected through free cells with clearance >= t."""
    vals = np.unique(dist[free])
    best = -math.inf
    for t in vals[vals <= min(dist[s], dist[g])]:
        lab = ndimage.label(free & (dist >= t))[0]
        if lab[s] and lab[s] == lab[g]:
            best = t
    return float(best)


def test_nf2_keeps_the_bottleneck_clearance_and_blend_keeps_off_walls():
    occ = np.zeros((40, 60), bool)
    occ[0, :] = occ[-1, :] = True
    occ[:, 0] = occ[:, -1] = True
    occ[12:28, 20:40] = True  # a block in a wide hall: the ways round it are 11 cells wide
    gm = wall_map(occ)
    dist = brushfire(gm, metric="euclidean").distance
    s, g = (5.5, 20.5), (54.5, 20.5)
    need = bottleneck(dist, ~occ, (20, 5), (20, 54))
    p1 = plan("potential", gm, s, g, {"model": "nf1", "clearance_band": 0})  # plain nf1: the shortest way
    p2 = plan("potential", gm, s, g, {"model": "nf2"})
    pb = plan("potential", gm, s, g, {"model": "nf-blend"})
    pd = plan("potential", gm, s, g)  # the default: nf1 with its clearance band (6 cells)
    assert {p1.status, p2.status, pb.status, pd.status} == {"reached"}
    assert p1.min_clearance <= 1.5  # the shortest way touches the block's corners
    assert pd.params["model"] == "nf1" and pd.params["clearance_band"] == 6.0
    # ~3 cells off the corners for ~6 % of length here (a tight turn round a block: the costliest case)
    assert pd.min_clearance >= 2.0 and pd.length <= 1.08 * p1.length, (pd.min_clearance, pd.length, p1.length)
    assert p2.min_clearance >= need - 1.0, (p2.min_clearance, need)
    assert pb.min_clearance >= 2.0 and pb.min_clearance > p1.min_clearance
    assert p1.length < pb.length < p2.length + 1e-9 or p1.length < pb.length


def test_skeleton_finds_the_middle_of_a_room_of_one_obstacle():
    occ = np.zeros((21, 21), bool)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = True  # one connected wall: no GVD of labels inside
    d = brushfire(wall_map(occ), metric="euclidean", compute_labels=True, compute_gvd=True)
    sk = skeleton(d)
    assert not d.gvd.any()  # one obstacle (the border ring touches it): the GVD of labels is empty
    assert sk[10, 10] and sk[5, 5] and sk[15, 5] and sk[5, 15]  # the medial axis of a square: its diagonals
    assert not sk[2, 10] and not sk[10, 2]


def test_nav_field_refuses_other_models_and_foreign_distance_maps():
    from gridfield.core.errors import ParameterError

    gm = wall_map(np.zeros((5, 5), bool))
    with pytest.raises(ParameterError, match="models"):
        nav_field(gm, (0.5, 0.5), {"model": "khatib"})
    other = brushfire(GridMap(Grid((6, 6), 1.0), np.zeros((6, 6), bool)), metric="euclidean")
    with pytest.raises(ParameterError, match="brushfire"):
        nav_field(gm, (0.5, 0.5), {"model": "nf1"}, dmap=other)


# ------------------------------------------------------------------------------------------------
# nf1's clearance band (issue 25): the default keeps off the walls and runs down the middle
# ------------------------------------------------------------------------------------------------
def test_the_default_runs_down_the_middle_of_a_passage_and_through_a_one_cell_door():
    occ = np.zeros((30, 60), bool)
    occ[:10, :] = occ[19:, :] = True  # a corridor of rows 10..18 (9 cells: narrower than 2 x 6 cells)
    occ[10:19, 30] = True
    occ[14, 30] = False  # a wall across it with a one-cell door in the middle row
    gm = wall_map(occ)
    s, g = (2.5, 11.5), (57.5, 17.5)  # near opposite walls
    plain = plan("potential", gm, s, g, {"clearance_band": 0})
    p = plan("potential", gm, s, g)
    assert p.status == "reached" and plain.status == "reached"
    assert p.params["model"] == "nf1" and "median_clearance" in p.extra
    ys = p.points[:, 1]
    xs = p.points[:, 0]
    mid = (xs > 12) & (xs < 48)  # away from the ends: along the middle row (14.5), within a cell
    assert np.abs(ys[mid] - 14.5).max() <= 1.0, ys[mid]
    assert p.extra["median_clearance"] > plain.extra["median_clearance"]
    assert p.length <= 1.05 * plain.length


def test_band_cost_is_bounded_and_a_huge_blend_gain_is_refused_not_a_crash():
    occ = np.zeros((12, 12), bool)
    occ[0] = True
    gm = GridMap(Grid((12, 12), 1.0, border="open"), occ)  # one wall: row 0
    c = band_cost(brushfire(gm, metric="euclidean"), 6.0, 0.5)
    assert np.isinf(c[occ]).all() and (c[~occ] >= 1).all() and (c[~occ] <= 1.5).all()
    assert (c[7:] == 1.0).all() and (c[1] == 1.0 + 0.5 * (5 / 6) ** 2).all()  # beyond the band; one cell off
    gm = wall_map(occ)
    with pytest.raises(ParameterError, match="slowness"):
        plan("potential", gm, (2.5, 5.5), (9.5, 9.5), {"model": "nf-blend", "clearance_gain": 1e15})


# ----------------------------------------------------------------------------------------------
# a stalled follower on a complete field is finished by the field's discrete descent
# ----------------------------------------------------------------------------------------------
def test_nf_blend_stall_at_a_one_cell_door_is_finished_by_the_discrete_descent(test_maps):
    """8room_000 scenario 918: nf-blend's steep cost at a one-cell door stalled the follower ("confined",
    a hint blaming q_star) though the field has one minimum (the benchmark's one miss of 460)."""
    from test_potential_planner import assert_path_free

    from gridfield.io import read_scen

    d = test_maps / "movingai" / "8room_000"
    gm = read_movingai_map(next(d.glob("*.map.gz")))
    scen = read_scen(next(d.glob("*.scen.gz")), map_height=gm.shape[0])
    s, g = scen.start_xy[918], scen.goal_xy[918]
    import gridfield.fields.navfield as navfield

    # the stall happens with the planned march's A* weight at 1 or below (0.7 when it was found); the
    # default's 1.25 settles other cells there and reaches without it, so the case pins the weight
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(navfield, "ASTAR_WEIGHT", 1.0)
        p = plan("potential", gm, s, g, {"model": "nf-blend"})
    assert p.status == "reached" and np.allclose(p.points[-1], g) and "hint" not in p.extra
    fin = p.extra["finish"]
    assert fin["stop_reason"] == "confined" and fin["cells"] >= 1
    assert_path_free(gm, p.points)
    # not longer than the octile optimum by more than the blend's usual clearance detour
    assert p.length <= 1.5 * plan("wavefront-octile", gm, s, g).length


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["nf1", "nf2", "nf-blend"]))
def test_descend_cells_strictly_descends_by_legal_moves_to_the_goal(seed, model):
    """From every free cell of the goal's component, on fields of random maps: each move is to an
    8-neighbour (a diagonal only with both side cells free), U strictly falls, the walk ends at the goal;
    checked against the map directly (not through the field's own code)."""
    from gridfield.following.follower import descend_cells

    rng = np.random.default_rng(seed)
    occ = rng.random((14, 17)) < 0.3
    free = ~occ
    lab = ndimage.label(free)[0]
    cells = np.argwhere(free)
    if len(cells) < 2:
        return
    gcell = tuple(cells[rng.integers(len(cells))])
    gm = wall_map(occ)
    goal = (gcell[1] + 0.5, gcell[0] + 0.5)
    U = nav_field(gm, goal, {"model": model}).potential
    for r, c in cells[lab[tuple(cells.T)] == lab[gcell]]:
        way = descend_cells(gm, U, (c + 0.5, r + 0.5), goal)
        assert way is not None and tuple(way[-1]) == goal
        if (r, c) == gcell:
            assert len(way) == 1
            continue
        prev, pu = (r, c), U[r, c]
        for x, y in way:
            rr, cc = int(y), int(x)
            dr, dc = rr - prev[0], cc - prev[1]
            assert max(abs(dr), abs(dc)) == 1 and not occ[rr, cc]
            assert not (dr and dc and (occ[prev[0] + dr, prev[1]] or occ[prev[0], prev[1] + dc]))
            assert U[rr, cc] < pu
            prev, pu = (rr, cc), U[rr, cc]


def test_a_run_that_drifts_past_the_settled_cells_is_finished_from_the_last_valued_point():
    """Hypothesis's counterexample (nf-blend, open border): the planned march settles cells only up to
    about U(start); the follower's interpolated steps drifted up into a free cell beyond that (U inf,
    zero gradient) and stopped there on small_gradient, where the discrete descent has no value to
    start from. The finish now starts from the last point whose cell has a value."""
    occ = np.array([[False, False,  True,  True, False, False, False, False, False, False,  True,  True, False, False,  True, False, False,  True, False, False, False,  True],
    [False, False, False, False,  True, False,  True, False, False, False, False, False, False, False,  True, False, False, False, False,  True, False, False],
    [False, False, False, False, False, False, False,  True, False, False, False, False, False, False,  True, False, False,  True, False,  True, False,  True],
    [False, False, False,  True, False, False, False,  True,  True, False, False, False, False, False,  True, False, False, False, False, False, False, False],
    [ True,  True, False,  True, False,  True, False, False, False, False,  True,  True, False,  True,  True, False, False, False, False, False,  True, False],
    [False, False, False, False,  True, False, False,  True,  True, False,  True, False, False, False,  True,  True, False, False, False, False, False, False],
    [False, False, False, False, False, False, False, False,  True,  True, False,  True,  True, False, False, False, False, False, False, False, False, False],
    [False, False,  True, False,  True, False,  True,  True, False, False,  True,  True,  True, False,  True, False,  True,  True, False,  True,  True,  True],
    [False,  True, False, False,  True,  True, False,  True, False, False, False,  True, False, False,  True, False, False, False,  True, False, False, False],
    [False,  True, False, False,  True, False, False, False, False,  True, False, False, False, False, False, False,  True, False,  True, False, False, False],
    [False, False,  True, False, False, False, False, False, False,  True,  True, False, False, False, False,  True, False, False, False, False, False, False],
    [False, False,  True,  True, False, False,  True, False, False, False, False, False, False, False, False,  True, False,  True, False, False, False, False],
    [False,  True, False, False, False, False, False,  True, False, False, False, False, False, False, False, False, False,  True,  True, False, False, False],
    [False,  True, False, False, False,  True, False, False, False,  True,  True,  True,  True, False,  True,  True, False, False,  True, False, False,  True],
    [False, False, False, False, False, False, False, False, False,  True,  True, False,  True, False, False, False, False, False, False, False, False,  True],
    [ True, False, False, False, False,  True, False, False, False, False, False, False, False, False,  True, False, False, False, False,  True,  True,  True]])
    gm = GridMap(Grid((16, 22), 1.0, border="open"), occ)
    start, goal = np.array([3.79334028, 14.49175543]), np.array([9.64540457, 1.80895656])
    p = plan("potential", gm, start, goal, {"model": "nf-blend"})
    assert p.status == "reached" and np.allclose(p.points[-1], goal)
    assert p.extra["finish"]["dropped"] >= 1  # the drifted points are not part of the path
    assert_path_free(gm, p.points)
