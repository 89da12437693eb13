"""Metrics between paths and against the world: pure functions on point arrays ``(N, 2)`` (a
:class:`~gridfield.core.path.Path` works too), the brushfire distance maps' errors against the exact
obstacle distance, and the observed order of convergence of an error. Part of :mod:`gridfield.compare`
(import the names from there)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.distance import directed_hausdorff

from ..core.errors import ParameterError, check_positive
from ..core.path import Path, path_length
from ..geometry.world import World


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


def max_deviation(path: ArrayLike | Path, reference: ArrayLike | Path) -> float:
    """The largest distance of a path's points from a reference polyline (a one-sided Hausdorff
    distance to the reference's segments, not only to its vertices).

    Parameters
    ----------
    path : array_like, shape (N, 2), or Path
        The points measured (e.g. a grid planner's path).
    reference : array_like, shape (M, 2), or Path
        The polyline measured against (e.g. the exact planner's path); a single point is a point.

    Returns
    -------
    float
        ``max_i dist(path[i], reference)``.

    Raises
    ------
    ParameterError
        When either has no points.

    Examples
    --------
    >>> max_deviation([[0.5, 0.5], [0.5, 3.5]], [[0.5, 0.5], [0.7, 3.5]])
    0.2
    >>> max_deviation([[1.0, 1.0]], [[0.0, 0.0], [2.0, 0.0]])    # to the segment, not its ends
    1.0
    """
    p, q = _points(path, "path"), _points(reference, "reference")
    ref = shapely.LineString(q) if len(q) > 1 else shapely.Point(q[0])
    return float(np.max(shapely.distance(ref, shapely.points(p))))


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
    last: NDArray[np.float64] = _points(path, "path")[-1]
    return last


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
    >>> from gridfield.geometry.world import world_from_dict
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
    >>> from gridfield.geometry.world import world_from_dict
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
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 2}}]})
    >>> e = distance_map_errors(w, 0.5, metrics=["euclidean"])
    >>> e["euclidean"]["max"] <= 0.5 / 2 ** 0.5
    True
    """
    from ..distance.brushfire import METRICS, brushfire
    from ..geometry.rasterize import rasterize

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
# Observed order of convergence
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
