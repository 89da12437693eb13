"""The follower's specification: step rules, stop rules and local-minimum escapes (:func:`descend`).

The rules are written once, as the methods of :class:`Rules` (resolved from the parameters by
:func:`rules`): each takes floats or numpy arrays alike, so the scalar follower :func:`descend` and
the batch follower :func:`gridfield.following.follower.follow_many` run the same code, and the end of a
reached run is the one function :func:`goal_hop`. :func:`descend` sees the field only through
callables, ``force(p) -> (fx, fy)`` and ``blocked(p, q) -> bool``, so the grid follower
(:func:`gridfield.following.follower.follow`, fields sampled from gradient arrays by
:mod:`gridfield.fields.sampling`) and the exact planner
(:func:`gridfield.exact.continuous.plan_exact_potential`, forces from exact obstacle distances) share it; it
returns a :class:`~gridfield.core.path.Path`. ``tests/test_follower_spec.py`` checks that both followers
give the same points, status and details for every step rule, sampling, border, stop rule and
escape.

Step rules (names: Choset et al. ch. 4; registry: gridfield.core.params)
    ``normalized``: ``x += step * F/|F|`` (the classic Khatib-potential follower).
    ``scaled``: ``x += alpha * F``; with ``min_speed > 0`` a step shorter than ``min_speed`` is
    stretched to ``min_speed`` along ``F`` (the saturated-potential follower of the configuration-space
    explorer). ``alpha`` may be a pair ``(ax, ay)`` (used by the vortex field's nearest-node follower,
    whose x and y steps are scaled by different constants).

Stop rules, checked in this order before every step
    ``reached``: the current point is closer than ``tolerance`` to the goal (the reference
    follower's ``norm(x - Xf) < 0.1``). The goal itself is then appended to the path, as its
    ``P = [P Xf]`` does (unless that last hop is blocked; ``extra["goal_appended"]`` tells).
    ``local_minimum``, four detectors:

    - *oscillation*: the point is back within ``revisit_tolerance`` of the point two steps back
      (the reference follower's test; default tolerance ``1e-6 * step``). The stall point is the one of the two
      alternating points with the smaller ``|F|``; both are in ``extra["oscillation"]``.
    - *no progress*: the best distance to the goal has not improved by more than
      ``1e-3 * step`` during the last ``progress_window`` steps (0 disables). On grids the
      follower rarely returns exactly to a point it visited, so this is the grid's main
      detector. The stall point is the point of that stretch with the smallest ``|F|``.
    - *confined* (normalized rule): the last ``confine_window`` steps stayed within a box of side
      ``2 * step`` (a jitter about an equilibrium, which never exactly revisits a point). The stall point is
      the point of that stretch with the smallest ``|F|``.
    - *small gradient*: ``|F| <= gradient_threshold`` (the saturated-potential follower), or ``F`` is zero or not
      finite. The stall point is the current point.

    - *blocked*: the step would enter an obstacle (or leave a walled map) and so would every
      fallback step (below): the force presses the follower onto an obstacle. The stall point
      is the current point; ``extra["blocked_at"]`` holds the rejected full step.

    ``max_iterations``: the step budget is used up.

Steps never enter an obstacle
    Every move (step, fallback step, escape move, the appended goal) is checked with ``blocked``
    before it is made. When the full step is blocked, the follower tries shorter and turned
    steps, in the order of ``SLIDES``: the step direction turned by 0, +-15, ..., +-75 degrees
    (all within 75 degrees of the force, so each still descends), each at 1, 1/2, 1/4 and 1/8 of
    the step length; it takes the first free one (it slides along the wall), and
    ``extra["slid_steps"]`` counts them. So a normal run ends ``reached``, ``local_minimum`` or
    ``max_iterations``; ``collision`` is left to callers for a start that is not free.

A stalled run is never reported as ``reached``.

Escapes (the Khatib-potential exercise's bonus question), tried when a local minimum is detected
    ``random_walk``: jump a length ``r ~ U(0, escape_radius]`` in a uniformly random direction,
    resampling (up to 100 times) until the straight jump is not blocked, then resume descending.
    ``potential_increase``: the reference ``Path_generator_esc``: from the stall point move along
    ``F_rep + 0.05 * F_attr`` with a step that starts at ``step`` and grows by 1.25 per sub-step
    until the potential is at least 25 % above the local minimum's (at most 60 sub-steps; a
    blocked sub-step fails the escape). The k-th escape from the same minimum requires an
    increase by ``1.25**k`` (that rule is deterministic, so repeating it unchanged would
    retrace the same jump).
    ``navigation`` (grid fields: :class:`gridfield.following.escapes.NavigationEscape`): drive down the
    octile wavefront to the first cell of the goal's basin (the last try: to the goal). Before it
    the jitter of the stall is cut from the path: the escape starts from the point chosen by
    :func:`gridfield.following.escapes.navigation_cut` among :meth:`Rules.dither_starts` (and the points of
    the current descent), and the points after it are dropped (``escapes[k]["dropped"]``); at the
    end of the run the path's loops are cut (:func:`without_loops`, also run by
    :func:`gridfield.following.follower.follow_many` on its own runs). ``iterations`` still counts every move
    made (the dropped ones too: the step budget is the work done).

    Each jump costs one try of ``escape_tries``. An escape *succeeds* when the follower's next
    stop is the goal or a stall at another local minimum (farther than
    ``max(3 * step, tolerance)`` from the one it left). ``extra`` counts ``escapes_tried`` and
    ``escapes_succeeded`` and logs each escape.

    How often each escape succeeds on the Khatib-potential segment world (``seed000_segment.yaml``)
    is measured by ``benchmarks/follow.py --escapes 50`` (``benchmarks/README.md``, "Escapes on the
    seed 000 segment world").

Examples
--------
A quadratic bowl ``U = |x - g|^2 / 2`` with a normalized step:

>>> p = descend(lambda p: (3.0 - p[0], 1.0 - p[1]), (0.0, 1.0), (3.0, 1.0), step=0.5, tolerance=0.3)
>>> p.status, p.iterations, p.end.tolist()
('reached', 6, [3.0, 1.0])
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.coords import as_xy
from ..core.errors import ParameterError
from ..core.params import Escape, Follower, check, group, names, resolve
from ..core.path import Path
from ._rules import ESCAPES, SLIDES, STEP_RULES, Rules, rules
from .escapes import cut_loops, navigation_cut, navigation_finish, navigation_moves, potential_increase, random_jump

__all__ = ["DESCEND_UNIT", "ESCAPES", "FOLLOWER_GROUPS", "SLIDES", "STEP_RULES", "Rules", "descend", "goal_hop", "resolve_rules",
           "rules", "without_loops"]

Point = tuple[float, float]


#: The follower's concerns (:class:`gridfield.core.params.Follower` and :class:`gridfield.core.params.Escape`):
#: their registry parameters are what :func:`descend` takes as keywords.
FOLLOWER_GROUPS: tuple[type, ...] = (Follower, Escape)

#: The length unit of :func:`descend`'s defaults when called directly (the registry's scaled
#: defaults: ``step`` 1 unit, ``tolerance`` = ``step``, ``escape_radius`` 6 units).
DESCEND_UNIT = 0.1


def resolve_rules(params: Mapping[str, Any] | None = None, *, unit: float = DESCEND_UNIT,
                  revisit_tolerance: float | None = None) -> Rules:
    """The :class:`Rules` of follower parameters given by name: checked as function arguments
    (``None`` is refused), the others the registry's defaults scaled to ``unit``.

    Parameters
    ----------
    params : mapping, optional
        Names of the follower's concerns (:data:`FOLLOWER_GROUPS`) and their values.
    unit : float
        The length unit of the scaled defaults (:func:`gridfield.core.params.resolve`).
    revisit_tolerance : float, optional
        As in :func:`rules`.

    Returns
    -------
    Rules

    Examples
    --------
    >>> r = resolve_rules({"step": 0.5})
    >>> r.step, r.tolerance, r.escape_radius, r.max_iterations
    (0.5, 0.5, 0.6000000000000001, 10000)
    >>> resolve_rules({"q_star": 1.0})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: q_star is no follower parameter; the follower's: step_rule, ...
    """
    allowed = names(*FOLLOWER_GROUPS)
    given = {}
    for k, v in (params or {}).items():
        if k not in allowed:
            raise ParameterError(f"{k} is no follower parameter; the follower's: {', '.join(allowed)}")
        given[k] = check(k, tuple(v.tolist()) if isinstance(v, np.ndarray) else v)
    full = resolve(given, unit=check("unit", unit, minimum=0.0, strict=True))
    return rules(group(Follower, full), group(Escape, full), revisit_tolerance=revisit_tolerance)


def _free_step(x: float, y: float, sx: float, sy: float,
               blocked: Callable[[Point, Point], bool]) -> Point | None:
    """The first free fallback of the blocked step ``(sx, sy)`` from ``(x, y)`` (see :data:`SLIDES`).

    Examples
    --------
    >>> wall = lambda p, q: q[0] > 1.0          # free for x <= 1
    >>> _free_step(0.5, 0.0, 1.0, 0.0, wall)    # shortened to half
    (1.0, 0.0)
    >>> _free_step(1.0, 0.0, 1.0, 0.0, wall) is None   # pressed against the wall
    True
    """
    for k in range(len(SLIDES)):
        q = Rules.slide(x, y, sx, sy, k)
        if not blocked((x, y), q):
            return q
    return None


def goal_hop(x: float, y: float, goal: Point, blocked: Callable[[Point, Point], bool] | None,
             navigate: Callable[..., list[Point]] | None) -> list[Point] | None:
    """The points a reached run appends to end on the goal: the goal itself, or, when that straight
    hop is blocked, the way down the navigation function (``navigate``); ``None`` when neither is
    free. Shared by :func:`descend` and :func:`gridfield.following.follower.follow_many`.

    Parameters
    ----------
    x, y : float
        Where the reached run stopped (within the tolerance of the goal).
    goal : (float, float)
    blocked : callable or None
        ``blocked(p, q)``, as in :func:`descend`.
    navigate : callable or None
        The navigation moves (:class:`gridfield.following.escapes.NavigationEscape`).

    Returns
    -------
    list of (float, float) or None

    Examples
    --------
    >>> goal_hop(0.9, 0.0, (1.0, 0.0), None, None)
    [(1.0, 0.0)]
    >>> goal_hop(0.9, 0.0, (1.0, 0.0), lambda p, q: True, None) is None
    True
    """
    if blocked is None or not blocked((x, y), goal):
        return [goal]
    if navigate is not None:
        return navigation_finish(navigate, x, y, blocked)
    return None


def without_loops(points: NDArray[np.float64], radius: float, blocked: Callable[[Point, Point], bool] | None,
                  log: list[dict[str, Any]] | None = None) -> NDArray[np.float64]:
    """The path ``points`` with its loops cut (:func:`gridfield.following.escapes.cut_loops`), the point
    indices in an escape ``log`` (its entries' ``points``) moved to the points kept. Shared by
    :func:`descend` and :func:`gridfield.following.follower.follow_many` for the ``navigation`` escape.

    Parameters
    ----------
    points : ndarray, shape (N, 2)
    radius : float
    blocked : callable or None
    log : list of dict, optional
        Changed in place.

    Returns
    -------
    ndarray, shape (M, 2)

    Examples
    --------
    >>> log = [{"points": [2, 5]}]
    >>> pts = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.1, 0.9], [2.0, 0.1], [3.0, 0.0]])
    >>> without_loops(pts, 0.5, None, log).tolist(), log
    ([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 0.1], [3.0, 0.0]], [{'points': [2, 4]}])
    """
    kept = cut_loops(points, radius, blocked)
    if len(kept) == len(points):
        return points
    for e in log or ():
        if "points" in e:  # a dropped point moves to the next point kept
            e["points"] = [int(np.searchsorted(kept, k)) for k in e["points"]]
    return points[kept]


def descend(
    force: Callable[[Point], tuple[float, float]],
    start: ArrayLike,
    goal: ArrayLike,
    *,
    blocked: Callable[[Point, Point], bool] | None = None,
    potential: Callable[[Point], float] | None = None,
    attraction: Callable[[Point], tuple[float, float]] | None = None,
    navigate: Callable[..., list[Point]] | None = None,
    revisit_tolerance: float | None = None,
    rng: np.random.Generator | int | None = None,
    append_goal: bool = True,
    planner: str = "potential",
    spec: Rules | None = None,
    **params: Any,
) -> Path:
    """Follow the force field ``force`` from ``start`` until a stop rule fires.

    Parameters
    ----------
    force : callable
        ``force((x, y)) -> (fx, fy)``, the force ``F = -grad U`` at a point.
    start, goal : (2,) array_like
        World points.
    blocked : callable, optional
        ``blocked((x, y), (x2, y2)) -> bool``: whether the straight move enters an obstacle or
        leaves a walled map. ``None``: nothing blocks.
    potential : callable, optional
        ``potential((x, y)) -> U``; needed by the ``potential_increase`` escape.
    attraction : callable, optional
        The attractive part of the force; needed by the ``potential_increase`` escape.
    navigate : callable, optional
        ``navigate((x, y), final=bool) -> [points]``: the moves of the ``navigation`` escape
        (:class:`gridfield.following.escapes.NavigationEscape`); needed by that escape.
    revisit_tolerance : float, optional
        Oscillation when the point is this close to the point two steps back
        (default ``1e-6 * step``; for the scaled rule ``1e-6 * tolerance``).
    rng : numpy.random.Generator or int, optional
        Random source of the random-walk escape (an int seeds a new Generator).
    append_goal : bool
        Append the goal to the path when reached.
    planner : str
        The name the returned Path carries (the planner that runs the follower).
    spec : Rules, optional
        The resolved rules (:func:`rules`, from the registry's typed groups); the grid follower
        and the exact planner pass them. Not together with ``**params``.
    **params
        The follower's parameters by their registry names (:data:`FOLLOWER_GROUPS`:
        :class:`gridfield.core.params.Follower` and :class:`gridfield.core.params.Escape`: ``step_rule``,
        ``step``, ``alpha``, ``min_speed``, ``tolerance``, ``max_iterations``,
        ``gradient_threshold``, ``progress_window``, ``confine_window``, ``escape``,
        ``escape_tries``, ``escape_radius``, ...; ``sampling`` and ``seed`` are the grid
        follower's), checked as the registry checks them; the others take the registry's
        defaults scaled to :data:`DESCEND_UNIT` (:func:`resolve_rules`).

    Returns
    -------
    Path
        ``points`` (N, 2); ``status`` ``reached``, ``local_minimum`` or ``max_iterations``;
        ``iterations``, the moves made (steps and escape moves; the appended goal is not counted);
        ``params``, the resolved :class:`Rules`; ``seconds``, the time following; ``extra``:
        ``stop_reason``; ``stall_point`` and ``local_minima`` (every stall point met, escaped or
        not); ``oscillation`` (the two alternating points); ``blocked_at``; ``slid_steps``;
        ``goal_appended``; ``escapes_tried``, ``escapes_succeeded`` and ``escapes`` (a log) when
        escaping; ``navigation_segments`` for the navigation escape.

    Examples
    --------
    A wall across the bowl stops the follower: it shortens its steps up to the wall (never
    into it), then no descent step is free:

    >>> wall = lambda p, q: q[0] >= 2.0
    >>> p = descend(lambda p: (3.0 - p[0], 0.0), (0.0, 0.0), (3.0, 0.0), step=0.5, tolerance=0.3, blocked=wall)
    >>> p.status, p.extra["stop_reason"], bool(p.points[:, 0].max() < 2.0), p.extra["blocked_at"][0] >= 2.0
    ('local_minimum', 'blocked', True, True)

    A wrong parameter is named:

    >>> descend(lambda p: (1.0, 0.0), (0, 0), (1, 0), step=0)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: step must be a finite number > 0, got 0
    """
    r = _descend_rules(spec, params, revisit_tolerance)
    rng = _escape_inputs(r.escape, potential, attraction, navigate, rng)
    escape, escape_tries = r.escape, r.escape_tries
    max_iterations, progress_window, confine_window = r.max_iterations, r.progress_window, r.confine_window
    box = r.box

    x, y = as_xy(start, "start")
    gx, gy = as_xy(goal, "goal")
    t0 = time.perf_counter()
    xs, ys = [x], [y]
    fns: list[float] = []  # |F| at xs[i], ys[i]
    it = 0
    best = math.sqrt((x - gx) * (x - gx) + (y - gy) * (y - gy))
    best_it = best_idx = 0  # when the best distance was reached (iteration) and where (point index)
    win_min, win_idx = math.inf, 0  # smallest |F| since the last improvement, and where
    status = ""
    extra: dict[str, Any] = {}
    minima: list[list[float]] = []
    log: list[dict[str, Any]] = []
    tried = 0
    slid = 0  # steps shortened or turned because the full step was blocked
    since = 0  # index of the first point of the current descent (after the last escape move)
    pinned = False  # no free descent step from the current point

    fx = fy = fn = 0.0
    sqrt = math.sqrt
    # the rules (bound once: they run every step)
    reached, oscillating, confined, stalled = r.reached, r.oscillating, r.confined, r.stalled
    progressed, small_gradient, next_point = r.progressed, r.small_gradient, r.next_point
    append_x, append_y = xs.append, ys.append
    dx, dy = x - gx, y - gy
    d = sqrt(dx * dx + dy * dy)
    while not reached(d):  # the stop rules, in the order of STOP_RULES: the goal first
        n = len(xs)
        reason = ""
        stall = -1
        if pinned:
            reason = "blocked"
            stall = n - 1
            pinned = False
        elif n > 2 and oscillating(sqrt((x - xs[-3]) * (x - xs[-3]) + (y - ys[-3]) * (y - ys[-3]))):
            reason = "oscillation"
            stall = n - 3 if r.older_stalls(fns[n - 3], fns[n - 2]) else n - 2
            extra["oscillation"] = [[xs[n - 2], ys[n - 2]], [x, y]]
        elif (confine_window and n - since > confine_window
              # cheap necessary condition first: a stretch whose ends are more than a box apart
              # spans more than a box (max - min >= |end - start|, exactly in floating point)
              and abs(x - xs[-confine_window - 1]) <= box and abs(y - ys[-confine_window - 1]) <= box
              and confined(max(wx := xs[-confine_window - 1:]) - min(wx),
                           max(wy := ys[-confine_window - 1:]) - min(wy))):
            reason = "confined"
            k0 = n - confine_window - 1
            stall = k0 + int(r.weakest(fns[k0:n - 1]))
        elif progress_window and stalled(it - best_it):
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
            fns.append(fn)
            if fn < win_min:
                win_min, win_idx = fn, n - 1
            if small_gradient(fn):
                reason = "small_gradient" if fn == fn and fn != math.inf else "undefined_force"
                stall = n - 1

        if reason:
            # -- a local minimum: stop, or escape ---------------------------------------------
            where = [xs[stall], ys[stall]]
            minima.append(where)
            _settle(log, r, "local_minimum", where)
            if escape == "none" or tried >= escape_tries:
                status = "local_minimum"
                extra["stop_reason"] = reason
                extra["stall_point"] = where
                break
            tried += 1
            moves = _escape_moves(r, reason, where, (xs, ys, fns), since, best_idx, it, tried, log,
                                  (force, potential, attraction, navigate, blocked), rng)
            if not moves:  # the force is computed again at the same point
                del fns[n - 1:]
                continue
            xs.extend([q[0] for q in moves])
            ys.extend([q[1] for q in moves])
            fns.extend([math.nan] * len(moves))
            it += len(moves)
            x, y = moves[-1]
            dx, dy = x - gx, y - gy
            d = sqrt(dx * dx + dy * dy)
            best, best_it, best_idx = d, it, len(xs) - 1
            win_min, win_idx = math.inf, len(xs) - 1
            since = len(xs) - 1
            continue

        # -- one step --------------------------------------------------------------------
        nx, ny = next_point(x, y, fx, fy, fn)
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
        if progressed(d, best):
            best, best_it, best_idx = d, it, len(xs) - 1
            win_min, win_idx = math.inf, len(xs) - 1

    status = status or "reached"  # (the loop ends without a status when the goal is reached)
    extra.setdefault("stop_reason", "goal")
    _settle(log, r, status)
    extra["slid_steps"] = slid
    points = _descent_points(r, status, append_goal, xs, ys, (gx, gy), blocked, navigate, log, extra, minima, tried)
    return Path(points, status, planner, iterations=it, params=r.record(),
                seconds=time.perf_counter() - t0, extra=extra)


#: The stop rules in the order both followers check them before every step (:func:`descend` and
#: :func:`gridfield.following.follower.follow_many`, each spelling the order out in its loop: ``tests/test_stop_rules_order.py``
#: checks both against this table, ``tests/test_follower_spec.py`` that they agree): each
#: name is a ``stop_reason`` (``reached`` is the reason ``goal``; ``small_gradient`` includes
#: ``undefined_force``).
STOP_RULES: tuple[str, ...] = ("goal", "blocked", "oscillation", "confined", "no_progress", "max_iterations",
                               "small_gradient")


def _descend_rules(spec: Rules | None, params: Mapping[str, Any], revisit_tolerance: float | None) -> Rules:
    """:func:`descend`'s rules: ``spec``, or resolved from its keywords (not both)."""
    if spec is None:
        return resolve_rules(params, revisit_tolerance=revisit_tolerance)
    if params or revisit_tolerance is not None:
        raise ParameterError("descend takes the rules (spec=) or the follower's parameters, not both")
    return spec


def _escape_inputs(escape: str, potential: Any, attraction: Any, navigate: Any, rng: Any) -> Any:
    """Check that the escape has what it needs; the random source (a Generator for the random walk)."""
    if escape == "potential_increase" and (potential is None or attraction is None):
        raise ParameterError("escape='potential_increase' needs the potential and the attractive force "
                             "(pass potential= and attraction=)")
    if escape == "navigation" and navigate is None:
        raise ParameterError("escape='navigation' follows a grid navigation function: it needs navigate= "
                             "(the grid follower, gridfield.following.follower.follow, provides it)")
    if escape == "random_walk" and not isinstance(rng, np.random.Generator):
        return np.random.default_rng(rng)
    return rng


def _settle(log: list[dict[str, Any]], r: Rules, outcome: str, where: list[float] | None = None) -> None:
    """Classify the pending escape (the last one of ``log``) by how the follower stopped next."""
    if log and log[-1]["outcome"] is None:
        if outcome == "local_minimum" and where is not None:
            frm = log[-1]["from"]
            near = math.hypot(where[0] - frm[0], where[1] - frm[1]) <= r.same_radius
            outcome = "same_minimum" if near else "other_minimum"
        log[-1]["outcome"] = outcome


def _escape_moves(r: Rules, reason: str, where: list[float], path: tuple[list[float], list[float], list[float]],
                  since: int, best_idx: int, it: int, tried: int, log: list[dict[str, Any]],
                  field: tuple[Any, Any, Any, Any, Any], rng: Any) -> list[Point]:
    """One escape from the stall at ``where`` (the ``tried``-th): its moves (none: no jump), logged in
    ``log``; the navigation escape first cuts the jitter before the stall from ``path`` (in place)."""
    xs, ys, fns = path
    force, potential, attraction, navigate, blocked = field
    n = len(xs)
    x, y = xs[-1], ys[-1]
    again = sum(1 for e in log if math.hypot(e["from"][0] - where[0], e["from"][1] - where[1]) <= r.same_radius)
    entry: dict[str, Any] = {"from": where, "at_iteration": it, "kind": r.escape, "outcome": None}
    moves: list[Point]
    if r.escape == "random_walk":
        assert isinstance(rng, np.random.Generator)
        moves = random_jump(x, y, r.escape_radius, rng, blocked)
    elif r.escape == "navigation":
        assert navigate is not None
        # the jitter before the stall stays out of the path: the escape starts at the point of
        # this descent (where the dithering began, the best one, or here) that keeps it shortest
        cut = navigation_cut(navigate, xs, ys, r.dither_starts(reason, xs, ys, since, best_idx), since)
        moves = navigation_moves(navigate, xs[cut], ys[cut], final=tried >= r.escape_tries, blocked=blocked)
        if moves and cut < n - 1:
            entry["dropped"] = n - 1 - cut  # the points after the cut, before the escape
            del xs[cut + 1:], ys[cut + 1:], fns[cut + 1:]
    else:
        assert potential is not None and attraction is not None
        moves, entry["required_potential"] = potential_increase(
            x, y, force, attraction, potential, first_step=r.unit, repeat=again, blocked=blocked)
    if not moves:
        entry["outcome"] = "no_jump"
        log.append(entry)
        return moves
    entry["to"] = [moves[-1][0], moves[-1][1]]
    entry["points"] = [len(xs) - 1, len(xs) - 1 + len(moves)]  # the escape's stretch of the path
    log.append(entry)
    return moves


def _descent_points(r: Rules, status: str, append_goal: bool, xs: list[float], ys: list[float], goal: Point,
                    blocked: Any, navigate: Any, log: list[dict[str, Any]], extra: dict[str, Any],
                    minima: list[list[float]], tried: int) -> NDArray[np.float64]:
    """The path of a finished descent: the goal hop of a reached run appended, the navigation escape's
    loops cut; ``extra`` completed (``goal_appended``, the stall points, the escape log)."""
    x, y = xs[-1], ys[-1]
    if status == "reached" and append_goal and (x, y) != goal:
        hop = goal_hop(x, y, goal, blocked, navigate)
        if hop is not None:
            xs.extend(q[0] for q in hop)
            ys.extend(q[1] for q in hop)
        extra["goal_appended"] = hop is not None
    elif status == "reached":
        extra["goal_appended"] = False
    if minima:
        extra["local_minima"] = minima
    if r.escape != "none":
        extra["escapes_tried"] = tried
        extra["escapes_succeeded"] = sum(1 for e in log if e["outcome"] in ("reached", "other_minimum"))
        extra["escapes"] = log
    points = np.column_stack([xs, ys])
    if r.escape == "navigation":  # the loops of the path (jitter, detours that came back) are cut too
        points = without_loops(points, r.box, blocked, log)
        extra["navigation_segments"] = [e["points"] for e in log if "points" in e]
    return points
