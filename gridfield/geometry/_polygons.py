"""Convex polygons as vertex arrays, and their Minkowski sums (private; import from gridfield.geometry.cspace).

The normalization every convex polygon of the package goes through (validation of user input,
cleaning of computed vertex cycles: counter-clockwise, lowest vertex first, no duplicate or
collinear vertex), and the two independent constructions of a C-obstacle ``O ⊕ (−R)``:
:func:`minkowski_obstacle` (convex hull of the vertex differences) and :func:`star_algorithm`
(edges merged by direction, seed 004). Also the radius check both disc inflations share.

A leaf below :mod:`gridfield.geometry.world` (it imports only ``errors``), so that ``world`` checks a robot
polygon with the normalization ``cspace`` uses without importing ``cspace``, which builds on ``world``.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry

from ..core.errors import ParameterError, shorten

#: Relative tolerance for collinearity: |sin| of the turn between two edges below which a
#: vertex counts as collinear.
_COLLINEAR_TOL = 1e-12


# ----------------------------------------------------------------------------------------
# Convex polygons as vertex arrays
# ----------------------------------------------------------------------------------------
#: Largest coordinate of a polygon vertex: cross products of edges (squares of coordinates, times the
#: vertex count) stay finite floats.
COORD_MAX = 1e100


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
    if np.any(np.abs(v) > COORD_MAX):
        raise ParameterError(f"{name} must hold coordinates within ±{COORD_MAX:g} (so that the products of the "
                             f"convexity test stay finite), got {shorten(v.tolist())}")
    return _merge_duplicates(v)


def _merge_duplicates(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Drop vertices equal to their predecessor (cyclically, so also a repeated closing vertex)
    up to ``_COLLINEAR_TOL`` times the polygon's extent."""
    extent = float(np.max(np.abs(v - v[0]))) if len(v) else 0.0
    step = np.max(np.abs(v - np.roll(v, 1, axis=0)), axis=1)
    keep: NDArray[np.bool_] = step > _COLLINEAR_TOL * extent
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
    gridfield.core.errors.ParameterError: robot_vertices must be a convex polygon; vertex (1.0, 0.5) is reflex (vertices: [[0.0, 0.0], [2.0, 0.0], [1.0, 0.5], [1.0, 2.0]])
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
# Argument checks shared by the submodules
# ----------------------------------------------------------------------------------------
def _check_radius(radius: float) -> float:
    try:
        r = float(radius)
    except (TypeError, ValueError):
        raise ParameterError(f"radius must be a number >= 0, got {radius!r}") from None
    if not (math.isfinite(r) and r >= 0):
        raise ParameterError(f"radius must be a finite number >= 0 (the robot's radius), got {radius!r}")
    return r
