"""Vector worlds: bounds, a border rule, and obstacles as exact shapely geometries.

A world is what the exact planners work on and what the rasterizer turns into a grid.
Obstacles may be polygons (convex or not, any orientation; at least 3 distinct vertices, listed in
order or sorted with ``vertex_order: sort``), circles, segments, rectangles and points; in the Khatib-potential exercise's
``b_matrix`` an obstacle with two vertices is a segment and one with one vertex a point. Each carries a
1-based ``id`` that survives rasterization (``GridMap.obstacle_id``), so that potentials
can be summed per obstacle.

Parsing of the world *file* format lives in :mod:`gridfield.io`; this module turns plain
Python data (as read from YAML) into validated objects: :func:`world_from_dict`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry

from ..core.errors import GridfieldError, MapFormatError, shorten
from ..core.grid import BORDERS

__all__ = ["CIRCLE_SEGMENTS", "VERTEX_ORDERS", "Obstacle", "Robot", "World", "robot_from_value", "sort_vertices",
           "world_from_dict"]

#: Values of the world file's ``vertex_order`` (per file, or per polygon): ``as_given`` (default) takes
#: the vertices in the order listed; ``sort`` sorts them by angle around their centroid (the exercise's
#: VerticesSorter), for files that list a polygon's vertices in any order.
VERTEX_ORDERS = ("as_given", "sort")

#: Segments per quarter circle used for the polygonal outline of a circle (``Obstacle.geometry``,
#: used for display). The outline is inscribed; its largest gap to the true circle is
#: r * (1 - cos(pi / (4*16))), i.e. 0.12 % of the radius. Distances, clearance and rasterization use
#: the exact circle; the visibility graph uses a circumscribed outline (see gridfield.exact.visibility).
CIRCLE_SEGMENTS = 16


@dataclass(frozen=True, eq=False)
class Obstacle:
    """One obstacle of a world.

    Attributes
    ----------
    id : int
        1-based obstacle id (the "B matrix" tag when the world came from one).
    kind : str
        ``"polygon"``, ``"circle"``, ``"segment"``, ``"point"``.
    geometry : shapely geometry
        Exact for polygons, segments and points; for circles a fine inscribed polygon outline
        (see :data:`CIRCLE_SEGMENTS`); use ``center`` and ``radius`` for exact circle geometry.
    center, radius : circle parameters (``None`` for other kinds)
    star_center : (x, y) or None
        For a polygon: the centre it is star-shaped about, when the world file gives one
        (``polygon: {vertices: ..., center: [x, y]}``); the ``star-nav`` planner finds one otherwise.

    Examples
    --------
    >>> from shapely.geometry import Polygon
    >>> ob = Obstacle(id=1, kind="polygon", geometry=Polygon([(0, 0), (2, 0), (2, 1), (0, 1)]))
    >>> ob.vertices.shape, ob.bounds()
    ((4, 2), (0.0, 0.0, 2.0, 1.0))
    >>> ob.distance([[5, 0.5], [1, 4]]).tolist()  # to the right edge, to the top edge
    [3.0, 3.0]
    """

    id: int
    kind: str
    geometry: BaseGeometry
    center: tuple[float, float] | None = None
    radius: float | None = None
    star_center: tuple[float, float] | None = None

    @property
    def vertices(self) -> NDArray[np.float64]:
        """Vertices of the outline, shape ``(N, 2)`` (closed rings are not repeated)."""
        g = self.geometry
        coords = np.asarray(g.exterior.coords if isinstance(g, Polygon) else g.coords, dtype=float)
        if isinstance(g, Polygon):
            coords = coords[:-1]
        return coords

    def distance(self, points: ArrayLike) -> NDArray[np.float64]:
        """Exact Euclidean distance from world points ``(N, 2)`` to this obstacle (0 inside)."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        if self.kind == "circle":
            assert self.center is not None and self.radius is not None
            d = np.hypot(p[:, 0] - self.center[0], p[:, 1] - self.center[1]) - self.radius
            return np.maximum(d, 0.0)
        dist: NDArray[np.float64] = shapely.distance(self.geometry, shapely.points(p))
        return dist

    def bounds(self) -> tuple[float, float, float, float]:
        if self.kind == "circle":
            assert self.center is not None and self.radius is not None
            (cx, cy), r = self.center, self.radius
            return (cx - r, cy - r, cx + r, cy + r)
        return tuple(self.geometry.bounds)

    def __repr__(self) -> str:
        x0, y0, x1, y1 = self.bounds()
        return f"Obstacle(id={self.id}, kind={self.kind!r}, bounds=({x0:.6g}, {y0:.6g}, {x1:.6g}, {y1:.6g}))"


@dataclass(frozen=True, eq=False)
class Robot:
    """The robot's shape, for planning in its configuration space (see :func:`gridfield.geometry.cspace.apply_robot`).

    Exactly one of ``radius`` (a disc centred on the reference point) and ``vertices`` (a convex
    polygon ``(N, 2)`` in the robot's frame, whose origin ``(0, 0)`` is the reference point, the
    point the planners move) is given. The robot translates; it does not rotate.

    Parameters
    ----------
    radius : float, optional
        The disc's radius, >= 0 (0: a point robot).
    vertices : array_like, shape (N, 2), optional
        The convex polygon's vertices in the robot's frame (stored read-only).

    Raises
    ------
    GridfieldError
        If both or neither of ``radius`` and ``vertices`` are given, or a value is not finite.

    Examples
    --------
    >>> Robot(radius=0.3).describe(), Robot(vertices=[[0, 0], [1, 0], [0, 1]]).extent
    ('disc of radius 0.3', 1.0)
    """

    radius: float | None = None
    vertices: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        if (self.radius is None) == (self.vertices is None):
            raise GridfieldError("a robot is either a disc (radius) or a convex polygon (vertices), exactly one")
        if self.radius is not None:
            try:
                r = float(self.radius)
            except (TypeError, ValueError):
                r = math.nan
            if not (math.isfinite(r) and r >= 0):
                raise GridfieldError(f"the robot's radius must be a finite number >= 0, got {self.radius!r}")
            object.__setattr__(self, "radius", r)
        else:
            v = np.asarray(self.vertices, dtype=float)
            if v.ndim != 2 or v.shape[1] != 2 or len(v) < 1 or not np.all(np.isfinite(v)):
                raise GridfieldError(f"the robot's polygon must be finite vertices [[x, y], ...], got {self.vertices!r}")
            v = v.copy()
            v.setflags(write=False)
            object.__setattr__(self, "vertices", v)

    @property
    def extent(self) -> float:
        """The largest distance from the reference point to a point of the robot."""
        if self.radius is not None:
            return float(self.radius)
        assert self.vertices is not None
        return float(np.max(np.hypot(self.vertices[:, 0], self.vertices[:, 1])))

    @property
    def is_point(self) -> bool:
        """True for a robot of no size (radius 0, or a single vertex at the reference point)."""
        return self.extent == 0.0

    def describe(self) -> str:
        """A short description for messages."""
        if self.radius is not None:
            return f"disc of radius {self.radius:g}"
        assert self.vertices is not None
        return "polygon " + " ".join(f"{x:g},{y:g}" for x, y in self.vertices.tolist())

    def outline(self, at: ArrayLike = (0.0, 0.0)) -> BaseGeometry:
        """The robot's shape placed with its reference point at ``at`` (a shapely geometry)."""
        x, y = (float(v) for v in np.asarray(at, dtype=float).reshape(2))
        if self.radius is not None:
            return Point(x, y).buffer(self.radius, quad_segs=CIRCLE_SEGMENTS) if self.radius > 0 else Point(x, y)
        assert self.vertices is not None
        v = self.vertices + np.array([x, y])
        if len(v) == 1:
            return Point(v[0])
        if len(v) == 2:
            return LineString(v)
        return shapely.convex_hull(shapely.multipoints(v))


def robot_from_value(value: Any, what: str = "robot") -> Robot:
    """A :class:`Robot` from a world file's ``robot:`` entry: a number (the radius),
    ``{radius: R}`` or ``{polygon: [[x, y], ...]}`` (a convex polygon around the reference point).

    Parameters
    ----------
    value : float or mapping
        The entry as read from YAML.
    what : str, default "robot"
        Where the entry came from (file and key), for the message.

    Returns
    -------
    Robot

    Raises
    ------
    MapFormatError
        Naming ``what``, for any other value or a polygon that is not convex.

    Examples
    --------
    >>> robot_from_value({"radius": 0.5}).radius, robot_from_value(0.2).radius
    (0.5, 0.2)
    >>> robot_from_value({"polygon": [[0, 0], [1, 0], [0, 1]]}).vertices.shape
    (3, 2)
    """
    if isinstance(value, bool):
        raise MapFormatError(f"{what} must be a radius or {{radius: R}} or {{polygon: [[x, y], ...]}}, got {value!r}")
    if isinstance(value, int | float):
        value = {"radius": value}
    if not isinstance(value, Mapping) or len(value) != 1 or next(iter(value)) not in ("radius", "polygon"):
        raise MapFormatError(f"{what} must be {{radius: R}} or {{polygon: [[x, y], ...]}}, got {value!r}")
    (kind, v), = value.items()
    try:
        if kind == "radius":
            try:
                r = float(v)
            except (TypeError, ValueError):
                raise MapFormatError(f"{what}.radius must be a number >= 0, got {v!r}") from None
            return Robot(radius=r)
        from ._polygons import _convex_polygon  # = cspace.check_robot_polygon (cspace builds on world)

        return Robot(vertices=_convex_polygon(_points(v, f"{what}.polygon"), f"{what}.polygon"))
    except GridfieldError as e:
        if isinstance(e, MapFormatError):
            raise
        raise MapFormatError(f"{what}: {e}") from None


@dataclass(frozen=True, eq=False)
class World:
    """A 2-D world of vector obstacles.

    Usually built by :func:`world_from_dict` (or :func:`gridfield.io.read_world`), which validates
    every field.

    Parameters
    ----------
    bounds : (xmin, ymin, xmax, ymax)
        The world's rectangle, in world units.
    obstacles : tuple of Obstacle
    border : {"open", "wall"}, default "open"
        What lies outside the bounds: free space, or an obstacle (counted by :meth:`distance`).
    start, goal : (x, y), optional
        The world file's default start and goal.
    params : mapping, default {}
        The world file's planner parameters (see :mod:`gridfield.core.params`).
    resolution : float, optional
        Default cell size when the world is rasterized.
    source : str, default ""
        The file it was read from, for messages.
    robot : Robot, optional
        The robot's shape; the commands plan in its configuration space.

    Examples
    --------
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10],
    ...                      "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}]})
    >>> len(w.obstacles), w.border
    (1, 'open')
    >>> round(float(w.distance([[8, 5]])[0]), 6)
    2.0
    """

    bounds: tuple[float, float, float, float]
    obstacles: tuple[Obstacle, ...]
    border: Literal["open", "wall"] = "open"
    start: tuple[float, float] | None = None
    goal: tuple[float, float] | None = None
    params: Mapping[str, Any] = field(default_factory=dict)
    resolution: float | None = None
    source: str = ""
    robot: Robot | None = None

    def distance(self, points: ArrayLike) -> NDArray[np.float64]:
        """Exact distance from each point to the nearest obstacle (the border counts when it is a wall)."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        d = np.full(len(p), np.inf)
        for ob in self.obstacles:
            d = np.minimum(d, ob.distance(p))
        if self.border == "wall":
            xmin, ymin, xmax, ymax = self.bounds
            dw = np.minimum.reduce([p[:, 0] - xmin, xmax - p[:, 0], p[:, 1] - ymin, ymax - p[:, 1]])
            d = np.minimum(d, np.maximum(dw, 0.0))
        return d

    def clearance(self, points: ArrayLike) -> float:
        """Smallest exact distance from the polyline ``points`` (its vertices and segments) to the
        obstacles; the border counts when it is a wall. 0 where the path touches or enters an obstacle.

        Circles are measured analytically (closest point of each segment to the centre, minus the
        radius), other obstacles with shapely. For a polyline inside the bounds the nearest point to
        a wall border is a vertex.

        Examples
        --------
        >>> w = world_from_dict({"bounds": [0, 0, 10, 10],
        ...                      "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}]})
        >>> round(w.clearance([[0, 3], [10, 3]]), 6), w.clearance([[0, 5], [10, 5]])
        (1.0, 0.0)
        """
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        if len(pts) == 0:
            return math.nan
        best = math.inf
        a, b = pts[:-1], pts[1:]
        line = shapely.linestrings(pts) if len(pts) > 1 else shapely.points(pts[0])
        for ob in self.obstacles:
            if ob.kind == "circle":
                assert ob.center is not None and ob.radius is not None
                c = np.asarray(ob.center, dtype=float)
                if len(a):
                    v = b - a
                    vv = np.einsum("ij,ij->i", v, v)
                    with np.errstate(invalid="ignore", divide="ignore"):
                        t = np.clip(np.where(vv > 0, np.einsum("ij,ij->i", c - a, v) / vv, 0.0), 0.0, 1.0)
                    dist = float(np.min(np.hypot(*(a + t[:, None] * v - c).T)))
                else:
                    dist = float(np.hypot(*(pts[0] - c)))
                best = min(best, max(dist - ob.radius, 0.0))
            else:
                best = min(best, float(shapely.distance(ob.geometry, line)))
        if self.border == "wall":
            xmin, ymin, xmax, ymax = self.bounds
            dw = np.minimum.reduce([pts[:, 0] - xmin, xmax - pts[:, 0], pts[:, 1] - ymin, ymax - pts[:, 1]])
            best = min(best, float(np.maximum(dw, 0.0).min()))
        return best

    def union(self) -> BaseGeometry:
        """All obstacles as one shapely geometry."""
        return shapely.union_all([ob.geometry for ob in self.obstacles])

    def contains_free(self, point: ArrayLike) -> bool:
        """True if the point is inside the bounds and not inside or on any obstacle."""
        x, y = (float(v) for v in np.asarray(point, dtype=float).reshape(2))
        xmin, ymin, xmax, ymax = self.bounds
        if not (xmin <= x <= xmax and ymin <= y <= ymax):
            return False
        return bool(np.all(np.asarray([ob.distance([[x, y]])[0] for ob in self.obstacles]) > 0))

    def check_point(self, name: str, point: ArrayLike) -> NDArray[np.float64]:
        """Validate a start/goal point against the world; return it as ``(2,)`` or raise."""
        p = np.asarray(point, dtype=float).reshape(-1)
        if p.shape != (2,) or not np.all(np.isfinite(p)):
            raise GridfieldError(f"{name} must be two finite numbers X Y, got {shorten(point)}")
        xmin, ymin, xmax, ymax = self.bounds
        if not (xmin <= p[0] <= xmax and ymin <= p[1] <= ymax):
            raise GridfieldError(
                f"{name} ({p[0]:g}, {p[1]:g}) lies outside the world bounds [{xmin:g}, {ymin:g}, {xmax:g}, {ymax:g}]"
            )
        for ob in self.obstacles:
            if ob.distance(p[None, :])[0] <= 0.0:
                raise GridfieldError(f"{name} ({p[0]:g}, {p[1]:g}) lies inside obstacle {ob.id} ({ob.kind})")
        return p

    def __repr__(self) -> str:
        def pt(p: tuple[float, float] | None) -> str:
            return "None" if p is None else f"({p[0]:.6g}, {p[1]:.6g})"

        name = self.source.replace("\\", "/").rsplit("/", 1)[-1]
        return (f"World(obstacles={len(self.obstacles)}, bounds=({', '.join(f'{v:.6g}' for v in self.bounds)}), "
                f"border={self.border!r}, start={pt(self.start)}, goal={pt(self.goal)}, source={name!r})")


# ----------------------------------------------------------------------------------------
# Parsing plain data (as read from YAML) into a World
# ----------------------------------------------------------------------------------------
def _where(source: str, key: str) -> str:
    return f"{source}: {key}" if source else key


def _point(value: Any, what: str) -> tuple[float, float]:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise MapFormatError(f"{what} must be a point [x, y], got {shorten(value)}") from None
    if arr.shape != (2,):
        raise MapFormatError(f"{what} must be a point [x, y], got {shorten(value)}")
    if not np.all(np.isfinite(arr)):
        raise MapFormatError(f"{what} must be finite numbers, got {shorten(value)}")
    return (float(arr[0]), float(arr[1]))


def _points(value: Any, what: str) -> NDArray[np.float64]:
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) == 0:
        raise MapFormatError(f"{what} must be a list of points [[x, y], ...], got {shorten(value)}")
    return np.array([_point(v, f"{what}[{i}]") for i, v in enumerate(value)])


def sort_vertices(pts: ArrayLike) -> NDArray[np.float64]:
    """Vertices sorted counter-clockwise by their angle around the centroid (mean) of the vertices.

    The VerticesSorter of the attractive/repulsive exercise: a polygon whose vertices are listed in any order becomes the polygon
    through them in angular order (a simple polygon when the vertices are in convex position, or more
    generally when the polygon is star-shaped about their centroid). Ties in angle are broken by the
    distance to the centroid.

    Parameters
    ----------
    pts : array_like, shape (N, 2)
        The vertices, in any order.

    Returns
    -------
    ndarray, shape (N, 2)
        The same vertices, starting from the one of smallest angle in ``(-pi, pi]``.

    Examples
    --------
    >>> sort_vertices([[0, 0], [1, 1], [1, 0], [0, 1]]).tolist()
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    """
    p = np.asarray(pts, dtype=float).reshape(-1, 2)
    rel = p - p.mean(axis=0)
    order = np.lexsort((np.hypot(rel[:, 0], rel[:, 1]), np.arctan2(rel[:, 1], rel[:, 0])))
    return p[order]


def _vertex_order(value: Any, what: str) -> str:
    if value not in VERTEX_ORDERS:
        raise MapFormatError(f"{what}: expected one of {list(VERTEX_ORDERS)}, got {value!r}")
    return str(value)


def _polygon(pts: NDArray[np.float64], oid: int, what: str, order: str,
             star_center: tuple[float, float] | None = None) -> Obstacle:
    """A ``polygon:`` entry: at least 3 distinct, not all collinear vertices, simple in the given order."""
    if len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
        pts = pts[:-1]  # a repeated closing vertex
    n = len(np.unique(pts, axis=0))
    if n < 3:
        raise MapFormatError(
            f"{what} (obstacle {oid}) has {n} distinct vertex{'es' if n != 1 else ''}; a polygon needs at least 3"
            + (" (use segment: [[x1, y1], [x2, y2]] for a segment)" if n == 2 else " (use point: [x, y] for a point)")
        )
    rel = pts - pts[0]
    d = rel[np.argmax(np.hypot(rel[:, 0], rel[:, 1]))]
    if np.all(rel[:, 0] * d[1] - rel[:, 1] * d[0] == 0.0):
        raise MapFormatError(f"{what} (obstacle {oid}): all vertices are collinear, the polygon has no area "
                             "(use segment: for a segment)")
    if order == "sort":
        pts = sort_vertices(np.unique(pts, axis=0))
    poly = Polygon(pts)
    if not poly.is_valid:
        reason = shapely.is_valid_reason(poly)
        if order == "sort":
            raise MapFormatError(f"{what} (obstacle {oid}) is not a simple polygon ({reason}) even with its vertices "
                                 "sorted by angle around their centroid (vertex_order: sort); list them in order "
                                 "around it")
        raise MapFormatError(f"{what} (obstacle {oid}) is not a simple polygon as given ({reason}); list the "
                             "vertices in order around it, or set vertex_order: sort to sort them by angle around "
                             "their centroid")
    return Obstacle(oid, "polygon", poly, star_center=star_center)


def _shape_from_vertices(pts: NDArray[np.float64], oid: int, what: str, order: str = "as_given") -> Obstacle:
    """A b_matrix obstacle or a rectangle: degenerate vertex lists become points and segments."""
    # drop a repeated closing vertex
    if len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
        pts = pts[:-1]
    if len(pts) == 1:
        return Obstacle(oid, "point", Point(pts[0]))
    if len(pts) == 2:
        if np.array_equal(pts[0], pts[1]):
            return Obstacle(oid, "point", Point(pts[0]))
        return Obstacle(oid, "segment", LineString(pts))
    rel = pts - pts[0]
    d = rel[np.argmax(np.hypot(rel[:, 0], rel[:, 1]))]
    if np.all(rel[:, 0] * d[1] - rel[:, 1] * d[0] == 0.0):
        # all vertices collinear (a zero signed area alone would also accept a symmetric bow-tie):
        # the obstacle is the segment between the two extreme vertices
        t = rel @ d
        return Obstacle(oid, "segment", LineString([pts[np.argmin(t)], pts[np.argmax(t)]]))
    return _polygon(pts, oid, what, order)


def _polygon_entry(value: Any, oid: int, what: str, order: str) -> Obstacle:
    """A ``polygon`` obstacle: a list of points, or ``{vertices, center, vertex_order}``."""
    star_center = None
    if isinstance(value, Mapping):
        bad = sorted(set(value) - {"vertices", "center", "vertex_order"}, key=str)
        if bad or "vertices" not in value:
            raise MapFormatError(f"{what}.polygon must be a list of points or a mapping with 'vertices' and "
                                 f"optional 'center' and 'vertex_order', got {value!r}")
        if "vertex_order" in value:
            order = _vertex_order(value["vertex_order"], f"{what}.polygon.vertex_order")
        if value.get("center") is not None:
            star_center = _point(value["center"], f"{what}.polygon.center")
        value = value["vertices"]
    return _polygon(_points(value, f"{what}.polygon"), oid, f"{what}.polygon", order, star_center)


def _segment_entry(value: Any, oid: int, what: str) -> Obstacle:
    """A ``segment`` obstacle: exactly two points."""
    pts = _points(value, f"{what}.segment")
    if len(pts) != 2:
        raise MapFormatError(f"{what}.segment must have exactly two points, got {len(pts)}")
    return _shape_from_vertices(pts, oid, f"{what}.segment")


def _circle_entry(value: Any, oid: int, what: str) -> Obstacle:
    """A ``circle`` obstacle: ``{center: [x, y], radius: r}`` (a polygon of CIRCLE_SEGMENTS per quarter)."""
    if not isinstance(value, Mapping) or "center" not in value or "radius" not in value:
        raise MapFormatError(f"{what}.circle must be {{center: [x, y], radius: r}}, got {shorten(value)}")
    c = _point(value["center"], f"{what}.circle.center")
    try:
        r = float(value["radius"])
    except (TypeError, ValueError):
        r = math.nan
    if not (math.isfinite(r) and r > 0):
        raise MapFormatError(f"{what}.circle.radius must be a positive number, got {shorten(value['radius'])}")
    geom = Point(c).buffer(r, quad_segs=CIRCLE_SEGMENTS)
    return Obstacle(oid, "circle", geom, center=c, radius=r)


def _rectangle_corners(value: Any, what: str) -> tuple[tuple[float, float], tuple[float, float]]:
    """The lower and upper corners of a ``rectangle`` entry, in any of its three forms."""
    if isinstance(value, Mapping):
        if "min" in value and "max" in value:
            return _point(value["min"], f"{what}.rectangle.min"), _point(value["max"], f"{what}.rectangle.max")
        if "center" in value and "size" in value:
            c = _point(value["center"], f"{what}.rectangle.center")
            s = _point(value["size"], f"{what}.rectangle.size")
            return (c[0] - s[0] / 2, c[1] - s[1] / 2), (c[0] + s[0] / 2, c[1] + s[1] / 2)
        raise MapFormatError(
            f"{what}.rectangle must be [xmin, ymin, xmax, ymax], {{min: [x, y], max: [x, y]}} "
            f"or {{center: [x, y], size: [w, h]}}; got {shorten(value)}"
        )
    try:
        xmin, ymin, xmax, ymax = (float(v) for v in value)
    except (TypeError, ValueError):
        raise MapFormatError(f"{what}.rectangle must be [xmin, ymin, xmax, ymax], got {shorten(value)}") from None
    return (xmin, ymin), (xmax, ymax)


def _rectangle_entry(value: Any, oid: int, what: str) -> Obstacle:
    """A ``rectangle`` obstacle (a degenerate one is a segment or a point)."""
    lo, hi = _rectangle_corners(value, what)
    if not all(math.isfinite(v) for v in (*lo, *hi)) or hi[0] < lo[0] or hi[1] < lo[1]:
        raise MapFormatError(f"{what}.rectangle needs finite min <= max, got {shorten(value)}")
    pts = np.array([lo, (hi[0], lo[1]), hi, (lo[0], hi[1])])
    return _shape_from_vertices(np.unique(pts, axis=0) if (hi[0] == lo[0] or hi[1] == lo[1]) else pts,
                                oid, f"{what}.rectangle")


def _obstacle(entry: Any, oid: int, what: str, order: str = "as_given") -> Obstacle:
    if not isinstance(entry, Mapping) or len(entry) != 1:
        raise MapFormatError(
            f"{what} must be a mapping with one key: polygon, circle, segment, rectangle or point; got {shorten(entry)}"
        )
    (kind, value), = entry.items()
    if kind == "polygon":
        return _polygon_entry(value, oid, what, order)
    if kind == "point":
        return Obstacle(oid, "point", Point(_point(value, f"{what}.point")))
    if kind == "segment":
        return _segment_entry(value, oid, what)
    if kind == "circle":
        return _circle_entry(value, oid, what)
    if kind == "rectangle":
        return _rectangle_entry(value, oid, what)
    raise MapFormatError(f"{what}: unknown obstacle kind {shorten(kind)}; expected polygon, circle, segment, rectangle "
                         "or point")


def _b_matrix(value: Any, first_id: int, what: str, order: str = "as_given") -> list[Obstacle]:
    try:
        b = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise MapFormatError(f"{what} must be three rows of numbers (x, y, obstacle id)") from None
    if b.ndim != 2 or b.shape[0] != 3 or b.shape[1] == 0:
        raise MapFormatError(f"{what} must be three rows (x, y, obstacle id), got shape {b.shape}")
    if not np.all(np.isfinite(b)):
        raise MapFormatError(f"{what} must hold finite numbers")
    tags = b[2]
    if not np.all(tags == np.round(tags)):
        raise MapFormatError(f"{what}: the third row holds obstacle ids and must be integers, got {tags.tolist()}")
    if np.any(tags < first_id):
        raise MapFormatError(
            f"{what}: the third row holds obstacle ids, which must be integers >= {first_id}, "
            f"got {sorted(set(tags.astype(int).tolist()))} (for 0-based ids add 1)"
        )
    obstacles = []
    for tag in dict.fromkeys(tags.astype(int).tolist()):  # order of first appearance
        pts = b[:2, tags == tag].T
        obstacles.append(_shape_from_vertices(pts, int(tag), f"{what} obstacle {tag}", order))
    return obstacles


def world_from_dict(data: Any, *, source: str = "") -> World:
    """Build a validated :class:`World` from the data of a world file.

    Keys: ``bounds`` (required), ``border`` (``open`` default, or ``wall``), ``obstacles``
    (list), ``b_matrix`` (the three-row vertex matrix of the segment worlds), ``start``, ``goal``, ``params``,
    ``resolution`` (default cell size when the world is rasterized), ``vertex_order``, ``robot`` (the
    robot's shape, see :func:`robot_from_value`; the commands plan in its configuration space).

    A ``polygon`` obstacle is a list of at least 3 distinct vertices (not all collinear), or a mapping
    ``{vertices: [...], center: [x, y], vertex_order: ...}`` (``center``: the point it is star-shaped
    about, for ``star-nav``). ``vertex_order`` (per file, overridden per polygon) is ``as_given``
    (default: the vertices must be listed in order around the polygon) or ``sort`` (they are sorted
    by angle around their centroid, the VerticesSorter: :func:`sort_vertices`); it also applies
    to the polygons of a ``b_matrix``, whose one- and two-vertex obstacles are points and segments.

    Parameters
    ----------
    data : mapping
        The file's content as read from YAML.
    source : str, default ""
        The file's name, put in front of every message.

    Returns
    -------
    World
        With obstacle ids numbered from 1 in file order (``b_matrix`` first).

    Examples
    --------
    >>> w = world_from_dict({"bounds": [0, 0, 4, 4], "vertex_order": "sort",
    ...                      "obstacles": [{"polygon": [[1, 1], [2, 2], [2, 1], [1, 2]]}]})
    >>> w.obstacles[0].vertices.tolist()
    [[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]]
    >>> world_from_dict({"bounds": [0, 0, 4, 4], "obstacles": [{"polygon": [[1, 1], [2, 2], [2, 1], [1, 2]]}]})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.MapFormatError: obstacles[0].polygon (obstacle 1) is not a simple polygon as given ...

    Raises
    ------
    MapFormatError
        naming ``source`` and the key at fault.
    """
    if not isinstance(data, Mapping):
        raise MapFormatError(f"{source or 'world'}: a world file must be a YAML mapping with at least 'bounds'")
    unknown = sorted(set(data) - _WORLD_KEYS, key=str)
    if unknown:
        raise MapFormatError(f"{_where(source, unknown[0])}: unknown key; expected one of {sorted(_WORLD_KEYS)}")
    bounds = _bounds(data, source)
    border = data.get("border", "open")
    if border not in BORDERS:
        raise MapFormatError(f"{_where(source, 'border')}: expected one of {list(BORDERS)}, got {shorten(border)}")
    obstacles = _obstacles(data, source, border)
    resolution = _resolution(data, source)
    params = _world_params(data, source)
    robot = robot_from_value(data["robot"], _where(source, "robot")) if data.get("robot") is not None else None
    world = World(bounds=bounds, obstacles=tuple(obstacles), border=border, params=dict(params),
                  resolution=resolution, source=source)
    start = goal = None
    if data.get("start") is not None:
        start = _point(data["start"], _where(source, "start"))
        _check_in_world(world, "start", start, source)
    if data.get("goal") is not None:
        goal = _point(data["goal"], _where(source, "goal"))
        _check_in_world(world, "goal", goal, source)
    return World(bounds=bounds, obstacles=tuple(obstacles), border=border, start=start, goal=goal,
                 params=dict(params), resolution=resolution, source=source, robot=robot)


#: The keys of a world file.
_WORLD_KEYS = frozenset({"bounds", "border", "obstacles", "b_matrix", "start", "goal", "params", "resolution",
                         "name", "description", "vertex_order", "robot"})


def _bounds(data: Mapping[str, Any], source: str) -> tuple[float, float, float, float]:
    """The world file's ``bounds``: four finite numbers with max > min."""
    if "bounds" not in data:
        raise MapFormatError(f"{_where(source, 'bounds')}: missing; a world needs bounds: [xmin, ymin, xmax, ymax]")
    try:
        bounds = tuple(float(v) for v in data["bounds"])
    except (TypeError, ValueError):
        bounds = ()
    if len(bounds) != 4 or not all(math.isfinite(v) for v in bounds) or not (
        bounds[2] > bounds[0] and bounds[3] > bounds[1]
    ):
        raise MapFormatError(
            f"{_where(source, 'bounds')}: expected [xmin, ymin, xmax, ymax] with finite max > min, got {shorten(data['bounds'])}"
        )
    return bounds[0], bounds[1], bounds[2], bounds[3]


def _obstacles(data: Mapping[str, Any], source: str, border: str) -> list[Obstacle]:
    """The world file's obstacles: its ``b_matrix`` first, then its ``obstacles``, numbered from 1."""
    order = _vertex_order(data.get("vertex_order", "as_given"), _where(source, "vertex_order"))
    obstacles: list[Obstacle] = []
    if "b_matrix" in data:
        obstacles += _b_matrix(data["b_matrix"], 1, _where(source, "b_matrix"), order)
    raw = data.get("obstacles") or []
    if not isinstance(raw, Sequence) or isinstance(raw, str):
        raise MapFormatError(f"{_where(source, 'obstacles')}: expected a list of obstacles, got {shorten(raw)}")
    next_id = max((o.id for o in obstacles), default=0) + 1
    for i, entry in enumerate(raw):
        obstacles.append(_obstacle(entry, next_id + i, _where(source, f"obstacles[{i}]"), order))
    if not obstacles and border == "open":
        raise MapFormatError(
            f"{source or 'world'}: the world is empty (no obstacles and an open border); "
            "add obstacles or set border: wall"
        )
    return obstacles


def _resolution(data: Mapping[str, Any], source: str) -> float | None:
    """The world file's ``resolution`` (a positive number), or None."""
    resolution = data.get("resolution")
    if resolution is None:
        return None
    try:
        value = float(resolution)
    except (TypeError, ValueError):
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise MapFormatError(f"{_where(source, 'resolution')}: must be a positive number, got {shorten(resolution)}")
    return value


def _world_params(data: Mapping[str, Any], source: str) -> Mapping[str, Any]:
    """The world file's ``params`` mapping (values checked by the planners; NaN refused here)."""
    params = data.get("params") or {}
    if not isinstance(params, Mapping):
        raise MapFormatError(f"{_where(source, 'params')}: expected a mapping of parameter names to values")
    for k, v in params.items():
        if isinstance(v, bool | str):
            continue
        if isinstance(v, int | float) and math.isnan(v):
            raise MapFormatError(f"{_where(source, 'params.' + str(k))}: must not be NaN")
    return params


def _check_in_world(world: World, name: str, p: tuple[float, float], source: str) -> None:
    try:
        world.check_point(name, p)
    except GridfieldError as e:
        raise MapFormatError(f"{source}: {e}" if source else str(e)) from None
