"""Any-angle optimum on grid maps (gridfield.exact.anyangle) against independent references.

- a brute force written here: every cell corner (but pinch points) as a vertex, every pair tested
  with shapely's exact predicates against the union of the blocked squares, Dijkstra in plain Python;
- an octile (8-connected, no corner cutting) Dijkstra written here: any-angle <= octile (an octile
  path is a feasible any-angle path); the other bound of the issue, any-angle >= octile / 1.0824, is
  false in general (``test_staircase_breaks_the_octile_metric_bound``);
- Polyanya's published Euclidean lengths of the 160 arena.map queries (tests/data/maps/polygon);
- the octile optima printed in Moving AI scenario files, on a sample of scenarios per map.
"""

from __future__ import annotations

import heapq
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import box

from gridfield.core.errors import GridfieldError
from gridfield.core.grid import Grid, GridMap
from gridfield.exact.anyangle import grid_graph, plan_anyangle
from gridfield.io import read_movingai_map, read_scen
from gridfield.planners import plan

from mapdata import TEST_MAPS

SQRT2 = math.sqrt(2.0)


# ----------------------------------------------------------------------------------------
# Independent references
# ----------------------------------------------------------------------------------------
def padded(occ: np.ndarray, wall: bool) -> np.ndarray:
    B = np.full((occ.shape[0] + 2, occ.shape[1] + 2), wall)
    B[1:-1, 1:-1] = occ
    return B


def obstacles(occ: np.ndarray, wall: bool):
    """Union of the blocked unit squares (and a frame round the map for a wall border)."""
    rows, cols = occ.shape
    # one box per horizontal run of blocked cells (their union is the union of the squares)
    edge = np.diff(np.pad(occ.astype(np.int8), ((0, 0), (1, 1))), axis=1)
    r0, c0 = np.nonzero(edge == 1)
    _, c1 = np.nonzero(edge == -1)
    shapes = list(shapely.box(c0, r0, c1, r0 + 1))
    if wall:
        shapes.append(box(-5, -5, cols + 5, rows + 5).difference(box(0, 0, cols, rows)))
    return shapely.union_all(shapes) if shapes else shapely.GeometryCollection()


def pinch_points(occ: np.ndarray, wall: bool) -> np.ndarray:
    """Corners whose two diagonally opposite cells are blocked and the other two free."""
    B = padded(occ, wall)
    sw, se, nw, ne = B[:-1, :-1], B[:-1, 1:], B[1:, :-1], B[1:, 1:]
    pinch = (sw & ne & ~se & ~nw) | (se & nw & ~sw & ~ne)
    y, x = np.nonzero(pinch)
    return np.column_stack([x, y]).astype(float)


def admissible(p: np.ndarray, q: np.ndarray, union, pinches: np.ndarray) -> np.ndarray:
    """Segments p[i] -> q[i] that miss the obstacles' interior and pass through no pinch point."""
    lines = shapely.linestrings(np.stack([p, q], axis=1))
    ok = ~shapely.relate_pattern(lines, union, "T********") if not union.is_empty else np.ones(len(p), bool)
    for c in pinches:
        ok &= ~shapely.relate_pattern(lines, shapely.points(c), "T********")  # through it, not ending on it
    return ok


def brute_force(occ: np.ndarray, wall: bool, s, g) -> float:
    rows, cols = occ.shape
    union = obstacles(occ, wall)
    pinches = pinch_points(occ, wall)
    X, Y = np.meshgrid(np.arange(cols + 1.0), np.arange(rows + 1.0))
    pts = np.column_stack([X.ravel(), Y.ravel()])
    if len(pinches):
        keep = ~(np.abs(pts[:, None, :] - pinches[None]).sum(axis=2) == 0).any(axis=1)
        pts = pts[keep]
    pts = np.vstack([np.asarray(s, float), np.asarray(g, float), pts])
    n = len(pts)
    i, j = np.triu_indices(n, 1)
    ok = admissible(pts[i], pts[j], union, pinches)
    adj: list[list[tuple[int, float]]] = [[] for _ in range(n)]
    for a, b in zip(i[ok].tolist(), j[ok].tolist(), strict=True):
        d = math.dist(pts[a], pts[b])
        adj[a].append((b, d))
        adj[b].append((a, d))
    dist = [math.inf] * n
    dist[0] = 0.0
    heap = [(0.0, 0)]
    while heap:
        d, u = heapq.heappop(heap)
        if d > dist[u]:
            continue
        if u == 1:
            return d
        for v, w in adj[u]:
            if d + w < dist[v]:
                dist[v] = d + w
                heapq.heappush(heap, (d + w, v))
    return math.inf


def octile(occ: np.ndarray, wall: bool, s_cell, g_cell) -> float:
    """8-connected Dijkstra between cell centres, diagonal only when both side cells are free."""
    B = padded(occ, wall)
    start = (s_cell[0] + 1, s_cell[1] + 1)
    goal = (g_cell[0] + 1, g_cell[1] + 1)
    dist = {start: 0.0}
    heap = [(0.0, start)]
    while heap:
        d, (r, c) = heapq.heappop(heap)
        if (r, c) == goal:
            return d
        if d > dist[(r, c)]:
            continue
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                if (dr, dc) == (0, 0):
                    continue
                rr, cc = r + dr, c + dc
                if not (0 <= rr < B.shape[0] and 0 <= cc < B.shape[1]) or B[rr, cc]:
                    continue
                if dr and dc and (B[r + dr, c] or B[r, c + dc]):
                    continue
                if not (1 <= rr <= occ.shape[0] and 1 <= cc <= occ.shape[1]):
                    continue  # an open border's outside is free, but the octile search stays on the map
                nd = d + (SQRT2 if dr and dc else 1.0)
                if nd < dist.get((rr, cc), math.inf):
                    dist[(rr, cc)] = nd
                    heapq.heappush(heap, (nd, (rr, cc)))
    return math.inf


def check_path(pts: np.ndarray, occ: np.ndarray, wall: bool) -> None:
    union = obstacles(occ, wall)
    ok = admissible(pts[:-1], pts[1:], union, pinch_points(occ, wall))
    assert ok.all(), f"segments {np.flatnonzero(~ok).tolist()} of {pts.tolist()} leave the free space"


# ----------------------------------------------------------------------------------------
# Random small grids
# ----------------------------------------------------------------------------------------
@st.composite
def grids(draw):
    rows = draw(st.integers(6, 10))
    cols = draw(st.integers(6, 10))
    p = draw(st.sampled_from([0.15, 0.3, 0.45]))
    seed = draw(st.integers(0, 2**32 - 1))
    occ = np.random.default_rng(seed).random((rows, cols)) < p
    free = np.argwhere(~occ)
    if len(free) < 2:
        occ[0, 0] = occ[-1, -1] = False
        free = np.argwhere(~occ)
    a = free[draw(st.integers(0, len(free) - 1))]
    b = free[draw(st.integers(0, len(free) - 1))]
    # points anywhere in the free cell, on a 1/4 lattice (exact in binary), centres included
    da = draw(st.tuples(st.integers(0, 3), st.integers(0, 3)))
    db = draw(st.tuples(st.integers(0, 3), st.integers(0, 3)))
    wall = draw(st.booleans())
    return occ, wall, a, b, da, db


@settings(max_examples=40)
@given(grids())
def test_random_grids_match_brute_force_and_octile_bounds(case):
    occ, wall, a, b, da, db = case
    gm = GridMap(Grid(occ.shape, 1.0, border="wall" if wall else "open"), occ)
    g = grid_graph(gm)
    # cell centres: the brute force, and the octile bounds
    s, t = (a[1] + 0.5, a[0] + 0.5), (b[1] + 0.5, b[0] + 0.5)
    pts, length = g.shortest_path(s, t)
    frame = True  # paths stay on the map with either border (module docstring, "Border")
    ref = brute_force(occ, frame, s, t)
    oct_len = octile(occ, wall, a, b)
    lazy_pts, lazy_length = g.shortest_path(s, t, search="lazy")  # the search without a graph
    others = {name: g.shortest_path(s, t, search=name) for name in ("graph", "polyanya")}
    if math.isinf(ref):
        assert math.isinf(length) and math.isinf(oct_len) and math.isinf(lazy_length) and len(lazy_pts) == 0
        assert all(math.isinf(v[1]) and len(v[0]) == 0 for v in others.values())
    else:
        assert length == pytest.approx(ref, abs=1e-9)
        assert lazy_length == pytest.approx(ref, abs=1e-9)
        check_path(lazy_pts, occ, frame)
        for name, (o_pts, o_len) in others.items():
            assert o_len == pytest.approx(ref, abs=1e-9), name
            check_path(o_pts, occ, frame)
        assert length <= oct_len + 1e-9  # an octile path is an any-angle path
        assert length >= math.dist(s, t) - 1e-12
        # the bound that holds: the obstacle-free octile *distance* over sqrt(4 - 2 sqrt 2) = 1.08239...
        dx, dy = abs(t[0] - s[0]), abs(t[1] - s[1])
        assert length >= (max(dx, dy) + (SQRT2 - 1) * min(dx, dy)) / math.sqrt(4 - 2 * SQRT2) - 1e-12
        assert pts[0].tolist() == list(s) and pts[-1].tolist() == list(t)
        assert float(np.hypot(*np.diff(pts, axis=0).T).sum()) == pytest.approx(length, abs=1e-9)
        check_path(pts, occ, frame)
    # points off the centres, anywhere in their cells (1/4 lattice: on edges and corners too)
    s2 = (a[1] + da[0] / 4, a[0] + da[1] / 4)
    t2 = (b[1] + db[0] / 4, b[0] + db[1] / 4)
    pinches = {tuple(c) for c in pinch_points(occ, frame).tolist()}
    if s2 in pinches or t2 in pinches:
        with pytest.raises(GridfieldError, match="pinch point"):
            g.shortest_path(s2, t2)
        return
    pts2, length2 = g.shortest_path(s2, t2)
    lazy2 = g.shortest_path(s2, t2, search="lazy")[1]
    others2 = [g.shortest_path(s2, t2, search=name) for name in ("graph", "polyanya")]
    ref2 = brute_force(occ, frame, s2, t2)
    if math.isinf(ref2):
        assert math.isinf(length2) and math.isinf(lazy2) and all(math.isinf(v[1]) for v in others2)
    else:
        assert length2 == pytest.approx(ref2, abs=1e-9)
        assert lazy2 == pytest.approx(ref2, abs=1e-9)
        check_path(pts2, occ, frame)
        for o_pts, o_len in others2:
            assert o_len == pytest.approx(ref2, abs=1e-9)
            check_path(o_pts, occ, frame)


def test_staircase_breaks_the_octile_metric_bound():
    """A one-cell staircase: the any-angle path runs diagonally across convex corners where the
    octile path needs two orthogonal steps, so octile / any-angle exceeds 1.0824 (here sqrt(2))."""
    n = 8
    occ = np.ones((n, n + 1), bool)
    for k in range(n):
        occ[k, k] = occ[k, k + 1] = False
    gm = GridMap(Grid(occ.shape, 1.0, border="wall"), occ)
    _, length = grid_graph(gm).shortest_path((0.5, 0.5), (n - 0.5, n - 0.5))
    oct_len = octile(occ, True, (0, 0), (n - 1, n - 1))
    assert length == pytest.approx(brute_force(occ, True, (0.5, 0.5), (n - 0.5, n - 0.5)), abs=1e-9)
    assert oct_len == 2 * (n - 1)
    assert oct_len / length > 1.0824
    assert oct_len / length <= SQRT2 + 1e-12


def test_pinch_points_block_passage():
    """Two cells touching at a corner close the only gap: the path must go round (or not exist)."""
    occ = np.zeros((4, 4), bool)
    occ[0:2, 1] = True      # a wall from the bottom up to y = 2 in column 1 ...
    occ[2:4, 2] = True      # ... and one from y = 2 to the top in column 2: they touch at (2, 2)
    gm = GridMap(Grid(occ.shape, 1.0, border="wall"), occ)
    g = grid_graph(gm)
    assert not g.visible((1.5, 2.5), (2.5, 1.5))
    with pytest.raises(GridfieldError, match="pinch point"):
        g.shortest_path((2.0, 2.0), (0.5, 0.5))
    pts, length = g.shortest_path((0.5, 3.5), (3.5, 0.5))
    assert math.isinf(length) and len(pts) == 0
    # with an open border the only way round runs along the map's lower edge, outside the free cells
    # (below the wall in column 1): not a path on the map (test_open_border_paths_stay_on_the_map)
    gm_open = GridMap(Grid(occ.shape, 1.0, border="open"), occ)
    pts, length = grid_graph(gm_open).shortest_path((0.5, 3.5), (3.5, 0.5))
    assert math.isinf(length) and len(pts) == 0


@pytest.mark.parametrize("where", ["column", "row", "touching"])
def test_open_border_paths_stay_on_the_map(where):
    """A map whose only connection runs outside the grid (along its edge): with an open border the
    outside is free for clearance, but no planner's path leaves the map, so every planner agrees
    there is no path (the any-angle optimum ran along the edge before)."""
    occ = np.zeros((5, 6), bool)
    if where == "column":
        occ[:, 2] = True         # a full column: the two halves meet only outside the map
    elif where == "row":
        occ[2, :] = True
    else:
        occ[0:3, 2] = True       # a wall from the bottom edge ...
        occ[2:5, 3] = True       # ... and one to the top edge, overlapping (no pinch): only the edges join
    s, t = ((0.5, 2.5), (5.5, 2.5)) if where != "row" else ((2.5, 0.5), (2.5, 4.5))
    assert math.isinf(brute_force(occ, True, s, t))  # the map's free cells: no connection
    assert math.isfinite(brute_force(occ, False, s, t))  # the free plane round the map: one
    for border in ("open", "wall"):
        gm = GridMap(Grid(occ.shape, 1.0, border=border), occ)
        pts, length = grid_graph(gm).shortest_path(s, t)
        assert math.isinf(length) and len(pts) == 0, border
        for name in ("visibility", "wavefront", "wavefront-octile"):
            assert plan(name, gm, s, t).status == "no_path", (border, name)
    # the border still decides the clearance: an open border is no obstacle
    occ2 = np.zeros((4, 4), bool)
    occ2[2, 2] = True
    for border, expect in (("open", math.sqrt(2)), ("wall", 0.5)):  # to the cell (2, 2), or to x = 0
        g2 = grid_graph(GridMap(Grid(occ2.shape, 1.0, border=border), occ2))
        assert g2.clearance([[0.5, 1.0], [1.0, 1.0]]) == pytest.approx(expect)


def test_world_units_and_errors():
    occ = np.zeros((4, 4), bool)
    occ[1:3, 1:3] = True
    gm = GridMap(Grid((4, 4), 0.5, origin=(10.0, -3.0), border="wall"), occ)
    p = plan("visibility", gm, (10.25, -2.75), (11.75, -1.25))
    # in lattice units (0.5, 0.5) -> (3.5, 3.5) round the 2 x 2 block: via corner (1, 3) or (3, 1)
    ref = brute_force(occ, True, (0.5, 0.5), (3.5, 3.5)) * 0.5
    assert p.status == "reached" and p.length == pytest.approx(ref, abs=1e-12)
    assert p.min_clearance == 0.0  # it touches a corner
    assert p.extra["goal"] == (11.75, -1.25)
    with pytest.raises(GridfieldError, match="inside an obstacle"):
        plan("visibility", gm, (10.75, -2.25), (11.75, -1.25))
    with pytest.raises(GridfieldError, match="outside"):
        grid_graph(gm).shortest_path((0.0, 0.0), (11.75, -1.25))


def test_cache_is_per_map_content():
    occ = np.zeros((5, 5), bool)
    occ[2, 1:4] = True
    a = GridMap(Grid((5, 5), 1.0), occ)
    b = GridMap(Grid((5, 5), 1.0), occ.copy())
    cache: dict = {}
    assert grid_graph(a, cache=cache) is grid_graph(b, cache=cache)
    c = GridMap(Grid((5, 5), 1.0), ~occ)
    assert grid_graph(c, cache=cache) is not grid_graph(a, cache=cache)
    p1 = plan("visibility", a, (2.5, 0.5), (2.5, 4.5), cache=cache)
    assert p1.extra["nodes"] == 4 and p1.length == pytest.approx(1 + 2 * math.hypot(1.5, 1.5), abs=1e-12)


# ----------------------------------------------------------------------------------------
# Published any-angle lengths and Moving AI scenarios
# ----------------------------------------------------------------------------------------
def test_polyanya_arena_lengths():
    """All 160 arena.map queries against Polyanya's lengths (corner points, upstream tolerance 1e-4)."""
    import json

    cases = json.loads((TEST_MAPS / "polygon" / "polyanya_arena" / "arena_cases.json").read_text())
    m = read_movingai_map(TEST_MAPS / "movingai" / "arena" / "arena.map.gz")
    H = m.shape[0]
    g = grid_graph(m)
    got = np.array([g.shortest_path((q["start"][0], H - q["start"][1]), (q["goal"][0], H - q["goal"][1]))[1]
                    for q in cases["queries"]])
    want = np.array([q["expected_length"] for q in cases["queries"]])
    assert len(want) == 160
    np.testing.assert_allclose(got, want, atol=1e-4, rtol=0)
    for search in ("lazy", "graph", "polyanya"):
        got = np.array([g.shortest_path((q["start"][0], H - q["start"][1]), (q["goal"][0], H - q["goal"][1]),
                                        search=search)[1] for q in cases["queries"]])
        np.testing.assert_allclose(got, want, atol=1e-4, rtol=0, err_msg=search)


@pytest.mark.parametrize(("name", "n"), [("den312d", 150), ("arena", 100), ("mapf_random-32-32-10", 150)])
def test_lazy_and_polyanya_find_the_graphs_optimum_on_scenarios(name, n):
    """Scenarios spread over small Moving AI maps (400 in all): the lazy search (no visibility graph),
    Polyanya (no visibility graph either) and the graph search give the same length (1e-9 relative)
    and the paths' segments are free; the graph is the reference (itself checked against the brute
    force and Polyanya's published lengths above)."""
    import itertools

    folder = TEST_MAPS / "movingai" / name
    m = read_movingai_map(next(folder.glob("*.map.gz")))
    scen = read_scen(next(folder.glob("*.scen.gz")))
    ok = np.flatnonzero(~scen.no_path)
    idx = ok[np.linspace(0, len(ok) - 1, min(n, len(ok))).astype(int)]
    g = grid_graph(m, cache={})
    assert not g.graph_built and not g.mesh_built  # the per-map part alone so far
    answers = {int(k): g.shortest_path(scen.start_xy[k], scen.goal_xy[k], search="polyanya") for k in idx}
    assert g.mesh_built and not g.graph_built  # Polyanya needs no visibility graph
    for k in idx:
        s, t = scen.start_xy[k], scen.goal_xy[k]
        want = g.shortest_path(s, t, search="graph")[1]
        for search in ("lazy", "polyanya"):
            pts, length = g.shortest_path(s, t, search=search) if search == "lazy" else answers[int(k)]
            assert length == pytest.approx(want, rel=1e-9, abs=1e-12), (name, int(k), search)
            assert all(g.visible(a, b) for a, b in itertools.pairwise(pts))
            assert float(np.hypot(*np.diff(pts, axis=0).T).sum()) == pytest.approx(length, rel=1e-12)
    assert g.graph_built


def test_unknown_search_is_refused():
    from gridfield.core.errors import ParameterError

    g = grid_graph(GridMap(Grid((4, 4), 1.0), np.zeros((4, 4), bool)))
    with pytest.raises(ParameterError, match="search must be one of 'lazy', 'graph', 'polyanya'"):
        g.shortest_path((0.5, 0.5), (3.5, 3.5), search="visibility")


MAPS = ["den312d", "mapf_random-32-32-10", "AR0011SR", "16room_000", "Berlin_0_256", "brc202d"]


@pytest.mark.parametrize("name", MAPS)
def test_movingai_scenarios_within_octile_bounds(name):
    folder = TEST_MAPS / "movingai" / name
    map_file = next(folder.glob("*.map.gz"))
    scen = read_scen(next(folder.glob("*.scen.gz")))
    m = read_movingai_map(map_file)
    occ = m.occupied
    rng = np.random.default_rng(16)
    idx = rng.choice(np.flatnonzero(~scen.no_path), size=12, replace=False)
    cache: dict = {}
    union = None
    for k in idx:
        p = plan_anyangle(m, scen.start_xy[k], scen.goal_xy[k], cache=cache)
        opt, tol = float(scen.optimal[k]), float(scen.tolerance()[k])
        assert p.status == "reached"
        assert p.length <= opt + tol
        # no constant lower bound holds on every map (staircases); on these maps the octile optimum
        # is at most 1.25 times the any-angle one (max seen on the samples: 1.21, den312d)
        assert p.length >= opt / 1.25
        assert p.length >= math.dist(scen.start_xy[k], scen.goal_xy[k]) - 1e-12
        if union is None:
            union = obstacles(occ, True)
            shapely.prepare(union)
            pinches = pinch_points(occ, True)
        assert admissible(p.points[:-1], p.points[1:], union, pinches).all()


@settings(max_examples=25)
@given(st.integers(20, 70), st.integers(20, 70), st.sampled_from([0.05, 0.15, 0.3, 0.5]),
       st.integers(0, 2**32 - 1), st.booleans(), st.sampled_from([3, 4, 8, 32]))
def test_occlusion_culling_changes_nothing(rows, cols, p, seed, wall, block):
    """The nearest-first search with occlusion culling finds exactly the pairs and the distances of
    walking every taut pair (small blocks on these grids, so that its early stop happens)."""
    from gridfield.exact import _anyangle as k
    from gridfield.exact import _occlusion as ko
    from gridfield.exact.anyangle import _buckets, _padded_blocked, convex_corners

    rng = np.random.default_rng(seed)
    occ = rng.random((rows, cols)) < p
    if p == 0.5:  # long walls with gaps, so that some corners see far
        occ[:, ::9] = rng.random((rows, len(range(0, cols, 9)))) < 0.8
    gm = GridMap(Grid((rows, cols), 1.0, border="wall" if wall else "open"), occ)
    B = _padded_blocked(gm)
    vx, vy, qx, qy = convex_corners(B)
    blocks = _buckets(vx, vy, gm.shape, block)  # small blocks: many rings, so the early stop happens
    plain = set(zip(*k.visibility_edges(B, vx, vy, qx, qy), strict=True))
    culled = set(zip(*ko.visibility_edges_culled(B, vx, vy, qx, qy, *blocks), strict=True))
    assert culled == plain
    for _ in range(5):
        # lattice points, half-integers and generic points
        px, py = rng.integers(0, 2 * cols + 1) / 2, rng.integers(0, 2 * rows + 1) / 2
        if rng.random() < 0.3:
            px, py = rng.uniform(0, cols), rng.uniform(0, rows)
        a = k.visible_from(B, px, py, vx, vy, qx, qy)
        b = ko.visible_from_culled(B, ko.run_extents(B), px, py, vx, vy, qx, qy, *blocks)
        np.testing.assert_array_equal(a, b)


def test_benchmark_script_runs_and_checks(capsys):
    """benchmarks/anyangle.py on two small maps: its table, and none of its correctness checks fails."""
    import sys

    bench = Path(__file__).resolve().parent.parent / "benchmarks"
    sys.path.insert(0, str(bench))
    try:
        import anyangle as bench_anyangle
    finally:
        sys.path.remove(str(bench))
    rc = bench_anyangle.main(["--root", str(TEST_MAPS / "movingai"), "--maps", "den312d", "arena", "--queries", "5"])
    out = capsys.readouterr().out
    assert rc == 0
    assert "| den312d | 65 x 81 |" in out and "| arena |" in out


@settings(max_examples=60)
@given(st.integers(1, 12).flatmap(lambda n: st.tuples(
    st.just(n), st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)).filter(lambda e: e[0] != e[1]),
                         max_size=30), st.booleans())))
def test_the_graph_csr_is_a_stable_sort_of_both_directions(case):
    """The linear-time CSR of the graph equals the stable argsort of (ei, ej) + (ej, ei) by first node,
    for edges grouped by ei (as the kernel emits them), and holds the same neighbours otherwise."""
    from gridfield.exact.anyangle import _symmetric_csr

    n, edges, grouped = case
    if grouped:
        edges = sorted(edges, key=lambda e: e[0])
    ei = np.array([e[0] for e in edges], dtype=np.int32)
    ej = np.array([e[1] for e in edges], dtype=np.int32)
    w = np.arange(len(edges), dtype=float) + 0.5
    ptr, idx, wt = _symmetric_csr(n, ei, ej, w)
    rows, cols, ww = np.concatenate([ei, ej]), np.concatenate([ej, ei]), np.concatenate([w, w])
    order = np.argsort(rows, kind="stable")
    assert ptr.tolist() == [0, *np.cumsum(np.bincount(rows, minlength=n)).tolist()]
    if grouped:
        assert idx.tolist() == cols[order].tolist() and wt.tolist() == ww[order].tolist()
    for v in range(n):
        mine = sorted(zip(idx[ptr[v]:ptr[v + 1]].tolist(), wt[ptr[v]:ptr[v + 1]].tolist(), strict=True))
        assert mine == sorted(zip(cols[rows == v].tolist(), ww[rows == v].tolist(), strict=True))


# ----------------------------------------------------------------------------------------
# Polyanya (search="polyanya") and its navigation mesh
# ----------------------------------------------------------------------------------------
@st.composite
def mesh_grids(draw):
    """Random grids up to 30 x 30: random cells, sometimes walls with one-cell gaps (rooms, pinches)."""
    rows = draw(st.integers(1, 30))
    cols = draw(st.integers(1, 30))
    p = draw(st.sampled_from([0.0, 0.1, 0.25, 0.4, 0.55]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    occ = rng.random((rows, cols)) < p
    if draw(st.booleans()):
        k = draw(st.integers(2, 6))
        occ[:, ::k] = rng.random((rows, occ[:, ::k].shape[1])) < 0.85
    return occ, draw(st.booleans()), rng


@settings(max_examples=60, deadline=None)
@given(mesh_grids())
def test_navigation_mesh_is_a_partition_with_matched_edges(case):
    """The mesh's rectangles cover each free cell once and nothing else; their vertices run
    counter-clockwise; every edge with a neighbour is that neighbour's edge reversed, the neighbour
    holds the cell across it, and an edge has none exactly where that cell is blocked or outside
    (so two cells touching at a pinch point are not neighbours); the turning points are the convex
    corners."""
    from gridfield.exact.anyangle import _padded_blocked, convex_corners, navigation_mesh

    occ, wall, rng = case
    rows, cols = occ.shape
    g = grid_graph(GridMap(Grid(occ.shape, 1.0, border="wall" if wall else "open"), occ), cache={})
    split = bool(rng.integers(2))  # either partition (by default the one with fewer rectangles)
    mesh = navigation_mesh(_padded_blocked(GridMap(g.grid, occ)), split=split)
    assert g.mesh.n_polygons <= mesh.n_polygons
    labels = mesh.labels[1:-1, 1:-1]
    assert np.array_equal(labels >= 0, ~occ) and (mesh.labels[[0, -1]] == -1).all() and (mesh.labels[:, [0, -1]] == -1).all()
    for p in range(mesh.n_polygons):
        sl = slice(mesh.pstart[p], mesh.pstart[p + 1])
        x, y = mesh.vx[sl], mesh.vy[sl]
        x0, x1, y0, y1 = int(x.min()), int(x.max()), int(y.min()), int(y.max())
        cells = np.argwhere(labels == p)
        assert len(cells) == (x1 - x0) * (y1 - y0)  # a rectangle of its own cells
        assert cells[:, 0].min() == y0 and cells[:, 1].min() == x0
        area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
        assert (x1 - x0) * (y1 - y0) == area  # counter-clockwise, no vertex off the boundary
    n_slots = len(mesh.vx)
    for k in range(n_slots):
        p = int(np.searchsorted(mesh.pstart, k, side="right") - 1)
        k2 = k + 1 if k + 1 < mesh.pstart[p + 1] else mesh.pstart[p]
        (ax, ay), (bx, by) = (mesh.vx[k], mesh.vy[k]), (mesh.vx[k2], mesh.vy[k2])
        dx, dy = np.sign(bx - ax), np.sign(by - ay)
        assert abs(dx) + abs(dy) == 1  # axis-aligned, not degenerate
        c, r = math.floor((ax + bx + dy) / 2), math.floor((ay + by - dx) / 2)  # the cell on its right
        across = int(labels[r, c]) if 0 <= r < rows and 0 <= c < cols else -1
        assert mesh.nb[k] == across
        if across >= 0:
            j = mesh.pstart[across] + mesh.nbslot[k]
            j2 = j + 1 if j + 1 < mesh.pstart[across + 1] else mesh.pstart[across]
            assert (mesh.vx[j], mesh.vy[j], mesh.vx[j2], mesh.vy[j2]) == (bx, by, ax, ay)
    assert (mesh.degree == np.add.reduceat((mesh.nb >= 0).astype(int), mesh.pstart[:-1])).all() or mesh.n_polygons == 0
    cx, cy, _, _ = convex_corners(_padded_blocked(GridMap(g.grid, occ)))
    assert sorted(np.flatnonzero(mesh.turn).tolist()) == sorted((cy * (cols + 1) + cx).astype(int).tolist())
    lattice = (mesh.vy * (cols + 1) + mesh.vx).astype(int)  # each slot's root number: that of its turning point
    turning = np.flatnonzero(mesh.turn)
    assert mesh.n_roots == len(turning)
    assert np.array_equal(mesh.root, np.where(mesh.turn[lattice] == 1, np.searchsorted(turning, lattice), -1))


@settings(max_examples=80, deadline=None)
@given(mesh_grids(), st.integers(1, 6))
def test_polyanya_equals_the_graph_search(case, n_queries):
    """Polyanya against the graph search on random grids up to 30 x 30, wall and open borders, with
    walls of one-cell gaps (rooms, pinches): the same length (1e-9 relative), ``inf`` and no points
    together, free segments; points on a 1/4 lattice (cell centres, edges, corners, the map's border),
    start == goal too. The kernel is also called directly, without the straight-line shortcut of
    :meth:`AnyAngleGraph.shortest_path` (seeds from a polygon holding both points)."""
    import itertools

    occ, wall, rng = case
    free = np.argwhere(~occ)
    if len(free) == 0:
        return
    g = grid_graph(GridMap(Grid(occ.shape, 1.0, border="wall" if wall else "open"), occ), cache={})
    for _ in range(n_queries):
        a, b = free[rng.integers(len(free))], free[rng.integers(len(free))]
        s = (a[1] + rng.integers(0, 5) / 4, a[0] + rng.integers(0, 5) / 4)
        t = s if rng.random() < 0.1 else (b[1] + rng.integers(0, 5) / 4, b[0] + rng.integers(0, 5) / 4)
        try:
            want = g.shortest_path(s, t, search="graph")[1]
        except GridfieldError:  # a pinch point
            continue
        pts, length = g.shortest_path(s, t, search="polyanya")
        direct, turns, _ = g._polyanya(s[0], s[1], t[0], t[1])  # the kernel alone
        if math.isinf(want):
            assert math.isinf(length) and len(pts) == 0 and math.isinf(direct)
            continue
        assert length == pytest.approx(want, rel=1e-9, abs=1e-12)
        assert direct == pytest.approx(want, rel=1e-9, abs=1e-12)
        path = np.vstack([s, turns, t])
        for q in (pts, path):
            assert all(g.visible(u, v) for u, v in itertools.pairwise(q))
            assert float(np.hypot(*np.diff(q, axis=0).T).sum()) == pytest.approx(want, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize(("name", "n"), [("random512-10-0", 5), ("8room_000", 3)])
def test_polyanya_on_512_maps_equals_the_lazy_search(name, n):
    """A few scenarios of two 512 x 512 Moving AI maps (random obstacles: the most polygons; rooms):
    Polyanya's length equals the lazy search's (1e-9 relative; the lazy search is checked against
    the graph above, whose build here would take seconds), its segments are free, and it builds no
    visibility graph."""
    import itertools

    folder = TEST_MAPS / "movingai" / name
    m = read_movingai_map(next(folder.glob("*.map.gz")))
    scen = read_scen(next(folder.glob("*.scen.gz")))
    ok = np.flatnonzero(~scen.no_path & (scen.optimal > 0))
    idx = ok[np.linspace(len(ok) // 3, len(ok) - 1, n).astype(int)]  # the longer queries
    g = grid_graph(m, cache={})
    for k in idx:
        s, t = scen.start_xy[k], scen.goal_xy[k]
        pts, length = g.shortest_path(s, t, search="polyanya")
        assert length == pytest.approx(g.shortest_path(s, t, search="lazy")[1], rel=1e-9), (name, int(k))
        assert length <= scen.optimal[k] + scen.tolerance()[k]
        assert all(g.visible(a, b) for a, b in itertools.pairwise(pts))
    assert g.mesh_built and not g.graph_built


def test_plan_reports_the_mesh():
    """plan('visibility') with the default search (Polyanya): the mesh's polygons in ``extra``, its build
    counted in ``graph_seconds``, no visibility graph built (no ``edges``)."""
    import gridfield.exact.anyangle as aa

    assert aa.SEARCH == "polyanya"
    occ = np.zeros((6, 6), bool)
    occ[1:5, 3] = True
    gm = GridMap(Grid((6, 6), 1.0, border="wall"), occ)
    cache: dict = {}
    p = plan("visibility", gm, (0.5, 2.5), (5.5, 2.5), cache=cache)
    g = grid_graph(gm, cache=cache)
    assert p.status == "reached" and p.length == pytest.approx(math.hypot(2.5, 1.5) + 1 + math.hypot(1.5, 1.5))  # under the wall
    assert p.extra["polygons"] == g.mesh.n_polygons == 4  # below, left and right of the wall, above
    assert "edges" not in p.extra and not g.graph_built
    assert p.extra["graph_seconds"] == pytest.approx(g.seconds + g.mesh_seconds)


@settings(max_examples=50, deadline=None)
@given(mesh_grids(), st.sampled_from([1e-12, 1e-9, 1e-8, 2e-8, 5e-8, 1e-7, 2e-7, 1e-6]))
def test_polyanya_near_cell_edges(case, offset):
    """Start and goal a hair off cell edges and corners (``offset`` cells): within ``SNAP`` (1e-7)
    Polyanya searches from the edge, so its length is the graph search's to within twice the offset
    (the path keeps the given ends); beyond it, to 1e-9 relative. Before the snapping such points
    (1e-9 to 3e-8 off) missed the optimum by up to 5.7 cells on these grids."""
    from gridfield.exact.anyangle import SNAP

    occ, wall, rng = case
    free = np.argwhere(~occ)
    if len(free) == 0:
        return
    g = grid_graph(GridMap(Grid(occ.shape, 1.0, border="wall" if wall else "open"), occ), cache={})
    for _ in range(30):
        a, b = free[rng.integers(len(free))], free[rng.integers(len(free))]
        s = tuple(float(a[1 - i] + rng.choice([offset, 0.5, 1 - offset])) for i in range(2))
        t = tuple(float(b[1 - i] + rng.choice([offset, 0.5, 1 - offset])) for i in range(2))
        want = g.shortest_path(s, t, search="graph")[1]
        pts, length = g.shortest_path(s, t, search="polyanya")
        if math.isinf(want):
            assert math.isinf(length)
            continue
        tol = 4 * offset if offset <= SNAP else 1e-9 * want
        assert length == pytest.approx(want, abs=tol + 1e-12)
        assert pts[0].tolist() == list(s) and pts[-1].tolist() == list(t)
        assert float(np.hypot(*np.diff(pts, axis=0).T).sum()) == pytest.approx(length, rel=1e-12)


def test_polyanya_answers_other_components_without_a_search():
    """A goal in another connected component of the mesh: ``inf`` at once (no node expanded), where
    the search would expand the whole component of the start."""
    occ = np.zeros((6, 9), bool)
    occ[:, 4] = True  # two halves
    g = grid_graph(GridMap(Grid(occ.shape, 1.0, border="wall"), occ), cache={})
    pts, length, expanded = g._search((0.5, 0.5), (8.5, 5.5), "polyanya")
    assert math.isinf(length) and len(pts) == 0 and expanded == 0
    assert len(set(g.mesh.component.tolist())) == 2
    pts, length, expanded = g._search((0.5, 0.5), (3.5, 5.5), "polyanya")
    assert length == pytest.approx(math.hypot(3, 5)) and expanded == 0  # in sight: no search either


def test_a_graph_with_its_mesh_pickles():
    """The mesh and the search's workspace travel with a pickled graph (no lock inside it)."""
    import pickle

    occ = np.zeros((5, 5), bool)
    occ[1:4, 2] = True
    g = grid_graph(GridMap(Grid((5, 5), 1.0), occ), cache={})
    want = g.shortest_path((0.5, 2.5), (4.5, 2.5))[1]
    g2 = pickle.loads(pickle.dumps(g))
    assert g2.mesh_built and g2.shortest_path((0.5, 2.5), (4.5, 2.5))[1] == want
