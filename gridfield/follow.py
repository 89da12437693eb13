"""The gradient-descent follower: step rules, stop rules, local-minimum escapes, basins of attraction.

One core, :func:`descend`, holds the step and stop logic. It sees the field only through two
callables, ``force(p) -> (fx, fy)`` and ``blocked(p, q) -> bool``, so the grid follower
(:func:`follow`, fields sampled from gradient arrays) and the exact planner
(:func:`gridfield.exact.plan_exact_potential`, forces from exact obstacle distances) share it.

Step rules (names: Choset et al. ch. 4; registry: gridfield.params)
    ``normalized``: ``x += step * F/|F|`` (seed 000).
    ``scaled``: ``x += alpha * F``; with ``min_speed > 0`` a step shorter than ``min_speed`` is
    stretched to ``min_speed`` along ``F`` (seed 004). ``alpha`` may be a pair ``(ax, ay)`` (used by
    seed 003's follower, whose x and y steps are scaled by different constants).

Stop rules, checked in this order before every step
    ``reached``: the current point is closer than ``tolerance`` to the goal (the seed's
    ``norm(x - Xf) < 0.1``). The goal itself is then appended to the path, as the seed's
    ``P = [P Xf]`` does (unless that last hop is blocked; ``extra["goal_appended"]`` tells).
    ``local_minimum``, four detectors:

    - *oscillation*: the point is back within ``revisit_tolerance`` of the point two steps back
      (seed 000; default tolerance ``1e-6 * step``). The stall point is the one of the two
      alternating points with the smaller ``|F|``; both are in ``extra["oscillation"]``.
    - *no progress*: the best distance to the goal has not improved by more than
      ``1e-3 * step`` during the last ``progress_window`` steps (0 disables). On grids the
      follower rarely returns exactly to a point it visited, so this is the grid's main
      detector. The stall point is the point of that stretch with the smallest ``|F|``.
    - *confined* (normalized rule): the last ``confine_window`` steps stayed within a box of side
      ``2 * step`` (a jitter about an equilibrium, which never exactly revisits a point). The stall point is
      the point of that stretch with the smallest ``|F|``.
    - *small gradient*: ``|F| <= gradient_threshold`` (seed 004), or ``F`` is zero or not
      finite. The stall point is the current point.

    - *blocked*: the step would enter an obstacle (or leave a walled map) and so would every
      fallback step (below): the force presses the follower onto an obstacle. The stall point
      is the current point; ``extra["blocked_at"]`` holds the rejected full step.

    ``max_iterations``: the step budget is used up.

Steps never enter an obstacle
    Every move (step, fallback step, escape move, the appended goal) is checked with ``blocked``
    before it is made. When the full step is blocked, the follower tries shorter and turned
    steps, in the order of ``_SLIDES``: the step direction turned by 0, +-15, ..., +-75 degrees
    (all within 75 degrees of the force, so each still descends), each at 1, 1/2, 1/4 and 1/8 of
    the step length; it takes the first free one (it slides along the wall), and
    ``extra["slid_steps"]`` counts them. So a normal run ends ``reached``, ``local_minimum`` or
    ``max_iterations``; ``collision`` is left to callers for a start that is not free.

A stalled run is never reported as ``reached``.

Escapes (seed 000's bonus question), tried when a local minimum is detected
    ``random_walk``: jump a length ``r ~ U(0, escape_radius]`` in a uniformly random direction,
    resampling (up to 100 times) until the straight jump is not blocked, then resume descending.
    ``potential_increase``: the seed's ``Path_generator_esc``: from the stall point move along
    ``F_rep + 0.05 * F_attr`` with a step that starts at ``step`` and grows by 1.25 per sub-step
    until the potential is at least 25 % above the local minimum's (at most 60 sub-steps; a
    blocked sub-step fails the escape). The k-th escape from the same minimum requires an
    increase by ``1.25**k`` (the seed's rule is deterministic, so repeating it unchanged would
    retrace the same jump).

    Each jump costs one try of ``escape_tries``. An escape *succeeds* when the follower's next
    stop is the goal or a stall at another local minimum (farther than
    ``max(3 * step, tolerance)`` from the one it left). ``extra`` counts ``escapes_tried`` and
    ``escapes_succeeded`` and logs each escape.

    Measured on the seed 000 segment world (step 0.1; ``benchmarks/follow.py --escapes 50``,
    table in ``benchmarks/README.md``): one random jump escapes about one time in three (exact
    planner 17/50 seeds, grid at h = 0.05 19/50); with up to 10 tries 49/50 runs reach the goal
    (about 36 % of all jumps succeed). The seed's potential-increase escape reaches the goal with
    its first jump on the exact field, and with the third on the grid.

Grid fields
    :func:`grid_sampler` samples ``F = -grad U`` from a :class:`~gridfield.potential.Field`'s
    gradient arrays: ``bilinear`` interpolation between the four surrounding cell centres that are
    *free* (obstacle cells' weights are dropped and the rest renormalized, so obstacle cells'
    zero gradients never blend in), clamped to the grid (no extrapolation); or ``nearest`` (the
    cell containing the point, seed 003). :func:`grid_blocked` walks the cells a segment crosses
    exactly. **Open border**: what lies outside the grid is free space; the follower may leave
    the grid, and the field there is the field at the nearest point of the grid (clamping).
    **Wall border**: leaving the grid is blocked, like entering an obstacle.

Examples
--------
A quadratic bowl ``U = |x - g|^2 / 2`` with a normalized step:

>>> pts, status, n, extra = descend(lambda p: (3.0 - p[0], 1.0 - p[1]), (0.0, 1.0), (3.0, 1.0),
...                                 step=0.5, tolerance=0.3)
>>> status, n, pts[-1].tolist()
('reached', 6, [3.0, 1.0])
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._kernels_follow import (
    _bilinear2,
    _blocked_many,
    _cell_values,
    _force_at,
    _force_many,
    _nearest2,
    _segment_blocked,
)
from ._kernels_follow import entry_point as _direct
from .errors import GridfieldError, ParameterError
from .grid import Grid, GridMap, _as_points
from .path import Path

__all__ = [
    "ESCAPES",
    "FOLLOW_DEFAULTS",
    "SAMPLINGS",
    "STEP_RULES",
    "Basins",
    "attraction_force",
    "basins",
    "descend",
    "descent_successor",
    "follow",
    "follow_many",
    "grid_blocked",
    "grid_potential_sampler",
    "grid_sampler",
    "plan_potential",
    "resolve_follow_params",
    "sample_force",
]

STEP_RULES = ("normalized", "scaled")
ESCAPES = ("none", "random_walk", "potential_increase", "navigation")
SAMPLINGS = ("bilinear", "nearest")

#: Follower parameters and their defaults (the registry's, :mod:`gridfield.params`). ``None``
#: lengths scale with the map: ``step`` 1 cell (exact planner: see :mod:`gridfield.exact`),
#: ``tolerance`` ``step`` for the normalized rule or 1 cell for the scaled rule, ``escape_radius``
#: 6 cells.
FOLLOW_DEFAULTS: dict[str, Any] = {
    "step_rule": "normalized",
    "step": None,
    "alpha": 0.1,
    "min_speed": 0.0,
    "tolerance": None,
    "max_iterations": 10_000,
    "sampling": "bilinear",
    "gradient_threshold": 0.0,
    "progress_window": 200,
    "confine_window": 20,
    "escape": "none",
    "escape_tries": 10,
    "escape_radius": None,
    "seed": 0,
}

#: Rejected random-walk jumps (blocked) before a try counts as failed.
_JUMP_SAMPLES = 100
#: Sub-steps of the potential-increase escape before it gives up.
_ESCAPE_SUBSTEPS = 60
Point = tuple[float, float]


# ----------------------------------------------------------------------------------------------
# Parameters
# ----------------------------------------------------------------------------------------------
def _choice(name: str, value: Any, options: Sequence[str]) -> str:
    if value not in options:
        raise ParameterError(f"{name} must be one of {', '.join(map(repr, options))}; got {value!r}")
    return str(value)


def _number(name: str, value: Any, *, positive: bool = False, allow_zero: bool = True) -> float:
    if isinstance(value, str):  # issue 17: "0.1" is not a number (float() would take it)
        raise ParameterError(f"{name} must be a number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number, got {value!r}") from None
    if isinstance(value, bool) or math.isnan(v) or math.isinf(v):
        raise ParameterError(f"{name} must be a finite number, got {value!r}")
    if positive and not (v > 0 or (allow_zero and v == 0)):
        raise ParameterError(f"{name} must be {'>= 0' if allow_zero else '> 0'}, got {value!r}")
    return v


def _integer(name: str, value: Any, *, minimum: int = 0) -> int:
    if isinstance(value, bool | str):  # issue 17: "10" is not an integer (float() would take it)
        raise ParameterError(f"{name} must be an integer >= {minimum}, got {value!r}")
    try:
        f = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be an integer >= {minimum}, got {value!r}") from None
    if not math.isfinite(f) or f != int(f) or f < minimum:
        raise ParameterError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(f)


def _alpha(value: Any) -> tuple[float, float]:
    if isinstance(value, Sequence | np.ndarray) and not isinstance(value, str):
        vals = list(value)
        if len(vals) != 2:
            raise ParameterError(f"alpha must be a number or a pair (ax, ay), got {value!r}")
        ax, ay = (_number("alpha", v, positive=True, allow_zero=False) for v in vals)
        return ax, ay
    a = _number("alpha", value, positive=True, allow_zero=False)
    return a, a


def resolve_follow_params(params: Mapping[str, Any] | None = None, *, unit: float = 1.0) -> dict[str, Any]:
    """The follower parameters of ``params`` with defaults filled in and values validated.

    Parameters
    ----------
    params : mapping, optional
        May hold other (potential) parameters; only the names in :data:`FOLLOW_DEFAULTS` are read.
        Checked against the registry (:mod:`gridfield.params`).
    unit : float
        The map's length unit (a grid's cell size): ``step`` defaults to 1 unit, ``tolerance`` to
        ``step`` (normalized rule) or 1 unit (scaled rule), ``escape_radius`` to 6 units.

    Returns
    -------
    dict
        Every key of :data:`FOLLOW_DEFAULTS`, validated and resolved.

    Examples
    --------
    >>> p = resolve_follow_params({"step": 0.1}, unit=0.05)
    >>> p["step"], p["tolerance"], p["step_rule"], round(p["escape_radius"], 6)
    (0.1, 0.1, 'normalized', 0.3)
    >>> resolve_follow_params({"step": -1})
    Traceback (most recent call last):
    ...
    gridfield.errors.ParameterError: step must be a finite number > 0, got -1
    """
    from .params import resolve

    full = resolve(params, unit=_number("unit", unit, positive=True, allow_zero=False))
    out = {k: full[k] for k in FOLLOW_DEFAULTS}
    if out["max_iterations"] is None:
        out["max_iterations"] = FOLLOW_DEFAULTS["max_iterations"]
    return out


# ----------------------------------------------------------------------------------------------
# The core
# ----------------------------------------------------------------------------------------------
def _xy(p: ArrayLike, name: str) -> Point:
    a = np.asarray(p, dtype=float).reshape(-1)
    if a.shape != (2,) or not np.all(np.isfinite(a)):
        raise ParameterError(f"{name} must be two finite numbers (x, y), got {p!r}")
    return float(a[0]), float(a[1])


#: Fallback steps when the full step is blocked, in the order tried: the step direction turned by
#: these angles (degrees; every one within 75 degrees of the force, so each is a descent
#: direction), each at these fractions of the step length. The first free one is taken.
_SLIDE_ANGLES = (0.0, 15.0, -15.0, 30.0, -30.0, 45.0, -45.0, 60.0, -60.0, 75.0, -75.0)
_SLIDE_FACTORS = (1.0, 0.5, 0.25, 0.125)
#: ``(cos, sin, factor)`` of every fallback step (the unturned full step, already blocked, left out).
_SLIDES: tuple[tuple[float, float, float], ...] = tuple(
    (math.cos(math.radians(a)), math.sin(math.radians(a)), f)
    for a in _SLIDE_ANGLES for f in _SLIDE_FACTORS if (a, f) != (0.0, 1.0)
)


def _free_step(x: float, y: float, sx: float, sy: float,
               blocked: Callable[[Point, Point], bool]) -> Point | None:
    """The first free fallback of the blocked step ``(sx, sy)`` from ``(x, y)`` (see :data:`_SLIDES`).

    Examples
    --------
    >>> wall = lambda p, q: q[0] > 1.0          # free for x <= 1
    >>> _free_step(0.5, 0.0, 1.0, 0.0, wall)    # shortened to half
    (1.0, 0.0)
    >>> _free_step(1.0, 0.0, 1.0, 0.0, wall) is None   # pressed against the wall
    True
    """
    for c, sn, f in _SLIDES:
        q = (x + f * (c * sx - sn * sy), y + f * (sn * sx + c * sy))
        if not blocked((x, y), q):
            return q
    return None


def descend(
    force: Callable[[Point], tuple[float, float]],
    start: ArrayLike,
    goal: ArrayLike,
    *,
    step_rule: str = "normalized",
    step: float = 0.1,
    alpha: float | tuple[float, float] = 0.1,
    min_speed: float = 0.0,
    tolerance: float = 0.1,
    max_iterations: int = 10_000,
    blocked: Callable[[Point, Point], bool] | None = None,
    potential: Callable[[Point], float] | None = None,
    attraction: Callable[[Point], tuple[float, float]] | None = None,
    navigate: Callable[..., list[Point]] | None = None,
    gradient_threshold: float = 0.0,
    progress_window: int = 200,
    confine_window: int = 20,
    revisit_tolerance: float | None = None,
    escape: str = "none",
    escape_tries: int = 10,
    escape_radius: float = 6.0,
    rng: np.random.Generator | int | None = None,
    append_goal: bool = True,
) -> tuple[NDArray[np.float64], str, int, dict[str, Any]]:
    """Follow the force field ``force`` from ``start`` until a stop rule fires.

    Parameters
    ----------
    force : callable
        ``force((x, y)) -> (fx, fy)``, the force ``F = -grad U`` at a point.
    start, goal : (2,) array_like
        World points.
    step_rule : {"normalized", "scaled"}
    step : float
        Step length of the normalized rule (> 0); also the length unit of the stop rules.
    alpha : float or (float, float)
        Gain of the scaled rule (> 0), or one gain per axis.
    min_speed : float
        Minimum step length of the scaled rule (0: none).
    tolerance : float
        Reached when closer than this to the goal.
    max_iterations : int
        Step budget (escape moves count as steps).
    blocked : callable, optional
        ``blocked((x, y), (x2, y2)) -> bool``: whether the straight move enters an obstacle or
        leaves a walled map. ``None``: nothing blocks.
    potential : callable, optional
        ``potential((x, y)) -> U``; needed by the ``potential_increase`` escape.
    attraction : callable, optional
        The attractive part of the force; needed by the ``potential_increase`` escape.
    navigate : callable, optional
        ``navigate((x, y), final=bool) -> [points]``: the moves of the ``navigation`` escape
        (:class:`gridfield.escapes.NavigationEscape`); needed by that escape.
    gradient_threshold : float
        Local minimum when ``|F| <= gradient_threshold``.
    progress_window : int
        Local minimum when the distance to the goal has not improved over this many steps (0: off).
    confine_window : int
        Local minimum when the last this many steps stayed within a box of 2 steps (a jitter about
        an equilibrium that never exactly revisits a point; 0: off).
    revisit_tolerance : float, optional
        Oscillation when the point is this close to the point two steps back
        (default ``1e-6 * step``; for the scaled rule ``1e-6 * tolerance``).
    escape : {"none", "random_walk", "potential_increase"}
    escape_tries : int
    escape_radius : float
        Maximum jump length ``a`` of the random walk.
    rng : numpy.random.Generator or int, optional
        Random source of the random-walk escape (an int seeds a new Generator).
    append_goal : bool
        Append the goal to the path when reached.

    Returns
    -------
    points : ndarray, shape (N, 2)
    status : str
        ``reached``, ``local_minimum``, ``collision`` or ``max_iterations``.
    iterations : int
        Moves made (steps and escape moves; the appended goal is not counted).
    extra : dict
        ``stop_reason``; ``stall_point`` and ``local_minima`` (every stall point met, escaped or
        not); ``oscillation`` (the two alternating points); ``collision_at``; ``goal_appended``;
        ``escapes_tried``, ``escapes_succeeded`` and ``escapes`` (a log) when escaping.

    Examples
    --------
    A wall across the bowl stops the follower: it shortens its steps up to the wall (never
    into it), then no descent step is free:

    >>> wall = lambda p, q: q[0] >= 2.0
    >>> pts, status, n, extra = descend(lambda p: (3.0 - p[0], 0.0), (0.0, 0.0), (3.0, 0.0),
    ...                                 step=0.5, tolerance=0.3, blocked=wall)
    >>> status, extra["stop_reason"], bool(pts[:, 0].max() < 2.0), extra["blocked_at"][0] >= 2.0
    ('local_minimum', 'blocked', True, True)

    A wrong parameter is named:

    >>> descend(lambda p: (1.0, 0.0), (0, 0), (1, 0), step=0)
    Traceback (most recent call last):
    ...
    gridfield.errors.ParameterError: step must be > 0, got 0
    """
    step_rule = _choice("step_rule", step_rule, STEP_RULES)
    escape = _choice("escape", escape, ESCAPES)
    step = _number("step", step, positive=True, allow_zero=False)
    ax, ay = _alpha(alpha)
    min_speed = _number("min_speed", min_speed, positive=True)
    tolerance = _number("tolerance", tolerance, positive=True, allow_zero=False)
    max_iterations = _integer("max_iterations", max_iterations)
    gradient_threshold = _number("gradient_threshold", gradient_threshold, positive=True)
    progress_window = _integer("progress_window", progress_window)
    confine_window = _integer("confine_window", confine_window)
    if step_rule != "normalized":  # scaled steps shrink where the field is weak: no fixed box to judge by
        confine_window = 0
    escape_tries = _integer("escape_tries", escape_tries)
    escape_radius = _number("escape_radius", escape_radius, positive=True, allow_zero=False)
    normalized = step_rule == "normalized"
    unit = step if normalized else tolerance
    rev_tol = 1e-6 * unit if revisit_tolerance is None else _number("revisit_tolerance", revisit_tolerance,
                                                                        positive=True)
    min_gain = 1e-3 * unit
    same_radius = max(3.0 * unit, tolerance)
    if escape == "potential_increase" and (potential is None or attraction is None):
        raise ParameterError("escape='potential_increase' needs the potential and the attractive force "
                             "(pass potential= and attraction=)")
    if escape == "navigation" and navigate is None:
        raise ParameterError("escape='navigation' follows a grid navigation function: it needs navigate= "
                             "(the grid follower, gridfield.follow.follow, provides it)")
    if escape == "random_walk" and not isinstance(rng, np.random.Generator):
        rng = np.random.default_rng(rng)

    x, y = _xy(start, "start")
    gx, gy = _xy(goal, "goal")
    xs, ys = [x], [y]
    fns: list[float] = []  # |F| at xs[i], ys[i]
    it = 0
    best = math.sqrt((x - gx) * (x - gx) + (y - gy) * (y - gy))
    best_it = 0
    win_min, win_idx = math.inf, 0  # smallest |F| since the last improvement, and where
    status = ""
    extra: dict[str, Any] = {}
    minima: list[list[float]] = []
    log: list[dict[str, Any]] = []
    tried = 0
    slid = 0  # steps shortened or turned because the full step was blocked
    since = 0  # index of the first point of the current descent (after the last escape move)
    box = 2.0 * unit
    pinned = False  # no free descent step from the current point

    def settle(outcome: str, where: list[float] | None = None) -> None:
        """Classify the pending escape (the last one) by how the follower stopped next."""
        if log and log[-1]["outcome"] is None:
            if outcome == "local_minimum" and where is not None:
                frm = log[-1]["from"]
                near = math.hypot(where[0] - frm[0], where[1] - frm[1]) <= same_radius
                outcome = "same_minimum" if near else "other_minimum"
            log[-1]["outcome"] = outcome

    fx = fy = fn = 0.0
    sqrt = math.sqrt
    isinf = math.isinf
    append_x, append_y = xs.append, ys.append
    dx, dy = x - gx, y - gy
    d = sqrt(dx * dx + dy * dy)
    while True:
        if d < tolerance:
            status = "reached"
            extra["stop_reason"] = "goal"
            break
        n = len(xs)
        reason = ""
        stall = -1
        if pinned:
            reason = "blocked"
            stall = n - 1
            pinned = False
        elif n > 2 and sqrt((x - xs[-3]) * (x - xs[-3]) + (y - ys[-3]) * (y - ys[-3])) <= rev_tol:
            reason = "oscillation"
            stall = n - 3 if fns[n - 3] <= fns[n - 2] else n - 2
            extra["oscillation"] = [[xs[n - 2], ys[n - 2]], [x, y]]
        elif (confine_window and n - since > confine_window
              and max(xs[-confine_window - 1:]) - min(xs[-confine_window - 1:]) <= box
              and max(ys[-confine_window - 1:]) - min(ys[-confine_window - 1:]) <= box):
            reason = "confined"
            k0 = n - confine_window - 1
            stall = min(range(k0, n - 1), key=lambda k: fns[k] if fns[k] == fns[k] else math.inf)
        elif progress_window and it - best_it >= progress_window:
            reason = "no_progress"
            stall = win_idx
        else:
            if it >= max_iterations:
                status = "max_iterations"
                extra["stop_reason"] = "max_iterations"
                break
            fx, fy = force((x, y))
            fx, fy = float(fx), float(fy)
            fn = sqrt(fx * fx + fy * fy)
            if len(fns) < n:
                fns.append(fn)
            else:  # recomputed at the same point after a failed escape
                fns[n - 1] = fn
            if fn < win_min:
                win_min, win_idx = fn, n - 1
            if not (fn > gradient_threshold) or isinf(fn):
                reason = "small_gradient" if fn == fn and not isinf(fn) else "undefined_force"
                stall = n - 1

        if reason:
            where = [xs[stall], ys[stall]]
            minima.append(where)
            settle("local_minimum", where)
            if escape == "none" or tried >= escape_tries:
                status = "local_minimum"
                extra["stop_reason"] = reason
                extra["stall_point"] = where
                break
            tried += 1
            again = sum(1 for e in log if math.hypot(e["from"][0] - where[0], e["from"][1] - where[1]) <= same_radius)
            entry: dict[str, Any] = {"from": where, "at_iteration": it, "kind": escape, "outcome": None}
            moves: list[Point] = []
            if escape == "random_walk":
                assert isinstance(rng, np.random.Generator)
                for _ in range(_JUMP_SAMPLES):
                    r = escape_radius * (1.0 - rng.random())
                    th = 2.0 * math.pi * rng.random()
                    q = (x + r * math.cos(th), y + r * math.sin(th))
                    if blocked is None or not blocked((x, y), q):
                        moves.append(q)
                        break
            elif escape == "navigation":
                assert navigate is not None
                for q in navigate((x, y), final=tried >= escape_tries):
                    if blocked is not None and blocked(moves[-1] if moves else (x, y), q):
                        break  # (never: the moves join free cell centres) keep what is free
                    moves.append(q)
            else:
                assert potential is not None and attraction is not None
                fx, fy = force((x, y))
                fax, fay = attraction((x, y))
                ux = float(fx) - float(fax) + 0.05 * float(fax)
                uy = float(fy) - float(fay) + 0.05 * float(fay)
                un = math.hypot(ux, uy)
                u0 = float(potential((x, y)))
                bar = 1.25 ** (again + 1) * u0
                entry["required_potential"] = bar
                if un > 0 and math.isfinite(un):
                    px, py, eps = x, y, unit
                    for _ in range(_ESCAPE_SUBSTEPS):
                        q = (px + eps * ux / un, py + eps * uy / un)
                        if blocked is not None and blocked((px, py), q):
                            moves = []
                            break
                        moves.append(q)
                        px, py = q
                        eps *= 1.25
                        if float(potential(q)) >= bar:
                            break
                    else:
                        moves = []
            if not moves:
                entry["outcome"] = "no_jump"
                log.append(entry)
                continue
            entry["to"] = [moves[-1][0], moves[-1][1]]
            entry["points"] = [len(xs) - 1, len(xs) - 1 + len(moves)]  # the escape's stretch of the path
            log.append(entry)
            for q in moves:
                xs.append(q[0])
                ys.append(q[1])
                fns.append(math.nan)
                it += 1
            x, y = moves[-1]
            dx, dy = x - gx, y - gy
            d = sqrt(dx * dx + dy * dy)
            best, best_it = d, it
            win_min, win_idx = math.inf, len(xs) - 1
            since = len(xs) - 1
            continue

        # -- one step --------------------------------------------------------------------
        if normalized:
            nx = x + step * fx / fn
            ny = y + step * fy / fn
        else:
            sx, sy = ax * fx, ay * fy
            if min_speed > 0.0 and sqrt(sx * sx + sy * sy) < min_speed:
                sx, sy = min_speed * fx / fn, min_speed * fy / fn
            nx, ny = x + sx, y + sy
        if blocked is not None and blocked((x, y), (nx, ny)):
            free = _free_step(x, y, nx - x, ny - y, blocked)
            if free is None:  # no descent step is free: the force presses the follower onto an obstacle
                extra["blocked_at"] = [nx, ny]
                pinned = True
                continue
            nx, ny = free
            slid += 1
        x, y = nx, ny
        append_x(x)
        append_y(y)
        it += 1
        dx, dy = x - gx, y - gy
        d = sqrt(dx * dx + dy * dy)
        if d < best - min_gain:
            best, best_it = d, it
            win_min, win_idx = math.inf, len(xs) - 1

    settle(status)
    extra["slid_steps"] = slid
    if status == "reached" and append_goal and (x, y) != (gx, gy):
        ok = blocked is None or not blocked((x, y), (gx, gy))
        if ok:
            xs.append(gx)
            ys.append(gy)
        elif navigate is not None:  # the straight hop is blocked: down the navigation function instead
            hop = navigate((x, y), final=True)
            if hop and blocked is not None and all(not blocked(a, b) for a, b in zip([(x, y), *hop[:-1]], hop, strict=True)):
                xs.extend(q[0] for q in hop)
                ys.extend(q[1] for q in hop)
                ok = True
        extra["goal_appended"] = ok
    elif status == "reached":
        extra["goal_appended"] = False
    if minima:
        extra["local_minima"] = minima
    if escape != "none":
        extra["escapes_tried"] = tried
        extra["escapes_succeeded"] = sum(1 for e in log if e["outcome"] in ("reached", "other_minimum"))
        extra["escapes"] = log
    if escape == "navigation":
        extra["navigation_segments"] = [e["points"] for e in log if "points" in e]
    return np.column_stack([xs, ys]), status, it, extra


# ----------------------------------------------------------------------------------------------
# Grid samplers (kernels in gridfield._kernels_follow; shared by follow and follow_many)
# ----------------------------------------------------------------------------------------------
def _grid_args(gridmap: GridMap) -> tuple[NDArray[np.bool_], float, float, float]:
    g = gridmap.grid
    occ = np.ascontiguousarray(gridmap.occupied, dtype=np.bool_)
    return occ, float(g.origin[0]), float(g.origin[1]), float(g.resolution)


def _field_arrays(field: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    return (np.ascontiguousarray(field.grad_x, dtype=np.float64),
            np.ascontiguousarray(field.grad_y, dtype=np.float64))


def grid_sampler(field: Any, *, sampling: str = "bilinear") -> Callable[[Point], tuple[float, float]]:
    """``force(p) -> (fx, fy)``: the force ``-grad U`` of a Field at world points, from its arrays.

    ``bilinear`` interpolates among the free corner cells only (renormalized weights) and clamps to
    the grid; ``nearest`` takes the cell containing the point (clamped); obstacle cells give 0.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> gm = GridMap(Grid((2, 3), 1.0), np.array([[False, False, True], [False, False, False]]))
    >>> gx = np.array([[1.0, 3.0, 0.0], [1.0, 3.0, 5.0]])
    >>> f = grid_sampler(SimpleNamespace(map=gm, grad_x=gx, grad_y=np.zeros((2, 3))))
    >>> f((1.0, 1.0))   # halfway between the centres 0.5 and 1.5: -(1 + 3) / 2
    (-2.0, -0.0)
    >>> f((2.0, 0.5))   # the obstacle cell (row 0, col 2) is left out
    (-3.0, -0.0)
    """
    _choice("sampling", sampling, SAMPLINGS)
    gx, gy = _field_arrays(field)
    occ, x0, y0, res = _grid_args(field.map)
    nearest = sampling == "nearest"
    kern = _direct(_force_at, gx, gy, occ, x0, y0, res, nearest, x0, y0)

    def force(p: Point) -> tuple[float, float]:
        return kern(gx, gy, occ, x0, y0, res, nearest, p[0], p[1])

    return force


def sample_force(field: Any, points: ArrayLike, *, sampling: str = "bilinear") -> NDArray[np.float64]:
    """The force ``-grad U`` of a Field at many world points at once, sampled like :func:`grid_sampler`.

    One compiled pass over the points: use it rather than a Python loop over ``grid_sampler`` calls
    when the points are known together (a quiver plot, a batch of robot positions, a trajectory).

    Parameters
    ----------
    field : Field
        From :func:`gridfield.potential.build_field` (anything with ``map``, ``grad_x``, ``grad_y``).
    points : array_like, shape (N, 2) or (2,)
        World points ``(x, y)``; they must be finite. Points outside the grid are clamped to it.
    sampling : {"bilinear", "nearest"}

    Returns
    -------
    ndarray, shape (N, 2)
        ``(fx, fy)`` per point; 0 in obstacle cells.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> gm = GridMap(Grid((2, 3), 1.0), np.array([[False, False, True], [False, False, False]]))
    >>> gx = np.array([[1.0, 3.0, 0.0], [1.0, 3.0, 5.0]])
    >>> sample_force(SimpleNamespace(map=gm, grad_x=gx, grad_y=np.zeros((2, 3))), [[1.0, 1.0], [2.0, 0.5]])
    array([[-2., -0.],
           [-3., -0.]])
    """
    _choice("sampling", sampling, SAMPLINGS)
    pts = _as_points(points)
    if not np.isfinite(pts).all():
        k = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise ParameterError(f"points must be finite; point {k} is {pts[k].tolist()}")
    gx, gy = _field_arrays(field)
    occ, x0, y0, res = _grid_args(field.map)
    xs, ys = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
    fx, fy = np.empty(len(pts)), np.empty(len(pts))
    if len(pts):
        _force_many(gx, gy, occ, x0, y0, res, sampling == "nearest", xs, ys, fx, fy)
    return np.stack([fx, fy], axis=1)


def grid_potential_sampler(field: Any, *, sampling: str = "bilinear") -> Callable[[Point], float]:
    """``potential(p) -> U`` sampled like :func:`grid_sampler` (free corners only)."""
    _choice("sampling", sampling, SAMPLINGS)
    u = np.ascontiguousarray(field.potential, dtype=np.float64)
    occ, x0, y0, res = _grid_args(field.map)
    kern = _direct(_nearest2 if sampling == "nearest" else _bilinear2, u, u, occ, x0, y0, res, x0, y0)

    def potential(p: Point) -> float:
        return kern(u, u, occ, x0, y0, res, p[0], p[1])[0]

    return potential


def grid_blocked(gridmap: GridMap) -> Callable[[Point, Point], bool]:
    """``blocked(p, q)``: whether the segment ``p -> q`` crosses an occupied cell or leaves a walled map.

    The cells are walked exactly (a segment through a cell corner checks both side cells). Outside
    an open-border grid is free.

    Examples
    --------
    >>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
    >>> b = grid_blocked(GridMap(Grid((3, 3), 1.0), occ))
    >>> b((0.5, 0.5), (2.5, 0.5)), b((0.5, 0.5), (2.5, 2.5)), b((0.5, 1.5), (-1.0, 1.5))
    (False, True, False)
    >>> bw = grid_blocked(GridMap(Grid((3, 3), 1.0, border="wall"), occ))
    >>> bw((0.5, 1.5), (-1.0, 1.5))
    True
    """
    occ, x0, y0, res = _grid_args(gridmap)
    wall = gridmap.grid.border == "wall"
    kern = _direct(_segment_blocked, occ, x0, y0, res, wall, x0, y0, x0, y0)

    def blocked(p: Point, q: Point) -> bool:
        return kern(occ, x0, y0, res, wall, p[0], p[1], q[0], q[1])

    return blocked


# ----------------------------------------------------------------------------------------------
# Following a Field
# ----------------------------------------------------------------------------------------------
def attraction_force(goal: ArrayLike, params: Mapping[str, Any]) -> Callable[[Point], tuple[float, float]]:
    """``attraction(p) -> (fx, fy)``: the attractive force of the potential models at a point.

    ``model="khatib"``: ``-grad`` of :mod:`gridfield.potential`'s quadratic / combined / conic
    attractive potential (``zeta``, ``d_star``); ``model="vortex"``: ``-ka * (p - goal)``.

    Examples
    --------
    >>> f = attraction_force((0.0, 0.0), {"zeta": 2.0, "d_star": 1.0})
    >>> f((0.5, 0.0)), f((4.0, 0.0))
    ((-1.0, -0.0), (-2.0, -0.0))
    """
    gx, gy = _xy(goal, "goal")
    if params.get("model", "khatib") == "vortex":
        ka = float(params.get("ka", 25.0))

        def vortex_attr(p: Point) -> tuple[float, float]:
            return -ka * (p[0] - gx), -ka * (p[1] - gy)

        return vortex_attr
    zeta = float(params.get("zeta", 1.0))
    d_star = float(params.get("d_star", math.inf))

    def attr(p: Point) -> tuple[float, float]:
        dx, dy = p[0] - gx, p[1] - gy
        d = math.sqrt(dx * dx + dy * dy)
        if d == 0.0:
            return 0.0, 0.0
        if d_star == 0.0:  # pure conic (potential.py's separate case)
            return -zeta * dx / d, -zeta * dy / d
        if d <= d_star:
            return -zeta * dx, -zeta * dy
        return -d_star * zeta * dx / d, -d_star * zeta * dy / d

    return attr


def _vortex_norms(field: Any, params: Mapping[str, Any]) -> tuple[float, float]:
    """Matrix 2-norms of seed 003's force components ``fX``, ``fY`` over the whole lattice.

    The seed's arrays are defined everywhere, inside the circles too, while a Field holds zeros on
    obstacle cells; the norms are therefore taken from the same field rebuilt on the lattice without
    occupancy (when the field's map carries its world), else from the field's own arrays.
    """
    from .world import World

    world = getattr(field.map, "world", None)
    gx, gy = field.grad_x, field.grad_y
    if isinstance(world, World) and world.start is not None:
        from .potential import vortex_field

        open_map = GridMap(field.map.grid, np.zeros(field.map.grid.shape, bool))
        full = vortex_field(open_map, world, world.start, field.goal, ka=float(params.get("ka", 25.0)),
                            kr=float(params.get("kr", 30.0)), ko=float(params.get("ko", 5.0)),
                            sample_radius=params.get("sample_radius"))
        gx, gy = full.grad_x, full.grad_y
    nx = float(np.linalg.norm(np.asarray(gx, dtype=float), 2))
    ny = float(np.linalg.norm(np.asarray(gy, dtype=float), 2))
    if not (nx > 0 and ny > 0 and math.isfinite(nx) and math.isfinite(ny)):
        raise GridfieldError(f"the vortex field's force components have matrix norms {nx:g}, {ny:g}; "
                             "cannot scale the steps (seed 003's follower divides by them)")
    return nx, ny


@dataclass(frozen=True)
class _Setup:
    params: dict[str, Any]
    kwargs: dict[str, Any]
    sampling: str
    vortex: bool


def _setup(field: Any, params: Mapping[str, Any] | None) -> _Setup:
    """Resolve the follower parameters for a Field (with seed 003's follower for the vortex model)."""
    merged = dict(field.params or {})
    merged.update(params or {})
    grid: Grid = field.map.grid
    vortex = merged.get("model", "khatib") == "vortex"
    if vortex:
        # Seed 003's nearest-node follower: x += spacing * (Fx / ||fX||_2, Fy / ||fY||_2), where
        # ||.||_2 is the matrix 2-norm (largest singular value) of each force component's array.
        spacing = float(merged.get("spacing", grid.resolution))
        merged.setdefault("sampling", "nearest")
        merged.setdefault("tolerance", 0.4)
        merged.setdefault("confine_window", 0)  # seed 003's follower: no jitter rule
        merged["step_rule"] = "scaled"
        nx, ny = _vortex_norms(field, merged)
        merged["alpha"] = (spacing / nx, spacing / ny)
    if merged.get("max_iterations") is None:  # enough to cross every free cell once
        merged["max_iterations"] = max(FOLLOW_DEFAULTS["max_iterations"], int(np.count_nonzero(~field.map.occupied)))
    p = resolve_follow_params(merged, unit=grid.resolution)
    out = dict(merged)
    out.update(p)
    kwargs = {k: p[k] for k in ("step_rule", "step", "alpha", "min_speed", "tolerance", "max_iterations",
                                "gradient_threshold", "progress_window", "confine_window", "escape", "escape_tries",
                                "escape_radius")}
    return _Setup(out, kwargs, p["sampling"], vortex)


def _distance_at(field: Any, points: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Brushfire (Euclidean) distance of the cells containing the points (clamped to the grid), and
    whether each point lies inside the grid."""
    dmap = getattr(field, "distance", None)
    if dmap is None:
        from .brushfire import brushfire

        dmap = brushfire(field.map, metric="euclidean")
    dist = np.ascontiguousarray(dmap.distance, dtype=np.float64)
    grid: Grid = field.map.grid
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    out = np.empty(len(pts))
    inside = np.empty(len(pts), np.bool_)
    _cell_values(dist, grid.origin[0], grid.origin[1], grid.resolution, pts[:, 0].copy(), pts[:, 1].copy(), out,
                 inside)
    return out, inside


def _clearance(field: Any, points: NDArray[np.float64]) -> float:
    """Smallest brushfire distance at the cells of the path's points."""
    return float(np.min(_distance_at(field, points)[0])) if len(points) else math.nan


def _note_outside(extra: dict[str, Any], grid: Grid, pts: NDArray[np.float64]) -> None:
    """Record when the follower left an open-border grid (where the field is only clamped)."""
    outside = ~grid.contains(pts)
    if outside.any():
        extra["left_map"] = True
        extra["outside_fraction"] = float(outside.mean())


def follow(field: Any, start: ArrayLike, *, params: Mapping[str, Any] | None = None,
           navigation: Any = None) -> Path:
    """Follow a Field's force from ``start`` to its goal with :func:`descend`.

    Parameters
    ----------
    field : gridfield.potential.Field
    start : (2,) array_like
        World point in a free cell of the field's map.
    params : mapping, optional
        Follower parameters (:data:`FOLLOW_DEFAULTS`); the field's own params are the base.
    navigation : gridfield.escapes.NavigationEscape, optional
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
    goal = _xy(field.goal, "goal")
    p = setup.params
    force = grid_sampler(field, sampling=setup.sampling)
    blocked = grid_blocked(grid_map)
    potential = attraction = navigate = None
    if p["escape"] == "navigation":
        from .escapes import NavigationEscape

        navigate = navigation if navigation is not None else NavigationEscape(field)
    if p["escape"] == "potential_increase":
        potential = grid_potential_sampler(field, sampling=setup.sampling)
        attraction = attraction_force(goal, p)
    t0 = time.perf_counter()
    pts, status, n, extra = descend(force, s, goal, blocked=blocked, potential=potential, attraction=attraction,
                                    navigate=navigate, rng=np.random.default_rng(p["seed"]), **setup.kwargs)
    seconds = time.perf_counter() - t0
    extra["sampling"] = setup.sampling
    _note_outside(extra, grid_map.grid, pts)
    if setup.vortex:
        extra["alpha_xy"] = list(setup.kwargs["alpha"]) if isinstance(setup.kwargs["alpha"], tuple) else None
    return Path(pts, status, "potential", iterations=n, params=p, seconds=seconds,
                min_clearance=_clearance(field, pts), extra=extra)


#: Maps up to this many cells get the reachability check before any work (a labelling of the free
#: space, about 30 ms at 2048^2); larger ones only when a run does not reach the goal.
_REACH_FIRST_CELLS = 1 << 22


def _same_component(gridmap: GridMap, start: Point, goal: Point, cache: dict[Any, Any] | None) -> bool:
    """Whether ``start`` and ``goal`` lie in one 4-connected free region of the navigation map (a
    diagonal move that cuts no corner is two orthogonal ones, so this is the wavefront's rule)."""
    from scipy import ndimage

    from .escapes import navigation_map

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
    """The ``potential`` planner: build the field (:func:`gridfield.potential.build_field`), follow it.

    A goal that cannot be reached from the start (no free path joins them) ends as ``no_path`` at
    once, with a hint. A run that does not reach the goal carries ``extra["hint"]`` and
    ``extra["diagnosis"]`` (:func:`gridfield.diagnose.diagnose`).

    ``Path.seconds`` is the following time; ``extra["build_seconds"]`` the field's build time;
    ``Path.params`` the resolved potential and follower parameters. With a ``cache`` dict, the
    brushfire of ``gridmap`` (per metric and saturation) and its free regions are computed once and
    reused by later calls (batch sweeps: many goals and gains on one map).
    """
    from .diagnose import diagnose, unreachable_hint
    from .escapes import NavigationEscape
    from .potential import build_field, field_distance_map, resolve_params

    params = dict(params or {})
    s, g = _xy(start, "start"), _xy(goal, "goal")
    t0 = time.perf_counter()
    resolved = resolve_params(params, unit=gridmap.grid.resolution)
    vortex = resolved["model"] == "vortex"
    if not vortex and gridmap.grid.rows * gridmap.grid.cols <= _REACH_FIRST_CELLS and not _same_component(gridmap, s, g, cache):
        merged = {**resolved, **resolve_follow_params(params, unit=gridmap.grid.resolution)}
        return Path(np.array([s]), "no_path", "potential", params=merged, seconds=0.0,
                    extra={"stop_reason": "unreachable", "hint": unreachable_hint(s, g),
                           "diagnosis": {"reachable": False}, "build_seconds": time.perf_counter() - t0})
    dmap = None
    if cache is not None and not vortex:
        key = ("brushfire", gridmap, resolved["metric"], resolved["saturate"])
        if key not in cache:
            cache[key] = field_distance_map(gridmap, resolved)
        dmap = cache[key]
    field = build_field(gridmap, g, params, dmap=dmap)
    if cache is not None:  # the latest field, for planners.plan(..., return_field=True)
        cache["field"] = field
    build = time.perf_counter() - t0
    esc = None if vortex else NavigationEscape(field)
    path = follow(field, s, params=params, navigation=esc)
    merged = dict(resolved)
    merged.update(path.params)
    extra = dict(path.extra)
    extra["build_seconds"] = build
    status = path.status
    points = path.points
    if status != "reached" and esc is not None:
        diag = diagnose(path, field, esc)
        if not math.isfinite(esc.value(s)):  # large maps: found unreachable only now
            diag = {"reachable": False, "hint": unreachable_hint(s, g)}
            status, points = "no_path", points[:1]
            extra["stop_reason"] = "unreachable"
        extra["hint"] = diag["hint"]
        extra["diagnosis"] = diag
    return replace(path, points=points, status=status, params=merged, extra=extra)


# ----------------------------------------------------------------------------------------------
# Many starts at once
# ----------------------------------------------------------------------------------------------
_CODES = ("", "reached", "local_minimum", "collision", "max_iterations")


def follow_many(field: Any, starts: ArrayLike, *, params: Mapping[str, Any] | None = None,
                keep_paths: bool = True) -> list[Path]:
    """Follow a Field from many starts at once (numpy over the points at every step).

    Each point runs the same step and stop rules as :func:`follow` and stops independently; the
    result equals ``[follow(field, s, params=params) for s in starts]`` (escapes are run by
    :func:`follow` for the points that stall, after the batch).

    Parameters
    ----------
    field : gridfield.potential.Field
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
    p, kw = setup.params, setup.kwargs
    grid_map: GridMap = field.map
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
    goal = _xy(field.goal, "goal")
    gx, gy = _field_arrays(field)
    occ, x0, y0, res = _grid_args(grid_map)
    nearest = setup.sampling == "nearest"
    wall = grid_map.grid.border == "wall"
    normalized = kw["step_rule"] == "normalized"
    step, tol, max_it = kw["step"], kw["tolerance"], kw["max_iterations"]
    ax, ay = _alpha(kw["alpha"])
    min_speed, thr, window = kw["min_speed"], kw["gradient_threshold"], kw["progress_window"]
    cw = kw["confine_window"] if normalized else 0
    unit = step if normalized else tol
    rev_tol, min_gain = 1e-6 * unit, 1e-3 * unit

    t0 = time.perf_counter()
    N = len(S)
    ids = np.arange(N)  # original index of each active point
    X, Y = S[:, 0].copy(), S[:, 1].copy()
    P1x = np.full(N, np.nan)  # position one and two steps back
    P1y = np.full(N, np.nan)
    P2x = np.full(N, np.nan)
    P2y = np.full(N, np.nan)
    F1 = np.full(N, np.nan)  # |F| one and two steps back
    F2 = np.full(N, np.nan)
    best = np.sqrt((X - goal[0]) * (X - goal[0]) + (Y - goal[1]) * (Y - goal[1]))
    best_it = np.zeros(N, np.int64)
    win_min = np.full(N, np.inf)
    win_x, win_y = X.copy(), Y.copy()
    # the last cw + 1 positions and their |F| (column = iteration mod cw + 1), for the confined rule
    RX = np.empty((N, cw + 1))
    RY = np.empty((N, cw + 1))
    RF = np.full((N, cw + 1), np.nan)
    RX[:, 0], RY[:, 0] = X, Y
    box = 2.0 * unit
    hist_x = [X.copy()] if keep_paths else []
    hist_y = [Y.copy()] if keep_paths else []
    hist_ids = [ids.copy()] if keep_paths else []
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
        idx = ids[mask]
        code[idx] = c
        reason[idx] = why
        end_it[idx] = it
        last[idx, 0], last[idx, 1] = X[mask], Y[mask]

    while len(ids):
        dx, dy = X - goal[0], Y - goal[1]
        d = np.sqrt(dx * dx + dy * dy)
        done = d < tol
        finish(done, 1, "goal")
        ox, oy = X - P2x, Y - P2y
        osc_m = ~done & (np.sqrt(ox * ox + oy * oy) <= rev_tol)
        if osc_m.any():
            idx = ids[osc_m]
            first = F2[osc_m] <= F1[osc_m]
            stall[idx, 0] = np.where(first, P2x[osc_m], P1x[osc_m])
            stall[idx, 1] = np.where(first, P2y[osc_m], P1y[osc_m])
            osc[idx, 0, 0], osc[idx, 0, 1] = P1x[osc_m], P1y[osc_m]
            osc[idx, 1, 0], osc[idx, 1, 1] = X[osc_m], Y[osc_m]
            finish(osc_m, 2, "oscillation")
        done |= osc_m
        if cw and it >= cw:
            cf_m = ~done & (np.ptp(RX, axis=1) <= box) & (np.ptp(RY, axis=1) <= box)
            if cf_m.any():
                order = (np.arange(it - cw, it) % (cw + 1))  # the stretch's points before the current one
                fk = np.where(np.isnan(RF[cf_m][:, order]), np.inf, RF[cf_m][:, order])
                k = order[np.argmin(fk, axis=1)]
                rows = np.flatnonzero(cf_m)
                idx = ids[cf_m]
                stall[idx, 0], stall[idx, 1] = RX[rows, k], RY[rows, k]
                finish(cf_m, 2, "confined")
            done |= cf_m
        if window:
            np_m = ~done & (it - best_it >= window)
            if np_m.any():
                idx = ids[np_m]
                stall[idx, 0], stall[idx, 1] = win_x[np_m], win_y[np_m]
                finish(np_m, 2, "no_progress")
            done |= np_m
        if it >= max_it:
            finish(~done, 4, "max_iterations")
            break
        keep = ~done
        if not keep.all():
            ids, X, Y = ids[keep], X[keep], Y[keep]
            P1x, P1y, P2x, P2y, F1, F2 = P1x[keep], P1y[keep], P2x[keep], P2y[keep], F1[keep], F2[keep]
            best, best_it, win_min, win_x, win_y = best[keep], best_it[keep], win_min[keep], win_x[keep], win_y[keep]
            RX, RY, RF = RX[keep], RY[keep], RF[keep]
            if not len(ids):
                break
        n = len(ids)
        fx, fy = FX[:n], FY[:n]
        _force_many(gx, gy, occ, x0, y0, res, nearest, X, Y, fx, fy)
        fn = np.sqrt(fx * fx + fy * fy)
        RF[:, it % (cw + 1)] = fn
        upd = fn < win_min
        win_min = np.where(upd, fn, win_min)
        win_x = np.where(upd, X, win_x)
        win_y = np.where(upd, Y, win_y)
        bad = ~(fn > thr) | np.isinf(fn)
        if bad.any():
            idx = ids[bad]
            stall[idx, 0], stall[idx, 1] = X[bad], Y[bad]
            finish(bad, 2, "small_gradient")
            reason[ids[bad & ~np.isfinite(fn)]] = "undefined_force"
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            if normalized:
                NX = X + step * fx / fn
                NY = Y + step * fy / fn
            else:
                sx, sy = ax * fx, ay * fy
                if min_speed > 0.0:
                    short = np.sqrt(sx * sx + sy * sy) < min_speed
                    sx = np.where(short, min_speed * fx / fn, sx)
                    sy = np.where(short, min_speed * fy / fn, sy)
                NX, NY = X + sx, Y + sy
        NX = np.where(bad, X, NX)
        NY = np.where(bad, Y, NY)
        ob = out_b[:n]
        _blocked_many(occ, x0, y0, res, wall, X, Y, NX, NY, ob)
        hit = ob & ~bad
        if hit.any():  # the fallback steps of descend, in the same order, for the blocked points
            todo = np.flatnonzero(hit)
            SX, SY = NX[todo] - X[todo], NY[todo] - Y[todo]
            for c, sn, f in _SLIDES:
                k = len(todo)
                CX = X[todo] + f * (c * SX - sn * SY)
                CY = Y[todo] + f * (sn * SX + c * SY)
                cb = np.empty(k, np.bool_)
                _blocked_many(occ, x0, y0, res, wall, X[todo], Y[todo], CX, CY, cb)
                freed = ~cb
                NX[todo[freed]], NY[todo[freed]] = CX[freed], CY[freed]
                slid[ids[todo[freed]]] += 1
                todo, SX, SY = todo[cb], SX[cb], SY[cb]
                if not len(todo):
                    break
            pinned = np.zeros(n, np.bool_)
            pinned[todo] = True
            if len(todo):
                idx = ids[pinned]
                coll[idx, 0], coll[idx, 1] = NX[pinned], NY[pinned]
                stall[idx, 0], stall[idx, 1] = X[pinned], Y[pinned]
                finish(pinned, 2, "blocked")
            hit = pinned
        move = ~(bad | hit)
        P2x, P2y, P1x, P1y = P1x, P1y, X, Y
        F2, F1 = F1, fn
        X = np.where(move, NX, X)
        Y = np.where(move, NY, Y)
        it += 1
        if not move.all():
            ids, X, Y = ids[move], X[move], Y[move]
            P1x, P1y, P2x, P2y, F1, F2 = P1x[move], P1y[move], P2x[move], P2y[move], F1[move], F2[move]
            best, best_it, win_min, win_x, win_y = best[move], best_it[move], win_min[move], win_x[move], win_y[move]
            RX, RY, RF = RX[move], RY[move], RF[move]
        RX[:, it % (cw + 1)], RY[:, it % (cw + 1)] = X, Y
        RF[:, it % (cw + 1)] = np.nan
        if keep_paths:  # X, Y, ids are fresh arrays every step (never written in place)
            hist_x.append(X)
            hist_y.append(Y)
            hist_ids.append(ids)
        dx, dy = X - goal[0], Y - goal[1]
        d = np.sqrt(dx * dx + dy * dy)
        imp = d < best - min_gain
        best = np.where(imp, d, best)
        best_it = np.where(imp, it, best_it)
        win_min = np.where(imp, np.inf, win_min)
        win_x = np.where(imp, X, win_x)
        win_y = np.where(imp, Y, win_y)
    seconds = time.perf_counter() - t0

    # paths: hist[k] holds the positions after k moves of the points still moving then; a stable
    # sort by point id lists each point's positions in step order
    if keep_paths:
        HI = np.concatenate(hist_ids)
        order = np.argsort(HI, kind="stable")
        HX, HY = np.concatenate(hist_x)[order], np.concatenate(hist_y)[order]
        first = np.concatenate([[0], np.cumsum(np.bincount(HI, minlength=N))[:-1]])
        del HI, order, hist_x, hist_y, hist_ids
    blocked = grid_blocked(grid_map)
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
        extra: dict[str, Any] = {"stop_reason": reason[i], "slid_steps": int(slid[i]), "sampling": setup.sampling}
        if status == "reached":
            lx, ly = float(last[i, 0]), float(last[i, 1])
            if (lx, ly) != goal:
                ok_i = not blocked((lx, ly), goal)
                if ok_i:
                    pts = np.vstack([pts, goal])
                extra["goal_appended"] = ok_i
            else:
                extra["goal_appended"] = False
        elif status == "local_minimum":
            extra["stall_point"] = stall[i].tolist()
            extra["local_minima"] = [stall[i].tolist()]
            if reason[i] == "oscillation":
                extra["oscillation"] = osc[i].tolist()
            elif reason[i] == "blocked":
                extra["blocked_at"] = coll[i].tolist()
        pts_list.append(pts)
        extras.append(extra)
    # clearance and the outside-the-map note for all paths at once
    lengths = np.array([len(q) for q in pts_list])
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    all_pts = np.concatenate(pts_list)
    dist, inside = _distance_at(field, all_pts)
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


# ----------------------------------------------------------------------------------------------
# Basins of attraction
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Basins:
    """Where discrete steepest descent on a potential array ends, for every free cell.

    Attributes
    ----------
    grid : Grid
    label : ndarray of int32, the grid's shape
        0 on obstacles, 1 for cells whose descent ends where the goal cell's descent ends,
        ``k >= 2`` for the other sinks (local minima), numbered by increasing potential.
    minima : ndarray, shape (K, 2)
        World point (cell centre) of the sink of label ``k`` at row ``k - 1``.
    sink : ndarray of intp, the grid's shape
        Flat index of the sink each cell descends to (-1 on obstacles).
    goal_cell : (int, int)
        ``(row, col)`` of the cell containing the goal.
    """

    grid: Grid
    label: NDArray[np.int32]
    minima: NDArray[np.float64]
    sink: NDArray[np.intp]
    goal_cell: tuple[int, int]

    def __repr__(self) -> str:
        return f"Basins(shape={self.grid.shape}, basins={len(self.minima)}, goal_fraction={self.goal_fraction:.3g})"

    @property
    def goal_fraction(self) -> float:
        """Fraction of the free cells that descend to the goal."""
        free = self.label > 0
        return float((self.label[free] == 1).mean()) if free.any() else math.nan


_NEIGHBOURS = ((-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1))


def descent_successor(potential: NDArray[np.float64], free: NDArray[np.bool_]) -> NDArray[np.intp]:
    """Flat index of each cell's steepest-descent successor: its lowest free 8-neighbour if lower than
    itself (ties: the first in row-major neighbour order), else the cell itself (a sink; also obstacles).

    A diagonal neighbour counts only when both cells beside the diagonal are free too: the move
    between the centres passes their common corner, and the follower never touches an obstacle.

    Examples
    --------
    >>> u = np.array([[3.0, 2.0, 1.0], [4.0, 5.0, 0.5]])
    >>> descent_successor(u, np.ones(u.shape, bool)).reshape(u.shape)
    array([[1, 5, 5],
           [1, 5, 5]])
    """
    u = np.where(free, np.asarray(potential, dtype=float), np.inf)
    u = np.where(np.isnan(u), np.inf, u)
    rows, cols = u.shape
    pad = np.pad(u, 1, constant_values=np.inf)
    fpad = np.pad(np.asarray(free, dtype=bool), 1, constant_values=False)
    best = u.copy()
    succ = np.arange(rows * cols, dtype=np.intp).reshape(rows, cols)
    r, c = np.indices((rows, cols))
    for dr, dc in _NEIGHBOURS:
        nb = pad[1 + dr: 1 + dr + rows, 1 + dc: 1 + dc + cols]
        if dr and dc:  # a diagonal move passes the corner of both side cells: both must be free
            side = fpad[1 + dr: 1 + dr + rows, 1: 1 + cols] & fpad[1: 1 + rows, 1 + dc: 1 + dc + cols]
            nb = np.where(side, nb, np.inf)
        lower = nb < best
        best = np.where(lower, nb, best)
        succ = np.where(lower, (r + dr) * cols + (c + dc), succ)
    succ = np.where(free, succ, np.arange(rows * cols).reshape(rows, cols))
    return succ.reshape(-1)


def basins(field: Any) -> Basins:
    """Basins of attraction of discrete steepest descent on ``field.potential`` (no loop over cells).

    Each free cell moves to its lowest 8-neighbour while that is lower (:func:`descent_successor`);
    the sink of every cell is found by pointer jumping (``succ = succ[succ]``, at most
    ``log2(cells) + 1`` rounds).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> g = Grid((1, 7), 1.0)
    >>> u = np.array([[2.0, 1.0, 2.0, 3.0, 1.5, 0.0, 1.0]])
    >>> f = SimpleNamespace(map=GridMap(g, np.zeros(g.shape, bool)), potential=u, goal=(5.5, 0.5))
    >>> b = basins(f)
    >>> b.label.tolist(), b.minima.tolist()
    ([[2, 2, 2, 1, 1, 1, 1]], [[5.5, 0.5], [1.5, 0.5]])
    """
    grid: Grid = field.map.grid
    free = ~np.asarray(field.map.occupied, dtype=bool)
    succ = descent_successor(np.asarray(field.potential, dtype=float), free)
    for _ in range(math.ceil(math.log2(max(succ.size, 2))) + 1):
        nxt = succ[succ]
        if np.array_equal(nxt, succ):
            break
        succ = nxt
    flat_free = free.reshape(-1)
    sink = np.where(flat_free, succ, -1)
    cells, _ = grid.world_to_cell(np.asarray(field.goal, dtype=float))
    gr = int(np.clip(cells[0, 0], 0, grid.rows - 1))
    gc = int(np.clip(cells[0, 1], 0, grid.cols - 1))
    goal_flat = gr * grid.cols + gc
    goal_sink = int(succ[goal_flat]) if flat_free[goal_flat] else -1
    sinks = np.unique(sink[flat_free])
    u = np.asarray(field.potential, dtype=float).reshape(-1)
    others = sinks[sinks != goal_sink]
    others = others[np.lexsort((others, u[others]))]
    order = np.concatenate([[goal_sink], others]) if goal_sink >= 0 else others
    lab_of = np.zeros(grid.rows * grid.cols + 1, np.int32)  # last slot: obstacles (-1)
    start_label = 1 if goal_sink >= 0 else 2
    lab_of[order] = np.arange(start_label, start_label + len(order), dtype=np.int32)
    label = lab_of[sink].reshape(grid.shape)
    label[~free] = 0
    rr, cc = np.divmod(order, grid.cols)
    minima = grid.cell_to_world(np.stack([rr, cc], axis=1)) if len(order) else np.zeros((0, 2))
    if goal_sink < 0:  # the goal lies in an obstacle cell: no basin 1
        minima = np.vstack([np.full((1, 2), np.nan), minima])
    return Basins(grid, label, minima, sink.reshape(grid.shape), (gr, gc))
