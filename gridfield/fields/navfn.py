"""Nav2's NavFn planner on a costmap: its navigation function (potential) and gradient path.

The rules are those of ROS 2 Nav2's ``nav2_navfn_planner`` (``navfn.cpp``, ``navfn_planner.cpp``;
Brock and Konolige's navigation function), computed by gridfield's own kernel
(``gridfield.fields._navfn``):

- cell cost ``COST_NEUTRAL + COST_FACTOR * cost`` = ``50 + 0.8 * cost`` (truncated) for costmap costs
  below 253; lethal (254) and inscribed (253) cells are blocked (NavFn's 254), unknown cells (255)
  cost 253 with ``allow_unknown`` (Nav2's default) and are blocked without; the grid's outer ring is
  blocked, and the start cell is cleared to cost 0 first (``clearRobotCell``);
- a Dijkstra propagation in float32 from the *start* (as ``NavfnPlanner`` does), with NavFn's
  planar-wave update from the lower neighbour of each axis (``ta + hf * (-0.2301 r^2 + 0.5307 r +
  0.7040)``, ``r = |tc - ta| / hf``, or ``ta + hf`` when ``|tc - ta| >= hf``), its three priority
  blocks of at most 10000 cells and its threshold step of 100, stopped once the goal has a potential;
- with an unreachable goal, the nearest reachable point of the square ``goal +- goal_tolerance``
  scanned in resolution steps (NavFn's ``tolerance``, default 0.5);
- the path from the goal down the potential: half-cell steps along the bilinear interpolation of the
  normalized four-neighbour gradients, stepping to the lowest of the 8 neighbours next to unassigned
  cells or on an oscillation (``calcPath``), at most ``4 * max(rows, cols)`` steps; reversed, so it
  runs from the start to the goal.

gridfield's cell convention is kept: a world point is in the cell that contains it and a path point
``(x, y)`` in cells is at ``origin + (x + 0.5, y + 0.5) * resolution`` (Nav2's ``NavfnPlanner`` rounds
``(w - origin) / resolution`` instead and maps back without the half cell; the cells and the path in
cells are the same). A* (``use_astar``) is not implemented.

:func:`navfn` gives the potential from a goal as a :class:`~gridfield.fields.navigation.NavigationField`
(``kind="navfn"``; the propagation runs over the whole map), :func:`plan_navfn` is the ``navfn``
planner.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ..core.params import NavFn, validate
from ..core.path import Path
from .costmap import Costmap, inflate

__all__ = ["COST_FACTOR", "COST_NEUTRAL", "POT_HIGH", "navfn", "navfn_costs", "plan_navfn"]

COST_NEUTRAL = 50
COST_FACTOR = 0.8
COST_OBS = 254
POT_HIGH = np.float32(1.0e10)
#: Nav2's ``max_cycles_factor`` default: the path may take ``4 * max(rows, cols)`` steps.
MAX_CYCLES_FACTOR = 4


def _kernels() -> Any:
    """The compiled kernel module (gridfield/fields/_navfn.pyx), imported on first use."""
    from . import _navfn  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _navfn


def _as_costmap(target: GridMap, options: NavFn, cache: dict[Any, Any] | None = None) -> Costmap:
    if isinstance(target, Costmap):
        return target
    if not isinstance(target, GridMap):
        raise ParameterError(f"navfn plans on a GridMap or a Costmap, got {type(target).__name__}")
    key = ("navfn-costmap", options.robot_radius, options.inflation_radius, options.cost_scaling_factor,
           options.lut_precision)
    if cache is not None and key in cache:
        cm: Costmap = cache[key]
        return cm
    cm = inflate(target, robot_radius=options.robot_radius, inflation_radius=options.inflation_radius,
                 cost_scaling_factor=options.cost_scaling_factor, lut_precision=options.lut_precision)
    if cache is not None:
        cache[key] = cm
    return cm


def navfn_costs(costmap: Costmap, *, allow_unknown: bool = True,
                clear: tuple[int, ...] | None = None) -> NDArray[np.uint8]:
    """NavFn's cost array of a costmap (``setCostmap`` then ``setupNavFn``'s blocked outer ring).

    Parameters
    ----------
    costmap : Costmap
    allow_unknown : bool
        Unknown cells (255) cost 253 (traversable) instead of blocked.
    clear : (row, col), optional
        A cell set to free space first (``clearRobotCell``: the planner's start).

    Returns
    -------
    ndarray of uint8, shape ``costmap.shape``
        ``50 + int(0.8 * cost)`` below 253, 253 for allowed unknown cells, 254 blocked.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> cm = Costmap.from_costs(Grid((3, 4), 1.0), np.array([[0, 0, 0, 0], [0, 100, 255, 0], [0, 0, 0, 0]], np.uint8))
    >>> navfn_costs(cm)[1].tolist(), navfn_costs(cm, allow_unknown=False)[1].tolist()
    ([254, 130, 253, 254], [254, 130, 254, 254])
    """
    r, c = clear if clear is not None else (-1, -1)
    out: NDArray[np.uint8] = _kernels().navfn_costs(np.ascontiguousarray(costmap.cost), bool(allow_unknown),
                                                    int(r), int(c))
    return out


def _cycles(rows: int, cols: int) -> int:
    return max(rows * cols // 20, rows + cols)


def _allow(options: NavFn) -> bool:
    return options.allow_unknown == "true"


def navfn(target: GridMap, goal: ArrayLike, *, params: Mapping[str, Any] | None = None) -> Any:
    """NavFn's potential from ``goal`` over the whole map, as a navigation field.

    Parameters
    ----------
    target : GridMap or Costmap
        A costmap's costs are used as they are; an occupancy map is inflated first (the costmap
        parameters of ``params``).
    goal : (x, y)
        World point in a cell NavFn does not block.
    params : mapping, optional
        The ``navfn`` parameters (:class:`gridfield.core.params.NavFn`).

    Returns
    -------
    NavigationField
        ``kind="navfn"``; ``value`` the potential (float32 values, in NavFn's cost units: 50 a free
        cell), ``inf`` where unassigned; ``map`` the costmap; ``aux["cost"]`` NavFn's cost array (as floats).

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> cm = Costmap.from_costs(Grid((3, 5), 1.0), np.zeros((3, 5), np.uint8))
    >>> navfn(cm, (1.5, 1.5)).value[1].tolist()
    [inf, 0.0, 50.0, 100.0, inf]
    """
    from .navigation import NavigationField

    p = validate(params)
    opts = p.group(NavFn)
    cm = _as_costmap(target, opts)
    g = np.asarray(goal, dtype=np.float64).reshape(-1)
    cell = cm.grid.cell_of(float(g[0]), float(g[1])) if g.size == 2 else None
    if cell is None:
        raise ParameterError(f"goal must be a point (x, y) inside the map, got {goal!r}")
    rows, cols = cm.shape
    t0 = time.perf_counter()
    cost = navfn_costs(cm, allow_unknown=_allow(opts), clear=cell)
    if cost[cell] >= COST_OBS:
        raise ParameterError(f"goal ({g[0]:g}, {g[1]:g}) lies in a cell NavFn blocks (the map's outer ring)")
    idx = cell[0] * cols + cell[1]
    pot, cycles, _ = _kernels().propagate(cost.reshape(-1), cols, rows, idx, idx, False, _cycles(rows, cols))
    value = pot.reshape(rows, cols).astype(np.float64)
    value[pot.reshape(rows, cols) >= POT_HIGH] = np.inf
    return NavigationField(cm, value, g, cell, "navfn", {"allow_unknown": opts.allow_unknown},
                           {"cost": cost.astype(np.float64), "iterations": int(cycles),
                            "seconds": time.perf_counter() - t0})


def _tolerance_goal(pot: NDArray[np.float32], cm: Costmap, goal: NDArray[np.float64],
                    tolerance: float) -> tuple[NDArray[np.float64], tuple[int, int]] | None:
    """NavfnPlanner's search of the square ``goal +- tolerance`` (resolution steps, y outer, x inner) for the
    reachable point nearest the goal (first found on a tie); ``None`` when there is none."""
    res = cm.grid.resolution
    gx, gy = float(goal[0]), float(goal[1])

    def axis(c: float) -> NDArray[np.float64]:
        # the loop's own accumulation p += resolution, while p <= c + tolerance
        n = int(math.floor(2 * tolerance / res)) + 3
        vals = np.add.accumulate(np.concatenate([[c - tolerance], np.full(n, res)]))
        return vals[vals <= c + tolerance]

    ys, xs = axis(gy), axis(gx)
    if not len(ys) or not len(xs):
        return None
    py, px = np.meshgrid(ys, xs, indexing="ij")
    pts = np.stack([px.ravel(), py.ravel()], axis=1)
    cells, inside = cm.grid.world_to_cell(pts)
    ok = inside.copy()
    r, c = cells[inside].T
    ok[inside] = pot.reshape(cm.shape)[r, c] < POT_HIGH
    if not ok.any():
        return None
    d2 = (pts[:, 0] - gx) ** 2 + (pts[:, 1] - gy) ** 2
    d2 = np.where(ok, d2, np.inf)
    k = int(np.argmin(d2))  # the first of the smallest, as the loop's strict '<'
    return pts[k], (int(cells[k, 0]), int(cells[k, 1]))


def plan_navfn(target: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64], params: Mapping[str, Any],
               *, cache: dict[Any, Any] | None = None) -> Path:
    """Planner ``navfn``: Nav2's NavFn on the map's costmap (see the module docstring).

    Parameters
    ----------
    target : GridMap or Costmap
        A :class:`~gridfield.fields.costmap.Costmap` (e.g. read from ``gridfield costmap``'s YAML) is planned
        on with its costs; an occupancy map is inflated first (``robot_radius``, ``inflation_radius``,
        ``cost_scaling_factor``, ``lut_precision``; cached in ``cache``).
    start, goal : ndarray, shape (2,)
        World points.
    params : mapping
        ``allow_unknown``, ``goal_tolerance`` and the costmap options.
    cache : dict, optional
        Per-map work kept across calls (the inflated costmap).

    Returns
    -------
    Path
        ``points``: the start, NavFn's path (cell centres and gradient steps) and the goal;
        ``status`` ``"reached"``, ``"no_path"`` (the goal is unreachable, or NavFn's path extraction
        failed: ``extra["reason"]``) or ``"local_minimum"`` (the goal unreachable, the path ends at the
        nearest reachable point within ``goal_tolerance``); ``extra["value"]`` the potential at the goal.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((20, 20), bool); occ[5:15, 9:11] = True
    >>> p = plan_navfn(GridMap(Grid((20, 20), 0.1), occ), np.array([0.55, 1.05]), np.array([1.75, 1.05]), {})
    >>> p.status, p.points[0].tolist(), p.points[-1].tolist()
    ('reached', [0.55, 1.05], [1.75, 1.05])
    """
    params = validate(params)
    opts = params.group(NavFn)
    t0 = time.perf_counter()
    cm = _as_costmap(target, opts, cache)
    grid = cm.grid
    rows, cols = cm.shape
    s = np.asarray(start, dtype=np.float64).reshape(-1)
    g = np.asarray(goal, dtype=np.float64).reshape(-1)
    s_cell = grid.cell_of(float(s[0]), float(s[1]))
    g_cell = grid.cell_of(float(g[0]), float(g[1]))
    if s_cell is None or g_cell is None:
        raise ParameterError("navfn: the start and the goal must lie inside the map")
    k = _kernels()
    cost = navfn_costs(cm, allow_unknown=_allow(opts), clear=s_cell)
    s_idx = s_cell[0] * cols + s_cell[1]
    g_idx = g_cell[0] * cols + g_cell[1]
    pot, cycles, _ = k.propagate(cost.reshape(-1), cols, rows, s_idx, g_idx, True, _cycles(rows, cols))
    field_seconds = time.perf_counter() - t0
    out_params = {**dict(params), "costmap": dict(cm.inflation)}
    best: tuple[NDArray[np.float64], tuple[int, ...]] | None
    best = (g, g_cell) if pot[g_idx] < POT_HIGH else _tolerance_goal(pot, cm, g, opts.goal_tolerance)
    if best is None:
        return Path(s[None, :], "no_path", "navfn", int(cycles), out_params, time.perf_counter() - t0,
                    extra={"value": math.inf, "reason": "the goal is unreachable from the start (NavFn's potential "
                           "never reaches it, nor any point within goal_tolerance)", "field_seconds": field_seconds})
    end, end_cell = best
    max_steps = max(rows, cols) * MAX_CYCLES_FACTOR
    cells, status = k.gradient_path(pot, cols, rows, end_cell[1], end_cell[0], s_cell[1], s_cell[0], max_steps)
    if status != 0:
        why = {1: "the path left the map", 2: "the path met an unassigned potential", 3: "zero gradient",
               4: f"out of steps ({max_steps})"}[int(status)]
        return Path(s[None, :], "no_path", "navfn", int(cycles), out_params, time.perf_counter() - t0,
                    extra={"value": float(pot[g_idx]), "reason": f"NavFn's path extraction failed: {why}",
                           "field_seconds": field_seconds})
    x0, y0 = grid.origin
    res = grid.resolution
    pts = (cells[::-1].astype(np.float64) + 0.5) * res + np.array([x0, y0])
    # Nav2's smoothApproachToGoal: the goal replaces the last point when it lies nearer the one before
    if len(pts) >= 2 and (np.sum((pts[-1] - pts[-2]) ** 2) > np.sum((end - pts[-2]) ** 2)
                          or np.sum((pts[-1] - end) ** 2) < 1e-6 * res * res):
        pts[-1] = end
    else:
        pts = np.vstack([pts, end])
    points = np.vstack([s, pts])
    keep = np.ones(len(points), bool)
    keep[1:] = np.any(np.diff(points, axis=0) != 0, axis=1)
    points = points[keep]
    at_goal = end is g
    extra: dict[str, Any] = {"value": float(pot[g_idx]) if at_goal else math.inf,
                             "grid_length": float(np.hypot(*np.diff(cells, axis=0).T.astype(np.float64)).sum() * res),
                             "field_seconds": field_seconds}
    if not at_goal:
        extra["reason"] = (f"the goal is unreachable; NavFn's goal_tolerance ({opts.goal_tolerance:g}) chose "
                           f"({end[0]:.6g}, {end[1]:.6g})")
    clearance = _clearance(cm, points)
    return Path(points, "reached" if at_goal else "local_minimum", "navfn", len(cells), out_params,
                time.perf_counter() - t0, clearance, extra)


def _clearance(cm: Costmap, points: NDArray[np.float64]) -> float:
    """Smallest exact distance of the path's cells to a blocked cell of the costmap (``cost >= 253``)."""
    from .navigation import NavigationField

    return NavigationField(cm, np.zeros(cm.shape), points[-1], (0, 0), "navfn").min_clearance(points)
