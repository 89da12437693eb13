"""Exact any-angle shortest paths on grid maps: Polyanya over a navigation mesh, or the taut visibility
graph of the convex corners.

The free space of a grid map is the union of its free cells (closed squares), with the corner rule
of :mod:`gridfield.geometry.gridpoly`: a path may touch a blocked cell's corner and run along its edges, but
never enters a blocked cell and never passes through a *pinch point* (a corner whose two diagonally
opposite cells are blocked). The Euclidean shortest path in it is a polyline whose inner vertices are
obstacle corners where it wraps round an obstacle (Lozano-Pérez & Wesley 1979). Three exact searches
find it (``search=``, :data:`SEARCH`); the default needs no graph:

Polyanya
    ``search="polyanya"`` (the default): Polyanya (Cui, Harabor & Grastien, "Compromise-free
    Pathfinding on a Navigation Mesh", IJCAI 2017; written here from the paper) over a navigation
    mesh of the free cells (:func:`navigation_mesh`: the row runs of free cells, runs with the same
    columns in consecutive rows merged into one rectangle, each rectangle's boundary a convex polygon
    with a vertex wherever the neighbour across changes; cells touching only at a corner share no
    edge, so a pinch point is never crossed). A search node is a root (the start or a corner the
    path turns at) and an interval of a polygon edge the root sees; expanding it projects the
    interval through the next polygon (observable successors, same root) and turns round an interval
    end that is a *turning point* (exactly one of the four cells round it blocked: the convex corners
    below) for the rest (non-observable successors); ``f = g + h`` with ``h`` the exact distance
    from the root through the interval to the goal (mirrored across the interval's line when on the
    root's side); a root reached more cheaply before prunes the node; dead-end polygons (one
    neighbour) are never entered but the goal's, and a lone successor with the same root is expanded
    without the open list (the paper's intermediate pruning). The start and goal may lie on polygon
    edges or vertices (the search starts from every polygon holding the start). Its per-map part is
    the mesh, built in numpy on the first Polyanya search (0.01-0.1 s on 512 x 512 maps) and kept
    with the corners (:attr:`AnyAngleGraph.mesh`); the search is compiled
    (:mod:`gridfield.exact._polyanya`).

The graph search needs:

Vertices
    the *convex corners*: cell corners where exactly one of the four surrounding cells is blocked
    (outside the grid counts as blocked: see "Border" below). Corners with two
    adjacent blocked cells lie on a straight edge, three blocked is a reflex corner, and at a pinch
    point (two diagonal blocked cells) each free side is a 90-degree wedge: no shortest path bends at
    any of them.
Edges
    pairs of convex corners that see each other (:func:`gridfield.exact._anyangle.segment_free`,
    an exact grid walk) along a *taut* direction: a shortest path bending at a corner wraps round its
    one blocked cell, so the line must keep both edges of that cell on one side. Only those pairs are
    walked, in compiled code, nearest corners first (corners bucketed in 32 x 32 blocks); every blocked
    cell a walk runs into is recorded in an angular occlusion table, so farther corners behind it are
    skipped without a walk and the search round a corner stops once every direction is blocked
    (exact: a skipped corner's segment would enter that cell). Cluttered maps (random obstacles) need
    this; on open maps it changes little.
Queries
    the start and the goal are joined to the corners they see along taut directions (one compiled
    pass over the corners each), then A* with the straight-line heuristic runs over the graph
    (``search="graph"``; the graph is built on its first query and kept: seconds on maps with tens of
    thousands of corners, 2.9 M edges on random512-10-0).
Lazy search
    ``search="lazy"`` needs no graph: A* over the same corners, each corner's visible neighbours
    found by the same compiled nearest-first pass when the corner is expanded, restricted to taut
    directions and to the *taut turn* from the corner's parent (the path must bend round the
    corner's blocked cell; any other turn leaves a free wedge inside it near the corner, so cutting
    it is strictly shorter: the standard taut-path pruning of any-angle search, e.g. Oh & Leong,
    Edge N-Level Sparse Visibility Graphs, SoCS 2017), and to corners the edge improves within the
    best goal length found. The per-map part is then only the corners, their buckets and the
    blocked runs; the same optimum (``tests/test_anyangle.py``), but every expansion costs one
    visibility pass, and a query expands tens to thousands of corners: 10-100x slower per query
    than the graph search on the Moving AI maps (benchmarks/README.md).

Border
    Paths stay on the map with either border, as those of the grid planners (``wavefront``,
    ``wavefront-octile``, ``fmm``: they never step outside the grid): the free space is the closed
    union of the map's free cells, so a path may run along the map's edge beside free cells but not
    between a blocked cell and the edge, nor outside. The border only decides the clearance: an
    ``open`` border is no obstacle (:meth:`AnyAngleGraph.clearance` measures to the blocked cells
    alone), a ``wall`` is one. (A vector world with an open border is another matter: there the plane
    outside the bounds is free, :mod:`gridfield.exact.visibility`.)

The corners of a map are found once and cached (per map content; :func:`grid_graph`); its navigation
mesh and its visibility graph are built on the first search that needs them and kept with them, so
many queries on one map pay only for the search. Every search first tries the straight segment
(one exact grid walk). Build and query times of the three searches on 512 x 512 Moving AI maps,
beside the octile wavefront on the same queries: ``benchmarks/README.md``, "Any-angle optimum on
grid maps".

Relation to the octile optimum (8-connected, no corner cutting, the length in Moving AI ``.scen``
files): between cell centres the any-angle optimum is never longer (an octile path is a feasible
any-angle path) and never shorter than the straight line. The octile metric overestimates a straight
line by at most 1.0824, but the octile *optimum* can exceed the any-angle optimum by more: in a
one-cell staircase corridor the any-angle path runs diagonally across convex corners where the
octile path needs two orthogonal steps (ratio ``sqrt(2)``; ``tests/test_anyangle.py``), and on the
Moving AI maps ratios up to 1.21 (den312d) and 1.14 (Polyanya's arena lengths) occur.

Examples
--------
>>> import numpy as np
>>> from gridfield.core.grid import Grid, GridMap
>>> occ = np.zeros((5, 5), bool); occ[0:4, 2] = True          # a wall in column 2, rows 0-3
>>> gm = GridMap(Grid((5, 5), 1.0, border="wall"), occ)
>>> pts, length = grid_graph(gm).shortest_path([0.5, 2.5], [4.5, 2.5])
>>> pts.tolist(), round(length, 6)                               # 1 + 2 * 1.5 * sqrt(2)
([[0.5, 2.5], [2.0, 4.0], [3.0, 4.0], [4.5, 2.5]], 5.242641)
"""

from __future__ import annotations

import hashlib
import math
import threading
import time
import weakref
from collections import OrderedDict
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import GridfieldError, ParameterError
from ..core.grid import Grid, GridMap
from ..core.params import validate
from ..core.path import Path
from ._navmesh import SLOT_DTYPE, NavMesh, _cells_at, _one_blocked, navigation_mesh

__all__ = ["SLOT_DTYPE", "AnyAngleGraph", "NavMesh", "convex_corners", "grid_graph", "navigation_mesh", "plan_anyangle"]

#: Graphs kept by :func:`grid_graph` without an explicit cache (most recently used maps).
CACHE_SIZE = 4
_GRAPHS: OrderedDict[tuple[Any, ...], AnyAngleGraph] = OrderedDict()
# Polyanya queries take turns at the meshes' workspaces (module-wide, so that a graph still pickles)
_MESH_LOCK = threading.Lock()


def _kernel_anyangle() -> Any:
    """The compiled kernel module (gridfield/exact/_anyangle.pyx: the segment walk, the exhaustive visibility),
    imported on first use."""
    from . import _anyangle  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _anyangle


def _kernel_occlusion() -> Any:
    """The compiled kernel module (gridfield/exact/_occlusion.pyx: the occlusion-culled visibility), imported on
    first use."""
    from . import _occlusion  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _occlusion


def _kernel_astar() -> Any:
    """The compiled kernel module (gridfield/exact/_astar.pyx: A* on the graph and lazy A*), imported on first use."""
    from . import _astar  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _astar


def _kernel_polyanya() -> Any:
    """The compiled kernel module (gridfield/exact/_polyanya.pyx), imported on first use."""
    from . import _polyanya  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _polyanya


def _padded_blocked(gm: GridMap) -> NDArray[np.uint8]:
    # the frame is blocked for either border: paths stay on the map (module docstring, "Border")
    rows, cols = gm.shape
    B = np.ones((rows + 2, cols + 2), dtype=np.uint8)
    B[1:-1, 1:-1] = gm.occupied
    return B


def convex_corners(blocked_padded: NDArray[np.uint8]) -> tuple[NDArray[np.float64], ...]:
    """Convex corners of a padded blocked array: lattice ``x, y`` and the quadrant ``qx, qy`` (+-1)
    of each corner's one blocked cell.

    Parameters
    ----------
    blocked_padded : ndarray of uint8, shape (rows + 2, cols + 2)
        The blocked cells with a one-cell frame (1 for the map's outside, 0 to let paths leave it).

    Returns
    -------
    x, y, qx, qy : ndarray of float
        Lattice coordinates of each convex corner (``x`` a column line, ``y`` a row line of the
        unpadded grid) and the side (+1 or -1 along each axis) of its one blocked cell.

    Examples
    --------
    >>> B = np.zeros((3, 3), np.uint8); B[1, 1] = 1      # one blocked cell in a 1 x 1 grid, a free frame
    >>> [a.tolist() for a in convex_corners(B)]
    [[0.0, 1.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0], [1.0, -1.0, 1.0, -1.0], [1.0, 1.0, -1.0, -1.0]]
    """
    B = blocked_padded.astype(bool)
    se, nw, ne = B[:-1, 1:], B[1:, :-1], B[1:, 1:]  # the cells round each lattice point but the lower left
    y, x = np.nonzero(_one_blocked(blocked_padded))
    qx = np.where(se[y, x] | ne[y, x], 1.0, -1.0)
    qy = np.where(nw[y, x] | ne[y, x], 1.0, -1.0)
    return x.astype(np.float64), y.astype(np.float64), qx, qy


#: A start or goal closer than this (lattice units, cells) to a cell edge is searched by Polyanya from
#: the edge (the path keeps the given point): its tolerances cannot tell such a point from one on the
#: edge, and between 1e-9 and 3e-8 off an edge it missed the optimum on random grids (in 0.15-0.7 % of
#: the queries); from 1e-7 on, none of 10000-19000 queries per offset did.
SNAP = 1e-7


#: The default search of :meth:`AnyAngleGraph.shortest_path` (and so of :func:`plan_anyangle`):
#: ``"polyanya"`` (Polyanya over the navigation mesh of the free cells, built on first use and kept),
#: ``"graph"`` (A* over the taut visibility graph, built on first use and kept) or ``"lazy"`` (A* over
#: the corners, each corner's visible neighbours found when it is expanded; no per-map graph). All
#: three give the same optimum; the figures behind the choice: benchmarks/README.md, "Any-angle
#: optimum on grid maps".
SEARCH = "polyanya"
SEARCHES = ("lazy", "graph", "polyanya")


@dataclass(frozen=True, eq=False)
class AnyAngleGraph:
    """A grid map's convex corners, its navigation mesh and the searches over them; build it with
    :func:`grid_graph`.

    The per-map part is the corner list, its 32 x 32 buckets and the blocked runs (milliseconds);
    the navigation mesh (:attr:`mesh`, by the ``"polyanya"`` search, the default) and the taut
    visibility graph over the corners (:attr:`edges`, by the ``"graph"`` search) are built on first
    use only and then kept.

    Attributes
    ----------
    grid : Grid
    nodes : ndarray, shape (n, 2)
        Convex corners in world coordinates.
    seconds : float
        Time of the per-map part (corners, buckets, runs).
    edges : ndarray of int, shape (m, 2)
        Taut visible pairs ``i < j`` (built on first access; :attr:`graph_seconds`).
    mesh : NavMesh
        The navigation mesh of the free cells (built on first access; :attr:`mesh_seconds`).

    Examples
    --------
    >>> occ = np.zeros((3, 3), bool); occ[1, 1] = True                # one blocked cell in the middle
    >>> g = grid_graph(GridMap(Grid((3, 3), 1.0), occ))
    >>> g.n_nodes, g.n_edges, g.nodes.tolist()                        # its four corners, the square's sides
    (4, 4, [[1.0, 1.0], [2.0, 1.0], [1.0, 2.0], [2.0, 2.0]])
    >>> g.shortest_path([0.5, 0.5], [2.5, 2.5])[1] == 2 * (0.5 ** 2 + 1.5 ** 2) ** 0.5
    True
    >>> g.mesh.n_polygons                                             # rows 0 and 2, the cells left and right of it
    4
    """

    grid: Grid
    nodes: NDArray[np.float64]
    seconds: float
    _B: NDArray[np.uint8] = field(repr=False)
    _vx: NDArray[np.float64] = field(repr=False)
    _vy: NDArray[np.float64] = field(repr=False)
    _qx: NDArray[np.float64] = field(repr=False)
    _qy: NDArray[np.float64] = field(repr=False)
    _blocks: tuple[Any, ...] = field(repr=False)
    _ext: tuple[Any, ...] = field(repr=False)
    _lazy: dict[str, Any] = field(default_factory=dict, repr=False)
    _source: str = field(default="", repr=False)

    @property
    def n_nodes(self) -> int:
        return len(self._vx)

    @property
    def edges(self) -> NDArray[np.intp]:
        """The taut visibility graph's edges ``(m, 2)``, pairs ``i < j`` (built on first access)."""
        edges: NDArray[np.intp] = self._graph()["edges"]
        return edges

    @property
    def n_edges(self) -> int:
        return len(self.edges)

    @property
    def graph_built(self) -> bool:
        """Whether the visibility graph (:attr:`edges`) has been built."""
        return "edges" in self._lazy

    @property
    def graph_seconds(self) -> float:
        """Time the visibility graph took to build (building it if it was not)."""
        return float(self._graph()["seconds"])

    def _graph(self) -> dict[str, Any]:
        if "edges" not in self._lazy:
            from ..core.limits import check_seconds

            # the graph's build grows with the corners (seconds on cluttered maps): refused up front when
            # over the time limit; the corners, the mesh and the Polyanya search need no such check
            check_seconds({"convex corner": self.n_nodes}, f"any-angle graph of {self._source or 'the grid map'}")
            k = _kernel_occlusion()
            t0 = time.perf_counter()
            vx, vy = self._vx, self._vy
            ei, ej = k.visibility_edges_culled(self._B, vx, vy, self._qx, self._qy, *self._blocks)
            w = np.hypot(vx[ej] - vx[ei], vy[ej] - vy[ei])
            indptr, indices, weights = _symmetric_csr(len(vx), ei, ej, w)
            edges = np.empty((len(ei), 2), dtype=np.intp)
            edges[:, 0], edges[:, 1] = ei, ej
            self._lazy.update(csr=(indptr, indices, weights), seconds=time.perf_counter() - t0)
            self._lazy["edges"] = edges
        return self._lazy

    @property
    def mesh(self) -> NavMesh:
        """The navigation mesh of the free cells (built on first access; :attr:`mesh_seconds`)."""
        mesh: NavMesh = self._mesh()["mesh"]
        return mesh

    @property
    def mesh_built(self) -> bool:
        """Whether the navigation mesh (:attr:`mesh`) has been built."""
        return "mesh" in self._lazy

    @property
    def mesh_seconds(self) -> float:
        """Time the navigation mesh took to build (building it if it was not)."""
        return float(self._mesh()["mesh_seconds"])

    def _mesh(self) -> dict[str, Any]:
        if "mesh" not in self._lazy:
            t0 = time.perf_counter()
            mesh = navigation_mesh(self._B)
            n = max(mesh.n_roots, 1)
            # the search's best g per root, valid where stamp == the query's number (never cleared)
            self._lazy.update(mesh_best=np.zeros(n), mesh_stamp=np.zeros(n, dtype=np.int32), mesh_sid=0,
                              mesh_seconds=time.perf_counter() - t0)
            self._lazy["mesh"] = mesh
        return self._lazy

    def _polyanya(self, sx: float, sy: float, gx: float, gy: float) -> tuple[float, NDArray[np.float64], int] | None:
        """Polyanya from ``(sx, sy)`` to ``(gx, gy)`` (lattice units): length, turning points ``(k, 2)``
        (lattice), nodes expanded; ``None`` if it found no path between polygons of one component
        (a numerical failure, never seen: the caller then runs the lazy search).

        A start or goal within :data:`SNAP` of a cell edge is searched from the edge (the kernel's
        tolerances cannot tell such a point from one on the edge); the path keeps the given ends and
        its length is measured along it. Points in different components are answered without a search.
        """
        lz = self._mesh()
        mesh: NavMesh = lz["mesh"]
        s2, g2 = self._snapped(sx, sy), self._snapped(gx, gy)
        sp, tp = mesh.polygons_at(*s2), mesh.polygons_at(*g2)
        if not np.intersect1d(mesh.component[sp], mesh.component[tp]).size:
            return math.inf, np.empty((0, 2)), 0
        with _MESH_LOCK:  # one query at a time uses a mesh's workspace
            lz["mesh_sid"] += 1
            if lz["mesh_sid"] >= 2**31 - 1:
                lz["mesh_stamp"].fill(0)
                lz["mesh_sid"] = 1
            length, xs, ys, expanded, _ = _kernel_polyanya().polyanya(
                mesh.pstart, mesh.slots.view(np.uint8), mesh.degree, lz["mesh_best"],
                lz["mesh_stamp"], lz["mesh_sid"], mesh.max_vertices, s2[0], s2[1], sp, g2[0], g2[1], tp)
        if not math.isfinite(length):
            return None
        turns = np.column_stack([xs, ys])
        if s2 != (sx, sy) or g2 != (gx, gy):
            pts = np.vstack([[sx, sy], turns, [gx, gy]])
            length = float(np.hypot(*np.diff(pts, axis=0).T).sum())
        return float(length), turns, int(expanded)

    def _snapped(self, u: float, v: float) -> tuple[float, float]:
        """``(u, v)`` with each coordinate within :data:`SNAP` of an integer moved onto it (unless that
        lands on a pinch point)."""
        su = float(round(u)) if abs(u - round(u)) <= SNAP else u
        sv = float(round(v)) if abs(v - round(v)) <= SNAP else v
        if (su, sv) == (u, v) or (su == round(su) and sv == round(sv) and self._pinch(int(su), int(sv))):
            return u, v
        return su, sv

    def _pinch(self, x: int, y: int) -> bool:
        """Whether the lattice point ``(x, y)`` is a pinch point (two diagonal cells blocked, two free)."""
        sw, se, nw, ne = (bool(self._B[y + i, x + j]) for i, j in ((0, 0), (0, 1), (1, 0), (1, 1)))
        return (sw and ne and not se and not nw) or (se and nw and not sw and not ne)

    # -- coordinates --------------------------------------------------------------------
    def _lattice(self, point: ArrayLike, name: str) -> tuple[float, float]:
        p = np.asarray(point, dtype=float).reshape(-1)
        if p.shape != (2,) or not np.all(np.isfinite(p)):
            raise GridfieldError(f"{name} must be two finite numbers X Y, got {point!r}")
        (x0, y0), h = self.grid.origin, self.grid.resolution
        u, v = (p[0] - x0) / h, (p[1] - y0) / h
        rows, cols = self.grid.shape
        if not (0.0 <= u <= cols and 0.0 <= v <= rows):
            xmin, ymin, xmax, ymax = self.grid.bounds
            raise GridfieldError(f"{name} ({p[0]:g}, {p[1]:g}) lies outside the map "
                                 f"[{xmin:g}, {ymin:g}, {xmax:g}, {ymax:g}]")
        rs, cs = _cells_at(u, v)  # the closed cells holding the point: free if one of them is
        if all(self._B[r + 1, c + 1] for r in rs for c in cs):
            raise GridfieldError(f"{name} ({p[0]:g}, {p[1]:g}) lies inside an obstacle")
        if len(cs) == 2 and len(rs) == 2 and self._pinch(int(u), int(v)):
            raise GridfieldError(f"{name} ({p[0]:g}, {p[1]:g}) lies on a pinch point where two blocked cells "
                                 "touch: which side it is on is ambiguous; move it off the point")
        return float(u), float(v)

    def clearance(self, points: ArrayLike) -> float:
        """Exact smallest distance from the polyline ``points`` (world, ``(N, 2)``) to the blocked
        cells (and to the bounds for a wall border); 0 where it touches one.

        The distance to a union of squares is the smallest distance to one of them: an STRtree of
        the row runs of blocked cells (:func:`gridfield.geometry.gridpoly.blocked_runs`) finds it.

        Examples
        --------
        >>> from gridfield.core.grid import Grid, GridMap
        >>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
        >>> grid_graph(GridMap(Grid((3, 3), 1.0), occ)).clearance([[0, 0.5], [3, 0.5]])
        0.5
        """
        import shapely

        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        if len(pts) == 0:
            return math.nan
        tree = self._runs_tree()
        best = math.inf
        if tree is not None:
            geom = shapely.linestrings(pts) if len(pts) > 1 else shapely.points(pts[0])
            if len(tree.query(geom, predicate="intersects")):
                best = 0.0  # touches a blocked cell (optimal paths wrap round corners): no nearest search
            else:
                _, dist = tree.query_nearest(geom, return_distance=True)
                best = float(dist.min()) if len(dist) else math.inf
        if self.grid.border == "wall":
            xmin, ymin, xmax, ymax = self.grid.bounds
            dw = np.minimum.reduce([pts[:, 0] - xmin, xmax - pts[:, 0], pts[:, 1] - ymin, ymax - pts[:, 1]])
            best = min(best, float(np.maximum(dw, 0.0).min()))
        return best

    def _runs_tree(self) -> Any:
        if "tree" not in self._lazy:
            import shapely

            from ..geometry.gridpoly import blocked_runs

            rows, c0, c1 = blocked_runs(self._B[1:-1, 1:-1].astype(bool))
            (x0, y0), h = self.grid.origin, self.grid.resolution
            boxes = shapely.box(x0 + c0 * h, y0 + rows * h, x0 + c1 * h, y0 + (rows + 1) * h)
            self._lazy["tree"] = shapely.STRtree(boxes) if len(boxes) else None
        return self._lazy["tree"]

    def visible(self, p: ArrayLike, q: ArrayLike) -> bool:
        """Whether the straight segment ``p -> q`` (world points) lies in the free space.

        Examples
        --------
        >>> from gridfield.core.grid import Grid, GridMap
        >>> occ = np.zeros((2, 2), bool); occ[0, 1] = occ[1, 0] = True     # a pinch at (1, 1)
        >>> g = grid_graph(GridMap(Grid((2, 2), 1.0), occ))
        >>> g.visible([0.5, 0.5], [1.5, 1.5]), g.visible([0.5, 0.5], [0.5, 0.9])
        (False, True)
        """
        a = self._lattice(p, "p")
        b = self._lattice(q, "q")
        return bool(_kernel_anyangle().segment_free(self._B, a[0], a[1], b[0], b[1]))

    def shortest_path(self, start: ArrayLike, goal: ArrayLike, *, search: str | None = None
                      ) -> tuple[NDArray[np.float64], float]:
        """The Euclidean shortest path from ``start`` to ``goal``: vertices ``(k, 2)`` and length.

        An empty ``(0, 2)`` array and ``inf`` when the goal cannot be reached.

        Parameters
        ----------
        start, goal : array_like, shape (2,)
            World points in the free space.
        search : {"lazy", "graph", "polyanya"}, optional
            :data:`SEARCH` when not given. All three find the optimum (module docstring, "Queries",
            "Polyanya").

        Returns
        -------
        points : ndarray, shape (k, 2)
        length : float

        Raises
        ------
        GridfieldError
            when a point is not finite, outside the map, inside a blocked cell or on a pinch point
            (a corner between two diagonally touching blocked cells: its side is ambiguous).
        ParameterError
            for an unknown ``search``.

        Examples
        --------
        >>> occ = np.zeros((5, 5), bool); occ[0:4, 2] = True
        >>> g = grid_graph(GridMap(Grid((5, 5), 1.0, border="wall"), occ))
        >>> [round(g.shortest_path([0.5, 2.5], [4.5, 2.5], search=s)[1], 9) for s in SEARCHES]
        [5.242640687, 5.242640687, 5.242640687]
        """
        pts, length, _ = self._search(start, goal, SEARCH if search is None else search)
        return pts, length

    def _search(self, start: ArrayLike, goal: ArrayLike, search: str) -> tuple[NDArray[np.float64], float, int]:
        """:meth:`shortest_path` and how many corners the search expanded (-1: not counted)."""
        if search not in SEARCHES:
            raise ParameterError(f"search must be one of {', '.join(map(repr, SEARCHES))}, got {search!r}")
        sx, sy = self._lattice(start, "start")
        gx, gy = self._lattice(goal, "goal")
        h = self.grid.resolution
        x0, y0 = self.grid.origin
        s_w = np.array([x0 + sx * h, y0 + sy * h])
        g_w = np.array([x0 + gx * h, y0 + gy * h])
        if _kernel_anyangle().segment_free(self._B, sx, sy, gx, gy):
            return np.array([s_w, g_w]), float(math.hypot(gx - sx, gy - sy) * h), 0
        if search == "polyanya":
            found = self._polyanya(sx, sy, gx, gy)
            if found is not None:
                length, turns, expanded = found
                if not math.isfinite(length):
                    return np.empty((0, 2)), math.inf, expanded
                return np.vstack([s_w, np.array([x0, y0]) + turns * h, g_w]), length * h, expanded
            search = "lazy"  # the safety net of _polyanya
        corners = (self._vx, self._vy, self._qx, self._qy)
        ko, ka = _kernel_occlusion(), _kernel_astar()
        sd = ko.visible_from_culled(self._B, self._ext, sx, sy, *corners, *self._blocks)
        gd = ko.visible_from_culled(self._B, self._ext, gx, gy, *corners, *self._blocks)
        if search == "lazy":
            best, pred, last, expanded = ka.lazy_astar(self._B, self._ext, *corners, *self._blocks, sx, sy, sd, gd,
                                                       gx, gy)
        else:
            best, pred, last = ka.astar(*self._graph()["csr"], self._vx, self._vy, sd, gd, gx, gy)
            expanded = -1
        if not math.isfinite(best):
            return np.empty((0, 2)), math.inf, int(expanded)
        order = [int(last)]
        while pred[order[-1]] >= 0:
            order.append(int(pred[order[-1]]))
        order.reverse()
        mid = self.nodes[order]
        return np.vstack([s_w, mid, g_w]), float(best * h), int(expanded)


_KEYS: weakref.WeakKeyDictionary[GridMap, tuple[Any, ...]] = weakref.WeakKeyDictionary()


def _content_key(gm: GridMap) -> tuple[Any, ...]:
    key = _KEYS.get(gm)
    if key is None:
        key = _KEYS[gm] = _hash_key(gm)
    return key


def _hash_key(gm: GridMap) -> tuple[Any, ...]:
    digest = hashlib.blake2b(np.ascontiguousarray(gm.occupied, dtype=bool).tobytes(), digest_size=16).hexdigest()
    g = gm.grid
    return ("anyangle", g.shape, g.resolution, g.origin, g.border, digest)


def _build(gm: GridMap) -> AnyAngleGraph:
    k = _kernel_occlusion()
    t0 = time.perf_counter()
    B = _padded_blocked(gm)
    vx, vy, qx, qy = convex_corners(B)
    blocks = _buckets(vx, vy, gm.shape)
    (x0, y0), h = gm.grid.origin, gm.grid.resolution
    nodes = np.column_stack([x0 + vx * h, y0 + vy * h])
    ext = k.run_extents(B)
    return AnyAngleGraph(gm.grid, nodes, time.perf_counter() - t0, B, vx, vy, qx, qy, blocks, ext,
                         _source=gm.source)


def _symmetric_csr(n: int, ei: NDArray[np.integer[Any]], ej: NDArray[np.integer[Any]], w: NDArray[np.float64]
                   ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """CSR (``indptr, indices, weights``) of the undirected graph of the edges ``ei[k] - ej[k]``.

    Row ``v`` lists the edges with ``ei == v`` (in their order) and then those with ``ej == v`` (by
    ascending ``ei``), as a stable sort of both directions by their first node would, but in linear
    time: the kernel emits the edges grouped by ``ei`` in ascending order, the first half is placed
    directly and the second is the transpose (scipy's linear-time CSR -> CSC conversion).

    Examples
    --------
    >>> ptr, idx, wt = _symmetric_csr(3, np.array([0, 0, 1]), np.array([2, 1, 2]), np.array([2.0, 1.0, 1.5]))
    >>> ptr.tolist(), idx.tolist(), wt.tolist()
    ([0, 2, 4, 6], [2, 1, 2, 0, 0, 1], [2.0, 1.0, 1.5, 1.0, 2.0, 1.5])
    """
    import scipy.sparse

    if len(ei) > 1 and not bool(np.all(ei[1:] >= ei[:-1])):  # not grouped by ei: group them (stable)
        order = np.argsort(ei, kind="stable")
        ei, ej, w = ei[order], ej[order], w[order]
    m = len(ei)
    fcount = np.bincount(ei, minlength=n)
    bcount = np.bincount(ej, minlength=n)
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(fcount + bcount, out=indptr[1:])
    fptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(fcount, out=fptr[1:])
    indices = np.empty(2 * m, dtype=np.int64)
    weights = np.empty(2 * m, dtype=np.float64)
    dest = np.arange(m, dtype=np.int64)
    dest += (indptr[:-1] - fptr[:-1])[ei]
    indices[dest], weights[dest] = ej, w
    back = scipy.sparse.csr_array((w, ej, fptr), shape=(n, n)).tocsc()  # column v: the ei of the edges to v, ascending
    dest = np.arange(m, dtype=np.int64)
    dest += np.repeat(indptr[:-1] + fcount - back.indptr[:-1], bcount)
    indices[dest], weights[dest] = back.indices, back.data
    return indptr, indices, weights


#: Side of the square blocks (lattice units) the corners are bucketed in for the nearest-first search
#: (32: random512-10-0 builds in less kernel CPU time than with 8 or 16, the game, room and maze maps in
#: no more than with 16; the figures: benchmarks/README.md, "Any-angle optimum on grid maps").
BLOCK = 32


def _buckets(vx: NDArray[np.float64], vy: NDArray[np.float64], shape: tuple[int, ...],
             block: int = BLOCK) -> tuple[Any, ...]:
    """CSR of the corners per ``block``-sized square block: ``(bstart, bverts, nbx, nby, block)``."""
    rows, cols = shape
    nbx, nby = cols // block + 1, rows // block + 1
    bid = (vy // block).astype(np.int64) * nbx + (vx // block).astype(np.int64)
    bstart = np.zeros(nbx * nby + 1, dtype=np.int64)
    np.cumsum(np.bincount(bid, minlength=nbx * nby), out=bstart[1:])
    return bstart, np.argsort(bid, kind="stable").astype(np.int64), nbx, nby, float(block)


def grid_graph(gridmap: GridMap, *, cache: dict[Any, Any] | None = None) -> AnyAngleGraph:
    """The any-angle searches of a grid map (:class:`AnyAngleGraph`), built once per map content.

    Parameters
    ----------
    gridmap : GridMap
    cache : dict, optional
        A caller's cache (e.g. the one given to :func:`gridfield.planners.plan`); without it the
        graphs of the :data:`CACHE_SIZE` most recently used maps are kept in this module. Either way
        the key is the grid geometry and a hash of the occupancy, so two map objects with the same
        content share one graph.

    Returns
    -------
    AnyAngleGraph

    Examples
    --------
    >>> occ = np.zeros((4, 4), bool); occ[1:3, 2] = True
    >>> a, b = (GridMap(Grid((4, 4), 0.5), occ.copy()) for _ in range(2))
    >>> cache = {}
    >>> grid_graph(a, cache=cache) is grid_graph(b, cache=cache), len(cache)   # same content: one graph
    (True, 1)
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"grid_graph needs a GridMap, got {type(gridmap).__name__}")
    key = _content_key(gridmap)
    store: Any = cache if cache is not None else _GRAPHS
    graph: AnyAngleGraph | None = store.get(key)
    if graph is None:  # the corners (linear in the cells); the visibility graph's time is checked when it is built
        graph = _build(gridmap)
        store[key] = graph
    if store is _GRAPHS:
        _GRAPHS.move_to_end(key)
        while len(_GRAPHS) > CACHE_SIZE:
            _GRAPHS.popitem(last=False)
    return graph


def plan_anyangle(gridmap: GridMap, start: ArrayLike, goal: ArrayLike, params: Mapping[str, Any] | None = None,
                  *, cache: dict[Any, Any] | None = None) -> Path:
    """Exact any-angle shortest path on a grid map (planner ``"visibility"`` on grid maps).

    Returns a :class:`~gridfield.core.path.Path` (``planner="visibility"``) with status ``"reached"``,
    or ``"no_path"`` (one point, the start) when the goal cannot be reached. ``seconds`` is the
    query time (the corners come from :func:`grid_graph`; the search is :data:`SEARCH`); ``extra``
    holds ``nodes`` (convex corners), ``graph_seconds`` (the per-map part, plus the builds of the
    navigation mesh and of the visibility graph when they were built), ``polygons`` (only when the
    mesh was built: the ``"polyanya"`` search), ``edges`` (only when the visibility graph was built:
    the ``"graph"`` search) and ``optimal_length``; ``min_clearance`` is the exact distance of the
    path to the blocked cells (0 where it touches one).

    Parameters
    ----------
    gridmap : GridMap
        The map (its blocked cells, corner rule of :mod:`gridfield.geometry.gridpoly`).
    start, goal : array_like, shape (2,)
        World points in the free space (not on a pinch point).
    params : mapping, optional
        Recorded in the path; the optimum has no parameters.
    cache : dict, optional
        Where the graph is kept (see :func:`grid_graph`).

    Returns
    -------
    Path
        The shortest path (``"reached"``) or the start alone (``"no_path"``).

    Examples
    --------
    >>> from gridfield.io import read_movingai_map, bundled_map
    >>> m = read_movingai_map(bundled_map("arena/arena.map"))
    >>> p = plan_anyangle(m, [1.5, 37.5], [1.5, 38.5])
    >>> p.status, p.length
    ('reached', 1.0)
    """
    params = validate(params)  # a raw mapping from a direct call is checked too
    graph = grid_graph(gridmap, cache=cache)
    # the per-map structure of the search before the query (a straight-line answer too), so that
    # seconds is the query alone
    if SEARCH == "graph":
        graph._graph()
    elif SEARCH == "polyanya":
        graph._mesh()
    t0 = time.perf_counter()
    pts, length, _ = graph._search(start, goal, SEARCH)
    seconds = time.perf_counter() - t0
    extra: dict[str, Any] = {"nodes": graph.n_nodes}
    if graph.mesh_built:  # the Polyanya search (or a caller) built the mesh: its size
        extra["polygons"] = graph.mesh.n_polygons
    if graph.graph_built:  # the graph search (or a caller) built the graph: its size and time
        extra["edges"] = graph.n_edges
    extra.update(graph_seconds=graph.seconds + (graph.mesh_seconds if graph.mesh_built else 0.0)
                 + (graph.graph_seconds if graph.graph_built else 0.0), optimal_length=length, pinch="block")
    if not math.isfinite(length):
        s = np.asarray(start, dtype=float).reshape(1, 2)
        return Path(s, "no_path", "visibility", iterations=graph.n_nodes, params=dict(params or {}),
                    seconds=seconds, min_clearance=graph.clearance(s), extra=extra)
    # inner vertices are corners of blocked cells: such a path touches an obstacle (clearance 0)
    clearance = 0.0 if len(pts) > 2 else graph.clearance(pts)
    return Path(pts, "reached", "visibility", iterations=graph.n_nodes, params=dict(params or {}), seconds=seconds,
                min_clearance=clearance, extra=extra)
