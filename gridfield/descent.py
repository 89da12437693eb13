"""The follower's specification: step rules, stop rules and local-minimum escapes (:func:`descend`).

One core, :func:`descend`, holds the step and stop logic. It sees the field only through two
callables, ``force(p) -> (fx, fy)`` and ``blocked(p, q) -> bool``, so the grid follower
(:func:`gridfield.follow.follow`, fields sampled from gradient arrays by
:mod:`gridfield.sampling`) and the exact planner
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
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import ParameterError
from .escapes import navigation_finish, navigation_moves, potential_increase, random_jump
from .grid import _as_xy
from .params import REGISTRY, check

__all__ = ["ESCAPES", "STEP_RULES", "descend"]

#: The step rules and the escapes (the registry's choices for ``step_rule`` and ``escape``).
STEP_RULES: tuple[str, ...] = REGISTRY["step_rule"].choices
ESCAPES: tuple[str, ...] = REGISTRY["escape"].choices

Point = tuple[float, float]


def _gains(alpha: Any) -> tuple[float, float]:
    """The scaled rule's gain ``alpha`` (a number, or a pair per axis) as ``(ax, ay)``, checked."""
    a = check("alpha", tuple(alpha.tolist()) if isinstance(alpha, np.ndarray) else alpha)
    return a if isinstance(a, tuple) else (a, a)


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
    escape : {"none", "random_walk", "potential_increase", "navigation"}
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
    gridfield.errors.ParameterError: step must be a finite number > 0, got 0
    """
    step_rule = check("step_rule", step_rule)
    escape = check("escape", escape)
    step = check("step", step)
    ax, ay = _gains(alpha)
    min_speed = check("min_speed", min_speed)
    tolerance = check("tolerance", tolerance)
    max_iterations = check("max_iterations", max_iterations)
    gradient_threshold = check("gradient_threshold", gradient_threshold)
    progress_window = check("progress_window", progress_window)
    confine_window = check("confine_window", confine_window)
    if step_rule != "normalized":  # scaled steps shrink where the field is weak: no fixed box to judge by
        confine_window = 0
    escape_tries = check("escape_tries", escape_tries)
    escape_radius = check("escape_radius", escape_radius)
    normalized = step_rule == "normalized"
    unit = step if normalized else tolerance
    rev_tol = 1e-6 * unit if revisit_tolerance is None else check("revisit_tolerance", revisit_tolerance,
                                                                       minimum=0.0)
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

    x, y = _as_xy(start, "start")
    gx, gy = _as_xy(goal, "goal")
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
            moves: list[Point]
            if escape == "random_walk":
                assert isinstance(rng, np.random.Generator)
                moves = random_jump(x, y, escape_radius, rng, blocked)
            elif escape == "navigation":
                assert navigate is not None
                moves = navigation_moves(navigate, x, y, final=tried >= escape_tries, blocked=blocked)
            else:
                assert potential is not None and attraction is not None
                moves, entry["required_potential"] = potential_increase(
                    x, y, force, attraction, potential, first_step=unit, repeat=again, blocked=blocked)
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
            hop = navigation_finish(navigate, x, y, blocked)
            if hop is not None:
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
