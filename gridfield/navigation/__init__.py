"""Navigation functions: potentials whose only minimum is the goal (Choset et al. sec. 4.5-4.6).

Four constructions, each returned as a :class:`NavigationField` (the value array and its grid):

- :func:`wavefront` -- the grid navigation function: the exact shortest-path cost to the goal cell
  over 4- or 8-connected moves, with unit costs or octile costs (1 and sqrt 2), optionally raised near
  obstacles (``clearance_weight``). Diagonal moves never cut a corner: a diagonal step is allowed only
  when both orthogonally adjacent cells are free (the Moving AI rule). Computed by Dijkstra with a
  bucket queue in a compiled kernel; :func:`extract_path` follows it down to the goal.
- :func:`fmm` -- the Euclidean geodesic distance by fast marching (scikit-fmm, optional extra
  ``gridfield[fmm]``), followed along its interpolated gradient: near-any-angle paths.
- :func:`harmonic` -- a solution of Laplace's equation (goal 0, obstacles and border 1), solved with a
  sparse preconditioned conjugate-gradient method. Far from the goal the harmonic function underflows;
  the field is continued by nested "shells" in log scale (see :func:`harmonic`).
- :func:`sphere_nav_function` -- the Rimon-Koditschek navigation function of a sphere world (disc
  obstacles inside a disc workspace), with its analytic gradient.

The planners ``wavefront``, ``wavefront-octile``, ``fmm``, ``harmonic`` and ``sphere-nav`` of
:mod:`gridfield.planners` are :func:`plan_wavefront`, :func:`plan_wavefront_octile`, :func:`plan_fmm`,
:func:`plan_harmonic` and :func:`plan_sphere_nav`; :func:`navigation_field` gives the field of any of
them (``gridfield field``).

Units: every value array is in world units (lengths, or costs measured as lengths), and every point
crosses the public boundary as world coordinates ``(x, y)``; arrays are indexed ``[row, col]`` with
row 0 the lowest y, as everywhere in gridfield. What lies outside the grid is never traversed by
the grid navigation functions, whatever the grid's ``border`` (the harmonic one treats it as a wall
at value 1).
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Literal, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import GridfieldError, ParameterError
from ..grid import Grid, GridMap
from ..path import Path

__all__ = [
    "KINDS",
    "NavigationField",
    "clearance_cost",
    "extract_path",
    "fmm",
    "harmonic",
    "navigation_field",
    "plan_fmm",
    "plan_harmonic",
    "plan_sphere_nav",
    "plan_wavefront",
    "plan_wavefront_octile",
    "sphere_nav_function",
    "wavefront",
]

#: The kinds of :class:`NavigationField`.
KINDS = ("wavefront", "fmm", "harmonic", "sphere-nav")
COSTS = ("unit", "octile")
SQRT2 = math.sqrt(2.0)


@functools.cache
def _kernels() -> Any:
    from .. import _kernels_navigation  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _kernels_navigation


@functools.cache
def _warm_followers() -> None:
    """Load the compiled followers once per process (importing the extension module, a few
    milliseconds), so that :attr:`Path.seconds` measures the path, not the start-up."""
    k = _kernels()
    one = np.zeros((1, 1))
    free = np.ones((1, 1), bool)
    k.descend(one, free, np.empty((0, 0)), 0, 0, 8, SQRT2, 0, 1.0)
    k.follow_interpolated(one, one, one, free, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 1, SQRT2)
    k.clearance_along(~free, np.zeros(1, np.int64), np.zeros(1, np.int64), False, 8)


# ----------------------------------------------------------------------------------------------
# The field object
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class NavigationField:
    """A navigation function sampled at the cell centres of a grid.

    Attributes
    ----------
    map : GridMap
        The occupancy map the field was computed on.
    value : ndarray of float64, shape ``map.shape``
        The navigation function: 0 at the goal cell, increasing away from it, ``inf`` on obstacles and
        on cells from which the goal cannot be reached (``1.0`` there for ``kind="sphere-nav"``,
        whose values lie in [0, 1]).
    goal : ndarray, shape (2,)
        The goal as given (world coordinates).
    goal_cell : tuple of int
        ``(row, col)`` of the cell containing the goal.
    kind : str
        One of :data:`KINDS`.
    params : mapping
        The construction's parameters (``connectivity``, ``costs``, ``clearance_weight``, ...).
    aux : mapping
        Extra arrays of the construction (e.g. the classic harmonic potential, the shell index, the
        analytic gradient of the sphere-world function) and scalars (solve statistics).

    Also ``potential`` (= ``value``), ``grad_x``, ``grad_y`` and ``distance`` (``None``), so that a
    navigation field can stand where a :class:`gridfield.potential.Field` is expected.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> m = GridMap(Grid((1, 4), 1.0), np.array([[False, False, True, False]]))
    >>> nav = wavefront(m, (0.5, 0.5))
    >>> nav.value
    array([[ 0.,  1., inf, inf]])
    >>> nav.value_at([[1.5, 0.5], [9.0, 0.5]])
    array([ 1., inf])
    """

    map: GridMap
    value: NDArray[np.float64]
    goal: NDArray[np.float64]
    goal_cell: tuple[int, int]
    kind: str
    params: Mapping[str, Any] = field(default_factory=dict)
    aux: Mapping[str, Any] = field(default_factory=dict)

    def __repr__(self) -> str:
        reach = int(np.count_nonzero(self.reachable))
        return (f"NavigationField(kind={self.kind!r}, shape={self.map.grid.shape}, "
                f"goal=({float(self.goal[0]):.6g}, {float(self.goal[1]):.6g}), reachable cells={reach})")

    @property
    def grid(self) -> Grid:
        return self.map.grid

    @property
    def potential(self) -> NDArray[np.float64]:
        """The value array (the name :class:`gridfield.potential.Field` uses)."""
        return self.value

    @property
    def distance(self) -> None:
        """No obstacle distance map travels with a navigation function (``Field`` compatibility)."""
        return None

    @property
    def reachable(self) -> NDArray[np.bool_]:
        """Cells from which the goal can be reached."""
        if self.kind == "sphere-nav":
            return self.value < 1.0
        return np.isfinite(self.value)

    @cached_property
    def _gradient(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        if "grad_x" in self.aux:
            return self.aux["grad_x"], self.aux["grad_y"]
        return upwind_gradient(self.value, self.grid.resolution)

    @property
    def grad_x(self) -> NDArray[np.float64]:
        """d value / dx at the cell centres (upwind differences; analytic for ``sphere-nav``)."""
        return self._gradient[0]

    @property
    def grad_y(self) -> NDArray[np.float64]:
        """d value / dy at the cell centres."""
        return self._gradient[1]

    @cached_property
    def clearance(self) -> NDArray[np.float64]:
        """Euclidean brushfire distance of each cell centre to the nearest obstacle cell centre (computed
        once per field; used for :attr:`Path.min_clearance`)."""
        from ..brushfire import brushfire

        return brushfire(self.map, metric="euclidean").distance

    def to_field(self) -> Any:
        """The same arrays as a :class:`gridfield.potential.Field` (for its follower and plots)."""
        from ..potential import Field

        return Field(self.map, self.value, self.grad_x, self.grad_y, (float(self.goal[0]), float(self.goal[1])),
                     {"navigation": self.kind, **dict(self.params)})

    def value_at(self, points: ArrayLike) -> NDArray[np.float64]:
        """Value of the cell containing each world point, shape ``(N,)``; ``inf`` outside the grid.

        A single point ``(x, y)`` gives an array of shape ``(1,)``.
        """
        cells, inside = self.grid.world_to_cell(points)
        out = np.full(len(cells), np.inf)
        r, c = cells[inside].T
        out[inside] = self.value[r, c]
        return out


def upwind_gradient(value: NDArray[np.float64], resolution: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gradient of a distance-like array by upwind differences: along each axis, the one-sided
    difference towards the lower neighbour (0 where no neighbour is lower, and on non-finite cells).
    Neighbours with non-finite values are never used, so obstacles do not leak into the gradient.

    Examples
    --------
    >>> gx, gy = upwind_gradient(np.array([[0.0, 1.0, 2.0], [1.0, np.inf, 3.0]]), 1.0)
    >>> gx
    array([[0., 1., 1.],
           [0., 0., 0.]])
    >>> gy
    array([[0., 0., 0.],
           [1., 0., 1.]])
    """
    v = np.asarray(value, dtype=np.float64)
    pad = np.pad(v, 1, constant_values=np.inf)
    left, right = pad[1:-1, :-2], pad[1:-1, 2:]
    down, up = pad[:-2, 1:-1], pad[2:, 1:-1]
    with np.errstate(invalid="ignore"):
        gx = np.where(left <= right, np.where(left < v, v - left, 0.0), np.where(right < v, right - v, 0.0))
        gy = np.where(down <= up, np.where(down < v, v - down, 0.0), np.where(up < v, up - v, 0.0))
    bad = ~np.isfinite(v)
    gx[bad | ~np.isfinite(gx)] = 0.0
    gy[bad | ~np.isfinite(gy)] = 0.0
    return gx / resolution, gy / resolution


# ----------------------------------------------------------------------------------------------
# Helpers
# ----------------------------------------------------------------------------------------------
def _goal_cell(gridmap: GridMap, goal: ArrayLike) -> tuple[NDArray[np.float64], tuple[int, int]]:
    """The goal as ``(2,)`` and its cell; :meth:`GridMap.check_point`'s errors when it is not free."""
    g = gridmap.check_point("goal", goal)
    cell = gridmap.grid.cell_of(g[0], g[1])
    assert cell is not None  # check_point: inside the grid
    return g, cell


def _check_connectivity(connectivity: Any) -> int:
    try:
        conn = int(connectivity)
    except (TypeError, ValueError):
        conn = -1
    if conn not in (4, 8) or conn != connectivity:
        raise ParameterError(f"connectivity must be 4 or 8, got {connectivity!r}")
    return conn


def _check_weight(clearance_weight: Any) -> float:
    try:
        w = float(clearance_weight)
    except (TypeError, ValueError):
        w = math.nan
    if not (math.isfinite(w) and w >= 0):
        raise ParameterError(f"clearance_weight must be a finite number >= 0, got {clearance_weight!r}")
    return w


def clearance_cost(gridmap: GridMap, clearance_weight: float, q_star: float | None = None) -> NDArray[np.float64]:
    """Cell cost of the clearance-aware navigation functions:
    ``1 + clearance_weight * max(0, 1 - D / q_star)``, with ``D`` the Euclidean brushfire distance
    from the cell centre to the nearest obstacle cell centre (world units).

    A cell next to an obstacle (``D = resolution``) costs almost ``1 + clearance_weight``; the extra cost
    falls linearly to 0 at ``D = q_star`` (default: 5 cells), like the inflation layer of a ROS
    costmap used by navfn. A step between cells costs its length times the mean of the two cell costs.
    Obstacle cells get ``inf``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((1, 5), bool); occ[0, 0] = True
    >>> clearance_cost(GridMap(Grid((1, 5), 1.0), occ), 2.0, q_star=4.0)
    array([[inf, 2.5, 2. , 1.5, 1. ]])
    """
    from ..brushfire import brushfire

    w = _check_weight(clearance_weight)
    res = gridmap.grid.resolution
    q = 5.0 * res if q_star is None else float(q_star)
    if not (math.isfinite(q) and q > 0):
        raise ParameterError(f"q_star must be a positive finite distance, got {q_star!r}")
    d = brushfire(gridmap, metric="euclidean").distance
    with np.errstate(invalid="ignore"):
        cost = 1.0 + w * np.clip(1.0 - d / q, 0.0, None)
    cost[~np.isfinite(d)] = 1.0  # no obstacle anywhere
    cost[gridmap.occupied] = np.inf
    return cost


# ----------------------------------------------------------------------------------------------
# Wavefront (grid navigation function)
# ----------------------------------------------------------------------------------------------
def wavefront(
    gridmap: GridMap,
    goal: ArrayLike,
    *,
    connectivity: int = 8,
    costs: Literal["unit", "octile"] = "unit",
    clearance_weight: float = 0.0,
    q_star: float | None = None,
    stop_at: ArrayLike | None = None,
) -> NavigationField:
    """The grid navigation function: shortest-path cost from every cell to the goal cell.

    Parameters
    ----------
    gridmap : GridMap
    goal : (x, y)
        Goal point (world coordinates); it must lie in a free cell of the grid.
    connectivity : {8, 4}
        Moves to the 8 or 4 neighbours. Diagonal moves never cut a corner: a diagonal step is allowed
        only when both orthogonally adjacent cells are free (the Moving AI rule).
    costs : {"unit", "octile"}
        ``"unit"``: every move costs one cell (Choset's wavefront, chessboard/taxicab steps);
        ``"octile"``: orthogonal moves cost 1, diagonal ones sqrt 2 (the Moving AI benchmark metric).
        Values are multiplied by the resolution (world units).
    clearance_weight : float
        0 (default) for plain costs; otherwise each step's cost is multiplied by the mean
        :func:`clearance_cost` of its two cells, so that paths keep away from obstacles.
    q_star : float, optional
        Distance of influence of the clearance cost (default 5 cells).
    stop_at : (x, y), optional
        End the search once the cell containing this point is settled (a point-to-point query). Values
        up to that cell's value are exact; larger ones are upper bounds or ``inf``.

    Returns
    -------
    NavigationField
        ``kind="wavefront"``; ``value`` is ``inf`` on obstacles and unreachable cells.

    Notes
    -----
    Dijkstra's algorithm with a bucket queue (Dial): buckets hold cells by ``floor(cost)`` in cells,
    and since every step costs at least one cell, a bucket's cells are final when it is reached and
    need no ordering. With octile costs only three buckets are ever live. The values are exact sums of
    step costs (floating point).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
    >>> m = GridMap(Grid((3, 3), 1.0), occ)
    >>> wavefront(m, (0.5, 0.5), costs="octile").value  # no diagonal step past the blocked centre
    array([[ 0.,  1.,  2.],
           [ 1., inf,  3.],
           [ 2.,  3.,  4.]])
    >>> wavefront(GridMap(Grid((2, 3), 1.0), np.zeros((2, 3), bool)), (0.5, 0.5), costs="octile").value.round(4)
    array([[0.    , 1.    , 2.    ],
           [1.    , 1.4142, 2.4142]])
    >>> wavefront(m, (0.5, 0.5), connectivity=4).value
    array([[ 0.,  1.,  2.],
           [ 1., inf,  3.],
           [ 2.,  3.,  4.]])
    """
    conn = _check_connectivity(connectivity)
    if costs not in COSTS:
        raise ParameterError(f"costs must be one of {COSTS}, got {costs!r}")
    w = _check_weight(clearance_weight)
    g, (gr, gc) = _goal_cell(gridmap, goal)
    sr = sc = -1
    if stop_at is not None:
        cells, inside = gridmap.grid.world_to_cell(stop_at)
        if not inside[0]:
            raise GridfieldError(f"stop_at {np.asarray(stop_at).tolist()} lies outside the map")
        sr, sc = (int(v) for v in cells[0])
    k = _kernels()
    free = ~gridmap.occupied
    diag = SQRT2 if costs == "octile" else 1.0
    aux: dict[str, Any] = {}
    if w > 0:
        cost = clearance_cost(gridmap, w, q_star)
        dist = k.wavefront_weighted(free, np.where(free, cost, 1.0), gr, gc, conn, diag, sr, sc,
                                    gridmap.grid.resolution)
        aux["cost"] = cost
    else:
        dist = k.wavefront_uniform(free, gr, gc, conn, diag, sr, sc, gridmap.grid.resolution)
    params = {"connectivity": conn, "costs": costs, "clearance_weight": w, "q_star": q_star}
    return NavigationField(gridmap, dist, g, (gr, gc), "wavefront", params, aux)


def extract_path(
    nav: NavigationField,
    start: ArrayLike,
    *,
    method: Literal["auto", "descent", "gradient"] = "auto",
    step: float | None = None,
    tolerance: float | None = None,
    max_iterations: int | None = None,
    planner: str | None = None,
) -> Path:
    """Follow a navigation field from ``start`` down to its goal.

    Parameters
    ----------
    nav : NavigationField
        From :func:`wavefront`, :func:`fmm` or :func:`harmonic`.
    start : (x, y)
        Start point (world coordinates), in a free cell.
    method : {"auto", "descent", "gradient"}
        ``"descent"``: discrete descent over the 8 (or 4) neighbour cells under the move rule of the
        field (no corner cutting). On a wavefront field it steps to a shortest-path parent (the
        neighbour minimizing value + step cost), so the cell chain costs exactly the value at the start
        cell; on a harmonic field it takes the steepest descent (largest drop per unit length).
        ``"gradient"``: normalized steps of length ``step`` along the bilinearly interpolated upwind
        gradient (falling back to a discrete step where a continuous one would not descend or would
        cut a corner): near-any-angle paths on a fast-marching field. ``"auto"``: gradient for
        ``fmm`` fields, descent otherwise.
    step : float, optional
        Step length of the gradient follower (default half a cell).
    tolerance : float, optional
        The gradient follower stops within this distance of the goal (default half a cell); it also
        stops on entering the goal cell.
    max_iterations : int, optional
        Step limit of the gradient follower (default ``4 * free cells / (step / resolution)``).
    planner : str, optional
        Name put in :attr:`Path.planner` (default: the field's kind).

    Returns
    -------
    Path
        ``points`` start exactly at ``start`` and end exactly at the goal; in between lie the centres
        of the cells the descent visits (the start cell's centre included) or the follower's positions.
        ``extra["value"]`` is the field's value at the start cell and ``extra["grid_length"]`` the
        length of the chain from the start cell's centre to the goal cell's centre -- for an octile
        wavefront without clearance cost the two are equal, and ``path.length`` differs from them only
        by the offsets of ``start`` and ``goal`` from their cell centres. ``status`` is ``"no_path"``
        (the start cell cannot reach the goal; ``points`` holds only the start), ``"reached"``,
        ``"local_minimum"`` (a numerically flat spot) or ``"max_iterations"``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
    >>> nav = wavefront(GridMap(Grid((3, 3), 1.0), occ), (0.5, 0.5), costs="octile")
    >>> p = extract_path(nav, (2.5, 2.5))
    >>> p.status, p.extra["value"], p.extra["grid_length"]
    ('reached', 4.0, 4.0)
    >>> p.points.tolist()
    [[2.5, 2.5], [2.5, 1.5], [2.5, 0.5], [1.5, 0.5], [0.5, 0.5]]
    """
    _warm_followers()
    t0 = time.perf_counter()
    gm = nav.map
    grid = gm.grid
    res = grid.resolution
    s = gm.check_point("start", start)
    sr, sc = grid.cell_of(s[0], s[1])  # type: ignore[misc]  # check_point: inside the grid
    name = planner or nav.kind
    if method == "auto":
        method = "gradient" if nav.kind == "fmm" else "descent"
    if method not in ("descent", "gradient"):
        raise ParameterError(f"method must be 'auto', 'descent' or 'gradient', got {method!r}")
    if nav.kind == "sphere-nav":
        raise ParameterError("extract_path follows grid fields; follow a sphere-world function with plan_sphere_nav")
    v0 = float(nav.value[sr, sc])
    params = dict(nav.params)
    if not math.isfinite(v0):
        return Path(s[None, :], "no_path", name, 0, params, time.perf_counter() - t0,
                    extra={"value": math.inf, "grid_length": math.inf, "reason": "the goal is unreachable from the start"})
    k = _kernels()
    free = ~gm.occupied
    conn = int(nav.params.get("connectivity", 8))
    if method == "descent":
        cost = nav.aux.get("cost")
        cost_arr = np.where(free, cost, 1.0) if cost is not None else np.empty((0, 0))
        diag = SQRT2 if nav.params.get("costs", "octile") == "octile" or nav.kind != "wavefront" else 1.0
        mode = 0 if nav.kind == "wavefront" else 1
        cells, reached = k.descend(nav.value, free, cost_arr, sr, sc, conn, diag, mode, res)
        x0, y0 = grid.origin
        points, grid_length = k.chain_points(cells, s[0], s[1], nav.goal[0], nav.goal[1], reached,
                                             x0, y0, res, SQRT2)
        status = "reached" if reached else "local_minimum"
        iterations = len(cells) - 1
        extra: dict[str, Any] = {"value": v0, "grid_length": grid_length, "cells": cells}
    else:
        step_len = 0.5 * res if step is None else float(step)
        tol = 0.5 * res if tolerance is None else float(tolerance)
        if not (math.isfinite(step_len) and 0 < step_len <= res):
            raise ParameterError(f"step must be in (0, resolution = {res:g}] for the gradient follower, got {step!r}")
        if not (math.isfinite(tol) and tol >= 0):
            raise ParameterError(f"tolerance must be a finite number >= 0, got {tolerance!r}")
        n_free = int(free.sum())
        max_it = int(4 * n_free * res / step_len) + 100 if max_iterations is None else int(max_iterations)
        x0, y0 = grid.origin
        gx, gy = nav.grad_x, nav.grad_y
        cpts, st, iterations = k.follow_interpolated(  # (only the order of the values matters)
            nav.value, gx, gy, free, (s[0] - x0) / res, (s[1] - y0) / res,
            (nav.goal[0] - x0) / res, (nav.goal[1] - y0) / res, step_len / res, tol / res, max_it, SQRT2)
        centres = cpts * res + np.array([x0, y0])
        status = ("reached", "local_minimum", "max_iterations")[st]
        pts = [centres] + ([nav.goal[None, :]] if st == 0 else [])
        extra = {"value": v0, "grid_length": float(np.hypot(*np.diff(centres, axis=0).T).sum()) if len(centres) > 1
                 else 0.0}
        iterations = int(iterations)
        points = np.concatenate(pts)
        keep = np.ones(len(points), bool)
        keep[1:] = np.any(np.diff(points, axis=0) != 0, axis=1)
        points = points[keep]
    seconds = time.perf_counter() - t0
    # a descent's points lie in its cell chain (start and goal in its first and last cells)
    clearance = _min_clearance(nav, points, extra["cells"] if method == "descent" else None)
    return Path(points, status, name, iterations, params, seconds, clearance, extra)


def _min_clearance(nav: NavigationField, points: NDArray[np.float64],
                   cells: NDArray[np.intp] | None = None) -> float:
    """Smallest Euclidean brushfire distance (cell centre to nearest obstacle cell centre) over the cells
    the path's points lie in; ``inf`` on a map without obstacles. A ring search around the path cells
    (cheap: a path seldom runs far from every obstacle), or the brushfire of :attr:`NavigationField.clearance`
    when that search would examine more than 8 cells per grid cell. ``cells``: the cells the points lie
    in, when the caller knows them (a descent's cell chain)."""
    if cells is None:
        cells, inside = nav.grid.world_to_cell(points)
        if not inside.any():
            return math.nan
        cells = cells[inside]
    r, c = np.ascontiguousarray(np.asarray(cells, dtype=np.int64).T)
    if "clearance" not in nav.__dict__:  # not computed yet
        # ~1-2 ns per examined cell: a budget of 8 cells per grid cell stays below a distance transform
        budget = 8 * nav.map.occupied.size + 100_000
        d = _kernels().clearance_along(nav.map.occupied, r, c, nav.grid.border == "wall", budget)
        if d >= 0:
            return float(d * nav.grid.resolution)
    return float(nav.clearance[r, c].min())


# ----------------------------------------------------------------------------------------------
# Fast marching
# ----------------------------------------------------------------------------------------------
def fmm(
    gridmap: GridMap,
    goal: ArrayLike,
    *,
    clearance_weight: float = 0.0,
    q_star: float | None = None,
    order: int = 2,
) -> NavigationField:
    """Euclidean geodesic distance to the goal cell by the fast marching method (scikit-fmm).

    The front starts at the goal cell's centre (value 0) and cannot enter obstacle cells; cells it
    never reaches get ``inf``. With ``clearance_weight > 0`` the front moves at speed
    ``1 / clearance_cost`` (the value is then a travel cost, as for :func:`wavefront`).

    Requires the optional dependency scikit-fmm (``pip install gridfield[fmm]``).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> nav = fmm(GridMap(Grid((1, 4), 0.5), np.zeros((1, 4), bool)), (0.25, 0.25))
    >>> nav.value
    array([[0. , 0.5, 1. , 1.5]])
    """
    try:
        import skfmm
    except ImportError:
        raise GridfieldError(
            "the fmm navigation function needs scikit-fmm: pip install gridfield[fmm] (or pip install scikit-fmm)"
        ) from None
    if order not in (1, 2):
        raise ParameterError(f"order must be 1 or 2, got {order!r}")
    w = _check_weight(clearance_weight)
    g, (gr, gc) = _goal_cell(gridmap, goal)
    res = gridmap.grid.resolution
    phi = np.ones(gridmap.shape)
    phi[gr, gc] = 0.0
    masked = np.ma.MaskedArray(phi, gridmap.occupied.copy())
    aux: dict[str, Any] = {}
    if w > 0:
        cost = clearance_cost(gridmap, w, q_star)
        speed = np.where(gridmap.occupied, 1.0, 1.0 / np.where(np.isfinite(cost), cost, 1.0))
        t = skfmm.travel_time(masked, speed, dx=res, order=order)
        aux["cost"] = cost
    else:
        t = skfmm.distance(masked, dx=res, order=order)
    value = np.ma.filled(np.ma.asarray(t, dtype=np.float64), np.inf)
    value[gridmap.occupied] = np.inf
    value[gr, gc] = 0.0
    params = {"clearance_weight": w, "q_star": q_star, "order": order}
    return NavigationField(gridmap, value, g, (gr, gc), "fmm", params, aux)


# ----------------------------------------------------------------------------------------------
# Harmonic potential
# ----------------------------------------------------------------------------------------------
SOLVERS = ("pcg", "scipy-cg", "spsolve")
#: Relaxation of the MIC(0) preconditioner (1 = full modification; 0 = plain IC(0)).
MIC_OMEGA = 0.99


def _solve_dirichlet(unknown: NDArray[np.bool_], one: NDArray[np.bool_], rtol: float,
                     solver: str = "pcg") -> tuple[NDArray[np.float64], int]:
    """Solve the 5-point Laplace equation on the ``unknown`` cells with value 1 on the ``one`` cells and 0
    on every other cell (and outside the grid). Returns the solution on the grid (0 elsewhere) and the
    number of conjugate-gradient iterations (0 for the direct solver).

    The system is ``A w = b`` over the unknowns in row-major order: ``A`` has 4 on the diagonal and -1
    between neighbouring unknowns (a scipy.sparse CSR matrix built from index arrays), ``b`` counts each
    unknown's neighbours in ``one``. ``solver``: ``"pcg"`` compiled conjugate gradients with a MIC(0)
    preconditioner (default); ``"scipy-cg"`` :func:`scipy.sparse.linalg.cg` with the same preconditioner;
    ``"spsolve"`` the direct :func:`scipy.sparse.linalg.spsolve` (small maps, reference).
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as sla

    rows, cols = unknown.shape
    n = int(unknown.sum())
    out = np.zeros(unknown.shape)
    if n == 0:
        return out, 0
    idx = np.full((rows + 2, cols + 2), -1, np.int64)
    idx[1:-1, 1:-1][unknown] = np.arange(n)
    left = idx[1:-1, :-2][unknown]
    right = idx[1:-1, 2:][unknown]
    down = idx[:-2, 1:-1][unknown]
    up = idx[2:, 1:-1][unknown]
    onep = np.pad(one, 1)
    b = (onep[1:-1, :-2].astype(np.float64)[unknown] + onep[1:-1, 2:][unknown] + onep[:-2, 1:-1][unknown]
         + onep[2:, 1:-1][unknown])
    nbr = np.stack([left, right, down, up])
    has = nbr >= 0
    row_i = np.concatenate([np.arange(n), np.broadcast_to(np.arange(n), nbr.shape)[has]])
    col_i = np.concatenate([np.arange(n), nbr[has]])
    vals = np.concatenate([np.full(n, 4.0), np.full(int(has.sum()), -1.0)])
    a = sp.csr_matrix((vals, (row_i, col_i)), shape=(n, n))
    k = _kernels()
    maxiter = 20 * (rows + cols) + 1000
    if solver == "pcg":
        x, its, _ = k.pcg_laplace(left, down, right, up, b, MIC_OMEGA, rtol, maxiter)
    elif solver == "scipy-cg":
        piv = k.mic0_factor(left, down, right, up, MIC_OMEGA)
        m = sla.LinearOperator((n, n), matvec=lambda r: k.mic0_apply(left, down, right, up, piv, np.ravel(r)),
                               dtype=np.float64)
        count = [0]

        def _count(_: Any) -> None:
            count[0] += 1

        x0 = k.mic0_apply(left, down, right, up, piv, b)
        x, _info = sla.cg(a, b, x0=x0, rtol=rtol, atol=0.0, M=m, maxiter=maxiter, callback=_count)
        its = count[0]
    elif solver == "spsolve":
        x = sla.spsolve(a.tocsc(), b)
        its = 0
    else:
        raise ParameterError(f"solver must be one of {SOLVERS}, got {solver!r}")
    r = a @ x - b  # (no BLAS calls here: OpenBLAS threads stall on a busy machine)
    resid = math.sqrt(float(np.sum(r * r)) / float(np.sum(b * b)))
    if not resid <= max(10 * rtol, 1e-10):
        raise GridfieldError(f"the harmonic solve ({solver}) did not converge: relative residual {resid:.2g} after "
                             f"{its} iterations (rtol {rtol:g})")
    out[unknown] = x
    return out, int(its)


def harmonic(
    gridmap: GridMap,
    goal: ArrayLike,
    *,
    tau: float = 1e-6,
    band: int | None = 64,
    rtol: float = 1e-12,
    solver: Literal["pcg", "scipy-cg", "spsolve"] = "pcg",
) -> NavigationField:
    """Harmonic navigation function: Laplace's equation with the goal at 0, obstacles and border at 1.

    Solves the 5-point discrete Laplace equation for ``w = 1 - u`` (1 at the goal cell, 0 on obstacle
    cells and outside the grid) on the free cells connected to the goal (4-connected: the cells a
    no-corner-cutting 8-connected path can reach). The sparse system (5-point Laplacian built from
    index arrays, a scipy.sparse matrix) is solved by conjugate gradients preconditioned by a modified
    incomplete Cholesky factorization, MIC(0) (compiled; ``solver="scipy-cg"`` runs
    :func:`scipy.sparse.linalg.cg` with the same preconditioner, ``"spsolve"`` the direct solver). Each
    solve is checked against the sparse matrix: relative residual at most ``max(10 * rtol, 1e-10)``.

    A discrete harmonic function has no local extrema away from its boundary values, so steepest
    descent over the neighbours reaches the goal -- in exact arithmetic. In floating point it does not:
    ``w`` decays exponentially along corridors and among clutter (by a factor of about
    ``exp(-pi * length / width)`` along a corridor), so far from the goal it drops below the solver's
    accuracy, underflows, and the field becomes numerically flat. This function therefore builds the
    field in *shells* and returns it in log scale:

    1. Shell 0 is the global solution ``w0``; its cells with ``w0 >= tau`` form the region ``S1``.
    2. Shell ``k`` solves Laplace's equation again, on the remaining reachable cells within taxicab
       distance ``band`` of the cells shell ``k - 1`` added (every remaining cell next to ``S_k`` is
       among them), with value 1 on ``S_k`` and 0 elsewhere; its cells with ``w_k >= tau`` join
       ``S_{k+1}``. Repeat until every reachable cell is in a shell.
    3. ``value = k * log(1/tau) - log(w_k)`` on shell ``k`` (0 at the goal, ``inf`` on obstacles and
       unreachable cells).

    Each shell is an exactly harmonic function of its own domain, resolved to relative accuracy, and
    every cell of shell ``k`` has a 4-neighbour of lower value (a larger ``w_k`` in the same shell, or a
    cell of an earlier shell), so the field has no local minimum other than the goal. Where ``w0`` is
    representable everywhere (small or open maps) there is one shell and ``value = -log(1 - u)``, a
    monotone function of the classic harmonic potential ``u``, which is kept in ``aux["harmonic"]``
    (``u`` of shell 0, 1 on obstacles).

    Parameters
    ----------
    gridmap : GridMap
    goal : (x, y)
    tau : float
        Smallest ``w`` trusted in a shell (default 1e-6, far above the solver's absolute error).
    band : int or None
        Width in cells of the region each continuation shell solves on (``None``: all remaining cells).
    rtol : float
        Relative residual tolerance of the conjugate-gradient solves.
    solver : {"pcg", "scipy-cg", "spsolve"}
        How each shell's linear system is solved (see above).

    Returns
    -------
    NavigationField
        ``kind="harmonic"``; ``aux`` holds ``harmonic`` (``u`` of shell 0), ``shell`` (shell index, -1
        off the field), ``shells``, ``iterations`` (CG iterations per shell) and ``seconds``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> nav = harmonic(GridMap(Grid((1, 3), 1.0), np.zeros((1, 3), bool)), (0.5, 0.5))
    >>> nav.aux["harmonic"].round(4)  # 1 - w: w = 1 at the goal, 0 beyond the border
    array([[0.    , 0.7333, 0.9333]])
    >>> bool(np.all(np.diff(nav.value[0]) > 0))
    True
    """
    from scipy import ndimage

    t0 = time.perf_counter()
    if not (isinstance(tau, int | float) and 0 < tau < 0.25):
        raise ParameterError(f"tau must be a number in (0, 0.25), got {tau!r}")
    if band is not None and (int(band) != band or band < 1):
        raise ParameterError(f"band must be a positive number of cells or None, got {band!r}")
    if not (0 < rtol < 1e-3):
        raise ParameterError(f"rtol must be in (0, 1e-3), got {rtol!r}")
    if solver not in SOLVERS:
        raise ParameterError(f"solver must be one of {SOLVERS}, got {solver!r}")
    g, (gr, gc) = _goal_cell(gridmap, goal)
    free = ~gridmap.occupied
    lab, _ = ndimage.label(free)  # 4-connected components
    reach = lab == lab[gr, gc]
    value = np.full(gridmap.shape, np.inf)
    value[gr, gc] = 0.0
    shell_of = np.full(gridmap.shape, -1, np.int32)
    shell_of[gr, gc] = 0
    inside = np.zeros(gridmap.shape, bool)
    inside[gr, gc] = True
    big_l = -math.log(tau)
    iterations: list[int] = []
    u0 = np.ones(gridmap.shape)
    u0[gr, gc] = 0.0
    shell = 0
    left = int(reach.sum()) - 1  # reachable cells not yet in a shell
    newest = (np.array([gr]), np.array([gc]))  # the cells the last shell added
    rows, cols = gridmap.shape
    while left > 0:
        if shell == 0 or band is None:
            box = (slice(None), slice(None))
            domain = reach & ~inside
        else:
            # Remaining cells next to S_k all lie next to the newest shell (the others were absorbed:
            # a cell next to the Dirichlet-1 set gets w >= 1/4), so the band around it suffices.
            rr, cc = newest
            box = (slice(max(0, int(rr.min()) - band), min(rows, int(rr.max()) + band + 1)),
                   slice(max(0, int(cc.min()) - band), min(cols, int(cc.max()) + band + 1)))
            seed = np.ones((box[0].stop - box[0].start, box[1].stop - box[1].start), bool)
            seed[rr - box[0].start, cc - box[1].start] = False
            near = ndimage.distance_transform_cdt(seed, metric="taxicab") <= band
            domain = reach[box] & ~inside[box] & near
        w, its = _solve_dirichlet(domain, inside[box], rtol, solver)
        iterations.append(its)
        if shell == 0:
            u0[domain] = 1.0 - w[domain]
        new = domain & (w >= tau)
        if not new.any():  # cannot happen: cells next to the shell have w >= 1/4
            raise GridfieldError("the harmonic shells stopped growing (the linear solve failed)")
        with np.errstate(divide="ignore"):
            value[box][new] = shell * big_l - np.log(w[new])
        shell_of[box][new] = shell
        inside[box] |= new
        nr, nc = np.nonzero(new)
        newest = (nr + (box[0].start or 0), nc + (box[1].start or 0))
        left -= len(nr)
        shell += 1
    params = {"tau": tau, "band": band, "rtol": rtol, "solver": solver}
    aux = {"harmonic": u0, "shell": shell_of, "shells": shell, "iterations": iterations,
           "seconds": time.perf_counter() - t0}
    return NavigationField(gridmap, value, g, (gr, gc), "harmonic", params, aux)


# ----------------------------------------------------------------------------------------------
# Sphere worlds (Rimon-Koditschek)
# ----------------------------------------------------------------------------------------------
def _discs_of(world_or_discs: Any) -> NDArray[np.float64]:
    """Disc obstacles as an array ``(M, 3)`` of ``(cx, cy, r)``."""
    obstacles = getattr(world_or_discs, "obstacles", None)
    if obstacles is not None:
        bad = [f"{ob.id} ({ob.kind})" for ob in obstacles if ob.kind != "circle"]
        if bad:
            raise ParameterError(
                "the sphere-world navigation function needs a world whose obstacles are all circles; "
                f"obstacle(s) {', '.join(bad)} are not"
            )
        discs = np.array([[ob.center[0], ob.center[1], ob.radius] for ob in obstacles], dtype=float)
        return discs.reshape(-1, 3)
    d = np.asarray(world_or_discs, dtype=float)
    if d.size == 0:
        return d.reshape(0, 3)
    if d.ndim != 2 or d.shape[1] != 3 or not np.all(np.isfinite(d)) or np.any(d[:, 2] <= 0):
        raise ParameterError(f"discs must be an array (M, 3) of finite (cx, cy, r > 0), got shape {d.shape}")
    return d


def _workspace(world_or_discs: Any, center: ArrayLike | None, radius: float | None) -> tuple[NDArray[np.float64], float]:
    bounds = getattr(world_or_discs, "bounds", None)
    if center is None or radius is None:
        if bounds is None:
            raise ParameterError("give workspace_center and workspace_radius (or a World, whose inscribed circle is used)")
        xmin, ymin, xmax, ymax = bounds
        center = ((xmin + xmax) / 2, (ymin + ymax) / 2) if center is None else center
        radius = min(xmax - xmin, ymax - ymin) / 2 if radius is None else radius
    c = np.asarray(center, dtype=float).reshape(-1)
    r = float(radius)
    if c.shape != (2,) or not np.all(np.isfinite(c)) or not (math.isfinite(r) and r > 0):
        raise ParameterError(f"workspace disc needs a finite centre (x, y) and radius > 0, got {center!r}, {radius!r}")
    return c, r


def _check_sphere_world(discs: NDArray[np.float64], c0: NDArray[np.float64], r0: float) -> None:
    for i, (cx, cy, r) in enumerate(discs):
        if math.hypot(cx - c0[0], cy - c0[1]) + r >= r0:
            raise ParameterError(
                f"disc obstacle {i + 1} (centre ({cx:g}, {cy:g}), radius {r:g}) is not strictly inside the "
                f"workspace disc (centre ({c0[0]:g}, {c0[1]:g}), radius {r0:g}); a sphere world needs that"
            )
    for i in range(len(discs)):
        for j in range(i + 1, len(discs)):
            if math.hypot(*(discs[i, :2] - discs[j, :2])) <= discs[i, 2] + discs[j, 2]:
                raise ParameterError(f"disc obstacles {i + 1} and {j + 1} overlap; a sphere world needs disjoint discs")


def _rk_terms(x: NDArray[np.float64], y: NDArray[np.float64], goal: NDArray[np.float64], discs: NDArray[np.float64],
              c0: NDArray[np.float64], r0: float) -> tuple[NDArray[np.float64], ...]:
    """gamma, log beta, sum(grad beta_i / beta_i) (x and y) and the free mask at points (x, y)."""
    dx, dy = x - goal[0], y - goal[1]
    gamma = dx * dx + dy * dy
    qx, qy = x - c0[0], y - c0[1]
    b0 = r0 * r0 - (qx * qx + qy * qy)
    valid = b0 > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        log_beta = np.log(np.where(valid, b0, 1.0))
        sx = -2 * qx / b0
        sy = -2 * qy / b0
        for cx, cy, r in discs:
            px, py = x - cx, y - cy
            bi = px * px + py * py - r * r
            valid = valid & (bi > 0)
            log_beta = log_beta + np.log(np.where(bi > 0, bi, 1.0))
            sx = sx + 2 * px / bi
            sy = sy + 2 * py / bi
    return gamma, log_beta, sx, sy, valid


def sphere_nav_function(
    world_or_discs: Any,
    goal: ArrayLike,
    *,
    kappa: float,
    workspace_center: ArrayLike | None = None,
    workspace_radius: float | None = None,
    grid: Grid,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rimon-Koditschek navigation function of a sphere world, at the cell centres of ``grid``.

    ``phi = gamma / (gamma**kappa + beta)**(1/kappa)`` with ``gamma = |q - goal|**2``,
    ``beta = beta_0 * prod(beta_i)``, ``beta_0 = r_0**2 - |q - c_0|**2`` (the workspace disc) and
    ``beta_i = |q - c_i|**2 - r_i**2`` (the disc obstacles). ``phi`` is 0 at the goal and 1 on every
    boundary; for ``kappa`` large enough its only minimum is the goal (the other critical points
    are saddles). Evaluated in log scale, so neither ``gamma**kappa`` nor ``beta`` overflows.

    The analytic gradient used is
    ``grad phi = phi * (beta / (gamma**kappa + beta)) * (grad gamma / gamma - (1/kappa) sum(grad beta_i / beta_i))``.

    Parameters
    ----------
    world_or_discs : World or array (M, 3)
        A world whose obstacles are all circles, or discs ``(cx, cy, r)``.
    goal : (x, y)
    kappa : float
        The exponent (> 0; the theory needs it large enough, about the number of obstacles or more).
    workspace_center, workspace_radius :
        The workspace disc; default: the circle inscribed in the world's bounds.
    grid : Grid
        Where to evaluate.

    Returns
    -------
    phi : ndarray, shape ``grid.shape``
        In [0, 1]; 1 outside the free space (inside obstacles, outside the workspace).
    grad : ndarray, shape ``(2,) + grid.shape``
        ``(d phi / dx, d phi / dy)``; 0 outside the free space.

    Examples
    --------
    >>> from gridfield.grid import Grid
    >>> phi, grad = sphere_nav_function([[0.5, 0.0, 0.2]], (-0.5, 0.0), kappa=2, workspace_center=(0, 0),
    ...                                 workspace_radius=1, grid=Grid((1, 4), 0.5, (-1, -0.25)))
    >>> phi.round(4)  # at x = -0.75, -0.25, 0.25, 0.75 (goal at -0.5, disc [0.3, 0.7])
    array([[0.0764, 0.0889, 0.9682, 0.998 ]])
    >>> grad[0].round(4)  # d phi / dx
    array([[-0.6751,  0.8091,  0.8499, -0.0312]])
    """
    discs = _discs_of(world_or_discs)
    c0, r0 = _workspace(world_or_discs, workspace_center, workspace_radius)
    k = float(kappa)
    if not (math.isfinite(k) and k > 0):
        raise ParameterError(f"kappa must be a positive number, got {kappa!r}")
    g = np.asarray(goal, dtype=float).reshape(-1)
    if g.shape != (2,) or not np.all(np.isfinite(g)):
        raise ParameterError(f"goal must be two finite numbers (x, y), got {goal!r}")
    xs, ys = grid.cell_centers()
    x, y = np.meshgrid(xs, ys)
    phi, gx, gy = _rk_phi_grad(x, y, g, discs, c0, r0, k)
    return phi, np.stack([gx, gy])


def _rk_phi_grad(x: NDArray[np.float64], y: NDArray[np.float64], goal: NDArray[np.float64], discs: NDArray[np.float64],
                 c0: NDArray[np.float64], r0: float, kappa: float) -> tuple[NDArray[np.float64], ...]:
    from scipy.special import expit

    gamma, log_beta, sx, sy, valid = _rk_terms(x, y, goal, discs, c0, r0)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_gamma = np.log(gamma)
        log_phi = log_gamma - np.logaddexp(kappa * log_gamma, log_beta) / kappa
        phi = np.exp(log_phi)
        ratio = expit(log_beta - kappa * log_gamma)  # beta / (gamma**kappa + beta)
        bx = 2 * (x - goal[0]) / gamma - sx / kappa
        by = 2 * (y - goal[1]) / gamma - sy / kappa
        gx = phi * ratio * bx
        gy = phi * ratio * by
    at_goal = gamma == 0
    phi = np.where(valid, np.where(at_goal, 0.0, phi), 1.0)
    gx = np.where(valid & ~at_goal, gx, 0.0)
    gy = np.where(valid & ~at_goal, gy, 0.0)
    return phi, gx, gy


def _follow_sphere_nav(start: NDArray[np.float64], goal: NDArray[np.float64], discs: NDArray[np.float64],
                       c0: NDArray[np.float64], r0: float, kappa: float, step: float, tolerance: float,
                       max_iterations: int, window: int) -> tuple[NDArray[np.float64], str, int]:
    """Normalized descent along -grad phi: the direction is that of the bracket in the gradient formula,
    which needs no exponentials and never underflows. Steps shrink near obstacles to half the clearance."""
    p = start.astype(float).copy()
    pts = [p.copy()]
    best = math.inf
    since = 0
    for it in range(1, max_iterations + 1):
        if math.hypot(*(p - goal)) <= tolerance:
            pts.append(goal.copy())
            return np.array(pts), "reached", it - 1
        gamma, log_beta, sx, sy, _ = _rk_terms(p[:1], p[1:], goal, discs, c0, r0)
        bx = 2 * (p[0] - goal[0]) / gamma[0] - sx[0] / kappa
        by = 2 * (p[1] - goal[1]) / gamma[0] - sy[0] / kappa
        nrm = math.hypot(bx, by)
        if not (nrm > 0 and math.isfinite(nrm)):
            return np.array(pts), "local_minimum", it - 1
        clearance = min([r0 - math.hypot(*(p - c0))] + [math.hypot(p[0] - cx, p[1] - cy) - r for cx, cy, r in discs])
        h = min(step, max(0.5 * clearance, 1e-3 * step), math.hypot(*(p - goal)))
        p = p - h * np.array([bx, by]) / nrm
        if not _rk_terms(p[:1], p[1:], goal, discs, c0, r0)[4][0]:
            pts.append(p.copy())
            return np.array(pts), "collision", it
        pts.append(p.copy())
        log_phi = math.log(gamma[0]) - np.logaddexp(kappa * math.log(gamma[0]), log_beta[0]) / kappa
        if log_phi < best - 1e-12:
            best = log_phi
            since = 0
        else:
            since += 1
            if since >= window:
                return np.array(pts), "local_minimum", it
    return np.array(pts), "max_iterations", max_iterations


#: kappa values tried, in order, when plan_sphere_nav is given none.
KAPPA_LADDER = (2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 48.0, 64.0)


def plan_sphere_nav(world: Any, start: NDArray[np.float64], goal: NDArray[np.float64], params: Mapping[str, Any]) -> Path:
    """Planner ``sphere-nav``: follow the Rimon-Koditschek navigation function of a sphere world.

    The workspace is the disc inscribed in the world's bounds (or ``params["workspace_center"]`` /
    ``params["workspace_radius"]``); every obstacle must be a circle strictly inside it, and the circles
    must be disjoint (else :class:`ParameterError`). The follower takes normalized steps along the
    analytic ``-grad phi`` (``step``, default 1/200 of the workspace radius, shortened to half the
    clearance near obstacles) until within ``tolerance`` (default ``step``) of the goal; no progress in
    ``phi`` over 200 steps is a ``local_minimum`` (``kappa`` too small). Without ``kappa`` the values
    of :data:`KAPPA_LADDER` are tried in turn and the first that reaches the goal is kept
    (``extra["kappa"]``).

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 1.5}}]})
    >>> p = plan_sphere_nav(w, np.array([2.0, 5.5]), np.array([8.0, 5.0]), {"kappa": 4})
    >>> p.status, p.end.tolist()
    ('reached', [8.0, 5.0])

    Exactly behind a disc, on the line through its centre, the descent runs into the saddle point:

    >>> plan_sphere_nav(w, np.array([2.0, 5.0]), np.array([8.0, 5.0]), {"kappa": 4}).status
    'local_minimum'
    """
    t0 = time.perf_counter()
    discs = _discs_of(world)
    c0, r0 = _workspace(world, params.get("workspace_center"), params.get("workspace_radius"))
    _check_sphere_world(discs, c0, r0)
    start = np.asarray(start, dtype=float)
    goal = np.asarray(goal, dtype=float)
    for name, p in (("start", start), ("goal", goal)):
        if not _rk_terms(p[:1], p[1:], goal, discs, c0, r0)[4][0]:
            raise GridfieldError(f"{name} ({p[0]:g}, {p[1]:g}) is not in the free space of the sphere world "
                                 f"(inside the workspace disc of radius {r0:g} and outside every disc)")
    step = float(params.get("step", r0 / 200))
    if not (math.isfinite(step) and step > 0):
        raise ParameterError(f"step must be a positive number, got {step!r}")
    tol = float(params.get("tolerance", step))
    if not (math.isfinite(tol) and tol >= 0):
        raise ParameterError(f"tolerance must be a finite number >= 0, got {tol!r}")
    max_it = int(params.get("max_iterations", 50 * int(2 * r0 / step) + 1000))
    window = int(params.get("progress_window", 200))
    kappas = [float(params["kappa"])] if params.get("kappa") is not None else list(KAPPA_LADDER)
    if not all(math.isfinite(k) and k > 0 for k in kappas):
        raise ParameterError(f"kappa must be a positive number, got {params.get('kappa')!r}")
    tried = []
    for kappa in kappas:
        pts, status, its = _follow_sphere_nav(start, goal, discs, c0, r0, kappa, step, tol, max_it, window)
        tried.append((kappa, status))
        if status == "reached":
            break
    used = dict(params)
    used["kappa"] = kappa
    clearance = float(world.distance(pts).min()) if hasattr(world, "distance") and discs.size else math.nan
    extra = {"kappa": kappa, "tried": tried, "workspace_center": c0.tolist(), "workspace_radius": r0}
    return Path(pts, status, "sphere-nav", its, used, time.perf_counter() - t0, clearance, extra)


# ----------------------------------------------------------------------------------------------
# Planner registry entry points
# ----------------------------------------------------------------------------------------------
def _common(params: Mapping[str, Any]) -> dict[str, Any]:
    return {"clearance_weight": params.get("clearance_weight", 0.0), "q_star": params.get("q_star")}


def _plan_grid(nav: NavigationField, start: NDArray[np.float64], params: Mapping[str, Any], name: str,
               field_seconds: float, method: Literal["auto", "descent", "gradient"] = "auto") -> Path:
    p = extract_path(nav, start, method=method, step=params.get("step"), tolerance=params.get("tolerance"),
                     max_iterations=params.get("max_iterations"), planner=name)
    extra = dict(p.extra)
    extra["field_seconds"] = field_seconds
    return Path(p.points, p.status, name, p.iterations, {**dict(params), **dict(nav.params)}, p.seconds,
                p.min_clearance, extra)


def plan_wavefront(gridmap: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64],
                   params: Mapping[str, Any]) -> Path:
    """Planner ``wavefront``: unit-cost wavefront (``connectivity`` 8 or 4, optional
    ``clearance_weight``/``q_star``) and the descent of :func:`extract_path`.

    ``Path.seconds`` is the path extraction; the wavefront's own time is ``extra["field_seconds"]``.

    Examples
    --------
    >>> from gridfield.grid import Grid, GridMap
    >>> m = GridMap(Grid((2, 3), 1.0), np.zeros((2, 3), bool))
    >>> plan_wavefront(m, np.array([0.5, 0.5]), np.array([2.5, 1.5]), {"connectivity": 4}).iterations
    3
    """
    t0 = time.perf_counter()
    nav = wavefront(gridmap, goal, connectivity=params.get("connectivity", 8), costs="unit", **_common(params))
    return _plan_grid(nav, start, params, "wavefront", time.perf_counter() - t0)


def plan_wavefront_octile(gridmap: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64],
                          params: Mapping[str, Any]) -> Path:
    """Planner ``wavefront-octile``: octile-cost wavefront (Moving AI metric) and its descent: a shortest
    8-connected path without corner cutting.

    Examples
    --------
    >>> from gridfield.grid import Grid, GridMap
    >>> m = GridMap(Grid((2, 3), 1.0), np.zeros((2, 3), bool))
    >>> round(plan_wavefront_octile(m, np.array([0.5, 0.5]), np.array([2.5, 1.5]), {}).length, 4)
    2.4142
    """
    t0 = time.perf_counter()
    nav = wavefront(gridmap, goal, connectivity=params.get("connectivity", 8), costs="octile", **_common(params))
    return _plan_grid(nav, start, params, "wavefront-octile", time.perf_counter() - t0)


def plan_fmm(gridmap: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64],
             params: Mapping[str, Any]) -> Path:
    """Planner ``fmm``: fast-marching geodesic distance followed along its gradient (``step``, at most
    one cell, default half a cell; ``tolerance``; ``max_iterations``; optional ``clearance_weight``/``q_star``).

    Examples
    --------
    >>> from gridfield.grid import Grid, GridMap
    >>> m = GridMap(Grid((10, 10), 1.0), np.zeros((10, 10), bool))
    >>> p = plan_fmm(m, np.array([0.5, 0.5]), np.array([9.5, 6.5]), {})
    >>> p.status, round(p.length, 1)
    ('reached', 10.8)
    """
    t0 = time.perf_counter()
    nav = fmm(gridmap, goal, **_common(params))
    if params.get("step") is not None:  # a world's step for the potential follower may exceed a cell
        params = {**params, "step": min(float(params["step"]), gridmap.grid.resolution)}
    return _plan_grid(nav, start, params, "fmm", time.perf_counter() - t0)


def plan_harmonic(gridmap: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64],
                  params: Mapping[str, Any]) -> Path:
    """Planner ``harmonic``: harmonic navigation function (:func:`harmonic`) and steepest descent over
    the 8 neighbour cells.

    Examples
    --------
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((5, 5), bool); occ[2, :4] = True
    >>> p = plan_harmonic(GridMap(Grid((5, 5), 1.0), occ), np.array([0.5, 0.5]), np.array([0.5, 4.5]), {})
    >>> p.status, bool(p.points[:, 0].max() > 4)
    ('reached', True)
    """
    t0 = time.perf_counter()
    nav = harmonic(gridmap, goal)
    return _plan_grid(nav, start, params, "harmonic", time.perf_counter() - t0, method="descent")


def navigation_field(gridmap: GridMap, goal: ArrayLike, planner_name: str,
                     params: Mapping[str, Any] | None = None) -> NavigationField:
    """The field behind a navigation-function planner (for ``gridfield field``).

    Parameters
    ----------
    gridmap : GridMap
    goal : (x, y)
    planner_name : {"wavefront", "wavefront-octile", "fmm", "harmonic", "sphere-nav"}
    params : mapping
        Planner parameters (``connectivity``, ``clearance_weight``, ``q_star``, ``kappa``); others ignored.
        ``sphere-nav`` needs the map to have been rasterized from a world of circles; without ``kappa``
        it uses the number of obstacles + 1.

    Returns
    -------
    NavigationField
        With ``potential`` (= ``value``), ``grad_x`` and ``grad_y`` arrays of the grid's shape.

    Examples
    --------
    >>> from gridfield.grid import Grid, GridMap
    >>> nav = navigation_field(GridMap(Grid((1, 3), 1.0), np.zeros((1, 3), bool)), (0.5, 0.5), "wavefront", {})
    >>> nav.potential, nav.grad_x
    (array([[0., 1., 2.]]), array([[0., 1., 1.]]))
    """
    p = dict(params or {})
    if planner_name == "wavefront":
        return wavefront(gridmap, goal, connectivity=p.get("connectivity", 8), costs="unit", **_common(p))
    if planner_name == "wavefront-octile":
        return wavefront(gridmap, goal, connectivity=p.get("connectivity", 8), costs="octile", **_common(p))
    if planner_name == "fmm":
        return fmm(gridmap, goal, **_common(p))
    if planner_name == "harmonic":
        return harmonic(gridmap, goal)
    if planner_name == "sphere-nav":
        world = gridmap.world
        if world is None:
            raise ParameterError("the sphere-nav field needs a vector world of circles; this map is a grid")
        discs = _discs_of(world)
        c0, r0 = _workspace(world, p.get("workspace_center"), p.get("workspace_radius"))
        _check_sphere_world(discs, c0, r0)
        g = np.asarray(goal, dtype=float).reshape(-1)
        cast(Any, world).check_point("goal", g)  # GridMap.world is typed object (no import cycle)
        kappa = float(p.get("kappa", len(discs) + 1))
        phi, grad = sphere_nav_function(discs, g, kappa=kappa, workspace_center=c0, workspace_radius=r0,
                                        grid=gridmap.grid)
        (gr, gc), = gridmap.grid.world_to_cell(g)[0]
        return NavigationField(gridmap, phi, g, (int(gr), int(gc)), "sphere-nav",
                               {"kappa": kappa, "workspace_center": c0.tolist(), "workspace_radius": r0},
                               {"grad_x": grad[0], "grad_y": grad[1]})
    raise ParameterError(
        f"unknown navigation planner {planner_name!r}; expected one of wavefront, wavefront-octile, fmm, harmonic, sphere-nav"
    )

