"""The plane geometry of :mod:`gridfield.exact.visibility` (a private module; import from there).

Circles as their circumscribed outline, directions round a point (angles, closed arcs, the free
arcs between obstacles), side and crossing tests of segments, the obstacle at a point, the union
of the area obstacles and its rings (obstacle on the left), and the merging of nearly equal points.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import NDArray
from scipy.spatial import cKDTree
from shapely.geometry import Point, Polygon, box
from shapely.geometry.base import BaseGeometry

from ..geometry.world import CIRCLE_SEGMENTS, Obstacle, World

_TWO_PI = 2.0 * math.pi
_ANGLE_EPS = 1e-9
#: Relative excess of the circumscribed circle outline: 1 / cos(pi / (4 * CIRCLE_SEGMENTS)) - 1.
CIRCLE_OUTLINE_EXCESS = 1.0 / math.cos(math.pi / (4 * CIRCLE_SEGMENTS)) - 1.0


# ----------------------------------------------------------------------------------------
# Circles and directions
# ----------------------------------------------------------------------------------------
def _circle_outline(ob: Obstacle) -> Polygon:
    """The circumscribed regular 4*CIRCLE_SEGMENTS-gon of a circle obstacle."""
    assert ob.center is not None and ob.radius is not None
    n = 4 * CIRCLE_SEGMENTS
    theta = np.arange(n) * (_TWO_PI / n)
    big = ob.radius * (1.0 + CIRCLE_OUTLINE_EXCESS)
    return Polygon(np.column_stack([ob.center[0] + big * np.cos(theta), ob.center[1] + big * np.sin(theta)]))


def _angle(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Angle of vectors ``(..., 2)`` in ``[0, 2 pi)``."""
    return np.mod(np.arctan2(v[..., 1], v[..., 0]), _TWO_PI)


def _in_arc(theta: NDArray[np.float64], start: float, width: float) -> NDArray[np.bool_]:
    """Whether angles lie in the closed arc ``[start, start + width]`` (counter-clockwise)."""
    rel = np.mod(np.asarray(theta) - start, _TWO_PI)
    return (rel <= width + _ANGLE_EPS) | (rel >= _TWO_PI - _ANGLE_EPS)


def _free_arcs(occupied: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Free directions round a point as closed arcs ``(start, width)``.

    ``occupied`` lists closed arcs ``(start, width)`` taken by obstacles; ``width == 0`` is a ray
    (a segment obstacle), which separates the arcs on its two sides.
    """
    if not occupied:
        return [(0.0, _TWO_PI)]
    bounds = np.sort(np.mod(np.concatenate([[s, s + w] for s, w in occupied]), _TWO_PI))
    keep = np.concatenate([[True], np.diff(bounds) > _ANGLE_EPS])
    bounds = bounds[keep]
    if len(bounds) > 1 and bounds[-1] - bounds[0] > _TWO_PI - _ANGLE_EPS:
        bounds = bounds[:-1]
    if len(bounds) == 1:
        return [(float(bounds[0]), _TWO_PI)]
    arcs = []
    for k in range(len(bounds)):
        a = bounds[k]
        b = bounds[k + 1] if k + 1 < len(bounds) else bounds[0] + _TWO_PI
        mid = 0.5 * (a + b)
        if any(np.mod(mid - s, _TWO_PI) < w for s, w in occupied):
            continue
        arcs.append((float(a), float(b - a)))
    return arcs


# ----------------------------------------------------------------------------------------
# Segments and points
# ----------------------------------------------------------------------------------------
def _side(a: NDArray[np.float64], b: NDArray[np.float64], p: NDArray[np.float64], tol: float) -> NDArray[np.int8]:
    """-1, 0, +1: side of points ``p`` of the lines ``a -> b`` (0 within ``tol``)."""
    d = b - a
    cross = d[:, 0] * (p[:, 1] - a[:, 1]) - d[:, 1] * (p[:, 0] - a[:, 0])
    dist = cross / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-300)
    return np.where(np.abs(dist) <= tol, 0, np.sign(dist)).astype(np.int8)


def _properly_cross(a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64],
                    e: NDArray[np.float64], tol: float) -> NDArray[np.bool_]:
    """Whether segments ``a-b`` and ``c-e`` cross at one point interior to both (with tolerance)."""
    return (_side(a, b, c, tol) * _side(a, b, e, tol) < 0) & (_side(c, e, a, tol) * _side(c, e, b, tol) < 0)


def _obstacle_at(world: World, p: NDArray[np.float64]) -> Obstacle | None:
    for ob in world.obstacles:
        if ob.kind in ("polygon", "circle") and shapely.intersects(ob.geometry if ob.kind != "circle"
                                                                   else _circle_outline(ob), Point(p)):
            return ob
    return None



# ----------------------------------------------------------------------------------------
# The area obstacles
# ----------------------------------------------------------------------------------------
def _area_union(world: World) -> BaseGeometry:
    shapes = []
    for ob in world.obstacles:
        if ob.kind == "circle":
            shapes.append(_circle_outline(ob))
        elif ob.kind == "polygon":
            shapes.append(ob.geometry)
    if world.border == "wall":
        xmin, ymin, xmax, ymax = world.bounds
        m = max(xmax - xmin, ymax - ymin)
        shapes.append(box(xmin - m, ymin - m, xmax + m, ymax + m).difference(box(xmin, ymin, xmax, ymax)))
    if not shapes:
        return shapely.GeometryCollection()
    return shapely.orient_polygons(shapely.union_all(shapes))


def _rings(union: BaseGeometry) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Vertices of every ring of the union with their previous and next ring vertices.

    Rings are oriented with the obstacle on the left (shell counter-clockwise, holes clockwise).
    """
    verts, prevs, nexts = [], [], []
    for poly in shapely.get_parts(union):
        if not isinstance(poly, Polygon) or poly.is_empty:
            continue
        for ring in (poly.exterior, *poly.interiors):
            v = np.asarray(ring.coords, dtype=float)[:-1]
            if len(v) < 3:
                continue
            verts.append(v)
            prevs.append(np.roll(v, 1, axis=0))
            nexts.append(np.roll(v, -1, axis=0))
    if not verts:
        e = np.empty((0, 2))
        return e, e, e
    return np.concatenate(verts), np.concatenate(prevs), np.concatenate(nexts)


def _dedupe(points: NDArray[np.float64], tol: float) -> NDArray[np.float64]:
    if len(points) == 0:
        return points
    tree = cKDTree(points)
    taken = np.zeros(len(points), dtype=bool)
    out = []
    for i in range(len(points)):
        if taken[i]:
            continue
        group = tree.query_ball_point(points[i], tol)
        taken[group] = True
        out.append(points[i])
    return np.array(out)
