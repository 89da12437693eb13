"""Configuration space (seed 004): obstacles grown by the robot's shape.

Two robot models, each on vector worlds and on grids:

- **disc robot** of radius ``r`` (rotation does not matter): every obstacle grows by ``r``;
  :func:`inflate_world` (shapely buffer) and :func:`inflate_grid` (Euclidean distance threshold);
- **convex polygon robot**, translation only: the C-obstacle of a workspace obstacle ``O`` is the
  Minkowski sum ``O ⊕ (−R)`` where ``R`` is the robot's shape in its own frame and the robot's
  **reference point is the origin (0, 0) of that frame**: the robot at configuration ``q``
  occupies ``q + R``, which meets ``O`` iff ``q ∈ O ⊕ (−R)``. :func:`minkowski_obstacle`
  computes it as the convex hull of all pairwise vertex differences, :func:`star_algorithm` by
  the seed's star algorithm (merging the two polygons' edges in the order of their directions);
  :func:`cspace_world` and :func:`cspace_grid` apply it to whole worlds and grids.

Polygon vertex arrays are ``(N, 2)`` world coordinates ``(x, y)``; convex polygons may be given
in either orientation and with or without a repeated closing vertex. Returned convex polygons are
counter-clockwise, start at the lowest vertex (lowest y, then lowest x), repeat no vertex and
contain no collinear vertices; a degenerate result has 1 (point) or 2 (segment) rows.
"""

from __future__ import annotations

import dataclasses
import math
from typing import cast

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry

from ..errors import GridfieldError, ParameterError
from ..grid import Grid, GridMap
from ..rasterize import rasterize_geometry
from ..world import CIRCLE_SEGMENTS, Obstacle, Robot, World

__all__ = [
    "apply_robot",
    "as_robot",
    "check_robot_point",
    "check_robot_polygon",
    "conservative_footprint",
    "cspace_grid",
    "cspace_world",
    "inflate_grid",
    "inflate_world",
    "minkowski_obstacle",
    "robot_clearance",
    "star_algorithm",
    "workspace_clearance",
]

#: Relative tolerance for collinearity: |sin| of the turn between two edges below which a
#: vertex counts as collinear.
_COLLINEAR_TOL = 1e-12


# ----------------------------------------------------------------------------------------
# Convex polygons as vertex arrays
# ----------------------------------------------------------------------------------------
def _vertices(value: ArrayLike, name: str) -> NDArray[np.float64]:
    try:
        v = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be an (N, 2) array of vertices (x, y), got {value!r}") from None
    if v.ndim == 1 and v.shape == (2,):
        v = v[None, :]
    if v.ndim != 2 or v.shape[1] != 2 or len(v) == 0:
        raise ParameterError(f"{name} must be an (N, 2) array of vertices (x, y), got shape {np.shape(v)}")
    if not np.all(np.isfinite(v)):
        raise ParameterError(f"{name} must hold finite numbers, got {v.tolist()}")
    return _merge_duplicates(v)


def _merge_duplicates(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Drop vertices equal to their predecessor (cyclically, so also a repeated closing vertex)
    up to ``_COLLINEAR_TOL`` times the polygon's extent."""
    extent = float(np.max(np.abs(v - v[0]))) if len(v) else 0.0
    step = np.max(np.abs(v - np.roll(v, 1, axis=0)), axis=1)
    keep = step > _COLLINEAR_TOL * extent
    if not keep.any():
        return v[:1].copy()
    return v[keep]


def _start_lowest(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotate a vertex cycle to start at its lowest vertex (lowest y, then lowest x)."""
    k = np.lexsort((v[:, 0], v[:, 1]))[0]
    return np.roll(v, -k, axis=0)


def _turns(v: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Per vertex: cross and dot of the incoming and outgoing edges, and |in| * |out|."""
    e_out = np.roll(v, -1, axis=0) - v
    e_in = v - np.roll(v, 1, axis=0)
    cross = e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]
    dot = np.einsum("ij,ij->i", e_in, e_out)
    norms = np.hypot(e_in[:, 0], e_in[:, 1]) * np.hypot(e_out[:, 0], e_out[:, 1])
    return cross, dot, norms


def _segment_ends(v: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """The two extreme points if all of ``v`` lie on one line (lower one first), else None."""
    rel = v - v[0]
    d = rel[np.argmax(np.hypot(rel[:, 0], rel[:, 1]))]
    n = math.hypot(d[0], d[1])
    cross = rel[:, 0] * d[1] - rel[:, 1] * d[0]
    if np.all(np.abs(cross) <= _COLLINEAR_TOL * n * np.maximum(np.hypot(rel[:, 0], rel[:, 1]), n)):
        t = rel @ d
        ends = np.array([v[np.argmin(t)], v[np.argmax(t)]])
        return _start_lowest(ends)
    return None


def _convex_polygon(value: ArrayLike, name: str) -> NDArray[np.float64]:
    """Validate a convex polygon; return it normalized (see the module docstring).

    Raises ParameterError for a non-convex or self-intersecting vertex list.
    """
    v = _vertices(value, name)
    if len(v) == 1:
        return v
    ends = _segment_ends(v)
    if ends is not None:
        return ends
    area2 = float(np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1]))
    if area2 < 0:
        v = v[::-1]
    cross, dot, norms = _turns(v)
    straight = np.abs(cross) <= _COLLINEAR_TOL * norms
    if np.any(~straight & (cross < 0)):
        k = int(np.flatnonzero(~straight & (cross < 0))[0])
        raise ParameterError(
            f"{name} must be a convex polygon; vertex {tuple(v[k].tolist())} is reflex "
            f"(vertices: {np.asarray(value, dtype=np.float64).tolist()})"
        )
    if np.any(straight & (dot < 0)):
        raise ParameterError(f"{name} doubles back on itself; it must be a simple convex polygon: {v.tolist()}")
    turning = float(np.sum(np.arctan2(cross, dot)))
    if not math.isclose(turning, 2 * math.pi, rel_tol=1e-6):
        raise ParameterError(
            f"{name} winds around {turning / (2 * math.pi):.3g} times; it must be a simple convex polygon "
            f"listed once around: {np.asarray(value, dtype=np.float64).tolist()}"
        )
    return _start_lowest(v[~straight])


def _clean_convex(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Normalize the vertex cycle of a convex polygon computed by this module (no validation):
    CCW, no duplicates, no collinear (or rounding-reflex) vertices, lowest vertex first."""
    v = np.asarray(v, dtype=np.float64)
    v = _merge_duplicates(v)
    if len(v) <= 1:
        return v
    ends = _segment_ends(v)
    if ends is not None:
        return ends
    area2 = float(np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1]))
    if area2 < 0:
        v = v[::-1]
    while len(v) > 3:
        cross, _, norms = _turns(v)
        flat = cross <= _COLLINEAR_TOL * norms
        if not flat.any():
            break
        v = v[~flat]
    return _start_lowest(v)


def _as_geometry(v: NDArray[np.float64]) -> BaseGeometry:
    if len(v) == 1:
        return Point(v[0])
    if len(v) == 2:
        return LineString(v)
    return Polygon(v)


def _kind(v: NDArray[np.float64]) -> str:
    return {1: "point", 2: "segment"}.get(len(v), "polygon")


# ----------------------------------------------------------------------------------------
# Minkowski sums of convex polygons
# ----------------------------------------------------------------------------------------
def minkowski_obstacle(obstacle_vertices: ArrayLike, robot_vertices: ArrayLike) -> NDArray[np.float64]:
    """C-obstacle of a convex obstacle for a convex robot that translates: ``O ⊕ (−R)``.

    Computed exactly as the convex hull of all pairwise differences ``o_i − r_j`` of the
    vertices. The robot's reference point is the origin of its vertex coordinates.

    Parameters
    ----------
    obstacle_vertices : (N, 2) array_like
        Convex obstacle (a point or a segment are allowed: 1 or 2 vertices).
    robot_vertices : (M, 2) array_like
        Convex robot shape in the robot's frame.

    Returns
    -------
    ndarray, shape (K, 2)
        Counter-clockwise vertices starting at the lowest one, without collinear vertices.

    Raises
    ------
    ParameterError
        if either polygon is not convex (or not simple), or not an (N, 2) finite array.

    Examples
    --------
    >>> square = [[0, 0], [2, 0], [2, 2], [0, 2]]
    >>> robot = [[0, 0], [1, 0], [0, 1]]          # reference point at the right-angle corner
    >>> minkowski_obstacle(square, robot)
    array([[ 0., -1.],
           [ 2., -1.],
           [ 2.,  2.],
           [-1.,  2.],
           [-1.,  0.]])

    A segment robot sweeps a parallelogram; a non-convex robot is refused:

    >>> minkowski_obstacle([[0, 0], [1, 0]], [[0, 0], [0, 1]])
    array([[ 0., -1.],
           [ 1., -1.],
           [ 1.,  0.],
           [ 0.,  0.]])
    >>> minkowski_obstacle(square, [[0, 0], [2, 0], [1, 0.5], [1, 2]])
    Traceback (most recent call last):
    ...
    gridfield.errors.ParameterError: robot_vertices must be a convex polygon; vertex (1.0, 0.5) is reflex (vertices: [[0.0, 0.0], [2.0, 0.0], [1.0, 0.5], [1.0, 2.0]])
    """
    obstacle = _convex_polygon(obstacle_vertices, "obstacle_vertices")
    robot = _convex_polygon(robot_vertices, "robot_vertices")
    diffs = (obstacle[:, None, :] - robot[None, :, :]).reshape(-1, 2)
    hull = shapely.convex_hull(shapely.multipoints(diffs))
    coords = np.asarray(hull.exterior.coords)[:-1] if isinstance(hull, Polygon) else np.asarray(hull.coords)
    return _clean_convex(coords)


def _edge_angles(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Directions in ``[0, 2π)`` of the edges ``v[k] -> v[k+1]`` of a normalized convex polygon
    (lowest vertex first): non-decreasing along the polygon."""
    if len(v) == 1:
        return np.empty(0)
    edges = np.roll(v, -1, axis=0) - v
    ang = np.mod(np.arctan2(edges[:, 1], edges[:, 0]), 2 * np.pi)
    # the first edge leaves the lowest vertex with a direction in [0, π); a later edge whose
    # direction rounds to 0 closes the polygon and belongs at the end
    ang[1:][ang[1:] == 0.0] = 2 * np.pi
    return ang


def star_algorithm(obstacle_vertices: ArrayLike, robot_vertices: ArrayLike) -> NDArray[np.float64]:
    """C-obstacle ``O ⊕ (−R)`` of a convex obstacle by the star algorithm (seed 004).

    The edges of the obstacle and of the reflected robot ``−R`` are merged in the order of their
    directions (equivalently, of their outward normals), starting from the sum of the two lowest
    vertices, which is the lowest vertex of the sum; walking the merged edges traces the
    C-obstacle; its vertices are the sums of the vertices the two walks stand on. Same inputs,
    output and reference point as :func:`minkowski_obstacle`, computed independently of it (no
    convex hull).

    Parameters
    ----------
    obstacle_vertices : (N, 2) array_like
        Convex obstacle (a point or a segment are allowed: 1 or 2 vertices).
    robot_vertices : (M, 2) array_like
        Convex robot shape in the robot's frame.

    Returns
    -------
    ndarray, shape (K, 2)
        Counter-clockwise vertices starting at the lowest one, without collinear vertices.

    Examples
    --------
    >>> star_algorithm([[0, 0], [2, 0], [2, 2], [0, 2]], [[0, 0], [1, 0], [0, 1]])
    array([[ 0., -1.],
           [ 2., -1.],
           [ 2.,  2.],
           [-1.,  2.],
           [-1.,  0.]])
    """
    a = _convex_polygon(obstacle_vertices, "obstacle_vertices")
    b = _start_lowest(-_convex_polygon(robot_vertices, "robot_vertices"))
    ta, tb = _edge_angles(a), _edge_angles(b)
    # merge the two edge sequences by direction (a stable sort keeps each polygon's own order);
    # after k merged edges the walk stands on a[i_k] + b[j_k], where i_k and j_k count the edges
    # taken from each polygon so far (vertex sums, not accumulated edge vectors: no drift)
    order = np.argsort(np.concatenate([ta, tb]), kind="stable")
    from_a = order < len(ta)
    i = np.concatenate([[0], np.cumsum(from_a)[:-1]]) % len(a)
    j = np.concatenate([[0], np.cumsum(~from_a)[:-1]]) % len(b)
    if len(order) == 0:
        return _clean_convex((a[0] + b[0])[None, :])
    return _clean_convex(a[i] + b[j])


# ----------------------------------------------------------------------------------------
# Worlds
# ----------------------------------------------------------------------------------------
def _check_radius(radius: float) -> float:
    try:
        r = float(radius)
    except (TypeError, ValueError):
        raise ParameterError(f"radius must be a number >= 0, got {radius!r}") from None
    if not (math.isfinite(r) and r >= 0):
        raise ParameterError(f"radius must be a finite number >= 0 (the robot's radius), got {radius!r}")
    return r


def _circle_obstacle(oid: int, center: tuple[float, float], radius: float) -> Obstacle:
    geom = Point(center).buffer(radius, quad_segs=CIRCLE_SEGMENTS)
    return Obstacle(oid, "circle", geom, center=(float(center[0]), float(center[1])), radius=float(radius))


def _circumscribed_outline(center: tuple[float, float], radius: float) -> NDArray[np.float64]:
    """Vertices of the regular polygon with ``4 * CIRCLE_SEGMENTS`` sides whose edges touch the circle."""
    n = 4 * CIRCLE_SEGMENTS
    rc = radius / math.cos(math.pi / n)
    t = 2 * np.pi * np.arange(n) / n
    return np.stack([center[0] + rc * np.cos(t), center[1] + rc * np.sin(t)], axis=1)


def inflate_world(world: World, radius: float, *, quad_segs: int = CIRCLE_SEGMENTS) -> World:
    """C-space of a disc robot of ``radius``: every obstacle grown by ``radius``.

    Circles stay exact circles (radius + ``radius``); a point becomes a circle of ``radius``.
    Polygons and segments become their shapely buffer (exact along straight parts) united with,
    at each vertex, the regular polygon with ``4 * quad_segs`` sides circumscribing the disc of
    ``radius``: the result contains the exact grown obstacle (conservative) and lies within
    ``radius * (1 / cos(π / (4 quad_segs)) − 1)`` (0.12 % of ``radius`` for 16) of it.

    Obstacle ids are kept; bounds, border, start, goal and params are copied unchanged (a wall
    border is not grown here, since a World cannot express it; :func:`inflate_grid` grows it;
    start and goal are not re-validated, use ``World.check_point``).

    Parameters
    ----------
    world : World
    radius : float
        Robot radius (>= 0, finite).
    quad_segs : int
        Segments per quarter circle of the round parts (>= 1).

    Returns
    -------
    World
        The grown world (its ``robot`` field unchanged).

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [
    ...     {"circle": {"center": [5, 5], "radius": 1}}, {"segment": [[1, 1], [3, 1]]}]})
    >>> grown = inflate_world(w, 0.5)
    >>> grown.obstacles[0].kind, grown.obstacles[0].radius
    ('circle', 1.5)
    >>> grown.obstacles[1].kind, [round(v, 3) for v in grown.obstacles[1].geometry.bounds]
    ('polygon', [0.5, 0.5, 3.5, 1.5])
    """
    if not isinstance(world, World):
        raise ParameterError(f"inflate_world needs a World, got {type(world).__name__}")
    r = _check_radius(radius)
    if isinstance(quad_segs, bool) or not isinstance(quad_segs, int | np.integer) or quad_segs < 1:
        raise ParameterError(f"quad_segs must be an integer >= 1, got {quad_segs!r}")
    if r == 0:
        return dataclasses.replace(world)
    rc = r / math.cos(math.pi / (4 * int(quad_segs)))
    grown: list[Obstacle] = []
    for ob in world.obstacles:
        if ob.kind == "circle" and ob.center is not None and ob.radius is not None:
            grown.append(_circle_obstacle(ob.id, ob.center, ob.radius + r))
        elif ob.kind == "point":
            (x, y), = np.asarray(ob.geometry.coords)
            grown.append(_circle_obstacle(ob.id, (float(x), float(y)), r))
        else:
            verts = shapely.get_coordinates(ob.geometry)
            discs = shapely.buffer(shapely.points(verts), rc, quad_segs=int(quad_segs))
            geom = shapely.union_all([ob.geometry.buffer(r, quad_segs=int(quad_segs)), *discs])
            grown.append(Obstacle(ob.id, "polygon", geom))
    return dataclasses.replace(world, obstacles=tuple(grown))


def _cspace_geometry(ob: Obstacle, neg_robot: NDArray[np.float64], robot: NDArray[np.float64]) -> tuple[
        str, BaseGeometry]:
    if ob.kind == "circle" and ob.center is not None and ob.radius is not None:
        v = minkowski_obstacle(_circumscribed_outline(ob.center, ob.radius), robot)
        return _kind(v), _as_geometry(v)
    if ob.kind in ("point", "segment"):
        pts = shapely.get_coordinates(ob.geometry)
        v = minkowski_obstacle(_clean_convex(pts), robot)
        return _kind(v), _as_geometry(v)
    poly = ob.geometry
    verts = np.asarray(poly.exterior.coords)[:-1]
    if isinstance(poly, Polygon) and not poly.interiors:
        try:
            v = minkowski_obstacle(verts, robot)
        except ParameterError:
            pass  # not convex: below
        else:
            return _kind(v), _as_geometry(v)
    # Non-convex P: P ⊕ S = (P + s0) ∪ ⋃_edges (edge ⊕ S) for convex S and any s0 in S
    # (a point p + s with p + s - s0 outside P puts some point of p + [s, s0] - s on ∂P).
    rings = [poly.exterior, *poly.interiors]
    segs = np.vstack([np.hstack([c[:-1], c[1:]]) for c in (np.asarray(r.coords) for r in rings)])
    k = len(neg_robot)
    pts = np.concatenate([segs[:, None, :2] + neg_robot[None], segs[:, None, 2:] + neg_robot[None]], axis=1)
    hulls = shapely.convex_hull(shapely.multipoints(pts.reshape(-1, 2), indices=np.repeat(np.arange(len(segs)), 2 * k)))
    moved = shapely.affinity.translate(poly, *neg_robot[0])
    return "polygon", shapely.union_all([moved, *hulls])


def cspace_world(world: World, robot_vertices: ArrayLike) -> World:
    """C-space of a convex polygon robot that translates: each obstacle becomes ``O ⊕ (−R)``.

    The robot's reference point is the origin of ``robot_vertices``. Convex polygons, segments
    and points go through :func:`minkowski_obstacle` (exact); circles through their
    circumscribed ``4 * CIRCLE_SEGMENTS``-gon (conservative: contains the exact C-obstacle);
    non-convex polygons as the union of the translated polygon and of the sums of each edge
    with ``−R`` (exact up to shapely's union). Ids are kept; a C-obstacle's kind is ``polygon``
    (``segment``/``point`` when degenerate). Bounds, border, start, goal and params are copied
    unchanged: a wall border is not grown (a World cannot express it; :func:`cspace_grid`
    grows it), and start/goal are not re-validated (use ``World.check_point``).

    Parameters
    ----------
    world : World
    robot_vertices : (M, 2) array_like
        Convex robot polygon in the robot's frame (origin = reference point).

    Returns
    -------
    World
        The configuration-space world, one C-obstacle per obstacle.

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[4, 4], [6, 4], [6, 6], [4, 6]]}]})
    >>> c = cspace_world(w, [[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> c.obstacles[0].id, c.obstacles[0].geometry.bounds
    (1, (3.0, 3.0, 6.0, 6.0))
    """
    if not isinstance(world, World):
        raise ParameterError(f"cspace_world needs a World, got {type(world).__name__}")
    robot = _convex_polygon(robot_vertices, "robot_vertices")
    neg = -robot
    obstacles = []
    for ob in world.obstacles:
        kind, geom = _cspace_geometry(ob, neg, robot)
        obstacles.append(Obstacle(ob.id, kind, geom))
    return dataclasses.replace(world, obstacles=tuple(obstacles))


# ----------------------------------------------------------------------------------------
# Grids
# ----------------------------------------------------------------------------------------
def inflate_grid(gridmap: GridMap, radius: float) -> GridMap:
    """C-space of a disc robot on a grid: occupied where the distance to an occupied cell <= radius.

    Distances are Euclidean and measured **between cell centres** (the feature transform of
    ``scipy.ndimage.distance_transform_edt`` on the free cells gives each cell's nearest obstacle
    cell; the comparison is exact in integer cell units, with a relative tolerance of ``1e-9`` on
    ``radius / resolution``); a radius below one cell therefore changes nothing. With ``border="wall"`` the wall (a ring of
    occupied cells just outside the grid, as in :mod:`gridfield.brushfire`) grows too. Each new
    cell takes the ``obstacle_id`` of its nearest obstacle cell (0 when that is the wall).

    Parameters
    ----------
    gridmap : GridMap
    radius : float
        Robot radius in world units (>= 0, finite).

    Returns
    -------
    GridMap
        Same grid, border and world; the grown occupancy and ``obstacle_id``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((5, 5), bool); occ[2, 2] = True
    >>> inflate_grid(GridMap(Grid((5, 5), 0.5), occ), 1.0).occupied.astype(int)
    array([[0, 0, 1, 0, 0],
           [0, 1, 1, 1, 0],
           [1, 1, 1, 1, 1],
           [0, 1, 1, 1, 0],
           [0, 0, 1, 0, 0]])
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"inflate_grid needs a GridMap, got {type(gridmap).__name__}")
    r = _check_radius(radius)
    grid = gridmap.grid
    res = grid.resolution
    wall = grid.border == "wall"
    occ = np.pad(gridmap.occupied, 1, constant_values=True) if wall else gridmap.occupied
    if r < res or not occ.any():
        return gridmap.with_occupied(gridmap.occupied.copy(),
                                     obstacle_id=None if gridmap.obstacle_id is None else gridmap.obstacle_id.copy())
    # The feature transform (index of the nearest obstacle cell) alone is faster in scipy than
    # the distances; the squared distance in cells follows from it exactly, in integers.
    idx = ndimage.distance_transform_edt(~occ, return_distances=False, return_indices=True)
    nrows, ncols = occ.shape
    dr = idx[0] - np.arange(nrows, dtype=idx.dtype)[:, None]
    dc = idx[1] - np.arange(ncols, dtype=idx.dtype)[None, :]
    limit = (r / res) ** 2 * (1 + 2e-9) + 1e-9
    inflated = (dr.astype(np.int64) ** 2 + dc.astype(np.int64) ** 2) <= limit
    del dr, dc
    ids = None
    if gridmap.obstacle_id is not None:
        src = np.pad(gridmap.obstacle_id, 1) if wall else gridmap.obstacle_id
        ids = np.where(inflated, src[idx[0], idx[1]], 0).astype(np.int32)
    if wall:
        inflated = inflated[1:-1, 1:-1]
        ids = None if ids is None else ids[1:-1, 1:-1]
    return gridmap.with_occupied(inflated, obstacle_id=ids)


def _footprint(robot: NDArray[np.float64], resolution: float) -> NDArray[np.bool_]:
    """Conservative rasterization of ``−R`` on a ``(2m+1)^2`` grid whose centre cell is centred on
    the reference point: cell ``(m + i, m + j)`` is the offset of ``i`` rows and ``j`` columns."""
    neg = -robot
    m = math.ceil(float(np.max(np.abs(neg))) / resolution + 0.5) + 1
    grid = Grid((2 * m + 1, 2 * m + 1), resolution, origin=(-(m + 0.5) * resolution, -(m + 0.5) * resolution))
    return rasterize_geometry(_as_geometry(_clean_convex(neg)), grid)


def _runs(footprint: NDArray[np.bool_]) -> list[tuple[int, int, int]]:
    """Horizontal runs ``(row offset, first col offset, last col offset)`` of a centred footprint."""
    m = footprint.shape[0] // 2
    padded = np.pad(footprint, ((0, 0), (1, 1))).astype(np.int8)
    d = np.diff(padded, axis=1)
    starts, ends = np.nonzero(d == 1), np.nonzero(d == -1)
    return [(int(r) - m, int(a) - m, int(b) - 1 - m) for r, a, b in zip(starts[0], starts[1], ends[1], strict=True)]


def _dilate(arr: NDArray, runs: list[tuple[int, int, int]], pad_value: int) -> NDArray:
    """``out[y, x] = max over runs (dr, a, b) and s in [a, b] of arr[y - dr, x - s]``, with
    ``pad_value`` outside ``arr`` (a Minkowski-sum dilation by the footprint), via one 1-D
    running maximum per run (cost independent of the run's length)."""
    rows, cols = arr.shape
    p = max(max(abs(dr), abs(a), abs(b)) for dr, a, b in runs) + 1
    padded = np.pad(arr, p, constant_values=pad_value)
    out = np.zeros_like(arr)
    cache: dict[tuple[int, int], NDArray] = {}
    for dr, a, b in runs:
        length = b - a + 1
        if (a, b) not in cache:
            cache[(a, b)] = ndimage.maximum_filter1d(padded, length, axis=1, mode="constant", cval=pad_value)
        f = cache[(a, b)]
        r0 = p - dr
        c0 = p - b + length // 2
        np.maximum(out, f[r0:r0 + rows, c0:c0 + cols], out=out)
    return out


def cspace_grid(gridmap: GridMap, robot_vertices: ArrayLike) -> GridMap:
    """C-space of a convex polygon robot that translates, on a grid.

    The occupancy is dilated by the **footprint**: the reflected robot ``−R`` rasterized
    conservatively (closed cells) at the grid's resolution on cells centred on the reference
    point (the origin of ``robot_vertices``). A cell ``q`` is occupied iff ``q = c + k`` for an
    occupied cell ``c`` and a footprint offset ``k``. The result contains every cell whose centre
    lies in the exact C-space of the rasterized obstacles and is within one cell of the exact
    C-space. With ``border="wall"`` the wall grows too. Each cell's ``obstacle_id`` is the
    lowest id among the obstacle cells that reach it (0 if only the wall or id-less cells do).

    Parameters
    ----------
    gridmap : GridMap
    robot_vertices : (M, 2) array_like
        Convex robot polygon in the robot's frame (origin = reference point), world units.

    Returns
    -------
    GridMap
        Same grid, border and world; the dilated occupancy and ``obstacle_id``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((4, 5), bool); occ[1, 2] = True
    >>> m = cspace_grid(GridMap(Grid((4, 5), 1.0), occ), [[0, 0], [1.6, 0], [1.6, 0.4], [0, 0.4]])
    >>> m.occupied.astype(int)  # the robot extends right of its reference point: C-obstacle to the left
    array([[0, 0, 0, 0, 0],
           [1, 1, 1, 0, 0],
           [0, 0, 0, 0, 0],
           [0, 0, 0, 0, 0]])
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"cspace_grid needs a GridMap, got {type(gridmap).__name__}")
    robot = _convex_polygon(robot_vertices, "robot_vertices")
    return _dilate_gridmap(gridmap, _runs(_footprint(robot, gridmap.grid.resolution)))


def _dilate_gridmap(gridmap: GridMap, runs: list[tuple[int, int, int]]) -> GridMap:
    """Dilate the occupancy (and the obstacle ids, the lowest id winning) by a footprint's runs;
    the wall border (``border="wall"``) grows too."""
    wall = gridmap.grid.border == "wall"
    ids = gridmap.obstacle_id
    if ids is None:
        occ = _dilate(gridmap.occupied.view(np.uint8), runs, pad_value=int(wall)).astype(bool)
        return gridmap.with_occupied(occ, obstacle_id=None)
    # priority: free 0, occupied without id 1, id k -> big - k (the maximum is the lowest id)
    big = int(max(int(ids.max(initial=0)), 0)) + 2
    dtype = np.uint8 if big <= np.iinfo(np.uint8).max else np.uint16 if big <= np.iinfo(np.uint16).max else np.int64
    prio = np.where(gridmap.occupied, np.where(ids > 0, big - ids, 1), 0).astype(dtype)
    out = _dilate(prio, runs, pad_value=1 if wall else 0)
    new_ids = np.where(out >= 2, big - out, 0).astype(np.int32)
    return gridmap.with_occupied(out > 0, obstacle_id=new_ids)


# ----------------------------------------------------------------------------------------
# A robot on any map: the one entry point the commands use
# ----------------------------------------------------------------------------------------
def check_robot_polygon(vertices: ArrayLike, name: str = "robot") -> NDArray[np.float64]:
    """Validate a convex robot polygon (vertices around its reference point, the origin); return it
    normalized (counter-clockwise, lowest vertex first).

    Parameters
    ----------
    vertices : (N, 2) array_like
        One vertex (a point), two (a segment) or a convex polygon; repeated vertices are dropped.
    name : str, default "robot"
        The argument's name, for the message.

    Returns
    -------
    ndarray, shape (K, 2)
        Counter-clockwise, lowest vertex first, collinear vertices removed.

    Raises
    ------
    ParameterError
        If the array is not (N, 2) finite numbers, or the polygon is not convex.

    Examples
    --------
    >>> check_robot_polygon([[0, 1], [0, 0], [1, 0]])
    array([[0., 0.],
           [1., 0.],
           [0., 1.]])
    """
    return _convex_polygon(vertices, name)


def as_robot(robot: Robot | float | ArrayLike | None) -> Robot | None:
    """A :class:`~gridfield.world.Robot` from a Robot, a radius (number) or convex polygon vertices.

    Parameters
    ----------
    robot : Robot, float, (N, 2) array_like or None
        What the API accepts as a robot.

    Returns
    -------
    Robot or None
        ``robot`` itself when it is a Robot; None for None (a point robot).

    Examples
    --------
    >>> as_robot(0.5).radius, as_robot([[0, 0], [1, 0], [0, 1]]).extent, as_robot(None)
    (0.5, 1.0, None)
    """
    if robot is None or isinstance(robot, Robot):
        return robot
    if isinstance(robot, int | float | np.integer | np.floating) and not isinstance(robot, bool):
        return Robot(radius=float(robot))
    return Robot(vertices=check_robot_polygon(robot, "robot"))


def conservative_footprint(robot: Robot, resolution: float) -> NDArray[np.bool_]:
    """The cell offsets a grid obstacle cell reaches in the configuration space, conservatively.

    Returns a ``(2m+1, 2m+1)`` boolean array whose centre is offset ``(0, 0)``: offset ``k`` is
    set iff the closed cell square ``k`` cells away meets ``S ⊕ (−R)``, where ``S`` is the closed
    cell square at the centre and ``R`` the robot. Dilating an occupancy by it marks every cell
    holding a configuration at which the robot touches an occupied cell (and only cells within
    one cell of such a configuration). A disc of radius ``r``: offsets whose squares are at most
    ``r`` apart (``h * hypot(max(|di|-1, 0), max(|dj|-1, 0)) <= r``); a polygon: the
    conservative rasterization of ``S ⊕ (−R)``. A robot of no size gives the single centre cell.

    Parameters
    ----------
    robot : Robot
    resolution : float
        The grid's cell size (> 0), in the robot's units.

    Returns
    -------
    ndarray of bool, shape (2m+1, 2m+1)
        ``m`` is one more than the robot's reach in cells, rounded up (a margin of unset offsets).

    Examples
    --------
    >>> conservative_footprint(Robot(radius=0.4), 1.0).astype(int)[1:-1, 1:-1]
    array([[1, 1, 1],
           [1, 1, 1],
           [1, 1, 1]])
    >>> int(conservative_footprint(Robot(radius=1.2), 1.0).sum())  # 5 x 5 minus the 4 corners
    21
    """
    h = check_positive_resolution(resolution)
    if robot.is_point:
        return np.ones((1, 1), dtype=bool)
    if robot.radius is not None:
        r = robot.radius
        m = math.ceil(r / h) + 1
        gap = np.maximum(np.abs(np.arange(-m, m + 1)) - 1, 0).astype(np.float64)
        d2 = gap[:, None] ** 2 + gap[None, :] ** 2
        return d2 * (h * h) <= (r * r) * (1 + 1e-9)
    assert robot.vertices is not None
    square = 0.5 * h * np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    reach = minkowski_obstacle(square, robot.vertices)  # S ⊕ (−R)
    m = math.ceil(float(np.max(np.abs(reach))) / h + 0.5) + 1
    grid = Grid((2 * m + 1, 2 * m + 1), h, origin=(-(m + 0.5) * h, -(m + 0.5) * h))
    return rasterize_geometry(_as_geometry(reach), grid)


def check_positive_resolution(resolution: float) -> float:
    h = float(resolution)
    if not (math.isfinite(h) and h > 0):
        raise ParameterError(f"resolution must be a positive number, got {resolution!r}")
    return h


def _wall_strips(world: World, robot: Robot) -> list[Obstacle]:
    """With a wall border: the bands along the bounds where the robot would touch the wall."""
    if world.border != "wall":
        return []
    if robot.radius is not None:
        left = right = bottom = top = robot.radius
    else:
        assert robot.vertices is not None
        v = robot.vertices
        left, right = max(0.0, -float(v[:, 0].min())), max(0.0, float(v[:, 0].max()))
        bottom, top = max(0.0, -float(v[:, 1].min())), max(0.0, float(v[:, 1].max()))
    xmin, ymin, xmax, ymax = world.bounds
    boxes = [(xmin, ymin, min(xmin + left, xmax), ymax) if left > 0 else None,
             (max(xmax - right, xmin), ymin, xmax, ymax) if right > 0 else None,
             (xmin, ymin, xmax, min(ymin + bottom, ymax)) if bottom > 0 else None,
             (xmin, max(ymax - top, ymin), xmax, ymax) if top > 0 else None]
    oid = max((o.id for o in world.obstacles), default=0)
    out = []
    for b in boxes:
        if b is not None:
            oid += 1
            out.append(Obstacle(oid, "polygon", shapely.box(*b)))
    return out


def apply_robot(target: World | GridMap, robot: Robot | float | ArrayLike | None) -> World | GridMap:
    """The configuration space of ``target`` for a robot that translates: what every command plans on.

    - a :class:`World`: exact C-obstacles, a disc's by :func:`inflate_world`, a convex polygon's
      by :func:`cspace_world` (Minkowski sums, seed 004), plus, with ``border="wall"``, the bands
      along the bounds where the robot would touch the wall; grid planners then rasterize them
      conservatively as usual, exact planners use them directly;
    - a :class:`GridMap` (bitmaps, ROS, Moving AI): the occupancy dilated by
      :func:`conservative_footprint` (no configuration at which the robot touches an occupied
      cell stays free; the wall border grows too); its ``world``, if any, becomes the world's
      C-space.

    Parameters
    ----------
    target : World or GridMap
    robot : Robot, float or (N, 2) array_like or None
        A radius, a convex polygon around the reference point (the origin of its vertices), or
        None (a point robot: ``target`` is returned unchanged).

    Returns
    -------
    World or GridMap
        Of the same type; a world's ``robot`` is cleared (it has been applied) and a grid's
        ``meta["robot"]`` describes the robot.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((5, 7), bool); occ[2, 3] = True
    >>> apply_robot(GridMap(Grid((5, 7), 1.0), occ), 0.5).occupied.astype(int)
    array([[0, 0, 0, 0, 0, 0, 0],
           [0, 0, 1, 1, 1, 0, 0],
           [0, 0, 1, 1, 1, 0, 0],
           [0, 0, 1, 1, 1, 0, 0],
           [0, 0, 0, 0, 0, 0, 0]])
    >>> from gridfield.io import read_world, bundled_map
    >>> c = apply_robot(read_world(bundled_map("seed000.yaml")), 0.3)
    >>> [round(v, 3) for v in c.obstacles[0].geometry.bounds]
    [3.7, 9.7, 12.3, 18.3]
    """
    r = as_robot(robot)
    if isinstance(target, World):
        if r is None or r.is_point:
            return dataclasses.replace(target, robot=None)
        grown = (inflate_world(target, r.radius) if r.radius is not None
                 else cspace_world(target, cast("NDArray[np.float64]", r.vertices)))
        return dataclasses.replace(grown, obstacles=(*grown.obstacles, *_wall_strips(target, r)), robot=None)
    if not isinstance(target, GridMap):
        raise ParameterError(f"apply_robot needs a World or a GridMap, got {type(target).__name__}")
    if r is None or r.is_point:
        return target
    out = _dilate_gridmap(target, _runs(conservative_footprint(r, target.grid.resolution)))
    world = apply_robot(target.world, r) if isinstance(target.world, World) else target.world
    meta = dict(target.meta)
    meta["robot"] = r.describe()
    return out.with_occupied(out.occupied, world=world, meta=meta)


def _grid_distance(gridmap: GridMap, p: NDArray[np.float64], reach: float) -> float:
    """Exact distance from ``p`` to the nearest occupied cell square (or the wall) within ``reach``
    (``inf`` when none is that close)."""
    grid = gridmap.grid
    h = grid.resolution
    x0, y0 = grid.origin
    c0, c1 = math.floor((p[0] - reach - x0) / h) - 1, math.floor((p[0] + reach - x0) / h) + 1
    r0, r1 = math.floor((p[1] - reach - y0) / h) - 1, math.floor((p[1] + reach - y0) / h) + 1
    c0, r0 = max(c0, 0), max(r0, 0)
    c1, r1 = min(c1, grid.cols - 1), min(r1, grid.rows - 1)
    best = math.inf
    if c0 <= c1 and r0 <= r1:
        rows, cols = np.nonzero(gridmap.occupied[r0:r1 + 1, c0:c1 + 1])
        if len(rows):
            cx = x0 + (cols + c0 + 0.5) * h
            cy = y0 + (rows + r0 + 0.5) * h
            dx = np.maximum(np.abs(p[0] - cx) - h / 2, 0.0)
            dy = np.maximum(np.abs(p[1] - cy) - h / 2, 0.0)
            best = float(np.min(np.hypot(dx, dy)))
    if grid.border == "wall":
        xmin, ymin, xmax, ymax = grid.bounds
        best = min(best, max(0.0, min(p[0] - xmin, xmax - p[0], p[1] - ymin, ymax - p[1])))
    return best


def check_robot_point(
    target: World | GridMap,
    robot: Robot | float | ArrayLike | None,
    name: str,
    point: ArrayLike,
    cspace: World | GridMap | None = None,
) -> None:
    """Raise a :class:`GridfieldError` naming the distance when the robot placed at ``point`` collides.

    ``target`` is the workspace (before :func:`apply_robot`). A disc collides when the nearest
    obstacle is at most its radius away; a polygon when its outline placed at ``point`` meets an
    obstacle (a world's exact geometry, or a grid's occupied cell squares; the wall border
    counts). With ``cspace`` (a grid from :func:`apply_robot`), a point whose cell the conservative
    grid configuration space blocks is also refused, with the distance and the cell size.
    A point outside the map is left to the planner's own check.

    Parameters
    ----------
    target : World or GridMap
        The workspace.
    robot : Robot, float, (N, 2) array_like or None
        As for :func:`apply_robot`; None checks nothing.
    name : str
        The point's name (``"start"``, ``"goal"``), for the message.
    point : (x, y)
    cspace : World or GridMap, optional
        The configuration space already built from ``target``.

    Returns
    -------
    None
        Nothing when the robot fits at ``point``.

    Raises
    ------
    GridfieldError
        When the robot placed at ``point`` touches an obstacle (or the grid C-space blocks it).

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> w = read_world(bundled_map("seed000.yaml"))
    >>> check_robot_point(w, 0.5, "start", (1, 10))
    >>> check_robot_point(w, 4, "start", (1, 10))
    Traceback (most recent call last):
    ...
    gridfield.errors.GridfieldError: start (1, 10) is 3.61 from obstacle 1, within the robot (disc of radius 4); ...
    """
    r = as_robot(robot)
    p = np.asarray(point, dtype=float).reshape(-1)
    if r is None or p.shape != (2,) or not np.all(np.isfinite(p)):
        return
    where = f"{name} ({p[0]:g}, {p[1]:g})"
    hint = "move it or make the robot smaller"
    if isinstance(target, World):
        xmin, ymin, xmax, ymax = target.bounds
        if not (xmin <= p[0] <= xmax and ymin <= p[1] <= ymax):
            return
        dists = [(float(ob.distance(p[None, :])[0]), f"obstacle {ob.id}") for ob in target.obstacles]
        if target.border == "wall":
            dists.append((float(min(p[0] - xmin, xmax - p[0], p[1] - ymin, ymax - p[1])), "the wall"))
        if not dists:
            return
        d, what = min(dists)
        if r.radius is not None:
            if d <= r.radius:
                raise GridfieldError(f"{where} is {d:.3g} from {what}, within the robot ({r.describe()}); {hint}")
        else:
            placed = r.outline(p)
            for ob in target.obstacles:
                hit = (placed.distance(Point(ob.center)) <= ob.radius
                       if ob.kind == "circle" and ob.center is not None and ob.radius is not None
                       else placed.intersects(ob.geometry))
                if hit:
                    raise GridfieldError(f"{where}: the robot ({r.describe()}) placed there overlaps obstacle {ob.id} "
                                         f"(the reference point is {float(ob.distance(p[None, :])[0]):.3g} from it); {hint}")
            if target.border == "wall":
                bx0, by0, bx1, by1 = placed.bounds
                if min(bx0 - xmin, xmax - bx1, by0 - ymin, ymax - by1) <= 0:
                    raise GridfieldError(f"{where}: the robot ({r.describe()}) placed there touches the wall; {hint}")
        return
    if not isinstance(target, GridMap) or not target.grid.contains(p)[0]:
        return
    h = target.grid.resolution
    d = _grid_distance(target, p, r.extent + 2 * h)
    if r.radius is not None:
        if d <= r.radius:
            raise GridfieldError(f"{where} is {d:.3g} from the nearest occupied cell, within the robot "
                                 f"({r.describe()}); {hint}")
    else:
        placed = r.outline(p)
        hits = rasterize_geometry(placed, target.grid) & target.occupied
        xmin, ymin, xmax, ymax = target.grid.bounds
        bx0, by0, bx1, by1 = placed.bounds
        outside = target.grid.border == "wall" and min(bx0 - xmin, xmax - bx1, by0 - ymin, ymax - by1) <= 0
        if hits.any() or outside:
            raise GridfieldError(f"{where}: the robot ({r.describe()}) placed there overlaps occupied cells "
                                 f"(the reference point is {d:.3g} from the nearest); {hint}")
    if isinstance(cspace, GridMap) and not cspace.is_free(p)[0]:
        raise GridfieldError(f"{where} is {d:.3g} from the nearest occupied cell, enough for the robot "
                             f"({r.describe()}), but its cell is blocked in the grid's configuration space, which "
                             f"is conservative by up to one cell ({h:g}); move it a little or use a finer grid")


def workspace_clearance(target: World | GridMap, points: ArrayLike) -> float:
    """Smallest distance from the path ``points`` to the workspace obstacles (before the robot grew them).

    A world: :meth:`World.clearance` (exact, segments included). A grid: the exact distance from
    each vertex to the nearest occupied cell square (the wall border counts). For a disc robot
    of radius ``r`` planned in the configuration space, this is at least ``r``, up to the
    follower's steps between vertices.

    Parameters
    ----------
    target : World or GridMap
        The workspace.
    points : (N, 2) array_like
        The path's vertices, world coordinates.

    Returns
    -------
    float
        The smallest distance (``inf`` with no obstacle and an open border).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((4, 4), bool); occ[0, 0] = True
    >>> round(workspace_clearance(GridMap(Grid((4, 4), 1.0), occ), [[3.0, 1.0], [3.0, 4.0]]), 6)
    2.0
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if isinstance(target, World):
        return float(target.clearance(pts))
    if not isinstance(target, GridMap):
        raise ParameterError(f"workspace_clearance needs a World or a GridMap, got {type(target).__name__}")
    from scipy.spatial import cKDTree

    grid = target.grid
    h = grid.resolution
    best = math.inf
    if grid.border == "wall":
        xmin, ymin, xmax, ymax = grid.bounds
        best = float(np.min(np.maximum(np.minimum.reduce(
            [pts[:, 0] - xmin, xmax - pts[:, 0], pts[:, 1] - ymin, ymax - pts[:, 1]]), 0.0)))
    cells = np.argwhere(target.occupied)
    if len(cells) == 0 or len(pts) == 0:
        return best
    centres = grid.cell_to_world(cells)
    tree = cKDTree(centres)
    d0, _ = tree.query(pts)
    # a square nearer than the nearest centre's square has its centre within d0 + h / sqrt(2)
    cand = tree.query_ball_point(pts, d0 + h * math.sqrt(0.5) + 1e-12)
    lens = np.fromiter((len(c) for c in cand), dtype=np.intp, count=len(cand))
    idx = np.concatenate([np.asarray(c, dtype=np.intp) for c in cand])
    owner = np.repeat(np.arange(len(pts)), lens)
    dx = np.maximum(np.abs(pts[owner, 0] - centres[idx, 0]) - h / 2, 0.0)
    dy = np.maximum(np.abs(pts[owner, 1] - centres[idx, 1]) - h / 2, 0.0)
    return min(best, float(np.min(np.hypot(dx, dy))))


def robot_clearance(target: World | GridMap, robot: Robot | float | ArrayLike, points: ArrayLike) -> float | None:
    """Smallest distance between the robot's body, placed at each path vertex, and the workspace obstacles.

    A world: exact (shapely; circles analytic; the wall counts). A grid: for a disc,
    :func:`workspace_clearance` less the radius; for a polygon on a grid, None (not computed).
    0 means the robot touches an obstacle at some vertex.

    Parameters
    ----------
    target : World or GridMap
        The workspace.
    robot : Robot, float or (N, 2) array_like
        As for :func:`apply_robot`.
    points : (N, 2) array_like
        The path's vertices (positions of the reference point).

    Returns
    -------
    float or None
        The smallest distance; None for a polygon robot on a grid.

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}]})
    >>> round(robot_clearance(w, [[0, -0.5], [1, -0.5], [1, 0.5], [0, 0.5]], [[2, 5], [2, 8]]), 6)
    1.0
    """
    r = as_robot(robot)
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if r is None or len(pts) == 0:
        return workspace_clearance(target, pts) if r is None else math.inf
    if r.radius is not None and not isinstance(target, World):
        return max(workspace_clearance(target, pts) - r.radius, 0.0)
    if not isinstance(target, World):
        return None
    if r.radius is not None:
        return max(float(target.distance(pts).min()) - r.radius, 0.0)
    assert r.vertices is not None
    v = r.vertices
    if len(v) >= 3:
        bodies = shapely.polygons(pts[:, None, :] + v[None])
    elif len(v) == 2:
        bodies = shapely.linestrings(pts[:, None, :] + v[None])
    else:
        bodies = shapely.points(pts + v[0])
    best = math.inf
    for ob in target.obstacles:
        if ob.kind == "circle" and ob.center is not None and ob.radius is not None:
            d = np.maximum(shapely.distance(bodies, Point(ob.center)) - ob.radius, 0.0)
        else:
            d = shapely.distance(bodies, ob.geometry)
        best = min(best, float(np.min(d)))
    if target.border == "wall":
        xmin, ymin, xmax, ymax = target.bounds
        b = shapely.bounds(bodies)
        best = min(best, float(np.maximum(np.minimum.reduce(
            [b[:, 0] - xmin, xmax - b[:, 2], b[:, 1] - ymin, ymax - b[:, 3]]), 0.0).min()))
    return best
