"""The convergence study: a grid planner at several resolutions against an exact planner
(:func:`convergence_study`), its error columns (:func:`study_errors`) and their observed orders
(:func:`study_orders`). Part of :mod:`gridfield.compare` (import the names from there)."""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..core.errors import GridfieldError, ParameterError, check_positive
from ..core.path import Path
from ..geometry.world import World
from ._common import _as_world, _grid_factor, _guard_seconds, _optimum
from ._metrics import (
    collides,
    discrete_frechet,
    end_error,
    hausdorff,
    length_ratio,
    min_clearance,
    observed_order,
    status_agreement,
)

#: Keys of every row of :func:`convergence_study`, in table order.
STUDY_COLUMNS = (
    "resolution", "cells", "build_ms", "plan_ms", "status", "exact_status", "status_agree", "length",
    "exact_length", "optimal_length", "length_ratio", "length_ratio_optimal", "hausdorff", "frechet",
    "end_error", "min_clearance", "collides",
)
#: Error columns whose convergence :func:`observed_order` is reported for.
ERROR_COLUMNS = ("hausdorff", "frechet", "end_error", "length_error")


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
        # a run that found no path (its one point, the start) has no length to compare
        "length_ratio": length_ratio(grid, exact.length) if grid.status != "no_path" else math.nan,
        # a path that did not reach the goal has no meaningful ratio to the optimum
        "length_ratio_optimal": length_ratio(grid, optimal) if grid.reached else math.nan,
        "hausdorff": hausdorff(grid, exact, spacing=spacing),
        "frechet": discrete_frechet(grid, exact, spacing=spacing),
        "end_error": end_error(grid, exact),
        # nor a clearance: its one point is the start, whose clearance says nothing of a path
        "min_clearance": min_clearance(world, grid) if grid.status != "no_path" else math.nan,
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

    On a grid map (a :class:`~gridfield.core.grid.GridMap` without a vector world) the exact planner
    runs on the map's blocked cells as exact polygons (:func:`gridfield.geometry.gridpoly.grid_world`) and
    the grid planner on the map itself at its resolution, on block-downsampled copies
    (:func:`gridfield.geometry.gridpoly.block_downsample`, conservative) at coarser resolutions, which
    must be multiples of the map's, and on subdivided copies (:func:`gridfield.geometry.gridpoly.subdivide`,
    the same free space) at finer ones, which must be the map's divided by an integer. A resolution at which the start or goal, free in the world, falls
    in a blocked (coarse) cell is skipped: its row has status ``"skipped: ..."`` saying which point
    and NaN metrics; any other failure of the grid planner gives status ``"error: ..."``.

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
        against the world; NaN when the grid planner found no path, as ``length_ratio``) and ``collides``.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})
    >>> rows = convergence_study(w, [1, 5], [9, 5], [1.0, 0.5], grid_planner="visibility",
    ...                          exact_planner="visibility")
    >>> [(r["resolution"], r["status"], r["hausdorff"]) for r in rows]
    [(1.0, 'reached', 0.0), (0.5, 'reached', 0.0)]
    """
    from ..geometry.rasterize import rasterize
    from ..planners import get_planner, plan

    _guard_seconds(world, exact_planner, params, f"compare {exact_planner} on {getattr(world, 'source', None) or 'the map'}")
    world, base = _as_world(world, "convergence_study")
    hs = [check_positive("resolution", r) for r in resolutions]
    if not hs:
        raise ParameterError("give at least one resolution")
    from ..core.grid import Grid

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
        from ..geometry.gridpoly import block_downsample, subdivide

        return block_downsample(base, factors[i]) if factors[i] > 0 else subdivide(base, -factors[i])

    if kind_grid == "grid":  # untimed warm-up: first-call costs (imports, caches)
        with contextlib.suppress(GridfieldError):
            plan(grid_planner, grid_at(int(np.argmax(hs))), s, g, params)
    rows = []
    for i, h in enumerate(hs):
        t0 = time.perf_counter()
        gm = grid_at(i)
        raster_s = time.perf_counter() - t0
        blocked = [name for name, point in (("start", s), ("goal", g)) if not bool(gm.is_free([point])[0])]
        if kind_grid == "grid" and blocked:  # unusable here: its cell is blocked at this resolution
            where = " and ".join(f"the {n}'s cell" for n in blocked) + (" are" if len(blocked) > 1 else " is")
            row: dict[str, Any] = {"resolution": h, "cells": int(gm.grid.rows * gm.grid.cols),
                                   "build_ms": 1e3 * raster_s, "plan_ms": math.nan}
            row.update(_error_row(f"skipped: {where} blocked at this resolution (every cell an obstacle "
                                  "touches is occupied)"))
            row["exact_status"], row["exact_length"], row["optimal_length"] = exact.status, exact.length, optimal
            rows.append({k: row[k] for k in STUDY_COLUMNS})
            continue
        # a world planner on the grid side only tests the plumbing
        try:
            path = plan(grid_planner, gm if kind_grid == "grid" else world, s, g, params)
        except GridfieldError as e:
            row = {"resolution": h, "cells": int(gm.grid.rows * gm.grid.cols),
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


def no_path_at_resolution(row: Mapping[str, Any]) -> bool:
    """Whether a convergence-study row's grid run found no path where the exact planner found one
    (the grid, conservative at that resolution, closes the way the exact planner takes).

    Parameters
    ----------
    row : mapping
        A row of :func:`convergence_study` (``status`` and ``exact_status``).

    Returns
    -------
    bool

    Examples
    --------
    >>> no_path_at_resolution({"status": "no_path", "exact_status": "reached"})
    True
    >>> no_path_at_resolution({"status": "no_path", "exact_status": "no_path"})
    False
    """
    return row.get("status") == "no_path" and row.get("exact_status") not in ("no_path", "", None)


def study_errors(rows: Sequence[Mapping[str, Any]]) -> dict[str, list[float]]:
    """The error columns (:data:`ERROR_COLUMNS`) of convergence-study rows.

    ``length_error`` is ``|length_ratio - 1|`` (grid length against the exact planner's) where both
    planners reached the goal, NaN elsewhere: a stalled follower's path length depends on when its
    oscillation was detected, not on the field's accuracy. A row whose grid run found no path where
    the exact planner found one (:func:`no_path_at_resolution`: the coarse, conservative grid closes
    the way) has NaN errors: its start-only "path" measures no discretization error.

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
    closed = [no_path_at_resolution(r) for r in rows]
    return {
        "hausdorff": [math.nan if c else float(r["hausdorff"]) for r, c in zip(rows, closed, strict=True)],
        "frechet": [math.nan if c else float(r["frechet"]) for r, c in zip(rows, closed, strict=True)],
        "end_error": [math.nan if c else float(r["end_error"]) for r, c in zip(rows, closed, strict=True)],
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
