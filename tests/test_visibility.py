"""Visibility-graph planner: external fixtures with known optimal lengths, edge cases, brute force."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
import shapely
from scipy.sparse.csgraph import dijkstra
from shapely.geometry import LineString, Polygon

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.path import path_length
from gridfield.exact.visibility import (
    CIRCLE_OUTLINE_EXCESS,
    plan_visibility,
    visibility_graph,
    world_from_polygon_environment,
)
from gridfield.geometry.world import world_from_dict
from gridfield.planners import plan


def assert_valid_path(vg, pts, length, start, goal):
    """The returned polyline starts and ends right, has the reported length and is admissible."""
    assert np.allclose(pts[0], start) and np.allclose(pts[-1], goal)
    assert path_length(pts) == pytest.approx(length, rel=1e-12, abs=1e-12)
    if len(pts) > 1:
        assert vg.visible(pts[:-1], pts[1:]).all()


# ----------------------------------------------------------------------------------------
# extremitypathfinder environments (closed free space; pinch points may be passed)
# ----------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def ept_cases(test_maps):
    return json.loads((test_maps / "polygon" / "extremitypathfinder" / "cases.json").read_text())


def test_extremitypathfinder_all_queries_both_directions(ept_cases):
    checked = 0
    for env in ept_cases["environments"]:
        world = world_from_polygon_environment(env["boundary"], env["holes"], source=env["name"])
        vg = visibility_graph(world, pinch="pass")
        for q in env["queries"]:
            for s, g in ((q["start"], q["goal"]), (q["goal"], q["start"])):
                pts, length = vg.shortest_path(s, g)
                if q["expected_length"] is None:  # no path exists
                    assert math.isinf(length) and pts.shape == (0, 2), (env["name"], s, g)
                else:
                    assert length == pytest.approx(q["expected_length"], rel=1e-6, abs=1e-12), (env["name"], s, g)
                    assert_valid_path(vg, pts, length, s, g)
                checked += 1
    assert checked == 2 * 39


def test_extremitypathfinder_no_path_gives_no_path_status(ept_cases):
    (env,) = [e for e in ept_cases["environments"] if e["name"] == "separated_env"]
    world = world_from_polygon_environment(env["boundary"], env["holes"])
    q = env["queries"][0]
    p = plan_visibility(world, q["start"], q["goal"], {})
    assert p.status == "no_path" and np.allclose(p.points, [q["start"]])


def test_extremitypathfinder_invalid_queries_raise(ept_cases):
    (env,) = [e for e in ept_cases["environments"] if e.get("invalid_queries")]
    vg = visibility_graph(world_from_polygon_environment(env["boundary"], env["holes"]), pinch="pass")
    assert len(env["invalid_queries"]) == 14
    for q in env["invalid_queries"]:
        assert q["expected"].startswith("ValueError")
        with pytest.raises(GridfieldError, match="outside the free space"):  # a ValueError subclass
            vg.shortest_path(q["start"], q["goal"])


def test_extremitypathfinder_pinch_query_needs_the_pass_rule(ept_cases):
    # grid_env: cells (6,5) and (7,6) meet diagonally at (7, 6) between two blocked cells
    (env,) = [e for e in ept_cases["environments"] if e["name"] == "grid_env"]
    world = world_from_polygon_environment(env["boundary"], env["holes"])
    s, g = [6.5, 5.5], [7.5, 6.5]
    assert visibility_graph(world, pinch="pass").shortest_path(s, g)[1] == pytest.approx(math.sqrt(2))
    blocked = visibility_graph(world, pinch="block").shortest_path(s, g)[1]
    assert blocked > math.sqrt(2) + 1


# ----------------------------------------------------------------------------------------
# Polyanya: arena.map navigation mesh, 160 scenario pairs
# ----------------------------------------------------------------------------------------
def test_polyanya_arena_all_160(test_maps):
    data = json.loads((test_maps / "polygon" / "polyanya_arena" / "arena_cases.json").read_text())
    poly = data["polygons_from_mesh"]
    vg = visibility_graph(world_from_polygon_environment(poly["boundary"], poly["holes"]))
    assert len(data["queries"]) == 160
    for q in data["queries"]:
        pts, length = vg.shortest_path(q["start"], q["goal"])
        # upstream lengths carry 6 significant digits: ours rounds to exactly them
        assert float(f"{length:.6g}") == q["expected_length"], (q, length)
        assert abs(length - q["expected_length"]) <= 1e-4  # upstream's own tolerance
        assert length == pytest.approx(q["independent_visgraph_length"], rel=1e-9)
        assert length <= q["octile_length_from_scen_no_corner_cutting"] * (1 + 5e-6)  # 6 significant digits
        assert_valid_path(vg, pts, length, q["start"], q["goal"])
        assert vg.shortest_path(q["goal"], q["start"])[1] == pytest.approx(length, rel=1e-12)


# ----------------------------------------------------------------------------------------
# Polyanya C++ tests: tiny meshes with pinch vertices (no squeezing through a point)
# ----------------------------------------------------------------------------------------
def read_mesh_free_space(path):
    """Union of the polygons of a Polyanya v2 mesh (the free space)."""
    tok = path.read_text().split()
    assert tok[:2] == ["mesh", "2"]
    n_vertices, n_polygons = int(tok[2]), int(tok[3])
    i, vertices, polygons = 4, [], []
    for _ in range(n_vertices):
        vertices.append((float(tok[i]), float(tok[i + 1])))
        i += 3 + int(tok[i + 2])
    for _ in range(n_polygons):
        k = int(tok[i])
        polygons.append(Polygon([vertices[int(j)] for j in tok[i + 1:i + 1 + k]]))
        i += 1 + 2 * k
    assert i == len(tok)
    return shapely.union_all(polygons)


def test_polyanya_cpp_tests(test_maps):
    base = test_maps / "polygon" / "polyanya_cpp_tests"
    cases = json.loads((base / "cases.json").read_text())["cases"]
    kinds = {"exact": 0, "approximate": 0, "ambiguous": 0}
    for c in cases:
        free = read_mesh_free_space(base / c["mesh"])
        assert free.geom_type == "Polygon"
        world = world_from_polygon_environment(free.exterior.coords, [r.coords for r in free.interiors])
        vg = visibility_graph(world)  # pinch="block": Polyanya's rule
        if c["expected"] == -1:
            # start or goal exactly on the pinch vertex (1, 1): documented as an error
            with pytest.raises(GridfieldError, match="pinch point"):
                vg.shortest_path(c["start"], c["goal"])
            kinds["ambiguous"] += 1
            continue
        pts, length = vg.shortest_path(c["start"], c["goal"])
        assert_valid_path(vg, pts, length, c["start"], c["goal"])
        assert length == pytest.approx(c["independent"], rel=1e-9)
        if "approximate" in c.get("note", ""):
            # Upstream wrote the idealised length through the pinch vertex's neighbours; start and
            # goal sit delta*sqrt(2) off the pinch vertex (delta = 0.001, 0.01), which changes the
            # length by at most 2*sqrt(2)*delta.
            delta = abs(c["start"][0] - 1.0)
            assert abs(length - c["expected"]) <= 2 * math.sqrt(2) * delta
            # and it does not squeeze through the pinch (that would be 2*sqrt(2)*delta long)
            assert length > 1.0
            kinds["approximate"] += 1
        else:
            assert length == pytest.approx(c["expected"], rel=1e-9)
            kinds["exact"] += 1
    assert kinds == {"exact": 4, "approximate": 2, "ambiguous": 3}


# ----------------------------------------------------------------------------------------
# Edge cases on hand-made worlds
# ----------------------------------------------------------------------------------------
def test_segment_blocks_crossing_but_not_its_end_points():
    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"segment": [[5, 2], [5, 8]]}]})
    vg = visibility_graph(w)
    assert vg.visible([[4, 5], [4, 1], [4, 7]], [[6, 5], [6, 9], [6, 3]]).tolist() == [False, False, False]
    # round an end point, from an end along it, and along its whole length (a zero-width wall)
    assert vg.visible([[4, 8], [5, 8], [5, 9]], [[6, 8], [5, 4], [5, 1]]).tolist() == [True, True, True]
    pts, length = vg.shortest_path([4, 5], [6, 5])
    assert length == pytest.approx(2 * math.hypot(1, 3))
    assert pts.tolist() == [[4, 5], [5, 8], [6, 5]]


def test_segment_end_on_polygon_edge_is_a_pinch():
    # a wall from the square's right edge: a path along the edge through the junction would
    # cross from below the wall to above it through a single point
    w = world_from_dict({"bounds": [0, 0, 10, 10],
                         "obstacles": [{"rectangle": [2, 2, 4, 6]}, {"segment": [[4, 4], [7, 4]]}]})
    s, g = [4, 3], [4, 5]
    block = visibility_graph(w).shortest_path(s, g)[1]
    assert block == pytest.approx(2 * math.hypot(3, 1))  # round the wall's free end (7, 4)
    assert visibility_graph(w, pinch="pass").shortest_path(s, g)[1] == pytest.approx(2.0)
    with pytest.raises(GridfieldError, match="pinch point"):
        visibility_graph(w).shortest_path([4, 4], g)


def test_start_on_a_segment_is_ambiguous_under_block():
    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"segment": [[5, 2], [5, 8]]}]})
    with pytest.raises(GridfieldError, match="segment obstacle 1"):
        visibility_graph(w).shortest_path([5, 5], [9, 9])
    assert visibility_graph(w, pinch="pass").shortest_path([5, 5], [6, 5])[1] == pytest.approx(1.0)


def test_corner_touching_squares():
    w = world_from_dict({"bounds": [0, 0, 4, 4], "border": "wall",
                         "obstacles": [{"rectangle": [1, 1, 2, 2]}, {"rectangle": [2, 2, 3, 3]}]})
    s, g = [1.5, 2.5], [2.5, 1.5]
    assert visibility_graph(w, pinch="pass").shortest_path(s, g)[1] == pytest.approx(math.sqrt(2))
    pts, length = visibility_graph(w).shortest_path(s, g)
    assert length == pytest.approx(2 + math.sqrt(2))  # round a square: (1, 2), (1, 1), (2, 1) or (2, 3), (3, 3), (3, 2)
    assert len(pts) == 5
    # touching the pinch from one side and leaving on the same side is fine
    assert visibility_graph(w).shortest_path([1.5, 2.5], [1.5, 3.5])[1] == pytest.approx(1.0)


def test_overlapping_obstacles_act_as_their_union():
    w = world_from_dict({"bounds": [0, 0, 10, 10],
                         "obstacles": [{"rectangle": [2, 2, 6, 4]}, {"rectangle": [4, 3, 8, 8]}]})
    vg = visibility_graph(w)
    assert not vg.visible([3, 3.5], [5, 3.5]).any()  # along the overlap, inside the union
    pts, length = vg.shortest_path([1, 3], [9, 3])
    expected = math.hypot(1, 1) + 4 + math.hypot(3, 1)  # below: (2, 2), (6, 2), then straight to the goal
    assert length == pytest.approx(expected)
    assert_valid_path(vg, pts, length, [1, 3], [9, 3])


def test_circle_detour_within_the_stated_bound():
    r = 2.0
    w = world_from_dict({"bounds": [-10, -10, 10, 10], "obstacles": [{"circle": {"center": [0, 0], "radius": r}}]})
    s, g = np.array([-6.0, 0.0]), np.array([6.0, 0.0])
    pts, length = visibility_graph(w).shortest_path(s, g)
    tangent = math.sqrt(36 - r * r)
    wrapped = math.pi - 2 * math.acos(r / 6)
    exact = 2 * tangent + r * wrapped
    assert exact <= length <= exact + wrapped * r * CIRCLE_OUTLINE_EXCESS
    assert w.clearance(pts) >= 0.0
    assert w.distance(pts).min() >= -1e-12  # every vertex outside the true circle


def test_no_path_and_plan_through_the_registry():
    w = world_from_dict({"bounds": [0, 0, 10, 10], "border": "wall",
                         "obstacles": [{"rectangle": [4, 0, 5, 10]}]})
    p = plan("visibility", w, [1, 1], [9, 1])
    assert p.status == "no_path" and p.points.shape == (1, 2)
    w2 = world_from_dict({"bounds": [0, 0, 10, 10], "border": "open",
                          "obstacles": [{"rectangle": [4, 0, 5, 10]}]})
    p2 = plan("visibility", w2, [1, 1], [9, 1])  # open border: round the wall outside the bounds
    assert p2.status == "reached" and p2.length == pytest.approx(math.hypot(3, 1) + 1 + math.hypot(4, 1))
    assert p2.min_clearance == 0.0 and p2.planner == "visibility"


def test_bad_input():
    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 4, 6, 6]}]})
    with pytest.raises(ParameterError, match="pinch must be one of 'block', 'pass'"):
        visibility_graph(w, pinch="squeeze")
    vg = visibility_graph(w)
    with pytest.raises(GridfieldError, match=r"start \(5, 5\) lies outside the free space: inside obstacle 1"):
        vg.shortest_path([5, 5], [1, 1])
    with pytest.raises(GridfieldError, match="goal must be two finite numbers"):
        vg.shortest_path([1, 1], [np.nan, 1])
    assert vg.shortest_path([4, 5], [4, 5])[1] == 0.0  # on an edge, same point
    with pytest.raises(GridfieldError, match="not a simple polygon"):
        world_from_polygon_environment([[0, 0], [1, 1], [1, 0], [0, 1]])


# ----------------------------------------------------------------------------------------
# Fast graph vs a slow reference: every vertex pair, plain shapely predicates
# ----------------------------------------------------------------------------------------
def brute_force_length(obstacles, start, goal):
    union = shapely.union_all(obstacles)
    pts = [tuple(start), tuple(goal)] + [tuple(v) for ob in obstacles for v in np.asarray(ob.exterior.coords)[:-1]]
    n = len(pts)
    mat = np.zeros((n, n))
    for i, j in itertools.combinations(range(n), 2):
        seg = LineString([pts[i], pts[j]])
        if seg.length > 0 and not shapely.relate_pattern(seg, union, "T********"):
            mat[i, j] = mat[j, i] = seg.length
    return dijkstra(mat, directed=False, indices=0)[1]


@pytest.mark.parametrize("seed", range(12))
def test_matches_brute_force_on_random_polygon_worlds(seed):
    rng = np.random.default_rng(seed)
    obstacles = []
    for _ in range(rng.integers(2, 7)):
        c = rng.uniform(1, 9, 2)
        k = rng.integers(3, 7)
        ang = np.sort(rng.uniform(0, 2 * np.pi, k))
        rad = rng.uniform(0.3, 1.8, k)
        poly = Polygon(c + np.column_stack([rad * np.cos(ang), rad * np.sin(ang)]))
        if poly.is_valid and poly.area > 0.05:
            obstacles.append(poly)
    w = world_from_dict({"bounds": [0, 0, 10, 10],
                         "obstacles": [{"polygon": np.asarray(p.exterior.coords)[:-1].tolist()} for p in obstacles]})
    vg = visibility_graph(w)
    union = shapely.union_all(obstacles)
    done = 0
    while done < 5:
        s, g = rng.uniform(0, 10, 2), rng.uniform(0, 10, 2)
        if union.contains(shapely.points(s)) or union.contains(shapely.points(g)):
            continue
        _, length = vg.shortest_path(s, g)
        assert length == pytest.approx(brute_force_length(obstacles, s, g), rel=1e-9)
        done += 1
