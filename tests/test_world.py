"""Vector worlds: parsing every obstacle kind, the B matrix, error messages, bundled seed worlds,
exact distances against shapely."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given
from hypothesis import strategies as st
from shapely.geometry import LineString, Point, Polygon

from gridfield.core.errors import GridfieldError, MapFormatError
from gridfield.geometry.world import CIRCLE_SEGMENTS, World, world_from_dict
from gridfield.io import bundled_map, read_world

SEED000_B = [
    [4, 10, 12, 6, 9, 12, 6, 11, 13, 17, 19, 15],
    [12, 18, 16, 10, 10, 4, 4, 12, 16, 16, 12, 8],
    [1, 1, 1, 1, 2, 2, 2, 3, 3, 3, 3, 3],
]


def world(**kw) -> World:
    data = {"bounds": [0, 0, 10, 10], **kw}
    return world_from_dict(data)


# ----------------------------------------------------------------------------------------
# obstacle kinds
# ----------------------------------------------------------------------------------------
def test_every_obstacle_kind() -> None:
    w = world(obstacles=[
        {"polygon": [[1, 1], [3, 1], [3, 2], [1, 2]]},
        {"circle": {"center": [5, 5], "radius": 1.5}},
        {"segment": [[6, 1], [8, 2]]},
        {"rectangle": [7, 7, 9, 8]},
        {"rectangle": {"min": [0.5, 8], "max": [1.5, 9]}},
        {"rectangle": {"center": [4, 8.5], "size": [2, 1]}},
    ])
    kinds = [(o.id, o.kind) for o in w.obstacles]
    assert kinds == [(1, "polygon"), (2, "circle"), (3, "segment"), (4, "polygon"), (5, "polygon"),
                     (6, "polygon")]
    circle = w.obstacles[1]
    assert circle.center == (5.0, 5.0) and circle.radius == 1.5
    # the outline is inscribed in the exact circle, with 4 * CIRCLE_SEGMENTS vertices
    assert len(circle.vertices) == 4 * CIRCLE_SEGMENTS
    np.testing.assert_allclose(np.hypot(*(circle.vertices - [5, 5]).T), 1.5)
    assert circle.bounds() == (3.5, 3.5, 6.5, 6.5)
    assert w.obstacles[2].geometry.equals(LineString([(6, 1), (8, 2)]))
    for ob, box in zip(w.obstacles[3:6], [(7, 7, 9, 8), (0.5, 8, 1.5, 9), (3, 8, 5, 9)], strict=True):
        assert ob.geometry.equals(shapely.box(*box))
    assert w.border == "open" and w.start is None and w.goal is None


def test_degenerate_b_matrix_obstacles_and_rectangles_are_points_and_segments() -> None:
    # seed 000's B matrix: an obstacle with two vertices is a segment, one vertex a point, collinear a segment
    w = world(b_matrix=[[1, 4, 0, 2, 1, -1, 3], [1, 5, 0, 0, 0, 0, 3], [1, 1, 2, 2, 2, 2, 3]],
              obstacles=[{"rectangle": [1, 1, 1, 3]}])
    assert [o.kind for o in w.obstacles] == ["segment", "segment", "point", "segment"]
    assert w.obstacles[0].geometry.equals(LineString([(1, 1), (4, 5)]))
    assert w.obstacles[1].geometry.equals(LineString([(-1, 0), (2, 0)]))
    assert len(w.obstacles[1].vertices) == 2
    assert w.obstacles[2].geometry.equals(Point(3, 3))


@pytest.mark.parametrize(("vertices", "match"), [
    ([[1, 1], [4, 5]], r"obstacles\[0\]\.polygon \(obstacle 1\) has 2 distinct vertexes; a polygon needs at least 3 "
                       r"\(use segment"),
    ([[2, 7]], r"has 1 distinct vertex; a polygon needs at least 3"),
    ([[3, 3], [3, 3], [3, 3], [4, 4]], r"has 2 distinct vertexes"),
    ([[0, 0], [2, 0], [1, 0], [-1, 0]], r"all vertices are collinear"),
])
def test_polygon_needs_three_distinct_vertices(vertices, match) -> None:
    with pytest.raises(MapFormatError, match=match):
        world(obstacles=[{"polygon": vertices}])


def test_non_convex_polygon_and_closing_vertex() -> None:
    l_shape = [[1, 1], [5, 1], [5, 2], [2, 2], [2, 5], [1, 5], [1, 1]]
    w = world(obstacles=[{"polygon": l_shape}])
    ob = w.obstacles[0]
    assert ob.kind == "polygon"
    assert len(ob.vertices) == 6
    assert ob.geometry.area == pytest.approx(4 + 3)
    assert not ob.geometry.equals(ob.geometry.convex_hull)
    # inside the notch: free; inside the L: distance 0
    np.testing.assert_allclose(ob.distance([[4, 4], [3, 3], [1.5, 4]]), [2.0, 1.0, 0.0])


def test_b_matrix_gives_the_seed_polygons() -> None:
    w = world_from_dict({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B})
    assert [o.id for o in w.obstacles] == [1, 2, 3]
    assert all(o.kind == "polygon" for o in w.obstacles)
    b = np.asarray(SEED000_B, dtype=float)
    for ob in w.obstacles:
        expected = b[:2, b[2] == ob.id].T
        np.testing.assert_array_equal(ob.vertices, expected)


def test_b_matrix_and_obstacles_ids_continue() -> None:
    w = world_from_dict({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B,
                         "obstacles": [{"segment": [[17.5, 10], [17.5, 8]]}]})
    assert [(o.id, o.kind) for o in w.obstacles] == [(1, "polygon"), (2, "polygon"), (3, "polygon"), (4, "segment")]


def test_wall_world_without_obstacles_and_start_goal() -> None:
    w = world_from_dict({"bounds": [0, 0, 4, 3], "border": "wall", "start": [1, 1], "goal": [3, 2],
                         "resolution": 0.5, "params": {"zeta": 2.0}})
    assert w.obstacles == () and w.border == "wall" and w.resolution == 0.5
    assert w.start == (1.0, 1.0) and w.goal == (3.0, 2.0) and w.params == {"zeta": 2.0}
    np.testing.assert_allclose(w.distance([[1, 1], [3.5, 1.5], [2, 2.9]]), [1.0, 0.5, 0.1])


# ----------------------------------------------------------------------------------------
# errors: MapFormatError naming the key and the value
# ----------------------------------------------------------------------------------------
BOWTIE = [[0, 0], [2, 2], [2, 0], [0, 2]]
SYMMETRIC_BOWTIE = [[0, 0], [1, 1], [1, 0], [0, 1]]  # zero signed area


@pytest.mark.parametrize(
    ("data", "match"),
    [
        ({"obstacles": [{"circle": {"center": [1, 1], "radius": 1}}]}, r"bounds: missing"),
        ({"bounds": [0, 0, math.nan, 1], "obstacles": []}, r"bounds: expected \[xmin, ymin, xmax, ymax\].*nan"),
        ({"bounds": [0, -math.inf, 1, 1]}, r"bounds: .*-inf"),
        ({"bounds": [0, 0, 0, 1]}, r"bounds: .*max > min, got \[0, 0, 0, 1\]"),
        ({"bounds": [0, 5, 1, 1]}, r"bounds: .*max > min, got \[0, 5, 1, 1\]"),
        ({"bounds": [0, 0, 1]}, r"bounds: expected \[xmin, ymin, xmax, ymax\]"),
        ({"bounds": "everywhere"}, r"bounds: expected"),
        ({"bounds": [0, 0, 1, 1], "border": "wall", "colour": "red"}, r"colour: unknown key; expected one of"),
        ({"bounds": [0, 0, 1, 1], "border": "wall", 3: 4}, r"3: unknown key"),
        ({"bounds": [0, 0, 1, 1], "border": "fence"}, r"border: expected one of \['open', 'wall'\], got 'fence'"),
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"blob": [[1, 1]]}]}, r"obstacles\[0\]: unknown obstacle kind 'blob'"),
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"polygon": BOWTIE}]}, r"obstacles\[0\]\.polygon \(obstacle 1\) is not a simple polygon as given .*set vertex_order: sort"),
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"polygon": SYMMETRIC_BOWTIE}]},
         r"obstacles\[0\]\.polygon \(obstacle 1\) is not a simple polygon as given .*set vertex_order: sort"),
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"polygon": [[1, 1], [2, "x"], [3, 1]]}]},
         r"obstacles\[0\]\.polygon\[1\] must be a point \[x, y\]"),
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"circle": {"center": [1, 1], "radius": -1}}]},
         r"obstacles\[0\]\.circle\.radius must be a positive number, got -1"),
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"circle": {"center": [1, 1], "radius": 0}}]},
         r"obstacles\[0\]\.circle\.radius must be a positive number, got 0"),
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"circle": {"center": [1, 1]}}]},
         r"obstacles\[0\]\.circle must be \{center: \[x, y\], radius: r\}"),
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"segment": [[1, 1], [2, 2], [3, 3]]}]},
         r"obstacles\[0\]\.segment must have exactly two points, got 3"),
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"rectangle": [3, 3, 1, 1]}]},
         r"obstacles\[0\]\.rectangle needs finite min <= max"),
        ({"bounds": [0, 0, 9, 9], "obstacles": {"polygon": [[1, 1], [2, 1], [2, 2]]}},
         r"obstacles: expected a list of obstacles"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B[:2]}, r"b_matrix must be three rows .*got shape \(2, 12\)"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": [*SEED000_B[:2], [1, 1, 1, 1, 2, 2, 2, 3, 3, 3, 3, 3.5]]},
         r"b_matrix: the third row holds obstacle ids and must be integers, got .*3\.5"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": [*SEED000_B[:2], [0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 2, 2]]},
         r"b_matrix: .*obstacle ids, which must be integers >= 1, got \[0, 1, 2\]"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": [[1, 2, math.nan], [1, 2, 3], [1, 1, 1]]},
         r"b_matrix must hold finite numbers"),
        ({"bounds": [0, 0, 9, 9]}, r"the world is empty \(no obstacles and an open border\)"),
        ({"bounds": [0, 0, 9, 9], "obstacles": []}, r"the world is empty"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B, "start": [30, 1]},
         r"start \(30, 1\) lies outside the world bounds \[0, 0, 25, 20\]"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B, "goal": [1, -0.5]},
         r"goal \(1, -0.5\) lies outside the world bounds"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B, "goal": [9, 6]}, r"goal \(9, 6\) lies inside obstacle 2"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B, "start": [12, 4]},
         r"start \(12, 4\) lies inside obstacle 2"),  # on a vertex counts as inside
        ({"bounds": [0, 0, 9, 9], "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}], "start": [5.5, 5.5]},
         r"start \(5.5, 5.5\) lies inside obstacle 1 \(circle\)"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B, "start": [math.nan, 1]},
         r"start must be finite numbers, got \[nan, 1\]"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B, "goal": [1, math.inf]}, r"goal must be finite numbers"),
        ({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B, "goal": [1, 2, 3]}, r"goal must be a point \[x, y\]"),
        ({"bounds": [0, 0, 9, 9], "border": "wall", "resolution": -0.1}, r"resolution: must be a positive number"),
        ({"bounds": [0, 0, 9, 9], "border": "wall", "params": {"eta": math.nan}}, r"params\.eta: must not be NaN"),
        ([1, 2, 3], r"a world file must be a YAML mapping"),
    ],
)
def test_bad_world_data(data: object, match: str) -> None:
    with pytest.raises(MapFormatError, match=match):
        world_from_dict(data)


def test_errors_name_the_source() -> None:
    with pytest.raises(MapFormatError, match=r"^worlds/a\.yaml: bounds: missing"):
        world_from_dict({"obstacles": []}, source="worlds/a.yaml")
    with pytest.raises(MapFormatError, match=r"^worlds/a\.yaml: obstacles\[1\]: unknown obstacle kind"):
        world_from_dict({"bounds": [0, 0, 1, 1], "obstacles": [{"polygon": [[0, 0], [1, 0], [0, 1]]}, {"x": 1}]},
                        source="worlds/a.yaml")


def test_check_point() -> None:
    w = world_from_dict({"bounds": [0, 0, 25, 20], "b_matrix": SEED000_B})
    np.testing.assert_array_equal(w.check_point("start", (1, 10)), [1, 10])
    assert w.contains_free((1, 10)) and not w.contains_free((9, 6)) and not w.contains_free((26, 1))
    with pytest.raises(GridfieldError, match="start must be two finite numbers"):
        w.check_point("start", (1, np.nan))


# ----------------------------------------------------------------------------------------
# bundled seed worlds (numbers from the comments in the files)
# ----------------------------------------------------------------------------------------
def test_read_seed000() -> None:
    w = read_world(bundled_map("seed000.yaml"))
    assert w.bounds == (0, 0, 25, 20) and w.border == "open" and w.resolution == 0.05
    assert [o.id for o in w.obstacles] == [1, 2, 3]
    assert w.obstacles[1].geometry.equals(Polygon([(9, 10), (12, 4), (6, 4)]))
    assert w.start == (1.0, 10.0) and w.goal == (22.0, 12.0)
    p = w.params
    assert (p["zeta"], p["eta"], p["q_star"], p["repulsive_power"], p["step"], p["tolerance"]) == (1, 1, 2, 3, 0.1, 0.1)
    assert p["d_star"] == math.inf
    assert w.source.endswith("seed000.yaml")


def test_read_seed000_segment() -> None:
    w = read_world(bundled_map("seed000_segment.yaml"))
    assert [(o.id, o.kind) for o in w.obstacles] == [(1, "polygon"), (2, "polygon"), (3, "polygon"), (4, "segment")]
    assert w.obstacles[3].geometry.equals(LineString([(17.5, 10), (17.5, 8)]))
    # the seed's local minimum (16.97, 9.028) is free, 0.53 left of the segment
    assert w.contains_free((16.97, 9.028))
    assert w.obstacles[3].distance([[16.97, 9.028]])[0] == pytest.approx(0.53)


def test_read_seed003_circles() -> None:
    w = read_world(bundled_map("seed003_circles.yaml"))
    assert w.bounds == (-5, -5, 5, 5) and w.resolution == 0.4
    assert [(o.kind, o.center, o.radius) for o in w.obstacles] == [("circle", (1.0, 0.0), 2.0), ("circle", (-1.0, 0.0), 2.0)]
    assert w.obstacles[0].geometry.intersects(w.obstacles[1].geometry)  # they overlap
    assert w.start == (0.0, 4.0) and w.goal == (0.0, -4.0)
    assert (w.params["ka"], w.params["kr"], w.params["ko"], w.params["sample_radius"]) == (25, 30, 5, 2.1)
    np.testing.assert_allclose(w.distance([[0, 4], [0, 0], [4, 0]]), [math.hypot(1, 4) - 2, 0, 1])


# ----------------------------------------------------------------------------------------
# exact distances against shapely
# ----------------------------------------------------------------------------------------
MIXED = {
    "bounds": [-2, -1, 12, 9],
    "obstacles": [
        {"polygon": [[1, 1], [5, 1], [5, 2], [2, 2], [2, 5], [1, 5]]},
        {"circle": {"center": [8, 6], "radius": 1.25}},
        {"segment": [[6, 0], [9, 3]]},
        {"point": [10, 8]},
        {"rectangle": [3, 6, 4, 8]},
    ],
}


def _brute_distance(w: World, p: np.ndarray) -> np.ndarray:
    d = np.full(len(p), np.inf)
    for ob in w.obstacles:
        if ob.kind == "circle":
            assert ob.center is not None and ob.radius is not None
            dist = [max(math.dist(q, ob.center) - ob.radius, 0.0) for q in p]
        else:
            dist = [ob.geometry.distance(Point(q)) for q in p]
        d = np.minimum(d, dist)
    if w.border == "wall":
        xmin, ymin, xmax, ymax = w.bounds
        frame = LineString([(xmin, ymin), (xmax, ymin), (xmax, ymax), (xmin, ymax), (xmin, ymin)])
        d = np.minimum(d, [frame.distance(Point(q)) for q in p])
    return d


@given(st.lists(st.tuples(st.floats(-2, 12), st.floats(-1, 9)), min_size=1, max_size=25), st.booleans())
def test_distance_matches_shapely(pts: list, wall: bool) -> None:
    w = world_from_dict({**MIXED, "border": "wall" if wall else "open"})
    p = np.asarray(pts, dtype=float)
    np.testing.assert_allclose(w.distance(p), _brute_distance(w, p), rtol=1e-12, atol=1e-12)


def test_distance_is_zero_inside_and_on_obstacles() -> None:
    w = world_from_dict(MIXED)
    np.testing.assert_array_equal(w.distance([[1.5, 3], [1, 1], [8, 6], [9.25, 6], [7.5, 1.5], [10, 8]]), 0.0)


# ----------------------------------------------------------------------------------------
# vertex order (seed 001's VerticesSorter)
# ----------------------------------------------------------------------------------------
@given(st.lists(st.tuples(st.integers(-50, 50), st.integers(-50, 50)), min_size=3, max_size=12, unique=True),
       st.randoms(use_true_random=False))
def test_vertex_order_sort_recovers_a_convex_polygon_from_shuffled_vertices(pts, rnd) -> None:
    hull = shapely.MultiPoint(pts).convex_hull
    if not isinstance(hull, Polygon) or hull.area == 0:
        return
    v = [list(c) for c in hull.exterior.coords[:-1]]
    rnd.shuffle(v)
    w = world(bounds=[-60, -60, 60, 60], vertex_order="sort", obstacles=[{"polygon": v}])
    assert w.obstacles[0].geometry.equals(hull)  # the same polygon, whatever order the file listed


def test_vertex_order_per_file_and_per_polygon() -> None:
    shuffled = [[1, 1], [2, 2], [2, 1], [1, 2]]  # a square listed as a bow-tie
    with pytest.raises(MapFormatError, match=r"obstacles\[1\]\.polygon \(obstacle 2\) is not a simple polygon as "
                                             r"given .*set vertex_order: sort"):
        world(obstacles=[{"polygon": [[5, 5], [6, 5], [6, 6]]}, {"polygon": shuffled}])
    square = shapely.box(1, 1, 2, 2)
    assert world(vertex_order="sort", obstacles=[{"polygon": shuffled}]).obstacles[0].geometry.equals(square)
    assert world(obstacles=[{"polygon": {"vertices": shuffled, "vertex_order": "sort"}}]).obstacles[0].geometry.equals(
        square)
    with pytest.raises(MapFormatError, match=r"not a simple polygon as given"):
        world(vertex_order="sort", obstacles=[{"polygon": {"vertices": shuffled, "vertex_order": "as_given"}}])
    # a non-convex polygon listed in order is kept as given
    comb = [[0, 0], [5, 0], [5, 3], [4, 3], [4, 1], [3, 1], [3, 3], [2, 3], [2, 1], [1, 1], [1, 3], [0, 3]]
    assert world(obstacles=[{"polygon": comb}]).obstacles[0].geometry.is_valid
    # the seed 000 B matrix sorts too
    b = [[1, 2, 2, 1], [1, 2, 1, 2], [1, 1, 1, 1]]
    assert world(vertex_order="sort", b_matrix=b).obstacles[0].geometry.equals(square)
    with pytest.raises(MapFormatError, match=r"vertex_order: expected one of \['as_given', 'sort'\], got 'sorted'"):
        world(vertex_order="sorted", obstacles=[{"polygon": shuffled}])
    with pytest.raises(MapFormatError, match=r"obstacles\[0\]\.polygon\.vertex_order: expected one of"):
        world(obstacles=[{"polygon": {"vertices": shuffled, "vertex_order": 1}}])
    with pytest.raises(MapFormatError, match=r"obstacles\[0\]\.polygon must be a list of points or a mapping"):
        world(obstacles=[{"polygon": {"points": shuffled}}])
    c = world(obstacles=[{"polygon": {"vertices": [[1, 1], [3, 1], [3, 3]], "center": [2.5, 1.5]}}]).obstacles[0]
    assert c.star_center == (2.5, 1.5)


def test_seed001_world_lists_vertices_out_of_order_and_reaches_the_goal() -> None:
    import yaml

    path = bundled_map("seed001.yaml")
    data = yaml.safe_load(path.read_text())
    assert data["vertex_order"] == "sort"
    with pytest.raises(MapFormatError, match=r"set vertex_order: sort"):
        world_from_dict({**data, "vertex_order": "as_given"})
    w = read_world(path)
    for ob, listed in zip(w.obstacles, data["obstacles"], strict=True):
        assert ob.geometry.is_valid and ob.geometry.equals(shapely.MultiPoint(listed["polygon"]).convex_hull)
    assert {k: w.params[k] for k in ("zeta", "d_star", "eta", "q_star")} == {"zeta": 0.8, "d_star": 2.0, "eta": 0.8,
                                                                              "q_star": 2.0}  # seed 001's
    from gridfield.planners import plan

    p = plan("potential", w, w.start, w.goal)
    assert p.reached and w.clearance(p.points) > 0
