"""Exact shortest paths among polygonal obstacles: the visibility graph.

The shortest path between two points of a plane with polygonal obstacles is a polyline whose
inner vertices are obstacle corners (Lozano-Pérez & Wesley 1979; Choset et al. ch. 5.1). The
*visibility graph* joins every pair of mutually visible corners; a Dijkstra search over it, with
the start and the goal added, gives the exact optimum. This module builds that graph on shapely
geometry and solves it with :func:`scipy.sparse.csgraph.dijkstra`.

Free space
    The free space is **closed**: a path may touch obstacle boundaries, run along edges and
    start or end on an edge or a vertex. With ``border: wall`` the world's bounds are a wall;
    with ``border: open`` the plane outside the bounds is free. Touching or overlapping
    obstacles act as their union.

Segments and points
    A segment obstacle has no area: a path may not cross it through its relative interior but
    may run along it and go round its end points. A point obstacle never blocks (a path may pass
    arbitrarily close round it) and is ignored.

Pinch points (``pinch=``)
    Where two obstacles touch at a single point (two squares touching corner to corner, a
    segment ending on a polygon edge) the closed free space is connected *through* that point.

    - ``"block"`` (default, the physically meaningful rule and Polyanya's): a path must be a
      limit of paths through the open free space, so it may not squeeze through a pinch point;
      it may still touch it from one side. A start or goal exactly on a pinch point, or on the
      relative interior of a segment obstacle, is ambiguous (which side is it on?) and raises
      :class:`~gridfield.core.errors.GridfieldError`.
    - ``"pass"`` (extremitypathfinder's rule): a path may pass through any point of the closed
      free space where obstacles merely touch; only the relative interior of a segment obstacle
      may not be crossed.

Circles
    A circle is replaced by its **circumscribed** regular polygon with ``4 * CIRCLE_SEGMENTS``
    (= 64) sides, whose edges are tangent to the circle. The planned path is therefore feasible
    (it never enters the true circle) and at most slightly too long: with ``R = r / cos(pi/64)``
    the polygon lies between the circles of radius ``r`` and ``R``, and the length of a geodesic
    wrapped round a circle grows with the radius at the rate of the wrapped angle ``phi``, so the
    excess is at most ``phi * (R - r) = phi * r * 1.2e-3`` per circle wrapped
    (``<= 2*pi * r * 1.2e-3 = 0.0076 r``). An inscribed outline would instead give paths up to
    ``r * (1 - cos(pi/64))`` inside the circle and lengths too short by about ``4e-4 * r * phi``.

Examples
--------
>>> from gridfield.geometry.world import world_from_dict
>>> w = world_from_dict({"bounds": [0, 0, 10, 10], "border": "wall",
...                      "obstacles": [{"rectangle": [4, 0, 6, 8]}]})
>>> vg = visibility_graph(w)
>>> pts, length = vg.shortest_path([1, 1], [9, 1])
>>> pts.tolist()
[[1.0, 1.0], [4.0, 8.0], [6.0, 8.0], [9.0, 1.0]]
>>> round(length, 6)
17.231546
"""

from __future__ import annotations

import math
import time
import weakref
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree
from shapely.geometry import Point, Polygon, box
from shapely.geometry.base import BaseGeometry

from ..core.errors import GridfieldError, MapFormatError, ParameterError
from ..core.params import validate
from ..core.path import Path
from ..geometry.world import Obstacle, World
from ._visibility_geometry import (
    _ANGLE_EPS,
    _TWO_PI,
    CIRCLE_OUTLINE_EXCESS,
    _angle,
    _area_union,
    _dedupe,
    _free_arcs,
    _in_arc,
    _obstacle_at,
    _properly_cross,
    _rings,
)

__all__ = [
    "PINCH_RULES",
    "VisibilityGraph",
    "cached_visibility_graph",
    "plan_visibility",
    "visibility_graph",
    "world_from_polygon_environment",
]

#: How a path may treat a point where obstacles touch (see the module docstring).
PINCH_RULES = ("block", "pass")


# ----------------------------------------------------------------------------------------
# World construction for polygon environments (boundary + holes)
# ----------------------------------------------------------------------------------------
def _as_ring(coords: Any, what: str) -> Polygon:
    try:
        pts = np.asarray(coords, dtype=float)
    except (TypeError, ValueError):
        raise MapFormatError(f"{what} must be a list of points [[x, y], ...], got {coords!r}") from None
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 3:
        raise MapFormatError(f"{what} must be at least three points [[x, y], ...], got shape {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise MapFormatError(f"{what} must hold finite coordinates")
    poly = Polygon(pts)
    if not poly.is_valid or poly.area == 0.0:
        reason = shapely.is_valid_reason(poly) if not poly.is_valid else "zero area"
        raise MapFormatError(f"{what} is not a simple polygon ({reason}); list the vertices in order around it")
    return poly


def world_from_polygon_environment(
    boundary: ArrayLike,
    holes: Sequence[ArrayLike] = (),
    *,
    start: ArrayLike | None = None,
    goal: ArrayLike | None = None,
    source: str = "",
) -> World:
    """A :class:`World` whose free space is inside ``boundary`` and outside every hole.

    This is the environment model of extremitypathfinder and of navigation meshes: the bounds
    become the bounding box of ``boundary`` with a wall border, the parts of that box outside
    the boundary become polygon obstacles, and each hole becomes a polygon obstacle (ids: the
    holes first, in order, then the outside parts). Holes may overlap each other and the
    boundary; the union is what counts. Orientation of the rings does not matter.

    ``start`` and ``goal`` are stored as given (they may lie on edges: the free space is
    closed); they are checked when a path is planned.

    Parameters
    ----------
    boundary : array_like, shape (N, 2)
        The outer ring of the free space (a simple polygon, N >= 3).
    holes : sequence of array_like, shape (M, 2)
        Obstacle rings inside it.
    start, goal : array_like, shape (2,), optional
        Stored in the world.
    source : str
        Where the environment came from (kept as the world's ``source``).

    Returns
    -------
    World
        Polygon obstacles only, a wall border at the boundary's bounding box.

    Examples
    --------
    >>> w = world_from_polygon_environment([[0, 0], [4, 0], [4, 4], [2, 2], [0, 4]],
    ...                                    [[[1, 0.5], [1, 1], [1.5, 1]]])
    >>> w.bounds, w.border, [ob.kind for ob in w.obstacles]
    ((0.0, 0.0, 4.0, 4.0), 'wall', ['polygon', 'polygon'])
    >>> round(visibility_graph(w).shortest_path([0.5, 3.5], [3.5, 3.5])[1], 6)
    4.242641
    """
    outer = _as_ring(boundary, "boundary")
    obstacles: list[Obstacle] = []
    for i, h in enumerate(holes):
        obstacles.append(Obstacle(len(obstacles) + 1, "polygon", _as_ring(h, f"holes[{i}]")))
    xmin, ymin, xmax, ymax = outer.bounds
    outside = box(xmin, ymin, xmax, ymax).difference(outer)
    for part in shapely.get_parts(outside):
        if isinstance(part, Polygon) and part.area > 0:
            obstacles.append(Obstacle(len(obstacles) + 1, "polygon", shapely.normalize(part)))

    def pt(v: ArrayLike | None, name: str) -> tuple[float, float] | None:
        if v is None:
            return None
        p = np.asarray(v, dtype=float).reshape(-1)
        if p.shape != (2,) or not np.all(np.isfinite(p)):
            raise MapFormatError(f"{name} must be two finite numbers [x, y], got {v!r}")
        return (float(p[0]), float(p[1]))

    return World(bounds=(xmin, ymin, xmax, ymax), obstacles=tuple(obstacles), border="wall",
                 start=pt(start, "start"), goal=pt(goal, "goal"), source=source)


# ----------------------------------------------------------------------------------------
# The graph
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class VisibilityGraph:
    """A visibility graph of a world, reusable for many start/goal queries.

    Build it with :func:`visibility_graph`.

    Attributes
    ----------
    world : World
    pinch : {"block", "pass"}
        The pinch-point rule (module docstring).
    nodes : ndarray, shape (n, 2)
        Corner points: convex obstacle vertices, segment end points and the sides of pinch points.
    edges : ndarray of int, shape (m, 2)
        Pairs of mutually visible nodes (only bitangent pairs: a shortest path uses no others).
    weights : ndarray, shape (m,)
        Euclidean edge lengths.
    obstacles : shapely geometry
        The union of the area obstacles as the graph sees them (circles circumscribed, the wall
        border as a frame round the bounds).

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 4, 6, 6]}]})
    >>> vg = visibility_graph(w)
    >>> vg.n_nodes, vg.pinch, sorted(map(tuple, vg.nodes.tolist()))
    (4, 'block', [(4.0, 4.0), (4.0, 6.0), (6.0, 4.0), (6.0, 6.0)])
    >>> round(vg.shortest_path([3, 5], [7, 5])[1], 6) == round(2 * 2 ** 0.5 + 2, 6)
    True
    """

    world: World
    pinch: str
    nodes: NDArray[np.float64]
    edges: NDArray[np.intp]
    weights: NDArray[np.float64]
    obstacles: BaseGeometry
    _tol: float = field(repr=False)
    _parts: NDArray[np.object_] = field(repr=False)
    _part_tree: shapely.STRtree = field(repr=False)
    _segments: NDArray[np.object_] = field(repr=False)
    _segment_tree: shapely.STRtree = field(repr=False)
    _segment_ids: NDArray[np.intp] = field(repr=False)
    _seg_coords: NDArray[np.float64] = field(repr=False)
    #: tangent test at nodes: previous/next ring vertex, NaN where no test applies
    _prev: NDArray[np.float64] = field(repr=False)
    _next: NDArray[np.float64] = field(repr=False)
    #: closed free arc (start, width) a node may be left through; NaN: any direction
    _wedge: NDArray[np.float64] = field(repr=False)
    #: points where the free space has several separate sides (block rule), and their free arcs
    _critical: tuple[tuple[NDArray[np.float64], tuple[tuple[float, float], ...]], ...] = field(repr=False)
    seconds: float = 0.0

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def n_edges(self) -> int:
        return len(self.edges)

    # -- visibility ------------------------------------------------------------------
    def visible(self, p: ArrayLike, q: ArrayLike) -> NDArray[np.bool_]:
        """Whether the straight segments ``p[i] -> q[i]`` are admissible paths.

        ``p`` and ``q`` are points ``(2,)`` or arrays ``(N, 2)``. A segment is admissible when it
        does not enter the interior of an area obstacle, does not cross a segment obstacle and,
        under the ``block`` rule, does not pass through a pinch point from one side to another.

        Examples
        --------
        >>> from gridfield.geometry.world import world_from_dict
        >>> w = world_from_dict({"bounds": [0, 0, 4, 4],
        ...                      "obstacles": [{"rectangle": [1, 1, 2, 2]}, {"rectangle": [2, 2, 3, 3]}]})
        >>> visibility_graph(w).visible([[1, 3], [0, 1]], [[3, 1], [4, 1]]).tolist()
        [False, True]
        >>> visibility_graph(w, pinch="pass").visible([1, 3], [3, 1]).tolist()
        [True]
        """
        P = np.atleast_2d(np.asarray(p, dtype=float))
        Q = np.atleast_2d(np.asarray(q, dtype=float))
        P, Q = np.broadcast_arrays(P, Q)
        return self._admissible(P, Q)

    def _admissible(self, P: NDArray[np.float64], Q: NDArray[np.float64]) -> NDArray[np.bool_]:
        m = len(P)
        ok = np.ones(m, dtype=bool)
        if m == 0:
            return ok
        d = Q - P
        length = np.hypot(d[:, 0], d[:, 1])
        proper = length > self._tol
        idx = np.flatnonzero(proper)
        if len(idx) == 0:
            return ok
        lines = shapely.linestrings(np.stack([P[idx], Q[idx]], axis=1))
        if len(self._parts):
            li, pj = self._part_tree.query(lines)  # bounding boxes; then the prepared obstacle
            touch = shapely.intersects(self._parts[pj], lines[li])
            li, pj = li[touch], pj[touch]
            if len(li):
                hit = shapely.relate_pattern(lines[li], self._parts[pj], "T********")
                ok[idx[li[hit]]] = False
        if len(self._segments):
            # proper crossings: each segment's end points strictly on both sides of the other's line
            li, sj = self._segment_tree.query(lines, predicate="intersects")
            if len(li):
                a, b = P[idx[li]], Q[idx[li]]
                c, e = self._seg_coords[sj, 0], self._seg_coords[sj, 1]
                ok[idx[li[_properly_cross(a, b, c, e, self._tol)]]] = False
        for c, arcs in self._critical:
            # segments whose relative interior passes through the pinch point c
            rel = c - P
            t = (rel[:, 0] * d[:, 0] + rel[:, 1] * d[:, 1]) / np.where(proper, length, 1.0)
            off = np.abs(d[:, 0] * rel[:, 1] - d[:, 1] * rel[:, 0]) / np.where(proper, length, 1.0)
            through = ok & proper & (off <= 4 * self._tol) & (t > self._tol) & (t < length - self._tol)
            if not through.any():
                continue
            k = np.flatnonzero(through)
            a_fwd = _angle(Q[k] - c)
            a_back = _angle(P[k] - c)
            common = np.zeros(len(k), dtype=bool)
            for s, w in arcs:
                common |= _in_arc(a_fwd, s, w) & _in_arc(a_back, s, w)
            ok[k[~common]] = False
        return ok

    def _node_ok(self, nodes: NDArray[np.intp], other: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Tangent and wedge conditions at graph nodes for segments towards ``other`` points."""
        u = self.nodes[nodes]
        d = other - u
        ok = np.ones(len(nodes), dtype=bool)
        a, b = self._prev[nodes], self._next[nodes]
        test = ~np.isnan(a[:, 0])
        if test.any():
            da, db = a[test] - u[test], b[test] - u[test]
            dd = d[test]
            ca = dd[:, 0] * da[:, 1] - dd[:, 1] * da[:, 0]
            cb = dd[:, 0] * db[:, 1] - dd[:, 1] * db[:, 0]
            scale = np.hypot(dd[:, 0], dd[:, 1])
            ca = np.where(np.abs(ca) <= self._tol * scale, 0.0, ca)
            cb = np.where(np.abs(cb) <= self._tol * scale, 0.0, cb)
            ok[test] = ca * cb >= 0.0
        w = self._wedge[nodes]
        wtest = ~np.isnan(w[:, 0])
        if wtest.any():
            th = _angle(d[wtest])
            rel = np.mod(th - w[wtest, 0], _TWO_PI)
            ok[wtest] &= (rel <= w[wtest, 1] + _ANGLE_EPS) | (rel >= _TWO_PI - _ANGLE_EPS)
        return ok

    # -- queries -----------------------------------------------------------------------
    def check_point(self, name: str, point: ArrayLike) -> NDArray[np.float64]:
        """Validate a start/goal point against the closed free space; return it as ``(2,)``.

        Raises
        ------
        GridfieldError
            when the point is not finite, outside the world's walls, inside an obstacle, or (under
            the ``block`` rule) on a pinch point or a segment obstacle, where its side is ambiguous.
        """
        p = np.asarray(point, dtype=float).reshape(-1)
        if p.shape != (2,) or not np.all(np.isfinite(p)):
            raise GridfieldError(f"{name} must be two finite numbers X Y, got {point!r}")
        x, y = p
        w = self.world
        if w.border == "wall":
            xmin, ymin, xmax, ymax = w.bounds
            if not (xmin <= x <= xmax and ymin <= y <= ymax):
                raise GridfieldError(f"{name} ({x:g}, {y:g}) lies outside the free space: outside the world's walls "
                                     f"[{xmin:g}, {ymin:g}, {xmax:g}, {ymax:g}]")
        pt = Point(p)
        if len(self._parts):
            hits = self._part_tree.query(pt, predicate="intersects")
            for j in hits:
                if shapely.contains(self._parts[j], pt):
                    ob = _obstacle_at(w, p)
                    what = f"obstacle {ob.id} ({ob.kind})" if ob is not None else "an obstacle"
                    extra = ""
                    if ob is not None and ob.kind == "circle":
                        extra = (" or within its circumscribed outline (the visibility graph's circle, "
                                 f"{CIRCLE_OUTLINE_EXCESS:.2%} of the radius outside it)")
                    raise GridfieldError(f"{name} ({x:g}, {y:g}) lies outside the free space: inside {what}{extra}")
        if self.pinch == "block":
            for c, arcs in self._critical:
                if np.hypot(*(p - c)) <= self._tol:
                    raise GridfieldError(
                        f"{name} ({x:g}, {y:g}) lies on a pinch point where obstacles touch: which side it is on is "
                        f"ambiguous ({len(arcs)} separate sides); move it off the point")
            if len(self._segments):
                for j in self._segment_tree.query(pt, predicate="dwithin", distance=self._tol):
                    seg = np.asarray(self._segments[j].coords)
                    if min(np.hypot(*(p - seg[0])), np.hypot(*(p - seg[1]))) > self._tol:
                        raise GridfieldError(
                            f"{name} ({x:g}, {y:g}) lies on segment obstacle {int(self._segment_ids[j])}: which side "
                            "it is on is ambiguous; move it off the segment")
        return p

    def shortest_path(self, start: ArrayLike, goal: ArrayLike) -> tuple[NDArray[np.float64], float]:
        """The shortest path from ``start`` to ``goal``: its vertices ``(k, 2)`` and its length.

        When no path exists, returns an empty ``(0, 2)`` array and ``inf``.

        Raises
        ------
        GridfieldError
            when ``start`` or ``goal`` is not in the free space (see :meth:`check_point`).

        Examples
        --------
        >>> w = world_from_polygon_environment([[0, 0], [3, 0], [3, 3], [0, 3]], [[[1, -1], [2, -1], [2, 4], [1, 4]]])
        >>> visibility_graph(w).shortest_path([0.5, 1], [2.5, 1])
        (array([], shape=(0, 2), dtype=float64), inf)
        """
        s = self.check_point("start", start)
        g = self.check_point("goal", goal)
        if np.hypot(*(g - s)) <= self._tol:
            return np.array([s, g]), float(np.hypot(*(g - s)))
        if self._admissible(s[None, :], g[None, :])[0]:
            return np.array([s, g]), float(np.hypot(*(g - s)))
        n = self.n_nodes
        all_nodes = np.arange(n)
        rows, cols, vals = [], [], []
        for k, p in ((n, s), (n + 1, g)):
            far = np.hypot(*(self.nodes - p).T) > self._tol
            cand = all_nodes[far]
            cand = cand[self._node_ok(cand, np.broadcast_to(p, (len(cand), 2)))]
            vis = self._admissible(np.broadcast_to(p, (len(cand), 2)), self.nodes[cand])
            cand = cand[vis]
            rows.append(np.full(len(cand), k))
            cols.append(cand)
            vals.append(np.hypot(*(self.nodes[cand] - p).T))
        rows.append(self.edges[:, 0])
        cols.append(self.edges[:, 1])
        vals.append(self.weights)
        r, c, v = np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
        mat = sparse.csr_matrix((v, (r, c)), shape=(n + 2, n + 2))
        dist, pred = csgraph.dijkstra(mat, directed=False, indices=n, return_predecessors=True)
        if not np.isfinite(dist[n + 1]):
            return np.empty((0, 2)), math.inf
        order = [n + 1]
        while order[-1] != n:
            order.append(int(pred[order[-1]]))
        order.reverse()
        pts = np.vstack([s, self.nodes[order[1:-1]], g]) if len(order) > 2 else np.array([s, g])
        return pts, float(dist[n + 1])


# ----------------------------------------------------------------------------------------
# Building the graph
# ----------------------------------------------------------------------------------------

def visibility_graph(world: World, *, pinch: str = "block") -> VisibilityGraph:
    """Build the (reduced) visibility graph of a world.

    Parameters
    ----------
    world : World
        Polygons, circles (circumscribed 64-gons), segments; points are ignored.
    pinch : {"block", "pass"}
        Whether a path may squeeze through a point where obstacles touch (module docstring).

    Returns
    -------
    VisibilityGraph
        Reusable for any number of :meth:`VisibilityGraph.shortest_path` queries.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"segment": [[5, 2], [5, 8]]}]})
    >>> vg = visibility_graph(w)
    >>> vg.n_nodes
    2
    >>> pts, length = vg.shortest_path([4, 5], [6, 5])
    >>> pts.tolist(), round(length, 4)
    ([[4.0, 5.0], [5.0, 8.0], [6.0, 5.0]], 6.3246)
    """
    if pinch not in PINCH_RULES:
        raise ParameterError(f"pinch must be one of {', '.join(map(repr, PINCH_RULES))}, got {pinch!r}")
    if not isinstance(world, World):
        raise ParameterError(f"visibility_graph needs a World (vector obstacles), got {type(world).__name__}")
    t0 = time.perf_counter()
    xmin, ymin, xmax, ymax = world.bounds
    scale = max(1.0, abs(xmin), abs(ymin), abs(xmax), abs(ymax), xmax - xmin, ymax - ymin)
    tol = 1e-9 * scale

    union, parts, part_tree = _area_parts(world, tol)
    segments, segment_ids, segment_tree, seg_coords = _segment_index(world)
    rings = _rings(union)
    rv, _, rn = rings
    edges_geom = shapely.linestrings(np.stack([rv, rn], axis=1)) if len(rv) else np.empty(0, dtype=object)
    edge_tree = shapely.STRtree(edges_geom)
    vtree = cKDTree(rv) if len(rv) else None
    special = _special_ring_vertices(rings, edge_tree, vtree, segments, segment_tree, tol)
    special_pts = _special_points(rv[special], segments, segment_tree, seg_coords, union, parts, tol)

    nodes, prev, nxt, wedge, critical = _nodes(rings, special, special_pts, union, parts, edge_tree, vtree,
                                               segment_tree, seg_coords, pinch, tol, scale)
    if world.border == "wall":  # the outer corners of the wall frame are never reached
        inside = ((nodes[:, 0] >= xmin - tol) & (nodes[:, 0] <= xmax + tol)
                  & (nodes[:, 1] >= ymin - tol) & (nodes[:, 1] <= ymax + tol))
        nodes, prev, nxt, wedge = nodes[inside], prev[inside], nxt[inside], wedge[inside]

    graph = VisibilityGraph(
        world=world, pinch=pinch, nodes=nodes, edges=np.empty((0, 2), dtype=np.intp), weights=np.empty(0),
        obstacles=union, _tol=tol, _parts=parts, _part_tree=part_tree, _segments=segments,
        _segment_tree=segment_tree, _segment_ids=segment_ids, _seg_coords=seg_coords, _prev=prev, _next=nxt, _wedge=wedge,
        _critical=tuple(critical)
    )
    edges = _bitangent_edges(graph, nodes, prev, nxt, tol)
    weights = np.hypot(*(nodes[edges[:, 0]] - nodes[edges[:, 1]]).T)
    object.__setattr__(graph, "edges", edges)
    object.__setattr__(graph, "weights", weights)
    object.__setattr__(graph, "seconds", time.perf_counter() - t0)
    return graph


# the phases of visibility_graph, in order

def _area_parts(world: World, tol: float) -> tuple[Any, NDArray[Any], Any]:
    """The union of the area obstacles (prepared) and its parts shrunk by ``tol``, with their STRtree.

    Visibility is tested against the obstacles shrunk by ``tol``: a segment along an edge or
    grazing a corner stays admissible when rounding puts it 1e-16 inside (rotated maps).
    """
    union = _area_union(world)
    shapely.prepare(union)
    shrunk = shapely.buffer(union, -tol, join_style="mitre", mitre_limit=10.0) if not union.is_empty else union
    parts = np.asarray([g for g in shapely.get_parts(shrunk) if isinstance(g, Polygon) and not g.is_empty],
                       dtype=object)
    part_tree = shapely.STRtree(parts)
    shapely.prepare(parts)
    return union, parts, part_tree


def _segment_index(world: World) -> tuple[NDArray[Any], NDArray[np.intp], Any, NDArray[np.float64]]:
    """The segment obstacles: geometries, ids, their STRtree and end points ``(k, 2, 2)``."""
    seg_obs = [ob for ob in world.obstacles if ob.kind == "segment"]
    segments = np.asarray([ob.geometry for ob in seg_obs], dtype=object)
    segment_ids = np.asarray([ob.id for ob in seg_obs], dtype=np.intp)
    segment_tree = shapely.STRtree(segments)
    seg_coords = np.asarray([np.asarray(s.coords)[[0, -1]] for s in segments], dtype=float).reshape(-1, 2, 2)
    return segments, segment_ids, segment_tree, seg_coords


def _special_ring_vertices(rings: tuple[NDArray[np.float64], ...], edge_tree: Any, vtree: Any, segments: NDArray[Any],
                           segment_tree: Any, tol: float) -> NDArray[np.bool_]:
    """Which ring vertices touch something else: another vertex, another ring edge, a segment."""
    rv, _, rn = rings
    special = np.zeros(len(rv), dtype=bool)
    if vtree is not None:
        counts = np.asarray([len(g) for g in vtree.query_ball_point(rv, tol)])
        special |= counts > 1
        vi, ej = edge_tree.query(shapely.points(rv), predicate="dwithin", distance=tol)
        away = (np.hypot(*(rv[vi] - rv[ej]).T) > tol) & (np.hypot(*(rv[vi] - rn[ej]).T) > tol)
        special[vi[away]] = True
        if len(segments):
            vi, _ = segment_tree.query(shapely.points(rv), predicate="dwithin", distance=tol)
            special[vi] = True
    return special


def _special_points(special_rv: NDArray[np.float64], segments: NDArray[Any], segment_tree: Any,
                    seg_coords: NDArray[np.float64], union: Any, parts: NDArray[Any], tol: float) -> NDArray[np.float64]:
    """Special ring vertices, segment end points and segment intersections (with the area
    boundaries and with each other), deduplicated."""
    cand = [special_rv]
    if len(segments):
        cand.append(seg_coords.reshape(-1, 2))
        if len(parts):
            boundary = shapely.boundary(union)
            cand.append(shapely.get_coordinates(shapely.intersection(segments, boundary)))
        si, sj = segment_tree.query(segments, predicate="intersects")
        pair = si < sj
        if pair.any():
            cand.append(shapely.get_coordinates(shapely.intersection(segments[si[pair]], segments[sj[pair]])))
    return _dedupe(np.concatenate(cand) if cand else np.empty((0, 2)), tol)


def _occupied_directions(c: NDArray[np.float64], rings: tuple[NDArray[np.float64], ...], edge_tree: Any, vtree: Any,
                         segment_tree: Any, seg_coords: NDArray[np.float64], tol: float) -> list[tuple[float, float]]:
    """The angular sectors ``(start, width)`` round the point ``c`` taken by obstacles touching it."""
    rv, rp, rn = rings
    pt = Point(c)
    occupied: list[tuple[float, float]] = []
    if vtree is not None:
        for k in vtree.query_ball_point(c, tol):
            sb, sa = _angle(rn[k] - c), _angle(rp[k] - c)
            occupied.append((float(sb), float(np.mod(sa - sb, _TWO_PI))))
        for j in edge_tree.query(pt, predicate="dwithin", distance=tol):
            if np.hypot(*(rv[j] - c)) > tol and np.hypot(*(rn[j] - c)) > tol:
                occupied.append((float(_angle(rn[j] - c)), math.pi))
    for j in segment_tree.query(pt, predicate="dwithin", distance=tol):
        for end in seg_coords[j]:
            if np.hypot(*(c - end)) > tol:
                occupied.append((float(_angle(end - c)), 0.0))
    return occupied


def _nodes(rings: tuple[NDArray[np.float64], ...], special: NDArray[np.bool_], special_pts: NDArray[np.float64],
           union: Any, parts: NDArray[Any], edge_tree: Any, vtree: Any, segment_tree: Any,
           seg_coords: NDArray[np.float64], pinch: str, tol: float, scale: float) -> tuple[Any, ...]:
    """The graph's nodes: ``nodes, prev, next, wedge`` arrays (ring neighbours and free wedge, NaN
    where none) and the critical points ``(point, free arcs)`` of the ``block`` rule."""
    rv, rp, rn = rings
    node_pts: list[NDArray[np.float64]] = []
    node_prev: list[NDArray[np.float64]] = []
    node_next: list[NDArray[np.float64]] = []
    node_wedge: list[NDArray[np.float64]] = []
    critical: list[tuple[NDArray[np.float64], tuple[tuple[float, float], ...]]] = []

    def add(c: NDArray[np.float64], wedge: NDArray[np.float64]) -> None:
        node_pts.append(c[None, :])
        node_prev.append(np.full((1, 2), np.nan))
        node_next.append(np.full((1, 2), np.nan))
        node_wedge.append(wedge)

    # ordinary convex corners: a strict left turn of a ring (obstacle on the left)
    plain = ~special
    if plain.any():
        a, c, b = rp[plain], rv[plain], rn[plain]
        e1, e2 = c - a, b - c
        turn = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        convex = turn > tol * np.hypot(*e1.T) * np.hypot(*e2.T) / scale
        node_pts.append(c[convex])
        node_prev.append(a[convex])
        node_next.append(b[convex])
        node_wedge.append(np.full((convex.sum(), 2), np.nan))

    for c in special_pts:
        if len(parts) and shapely.contains(union, Point(c)):
            continue  # inside an area obstacle: never on a path
        arcs = _free_arcs(_occupied_directions(c, rings, edge_tree, vtree, segment_tree, seg_coords, tol))
        if not arcs:
            continue
        if pinch == "block":
            if len(arcs) > 1:
                critical.append((c, tuple(arcs)))
            for s, w in arcs:
                if w > math.pi + _ANGLE_EPS:  # a path can only bend round a side wider than a half-plane
                    add(c, np.array([[s, w]]) if len(arcs) > 1 else np.full((1, 2), np.nan))
        elif len(arcs) > 1 or arcs[0][1] > math.pi + _ANGLE_EPS:
            add(c, np.full((1, 2), np.nan))

    nodes = np.concatenate(node_pts) if node_pts else np.empty((0, 2))
    prev = np.concatenate(node_prev) if node_prev else np.empty((0, 2))
    nxt = np.concatenate(node_next) if node_next else np.empty((0, 2))
    wedge = np.concatenate(node_wedge) if node_wedge else np.empty((0, 2))
    return nodes, prev, nxt, wedge, critical


def _bitangent_edges(graph: VisibilityGraph, nodes: NDArray[np.float64], prev: NDArray[np.float64],
                     nxt: NDArray[np.float64], tol: float) -> NDArray[np.intp]:
    """Bitangent pairs ``i < j`` of the nodes that see each other, ``(m, 2)``.

    The tangent test at both ends runs by broadcasting over blocks of rows (no gathers over n^2
    pairs): the pair (i, j) is kept when the ring neighbours of i lie on one side of the line i-j,
    and those of j too; nodes without ring neighbours (NaN) always pass.
    """
    n = len(nodes)
    ei, ej = [], []
    has = ~np.isnan(prev[:, 0])
    da = np.where(has[:, None], prev - nodes, 0.0)
    db = np.where(has[:, None], nxt - nodes, 0.0)
    chunk = max(1, 1_000_000 // max(n, 1))
    for i0 in range(0, n, chunk):
        i1 = min(n, i0 + chunk)
        # rows i0:i1 against columns i0: (the pairs i < j of these rows)
        dx = nodes[None, i0:, 0] - nodes[i0:i1, None, 0]
        dy = nodes[None, i0:, 1] - nodes[i0:i1, None, 1]
        dist = np.hypot(dx, dy)
        eps = tol * dist
        keep = (np.arange(i0, n)[None, :] > np.arange(i0, i1)[:, None]) & (dist > tol)
        for a, b in ((da[i0:i1, None, :], db[i0:i1, None, :]), (da[None, i0:, :], db[None, i0:, :])):
            ca = dx * a[..., 1] - dy * a[..., 0]
            cb = dx * b[..., 1] - dy * b[..., 0]
            ca[np.abs(ca) <= eps] = 0.0
            cb[np.abs(cb) <= eps] = 0.0
            keep &= ca * cb >= 0.0
        ii, jj = np.nonzero(keep)
        ii += i0
        jj += i0
        keep = graph._node_ok(ii, nodes[jj]) & graph._node_ok(jj, nodes[ii])  # wedges of pinch points
        ii, jj = ii[keep], jj[keep]
        vis = graph._admissible(nodes[ii], nodes[jj])
        ei.append(ii[vis])
        ej.append(jj[vis])
    if not ei:
        return np.empty((0, 2), dtype=np.intp)
    return np.stack([np.concatenate(ei), np.concatenate(ej)], axis=1).astype(np.intp)


# ----------------------------------------------------------------------------------------
# The planner of the registry
# ----------------------------------------------------------------------------------------
_CACHE: weakref.WeakKeyDictionary[World, dict[str, VisibilityGraph]] = weakref.WeakKeyDictionary()


def cached_visibility_graph(world: World, pinch: str = "block") -> VisibilityGraph:
    """The :func:`visibility_graph` of ``world``, built once per world and pinch rule and kept while
    the world lives (what ``plan("visibility")`` and :func:`gridfield.compare.optimum_solver` share);
    refused up front (:func:`gridfield.core.limits.check_seconds`) when its vertex pairs would take too long.

    Parameters
    ----------
    world : World
        The vector world.
    pinch : {"block", "pass"}, optional
        See :data:`PINCH_RULES`.

    Returns
    -------
    VisibilityGraph

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[4, 4], [6, 4], [6, 6], [4, 6]]}]})
    >>> cached_visibility_graph(w) is cached_visibility_graph(w, "block")
    True
    """
    per_world = _CACHE.setdefault(world, {})
    if pinch not in per_world:
        from ..core.limits import check_seconds

        n = sum(len(ob.vertices) for ob in world.obstacles)  # circles count their outline's vertices
        check_seconds({"vertex pair": n * n}, f"visibility graph of {world.source or 'the world'}")
        per_world[pinch] = visibility_graph(world, pinch=pinch)
    return per_world[pinch]


def plan_visibility(world: World, start: ArrayLike, goal: ArrayLike, params: Mapping[str, Any] | None = None,
                    *, cache: dict[Any, Any] | None = None) -> Path:
    """Exact shortest path by the visibility graph (planner ``"visibility"``).

    Uses the ``block`` pinch rule; the graph of a world is built once and cached while the world
    lives. ``params`` are recorded but not used (the optimum has no parameters). The path's
    ``min_clearance`` is exact (:meth:`World.clearance`): 0 wherever it touches an obstacle.
    A world made from a grid map (:func:`gridfield.geometry.gridpoly.grid_world`) is solved on the grid by
    :func:`gridfield.exact.anyangle.plan_anyangle` (the same optimum, much faster; ``cache`` is passed on).

    Returns a :class:`~gridfield.core.path.Path` with status ``"reached"``, or ``"no_path"`` (one
    point, the start) when the goal cannot be reached.

    Parameters
    ----------
    world : World
        The exact obstacles.
    start, goal : array_like, shape (2,)
        Points in the free space.
    params : mapping, optional
        Recorded in the path.
    cache : dict, optional
        Passed to :func:`gridfield.exact.anyangle.plan_anyangle` for a world made from a grid map.

    Returns
    -------
    Path
        The shortest path (``"reached"``) or the start alone (``"no_path"``); ``extra`` holds
        ``nodes``, ``edges``, ``pinch``, ``graph_seconds`` and ``optimal_length``.

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> w = read_world(bundled_map("seed000.yaml"))
    >>> p = plan_visibility(w, w.start, w.goal, {})
    >>> p.status, round(p.length, 4), len(p.points)
    ('reached', 22.3868, 4)
    """
    params = validate(params)  # a raw mapping from a direct call is checked too
    from ..geometry.gridpoly import source_grid

    gm = source_grid(world)
    if gm is not None:
        from .anyangle import plan_anyangle

        return plan_anyangle(gm, start, goal, params, cache=cache)
    t0 = time.perf_counter()
    vg = cached_visibility_graph(world, "block")
    pts, length = vg.shortest_path(start, goal)
    seconds = time.perf_counter() - t0
    extra = {"nodes": vg.n_nodes, "edges": vg.n_edges, "pinch": vg.pinch, "graph_seconds": vg.seconds,
             "optimal_length": length}
    if not np.isfinite(length):
        s = np.asarray(start, dtype=float).reshape(1, 2)
        return Path(s, "no_path", "visibility", iterations=vg.n_nodes, params=dict(params or {}),
                    seconds=seconds, min_clearance=world.clearance(s), extra=extra)
    return Path(pts, "reached", "visibility", iterations=vg.n_nodes, params=dict(params or {}), seconds=seconds,
                min_clearance=world.clearance(pts), extra=extra)
