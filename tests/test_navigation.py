"""Navigation functions: wavefront (against scipy's Dijkstra), path extraction, fast marching, harmonic
(against a direct solve; no local minima), Rimon-Koditschek sphere worlds (against finite differences),
and the planner / CLI entry points."""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.fields import navigation as nv
from gridfield.fields.navigation import _field, _sphere  # private helpers tested directly
from gridfield.fields.navtable import navigation_field
from gridfield.geometry.world import world_from_dict

SQRT2 = math.sqrt(2.0)


# ---------------------------------------------------------------------------------------------
# references and helpers
# ---------------------------------------------------------------------------------------------
def reference_distance(free, goal, *, connectivity=8, diag=SQRT2, cost=None):
    """Shortest-path cost to ``goal`` by scipy's Dijkstra on an explicitly built graph (move rule: a
    diagonal step needs both orthogonal neighbours free)."""
    rows, cols = free.shape
    idx = np.arange(rows * cols).reshape(rows, cols)
    c = np.ones(free.shape) if cost is None else np.where(free, cost, 1.0)
    src, dst, wts = [], [], []
    moves = [(0, 1), (1, 0)] + ([(1, 1), (1, -1)] if connectivity == 8 else [])
    for dr, dc in moves:
        r0, r1 = max(0, -dr), rows - max(0, dr)
        c0, c1 = max(0, -dc), cols - max(0, dc)
        a = (slice(r0, r1), slice(c0, c1))
        b = (slice(r0 + dr, r1 + dr), slice(c0 + dc, c1 + dc))
        ok = free[a] & free[b]
        if dr and dc:
            ok &= free[r0 + dr:r1 + dr, c0:c1] & free[r0:r1, c0 + dc:c1 + dc]
        length = diag if (dr and dc) else 1.0
        src.append(idx[a][ok])
        dst.append(idx[b][ok])
        wts.append(length * 0.5 * (c[a][ok] + c[b][ok]))
    g = coo_matrix((np.concatenate(wts), (np.concatenate(src), np.concatenate(dst))), shape=(rows * cols,) * 2)
    d = dijkstra(g.tocsr(), directed=False, indices=goal[0] * cols + goal[1]).reshape(rows, cols)
    d[~free] = np.inf
    return d


def assert_valid_chain(free, cells, connectivity=8):
    """Consecutive cells are neighbours, all free, and no diagonal step cuts a corner."""
    cells = np.asarray(cells)
    assert free[cells[:, 0], cells[:, 1]].all()
    step = np.diff(cells, axis=0)
    assert np.abs(step).max(initial=0) <= 1
    assert (np.abs(step).sum(axis=1) > 0).all()
    diag = (step[:, 0] != 0) & (step[:, 1] != 0)
    if connectivity == 4:
        assert not diag.any()
    a = cells[:-1][diag]
    s = step[diag]
    assert free[a[:, 0] + s[:, 0], a[:, 1]].all() and free[a[:, 0], a[:, 1] + s[:, 1]].all()


def assert_segments_free(gm, points, samples=16):
    """Every path segment stays in free cells (dense sampling, endpoints included)."""
    p = np.asarray(points)
    t = np.linspace(0.0, 1.0, samples)[None, :, None]
    dense = (p[:-1, None, :] * (1 - t) + p[1:, None, :] * t).reshape(-1, 2)
    assert gm.is_free(dense).all()


def random_map(seed, shape=(40, 50), p=0.3):
    rng = np.random.default_rng(seed)
    occ = rng.random(shape) < p
    return GridMap(Grid(shape, 1.0), occ)


def maze_map(n_cells=8, corridor=3, wall=1, seed=0):
    """A perfect maze (randomized DFS) on an n x n lattice of rooms, corridors ``corridor`` cells wide."""
    rng = np.random.default_rng(seed)
    pitch = corridor + wall
    size = n_cells * pitch + wall
    occ = np.ones((size, size), bool)
    seen = np.zeros((n_cells, n_cells), bool)
    stack = [(0, 0)]
    seen[0, 0] = True

    def room(i, j):
        r, c = wall + i * pitch, wall + j * pitch
        occ[r:r + corridor, c:c + corridor] = False

    room(0, 0)
    while stack:
        i, j = stack[-1]
        nbrs = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))
                if 0 <= i + di < n_cells and 0 <= j + dj < n_cells and not seen[i + di, j + dj]]
        if not nbrs:
            stack.pop()
            continue
        ni, nj = nbrs[rng.integers(len(nbrs))]
        seen[ni, nj] = True
        room(ni, nj)
        r0, c0 = wall + min(i, ni) * pitch, wall + min(j, nj) * pitch
        if ni != i:
            occ[r0:r0 + 2 * corridor + wall, c0:c0 + corridor] = False
        else:
            occ[r0:r0 + corridor, c0:c0 + 2 * corridor + wall] = False
        stack.append((ni, nj))
    return GridMap(Grid(occ.shape, 0.5, (-1.0, 2.0)), occ)


def centre(gm, cell):
    return gm.grid.cell_to_world([cell])[0]


# ---------------------------------------------------------------------------------------------
# wavefront
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize(("connectivity", "costs"), [(8, "octile"), (8, "unit"), (4, "unit"), (4, "octile")])
def test_wavefront_equals_scipy_dijkstra(seed, connectivity, costs):
    gm = random_map(seed)
    free = ~gm.occupied
    goal = tuple(np.argwhere(free)[seed * 7])
    nav = nv.wavefront(gm, centre(gm, goal), connectivity=connectivity, costs=costs)
    ref = reference_distance(free, goal, connectivity=connectivity, diag=SQRT2 if costs == "octile" else 1.0)
    assert np.array_equal(np.isinf(nav.value), np.isinf(ref))
    fin = np.isfinite(ref)
    np.testing.assert_allclose(nav.value[fin], ref[fin], rtol=0, atol=1e-9)
    assert nav.goal_cell == goal and nav.value[goal] == 0.0


@given(st.integers(1, 14), st.integers(1, 14), st.floats(0.0, 0.6), st.integers(0, 2**31 - 1),
       st.sampled_from([(8, "octile"), (8, "unit"), (4, "unit")]))
def test_wavefront_property(rows, cols, p, seed, mode):
    rng = np.random.default_rng(seed)
    occ = rng.random((rows, cols)) < p
    free_cells = np.argwhere(~occ)
    if len(free_cells) == 0:
        occ[0, 0] = False
        free_cells = np.array([[0, 0]])
    goal = tuple(free_cells[rng.integers(len(free_cells))])
    gm = GridMap(Grid((rows, cols), 0.25, (3.0, -2.0)), occ)
    conn, costs = mode
    nav = nv.wavefront(gm, centre(gm, goal), connectivity=conn, costs=costs)
    ref = reference_distance(~occ, goal, connectivity=conn, diag=SQRT2 if costs == "octile" else 1.0) * 0.25
    assert np.array_equal(np.isinf(nav.value), np.isinf(ref))
    fin = np.isfinite(ref)
    np.testing.assert_allclose(nav.value[fin], ref[fin], atol=1e-9)


@pytest.mark.parametrize("weight", [0.5, 3.0, 40.0])
def test_clearance_wavefront_equals_weighted_dijkstra(weight):
    gm = random_map(11, (30, 35), 0.2)
    free = ~gm.occupied
    goal = tuple(np.argwhere(free)[100])
    nav = nv.wavefront(gm, centre(gm, goal), costs="octile", clearance_weight=weight, q_star=4.0)
    cost = nv.clearance_cost(gm, weight, 4.0)
    assert cost[free].min() >= 1.0 and np.isinf(cost[~free]).all()
    ref = reference_distance(free, goal, cost=cost)
    assert np.array_equal(np.isinf(nav.value), np.isinf(ref))
    fin = np.isfinite(ref)
    np.testing.assert_allclose(nav.value[fin], ref[fin], rtol=1e-12, atol=1e-9)


def test_clearance_pushes_path_away_from_walls():
    occ = np.zeros((21, 41), bool)
    occ[10, 5:36] = True  # a long wall; start and goal on either end below it
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    start, goal = (2.5, 9.5), (38.5, 9.5)
    plain = nv.extract_path(nv.wavefront(gm, goal, costs="octile"), start)
    safe = nv.extract_path(nv.wavefront(gm, goal, costs="octile", clearance_weight=5.0, q_star=6.0), start)
    assert plain.reached and safe.reached
    assert safe.min_clearance > plain.min_clearance
    assert safe.extra["grid_length"] >= plain.extra["grid_length"]


def test_wavefront_unreachable_and_errors():
    occ = np.zeros((5, 7), bool)
    occ[:, 3] = True
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    nav = nv.wavefront(gm, (0.5, 0.5), costs="octile")
    assert np.isinf(nav.value[:, 3:]).all() and np.isfinite(nav.value[:, :3]).all()
    p = nv.extract_path(nav, (6.5, 4.5))
    assert p.status == "no_path" and len(p.points) == 1 and math.isinf(p.extra["value"])
    with pytest.raises(GridfieldError, match="inside an obstacle"):
        nv.wavefront(gm, (3.5, 0.5))
    with pytest.raises(GridfieldError, match="outside the map"):
        nv.wavefront(gm, (30.0, 0.5))
    with pytest.raises(ParameterError, match="connectivity must be 4 or 8"):
        nv.wavefront(gm, (0.5, 0.5), connectivity=6)
    with pytest.raises(ParameterError, match="costs must be one of"):
        nv.wavefront(gm, (0.5, 0.5), costs="euclid")
    with pytest.raises(ParameterError, match="clearance_weight"):
        nv.wavefront(gm, (0.5, 0.5), clearance_weight=-1)
    with pytest.raises(GridfieldError, match=r"start .* inside an obstacle"):
        nv.extract_path(nav, (3.5, 2.5))


def test_no_corner_cutting_between_diagonal_obstacles():
    occ = np.array([[False, True], [True, False]])
    gm = GridMap(Grid((2, 2), 1.0), occ)
    nav = nv.wavefront(gm, (0.5, 0.5), costs="octile")
    assert math.isinf(nav.value[1, 1])


def test_stop_at_gives_exact_values_up_to_the_stop_cell():
    gm = random_map(3, (60, 60), 0.25)
    free = ~gm.occupied
    cells = np.argwhere(free)
    goal, stop = tuple(cells[0]), tuple(cells[len(cells) // 2])
    full = nv.wavefront(gm, centre(gm, goal), costs="octile")
    assert np.isfinite(full.value[stop]), "the map (seed 3) must connect goal and stop cell"
    part = nv.wavefront(gm, centre(gm, goal), costs="octile", stop_at=centre(gm, stop))
    assert part.value[stop] == full.value[stop]
    settled = full.value < full.value[stop]
    np.testing.assert_array_equal(part.value[settled], full.value[settled])
    assert np.all(part.value >= full.value)
    p = nv.extract_path(part, centre(gm, stop))
    assert p.reached and p.extra["grid_length"] == pytest.approx(full.value[stop], abs=1e-9)


def test_large_open_grid_against_closed_form():
    gm = GridMap(Grid((300, 200), 1.0), np.zeros((300, 200), bool))
    nav = nv.wavefront(gm, (0.5, 0.5), costs="octile")
    r, c = np.mgrid[0:300, 0:200]
    octile = np.maximum(r, c) + (SQRT2 - 1) * np.minimum(r, c)
    np.testing.assert_allclose(nav.value, octile, atol=1e-9)


# ---------------------------------------------------------------------------------------------
# extract_path
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize(("connectivity", "costs", "weight"), [(8, "octile", 0.0), (8, "unit", 0.0),
                                                                (4, "unit", 0.0), (8, "octile", 2.0)])
def test_extracted_chain_costs_the_value(seed, connectivity, costs, weight):
    gm = random_map(seed + 20, (35, 45), 0.3)
    free = ~gm.occupied
    cells = np.argwhere(free)
    rng = np.random.default_rng(seed)
    goal = tuple(cells[rng.integers(len(cells))])
    nav = nv.wavefront(gm, centre(gm, goal), connectivity=connectivity, costs=costs, clearance_weight=weight)
    diag = SQRT2 if costs == "octile" else 1.0
    cost = nav.aux.get("cost", np.ones(gm.shape))
    for start in cells[rng.integers(len(cells), size=15)]:
        p = nv.extract_path(nav, centre(gm, start) + np.array([0.2, -0.3]))
        if not np.isfinite(nav.value[tuple(start)]):
            assert p.status == "no_path"
            continue
        assert p.status == "reached"
        ch = p.extra["cells"]
        assert tuple(ch[0]) == tuple(start) and tuple(ch[-1]) == goal
        assert_valid_chain(free, ch, connectivity)
        step = np.abs(np.diff(ch, axis=0)).sum(axis=1) == 2
        chain_cost = np.sum(np.where(step, diag, 1.0) * 0.5 * (cost[ch[:-1, 0], ch[:-1, 1]] + cost[ch[1:, 0], ch[1:, 1]]))
        assert chain_cost == pytest.approx(nav.value[tuple(start)], abs=1e-9)
        if costs == "octile" and weight == 0:
            assert p.extra["grid_length"] == pytest.approx(p.extra["value"], abs=1e-9)
        np.testing.assert_array_equal(p.points[0], centre(gm, start) + np.array([0.2, -0.3]))
        np.testing.assert_array_equal(p.points[-1], nav.goal)
        assert_segments_free(gm, p.points)
        assert p.iterations == len(ch) - 1


def test_extract_path_from_the_goal_cell():
    gm = GridMap(Grid((3, 3), 1.0), np.zeros((3, 3), bool))
    nav = nv.wavefront(gm, (1.5, 1.5), costs="octile")
    p = nv.extract_path(nav, (1.2, 1.9))
    assert p.reached and p.points.tolist() == [[1.2, 1.9], [1.5, 1.5]] and p.extra["grid_length"] == 0.0


def test_path_lengths_report_both_conventions():
    gm = GridMap(Grid((10, 10), 1.0), np.zeros((10, 10), bool))
    nav = nv.wavefront(gm, (9.5, 9.5), costs="octile")
    p = nv.extract_path(nav, (0.1, 0.1))
    assert p.extra["grid_length"] == pytest.approx(9 * SQRT2)
    assert p.length == pytest.approx(9 * SQRT2 + math.hypot(0.4, 0.4))


# ---------------------------------------------------------------------------------------------
# fast marching
# ---------------------------------------------------------------------------------------------
def test_fmm_matches_euclidean_distance_in_open_space():
    gm = GridMap(Grid((81, 81), 0.5), np.zeros((81, 81), bool))
    nav = nv.fmm(gm, (20.25, 20.25))
    xs, ys = gm.grid.cell_centers()
    x, y = np.meshgrid(xs, ys)
    exact = np.hypot(x - 20.25, y - 20.25)
    err = np.abs(nav.value - exact)
    assert err.max() < 0.06 * 0.5 * 10  # second order, error grows slowly with distance
    assert np.median(err / np.maximum(exact, 1)) < 0.01


def test_fmm_follower_on_a_maze_is_collision_free_and_near_any_angle():
    gm = maze_map(6, corridor=4, seed=3)
    free = ~gm.occupied
    cells = np.argwhere(free)
    goal, start = centre(gm, cells[0]), centre(gm, cells[-1])
    nav = nv.fmm(gm, goal)
    p = nv.extract_path(nav, start)
    assert p.reached and np.array_equal(p.end, goal)
    assert_segments_free(gm, p.points)
    octile = nv.extract_path(nv.wavefront(gm, goal, costs="octile"), start)
    # near-any-angle: shorter than the octile path, and not shorter than the straight line
    assert p.length < octile.length
    assert p.length > np.hypot(*(goal - start))


def test_fmm_unreachable_and_clearance():
    occ = np.zeros((20, 30), bool)
    occ[:, 15] = True
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    nav = nv.fmm(gm, (2.5, 2.5))
    assert np.isinf(nav.value[:, 15:]).all() and np.isfinite(nav.value[:, :15]).all()
    assert nv.extract_path(nav, (20.5, 2.5)).status == "no_path"
    slow = nv.fmm(gm, (2.5, 2.5), clearance_weight=3.0)
    assert (slow.value[np.isfinite(slow.value)] >= nav.value[np.isfinite(nav.value)] - 1e-9).all()


def test_fmm_without_scikit_fmm(monkeypatch):
    monkeypatch.setitem(sys.modules, "skfmm", None)
    gm = GridMap(Grid((3, 3), 1.0), np.zeros((3, 3), bool))
    with pytest.raises(GridfieldError, match=r"pip install gridfield\[fmm\]"):
        nv.fmm(gm, (0.5, 0.5))


def test_gradient_follower_rejects_bad_step():
    gm = GridMap(Grid((3, 3), 1.0), np.zeros((3, 3), bool))
    nav = nv.fmm(gm, (0.5, 0.5))
    with pytest.raises(ParameterError, match="step"):
        nv.extract_path(nav, (2.5, 2.5), step=2.0)
    p = nv.extract_path(nav, (2.5, 2.5), max_iterations=0)
    assert p.status == "max_iterations"


# ---------------------------------------------------------------------------------------------
# harmonic
# ---------------------------------------------------------------------------------------------
def lower_neighbour_missing(nav):
    """Reachable non-goal cells without an allowed (no corner cutting) neighbour of lower value."""
    v = nav.value
    free = ~nav.map.occupied
    rows, cols = v.shape
    pad = np.pad(v, 1, constant_values=np.inf)
    fp = np.pad(free, 1)
    best = np.full(v.shape, np.inf)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            if dr == dc == 0:
                continue
            ok = fp[1 + dr:rows + 1 + dr, 1 + dc:cols + 1 + dc].copy()
            if dr and dc:
                ok &= fp[1 + dr:rows + 1 + dr, 1:cols + 1] & fp[1:rows + 1, 1 + dc:cols + 1 + dc]
            best = np.minimum(best, np.where(ok, pad[1 + dr:rows + 1 + dr, 1 + dc:cols + 1 + dc], np.inf))
    return np.isfinite(v) & (v > 0) & ~(best < v)


def test_harmonic_equals_direct_solve_and_is_discrete_harmonic():
    gm = random_map(5, (30, 40), 0.15)
    free = ~gm.occupied
    goal = tuple(np.argwhere(free)[200])
    a = nv.harmonic(gm, centre(gm, goal), tau=1e-12)
    b = nv.harmonic(gm, centre(gm, goal), tau=1e-12, solver="spsolve")
    c = nv.harmonic(gm, centre(gm, goal), tau=1e-12, solver="scipy-cg")
    reach = a.aux["shell"] == 0
    u = a.aux["harmonic"]
    for other in (b, c):
        w, w_ref = 1 - u[reach], 1 - other.aux["harmonic"][reach]
        np.testing.assert_allclose(w, w_ref, rtol=1e-6, atol=1e-13)
    # discrete harmonic: u = mean of the 4 neighbours (obstacles and outside at 1) off the goal
    up = np.pad(np.where(free, u, 1.0), 1, constant_values=1.0)
    mean = 0.25 * (up[:-2, 1:-1] + up[2:, 1:-1] + up[1:-1, :-2] + up[1:-1, 2:])
    inner = free & (a.aux["shell"] >= 0)
    inner[goal] = False
    np.testing.assert_allclose(u[inner], mean[inner], atol=1e-12)
    assert u[goal] == 0 and (u[gm.occupied] == 1).all()


def test_harmonic_shells_have_no_local_minima_and_follower_reaches_goal_on_a_maze():
    gm = maze_map(10, corridor=3, seed=7)
    free = ~gm.occupied
    cells = np.argwhere(free)
    goal = centre(gm, cells[0])
    nav = nv.harmonic(gm, goal)
    assert nav.aux["shells"] > 1  # the maze is long enough for w to fall below tau
    assert np.isfinite(nav.value[free]).all()
    assert not lower_neighbour_missing(nav).any()
    rng = np.random.default_rng(0)
    for start in cells[rng.integers(len(cells), size=12)]:
        p = nv.extract_path(nav, centre(gm, start))
        assert p.status == "reached"
        assert_valid_chain(free, p.extra["cells"])
        assert np.all(np.diff(nav.value[tuple(p.extra["cells"].T)]) < 0)


def test_harmonic_underflow_in_a_long_corridor():
    # w decays like exp(-pi x / 3) in a corridor 3 cells wide: ~1e-137 at its end, below the solver's reach
    occ = np.ones((5, 304), bool)
    occ[1:4, 1:-1] = False
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    nav = nv.harmonic(gm, (1.5, 2.5))
    assert nav.aux["shells"] > 10
    w0 = 1 - nav.aux["harmonic"][2, 1:-1]
    assert w0[-1] < 1e-100 or w0[-1] == 0  # the plain harmonic potential is flat at 1 there
    assert np.all(np.diff(nav.value[2, 1:-1]) > 0)  # the shell field still decreases to the goal
    p = nv.extract_path(nav, (301.5, 1.5))
    assert p.reached and p.extra["grid_length"] == pytest.approx(300, abs=1.0)


def test_harmonic_unreachable_region_and_parameters():
    occ = np.zeros((6, 9), bool)
    occ[:, 4] = True
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    nav = nv.harmonic(gm, (0.5, 0.5))
    assert np.isinf(nav.value[:, 4:]).all() and (nav.aux["shell"][:, 4:] == -1).all()
    assert nv.extract_path(nav, (8.5, 0.5)).status == "no_path"
    for bad in ({"tau": 0.5}, {"band": 0}, {"rtol": 0.1}, {"solver": "lu"}):
        with pytest.raises(ParameterError):
            nv.harmonic(gm, (0.5, 0.5), **bad)


def test_harmonic_band_none_and_default_agree_on_a_small_map():
    gm = maze_map(5, corridor=2, seed=1)
    goal = centre(gm, np.argwhere(~gm.occupied)[0])
    a = nv.harmonic(gm, goal)
    b = nv.harmonic(gm, goal, band=None)
    assert not lower_neighbour_missing(a).any() and not lower_neighbour_missing(b).any()
    np.testing.assert_array_equal(np.isfinite(a.value), np.isfinite(b.value))


# ---------------------------------------------------------------------------------------------
# sphere worlds
# ---------------------------------------------------------------------------------------------
DISCS = np.array([[3.0, 1.0, 1.0], [-2.0, -2.5, 1.5], [-1.0, 3.0, 0.8]])


def test_sphere_nav_function_values_and_boundary():
    grid = Grid((120, 120), 0.1, (-6.0, -6.0))
    phi, grad = nv.sphere_nav_function(DISCS, (4.05, -1.95), kappa=4, workspace_center=(0, 0), workspace_radius=6,
                                       grid=grid)  # the goal at a cell centre
    assert phi.shape == grid.shape and grad.shape == (2, *grid.shape)
    assert phi.min() >= 0 and phi.max() <= 1
    xs, ys = grid.cell_centers()
    x, y = np.meshgrid(xs, ys)
    inside = np.hypot(x, y) >= 6
    for cx, cy, r in DISCS:
        inside |= np.hypot(x - cx, y - cy) <= r
    assert (phi[inside] == 1).all() and (grad[:, inside] == 0).all()
    # phi tends to 1 at every boundary
    ang = np.linspace(0, 2 * np.pi, 50)
    for cx, cy, r in [*DISCS, (0.0, 0.0, -6.0)]:
        rr = abs(r) + (1e-10 if r > 0 else -1e-10)
        ph, _, _ = _sphere._rk_phi_grad(cx + rr * np.cos(ang), cy + rr * np.sin(ang), np.array([4.0, -2.0]), DISCS,
                                   np.zeros(2), 6.0, 4.0)
        assert ph.min() > 0.999
    (gr, gc), = grid.world_to_cell([4.05, -1.95])[0]
    assert phi[gr, gc] == phi.min()


def test_sphere_nav_gradient_matches_finite_differences():
    rng = np.random.default_rng(0)
    goal = np.array([4.0, -2.0])
    c0 = np.array([0.0, 0.0])
    pts = rng.uniform(-5.5, 5.5, size=(400, 2))
    gamma, log_beta, _, _, valid = _sphere._rk_terms(pts[:, 0], pts[:, 1], goal, DISCS, c0, 6.0)
    pts = pts[valid & (np.sqrt(gamma) > 0.3)]
    for kappa in (2.0, 5.0):
        phi, gx, gy = _sphere._rk_phi_grad(pts[:, 0], pts[:, 1], goal, DISCS, c0, 6.0, kappa)
        h = 1e-6
        fx = (_sphere._rk_phi_grad(pts[:, 0] + h, pts[:, 1], goal, DISCS, c0, 6.0, kappa)[0]
              - _sphere._rk_phi_grad(pts[:, 0] - h, pts[:, 1], goal, DISCS, c0, 6.0, kappa)[0]) / (2 * h)
        fy = (_sphere._rk_phi_grad(pts[:, 0], pts[:, 1] + h, goal, DISCS, c0, 6.0, kappa)[0]
              - _sphere._rk_phi_grad(pts[:, 0], pts[:, 1] - h, goal, DISCS, c0, 6.0, kappa)[0]) / (2 * h)
        np.testing.assert_allclose(gx, fx, rtol=1e-5, atol=1e-8)
        np.testing.assert_allclose(gy, fy, rtol=1e-5, atol=1e-8)
        # closed form phi = gamma / (gamma^k + beta)^(1/k)
        beta = np.exp(log_beta[valid & (np.sqrt(gamma) > 0.3)])
        g = gamma[valid & (np.sqrt(gamma) > 0.3)]
        np.testing.assert_allclose(phi, g / (g**kappa + beta) ** (1 / kappa), rtol=1e-12)


def test_sphere_nav_no_overflow_with_many_discs_and_large_kappa():
    xs = np.linspace(-40, 40, 9)
    discs = np.array([[x, y, 2.0] for x in xs for y in xs if math.hypot(x, y) < 50])
    phi, grad = nv.sphere_nav_function(discs, (1.0, 5.0), kappa=60, workspace_center=(0, 0), workspace_radius=60,
                                       grid=Grid((60, 60), 2.0, (-60, -60)))
    assert np.isfinite(phi).all() and np.isfinite(grad).all()


def circles_world(extra=()):
    obstacles = [{"circle": {"center": [float(cx) + 10, float(cy) + 10], "radius": float(r)}} for cx, cy, r in DISCS]
    return world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": obstacles + list(extra)})


def test_plan_sphere_nav_reaches_goal_collision_free():
    w = circles_world()
    start, goal = np.array([6.5, 6.0]), np.array([14.0, 8.0])
    p = nv.plan_sphere_nav(w, start, goal, {"kappa": 6})
    assert p.status == "reached" and np.array_equal(p.end, goal) and np.array_equal(p.points[0], start)
    assert p.min_clearance > 0
    assert (w.distance(p.points) > 0).all()
    auto = nv.plan_sphere_nav(w, start, goal, {})
    assert auto.status == "reached" and auto.extra["kappa"] in nv.KAPPA_LADDER


def test_plan_sphere_nav_small_kappa_local_minimum():
    # two discs with a narrow gap between the robot and the goal: with kappa = 1, phi has a spurious
    # minimum near (17.65, 10) behind the gap; kappa = 4 removes it
    w = world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": [
        {"circle": {"center": [10.0, 12.2], "radius": 2.0}}, {"circle": {"center": [10.0, 7.8], "radius": 2.0}}]})
    start, goal = np.array([17.0, 12.0]), np.array([5.0, 10.0])
    p = nv.plan_sphere_nav(w, start, goal, {"kappa": 1})
    assert p.status == "local_minimum"
    assert np.hypot(*(p.end - [17.65, 10.0])) < 0.3
    assert nv.plan_sphere_nav(w, start, goal, {"kappa": 4}).reached
    auto = nv.plan_sphere_nav(w, start, goal, {})
    assert auto.reached and auto.extra["tried"][0] == (2.0, auto.extra["tried"][0][1])


def test_plan_sphere_nav_rejects_non_sphere_worlds():
    with pytest.raises(ParameterError, match="all circles"):
        nv.plan_sphere_nav(circles_world([{"polygon": [[1, 1], [2, 1], [2, 2]]}]), np.array([5.0, 10.0]),
                           np.array([15.0, 10.0]), {})
    overlapping = world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": [
        {"circle": {"center": [10, 10], "radius": 2}}, {"circle": {"center": [12, 10], "radius": 2}}]})
    with pytest.raises(ParameterError, match="overlap"):
        nv.plan_sphere_nav(overlapping, np.array([3.0, 10.0]), np.array([17.0, 10.0]), {})
    outside = world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": [{"circle": {"center": [1, 1], "radius": 1}}]})
    with pytest.raises(ParameterError, match="workspace disc"):
        nv.plan_sphere_nav(outside, np.array([10.0, 10.0]), np.array([15.0, 10.0]), {})
    with pytest.raises(GridfieldError, match="free space of the sphere world"):
        nv.plan_sphere_nav(circles_world(), np.array([0.5, 0.5]), np.array([15.0, 10.0]), {})


# ---------------------------------------------------------------------------------------------
# fields, planners and the command line
# ---------------------------------------------------------------------------------------------
def test_upwind_gradient_points_uphill_and_ignores_obstacles():
    gm = random_map(2, (30, 30), 0.2)
    free = ~gm.occupied
    nav = nv.wavefront(gm, centre(gm, np.argwhere(free)[0]), costs="octile")
    gx, gy = nav.grad_x, nav.grad_y
    assert np.isfinite(gx).all() and np.isfinite(gy).all()
    assert (gx[~free] == 0).all() and (gy[~free] == 0).all()
    fin = np.isfinite(nav.value) & (nav.value > 0)
    assert (np.hypot(gx, gy)[fin] > 0).all()


@pytest.mark.parametrize("name", ["wavefront", "wavefront-octile", "fmm", "harmonic", "sphere-nav"])
def test_navigation_field_for_every_planner(name):
    from gridfield.geometry.rasterize import as_gridmap

    gm = as_gridmap(circles_world(), 0.25)
    nav = navigation_field(gm, (14.125, 8.125), name, {"kappa": 5, "connectivity": 8, "zeta": 3.0})
    assert nav.potential.shape == nav.grad_x.shape == nav.grad_y.shape == gm.shape
    assert np.isfinite(nav.grad_x).all() and np.isfinite(nav.grad_y).all()
    assert nav.value[nav.goal_cell] == nav.value.min()
    f = nav.to_field()
    assert f.potential is nav.value and f.goal == (14.125, 8.125)


def test_navigation_field_errors():
    gm = GridMap(Grid((3, 3), 1.0), np.zeros((3, 3), bool))
    with pytest.raises(ParameterError, match="unknown navigation planner"):
        navigation_field(gm, (0.5, 0.5), "astar", {})
    with pytest.raises(ParameterError, match="vector world"):
        navigation_field(gm, (0.5, 0.5), "sphere-nav", {})


@pytest.mark.parametrize("name", ["wavefront", "wavefront-octile", "fmm", "harmonic"])
def test_registry_planners_on_a_maze(name):
    from gridfield.planners import plan

    gm = maze_map(6, corridor=3, seed=2)
    cells = np.argwhere(~gm.occupied)
    start, goal = centre(gm, cells[-1]), centre(gm, cells[0])
    p = plan(name, gm, start, goal, {"connectivity": 8, "tolerance": 0.1, "max_iterations": 100000, "eta": 2.0})
    assert p.planner == name and p.status == "reached"
    assert np.array_equal(p.points[0], start) and np.array_equal(p.end, goal)
    assert_segments_free(gm, p.points)
    assert p.min_clearance > 0 and "field_seconds" in p.extra
    json.dumps(p.to_json())


def test_registry_sphere_nav_and_no_path():
    from gridfield.planners import plan

    w = circles_world()
    p = plan("sphere-nav", w, (6.5, 6.0), (14.0, 8.0), {"kappa": 6})
    assert p.reached
    occ = np.zeros((5, 9), bool)
    occ[:, 4] = True
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    for name in ("wavefront", "wavefront-octile", "fmm", "harmonic"):
        assert plan(name, gm, (0.5, 0.5), (8.5, 0.5)).status == "no_path"


def test_cli_plan_wavefront_octile_json(repo_maps, capsys):
    from gridfield.cli import main

    arena = repo_maps / "arena" / "arena.map"
    rc = main(["plan", str(arena), "--start", "1.5", "37.5", "--goal", "4.5", "47.5", "--planner",
               "wavefront-octile", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc in (0, None) and out["status"] == "reached" and out["planner"] == "wavefront-octile"
    assert out["path"][0] == [1.5, 37.5] and out["end"] == [4.5, 47.5]


@pytest.mark.parametrize("border", ["open", "wall"])
def test_min_clearance_equals_brushfire(border):
    from gridfield.distance.brushfire import brushfire

    for seed, p in ((0, 0.3), (1, 0.02), (2, 0.0)):
        rng = np.random.default_rng(seed)
        occ = rng.random((40, 30)) < p
        occ[0, 0] = False
        gm = GridMap(Grid(occ.shape, 0.5, border=border), occ)
        cells = np.argwhere(~occ)
        pts = gm.grid.cell_to_world(cells[rng.integers(len(cells), size=25)])
        nav = nv.wavefront(gm, pts[0])
        d = brushfire(gm, metric="euclidean").distance
        cl, _ = gm.grid.world_to_cell(pts)
        expect = d[cl[:, 0], cl[:, 1]].min()
        assert _field._min_clearance(nav, pts) == pytest.approx(expect, abs=1e-12)
        assert _field._min_clearance(nav, pts[:1]) == pytest.approx(d[cl[0, 0], cl[0, 1]], abs=1e-12)


@given(st.floats(-3, 3), st.floats(-3, 3), st.sampled_from([0.1, 0.25, 0.3, 1.0, 1 / 3]),
       st.floats(-1, 1), st.floats(-1, 1))
def test_goal_cell_fast_path_agrees_with_world_to_cell(x, y, res, x0, y0):
    gm = GridMap(Grid((20, 20), res, (x0, y0)), np.zeros((20, 20), bool))
    for px, py in ((x, y), (x0 + round(x / res) * res, y0 + round(y / res) * res)):  # incl. exact boundaries
        cells, inside = gm.grid.world_to_cell([px, py])
        if inside[0]:
            _, cell = _field._goal_cell(gm, (px, py))
            assert cell == tuple(int(v) for v in cells[0])
        else:
            with pytest.raises(GridfieldError, match="outside the map"):
                _field._goal_cell(gm, (px, py))


def test_goal_errors_name_the_problem():
    gm = GridMap(Grid((2, 2), 1.0), np.array([[True, False], [False, False]]))
    with pytest.raises(GridfieldError, match=r"goal \(0.5, 0.5\) lies inside an obstacle"):
        nv.wavefront(gm, (0.5, 0.5))
    with pytest.raises(ParameterError, match="finite"):
        nv.wavefront(gm, (math.nan, 0.5))
    with pytest.raises(ParameterError, match="two numbers"):
        nv.wavefront(gm, (1.0, 2.0, 3.0))
