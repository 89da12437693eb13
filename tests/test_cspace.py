"""Configuration space: Minkowski sums (hull vs star algorithm vs the definition), C-space of
worlds and grids, disc inflation."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import assume, given
from hypothesis import strategies as st
from scipy import ndimage
from shapely.geometry import Point, Polygon

from gridfield.core.errors import ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.cspace import (
    cspace_grid,
    cspace_world,
    inflate_grid,
    inflate_world,
    minkowski_obstacle,
    star_algorithm,
)
from gridfield.geometry.rasterize import rasterize, rasterize_geometry
from gridfield.geometry.world import CIRCLE_SEGMENTS, world_from_dict
from gridfield.io import bundled_map, read_world

BLOCK = np.ones((3, 3), bool)
coord = st.floats(-4, 4, allow_nan=False, allow_infinity=False, allow_subnormal=False)


def as_geom(v: np.ndarray):
    v = np.asarray(v)
    if len(v) == 1:
        return Point(v[0])
    if len(v) == 2:
        return shapely.LineString(v)
    return Polygon(v)


@st.composite
def convex_polygons(draw, min_points: int = 1):
    """Convex hull vertices of random points, in a random orientation and starting vertex;
    sometimes a point or a segment."""
    n = draw(st.integers(min_points, 8))
    # rounded: GEOS's hull of points a subnormal distance apart can be a non-simple ring
    pts = np.round(np.array([[draw(coord), draw(coord)] for _ in range(n)]), 6)
    hull = shapely.convex_hull(shapely.multipoints(pts))
    if isinstance(hull, Polygon):
        v = np.asarray(hull.exterior.coords)[:-1]
        assume(hull.area > 1e-3)
    else:
        v = np.unique(np.asarray(hull.coords), axis=0)
        assume(len(v) == 1 or np.hypot(*(v[1] - v[0])) > 1e-3)
    if draw(st.booleans()):
        v = v[::-1]
    return np.roll(v, draw(st.integers(0, len(v))), axis=0)


# ----------------------------------------------------------------------------------------
# Minkowski sums
# ----------------------------------------------------------------------------------------
@given(convex_polygons(), convex_polygons())
def test_star_algorithm_equals_hull_of_differences(obstacle, robot) -> None:
    hull = minkowski_obstacle(obstacle, robot)
    star = star_algorithm(obstacle, robot)
    assert hull.shape == star.shape
    np.testing.assert_allclose(star, hull, atol=1e-9)
    if len(hull) >= 3:
        a, b = Polygon(hull), Polygon(star)
        assert a.is_valid and b.is_valid
        assert a.symmetric_difference(b).area <= 1e-9 * max(a.area, 1.0)
        # counter-clockwise, lowest vertex first
        assert a.exterior.is_ccw
        assert tuple(hull[0][::-1]) == min(tuple(p[::-1]) for p in hull)


@given(convex_polygons(min_points=3), convex_polygons(), st.lists(st.tuples(st.floats(-10, 10), st.floats(-10, 10)),
                                                                   min_size=1, max_size=20))
def test_c_obstacle_is_where_the_robot_hits_the_obstacle(obstacle, robot, qs) -> None:
    """The definition: q is in the C-obstacle iff the robot placed at q (q + R) meets O."""
    c_obs = as_geom(star_algorithm(obstacle, robot))
    o, r = as_geom(obstacle), as_geom(robot)
    for q in qs:
        placed = shapely.affinity.translate(r, *q)
        if c_obs.boundary.distance(Point(q)) < 1e-7:
            continue
        assert c_obs.intersects(Point(q)) == placed.intersects(o), q


def test_reference_point_and_degenerate_robots() -> None:
    square = [[0, 0], [2, 0], [2, 2], [0, 2]]
    # a point robot at its reference point: the C-obstacle is the obstacle itself
    np.testing.assert_array_equal(star_algorithm(square, [[0, 0]]), square)
    np.testing.assert_array_equal(minkowski_obstacle(square, [[0, 0]]), square)
    # a point robot off its reference point: the obstacle shifted the other way
    np.testing.assert_array_equal(star_algorithm(square, [[1, 2]]), np.array(square) - [1, 2])
    # a robot extending to the right of its reference point: the C-obstacle grows to the left
    bar = [[0, 0], [3, 0], [3, 0.5], [0, 0.5]]
    for f in (star_algorithm, minkowski_obstacle):
        assert as_geom(f(square, bar)).bounds == (-3.0, -0.5, 2.0, 2.0)
    # point + point, segment + parallel segment
    np.testing.assert_array_equal(star_algorithm([[1, 1]], [[1, 1]]), [[0, 0]])
    np.testing.assert_array_equal(star_algorithm([[0, 0], [1, 0]], [[0, 0], [2, 0]]), [[-2, 0], [1, 0]])
    np.testing.assert_array_equal(minkowski_obstacle([[0, 0], [1, 0]], [[0, 0], [2, 0]]), [[-2, 0], [1, 0]])
    # collinear input vertices and a repeated closing vertex are accepted
    np.testing.assert_array_equal(star_algorithm([[0, 0], [1, 0], [2, 0], [2, 2], [0, 2], [0, 0]], [[0, 0]]), square)


PENTAGRAM = [[math.cos(a), math.sin(a)] for a in np.arange(5) * 4 * np.pi / 5]


@pytest.mark.parametrize("f", [minkowski_obstacle, star_algorithm])
@pytest.mark.parametrize(
    ("robot", "match"),
    [
        ([[0, 0], [2, 0], [1, 0.5], [1, 2]], r"robot_vertices must be a convex polygon; vertex \(1.0, 0.5\) is reflex"),
        ([[0, 0], [2, 0], [2, 2], [1, 1], [0, 2]], "robot_vertices must be a convex polygon"),
        (PENTAGRAM, "robot_vertices winds around 2 times"),
        ([[0, 0], [2, 0], [1, 0], [1, 1]], "robot_vertices"),
        ([[0, 0], [1, math.nan], [0, 1]], "robot_vertices must hold finite numbers"),
        ([[0, 0, 0], [1, 1, 1]], r"robot_vertices must be an \(N, 2\) array"),
        ([], r"robot_vertices must be an \(N, 2\) array"),
        ("square", r"robot_vertices must be an \(N, 2\) array"),
    ],
)
def test_bad_robots(f, robot, match: str) -> None:
    with pytest.raises(ParameterError, match=match):
        f([[0, 0], [1, 0], [0, 1]], robot)


def test_non_convex_obstacle_is_refused_by_the_convex_functions() -> None:
    l_shape = [[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]]
    for f in (minkowski_obstacle, star_algorithm):
        with pytest.raises(ParameterError, match="obstacle_vertices must be a convex polygon"):
            f(l_shape, [[0, 0], [1, 0], [0, 1]])


# ----------------------------------------------------------------------------------------
# C-space worlds
# ----------------------------------------------------------------------------------------
ROBOT = np.array([[-0.3, -0.2], [0.4, -0.2], [0.1, 0.5]])
MIXED = {
    "bounds": [0, 0, 12, 10],
    "obstacles": [
        {"polygon": [[1, 1], [5, 1], [5, 2], [2, 2], [2, 5], [1, 5]]},  # non-convex L
        {"polygon": [[7, 1], [10, 2], [8, 4]]},
        {"circle": {"center": [9, 7], "radius": 1.2}},
        {"segment": [[4, 7], [6, 8.5]]},
        {"point": [2, 8]},
    ],
}


def exact_hits(world, q: np.ndarray, robot: np.ndarray) -> list[set[int]]:
    """Ids of the obstacles the robot placed at each q meets (circles exactly)."""
    r = as_geom(robot)
    out = []
    for p in q:
        placed = shapely.affinity.translate(r, *p)
        ids = set()
        for ob in world.obstacles:
            if ob.kind == "circle":
                if placed.distance(Point(ob.center)) <= ob.radius:
                    ids.add(ob.id)
            elif placed.intersects(ob.geometry):
                ids.add(ob.id)
        out.append(ids)
    return out


def test_cspace_world_matches_the_definition() -> None:
    w = world_from_dict(MIXED)
    c = cspace_world(w, ROBOT)
    assert [o.id for o in c.obstacles] == [1, 2, 3, 4, 5]
    assert [o.kind for o in c.obstacles] == ["polygon"] * 5
    assert c.bounds == w.bounds and c.border == w.border
    np.testing.assert_allclose(c.obstacles[1].vertices, minkowski_obstacle(w.obstacles[1].vertices, ROBOT))
    rng = np.random.default_rng(7)
    q = rng.uniform([0, 0], [12, 10], (600, 2))
    hits = exact_hits(w, q, ROBOT)
    circle_slack = 1.2 * (1 / math.cos(math.pi / (4 * CIRCLE_SEGMENTS)) - 1) + 1e-9
    for p, ids in zip(q, hits, strict=True):
        pt = Point(p)
        for ob in c.obstacles:
            inside = ob.geometry.intersects(pt)
            near_boundary = ob.geometry.boundary.distance(pt) < 1e-7
            if ob.id == 3:  # circle: conservative outline, at most circle_slack too big
                if ob.id in ids:
                    assert inside
                elif inside:
                    placed = shapely.affinity.translate(as_geom(ROBOT), *p)
                    assert placed.distance(Point(9, 7)) <= 1.2 + circle_slack
            elif not near_boundary:
                assert inside == (ob.id in ids), (p, ob.id)


def test_point_robot_gives_the_world_back() -> None:
    w = world_from_dict(MIXED)
    c = cspace_world(w, [[0, 0]])
    for a, b in zip(w.obstacles, c.obstacles, strict=True):
        if a.kind == "circle":
            assert b.geometry.contains(a.geometry)
        else:
            assert b.kind == a.kind and b.geometry.equals(a.geometry)


# ----------------------------------------------------------------------------------------
# C-space grids
# ----------------------------------------------------------------------------------------
def footprint_offsets(robot, res: float, tol: float = 0.0) -> list[tuple[int, int]]:
    """Brute force: offsets (dr, dc) whose closed cell centred on (dc, dr) * res meets -R
    (or comes within ``tol`` of it)."""
    neg = as_geom(-np.asarray(robot, dtype=float))
    out = []
    for dr in range(-8, 9):
        for dc in range(-8, 9):
            box = shapely.box((dc - 0.5) * res, (dr - 0.5) * res, (dc + 0.5) * res, (dr + 0.5) * res)
            if box.intersects(neg) or (tol > 0 and box.distance(neg) <= tol):
                out.append((dr, dc))
    return out


@given(st.data(), convex_polygons(), st.sampled_from([0.5, 1.0]), st.sampled_from(["open", "wall"]))
def test_cspace_grid_is_the_footprint_dilation(data, robot, res: float, border: str) -> None:
    rows, cols = data.draw(st.integers(1, 9)), data.draw(st.integers(1, 9))
    occ = np.array(data.draw(st.lists(st.booleans(), min_size=rows * cols, max_size=rows * cols))).reshape(rows, cols)
    ids = np.where(occ, np.array(data.draw(st.lists(st.integers(1, 4), min_size=rows * cols,
                                                    max_size=rows * cols))).reshape(rows, cols), 0)
    m = GridMap(Grid((rows, cols), res, border=border), occ, obstacle_id=ids)
    out = cspace_grid(m, robot)
    offsets = footprint_offsets(robot, res)
    # skip robots that pass within the rasterizer's tolerance of a footprint cell without touching it
    assume(offsets == footprint_offsets(robot, res, tol=1e-8 * res))
    expected = np.zeros((rows, cols), bool)
    expected_ids = np.zeros((rows, cols), np.int32)
    for r in range(rows):
        for c in range(cols):
            reach = []
            for dr, dc in offsets:
                sr, sc = r - dr, c - dc  # the source cell c' with c' + k = (r, c)
                if 0 <= sr < rows and 0 <= sc < cols:
                    if occ[sr, sc]:
                        reach.append(int(ids[sr, sc]))
                elif border == "wall":
                    reach.append(0)
            expected[r, c] = bool(reach)
            positive = [i for i in reach if i > 0]
            expected_ids[r, c] = min(positive) if positive else 0
    np.testing.assert_array_equal(out.occupied, expected)
    np.testing.assert_array_equal(out.obstacle_id, expected_ids)
    plain = cspace_grid(GridMap(m.grid, occ), robot)
    assert plain.obstacle_id is None
    np.testing.assert_array_equal(plain.occupied, expected)


def test_cspace_grid_orientation_and_wall() -> None:
    occ = np.zeros((5, 6), bool)
    occ[2, 3] = True
    robot = [[0, 0], [1.6, 0], [1.6, 0.4], [0, 0.4]]  # to the right of the reference point
    out = cspace_grid(GridMap(Grid((5, 6), 1.0), occ), robot).occupied
    assert np.argwhere(out).tolist() == [[2, 1], [2, 2], [2, 3]]
    # with a wall, the robot cannot get its reference point within 1.6 of the right wall
    wall = cspace_grid(GridMap(Grid((5, 6), 1.0, border="wall"), np.zeros((5, 6), bool)), robot).occupied
    assert wall[:, 4:].all() and not wall[:, :4].any()


@pytest.mark.parametrize("res", [0.25, 0.5])
def test_cspace_grid_against_the_exact_cspace(res: float) -> None:
    w = world_from_dict(MIXED)
    m = rasterize(w, res)
    g = cspace_grid(m, ROBOT)
    exact = rasterize(cspace_world(w, ROBOT), res)
    # within one cell of the rasterized exact C-space
    assert not (g.occupied & ~ndimage.binary_dilation(exact.occupied, BLOCK)).any()
    # every cell whose centre lies in an exact C-obstacle is occupied (non-convex ones too)
    xs, ys = m.grid.cell_centers()
    centres = shapely.points(np.stack(np.meshgrid(xs, ys), axis=-1))
    for ob in cspace_world(w, ROBOT).obstacles:
        if ob.id == 3:
            continue  # the circle's C-obstacle is the conservative outline
        inside = shapely.intersects(ob.geometry, centres)
        assert g.occupied[inside].all()
    # for the convex obstacles: the exact rasterization minus a one-cell band is inside
    convex = world_from_dict({**MIXED, "obstacles": MIXED["obstacles"][1:]})
    gc = cspace_grid(rasterize(convex, res), ROBOT)
    ec = rasterize(cspace_world(convex, ROBOT), res)
    assert not (ndimage.binary_erosion(ec.occupied, BLOCK) & ~gc.occupied).any()
    # ids: cells reached by one obstacle only carry its id
    both = g.occupied & exact.occupied & (g.obstacle_id > 0)
    assert (g.obstacle_id[both] == exact.obstacle_id[both]).mean() > 0.97


def test_cspace_on_seed000_segment() -> None:
    w = read_world(bundled_map("seed000_segment.yaml"))
    c = cspace_world(w, ROBOT)
    assert [o.id for o in c.obstacles] == [1, 2, 3, 4]
    g = cspace_grid(rasterize(w, 0.25), ROBOT)
    assert g.occupied.sum() > rasterize(w, 0.25).occupied.sum()


# ----------------------------------------------------------------------------------------
# disc robots
# ----------------------------------------------------------------------------------------
@given(st.data(), st.sampled_from([0.5, 1.0]), st.sampled_from(["open", "wall"]), st.floats(0, 3.2))
def test_inflate_grid_against_brute_force(data, res: float, border: str, radius: float) -> None:
    rows, cols = data.draw(st.integers(1, 8)), data.draw(st.integers(1, 8))
    occ = np.array(data.draw(st.lists(st.booleans(), min_size=rows * cols, max_size=rows * cols))).reshape(rows, cols)
    ids = np.where(occ, np.arange(1, rows * cols + 1).reshape(rows, cols), 0)
    m = GridMap(Grid((rows, cols), res, border=border), occ, obstacle_id=ids)
    out = inflate_grid(m, radius * res)
    src = [(r, c, int(ids[r, c])) for r in range(rows) for c in range(cols) if occ[r, c]]
    if border == "wall":
        src += [(r, c, 0) for r in range(-1, rows + 1) for c in range(-1, cols + 1)
                if not (0 <= r < rows and 0 <= c < cols)]
    for r in range(rows):
        for c in range(cols):
            d = [(math.hypot(r - sr, c - sc) * res, i) for sr, sc, i in src]
            dmin = min((di for di, _ in d), default=math.inf)
            assert out.occupied[r, c] == (dmin <= radius * res + 1e-9), (r, c)
            if out.occupied[r, c]:
                # the id of a nearest obstacle cell (the wall's is 0)
                assert out.obstacle_id[r, c] in {i for di, i in d if di <= dmin + 1e-12}
            else:
                assert out.obstacle_id[r, c] == 0


def test_inflate_grid_small_radius_and_errors() -> None:
    occ = np.zeros((3, 3), bool)
    occ[1, 1] = True
    m = GridMap(Grid((3, 3), 1.0), occ)
    np.testing.assert_array_equal(inflate_grid(m, 0.99).occupied, occ)
    assert inflate_grid(m, 1.0).occupied.sum() == 5
    assert inflate_grid(m, math.sqrt(2)).occupied.all()
    for bad in (-1, math.nan, math.inf, "x"):
        with pytest.raises(ParameterError, match="radius must be"):
            inflate_grid(m, bad)
    empty = GridMap(Grid((3, 3), 1.0), np.zeros((3, 3), bool))
    assert not inflate_grid(empty, 2.0).occupied.any()


@pytest.mark.parametrize("radius", [0.3, 0.8])
def test_inflate_grid_against_the_inflated_world(radius: float) -> None:
    res = 0.25
    w = world_from_dict(MIXED)
    g = inflate_grid(rasterize(w, res), radius)
    exact = rasterize(inflate_world(w, radius), res)
    assert not (g.occupied & ~ndimage.binary_dilation(exact.occupied, BLOCK)).any()
    xs, ys = g.grid.cell_centers()
    centres = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
    near = (w.distance(centres) <= radius - res / math.sqrt(2)).reshape(g.shape)
    assert g.occupied[near].all()


def test_inflate_world() -> None:
    w = world_from_dict(MIXED)
    r = 0.5
    grown = inflate_world(w, r)
    assert [(o.id, o.kind) for o in grown.obstacles] == [(1, "polygon"), (2, "polygon"), (3, "circle"),
                                                        (4, "polygon"), (5, "circle")]
    assert grown.obstacles[2].radius == 1.7 and grown.obstacles[2].center == (9.0, 7.0)
    assert grown.obstacles[4].radius == 0.5 and grown.obstacles[4].center == (2.0, 8.0)
    slack = r / math.cos(math.pi / (4 * CIRCLE_SEGMENTS))
    rng = np.random.default_rng(3)
    q = rng.uniform([0, 0], [12, 10], (3000, 2))
    for a, b in zip(w.obstacles, grown.obstacles, strict=True):
        if a.kind == "circle" or a.kind == "point":
            continue
        d = a.distance(q)
        # contains the exact grown obstacle ...
        assert shapely.covers(b.geometry, shapely.points(q[d <= r])).all()
        # ... and nothing farther than the circumscribed slack
        assert (a.distance(shapely.get_coordinates(b.geometry)) <= slack + 1e-9).all()
        outside = ~shapely.covers(b.geometry, shapely.points(q))
        assert (d[outside] > r - 1e-9).all()
    assert inflate_world(w, 0).obstacles == w.obstacles
    with pytest.raises(ParameterError, match="radius must be a finite number >= 0"):
        inflate_world(w, -0.1)
    with pytest.raises(ParameterError, match="quad_segs must be an integer >= 1"):
        inflate_world(w, 0.1, quad_segs=0)


def test_rasterized_footprint_is_centred_on_the_reference_point() -> None:
    # a square robot centred on its reference point, exactly one cell: touches the 3 x 3 block
    sq = [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]
    assert len(footprint_offsets(sq, 1.0)) == 9
    occ = np.zeros((5, 5), bool)
    occ[2, 2] = True
    out = cspace_grid(GridMap(Grid((5, 5), 1.0), occ), sq).occupied
    np.testing.assert_array_equal(out, ndimage.binary_dilation(occ, BLOCK))
    # the same through rasterize_geometry directly (the footprint grid is centred on cell (m, m))
    m = 2
    fp = rasterize_geometry(Polygon(sq), Grid((2 * m + 1, 2 * m + 1), 1.0, origin=(-(m + 0.5), -(m + 0.5))))
    assert fp.sum() == 9 and fp[1:4, 1:4].all()
