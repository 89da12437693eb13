"""Grid planners against exact-geometry planners: metrics, convergence study, batch comparison.

Metrics (pure functions on point arrays ``(N, 2)``; a :class:`~gridfield.path.Path` works too):

- :func:`length_ratio` — path length over a reference (the exact planner's, the visibility optimum);
- :func:`hausdorff` — symmetric Hausdorff distance (:func:`scipy.spatial.distance.directed_hausdorff`);
- :func:`discrete_frechet` — discrete Fréchet distance (dynamic programming, one numpy step per
  anti-diagonal); unlike Hausdorff it sees the order of the points, so a path that doubles back
  is far from a straight one even when it covers the same ground;
- :func:`end_error` — distance between the end points (the stall points of two stuck followers);
- :func:`min_clearance`, :func:`collides` — exact clearance of a path against the world;
- :func:`status_agreement` — whether two planners ended the same way;
- :func:`distance_map_errors` — every brushfire metric against the exact obstacle distance at the
  cell centres: max, mean and by distance band.

Both distances between curves are computed on the polylines resampled at ``spacing`` (their
vertices plus points at most ``spacing`` apart), which makes them independent of how densely each
planner records its points and within ``spacing / 2`` of the continuous distances.

:func:`convergence_study` runs a grid planner at a list of resolutions against an exact planner
and reports these metrics per resolution; :func:`observed_order` is the least-squares slope of an
error against the resolution on log-log axes (error ~ C h^order).

Observed orders on the bundled seed worlds (``gridfield compare maps/seed000*.yaml``: grid
``potential`` against ``exact-potential``, the seed's parameters with ``step`` 0.1, resolutions
0.4, 0.2, 0.1, 0.05; measured when this module was written)::

    world             error                        0.4     0.2     0.1     0.05   order
    seed000           Hausdorff                    0.361   0.189   0.084   0.046  1.01
    (both reach)      Frechet                      0.366   0.189   0.084   0.046  1.02
                      |length / exact length - 1|  0.042   0.023   0.0079  0.0038 1.19
    seed000_segment   Hausdorff                    0.557   0.260   0.182   0.048  1.11
    (both stall)      stall-point error            0.564   0.232   0.148   0.070  0.97
                      Frechet                      0.557   0.260   0.182   0.130  0.68

The path and the stall point converge at first order in the cell size, as expected from a
conservative rasterization that moves every obstacle boundary by up to one cell (and a Euclidean
brushfire whose distances are off by up to ``h / sqrt(2)``). Below ``h`` = 0.05 the errors level
off near the follower's step (0.1): both followers take fixed steps, and a stalled follower's
Fréchet distance also sees how long it oscillated before stopping.

:func:`batch_compare` plans many random start/goal pairs on one world and reports success rates
of the grid and exact potential fields and of the octile wavefront, and their length ratios to
the visibility-graph optimum.
"""

from __future__ import annotations

import contextlib
import itertools
import math
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.distance import directed_hausdorff

from ..errors import GridfieldError, ParameterError, check_positive
from ..path import Path, path_length
from ..world import World

__all__ = [
    "ERROR_COLUMNS",
    "STUDY_COLUMNS",
    "batch_compare",
    "collides",
    "convergence_study",
    "discrete_frechet",
    "distance_map_errors",
    "end_error",
    "final_point",
    "hausdorff",
    "length_ratio",
    "min_clearance",
    "observed_order",
    "resample",
    "status_agreement",
    "study_errors",
    "study_orders",
]

#: Keys of every row of :func:`convergence_study`, in table order.
STUDY_COLUMNS = (
    "resolution", "cells", "build_ms", "plan_ms", "status", "exact_status", "status_agree", "length",
    "exact_length", "optimal_length", "length_ratio", "length_ratio_optimal", "hausdorff", "frechet",
    "end_error", "min_clearance", "collides",
)
#: Error columns whose convergence :func:`observed_order` is reported for.
ERROR_COLUMNS = ("hausdorff", "frechet", "end_error", "length_error")


# ----------------------------------------------------------------------------------------
# Curves
# ----------------------------------------------------------------------------------------
def _points(p: ArrayLike | Path, name: str) -> NDArray[np.float64]:
    arr = p.points if isinstance(p, Path) else np.asarray(p, dtype=float)
    if arr.ndim == 1 and arr.shape[0] == 2:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ParameterError(f"{name} must be points of shape (N, 2), got shape {np.shape(arr)}")
    if len(arr) == 0:
        raise ParameterError(f"{name} has no points")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} must hold finite coordinates")
    return arr


def resample(points: ArrayLike | Path, spacing: float) -> NDArray[np.float64]:
    """The polyline's vertices plus evenly spaced points so that no gap exceeds ``spacing``.

    Parameters
    ----------
    points : array_like, shape (N, 2), or Path
        The polyline.
    spacing : float
        Largest gap between consecutive output points (> 0).

    Returns
    -------
    ndarray, shape (M, 2)
        The vertices in order with the inserted points; a single point is returned as is.

    Examples
    --------
    >>> resample([[0, 0], [1, 0], [1, 0.5]], 0.5).tolist()
    [[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.0, 0.5]]
    """
    p = _points(points, "points")
    h = check_positive("spacing", spacing)
    if len(p) < 2:
        return p.copy()
    seg = np.diff(p, axis=0)
    n = np.maximum(1, np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / h - 1e-9).astype(np.intp))
    owner = np.repeat(np.arange(len(seg)), n)
    first = np.cumsum(n) - n
    t = (np.arange(n.sum()) - first[owner]) / n[owner]
    out = p[owner] + t[:, None] * seg[owner]
    return np.vstack([out, p[-1:]])


def hausdorff(a: ArrayLike | Path, b: ArrayLike | Path, *, spacing: float | None = None) -> float:
    """Symmetric Hausdorff distance between two point sequences (polylines if ``spacing``).

    Parameters
    ----------
    a, b : array_like, shape (N, 2), or Path
        The two point sequences.
    spacing : float, optional
        Resample both as polylines at this step first (:func:`resample`): the distance of the curves,
        not only of their vertices.

    Returns
    -------
    float
        The largest distance from a point of either sequence to the nearest point of the other.

    Examples
    --------
    >>> hausdorff([[0, 0], [1, 0]], [[0, 1], [1, 1]])
    1.0
    >>> hausdorff([[0, 0], [4, 0]], [[0, 0], [2, 1], [4, 0]], spacing=0.5)
    1.0
    """
    p, q = _points(a, "a"), _points(b, "b")
    if spacing is not None:
        p, q = resample(p, spacing), resample(q, spacing)
    return float(max(directed_hausdorff(p, q)[0], directed_hausdorff(q, p)[0]))


def discrete_frechet(a: ArrayLike | Path, b: ArrayLike | Path, *, spacing: float | None = None) -> float:
    """Discrete Fréchet distance between two point sequences (polylines if ``spacing``).

    The smallest, over all monotone couplings of the two sequences, of the largest distance
    between coupled points (Eiter & Mannila 1994). Computed by dynamic programming along
    anti-diagonals: memory O(N + M), one vectorized step per diagonal.

    Parameters
    ----------
    a, b : array_like, shape (N, 2), or Path
        The two point sequences, in their order.
    spacing : float, optional
        Resample both as polylines at this step first (:func:`resample`).

    Returns
    -------
    float
        The discrete Fréchet distance (>= the Hausdorff distance of the same points).

    Examples
    --------
    >>> discrete_frechet([[0, 0], [1, 0]], [[0, 1], [1, 1]])
    1.0
    >>> back = [[0, 0], [2, 0], [1, 0], [3, 0]]      # doubles back over [1, 2]
    >>> round(discrete_frechet(back, [[0, 0], [3, 0]], spacing=0.01), 3), hausdorff(back, [[0, 0], [3, 0]], spacing=0.01)
    (0.5, 0.0)
    """
    p, q = _points(a, "a"), _points(b, "b")
    if spacing is not None:
        p, q = resample(p, spacing), resample(q, spacing)
    if len(p) > len(q):
        p, q = q, p
    n, m = len(p), len(q)
    inf = np.inf
    prev2 = np.full(n + 1, inf)  # diagonal k-2, index i+1 (index 0 = out of range)
    prev1 = np.full(n + 1, inf)  # diagonal k-1
    for k in range(n + m - 1):
        i0, i1 = max(0, k - m + 1), min(k, n - 1)
        i = np.arange(i0, i1 + 1)
        d = np.hypot(p[i, 0] - q[k - i, 0], p[i, 1] - q[k - i, 1])
        cur = np.full(n + 1, inf)
        if k == 0:
            cur[1] = d[0]
        else:
            best = np.minimum(np.minimum(prev1[i], prev2[i]), prev1[i + 1])
            cur[i + 1] = np.maximum(d, best)
        prev2, prev1 = prev1, cur
    return float(prev1[n])


def length_ratio(points: ArrayLike | Path, reference: float | ArrayLike | Path) -> float:
    """Length of a path over a reference length (a number, or a path whose length is used).

    Returns NaN when the reference length is not positive and finite.

    Parameters
    ----------
    points : array_like, shape (N, 2), or Path
        The path whose length is measured.
    reference : float, array_like or Path
        A reference length, or a path whose length is the reference.

    Returns
    -------
    float
        ``length(points) / reference``, NaN for a reference that is not positive and finite.

    Examples
    --------
    >>> length_ratio([[0, 0], [3, 4]], 4.0)
    1.25
    >>> length_ratio([[0, 0], [1, 0]], [[0, 0], [0, 2]])
    0.5
    """
    length = path_length(_points(points, "points"))
    if isinstance(reference, int | float | np.floating | np.integer):
        ref = float(reference)
    else:
        ref = path_length(_points(reference, "reference"))
    return length / ref if (math.isfinite(ref) and ref > 0) else math.nan


def final_point(path: ArrayLike | Path) -> NDArray[np.float64]:
    """Where a path ended: the follower's stall point (``extra["stall_point"]``) if it stalled in a
    local minimum, else its last point.

    Parameters
    ----------
    path : Path or array_like, shape (N, 2)
        A planner's path (its status and ``extra`` are used) or plain points.

    Returns
    -------
    ndarray, shape (2,)
        The stall point or the last point.

    Examples
    --------
    >>> p = Path(np.array([[0, 0], [1, 0], [1.1, 0]]), "local_minimum", "demo", extra={"stall_point": [1.0, 0.0]})
    >>> final_point(p).tolist(), final_point([[0, 0], [2, 3]]).tolist()
    ([1.0, 0.0], [2.0, 3.0])
    """
    if isinstance(path, Path) and path.status == "local_minimum" and "stall_point" in path.extra:
        return np.asarray(path.extra["stall_point"], dtype=float).reshape(2)
    return _points(path, "path")[-1]


def end_error(a: ArrayLike | Path, b: ArrayLike | Path) -> float:
    """Distance between where two paths ended (:func:`final_point`): the stall-point error of two
    followers stuck in the same local minimum, the distance between their ends otherwise.

    Parameters
    ----------
    a, b : Path or array_like, shape (N, 2)
        The two paths.

    Returns
    -------
    float
        The distance between their end points (:func:`final_point`).

    Examples
    --------
    >>> end_error([[0, 0], [1, 1]], [[0, 0], [4, 5]])
    5.0
    """
    return float(np.hypot(*(final_point(a) - final_point(b))))


def status_agreement(a: Path | str, b: Path | str) -> bool:
    """Whether two planners ended the same way (``reached`` vs ``local_minimum`` ...).

    Parameters
    ----------
    a, b : Path or str
        Two paths, or their statuses.

    Returns
    -------
    bool
        True when the statuses are equal.

    Examples
    --------
    >>> status_agreement("reached", "reached"), status_agreement("reached", "local_minimum")
    (True, False)
    """
    sa = a.status if isinstance(a, Path) else str(a)
    sb = b.status if isinstance(b, Path) else str(b)
    return sa == sb


# ----------------------------------------------------------------------------------------
# Paths against the world
# ----------------------------------------------------------------------------------------
def min_clearance(world: World, points: ArrayLike | Path) -> float:
    """Exact smallest distance from the path (its segments, not only its points) to the obstacles.

    0 when the path touches or enters an obstacle; see :func:`collides` to tell which.

    Parameters
    ----------
    world : World
        The exact obstacles.
    points : array_like, shape (N, 2), or Path
        The path (a single point is measured as a point).

    Returns
    -------
    float
        The exact distance from the polyline to the nearest obstacle (:meth:`World.clearance`).

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 4, 6, 6]}]})
    >>> min_clearance(w, [[0, 3], [10, 3]]), min_clearance(w, [[0, 4], [10, 4]])
    (1.0, 0.0)
    """

    return world.clearance(_points(points, "points"))


def _crosses_segment(p: NDArray[np.float64], seg: NDArray[np.float64]) -> bool:
    """Whether the polyline ``p`` passes from one side of the segment to the other through its interior."""
    c, e = seg
    d = e - c
    rel = p - c
    side = np.sign(d[0] * rel[:, 1] - d[1] * rel[:, 0])
    # edges whose end points are strictly on both sides, crossing the segment's line inside it
    a, b = p[:-1], p[1:]
    cand = side[:-1] * side[1:] < 0
    if cand.any():
        ab = b[cand] - a[cand]
        s1 = np.sign(ab[:, 0] * (c[1] - a[cand, 1]) - ab[:, 1] * (c[0] - a[cand, 0]))
        s2 = np.sign(ab[:, 0] * (e[1] - a[cand, 1]) - ab[:, 1] * (e[0] - a[cand, 0]))
        if (s1 * s2 < 0).any():
            return True
    # an inner vertex on the segment's relative interior with its neighbours on both sides
    t = (rel @ d) / float(d @ d)
    on = (side == 0) & (t > 0) & (t < 1)
    on[0] = on[-1] = False
    k = np.flatnonzero(on)
    return bool(len(k) and (side[k - 1] * side[k + 1] < 0).any())


def collides(world: World, points: ArrayLike | Path) -> bool:
    """Whether the path enters the interior of an obstacle or crosses a segment obstacle.

    Touching an obstacle (running along an edge, through a vertex) is not a collision. Circles are
    tested exactly (a segment passing closer to the centre than the radius collides).

    Parameters
    ----------
    world : World
        The exact obstacles (and border: with a wall border, leaving the bounds collides).
    points : array_like, shape (N, 2), or Path
        The path.

    Returns
    -------
    bool
        True when some part of the polyline lies inside an obstacle or crosses a segment obstacle.

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 4, 6, 6]},
    ...                                                             {"segment": [[8, 0], [8, 2]]}]})
    >>> collides(w, [[0, 4], [10, 4]]), collides(w, [[0, 5], [10, 5]]), collides(w, [[7, 1], [9, 1]])
    (False, True, True)
    """
    p = _points(points, "points")
    line = shapely.linestrings(p) if len(p) > 1 else shapely.points(p[0])
    for ob in world.obstacles:
        if ob.kind == "circle":
            assert ob.center is not None and ob.radius is not None
            if float(shapely.distance(line, shapely.points(ob.center))) < ob.radius * (1 - 1e-12):
                return True
        elif ob.kind == "polygon":
            if shapely.relate_pattern(line, ob.geometry, "T********") or (
                    len(p) == 1 and shapely.contains(ob.geometry, line)):
                return True
        elif ob.kind == "segment" and len(p) > 1 and _crosses_segment(p, np.asarray(ob.geometry.coords)[[0, -1]]):
            return True
    if world.border == "wall":
        xmin, ymin, xmax, ymax = world.bounds
        if (p[:, 0] < xmin).any() or (p[:, 0] > xmax).any() or (p[:, 1] < ymin).any() or (p[:, 1] > ymax).any():
            return True
    return False


# ----------------------------------------------------------------------------------------
# Distance maps against the exact distance
# ----------------------------------------------------------------------------------------
def distance_map_errors(
    world: World,
    resolution: float,
    *,
    metrics: Sequence[str] | None = None,
    bands: Sequence[float] | None = None,
) -> dict[str, dict[str, Any]]:
    """Error of every brushfire metric against the exact obstacle distance at the free cell centres.

    The world is rasterized (conservatively) at ``resolution``; for each metric the brushfire
    distance of every free cell is compared with ``world.distance`` at the cell centre.

    Parameters
    ----------
    world : World
    resolution : float
    metrics : sequence of str, optional
        Brushfire metrics (default all: chessboard on the 8-neighbourhood, taxicab on the
        4-neighbourhood, euclidean).
    bands : sequence of float, optional
        Edges of the exact-distance bands in world units (default ``resolution * [0, 1, 2, 4, 8,
        16, 32]`` and infinity).

    Returns
    -------
    dict
        ``{metric: {"max": max |error|, "mean": mean |error|, "bias": mean signed error
        (brushfire - exact), "cells": free cells compared, "bands": [{"lo", "hi", "cells", "max",
        "mean", "bias"}, ...]}}``.

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 2}}]})
    >>> e = distance_map_errors(w, 0.5, metrics=["euclidean"])
    >>> e["euclidean"]["max"] <= 0.5 / 2 ** 0.5
    True
    """
    from ..brushfire import METRICS, brushfire
    from ..rasterize import rasterize

    h = check_positive("resolution", resolution)
    metrics = list(METRICS if metrics is None else metrics)
    for m in metrics:
        if m not in METRICS:
            raise ParameterError(f"metric must be one of {', '.join(METRICS)}, got {m!r}")
    edges = np.asarray([0.0, 1, 2, 4, 8, 16, 32, np.inf] if bands is None else bands, dtype=float)
    if bands is None:
        edges[:-1] *= h
    if edges.ndim != 1 or len(edges) < 2 or np.any(np.diff(edges) <= 0) or np.isnan(edges).any():
        raise ParameterError(f"bands must be increasing distances, got {list(bands or [])!r}")
    gm = rasterize(world, h)
    xs, ys = gm.grid.cell_centers()
    X, Y = np.meshgrid(xs, ys)
    free = ~gm.occupied
    exact = world.distance(np.column_stack([X[free], Y[free]]))
    out: dict[str, dict[str, Any]] = {}
    for m in metrics:
        dm = brushfire(gm, connectivity=4 if m == "taxicab" else 8, metric=m)
        err = dm.distance[free] - exact
        ok = np.isfinite(err)
        err, ex = err[ok], exact[ok]
        rows = []
        for lo, hi in itertools.pairwise(edges):
            sel = (ex >= lo) & (ex < hi)
            e = err[sel]
            rows.append({"lo": float(lo), "hi": float(hi), "cells": int(sel.sum()),
                         "max": float(np.abs(e).max()) if e.size else math.nan,
                         "mean": float(np.abs(e).mean()) if e.size else math.nan,
                         "bias": float(e.mean()) if e.size else math.nan})
        out[m] = {"max": float(np.abs(err).max()) if err.size else math.nan,
                  "mean": float(np.abs(err).mean()) if err.size else math.nan,
                  "bias": float(err.mean()) if err.size else math.nan,
                  "cells": int(err.size), "bands": rows}
    return out


# ----------------------------------------------------------------------------------------
# Convergence study
# ----------------------------------------------------------------------------------------
def observed_order(resolutions: ArrayLike, errors: ArrayLike) -> float:
    """Least-squares slope of ``log(error)`` against ``log(resolution)``: error ~ C h^order.

    Pairs whose error is not positive and finite are left out; NaN when fewer than two remain.

    Parameters
    ----------
    resolutions : array_like
        Cell sizes ``h``.
    errors : array_like
        The error at each resolution (same length).

    Returns
    -------
    float
        The fitted exponent ``order`` (NaN when fewer than two usable pairs or a single resolution).

    Examples
    --------
    >>> round(observed_order([0.4, 0.2, 0.1], [0.16, 0.04, 0.01]), 6)
    2.0
    >>> observed_order([0.4, 0.2], [0.0, 0.1])
    nan
    """
    h = np.asarray(resolutions, dtype=float).reshape(-1)
    e = np.asarray(errors, dtype=float).reshape(-1)
    if h.shape != e.shape:
        raise ParameterError(f"resolutions and errors differ in length: {h.size} vs {e.size}")
    ok = np.isfinite(h) & (h > 0) & np.isfinite(e) & (e > 0)
    if ok.sum() < 2 or np.ptp(np.log(h[ok])) == 0:
        return math.nan
    return float(np.polyfit(np.log(h[ok]), np.log(e[ok]), 1)[0])


def _spacing_for(*paths: Path, resolution: float) -> float:
    """Resampling step for curve distances: a quarter of the finest scale involved."""
    steps = [resolution]
    for p in paths:
        if len(p.points) > 1:
            seg = np.hypot(*np.diff(p.points, axis=0).T)
            seg = seg[seg > 0]
            if seg.size:
                steps.append(float(np.median(seg)))
    return max(min(steps) / 4.0, 1e-9)


def _optimum_fn(world: Any, *, cache: dict[Any, Any] | None = None
                ) -> Callable[[NDArray[np.float64], NDArray[np.float64]], float]:
    """``(start, goal) -> exact optimum length`` (NaN for a bad point) on a World or a GridMap: the
    any-angle graph of the grid for a grid map or a world made from one (gridfield.gridpoly), kept in
    ``cache`` when given (the plan cache: :func:`gridfield.planners.plan` finds the same graph there),
    else the visibility graph of the world (the one ``plan("visibility")`` uses, cached per world)."""
    from ..grid import GridMap
    from ..gridpoly import source_grid

    if isinstance(world, GridMap):
        gm = world if not isinstance(world.world, World) else None
        world = world.world
    else:
        gm = source_grid(world)
    if gm is not None:
        from ..anyangle import grid_graph

        solver: Any = grid_graph(gm, cache=cache)
    else:
        from ..visibility import _cached_graph

        solver = _cached_graph(world, "block")

    def optimum(s: NDArray[np.float64], g: NDArray[np.float64]) -> float:
        try:
            return float(solver.shortest_path(s, g)[1])
        except GridfieldError:
            return math.nan

    return optimum


def _optimum(world: World, start: NDArray[np.float64], goal: NDArray[np.float64]) -> float:
    return _optimum_fn(world)(start, goal)


def _as_world(target: Any, what: str) -> tuple[World, Any]:
    """A vector world as is, or a grid map's exact polygons (gridfield.gridpoly) and the map."""
    from ..grid import GridMap

    if isinstance(target, World):
        return target, None
    if isinstance(target, GridMap):
        if isinstance(target.world, World):
            return target.world, None
        from ..gridpoly import grid_world

        return grid_world(target), target
    raise ParameterError(f"{what} needs a vector World or a GridMap, got {type(target).__name__}")


def _grid_factor(base: Any, h: float) -> int:
    """The integer block factor of resolution ``h`` on a grid map, or ParameterError."""
    res = base.grid.resolution
    k = int(round(h / res))
    if k < 1 or abs(k * res - h) > 1e-9 * h:
        raise ParameterError(f"on a grid map the resolutions must be multiples of the map's resolution {res:g} "
                             f"(coarser grids are block-downsampled), got {h:g}")
    return k


def _error_row(status: str) -> dict[str, Any]:
    nan = math.nan
    return {"status": status, "exact_status": "", "status_agree": False, "length": nan, "exact_length": nan,
            "optimal_length": nan, "length_ratio": nan, "length_ratio_optimal": nan, "hausdorff": nan,
            "frechet": nan, "end_error": nan, "min_clearance": nan, "collides": False}


def _compare_row(world: World, grid: Path, exact: Path, optimal: float, resolution: float) -> dict[str, Any]:
    spacing = _spacing_for(grid, exact, resolution=resolution)
    return {
        "status": grid.status,
        "exact_status": exact.status,
        "status_agree": status_agreement(grid, exact),
        "length": grid.length,
        "exact_length": exact.length,
        "optimal_length": optimal,
        "length_ratio": length_ratio(grid, exact.length),
        # a path that did not reach the goal has no meaningful ratio to the optimum
        "length_ratio_optimal": length_ratio(grid, optimal) if grid.reached else math.nan,
        "hausdorff": hausdorff(grid, exact, spacing=spacing),
        "frechet": discrete_frechet(grid, exact, spacing=spacing),
        "end_error": end_error(grid, exact),
        "min_clearance": min_clearance(world, grid),
        "collides": collides(world, grid),
    }


def convergence_study(
    world: World,
    start: ArrayLike,
    goal: ArrayLike,
    resolutions: Sequence[float],
    *,
    params: Mapping[str, Any] | None = None,
    grid_planner: str = "potential",
    exact_planner: str = "exact-potential",
) -> list[dict[str, Any]]:
    """Run a grid planner at several resolutions against an exact planner on one world.

    The exact planner runs once; the grid planner once per resolution on the conservative
    rasterization of ``world``. Both get the world's ``params`` updated by ``params``.

    On a grid map (a :class:`~gridfield.grid.GridMap` without a vector world) the exact planner
    runs on the map's blocked cells as exact polygons (:func:`gridfield.gridpoly.grid_world`) and
    the grid planner on the map itself at its resolution and on block-downsampled copies
    (:func:`gridfield.gridpoly.block_downsample`, conservative) at the coarser resolutions, which
    must be multiples of the map's. A resolution at which the start or goal falls in a blocked
    coarse cell gives a row with status ``"error: ..."`` and NaN metrics.

    Parameters
    ----------
    world : World or GridMap
    start, goal : (2,) array_like
    resolutions : sequence of float
        Cell sizes, each > 0.
    params : mapping, optional
        Planner parameters (override the world's).
    grid_planner, exact_planner : str
        Names in :data:`gridfield.planners.PLANNERS`; the grid planner must be a grid planner,
        the exact one a world planner (``"visibility"`` works on both sides for testing).

    Returns
    -------
    list of dict
        One row per resolution with the keys :data:`STUDY_COLUMNS`: ``cells`` (grid size),
        ``build_ms`` (rasterization plus field building), ``plan_ms`` (following), ``status`` and
        ``exact_status``, ``length_ratio`` (grid length / exact length) and
        ``length_ratio_optimal`` (grid length / visibility-graph optimum; NaN unless the grid planner
        reached the goal), ``hausdorff`` and
        ``frechet`` (grid path vs exact path), ``end_error`` (distance between the end points: the
        stall-point error when both stall), ``min_clearance`` (exact clearance of the grid path
        against the world) and ``collides``.

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})
    >>> rows = convergence_study(w, [1, 5], [9, 5], [1.0, 0.5], grid_planner="visibility",
    ...                          exact_planner="visibility")
    >>> [(r["resolution"], r["status"], r["hausdorff"]) for r in rows]
    [(1.0, 'reached', 0.0), (0.5, 'reached', 0.0)]
    """
    from ..planners import get_planner, plan
    from ..rasterize import rasterize

    world, base = _as_world(world, "convergence_study")
    hs = [check_positive("resolution", r) for r in resolutions]
    if not hs:
        raise ParameterError("give at least one resolution")
    from ..grid import Grid

    for h in hs:  # every resolution's grid sized against the memory limit before any planner runs
        Grid.covering(world.bounds, h, border=world.border)
    factors = [_grid_factor(base, h) for h in hs] if base is not None else []
    kind_exact = get_planner(exact_planner)[1]
    if kind_exact != "world":
        raise ParameterError(f"exact_planner must work on vector worlds; {exact_planner!r} is a grid planner")
    kind_grid = get_planner(grid_planner)[1]
    s = world.check_point("start", start)
    g = world.check_point("goal", goal)
    exact = plan(exact_planner, world, s, g, params)
    optimal = _optimum(world, s, g)
    def grid_at(i: int) -> Any:
        if base is None:
            return rasterize(world, hs[i])
        from ..gridpoly import block_downsample

        return block_downsample(base, factors[i])

    if kind_grid == "grid":  # untimed warm-up: first-call costs (imports, caches)
        with contextlib.suppress(GridfieldError):
            plan(grid_planner, grid_at(int(np.argmax(hs))), s, g, params)
    rows = []
    for i, h in enumerate(hs):
        t0 = time.perf_counter()
        gm = grid_at(i)
        raster_s = time.perf_counter() - t0
        # a world planner on the grid side only tests the plumbing
        try:
            path = plan(grid_planner, gm if kind_grid == "grid" else world, s, g, params)
        except GridfieldError as e:
            row: dict[str, Any] = {"resolution": h, "cells": int(gm.grid.rows * gm.grid.cols),
                                   "build_ms": 1e3 * raster_s, "plan_ms": math.nan}
            row.update(_error_row(f"error: {e}"))
            row["exact_status"], row["exact_length"], row["optimal_length"] = exact.status, exact.length, optimal
            rows.append({k: row[k] for k in STUDY_COLUMNS})
            continue
        build_s = raster_s + float(path.extra.get("build_seconds", 0.0))
        row = {"resolution": h, "cells": int(gm.grid.rows * gm.grid.cols), "build_ms": 1e3 * build_s,
               "plan_ms": 1e3 * float(path.extra.get("follow_seconds", path.seconds))}
        row.update(_compare_row(world, path, exact, optimal, h))
        rows.append({k: row[k] for k in STUDY_COLUMNS})
    return rows


def study_errors(rows: Sequence[Mapping[str, Any]]) -> dict[str, list[float]]:
    """The error columns (:data:`ERROR_COLUMNS`) of convergence-study rows.

    ``length_error`` is ``|length_ratio - 1|`` (grid length against the exact planner's) where both
    planners reached the goal, NaN elsewhere: a stalled follower's path length depends on when its
    oscillation was detected, not on the field's accuracy.

    Parameters
    ----------
    rows : sequence of mapping
        Rows of :func:`convergence_study` (at least ``hausdorff``, ``frechet``, ``end_error`` and
        ``length_ratio``; ``status`` and ``exact_status`` default to ``"reached"``).

    Returns
    -------
    dict of str to list of float
        ``hausdorff``, ``frechet``, ``end_error`` and ``length_error``, one value per row.

    Examples
    --------
    >>> study_errors([{"hausdorff": 0.4, "frechet": 0.5, "end_error": 0.1, "length_ratio": 1.2,
    ...                "status": "local_minimum", "exact_status": "local_minimum"}])
    {'hausdorff': [0.4], 'frechet': [0.5], 'end_error': [0.1], 'length_error': [nan]}
    """
    both_reached = [r.get("status", "reached") == r.get("exact_status", "reached") == "reached" for r in rows]
    return {
        "hausdorff": [float(r["hausdorff"]) for r in rows],
        "frechet": [float(r["frechet"]) for r in rows],
        "end_error": [float(r["end_error"]) for r in rows],
        "length_error": [abs(float(r["length_ratio"]) - 1.0) if ok else math.nan
                         for r, ok in zip(rows, both_reached, strict=True)],
    }


def study_orders(rows: Sequence[Mapping[str, Any]]) -> dict[str, float]:
    """Observed orders (:func:`observed_order`) of the error columns of a convergence study
    (:func:`study_errors`); NaN for a column with fewer than two positive errors.

    Parameters
    ----------
    rows : sequence of mapping
        Rows of :func:`convergence_study` (with ``resolution`` and the columns of :func:`study_errors`).

    Returns
    -------
    dict of str to float
        The observed order of each error column.

    Examples
    --------
    >>> rows = [{"resolution": 0.2, "hausdorff": 0.4, "frechet": 0.4, "end_error": 0.1, "length_ratio": 1.2},
    ...         {"resolution": 0.1, "hausdorff": 0.2, "frechet": 0.2, "end_error": 0.05, "length_ratio": 1.1}]
    >>> {k: round(v, 6) for k, v in study_orders(rows).items()}
    {'hausdorff': 1.0, 'frechet': 1.0, 'end_error': 1.0, 'length_error': 1.0}
    """
    h = [r["resolution"] for r in rows]
    return {k: observed_order(h, v) for k, v in study_errors(rows).items()}


# ----------------------------------------------------------------------------------------
# Batch comparison
# ----------------------------------------------------------------------------------------
def _progress(iterable: Any, *, total: int, enabled: bool, desc: str) -> Any:
    if not enabled or not sys.stderr.isatty():
        return iterable
    from tqdm import tqdm

    return tqdm(iterable, total=total, desc=desc, file=sys.stderr, leave=False)


def _random_pairs(world: World, gm: Any, n: int, rng: np.random.Generator, margin: float,
                  optimum: Callable[[NDArray[np.float64], NDArray[np.float64]], float]
                  ) -> list[tuple[NDArray[np.float64], NDArray[np.float64], float]]:
    xmin, ymin, xmax, ymax = world.bounds
    pairs: list[tuple[NDArray[np.float64], NDArray[np.float64], float]] = []
    tries = 0
    while len(pairs) < n:
        tries += 1
        if tries > 200 * n + 1000:
            raise GridfieldError(f"found only {len(pairs)} of {n} connected free start/goal pairs in "
                                 f"{world.source or 'the world'}; is there enough free space?")
        pts = rng.uniform([xmin, ymin], [xmax, ymax], size=(2, 2))
        if not (world.distance(pts) > margin).all() or not gm.is_free(pts).all():
            continue
        if np.hypot(*(pts[1] - pts[0])) < 2 * margin:
            continue
        opt = optimum(pts[0], pts[1])
        if not math.isfinite(opt):
            continue
        pairs.append((pts[0], pts[1], opt))
    return pairs


def batch_compare(
    world: World,
    n_pairs: int,
    *,
    resolution: float,
    params: Mapping[str, Any] | None = None,
    seed: int = 0,
    progress: bool = True,
    planners: Sequence[str] = ("potential", "exact-potential", "wavefront-octile"),
) -> dict[str, Any]:
    """Plan many random start/goal pairs on one world and compare planners with the optimum.

    Pairs are drawn uniformly in the bounds, both points at least one cell from every obstacle
    (and free on the grid), connected in the world; the visibility graph gives the optimum. On a
    grid map the exact planners use its exact polygons (:func:`gridfield.gridpoly.grid_world`), the
    optimum is the any-angle one (:mod:`gridfield.anyangle`) and the grid planners run on the map
    downsampled to ``resolution`` (a multiple of the map's).

    Parameters
    ----------
    world : World or GridMap
    n_pairs : int
    resolution : float
        Cell size of the grid planners.
    params : mapping, optional
    seed : int
        Seed of the random pairs.
    progress : bool
        Show a tqdm progress bar (only when stderr is a terminal).
    planners : sequence of str
        Planners to run (grid planners on the rasterized world); unavailable ones are reported
        in ``"skipped"``.

    Returns
    -------
    dict
        ``{"world", "resolution", "pairs", "seed", "planners": {name: {"success_rate",
        "statuses": {status: count}, "length_ratio": {"mean", "median", "max"} (reached pairs, to
        the optimum), "agreement_with_exact"?}}, "skipped": {name: reason}, "rows": [per pair]}``.

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})
    >>> r = batch_compare(w, 3, resolution=0.5, planners=("visibility",), progress=False)
    >>> r["planners"]["visibility"]["success_rate"], r["planners"]["visibility"]["length_ratio"]["max"]
    (1.0, 1.0)
    """
    from ..planners import get_planner, plan
    from ..rasterize import rasterize

    world, base = _as_world(world, "batch_compare")
    if isinstance(n_pairs, bool) or not isinstance(n_pairs, int | np.integer) or n_pairs < 1:
        raise ParameterError(f"n_pairs must be a positive integer, got {n_pairs!r}")
    h = check_positive("resolution", resolution)
    kinds: dict[str, str] = {}
    skipped: dict[str, str] = {}
    for name in planners:
        try:
            kinds[name] = get_planner(name)[1]
        except GridfieldError as e:
            skipped[name] = str(e)
    if base is None:
        gm = rasterize(world, h)
    else:
        from ..gridpoly import block_downsample

        gm = block_downsample(base, _grid_factor(base, h))
    optimum = _optimum_fn(world)

    rng = np.random.default_rng(seed)
    pairs = _random_pairs(world, gm, int(n_pairs), rng, h, optimum)
    rows: list[dict[str, Any]] = []
    for s, g, opt in _progress(pairs, total=len(pairs), enabled=progress, desc="pairs"):
        row: dict[str, Any] = {"start": s.tolist(), "goal": g.tolist(), "optimal_length": opt}
        for name, kind in kinds.items():
            try:
                p = plan(name, gm if kind == "grid" else world, s, g, params)
            except GridfieldError as e:
                row[name] = {"status": "error", "error": str(e)}
                continue
            row[name] = {"status": p.status, "length": p.length,
                         "length_ratio": length_ratio(p, opt) if p.reached else math.nan,
                         "end": p.end.tolist(), "seconds": p.seconds}
        rows.append(row)

    summary: dict[str, Any] = {}
    for name in kinds:
        st = [r[name]["status"] for r in rows]
        ratios = np.asarray([r[name].get("length_ratio", math.nan) for r in rows], dtype=float)
        ratios = ratios[np.isfinite(ratios)]
        entry: dict[str, Any] = {
            "success_rate": float(np.mean([x == "reached" for x in st])),
            "statuses": {k: st.count(k) for k in sorted(set(st))},
            "length_ratio": {"mean": float(ratios.mean()) if ratios.size else math.nan,
                             "median": float(np.median(ratios)) if ratios.size else math.nan,
                             "max": float(ratios.max()) if ratios.size else math.nan},
        }
        summary[name] = entry
    if "potential" in kinds and "exact-potential" in kinds:
        agree = [r["potential"]["status"] == r["exact-potential"]["status"] for r in rows]
        summary["potential"]["agreement_with_exact"] = float(np.mean(agree))
    return {"world": world.source, "resolution": h, "pairs": len(rows), "seed": seed, "planners": summary,
            "skipped": skipped, "rows": rows}
