"""The follower's step and stop rules (:class:`Rules`, resolved by :func:`rules`) of
:mod:`gridfield.following.descent` (a private module; import from there).

The rules are the specification both followers run: the scalar descent loop
(:func:`gridfield.following.descent.descend`) and the batch follower
(:func:`gridfield.following.follower.follow_many`) call the same methods of :class:`Rules`, each
written with arithmetic and comparisons only, so that a float and every element of an array give
the same bits. Here: the step rules and their fallback steps (:data:`SLIDES`), the stop rules'
tests, where a stall is, and the constants resolved once from the registry's typed groups
(:class:`gridfield.core.params.Follower`, :class:`gridfield.core.params.Escape`). The loop that
applies them, the escapes it runs and the end of a reached run are
:mod:`gridfield.following.descent`'s, whose module text describes every rule.

See Also
--------
gridfield.following.descent : The descent loop, and the public home of these names.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.params import REGISTRY, Escape, Follower, check

#: The step rules and the escapes (the registry's choices for ``step_rule`` and ``escape``).
STEP_RULES: tuple[str, ...] = REGISTRY["step_rule"].choices
ESCAPES: tuple[str, ...] = REGISTRY["escape"].choices


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
SLIDES: tuple[tuple[float, float, float], ...] = tuple(
    (math.cos(math.radians(a)), math.sin(math.radians(a)), f)
    for a in _SLIDE_ANGLES for f in _SLIDE_FACTORS if (a, f) != (0.0, 1.0)
)


_INF = math.inf


def _pick(c: Any, a: Any, b: Any) -> Any:
    """``a if c else b``: :func:`numpy.where` for one point (the rules below take either)."""
    return a if c else b


@dataclass(frozen=True)
class Rules:
    """The follower's step and stop rules, with their constants resolved once (:func:`rules`).

    This is the specification that both followers run: :func:`descend` (one point, Python floats)
    and :func:`gridfield.following.follower.follow_many` (many points, numpy arrays) call the same methods,
    each written with arithmetic and comparisons only, so that it gives the same bits on a float
    as on every element of an array. The stop rules are checked in this order before every step:
    :meth:`reached`, (blocked, found by the step before), :meth:`oscillating`, :meth:`confined`,
    :meth:`stalled` (no progress), the step budget, :meth:`small_gradient`.

    Attributes
    ----------
    normalized : bool
        The step rule: ``normalized`` (True) or ``scaled``.
    step, ax, ay, min_speed : float
        The normalized rule's step length; the scaled rule's gains per axis and minimum step.
    tolerance : float
        Reached when closer than this to the goal.
    max_iterations, progress_window, confine_window : int
        The step budget and the two stall windows (0: off; the confined rule is off for the
        scaled step rule, whose steps have no fixed length to judge a box by).
    gradient_threshold : float
        Stall when ``|F|`` is not above it.
    escape, escape_tries, escape_radius
        The escape from local minima, its number of tries and the random jump's length.
    unit : float
        The stop rules' length unit: ``step`` (normalized) or ``tolerance`` (scaled).
    revisit_tolerance : float
        The oscillation radius (default ``1e-6 * unit``).
    min_gain : float
        Progress is a distance to the goal lower by more than this (``1e-3 * unit``).
    box : float
        The confined rule's box side (``2 * unit``).
    same_radius : float
        An escape that stalls within this of where it started found the same minimum.
    follower, escapes : gridfield.core.params.Follower, gridfield.core.params.Escape
        The checked parameter groups the constants above were resolved from (a parameter the
        rules read that has no constant here is read from them).

    Examples
    --------
    >>> from gridfield.following.descent import resolve_rules
    >>> r = resolve_rules({"step": 0.5, "tolerance": 0.1})
    >>> r.reached(0.4), r.small_gradient(0.0), r.next_point(0.0, 0.0, 3.0, 4.0, 5.0)
    (False, True, (0.3, 0.4))
    >>> r = resolve_rules({"step_rule": "scaled", "alpha": 0.1, "min_speed": 1.0, "tolerance": 0.5})
    >>> r.unit, r.confine_window, r.next_point(0.0, 0.0, 3.0, 4.0, 5.0)
    (0.5, 0, (0.6, 0.8))
    """

    normalized: bool
    step: float
    ax: float
    ay: float
    min_speed: float
    tolerance: float
    max_iterations: int
    gradient_threshold: float
    progress_window: int
    confine_window: int
    escape: str
    escape_tries: int
    escape_radius: float
    unit: float
    revisit_tolerance: float
    min_gain: float
    box: float
    same_radius: float
    follower: Follower
    escapes: Escape

    def record(self) -> dict[str, Any]:
        """The rules as a parameter record: every parameter of the groups, then the resolved constants."""
        out = {name: getattr(g, f.name) for g in (self.follower, self.escapes) for f in dataclasses.fields(g)
               for name in (f.metadata["spec"].get("name_override", f.name),)}
        out.update((f.name, getattr(self, f.name)) for f in dataclasses.fields(self)
                   if f.name not in ("follower", "escapes"))
        return out

    # -- stop rules (distances and |F| as floats or arrays alike) ----------------------------------
    def reached(self, d: Any) -> Any:
        """The goal is reached: the distance ``d`` to it is below ``tolerance``."""
        return d < self.tolerance

    def oscillating(self, back: Any) -> Any:
        """Oscillation: the distance ``back`` to the point two steps back is within ``revisit_tolerance``."""
        return back <= self.revisit_tolerance

    def confined(self, span_x: Any, span_y: Any) -> Any:
        """Confined jitter: the last ``confine_window`` steps span at most ``box`` in x and in y."""
        return (span_x <= self.box) & (span_y <= self.box)

    def stalled(self, steps_since_best: Any) -> Any:
        """No progress: the best distance to the goal is ``progress_window`` steps old (window > 0)."""
        return steps_since_best >= self.progress_window

    def progressed(self, d: Any, best: Any) -> Any:
        """Progress: the distance ``d`` to the goal beats the best one by more than ``min_gain``."""
        return d < best - self.min_gain

    def small_gradient(self, fn: Any) -> Any:
        """A stall where the force gives out: ``|F|`` not above ``gradient_threshold`` (NaN
        included), or infinite. (``^ True`` negates a bool and a bool array alike.)"""
        return ((fn > self.gradient_threshold) ^ True) | (fn == _INF)

    # -- the step rule and its fallbacks ------------------------------------------------------------
    def next_point(self, x: Any, y: Any, fx: Any, fy: Any, fn: Any, sqrt: Callable[[Any], Any] = math.sqrt,
                   where: Callable[[Any, Any, Any], Any] = _pick) -> tuple[Any, Any]:
        """The full step from ``(x, y)`` under the force ``(fx, fy)`` of norm ``fn`` (> 0).

        ``normalized``: ``x + step * F/|F|``; ``scaled``: ``x + (ax, ay) * F``, stretched to
        ``min_speed`` along ``F`` when shorter. ``sqrt`` and ``where`` are :func:`math.sqrt` and
        ``a if c else b`` for one point, :func:`numpy.sqrt` and :func:`numpy.where` for arrays.
        """
        if self.normalized:
            return x + self.step * fx / fn, y + self.step * fy / fn
        sx, sy = self.ax * fx, self.ay * fy
        if self.min_speed > 0.0:
            short = sqrt(sx * sx + sy * sy) < self.min_speed
            sx = where(short, self.min_speed * fx / fn, sx)
            sy = where(short, self.min_speed * fy / fn, sy)
        return x + sx, y + sy

    @staticmethod
    def slide(x: Any, y: Any, sx: Any, sy: Any, k: int) -> tuple[Any, Any]:
        """The ``k``-th fallback (of ``len(SLIDES)``) of the blocked step ``(sx, sy)`` from
        ``(x, y)``: turned and shortened as :data:`SLIDES` lists; the first free one is taken."""
        c, sn, f = SLIDES[k]
        return x + f * (c * sx - sn * sy), y + f * (sn * sx + c * sy)

    # -- where the dithering before a stall began -------------------------------------------------
    def dither_starts(self, reason: str, xs: Any, ys: Any, since: int, best_idx: int) -> list[int]:
        """Where the jitter before a stall detected at the last point of ``xs, ys`` may have begun:
        the point indices (ascending, all ``>= since``, the last one the current point) from which
        the navigation escape may start instead (:func:`gridfield.following.escapes.navigation_cut` picks one).

        Two candidates besides the current point: the first point of the stretch the stop rule
        looked at (``oscillation``: the point two steps back; ``confined``: the first of the last
        ``confine_window + 1`` points; ``no_progress``: the point with the best distance to the
        goal, ``best_idx``, after which the rule saw no progress; other reasons: none), and the
        first point of the longest tail of the path that stays within a box of side ``box`` (the
        confined rule's box: the jitter about an equilibrium, however long it lasted). ``since`` is
        the first point of the current descent (the end of the last escape).

        Examples
        --------
        >>> from gridfield.following.descent import resolve_rules
        >>> r = resolve_rules({"step": 1.0})
        >>> r.dither_starts("no_progress", [0, 1, 2, 3, 3.2, 3.1], [0, 0, 0, 0, 0.3, 0.1], 0, 0)
        [0, 2, 5]
        >>> r.dither_starts("blocked", [0.0, 5.0], [0.0, 0.0], 0, 0)
        [1]
        """
        n = len(xs)
        last = n - 1
        rule = {"oscillation": n - 3, "confined": n - self.confine_window - 1, "no_progress": best_idx}.get(reason, last)
        tail_x = np.asarray(xs[since:], dtype=float)[::-1]
        tail_y = np.asarray(ys[since:], dtype=float)[::-1]
        span = np.maximum(np.maximum.accumulate(tail_x) - np.minimum.accumulate(tail_x),
                          np.maximum.accumulate(tail_y) - np.minimum.accumulate(tail_y))
        boxed = last - (int(np.argmax(span > self.box)) - 1 if (span > self.box).any() else len(span) - 1)
        return sorted({max(since, min(rule, last)), max(since, boxed), last})

    # -- where a stall is ---------------------------------------------------------------------------
    @staticmethod
    def older_stalls(f2: Any, f1: Any) -> Any:
        """Oscillation: whether the stall point is the older of the two alternating points (its
        ``|F|``, ``f2``, is not larger than the newer one's, ``f1``)."""
        return f2 <= f1

    @staticmethod
    def weakest(forces: Any) -> Any:
        """The stall point of a confined stretch: the index, along the last axis, of the first point
        with the smallest ``|F|`` (a point without a force, NaN, counts as infinite)."""
        f = np.asarray(forces, dtype=float)
        return np.argmin(np.where(np.isnan(f), np.inf, f), axis=-1)


#: The lengths the rules use: a value is required (a resolved default, never ``None``).
_NEEDED = ("step", "tolerance", "max_iterations", "escape_radius")


def _checked(values: Any) -> Any:
    """A follower concern (a dataclass of :mod:`gridfield.core.params`) with every value checked by the
    registry, and the lengths the rules use present."""
    out = {}
    for f in dataclasses.fields(values):
        name = f.metadata["spec"].get("name_override", f.name)
        v = getattr(values, f.name)
        out[f.name] = check(name, v) if name in _NEEDED else REGISTRY[name].check(v)
    return dataclasses.replace(values, **out)


def rules(follower: Follower, escapes: Escape | None = None, *, revisit_tolerance: float | None = None) -> Rules:
    """Check the follower's resolved parameters (typed groups of :mod:`gridfield.core.params`) and
    resolve its :class:`Rules`.

    Parameters
    ----------
    follower : gridfield.core.params.Follower
        The step and stop rules' parameters, resolved (``step``, ``tolerance`` and
        ``max_iterations`` given: :func:`gridfield.core.params.resolve` fills them in).
    escapes : gridfield.core.params.Escape, optional
        The escape's parameters, resolved (``escape_radius`` given); default: no escape.
    revisit_tolerance : float, optional
        The oscillation radius (default ``1e-6 * unit``); not a registry parameter.

    Returns
    -------
    Rules

    Examples
    --------
    >>> r = rules(Follower(step=0.5, tolerance=0.5, max_iterations=100), Escape(escape_radius=3.0))
    >>> r.unit, r.box, r.min_gain, r.same_radius
    (0.5, 1.0, 0.0005, 1.5)
    >>> rules(Follower(step=0.5, max_iterations=100), Escape(escape_radius=3.0))
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: tolerance must be a finite number > 0, got None
    """
    f = _checked(follower)
    e = _checked(Escape(escape_radius=1.0) if escapes is None else escapes)
    ax, ay = _gains(f.alpha)
    normalized = f.step_rule == "normalized"
    # scaled steps shrink where the field is weak: no fixed box to judge by
    confine_window = f.confine_window if normalized else 0
    unit = f.step if normalized else f.tolerance
    rev_tol = 1e-6 * unit if revisit_tolerance is None else check("revisit_tolerance", revisit_tolerance,
                                                                       minimum=0.0)
    return Rules(normalized, f.step, ax, ay, f.min_speed, f.tolerance, f.max_iterations, f.gradient_threshold,
                 f.progress_window, confine_window, e.escape, e.escape_tries, e.escape_radius, unit, rev_tol,
                 1e-3 * unit, 2.0 * unit, max(3.0 * unit, f.tolerance), f, e)
