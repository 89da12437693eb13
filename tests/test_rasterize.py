"""Conservative rasterization against shapely's ``intersects`` with closed cell boxes."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import assume, given
from hypothesis import strategies as st
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry

from gridfield.core.errors import ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.rasterize import as_gridmap, rasterize, rasterize_geometry
from gridfield.geometry.world import World, world_from_dict
from gridfield.io import bundled_map, read_world

#: extra cells may be marked only this close to the obstacle (the documented tolerance)
TOL = 1e-8


def boxes(g: Grid) -> np.ndarray:
    """Closed cell squares as shapely boxes, shape ``g.shape``, with the grid's own arithmetic."""
    x0, y0 = g.origin
    xe = x0 + np.arange(g.cols + 1) * g.resolution
    ye = y0 + np.arange(g.rows + 1) * g.resolution
    return shapely.box(xe[None, :-1], ye[:-1, None], xe[None, 1:], ye[1:, None])


def reference(geom: BaseGeometry, g: Grid) -> tuple[np.ndarray, np.ndarray]:
    b = boxes(g)
    with np.errstate(all="ignore"):  # GEOS warns on coordinates like 1e-308
        return shapely.intersects(geom, b), shapely.distance(geom, b)


def circle_reference(center: tuple[float, float], r: float, g: Grid) -> tuple[np.ndarray, np.ndarray]:
    """Exact: distance from the closed square to the centre <= r."""
    x0, y0 = g.origin
    xe = x0 + np.arange(g.cols + 1) * g.resolution
    ye = y0 + np.arange(g.rows + 1) * g.resolution
    dx = np.maximum(np.maximum(xe[:-1] - center[0], center[0] - xe[1:]), 0)
    dy = np.maximum(np.maximum(ye[:-1] - center[1], center[1] - ye[1:]), 0)
    d2 = dx[None, :] ** 2 + dy[:, None] ** 2
    return d2 <= r * r, np.sqrt(d2) - r


def assert_conservative(mask: np.ndarray, hit: np.ndarray, dist: np.ndarray, exact: bool) -> None:
    missing = hit & ~mask
    assert not missing.any(), f"cells touched but not marked: {np.argwhere(missing).tolist()}"
    extra = mask & ~hit
    if exact:
        assert not extra.any(), f"cells marked but not touched: {np.argwhere(extra).tolist()}"
    else:
        assert np.all(dist[extra] <= TOL), f"cells marked far from the shape: {np.argwhere(extra & (dist > TOL))}"


# ----------------------------------------------------------------------------------------
# strategies
# ----------------------------------------------------------------------------------------
@st.composite
def lattice_grids(draw) -> Grid:
    """Grids at resolution 1 or 0.5 with an origin on the half-integer lattice."""
    res = draw(st.sampled_from([1.0, 0.5]))
    shape = (draw(st.integers(1, 10)), draw(st.integers(1, 10)))
    origin = (draw(st.integers(-4, 4)) * 0.5, draw(st.integers(-4, 4)) * 0.5)
    return Grid(shape, res, origin=origin)


@st.composite
def float_grids(draw) -> Grid:
    res = draw(st.floats(0.05, 2.0, allow_subnormal=False))
    shape = (draw(st.integers(1, 12)), draw(st.integers(1, 12)))
    origin = (draw(st.floats(-5, 5, allow_subnormal=False)), draw(st.floats(-5, 5, allow_subnormal=False)))
    return Grid(shape, res, origin=origin)


def points_near(draw, g: Grid, n: int, lattice: bool) -> np.ndarray:
    """n points in and somewhat around the grid; on the quarter-cell lattice when ``lattice``."""
    xmin, ymin, xmax, ymax = g.bounds
    pad = 2 * g.resolution
    if lattice:
        q = g.resolution / 4
        xs = [draw(st.integers(int((xmin - pad) / q), int((xmax + pad) / q))) * q for _ in range(n)]
        ys = [draw(st.integers(int((ymin - pad) / q), int((ymax + pad) / q))) * q for _ in range(n)]
    else:
        xs = [draw(st.floats(xmin - pad, xmax + pad, allow_subnormal=False)) for _ in range(n)]
        ys = [draw(st.floats(ymin - pad, ymax + pad, allow_subnormal=False)) for _ in range(n)]
    return np.stack([xs, ys], axis=1)


def small_shape(draw, g: Grid, lattice: bool) -> np.ndarray:
    """Vertices of a shape smaller than a cell: centre near the grid, radius < res / 2."""
    c = points_near(draw, g, 1, lattice)[0]
    r = draw(st.floats(0.0, 0.45, allow_subnormal=False)) * g.resolution
    k = draw(st.integers(3, 6))
    ang = (np.arange(k) + draw(st.floats(0, 0.5, allow_subnormal=False))) * 2 * np.pi / k
    v = c + r * np.stack([np.cos(ang), np.sin(ang)], axis=1)
    return np.round(v / (g.resolution / 8)) * (g.resolution / 8) if lattice else v


@st.composite
def shapes(draw, lattice: bool):
    g = draw(lattice_grids() if lattice else float_grids())
    kind = draw(st.sampled_from(["point", "segment", "convex", "star", "rectangle", "small"]))
    if kind == "point":
        geom = Point(points_near(draw, g, 1, lattice)[0])
    elif kind == "segment":
        p = points_near(draw, g, 2, lattice)
        assume(not np.array_equal(p[0], p[1]))
        geom = LineString(p)
    elif kind == "convex":
        geom = shapely.convex_hull(shapely.multipoints(points_near(draw, g, draw(st.integers(3, 8)), lattice)))
        assume(isinstance(geom, Polygon) and geom.area > 0)
    elif kind == "star":  # star-shaped around a centre: simple and usually non-convex
        k = draw(st.integers(4, 10))
        c = points_near(draw, g, 1, lattice)[0]
        ang = (np.arange(k) + np.array([draw(st.floats(0, 0.8, allow_subnormal=False)) for _ in range(k)])) * 2 * np.pi / k
        rad = np.array([draw(st.floats(0.2, 4.0, allow_subnormal=False)) for _ in range(k)]) * g.resolution
        v = c + rad[:, None] * np.stack([np.cos(ang), np.sin(ang)], axis=1)
        if lattice:
            v = np.round(v / (g.resolution / 4)) * (g.resolution / 4)
        geom = Polygon(v)
        assume(geom.is_valid and geom.area > 0)
    elif kind == "rectangle":
        p = points_near(draw, g, 2, lattice)
        lo, hi = p.min(axis=0), p.max(axis=0)
        assume(np.all(hi > lo))
        geom = shapely.box(*lo, *hi)
    else:
        v = small_shape(draw, g, lattice)
        geom = Polygon(v) if Polygon(v).is_valid and Polygon(v).area > 0 else Point(v[0])
    return g, geom


# ----------------------------------------------------------------------------------------
# property tests
# ----------------------------------------------------------------------------------------
@given(shapes(lattice=False))
def test_random_shapes_match_shapely(case) -> None:
    g, geom = case
    hit, dist = reference(geom, g)
    assert_conservative(rasterize_geometry(geom, g), hit, dist, exact=False)


@given(shapes(lattice=True))
def test_lattice_shapes_match_shapely_exactly(case) -> None:
    """Vertices on the quarter-cell lattice: many touch cell edges and corners exactly."""
    g, geom = case
    hit, dist = reference(geom, g)
    assert_conservative(rasterize_geometry(geom, g), hit, dist, exact=True)


@given(st.data(), st.booleans())
def test_circles_match_the_exact_circle(data, lattice: bool) -> None:
    g = data.draw(lattice_grids() if lattice else float_grids())
    c = points_near(data.draw, g, 1, lattice)[0]
    r = (data.draw(st.integers(1, 12)) / 4 if lattice else data.draw(st.floats(1e-3, 3.0, allow_subnormal=False))) * g.resolution
    w = World(bounds=g.bounds, obstacles=(world_from_dict(
        {"bounds": [c[0] - 1, c[1] - 1, c[0] + 1, c[1] + 1],
         "obstacles": [{"circle": {"center": c.tolist(), "radius": r}}]}).obstacles[0],))
    m = rasterize(w, g.resolution, bounds=g.bounds)
    assert m.grid.shape == g.shape
    hit, dist = circle_reference((float(c[0]), float(c[1])), r, g)
    assert_conservative(m.occupied, hit, dist, exact=lattice)
    np.testing.assert_array_equal(m.obstacle_id, np.where(m.occupied, 1, 0))


@given(st.data())
def test_obstacle_id_is_the_lowest_intersecting_id(data) -> None:
    g = data.draw(lattice_grids())
    entries = []
    for _ in range(data.draw(st.integers(1, 5))):
        kind = data.draw(st.sampled_from(["circle", "segment", "rectangle", "point"]))
        p = points_near(data.draw, g, 2, lattice=True)
        if kind == "circle":
            entries.append({"circle": {"center": p[0].tolist(), "radius": float(data.draw(st.integers(1, 8)) * 0.25)}})
        elif kind == "segment" and not np.array_equal(p[0], p[1]):
            entries.append({"segment": p.tolist()})
        elif kind == "rectangle" and np.all(p[0] != p[1]):
            entries.append({"rectangle": [*p.min(axis=0).tolist(), *p.max(axis=0).tolist()]})
        else:
            entries.append({"point": p[0].tolist()})
    w = world_from_dict({"bounds": list(g.bounds), "obstacles": entries})
    m = rasterize(w, g.resolution)
    assert m.grid == g
    expected = np.zeros(g.shape, np.int32)
    for ob in sorted(w.obstacles, key=lambda o: -o.id):  # lowest id written last
        if ob.kind == "circle":
            hit, _ = circle_reference(ob.center, ob.radius, g)
        else:
            hit, _ = reference(ob.geometry, g)
        expected[hit] = ob.id
    np.testing.assert_array_equal(m.obstacle_id, expected)
    np.testing.assert_array_equal(m.occupied, expected > 0)


# ----------------------------------------------------------------------------------------
# hand-checked cases
# ----------------------------------------------------------------------------------------
def occupied_cells(mask: np.ndarray) -> list[tuple[int, int]]:
    return [tuple(int(v) for v in rc) for rc in np.argwhere(mask)]


@pytest.mark.parametrize(
    ("point", "cells"),
    [
        ((0.5, 0.5), [(0, 0)]),
        ((1.0, 0.5), [(0, 0), (0, 1)]),  # on a vertical cell edge: both cells
        ((1.5, 2.0), [(1, 1), (2, 1)]),  # on a horizontal cell edge
        ((1.0, 1.0), [(0, 0), (0, 1), (1, 0), (1, 1)]),  # on a corner: all four
        ((0.0, 0.0), [(0, 0)]),  # grid corner: the only cell inside the grid
        ((3.0, 3.0), [(2, 2)]),
        ((3.5, 1.0), []),  # outside
    ],
)
def test_points_on_edges_and_corners(point: tuple[float, float], cells: list) -> None:
    assert occupied_cells(rasterize_geometry(Point(point), Grid((3, 3), 1.0))) == cells


def test_points_on_edges_at_half_resolution() -> None:
    g = Grid((4, 4), 0.5)
    assert occupied_cells(rasterize_geometry(Point(1.0, 0.5), g)) == [(0, 1), (0, 2), (1, 1), (1, 2)]
    assert occupied_cells(rasterize_geometry(Point(0.75, 0.5), g)) == [(0, 1), (1, 1)]


def test_segment_on_a_grid_line_blocks_both_sides() -> None:
    m = rasterize_geometry(LineString([(0.5, 2), (2.5, 2)]), Grid((4, 4), 1.0))
    assert occupied_cells(m) == [(1, 0), (1, 1), (1, 2), (2, 0), (2, 1), (2, 2)]
    # a segment ending exactly on a cell edge also touches the next cell
    m = rasterize_geometry(LineString([(0.5, 0.5), (2.0, 0.5)]), Grid((2, 4), 1.0))
    assert occupied_cells(m) == [(0, 0), (0, 1), (0, 2)]


def test_diagonal_segment_through_corners_touches_corner_cells() -> None:
    m = rasterize_geometry(LineString([(0.5, 0.5), (2.5, 2.5)]), Grid((4, 4), 1.0))
    # interior crossings at the corners (1, 1) and (2, 2) touch the two off-diagonal cells each
    assert occupied_cells(m) == [(0, 0), (0, 1), (1, 0), (1, 1), (1, 2), (2, 1), (2, 2)]


def test_shapes_smaller_than_a_cell() -> None:
    g = Grid((3, 3), 1.0)
    tiny = Polygon([(1.2, 1.2), (1.3, 1.2), (1.25, 1.3)])
    assert occupied_cells(rasterize_geometry(tiny, g)) == [(1, 1)]
    straddling = Polygon([(0.95, 1.2), (1.05, 1.2), (1.0, 1.3)])
    assert occupied_cells(rasterize_geometry(straddling, g)) == [(1, 0), (1, 1)]
    w = world_from_dict({"bounds": [0, 0, 3, 3], "obstacles": [{"circle": {"center": [2.5, 0.5], "radius": 0.01}},
                                                              {"circle": {"center": [2.0, 2.0], "radius": 0.01}}]})
    m = rasterize(w, 1.0)
    assert occupied_cells(m.occupied) == [(0, 2), (1, 1), (1, 2), (2, 1), (2, 2)]


def test_polygon_with_hole_and_multipolygon() -> None:
    g = Grid((7, 7), 1.0)
    ring = Polygon([(0.5, 0.5), (6.5, 0.5), (6.5, 6.5), (0.5, 6.5)], holes=[[(2.2, 2.2), (4.8, 2.2), (4.8, 4.8), (2.2, 4.8)]])
    mask = rasterize_geometry(ring, g)
    assert not mask[3, 3] and mask[1, 1] and mask[2, 3]
    hit, dist = reference(ring, g)
    assert_conservative(mask, hit, dist, exact=False)
    multi = shapely.union(shapely.box(0.2, 0.2, 1.8, 1.8), shapely.box(4.1, 4.1, 4.9, 6.0))
    hit, dist = reference(multi, g)
    assert_conservative(rasterize_geometry(multi, g), hit, dist, exact=True)


def test_seed000_hand_checked_spot() -> None:
    m = rasterize(read_world(bundled_map("seed000.yaml")), 0.5)
    assert m.shape == (40, 50)
    ids = m.obstacle_id
    # obstacle 2 is the triangle (9, 10), (12, 4), (6, 4). Its base y = 4 lies on the boundary
    # between rows 7 and 8: row 7 ([3.5, 4]) touches it along x in [6, 12] -> columns 11..24
    # (column 11 = [5.5, 6] only at the corner x = 6, column 24 = [12, 12.5] at x = 12).
    assert np.flatnonzero(ids[7]).tolist() == list(range(11, 25))
    assert set(ids[7][ids[7] > 0].tolist()) == {2}
    assert not m.occupied[6].any()
    # the apex (9, 10) is the corner of cells (19|20, 17|18): all four touch it
    assert ids[19, 17] == ids[19, 18] == ids[20, 17] == ids[20, 18] == 2
    assert ids[20, 16] == ids[20, 19] == ids[19, 19] == 0  # [9.5, 10] x [9.5, 10] stays clear of the slope
    assert ids[14, 18] == 2  # (9.25, 7.25) inside
    # the start and goal cells are free
    assert m.is_free([[1, 10], [22, 12]]).all()
    assert m.world is not None and m.source.endswith("seed000.yaml") and m.grid.border == "open"
    # ids agree with which obstacle intersects each cell (the polygons do not touch each other)
    b = boxes(m.grid)
    for ob in m.world.obstacles:
        np.testing.assert_array_equal(ids == ob.id, shapely.intersects(ob.geometry, b))


def test_seed000_segment_blocks_the_cells_it_touches() -> None:
    m = rasterize(read_world(bundled_map("seed000_segment.yaml")), 0.5)
    # x = 17.5 is the boundary between columns 34 and 35; y in [8, 10] touches rows 15..20 (closed)
    ids = m.obstacle_id
    assert m.occupied[15:21, 34:36].all()
    assert not m.occupied[14, 34:36].any() and not m.occupied[15:20, 36].any()
    # obstacle 3's edge y = x - 7 passes (17, 10) and (17.5, 10.5): cells (19, 34), (20, 34) and
    # (20, 35) touch both obstacles, and the lower id wins
    assert (ids[15:19, 34:36] == 4).all()
    assert ids[19, 34:36].tolist() == [3, 4] and ids[20, 34:36].tolist() == [3, 3]


def test_bounds_override_and_clipping() -> None:
    w = read_world(bundled_map("seed000.yaml"))
    full = rasterize(w, 0.5)
    part = rasterize(w, 0.5, bounds=(5, 3, 15, 13))
    assert part.grid.origin == (5.0, 3.0) and part.shape == (20, 20)
    np.testing.assert_array_equal(part.obstacle_id, full.obstacle_id[6:26, 10:30])
    far = rasterize(w, 1.0, bounds=(100, 100, 110, 110))
    assert not far.occupied.any()


def test_wall_border_is_carried() -> None:
    w = world_from_dict({"bounds": [0, 0, 3, 2], "border": "wall"})
    m = rasterize(w, 1.0)
    assert m.grid.border == "wall" and not m.occupied.any() and m.obstacle_id.dtype == np.int32


@pytest.mark.parametrize("resolution", [0, -1, math.nan, math.inf, "x"])
def test_bad_resolution(resolution) -> None:
    w = read_world(bundled_map("seed000.yaml"))
    with pytest.raises(ParameterError, match="resolution must be a positive"):
        rasterize(w, resolution)


def test_bad_arguments() -> None:
    w = read_world(bundled_map("seed000.yaml"))
    with pytest.raises(ParameterError, match=r"bounds must be \[xmin, ymin, xmax, ymax\]"):
        rasterize(w, 1.0, bounds=(0, 0, 1))
    with pytest.raises(ParameterError, match="max > min"):
        rasterize(w, 1.0, bounds=(0, 0, -1, 1))
    with pytest.raises(ParameterError, match="rasterize needs a World, got dict"):
        rasterize({"bounds": [0, 0, 1, 1]}, 1.0)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="must be a shapely geometry"):
        rasterize_geometry([(0, 0)], Grid((2, 2), 1.0))  # type: ignore[arg-type]


# ----------------------------------------------------------------------------------------
# as_gridmap
# ----------------------------------------------------------------------------------------
def test_as_gridmap() -> None:
    w = read_world(bundled_map("seed003_circles.yaml"))
    m = as_gridmap(w)
    assert m.grid.resolution == 0.4 and m.shape == (25, 25)
    assert as_gridmap(w, 0.5).shape == (20, 20)
    assert as_gridmap(m) is m
    assert as_gridmap(m, 0.4) is m
    with pytest.raises(ParameterError, match=r"resolution 0\.4; resolution 0\.5 was requested, but resampling"):
        as_gridmap(m, 0.5)
    no_res = world_from_dict({"bounds": [0, 0, 2, 2], "border": "wall"}, source="w.yaml")
    with pytest.raises(ParameterError, match=r"the world w\.yaml has no 'resolution' key.*pass --resolution"):
        as_gridmap(no_res)
    assert as_gridmap(no_res, 0.5).shape == (4, 4)
    with pytest.raises(ParameterError, match="resolution must be a positive"):
        as_gridmap(no_res, -1.0)
    with pytest.raises(ParameterError, match="expected a World or a GridMap, got str"):
        as_gridmap("maps/seed000.yaml")  # type: ignore[arg-type]
    plain = GridMap(Grid((2, 2), 1.0), np.zeros((2, 2), bool))
    assert as_gridmap(plain) is plain
