"""The voxel wavefront (gridfield.fields.navigation3d, kernel _navigation3.pyx) against a brute-force
Dijkstra written plainly here (26 neighbours, the bounding-box rule of the Moving AI 3-D benchmarks),
and the exact segment test against a slab test over every blocked voxel."""

from __future__ import annotations

import heapq
import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.fields.navigation3d import (
    path_clear,
    segment_clear,
    shortcut_path,
    voxel_descent,
    voxel_wavefront,
)
from gridfield.planners import plan


# ---------------------------------------------------------------------------------------------
# the references, written plainly
# ---------------------------------------------------------------------------------------------
def brute_dijkstra(occ, goal, spacing=(1.0, 1.0, 1.0), periodic=False, slowness=None):
    """Shortest-path cost to ``goal`` (array order); a move needs every voxel of its bounding box free."""
    n0, n1, n2 = occ.shape

    def free(k, r, c):
        if periodic:
            k %= n0
        return 0 <= k < n0 and 0 <= r < n1 and 0 <= c < n2 and not occ[k, r, c]

    dist = np.full(occ.shape, np.inf)
    dist[goal] = 0.0
    heap = [(0.0, goal)]
    done = set()
    while heap:
        d, u = heapq.heappop(heap)
        if u in done:
            continue
        done.add(u)
        for m in itertools.product((-1, 0, 1), repeat=3):
            if m == (0, 0, 0):
                continue
            box = itertools.product(*[(0, m[a]) if m[a] else (0,) for a in range(3)])
            if not all(free(u[0] + e[0], u[1] + e[1], u[2] + e[2]) for e in box):
                continue
            v = ((u[0] + m[0]) % n0 if periodic else u[0] + m[0], u[1] + m[1], u[2] + m[2])
            length = math.sqrt(sum((spacing[a] * m[a]) ** 2 for a in range(3)))
            cost = length if slowness is None else length * 0.5 * (slowness[u] + slowness[v])
            if d + cost < dist[v]:
                dist[v] = d + cost
                heapq.heappush(heap, (d + cost, v))
    return dist


def touches(p, q, cube):
    """Whether segment p -> q (cell units, array order) meets the closed unit cube at integer index ``cube``."""
    lo, hi = 0.0, 1.0
    for a in range(3):
        d = q[a] - p[a]
        if d == 0:
            if not cube[a] <= p[a] <= cube[a] + 1:
                return False
            continue
        t1, t2 = sorted(((cube[a] - p[a]) / d, (cube[a] + 1 - p[a]) / d))
        lo, hi = max(lo, t1), min(hi, t2)
        if lo > hi:
            return False
    return True


def brute_clear(occ, p, q):
    """Every voxel of the grid and of a one-voxel shell round it: blocked ones (and the shell) must not be touched."""
    with np.errstate(over="ignore"):  # a tiny (subnormal) step: the slab times are infinite, as they should be
        return _brute_clear(occ, p, q)


def _brute_clear(occ, p, q):
    n = occ.shape
    for cube in itertools.product(*[range(-1, n[a] + 1) for a in range(3)]):
        inside = all(0 <= cube[a] < n[a] for a in range(3))
        if inside and not occ[cube]:
            continue
        if touches(p, q, cube):
            return False
    return True


def world(gm, cells):
    return gm.grid.cell_to_world(np.atleast_2d(cells))


@st.composite
def voxel_maps(draw, max_side=5):
    shape = tuple(draw(st.integers(1, max_side)) for _ in range(3))
    frac = draw(st.sampled_from([0.0, 0.15, 0.3, 0.45]))
    seed = draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    occ = rng.random(shape) < frac
    goal = tuple(int(rng.integers(0, s)) for s in shape)
    occ[goal] = False
    return occ, goal, rng


# ---------------------------------------------------------------------------------------------
# the wavefront
# ---------------------------------------------------------------------------------------------
@settings(max_examples=60, deadline=None)
@given(voxel_maps())
def test_wavefront_equals_brute_force(case):
    occ, goal, _ = case
    gm = GridMap(Grid(occ.shape, 0.5), occ)
    got = voxel_wavefront(gm, world(gm, goal)[0])
    want = brute_dijkstra(occ, goal) * 0.5
    assert np.array_equal(np.isfinite(got), np.isfinite(want))
    fin = np.isfinite(want)
    np.testing.assert_allclose(got[fin], want[fin], rtol=1e-12, atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(voxel_maps(), st.tuples(*[st.sampled_from([0.5, 1.0, 1.7, 3.0])] * 3), st.booleans())
def test_spacing_and_periodic_axis_equal_brute_force(case, spacing, periodic):
    occ, goal, _ = case
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    got = voxel_wavefront(gm, world(gm, goal)[0], spacing=spacing, periodic=periodic)
    want = brute_dijkstra(occ, goal, spacing, periodic)
    assert np.array_equal(np.isfinite(got), np.isfinite(want))
    fin = np.isfinite(want)
    np.testing.assert_allclose(got[fin], want[fin], rtol=1e-12)


@settings(max_examples=30, deadline=None)
@given(voxel_maps(), st.sampled_from([1.5, 40.0, 1000.0]))
def test_slowness_equals_brute_force(case, top):
    """A bounded slowness (the bucket queue) and a wide one (the heap) give the brute force's values."""
    occ, goal, rng = case
    slow = 1.0 + (top - 1.0) * rng.random(occ.shape)
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    got = voxel_wavefront(gm, world(gm, goal)[0], slowness=slow)
    want = brute_dijkstra(occ, goal, slowness=slow)
    fin = np.isfinite(want)
    assert np.array_equal(np.isfinite(got), fin)
    np.testing.assert_allclose(got[fin], want[fin], rtol=1e-12)


def test_periodic_axis_wraps():
    """On a ring of 6 layers the last layer is one step from the first."""
    gm = GridMap(Grid((6, 1, 1), 1.0), np.zeros((6, 1, 1), bool))
    v = voxel_wavefront(gm, (0.5, 0.5, 0.5), periodic=True).ravel()
    assert v.tolist() == [0.0, 1.0, 2.0, 3.0, 2.0, 1.0]
    assert voxel_wavefront(gm, (0.5, 0.5, 0.5)).ravel().tolist() == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]


def test_empty_map_equals_mcp_geometric():
    """Where the bounding-box rule does not bind (no obstacle), the values are skimage's MCP_Geometric's."""
    from skimage.graph import MCP_Geometric

    shape = (9, 7, 11)
    gm = GridMap(Grid(shape, 1.0), np.zeros(shape, bool))
    got = voxel_wavefront(gm, world(gm, (4, 2, 3))[0])
    cum, _ = MCP_Geometric(np.ones(shape), fully_connected=True).find_costs([(4, 2, 3)])
    np.testing.assert_allclose(got, cum, rtol=1e-12)


def test_stop_at_keeps_the_values_up_to_the_start():
    rng = np.random.default_rng(5)
    occ = rng.random((12, 12, 12)) < 0.2
    occ[0, 0, 0] = occ[6, 6, 6] = False
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    full = voxel_wavefront(gm, (0.5, 0.5, 0.5))
    part = voxel_wavefront(gm, (0.5, 0.5, 0.5), stop_at=(6.5, 6.5, 6.5), margin=1.0)
    if np.isfinite(full[6, 6, 6]):
        near = full <= full[6, 6, 6] + 1.0
        np.testing.assert_array_equal(part[near], full[near])
        assert np.isinf(part[full > full[6, 6, 6] + 2.0]).all()


@settings(max_examples=40, deadline=None)
@given(voxel_maps(max_side=6))
def test_descent_ends_at_the_goal_along_allowed_moves(case):
    occ, goal, rng = case
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    v = voxel_wavefront(gm, world(gm, goal)[0])
    reach = np.argwhere(np.isfinite(v))
    start = tuple(reach[rng.integers(len(reach))])
    for parent in (False, True):
        cells, reached = voxel_descent(gm, v, world(gm, start)[0], parent=parent)
        assert reached and tuple(cells[-1]) == goal and tuple(cells[0]) == start
        steps = np.diff(cells, axis=0)
        assert (np.abs(steps) <= 1).all()
        assert (np.diff(v[tuple(cells.T)]) < 0).all()
        if parent:  # shortest-path parents: the chain's length is the value
            length = float(np.sqrt((steps ** 2).sum(axis=1)).sum())
            assert math.isclose(length, float(v[start]), rel_tol=1e-9, abs_tol=1e-12)
        pts = cells + 0.5
        for a, b in itertools.pairwise(pts):
            assert brute_clear(occ, a, b)


# ---------------------------------------------------------------------------------------------
# the exact segment test
# ---------------------------------------------------------------------------------------------
coords = st.one_of(st.integers(0, 8).map(lambda v: v / 2), st.floats(0.0, 4.0, allow_nan=False))


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**31 - 1), st.tuples(coords, coords, coords), st.tuples(coords, coords, coords))
def test_segment_clear_equals_slab_test(seed, a, b):
    rng = np.random.default_rng(seed)
    occ = rng.random((4, 4, 4)) < 0.25
    gm = GridMap(Grid((4, 4, 4), 1.0), occ)
    p, q = np.array(a)[::-1], np.array(b)[::-1]  # (x, y, z) -> array order
    assert segment_clear(gm, a, b) == brute_clear(occ, p, q)


def test_segment_rule_matches_the_move_rule():
    """A diagonal between voxel centres touches its side voxels (the bounding-box rule)."""
    occ = np.zeros((2, 2, 2), bool)
    occ[1, 0, 0] = True
    gm = GridMap(Grid((2, 2, 2), 1.0), occ)
    assert not segment_clear(gm, (0.5, 0.5, 0.5), (1.5, 1.5, 1.5))  # 3-axis diagonal through the corner
    assert segment_clear(gm, (0.5, 0.5, 0.5), (1.5, 1.5, 0.5))  # a 2-axis diagonal in the free layer
    assert not segment_clear(gm, (0.5, 0.5, 0.5), (0.5, 0.5, 2.5))  # leaves the grid
    assert path_clear(gm, [(0.5, 0.5, 0.5), (1.5, 0.5, 0.5), (1.5, 1.5, 1.5), (0.5, 0.5, 0.5)]) == 2


def test_shortcut_keeps_segments_clear_and_never_lengthens():
    rng = np.random.default_rng(2)
    occ = rng.random((10, 10, 10)) < 0.25
    occ[0, 0, 0] = occ[9, 9, 9] = False
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    v = voxel_wavefront(gm, (9.5, 9.5, 9.5))
    if not np.isfinite(v[0, 0, 0]):
        pytest.skip("not connected")
    cells, _ = voxel_descent(gm, v, (0.5, 0.5, 0.5))
    pts = gm.grid.cell_to_world(cells)
    short = shortcut_path(gm, pts)
    length = lambda p: float(np.sqrt((np.diff(p, axis=0) ** 2).sum(axis=1)).sum())  # noqa: E731
    assert length(short) <= length(pts) + 1e-12
    q = short[:, ::-1]
    for a, b in itertools.pairwise(q):
        assert brute_clear(occ, a, b)


# ---------------------------------------------------------------------------------------------
# the planner and bad input
# ---------------------------------------------------------------------------------------------
def test_wavefront_octile_plans_on_voxels():
    occ = np.zeros((8, 8, 8), bool)
    occ[3:5, :, :] = True
    occ[3:5, 6, 6] = False  # a shaft
    gm = GridMap(Grid((8, 8, 8), 0.5, border="wall"), occ)
    p = plan("wavefront-octile", gm, (0.25, 0.25, 0.25), (3.75, 3.75, 3.75))
    assert p.status == "reached" and p.points.shape[1] == 3
    assert p.points[0].tolist() == [0.25, 0.25, 0.25] and p.points[-1].tolist() == [3.75, 3.75, 3.75]
    full = voxel_wavefront(gm, (3.75, 3.75, 3.75))
    assert math.isclose(p.extra["grid_length"], float(full[0, 0, 0]), rel_tol=1e-12)
    assert path_clear(gm, p.points) == -1
    assert p.to_json()["path"][0] == [0.25, 0.25, 0.25]
    assert p.min_clearance == 0.5  # the wall border's shell, one voxel away


def test_no_path_on_voxels():
    occ = np.zeros((3, 3, 3), bool)
    occ[1] = True
    gm = GridMap(Grid((3, 3, 3), 1.0), occ)
    p = plan("wavefront-octile", gm, (0.5, 0.5, 0.5), (0.5, 0.5, 2.5))
    assert p.status == "no_path" and "unreachable" in p.extra["reason"]


def test_bad_input():
    gm3 = GridMap(Grid((3, 3, 3), 1.0), np.zeros((3, 3, 3), bool))
    gm2 = GridMap(Grid((3, 3), 1.0), np.zeros((3, 3), bool))
    with pytest.raises(ParameterError, match="three numbers X Y Z"):
        plan("wavefront-octile", gm3, (0.5, 0.5), (1.5, 1.5, 1.5))
    with pytest.raises(ParameterError, match=r"start must be two finite numbers \(x, y\)"):
        plan("wavefront-octile", gm2, (0.5, 0.5, 0.5), (1.5, 1.5))
    with pytest.raises(ParameterError, match=r"goal must be three numbers X Y Z \(finite\) on a voxel grid"):
        plan("wavefront-octile", gm3, (0.5, 0.5, 0.5), (1.5, float("nan"), 1.5))
    for planner in ("fmm", "wavefront", "harmonic", "navfn", "visibility"):
        with pytest.raises(ParameterError, match=rf"planner '{planner}' plans on 2-D maps.*'potential' or 'wavefront-octile'"):
            plan(planner, gm3, (0.5, 0.5, 0.5), (1.5, 1.5, 1.5))
    with pytest.raises(ParameterError, match="26"):
        plan("wavefront-octile", gm3, (0.5, 0.5, 0.5), (1.5, 1.5, 1.5), {"connectivity": 4})
    with pytest.raises(GridfieldError, match=r"goal .* lies outside the map"):
        voxel_wavefront(gm3, (0.5, 0.5, 9.5))
    with pytest.raises(ParameterError, match="voxel grids"):
        voxel_wavefront(gm2, (0.5, 0.5))
    with pytest.raises(ParameterError, match="spacing"):
        voxel_wavefront(gm3, (0.5, 0.5, 0.5), spacing=(1, 0, 1))
    with pytest.raises(ParameterError, match="slowness"):
        voxel_wavefront(gm3, (0.5, 0.5, 0.5), slowness=np.zeros((3, 3, 3)))
