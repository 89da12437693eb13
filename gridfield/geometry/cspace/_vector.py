"""Configuration spaces of vector worlds (private; import from gridfield.geometry.cspace).

:func:`inflate_world` grows every obstacle of a :class:`~gridfield.geometry.world.World` by a disc robot's
radius (shapely buffers, circles kept exact); :func:`cspace_world` replaces every obstacle by its
C-obstacle for a convex polygon robot (Minkowski sums from ``_polygons``; non-convex polygons as a
union of edge sums).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import Point, Polygon
from shapely.geometry.base import BaseGeometry

from ...core.errors import ParameterError
from .._polygons import _as_geometry, _check_radius, _clean_convex, _convex_polygon, _kind, minkowski_obstacle
from ..world import CIRCLE_SEGMENTS, Obstacle, World


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
    >>> from gridfield.geometry.world import world_from_dict
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
    return "polygon", _drop_slivers(shapely.union_all([moved, *hulls]))


#: Holes of a Minkowski union smaller than this fraction of its envelope's area are rounding slivers.
SLIVER_AREA = 1e-9


def _drop_slivers(geom: BaseGeometry) -> BaseGeometry:
    """``geom`` without the zero-area holes that the union of edge sums leaves where edges meet (areas of
    1e-16 on ``maps/star_two.yaml``): a hole below :data:`SLIVER_AREA` times the envelope's area is filled."""
    tol = SLIVER_AREA * float(geom.envelope.area)

    def fill(p: Polygon) -> Polygon:
        keep = [r for r in p.interiors if Polygon(r).area > tol]
        return p if len(keep) == len(p.interiors) else Polygon(p.exterior, keep)

    if isinstance(geom, Polygon):
        return fill(geom)
    if isinstance(geom, shapely.MultiPolygon):
        return shapely.MultiPolygon([fill(p) for p in geom.geoms])
    return geom


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
    >>> from gridfield.geometry.world import world_from_dict
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
