"""The grid follower's loops, :func:`follow` (one start) and :func:`follow_many` (many at once), of
:mod:`gridfield.following.follower` (a private module; import from there).

:func:`follow` runs the follower's rules (:func:`gridfield.following.descent.descend`, the
specification) on a :class:`~gridfield.fields.potential.Field` sampled by :mod:`gridfield.fields.sampling`;
:func:`follow_many` runs the same rules vectorized over many starts (numpy over the points at
every step, the compiled samplers of :mod:`gridfield.fields._samplers`) and is tested equal to it.
Both resolve their parameters with :func:`resolve_follow_params`. The ``potential`` planner that
builds a field and follows it is :mod:`gridfield.following.follower`'s.

See Also
--------
gridfield.following.follower : The ``potential`` planner, and the public home of these names.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.coords import as_xy
from ..core.errors import GridfieldError, ParameterError
from ..core.grid import Grid, GridMap
from ..core.params import MAX_ITERATIONS, Escape, Follower, check, group, names
from ..core.path import Path
from ..core.results import GradientField
from ..fields._samplers import _blocked_many, _force_many
from ..fields.sampler_args import gradient_arrays, grid_args
from ..fields.sampling import (
    attraction_force,
    clearance_at,
    distance_at,
    grid_blocked,
    grid_potential_sampler,
    grid_sampler,
)
from ..fields.vortex import vortex_follower_params
from .descent import FOLLOWER_GROUPS, SLIDES, Point, Rules, descend, goal_hop, rules, without_loops
from .escapes import NavigationEscape


def resolve_follow_params(params: Mapping[str, Any] | None = None, *, unit: float = 1.0) -> dict[str, Any]:
    """The follower parameters of ``params`` with defaults filled in and values validated.

    Parameters
    ----------
    params : mapping, optional
        May hold other (potential) parameters; only the follower's are read (the registry's
        :class:`gridfield.core.params.Follower` and :class:`gridfield.core.params.Escape`,
        :data:`gridfield.following.descent.FOLLOWER_GROUPS`).
        Checked against the registry (:mod:`gridfield.core.params`).
    unit : float
        The map's length unit (a grid's cell size): ``step`` defaults to 1 unit, ``tolerance`` to
        ``step`` (normalized rule) or 1 unit (scaled rule), ``escape_radius`` to 6 units.

    Returns
    -------
    dict
        Every parameter of the follower's groups, in the registry's order, validated and resolved.

    Examples
    --------
    >>> p = resolve_follow_params({"step": 0.1}, unit=0.05)
    >>> p["step"], p["tolerance"], p["step_rule"], round(p["escape_radius"], 6)
    (0.1, 0.1, 'normalized', 0.3)
    >>> resolve_follow_params({"step": -1})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: step must be a finite number > 0, got -1
    """
    from ..core.params import resolve

    full = resolve(params, unit=check("unit", unit, minimum=0.0, strict=True))
    return {k: full[k] for k in names(*FOLLOWER_GROUPS)}


@dataclass(frozen=True)
class _Setup:
    params: dict[str, Any]
    rules: Rules
    sampling: str
    vortex: bool


def _setup(field: GradientField, params: Mapping[str, Any] | None) -> _Setup:
    """Resolve the follower parameters for a Field (with the nearest-node follower for the vortex model)."""
    merged = dict(field.params or {})
    merged.update(params or {})
    grid: Grid = field.map.grid
    vortex = merged.get("model") == "vortex"
    if vortex:
        merged = vortex_follower_params(field, merged)
    if merged.get("max_iterations") is None:  # enough to cross every free cell once
        merged["max_iterations"] = max(MAX_ITERATIONS, int(np.count_nonzero(~field.map.occupied)))
    p = resolve_follow_params(merged, unit=grid.resolution)
    out = dict(merged)
    out.update(p)
    return _Setup(out, rules(group(Follower, p), group(Escape, p)), p["sampling"], vortex)


def _note_outside(extra: dict[str, Any], grid: Grid, pts: NDArray[np.float64]) -> None:
    """Record when the follower left an open-border grid (where the field is only clamped)."""
    outside = ~grid.contains(pts)
    if outside.any():
        extra["left_map"] = True
        extra["outside_fraction"] = float(outside.mean())


def follow(field: GradientField, start: ArrayLike, *, params: Mapping[str, Any] | None = None,
           navigation: Any = None) -> Path:
    """Follow a Field's force from ``start`` to its goal with :func:`descend`.

    Parameters
    ----------
    field : gridfield.fields.potential.Field
    start : (2,) array_like
        World point in a free cell of the field's map.
    params : mapping, optional
        Follower parameters (:func:`resolve_follow_params`); the field's own params are the base.
    navigation : gridfield.following.escapes.NavigationEscape, optional
        The navigation escape's state to use for ``escape="navigation"`` (made here when omitted).

    Returns
    -------
    Path
        ``planner="potential"``; ``seconds`` is the following time; ``min_clearance`` the smallest
        brushfire distance at the path's cells; ``extra`` as in :func:`descend` plus ``sampling``.

    Examples
    --------
    A hand-made field on a 20 x 20 grid: a bowl around (8.5, 5.5) with the gradient ``x - g``:

    >>> from types import SimpleNamespace
    >>> g = Grid((20, 20), 0.5)
    >>> xs, ys = g.cell_centers()
    >>> X, Y = np.meshgrid(xs, ys)
    >>> occ = np.zeros(g.shape, bool)
    >>> f = SimpleNamespace(map=GridMap(g, occ), grad_x=X - 8.5, grad_y=Y - 5.5, goal=(8.5, 5.5),
    ...                     potential=0.5 * ((X - 8.5) ** 2 + (Y - 5.5) ** 2), params={}, distance=None)
    >>> p = follow(f, (1.0, 1.0), params={"step": 0.25})
    >>> p.status, p.iterations, p.end.tolist()
    ('reached', 34, [8.5, 5.5])
    """
    setup = _setup(field, params)
    grid_map: GridMap = field.map
    s = grid_map.check_point("start", start)
    goal = as_xy(field.goal, "goal")
    p = setup.params
    force = grid_sampler(field, sampling=setup.sampling)
    blocked = grid_blocked(grid_map)
    potential = attraction = None
    # the navigation escape's moves, and for every escape rule the finish of a reached run whose
    # straight last hop to the goal is blocked (built lazily: costs nothing unless used)
    navigate = navigation if navigation is not None else NavigationEscape(field)
    if p["escape"] == "potential_increase":
        potential = grid_potential_sampler(field, sampling=setup.sampling)
        attraction = attraction_force(goal, p)
    path = descend(force, s, goal, blocked=blocked, potential=potential, attraction=attraction, navigate=navigate,
                   rng=np.random.default_rng(p["seed"]), spec=setup.rules)
    extra = dict(path.extra)
    extra["sampling"] = setup.sampling
    _note_outside(extra, grid_map.grid, path.points)
    if setup.vortex:
        alpha = setup.rules.follower.alpha
        extra["alpha_xy"] = list(alpha) if isinstance(alpha, tuple) else None
    return replace(path, params=p, min_clearance=clearance_at(field, path.points), extra=extra)



# ----------------------------------------------------------------------------------------------
# Many starts at once
# ----------------------------------------------------------------------------------------------
_CODES = ("", "reached", "local_minimum", "collision", "max_iterations")


class _Active:
    """The points :func:`follow_many` still moves: one entry per point in every array below, kept
    in step by :meth:`keep` (the points that stop drop out of all of them at once)."""

    __slots__ = ("F1", "F2", "P1x", "P1y", "P2x", "P2y", "RF", "RX", "RY", "X", "Y", "best", "best_it", "ids",
                 "win_min", "win_x", "win_y")

    def __init__(self, starts: NDArray[np.float64], goal: Point, cw: int) -> None:
        n = len(starts)
        self.ids = np.arange(n)  # original index of each active point
        self.X, self.Y = starts[:, 0].copy(), starts[:, 1].copy()
        self.P1x = np.full(n, np.nan)  # position one and two steps back
        self.P1y = np.full(n, np.nan)
        self.P2x = np.full(n, np.nan)
        self.P2y = np.full(n, np.nan)
        self.F1 = np.full(n, np.nan)  # |F| one and two steps back
        self.F2 = np.full(n, np.nan)
        X, Y = self.X, self.Y
        self.best = np.sqrt((X - goal[0]) * (X - goal[0]) + (Y - goal[1]) * (Y - goal[1]))  # best distance to the goal
        self.best_it = np.zeros(n, np.int64)  # and when
        self.win_min = np.full(n, np.inf)  # smallest |F| since then, and where
        self.win_x, self.win_y = X.copy(), Y.copy()
        # the last cw + 1 positions and their |F| (column = iteration mod cw + 1), for the confined rule
        self.RX = np.empty((n, cw + 1))
        self.RY = np.empty((n, cw + 1))
        self.RF = np.full((n, cw + 1), np.nan)
        self.RX[:, 0], self.RY[:, 0] = X, Y

    def keep(self, mask: NDArray[np.bool_]) -> None:
        """Keep the points of ``mask`` in every array (fresh arrays: none is written in place)."""
        for name in self.__slots__:
            setattr(self, name, getattr(self, name)[mask])


def follow_many(field: GradientField, starts: ArrayLike, *, params: Mapping[str, Any] | None = None,
                keep_paths: bool = True) -> list[Path]:
    """Follow a Field from many starts at once (numpy over the points at every step).

    Each point runs the same step and stop rules as :func:`follow` and stops independently; the
    result equals ``[follow(field, s, params=params) for s in starts]`` (escapes are run by
    :func:`follow` for the points that stall, after the batch).

    Parameters
    ----------
    field : gridfield.fields.potential.Field
    starts : array_like, shape (N, 2)
    params : mapping, optional
    keep_paths : bool
        ``False``: each Path holds only its start and end point (saves memory for huge batches).

    Returns
    -------
    list of Path

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> g = Grid((20, 20), 0.5)
    >>> X, Y = np.meshgrid(*g.cell_centers())
    >>> f = SimpleNamespace(map=GridMap(g, np.zeros(g.shape, bool)), grad_x=X - 5.0, grad_y=Y - 5.0,
    ...                     goal=(5.0, 5.0), potential=None, params={}, distance=None)
    >>> [(p.status, p.iterations) for p in follow_many(f, [[1.0, 1.0], [9.0, 5.0]], params={"step": 0.5})]
    [('reached', 11), ('reached', 8)]
    """
    setup = _setup(field, params)
    p, r = setup.params, setup.rules
    grid_map: GridMap = field.map
    S = _checked_starts(grid_map, starts)
    goal = as_xy(field.goal, "goal")
    gx, gy = gradient_arrays(field)
    occ, x0, y0, res = grid_args(grid_map)
    nearest = setup.sampling == "nearest"
    wall = grid_map.grid.border == "wall"
    cw, max_it = r.confine_window, r.max_iterations

    t0 = time.perf_counter()
    N = len(S)
    a = _Active(S, goal, cw)
    hist_x = [a.X.copy()] if keep_paths else []
    hist_y = [a.Y.copy()] if keep_paths else []
    hist_ids = [a.ids.copy()] if keep_paths else []
    code = np.zeros(N, np.int8)
    end_it = np.zeros(N, np.int64)
    reason = np.empty(N, dtype=object)
    stall = np.full((N, 2), np.nan)
    osc = np.full((N, 2, 2), np.nan)
    coll = np.full((N, 2), np.nan)
    slid = np.zeros(N, np.int64)
    last = np.zeros((N, 2))
    FX = np.empty(N)
    FY = np.empty(N)
    out_b = np.empty(N, np.bool_)
    it = 0

    def finish(mask: NDArray[np.bool_], c: int, why: str) -> None:
        idx = a.ids[mask]
        code[idx] = c
        reason[idx] = why
        end_it[idx] = it
        last[idx, 0], last[idx, 1] = a.X[mask], a.Y[mask]

    while len(a.ids):
        dx, dy = a.X - goal[0], a.Y - goal[1]
        d = np.sqrt(dx * dx + dy * dy)
        done = _stops_before_step(r, a, d, it, stall, osc, finish)
        if it >= max_it:
            finish(~done, 4, "max_iterations")
            break
        keep = ~done
        if not keep.all():
            a.keep(keep)
            if not len(a.ids):
                break
        n = len(a.ids)
        fx, fy = FX[:n], FY[:n]
        _force_many(gx, gy, occ, x0, y0, res, nearest, a.X, a.Y, fx, fy)
        fn = np.sqrt(fx * fx + fy * fy)
        a.RF[:, it % (cw + 1)] = fn
        upd = fn < a.win_min
        a.win_min = np.where(upd, fn, a.win_min)
        a.win_x = np.where(upd, a.X, a.win_x)
        a.win_y = np.where(upd, a.Y, a.win_y)
        bad = r.small_gradient(fn)
        if bad.any():
            idx = a.ids[bad]
            stall[idx, 0], stall[idx, 1] = a.X[bad], a.Y[bad]
            finish(bad, 2, "small_gradient")
            reason[a.ids[bad & ~np.isfinite(fn)]] = "undefined_force"
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            NX, NY = r.next_point(a.X, a.Y, fx, fy, fn, np.sqrt, np.where)
        NX = np.where(bad, a.X, NX)
        NY = np.where(bad, a.Y, NY)
        ob = out_b[:n]
        _blocked_many(occ, x0, y0, res, wall, a.X, a.Y, NX, NY, ob)
        hit = ob & ~bad
        if hit.any():  # the fallback steps of descend, in the same order, for the blocked points
            pinned = _slide_many(a, hit, NX, NY, slid, (occ, x0, y0, res, wall))
            if pinned.any():
                idx = a.ids[pinned]
                coll[idx, 0], coll[idx, 1] = NX[pinned], NY[pinned]
                stall[idx, 0], stall[idx, 1] = a.X[pinned], a.Y[pinned]
                finish(pinned, 2, "blocked")
            hit = pinned
        move = ~(bad | hit)
        a.P2x, a.P2y, a.P1x, a.P1y = a.P1x, a.P1y, a.X, a.Y
        a.F2, a.F1 = a.F1, fn
        a.X = np.where(move, NX, a.X)
        a.Y = np.where(move, NY, a.Y)
        it += 1
        if not move.all():
            a.keep(move)
        a.RX[:, it % (cw + 1)], a.RY[:, it % (cw + 1)] = a.X, a.Y
        a.RF[:, it % (cw + 1)] = np.nan
        if keep_paths:  # a.X, a.Y, a.ids are fresh arrays every step (never written in place)
            hist_x.append(a.X)
            hist_y.append(a.Y)
            hist_ids.append(a.ids)
        dx, dy = a.X - goal[0], a.Y - goal[1]
        d = np.sqrt(dx * dx + dy * dy)
        imp = r.progressed(d, a.best)
        a.best = np.where(imp, d, a.best)
        a.best_it = np.where(imp, it, a.best_it)
        a.win_min = np.where(imp, np.inf, a.win_min)
        a.win_x = np.where(imp, a.X, a.win_x)
        a.win_y = np.where(imp, a.Y, a.win_y)
    seconds = time.perf_counter() - t0

    return _many_paths(field, S, params, p, r, setup.sampling, keep_paths, (hist_x, hist_y, hist_ids),
                       (code, end_it, reason, stall, osc, coll, slid, last), goal, seconds)


def _many_paths(field: GradientField, S: NDArray[np.float64], params: Mapping[str, Any] | None, p: dict[str, Any], r: Rules,
                sampling: str, keep_paths: bool, hist: tuple[list[Any], list[Any], list[Any]], ends: tuple[Any, ...],
                goal: Point, seconds: float) -> list[Path]:
    """:func:`follow_many`'s Paths from the positions it recorded (``hist``) and how each point stopped
    (``ends``): goal hops, stall details, loops cut, clearances; the stalled points of an escaping
    follower re-run by :func:`follow`."""
    hist_x, hist_y, hist_ids = hist
    code, end_it, reason, stall, osc, coll, slid, last = ends
    grid_map: GridMap = field.map
    N = len(S)
    # paths: hist[k] holds the positions after k moves of the points still moving then; a stable
    # sort by point id lists each point's positions in step order
    if keep_paths:
        HI = np.concatenate(hist_ids)
        order = np.argsort(HI, kind="stable")
        HX, HY = np.concatenate(hist_x)[order], np.concatenate(hist_y)[order]
        first = np.concatenate([[0], np.cumsum(np.bincount(HI, minlength=N))[:-1]])
        del HI, order, hist_x, hist_y, hist_ids
    blocked = grid_blocked(grid_map)
    navigate = NavigationEscape(field)  # the finish of a reached run whose last hop is blocked (lazy)
    pts_list: list[NDArray[np.float64]] = []
    extras: list[dict[str, Any]] = []
    for i in range(N):
        n_i = int(end_it[i])
        if keep_paths:
            o = first[i]
            pts = np.column_stack([HX[o: o + n_i + 1], HY[o: o + n_i + 1]])
        else:
            pts = np.array([S[i], last[i]]) if n_i else S[i][None, :]
        status = _CODES[code[i]]
        extra: dict[str, Any] = {"stop_reason": reason[i], "slid_steps": int(slid[i]), "sampling": sampling}
        if status == "reached":
            lx, ly = float(last[i, 0]), float(last[i, 1])
            if (lx, ly) != goal:
                hop = goal_hop(lx, ly, goal, blocked, navigate)
                if hop is not None:
                    pts = np.vstack([pts, np.asarray(hop, dtype=float)])
                extra["goal_appended"] = hop is not None
            else:
                extra["goal_appended"] = False
        elif status == "local_minimum":
            extra["stall_point"] = stall[i].tolist()
            extra["local_minima"] = [stall[i].tolist()]
            if reason[i] == "oscillation":
                extra["oscillation"] = osc[i].tolist()
            elif reason[i] == "blocked":
                extra["blocked_at"] = coll[i].tolist()
        if p["escape"] == "navigation" and keep_paths and status != "local_minimum":
            pts = without_loops(pts, r.box, blocked)  # the loops cut as descend cuts them (stalls: follow's)
        pts_list.append(pts)
        extras.append(extra)
    # clearance and the outside-the-map note for all paths at once
    lengths = np.array([len(q) for q in pts_list])
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    all_pts = np.concatenate(pts_list)
    dist, inside = distance_at(field, all_pts)
    clear = np.minimum.reduceat(dist, offsets)
    n_out = np.add.reduceat((~inside).astype(np.int64), offsets)
    paths: list[Path] = []
    per = seconds / max(N, 1)
    for i in range(N):
        status, extra, pts = _CODES[code[i]], extras[i], pts_list[i]
        if n_out[i]:
            extra["left_map"] = True
            extra["outside_fraction"] = float(n_out[i] / lengths[i])
        if p["escape"] != "none":
            if status == "local_minimum":
                paths.append(follow(field, S[i], params=params))
                continue
            extra.update(escapes_tried=0, escapes_succeeded=0, escapes=[])
        paths.append(Path(pts, status, "potential", iterations=int(end_it[i]), params=p, seconds=per,
                          min_clearance=float(clear[i]), extra=extra))
    return paths


def _checked_starts(grid_map: GridMap, starts: ArrayLike) -> NDArray[np.float64]:
    """The starts of :func:`follow_many` as an (N, 2) array, each in a free cell (else the first bad one named)."""
    S = np.asarray(starts, dtype=float)
    if S.ndim != 2 or S.shape[1] != 2:
        raise ParameterError(f"starts must have shape (N, 2), got {S.shape}")
    ok = np.isfinite(S).all(axis=1) & grid_map.grid.contains(S) & grid_map.is_free(S)
    if not ok.all():
        i = int(np.flatnonzero(~ok)[0])
        try:
            grid_map.check_point("start", S[i])
        except GridfieldError as e:
            raise type(e)(f"starts[{i}]: {e}") from None
    return S


def _stops_before_step(r: Rules, a: _Active, d: NDArray[np.float64], it: int, stall: NDArray[np.float64],
                       osc: NDArray[np.float64], finish: Callable[[NDArray[np.bool_], int, str], None]
                       ) -> NDArray[np.bool_]:
    """The stop rules before the step, in :data:`gridfield.following.descent.STOP_RULES` order up to the step
    budget (goal, oscillation, confined, no progress; ``blocked`` was found by the step before): the
    points that stop, each finished with its reason and stall point."""
    cw = r.confine_window
    done: NDArray[np.bool_] = r.reached(d)
    finish(done, 1, "goal")
    ox, oy = a.X - a.P2x, a.Y - a.P2y
    osc_m = ~done & r.oscillating(np.sqrt(ox * ox + oy * oy))
    if osc_m.any():
        idx = a.ids[osc_m]
        first = r.older_stalls(a.F2[osc_m], a.F1[osc_m])
        stall[idx, 0] = np.where(first, a.P2x[osc_m], a.P1x[osc_m])
        stall[idx, 1] = np.where(first, a.P2y[osc_m], a.P1y[osc_m])
        osc[idx, 0, 0], osc[idx, 0, 1] = a.P1x[osc_m], a.P1y[osc_m]
        osc[idx, 1, 0], osc[idx, 1, 1] = a.X[osc_m], a.Y[osc_m]
        finish(osc_m, 2, "oscillation")
    done |= osc_m
    if cw and it >= cw:
        cf_m = ~done & r.confined(np.ptp(a.RX, axis=1), np.ptp(a.RY, axis=1))
        if cf_m.any():
            order = (np.arange(it - cw, it) % (cw + 1))  # the stretch's points before the current one
            k = order[r.weakest(a.RF[cf_m][:, order])]
            rows = np.flatnonzero(cf_m)
            idx = a.ids[cf_m]
            stall[idx, 0], stall[idx, 1] = a.RX[rows, k], a.RY[rows, k]
            finish(cf_m, 2, "confined")
        done |= cf_m
    if r.progress_window:
        np_m = ~done & r.stalled(it - a.best_it)
        if np_m.any():
            idx = a.ids[np_m]
            stall[idx, 0], stall[idx, 1] = a.win_x[np_m], a.win_y[np_m]
            finish(np_m, 2, "no_progress")
        done |= np_m
    return done


def _slide_many(a: _Active, hit: NDArray[np.bool_], NX: NDArray[np.float64], NY: NDArray[np.float64],
                slid: NDArray[np.int64], grid: tuple[Any, ...]) -> NDArray[np.bool_]:
    """The fallback steps of :func:`gridfield.following.descent.descend` (``SLIDES``, in order) for the blocked
    points ``hit``: the first free one replaces ``NX, NY`` (in place, counted in ``slid``); the points
    with none (pinned) are returned."""
    occ, x0, y0, res, wall = grid
    todo = np.flatnonzero(hit)
    SX, SY = NX[todo] - a.X[todo], NY[todo] - a.Y[todo]
    for s in range(len(SLIDES)):
        CX, CY = Rules.slide(a.X[todo], a.Y[todo], SX, SY, s)
        cb = np.empty(len(todo), np.bool_)
        _blocked_many(occ, x0, y0, res, wall, a.X[todo], a.Y[todo], CX, CY, cb)
        freed = ~cb
        NX[todo[freed]], NY[todo[freed]] = CX[freed], CY[freed]
        slid[a.ids[todo[freed]]] += 1
        todo, SX, SY = todo[cb], SX[cb], SY[cb]
        if not len(todo):
            break
    pinned = np.zeros(len(hit), np.bool_)
    pinned[todo] = True
    return pinned
