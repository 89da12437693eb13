"""The follower on voxel grids (3-D) and the ``potential`` planner there.

:func:`follow3d` descends a voxel :class:`~gridfield.core.results.Field` (``grad_x``, ``grad_y``,
``grad_z``): steps of length ``step`` along the trilinearly interpolated ``-grad`` (over the free voxels
round the point with a finite potential), each taken only when its segment touches no blocked voxel
(the exact closed-cube test of :func:`gridfield.fields.navigation3d.segment_clear`, an Amanatides-Woo
walk) and the interpolated potential decreases; otherwise the discrete steepest descent takes over
(to the voxel's centre, then to the lowest allowed neighbour under the bounding-box rule, until below
the level where the step failed) and the continuous steps resume. So every segment of the path touches
only free voxels. On a complete field (``nf1``) the descent cannot stall: a run that uses up
``max_iterations`` is finished by the discrete descent, which ends at the goal. On the classic field
(``khatib``) a voxel without a lower allowed neighbour is a local minimum (status ``local_minimum``).
``shortcut=True`` adds a string-pulling pass over the path's own vertices (every segment kept clear).

:func:`plan_potential3d` is the ``potential`` planner on a voxel grid (a dispatch of
:func:`gridfield.following.follower.plan_potential_with_field`): the field of
:func:`gridfield.fields.potential3d.build_field3d` (default ``nf1``; ``model="khatib"`` the classic one),
settled up to the start's value for ``nf1``, then :func:`follow3d`.

Examples
--------
>>> from gridfield.core.grid import Grid, GridMap
>>> occ = np.zeros((6, 6, 6), bool); occ[:, 2:4, :4] = True   # a wall across y, open at x >= 4
>>> gm = GridMap(Grid((6, 6, 6), 1.0, border="wall"), occ)
>>> path, field = plan_potential3d(gm, (0.5, 0.5, 2.5), (0.5, 5.5, 2.5), {})
>>> path.status, path.points.shape[1], path_clear(gm, path.points)
('reached', 3, -1)
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ..core.path import Path
from ..core.results import Field
from ..fields.navigation3d import cell_units, check_voxel_map, free_mask, path_clear, path_clearance, shortcut_path
from ._follow import resolve_follow_params

__all__ = ["follow3d", "path_clear", "plan_potential3d"]

#: The complete models (a run of theirs is finished by the discrete descent).
_COMPLETE = ("nf1",)


def follow3d(field: Field, start: ArrayLike, params: Mapping[str, Any] | None = None, *,
             shortcut: bool = False) -> Path:
    """Descend a voxel field from ``start`` to its goal.

    Parameters
    ----------
    field : Field
        On a voxel grid (``grad_z`` set).
    start : (x, y, z)
        In a free voxel.
    params : mapping, optional
        Follower parameters over the field's own: ``step`` (default 1 cell, at most 1 cell),
        ``max_iterations`` (default 10000 or the free voxels, if more).
    shortcut : bool
        String-pull the path over its own vertices afterwards.

    Returns
    -------
    Path
        ``points`` ``(n, 3)`` from ``start``; ``reached`` (ending exactly at the goal),
        ``local_minimum`` or ``max_iterations``; ``extra["stop_reason"]`` and, for a stall, its
        ``stall_point``; ``iterations`` the steps taken (``params["discrete_steps"]`` of them by the
        discrete descent).

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> from gridfield.fields.navfield3d import nav_field3d
    >>> gm = GridMap(Grid((1, 1, 6), 1.0), np.zeros((1, 1, 6), bool))
    >>> p = follow3d(nav_field3d(gm, (5.5, 0.5, 0.5)), (0.5, 0.5, 0.5))
    >>> p.status, p.points[-1].tolist()
    ('reached', [5.5, 0.5, 0.5])
    """
    if not isinstance(field, Field) or field.grad_z is None:
        raise ParameterError("follow3d follows a voxel grid's Field (with grad_z)")
    gm = check_voxel_map(field.map, "follow3d")
    t0 = time.perf_counter()
    res = gm.grid.resolution
    merged = {**{k: v for k, v in dict(field.params).items() if k in _FOLLOW_NAMES}, **dict(params or {})}
    fp = resolve_follow_params(merged, unit=res)
    for name, only in _ONLY.items():
        if fp[name] != only:
            raise ParameterError(f"{name}={fp[name]!r} is a 2-D follower option; the voxel follower takes {name}="
                                 f"{only!r} (the default model nf1 reaches every reachable goal)")
    step = min(float(fp["step"]), res)
    free = free_mask(gm)
    n_free = int(free.sum())
    max_it = int(fp["max_iterations"]) if merged.get("max_iterations") is not None else max(10000, 4 * n_free)
    s = gm.check_point("start", start)
    goal = np.asarray(field.goal, dtype=float)
    q = cell_units(gm, np.vstack([s, goal]))
    complete = field.params.get("model") in _COMPLETE
    U = np.asarray(field.potential, dtype=np.float64)
    k, r, c = (int(v) for v in np.floor(q[0]))
    if not math.isfinite(U[k, r, c]):
        return Path(s[None, :], "no_path", "potential", 0, {**fp, "step": step}, time.perf_counter() - t0,
                    extra={"stop_reason": "unreachable", "reason": "the field has no value at the start (the goal is "
                           "unreachable from it)"})
    from ..fields import _voxelpath  # type: ignore[attr-defined]  # a compiled extension, no stubs

    pts, status, it, nd = _voxelpath.follow3(U, field.grad_z, field.grad_y, field.grad_x, free, *q[0], *q[1],
                                            step / res, max_it, complete)
    pts = np.asarray(pts)
    points = gm.grid.origin + pts[:, ::-1] * res
    if status == 0:
        points[-1] = goal  # exactly (no rounding through cell units)
    points[0] = s
    name = ("reached", "local_minimum", "max_iterations")[int(status)]
    extra: dict[str, Any] = {"stop_reason": ("goal", "confined", "max_iterations")[int(status)]}
    if status == 1:
        extra["stall_point"] = [float(v) for v in points[-1]]
        extra["local_minima"] = [extra["stall_point"]]
    if shortcut and len(points) > 2:
        points = shortcut_path(gm, points)
    cells, inside = gm.grid.world_to_cell(points)
    clearance = path_clearance(gm, cells[inside]) if inside.any() else math.nan
    ran = {**fp, "step": step, "max_iterations": max_it, "discrete_steps": int(nd)}
    return Path(points, name, "potential", int(it), ran, time.perf_counter() - t0, clearance, extra)


#: The follower options of 2-D that the voxel follower does not have, with the one value it takes.
_ONLY = {"escape": "none", "step_rule": "normalized", "sampling": "bilinear"}

#: The follower parameters a field's own ``params`` may carry.
_FOLLOW_NAMES = ("step", "tolerance", "max_iterations", "progress_window")


def plan_potential3d(gridmap: GridMap, start: ArrayLike, goal: ArrayLike, params: Mapping[str, Any], *,
                     cache: dict[Any, Any] | None = None) -> tuple[Path, Field | None]:
    """The ``potential`` planner on a voxel grid: build the field, follow it (:func:`follow3d`).

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    start, goal : (x, y, z)
        Free world points.
    params : mapping
        Potential and follower parameters; ``model`` unset means ``nf1``.
    cache : dict, optional
        Keeps the map's clearance and free regions between queries.

    Returns
    -------
    path : Path
        ``planner="potential"``; ``no_path`` at once (with a hint) when no free path joins start and goal.
    field : Field or None
        The field followed (None when none was built).

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((3, 3, 3), bool); occ[1] = True
    >>> path, field = plan_potential3d(GridMap(Grid((3, 3, 3), 1.0), occ), (0.5, 0.5, 0.5), (0.5, 0.5, 2.5), {})
    >>> path.status, field
    ('no_path', None)
    """
    from ..core.params import validate
    from ..fields.navfield3d import nav_field3d
    from ..fields.navigation3d import cached_clearance
    from ..fields.potential3d import build_field3d

    gm = check_voxel_map(gridmap, "the potential planner")
    given = dict(validate(params))
    if given.get("model") is None:
        given["model"] = "nf1"
    s, g = gm.check_point("start", start), gm.check_point("goal", goal)
    t0 = time.perf_counter()
    if not _same_component(gm, s, g, cache):
        fp = resolve_follow_params(given, unit=gm.grid.resolution)
        return Path(s[None, :], "no_path", "potential", params={**given, **fp}, seconds=0.0,
                    extra={"stop_reason": "unreachable", "hint": f"the goal ({_xyz(g)}) cannot be reached from the start "
                           f"({_xyz(s)}): no free path joins them on this voxel grid",
                           "diagnosis": {"reachable": False}, "build_seconds": time.perf_counter() - t0}), None
    if given["model"] == "nf1":
        field = nav_field3d(gm, g, given, stop_at=s, clearance=cached_clearance(gm, cache))
    else:
        field = build_field3d(gm, g, given)
    build = time.perf_counter() - t0
    path = follow3d(field, s, given)
    extra = dict(path.extra)
    extra["build_seconds"] = build
    if given["model"] == "nf1" and len(path.points):
        cells, inside = gm.grid.world_to_cell(path.points)
        extra["median_clearance"] = float(np.median(cached_clearance(gm, cache)[tuple(cells[inside].T)]))
    if path.status != "reached":
        extra["hint"] = (f"the {given['model']} field has a local minimum at "
                         f"({', '.join(f'{v:.4g}' for v in path.points[-1])}); the default model nf1 reaches every "
                         "reachable goal")
    return Path(path.points, path.status, "potential", path.iterations, {**dict(field.params), **dict(path.params)},
                path.seconds, path.min_clearance, extra), field


def _xyz(p: Any) -> str:
    return ", ".join(f"{float(v):g}" for v in p)


def _same_component(gm: GridMap, s: Any, g: Any, cache: dict[Any, Any] | None) -> bool:
    """Whether start and goal lie in one 6-connected free region (a move under the bounding-box rule is
    a chain of face moves, so this is the wavefront's reachability)."""
    from scipy import ndimage

    key = ("free_components3d", gm)
    lab = cache.get(key) if cache is not None else None
    if lab is None:
        lab = ndimage.label(~np.asarray(gm.occupied, dtype=bool))[0]
        if cache is not None:
            cache[key] = lab
    a, b = gm.grid.cell_of(*s), gm.grid.cell_of(*g)
    return a is not None and b is not None and lab[a] != 0 and lab[a] == lab[b]
