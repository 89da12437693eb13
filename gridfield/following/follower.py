"""The grid follower: follow a Field from one start or many, and the ``potential`` planner.

:func:`follow` runs the follower's rules (:func:`gridfield.following.descent.descend`, the specification:
step rules, stop rules, escapes) on a :class:`~gridfield.fields.potential.Field` sampled by
:mod:`gridfield.fields.sampling`; :func:`follow_many` runs the same rules vectorized over many starts and
is tested equal to it; :func:`plan_potential` builds the field, follows it and pulls an ``nf1`` path
taut (:mod:`gridfield.following.taut`). The vortex field's
nearest-node follower (steps scaled by the force arrays' norms) is set up by :mod:`gridfield.fields.vortex`.

The follower's loops (:func:`follow`, :func:`follow_many` and :func:`resolve_follow_params`) are
written in the private ``gridfield.following._follow``; this module is their public home and adds
the planner (:func:`plan_potential`, :func:`plan_potential_with_field`, :func:`descend_cells`).
The names that moved out of this module (``descend``, the samplers, ``basins``) are still
importable from here.

Examples
--------
A quadratic bowl ``U = |x - g|^2 / 2`` on an empty 8 x 8 grid:

>>> from types import SimpleNamespace
>>> from gridfield.core.grid import Grid
>>> g = Grid((8, 8), 1.0)
>>> X, Y = np.meshgrid(*g.cell_centers())
>>> f = SimpleNamespace(map=GridMap(g, np.zeros(g.shape, bool)), grad_x=X - 6.5, grad_y=Y - 6.5,
...                     goal=(6.5, 6.5), potential=None, params={}, distance=None)
>>> p = follow(f, (1.5, 1.5))
>>> p.status, p.end.tolist()
('reached', [6.5, 6.5])
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.coords import as_xy
from ..core.grid import GridMap
from ..core.params import validate
from ..core.path import Path
from ..core.results import GradientField
from ..fields.sampling import (
    SAMPLINGS,
    attraction_force,
    distance_at,
    grid_blocked,
    grid_potential_sampler,
    grid_sampler,
    sample_force,
)
from ._follow import _note_outside, follow, follow_many, resolve_follow_params

# not used here, importable from here as before the split (tests/test_follower_registry.py)
from ._follow import _setup as _setup
from .basins import Basins, basins, descent_successor
from .descent import ESCAPES, STEP_RULES, Point, descend
from .escapes import NavigationEscape, navigation_map
from .taut import TAUT_MODELS, crossed_clearance, taut_path

__all__ = [
    "ESCAPES",
    "SAMPLINGS",
    "STEP_RULES",
    "Basins",
    "attraction_force",
    "basins",
    "descend",
    "descend_cells",
    "descent_successor",
    "follow",
    "follow_many",
    "grid_blocked",
    "grid_potential_sampler",
    "grid_sampler",
    "plan_potential",
    "plan_potential_with_field",
    "resolve_follow_params",
    "sample_force",
]


#: Maps up to this many cells get the reachability check before any work (a labelling of the free
#: space, linear in the cells); larger ones only when a run does not reach the goal.
_REACH_FIRST_CELLS = 1 << 22


def _same_component(gridmap: GridMap, start: Point, goal: Point, cache: dict[Any, Any] | None) -> bool:
    """Whether ``start`` and ``goal`` lie in one 4-connected free region of the navigation map (a
    diagonal move that cuts no corner is two orthogonal ones, so this is the wavefront's rule)."""
    from scipy import ndimage

    key = ("free_components", gridmap)
    nm = navigation_map(gridmap)
    lab = cache.get(key) if cache is not None else None
    if lab is None:
        lab = ndimage.label(~np.asarray(nm.occupied, dtype=bool))[0]
        if cache is not None:
            cache[key] = lab
    a, b = nm.grid.cell_of(*start), nm.grid.cell_of(*goal)
    return a is not None and b is not None and lab[a] != 0 and lab[a] == lab[b]


def plan_potential(gridmap: GridMap, start: ArrayLike, goal: ArrayLike, params: Mapping[str, Any], *,
                   cache: dict[Any, Any] | None = None) -> Path:
    """The ``potential`` planner: build the field (:func:`gridfield.fields.potential.build_field`), follow it.
    (:func:`plan_potential_with_field` gives the field too.)

    With ``model`` unset it builds :data:`PLANNER_MODEL` (``"nf1"``, a complete model of
    :mod:`gridfield.fields.navfield`: one minimum, the goal); ``model="khatib"`` is the classic field. The
    complete models settle their fronts only up to the start's value (all the follower reads; the
    field :func:`plan_potential_with_field` returns is ``inf`` beyond), their brushfire (and NF2's
    skeleton) is computed once per map in ``cache``, and their paths carry
    ``extra["median_clearance"]``.

    A reached ``nf1`` path (the default; :data:`gridfield.following.taut.TAUT_MODELS`, the eikonal
    attraction: ``attraction="octile"`` keeps the descended path, as a stored field's plan does) is then pulled
    taut (:func:`gridfield.following.taut.taut_path`, issue 46): string pulling over the descended
    path's own vertices, every new segment checked by exact geometry against the blocked cells and
    never crossing a cell closer to an obstacle than ``min(clearance_band, the smallest brushfire
    distance of the descended vertices within a band of it)``; its ``min_clearance`` is then the
    smallest brushfire distance of the cells the taut segments cross, and ``median_clearance`` is
    taken at points a cell apart along them. On the test maps and generated ones this brings the length
    to 1.017 of the any-angle optimum (median; p95 1.062, max 1.148; benchmarks/README.md) from 1.027
    (p95 1.090, max 1.414).

    A complete model's field has one minimum, the goal; when the continuous follower still stalls
    on it (a one-cell door whose steep sides turn its steps), the run is finished by the field's own
    discrete descent (:func:`descend_cells`) and ``extra["finish"]`` records the stall.

    A goal that cannot be reached from the start (no free path joins them) ends as ``no_path`` at
    once, with a hint. A run that does not reach the goal carries ``extra["hint"]`` and
    ``extra["diagnosis"]`` (:func:`gridfield.following.diagnose.diagnose`).

    ``Path.seconds`` is the following time; ``extra["build_seconds"]`` the field's build time;
    ``Path.params`` the resolved potential and follower parameters. With a ``cache`` dict, the
    brushfire of ``gridmap`` (per metric and saturation) and its free regions are computed once and
    reused by later calls (batch sweeps: many goals and gains on one map).

    Parameters
    ----------
    gridmap : GridMap
    start, goal : (x, y)
        World points in free cells (:func:`gridfield.planners.plan` checks them).
    params : mapping
        Potential and follower parameters (:mod:`gridfield.core.params`); the map's scaled defaults
        fill in the rest.
    cache : dict, optional
        Shared between calls on the same map.

    Returns
    -------
    Path
        ``planner="potential"``, status ``reached``, ``local_minimum``, ``max_iterations`` or
        ``no_path``.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((10, 10), bool); occ[4:6, 0:7] = True
    >>> gm = GridMap(Grid((10, 10), 1.0), occ)
    >>> p = plan_potential(gm, (2.5, 1.5), (2.5, 8.5), {})   # the default: the complete model nf1
    >>> p.status, p.params["model"]
    ('reached', 'nf1')
    >>> p = plan_potential(gm, (2.5, 1.5), (2.5, 8.5), {"model": "khatib"})   # the classic field
    >>> p.status, p.extra["stop_reason"], "hint" in p.extra
    ('local_minimum', 'oscillation', True)
    >>> plan_potential(gm, (2.5, 1.5), (2.5, 8.5), {"model": "khatib", "escape": "navigation"}).status
    'reached'
    """
    return plan_potential_with_field(gridmap, start, goal, params, cache=cache)[0]


def plan_potential_with_field(gridmap: GridMap, start: ArrayLike, goal: ArrayLike, params: Mapping[str, Any], *,
                              cache: dict[Any, Any] | None = None) -> tuple[Path, Any]:
    """:func:`plan_potential` and the field it built and followed (``None`` when the goal was found
    unreachable before any field was built); :func:`gridfield.planners.plan_with_field` calls it.

    Parameters
    ----------
    gridmap, start, goal, params, cache
        As for :func:`plan_potential`.

    Returns
    -------
    path : Path
    field : Field or None

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((4, 8), 1.0, border="wall"), np.zeros((4, 8), bool))
    >>> path, field = plan_potential_with_field(gm, (0.5, 0.5), (7.5, 3.5), {})
    >>> path.status, field.params["model"], field.potential.shape
    ('reached', 'nf1', (4, 8))
    """
    if gridmap.grid.ndim == 3:  # a voxel grid: gridfield.following.follow3d
        from .follow3d import plan_potential3d

        return plan_potential3d(gridmap, start, goal, params, cache=cache)
    params = validate(params)  # a raw mapping from a direct call is checked too
    from ..fields.potential import build_field, field_distance_map, resolve_params
    from .diagnose import diagnose, unreachable_hint

    params = dict(params or {})
    if params.get("model") is None:  # the planner's default: a complete model (gridfield.fields.navfield)
        params["model"] = PLANNER_MODEL
    s, g = as_xy(start, "start"), as_xy(goal, "goal")
    t0 = time.perf_counter()
    resolved = resolve_params(params, unit=gridmap.grid.resolution)
    vortex = resolved["model"] == "vortex"
    if not vortex and gridmap.grid.rows * gridmap.grid.cols <= _REACH_FIRST_CELLS and not _same_component(gridmap, s, g, cache):
        merged = {**resolved, **resolve_follow_params(params, unit=gridmap.grid.resolution)}
        return Path(np.array([s]), "no_path", "potential", params=merged, seconds=0.0,
                    extra={"stop_reason": "unreachable", "hint": unreachable_hint(s, g),
                           "diagnosis": {"reachable": False}, "build_seconds": time.perf_counter() - t0}), None
    nf = resolved["model"] in ("nf1", "nf2", "nf-blend")
    dmap = None
    if nf:
        field = _nf_field(gridmap, s, g, params, resolved["model"], cache)
    else:
        if cache is not None and not vortex:
            key = ("brushfire", gridmap, resolved["metric"], resolved["saturate"])
            if key not in cache:
                cache[key] = field_distance_map(gridmap, resolved)
            dmap = cache[key]
        field = build_field(gridmap, g, params, dmap=dmap)
    build = time.perf_counter() - t0
    esc = None if vortex else NavigationEscape(field)
    path = follow(field, s, params=params, navigation=esc)
    merged = dict(resolved)
    merged.update(path.params)
    extra = dict(path.extra)
    extra["build_seconds"] = build
    status = path.status
    points = path.points
    if nf and status != "reached":  # a complete field cannot trap: its own discrete descent finishes
        k = _last_valued(field, points)  # the stall's cell, or the last one the run crossed with a value
        finish = None if k is None else descend_cells(field.map, field.potential, points[k], field.goal)
        if finish is not None and k is not None:
            extra["finish"] = {"stop_reason": extra.get("stop_reason"), "from": [float(v) for v in points[k]],
                               "cells": len(finish), "dropped": len(points) - 1 - k}
            extra["stop_reason"] = "goal"
            points, status = np.concatenate([points[: k + 1], finish]), "reached"
    if status != "reached" and esc is not None:
        diag = diagnose(path, field, esc, follow=follow)  # follow: the re-runs of a proposed q_star
        if not math.isfinite(esc.value(s)):  # large maps: found unreachable only now
            diag = {"reachable": False, "hint": unreachable_hint(s, g)}
            status, points = "no_path", points[:1]
            extra["stop_reason"] = "unreachable"
        extra["hint"] = diag["hint"]
        extra["diagnosis"] = diag
    min_clearance = path.min_clearance
    if status == "reached" and resolved["model"] in TAUT_MODELS and resolved["attraction"] == "eikonal" and len(points) > 2:
        # the taut post-pass (gridfield.following.taut): string pulling of the descended vertices, never
        # into a cell below min(clearance_band, the smallest clearance of the descended vertices near it)
        band = resolved["clearance_band"] if resolved["band_gain"] > 0 else 0.0
        points = taut_path(field.map, field.distance.distance, points, float(band))
        crossed = crossed_clearance(field.map, field.distance.distance, points)
        if crossed >= 0:  # (< 0: a segment of the descent itself clips a blocked cell; the follower's measure stays)
            min_clearance = crossed
    if nf and len(points):
        extra["median_clearance"] = float(np.median(distance_at(field, _every_cell(points, field.map.grid.resolution))[0]))
        if field.map is not gridmap:  # an open border: the field's ring lies outside the grid
            _note_outside(extra, gridmap.grid, points)
    return replace(path, points=points, status=status, params=merged, min_clearance=min_clearance, extra=extra), field


def _every_cell(points: NDArray[np.float64], spacing: float) -> NDArray[np.float64]:
    """The polyline ``points`` with points added along each segment at most ``spacing`` apart (a taut
    path's long segments sampled as densely as a follower's steps)."""
    if len(points) < 2:
        return points
    seg = np.diff(points, axis=0)
    n = np.maximum(1, np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / spacing).astype(np.int64))
    owner = np.repeat(np.arange(len(seg)), n)
    frac = (np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)) / np.repeat(n, n)
    return np.vstack([points[owner] + frac[:, None] * seg[owner], points[-1:]])


def _last_valued(field: GradientField, points: NDArray[np.float64]) -> int | None:
    """Index of the last point whose cell has a finite potential (None: none has). A planned complete
    field is settled only up to about the start's value (:mod:`gridfield.fields.navfield`); a follower whose
    interpolated steps drift across a steep slowness step can end in a cell beyond that (``inf``,
    zero gradient), and the discrete descent then starts from the last point the field values."""
    cells, inside = field.map.grid.world_to_cell(points)
    ok = inside.copy()
    r, c = cells[inside].T
    ok[inside] = np.isfinite(field.potential[r, c])
    idx = np.flatnonzero(ok)
    return int(idx[-1]) if len(idx) else None


def descend_cells(gridmap: GridMap, potential: NDArray[np.float64], point: ArrayLike,
                  goal: ArrayLike) -> NDArray[np.float64] | None:
    """The discrete descent of a complete model's potential from ``point`` to ``goal``: cell centre
    to cell centre along :func:`gridfield.following.basins.descent_successor` (the lowest of the 8 neighbours
    that a move may reach, a diagonal only when both side cells are free: the rule ``basins`` checks),
    ending exactly at ``goal``.

    A complete model's ``U`` is a travel time from the goal: the march gave every settled cell a value
    strictly above one of its neighbours along such a move, so the descent strictly decreases and
    ends in the goal's cell. It finishes a follower run that stalled on such a field (a one-cell door
    whose steep sides turn the continuous steps). ``None`` when ``point`` lies outside the grid, on a
    cell without a finite value, or a cell without a lower neighbour that is not the goal's.

    Parameters
    ----------
    gridmap : GridMap
        The field's map.
    potential : ndarray
        The field's ``U`` (``inf`` on obstacles and unsettled cells).
    point, goal : (x, y)
        Where the descent starts; the goal it ends at.

    Returns
    -------
    ndarray of shape (k, 2), or None
        The centres of the cells after ``point``'s own cell, the goal's cell's replaced by ``goal``.

    Examples
    --------
    Round the obstacle in the middle (no corner cut), along the lower side where ``U`` is lower:

    >>> from gridfield.core.grid import Grid
    >>> U = np.array([[0.0, 1.0, 2.0], [1.5, np.inf, 3.0], [2.5, 3.5, 4.0]])
    >>> occ = np.isinf(U)
    >>> descend_cells(GridMap(Grid((3, 3), 1.0), occ), U, (2.5, 2.5), (0.5, 0.5)).tolist()
    [[2.5, 1.5], [2.5, 0.5], [1.5, 0.5], [0.5, 0.5]]
    """
    grid = gridmap.grid
    gx, gy = as_xy(goal, "goal")
    here, target = grid.cell_of(*as_xy(point, "point")), grid.cell_of(gx, gy)
    if here is None or target is None or not np.isfinite(potential[here]):
        return None
    cols = grid.cols
    succ = descent_successor(potential, ~np.asarray(gridmap.occupied, dtype=bool))  # the rule basins checks
    k, goal_k = here[0] * cols + here[1], target[0] * cols + target[1]
    chain: list[int] = []
    while k != goal_k:  # strictly decreasing: each cell at most once
        nxt = int(succ[k])
        if nxt == k:
            return None
        chain.append(k := nxt)
    centres = grid.cell_to_world(np.column_stack(np.divmod(np.asarray(chain[:-1], dtype=np.intp), cols)))
    return np.vstack([centres, [[gx, gy]]])  # the goal itself instead of its cell's centre


#: The ``model`` the potential planner builds when none is given: the complete ``nf1``
#: (:mod:`gridfield.fields.navfield`); ``model="khatib"`` asks for the classic field.
PLANNER_MODEL = "nf1"


def _nf_field(gridmap: GridMap, start: Point, goal: Point, params: Mapping[str, Any], model: str,
              cache: dict[Any, Any] | None) -> Any:
    """The field of a complete model for one query: the fronts settled up to the start's value
    (:func:`gridfield.fields.navfield.nav_field` with ``stop_at``); the brushfire (and NF2's skeleton) once
    per map in ``cache``."""
    from ..distance.brushfire import brushfire
    from ..fields.navfield import nav_field, nf_skeleton, work_maps

    skel = None
    around = work_maps(gridmap)[1]
    if model == "nf2":
        key: tuple[Any, ...] = ("nf2_skeleton", gridmap)
        if cache is None or key not in cache:
            made = nf_skeleton(around)
            if cache is None:
                return nav_field(gridmap, goal, params, dmap=made[0], skel=made[1:], stop_at=start)
            cache[key] = made
        dmap, sk, cost = cache[key]
        skel = (sk, cost)
    else:
        key = ("nf_brushfire", gridmap)
        shared = ("brushfire", gridmap, "euclidean", None)  # the classic field's (or the explorer's)
        if cache is not None and key not in cache and around is gridmap and shared in cache:
            cache[key] = cache[shared]  # a wall border: the same Euclidean distances
        if cache is None or key not in cache:
            made_d = brushfire(around, metric="euclidean", compute_labels=False, compute_gvd=False)
            if cache is None:
                return nav_field(gridmap, goal, params, dmap=made_d, stop_at=start)
            cache[key] = made_d
        dmap = cache[key]
    return nav_field(gridmap, goal, params, dmap=dmap, skel=skel, stop_at=start)
