"""The navigation field object and what every construction shares.

:class:`NavigationField` is the one result type of the navigation functions (:mod:`gridfield.fields.navigation`):
the value array on its grid, plus the construction's parameters and extra arrays. It lives apart from
the constructions so that each of them (wavefront, fmm, harmonic, sphere worlds, star worlds)
depends on this module, not on the others (fmm borrows only the wavefront's :func:`clearance_cost`, star
worlds only the sphere world's terms). Also here: the upwind gradient of a
distance-like array, :func:`extract_path` (the compiled descent and gradient followers, the same for
every grid field), the input checks the constructions share, and the adapter that turns a field and a
start into a planner's :class:`~gridfield.core.path.Path`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core.errors import ParameterError
from ...core.grid import Grid, GridMap
from ...core.params import Navigation, Repulsion, validate
from ...core.path import NavigationAux, Path

#: The kinds of :class:`NavigationField`.
KINDS = ("wavefront", "fmm", "harmonic", "sphere-nav", "navfn")  # navfn: gridfield.fields.navfn (Nav2's NavFn)
COSTS = ("unit", "octile")
SQRT2 = math.sqrt(2.0)


def _kernel_navigation() -> Any:
    """The compiled kernel module (gridfield/fields/_navigation.pyx), imported on first use."""
    from .. import _navigation  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _navigation


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
    navigation field can stand where a :class:`gridfield.fields.potential.Field` is expected.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.fields.navigation import wavefront
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
    goal_cell: tuple[int, ...]
    kind: str
    params: Mapping[str, Any] = field(default_factory=dict)
    aux: NavigationAux | Mapping[str, Any] = field(default_factory=dict)  # keys: path.NavigationAux

    def __repr__(self) -> str:
        reach = int(np.count_nonzero(self.reachable))
        return (f"NavigationField(kind={self.kind!r}, shape={self.map.grid.shape}, "
                f"goal=({float(self.goal[0]):.6g}, {float(self.goal[1]):.6g}), reachable cells={reach})")

    @property
    def grid(self) -> Grid:
        return self.map.grid

    @property
    def potential(self) -> NDArray[np.float64]:
        """The value array (the name :class:`gridfield.fields.potential.Field` uses)."""
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
        from ...distance.brushfire import brushfire

        return brushfire(self.map, metric="euclidean").distance

    def to_field(self) -> Any:
        """The same arrays as a :class:`gridfield.fields.potential.Field` (for its follower and plots)."""
        from ...core.results import Field

        return Field(self.map, self.value, self.grad_x, self.grad_y, (float(self.goal[0]), float(self.goal[1])),
                     {"navigation": self.kind, **dict(self.params)})

    def min_clearance(self, points: ArrayLike) -> float:
        """Smallest Euclidean brushfire distance (cell centre to the nearest obstacle cell centre) over
        the cells the points lie in (:attr:`Path.min_clearance` of a path on this field).

        Parameters
        ----------
        points : array_like, shape (n, 2)
            World points (those outside the grid are left out; NaN when none is inside).

        Returns
        -------
        float
            In world units; ``inf`` on a map without obstacles.

        Examples
        --------
        >>> import numpy as np
        >>> from gridfield.core.grid import Grid, GridMap
        >>> from gridfield.fields.navigation import wavefront
        >>> nav = wavefront(GridMap(Grid((1, 4), 1.0), np.array([[False, False, True, False]])), (0.5, 0.5))
        >>> nav.min_clearance([[0.5, 0.5], [1.5, 0.5]])
        1.0
        """
        return _min_clearance(self, np.asarray(points, dtype=float).reshape(-1, 2))

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
def _goal_cell(gridmap: GridMap, goal: ArrayLike) -> tuple[NDArray[np.float64], tuple[int, ...]]:
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
    from ...core.params import REGISTRY

    most = REGISTRY["clearance_weight"].maximum  # the bucket queue of the weighted wavefront grows with w
    if most is not None and w > most:
        raise ParameterError(f"clearance_weight must be at most {most:g}, got {clearance_weight!r}")
    return w


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
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.fields.navigation import wavefront
    >>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
    >>> nav = wavefront(GridMap(Grid((3, 3), 1.0), occ), (0.5, 0.5), costs="octile")
    >>> p = extract_path(nav, (2.5, 2.5))
    >>> p.status, p.extra["value"], p.extra["grid_length"]
    ('reached', 4.0, 4.0)
    >>> p.points.tolist()
    [[2.5, 2.5], [2.5, 1.5], [2.5, 0.5], [1.5, 0.5], [0.5, 0.5]]
    """
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
    k = _kernel_navigation()
    free = ~gm.occupied
    conn = int(nav.params.get("connectivity", 8))
    if method == "descent":
        cost = nav.aux.get("cost")
        cost_arr = np.where(free, cost, 1.0) if cost is not None else np.empty((0, 0))
        diag = SQRT2 if nav.params.get("costs", "octile") == "octile" or nav.kind != "wavefront" else 1.0
        mode = 0 if nav.kind == "wavefront" else 1
        cells, reached = k.descend(nav.value, free, cost_arr, sr, sc, conn, diag, mode, res, gm.diagonals)
        x0, y0 = grid.origin
        points, grid_length = k.chain_points(cells, s[0], s[1], nav.goal[0], nav.goal[1], reached,
                                             x0, y0, res, SQRT2)
        status = "reached" if reached else "local_minimum"
        iterations = len(cells) - 1
        extra: dict[str, Any] = {"value": v0, "grid_length": grid_length, "cells": cells}
        params["method"] = "descent"
        if not reached:  # a numerically flat spot (harmonic fields): finish on the wavefront from there
            finish = _finish_on_wavefront(nav, points[-1])  # (the last cell's centre: no goal appended)
            if finish is not None:
                points = np.concatenate([points, finish.points[1:]])
                cells = np.concatenate([cells, np.asarray(finish.extra["cells"])[1:]])
                extra.update(cells=cells, finished_by="wavefront",
                             grid_length=grid_length + float(finish.extra["grid_length"]))
                status = "reached"
                iterations = len(cells) - 1
            else:
                extra["reason"] = "the descent found a flat spot and no free path leads from there to the goal"
    else:
        step_len = 0.5 * res if step is None else float(step)
        tol = 0.5 * res if tolerance is None else float(tolerance)
        if not (math.isfinite(step_len) and 0 < step_len <= res):
            raise ParameterError(f"step must be in (0, resolution = {res:g}] for the gradient follower, got {step!r}")
        if not (math.isfinite(tol) and tol >= 0):
            raise ParameterError(f"tolerance must be a finite number >= 0, got {tolerance!r}")
        n_free = int(free.sum())
        # a step below 1/1000 cell gets the budget of 1/1000 cell (a tiny step would overflow the count)
        budget = min(4 * n_free * res / step_len, 4000.0 * n_free)
        max_it = int(budget) + 100 if max_iterations is None else int(max_iterations)
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
        params.update(method="gradient", step=step_len, tolerance=tol, max_iterations=max_it)
        if st == 1:  # a flat spot of the interpolated field (no lower neighbour cell): finish on the wavefront
            finish = _finish_on_wavefront(nav, centres[-1])
            if finish is not None:
                pts = [centres, finish.points[1:]]
                extra["grid_length"] += float(finish.extra["grid_length"])
                status = "reached"
                iterations += finish.iterations
                extra["finished_by"] = "wavefront"
            else:
                extra["reason"] = (f"the fast-marching field is flat at ({centres[-1][0]:.4g}, {centres[-1][1]:.4g}) "
                                   "and no free path leads from there to the goal")
        points = np.concatenate(pts)
        keep = np.ones(len(points), bool)
        keep[1:] = np.any(np.diff(points, axis=0) != 0, axis=1)
        points = points[keep]
    seconds = time.perf_counter() - t0
    # a descent's points lie in its cell chain (start and goal in its first and last cells)
    clearance = _min_clearance(nav, points, extra["cells"] if method == "descent" else None)
    return Path(points, status, name, iterations, params, seconds, clearance, extra)


def _finish_on_wavefront(nav: NavigationField, point: NDArray[np.float64]) -> Path | None:
    """The octile wavefront's descent from ``point`` to ``nav``'s goal (a grid navigation function: no
    flat spot), or None when the goal cannot be reached from there. Used where a follower of a
    fast-marching or harmonic field stops short of the goal."""
    grid = nav.map.grid
    stop = grid.cell_of(float(point[0]), float(point[1]))
    if stop is None:
        return None
    # what _wavefront.wavefront(nav.map, nav.goal, costs="octile", stop_at=point) builds, from the kernel
    # itself: _wavefront builds on this module, so importing it here would tie the two both ways
    g, (gr, gc) = _goal_cell(nav.map, nav.goal)
    value = _kernel_navigation().wavefront_uniform(~nav.map.occupied, gr, gc, 8, SQRT2, int(stop[0]), int(stop[1]),
                                                   grid.resolution, nav.map.diagonals)
    wf = NavigationField(nav.map, value, g, (gr, gc), "wavefront",
                         {"connectivity": 8, "costs": "octile", "clearance_weight": 0.0, "q_star": None}, {})
    p = extract_path(wf, point, method="descent")
    return p if p.status == "reached" else None


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
        d = _kernel_navigation().clearance_along(nav.map.occupied, r, c, nav.grid.border == "wall", budget)
        if d >= 0:
            return float(d * nav.grid.resolution)
    return float(nav.clearance[r, c].min())


# ----------------------------------------------------------------------------------------------
# The planner adapter every grid construction shares
# ----------------------------------------------------------------------------------------------
def grid_options(params: Mapping[str, Any]) -> dict[str, Any]:
    """The keyword options of :func:`wavefront` and :func:`fmm` that a planner's parameters set.

    Parameters
    ----------
    params : mapping
        Planner parameters (checked by the registry).

    Returns
    -------
    dict
        ``clearance_weight`` and ``q_star``.

    Examples
    --------
    >>> grid_options({"q_star": 2.0})
    {'clearance_weight': 0.0, 'q_star': 2.0}
    """
    p = validate(params)
    return {"clearance_weight": p.group(Navigation).clearance_weight, "q_star": p.group(Repulsion).q_star}


def _plan_grid(nav: NavigationField, start: NDArray[np.float64], params: Mapping[str, Any], name: str,
               field_seconds: float, method: Literal["auto", "descent", "gradient"] = "auto") -> Path:
    p = extract_path(nav, start, method=method, step=params.get("step"), tolerance=params.get("tolerance"),
                     max_iterations=params.get("max_iterations"), planner=name)
    extra = dict(p.extra)
    extra["field_seconds"] = field_seconds
    extra["build_seconds"] = field_seconds  # planners.plan reports it as the query's field_seconds
    # the parameters it ran with: the given ones, the field's and the follower's (method, step, tolerance, ...)
    return Path(p.points, p.status, name, p.iterations, {**dict(params), **dict(p.params)}, p.seconds,
                p.min_clearance, extra)
