"""The one parameter registry: every planner parameter's type, default, scaling rule, range and meaning.

Each concern is a frozen dataclass (:class:`Attraction`, :class:`Repulsion`, :class:`Model`,
:class:`NavFunction`, :class:`Vortex`, :class:`Follower`, :class:`Escape`, :class:`Navigation`, :class:`NavFn`) whose fields carry a
:class:`Spec` in their metadata. :data:`REGISTRY` (name -> :class:`Spec`) is built from them, and
everything else is generated from it: :func:`validate` (the check behind
:func:`gridfield.planners.plan`), :func:`resolve` (defaults filled in, lengths scaled to the map),
the command line's flags and their help (:func:`help_text`), the sweep-spec check and the docs.

Adding a parameter is one field in one dataclass here, and reading it in the module that uses it.

Length defaults scale with the map
    A length whose default is ``None`` is resolved by :func:`resolve` from the map's length unit
    ``unit`` (a grid map's cell size; an exact planner's world resolution), so a map at resolution
    1 and the same map at 0.05 give the same path in cells:

    - ``q_star`` = 4 cells; ``d_star`` = 2 ``q_star`` (conic attraction beyond it);
    - ``step`` = 1 cell; ``tolerance`` = ``step`` (normalized rule) or 1 cell (scaled rule);
    - ``escape_radius`` = 6 cells;
    - ``clearance_band`` = 6 cells (nf1's band along the obstacles, where its front is slowed);
    - ``eta`` is balanced: the repulsive force at distance ``q_star / 2`` from an obstacle equals
      the largest attractive force ``zeta * min(d_star, 2 q_star)``, so that near a wall the
      repulsion wins (at one cell from a wall, with the defaults, it is 12 times the attraction).

    Values given by a world file's ``params`` or by the user always win.

Examples
--------
>>> p = validate({"q_star": 0.5, "escape": "random_walk"})
>>> p["q_star"], p["escape"]
(0.5, 'random_walk')
>>> validate({"step": "abc"})
Traceback (most recent call last):
...
gridfield.core.errors.ParameterError: step must be a finite number > 0, got 'abc'
>>> r = resolve({}, unit=0.05)
>>> r["q_star"], r["d_star"], r["step"], r["tolerance"], r["escape_radius"]
(0.2, 0.4, 0.05, 0.05, 0.30000000000000004)
"""

from __future__ import annotations

import dataclasses
import difflib
import functools
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from .errors import ParameterError
from .planner_table import PLANNERS

__all__ = [
    "FIELD_GROUPS",
    "GROUPS",
    "REGISTRY",
    "Attraction",
    "Escape",
    "Follower",
    "Model",
    "NavFn",
    "NavFunction",
    "Navigation",
    "Params",
    "Repulsion",
    "Spec",
    "Vortex",
    "check",
    "group",
    "help_text",
    "known",
    "names",
    "parse",
    "resolve",
    "resolve_field",
    "validate",
]

#: Cells (of the map's length unit) behind the scaled defaults.
Q_STAR_CELLS = 4.0
#: nf1's clearance band (issue 25): chosen on the test maps (tests/data/maps) with band_gain 0.5 for paths that keep off
#: the walls (ROS median minimum clearance 3.6-3.8 cells) within the length targets (benchmarks/README.md).
CLEARANCE_BAND_CELLS = 6.0
STEP_CELLS = 1.0
ESCAPE_RADIUS_CELLS = 6.0
D_STAR_PER_Q_STAR = 2.0
MAX_ITERATIONS = 10_000


@dataclass(frozen=True)
class Spec:
    """One parameter: how it is checked, its default, and what it means.

    ``kind`` is ``number``, ``integer``, ``choice``, ``alpha`` (a number or a pair) or ``point``;
    ``minimum``/``strict`` bound numbers (``strict``: ``> minimum``), ``least`` and ``maximum`` narrow
    that range where the values beyond are meaningless or overflow (``inf`` is governed by ``allow_inf``
    alone; each has its own message); ``allow_inf`` admits ``inf``;
    ``allow_none`` admits ``None`` (``scale`` then says what ``None`` resolves to).

    Attributes
    ----------
    name : str
        The parameter's name (a key of :data:`REGISTRY`, a CLI flag ``--name`` when ``flag``).
    group : str
        Its concern (``attraction``, ``repulsion``, ... ``navigation``).
    kind : {"number", "integer", "choice", "alpha", "point"}
    default : object
        The value :func:`resolve` gives when none is given (``None``: scaled, see ``scale``).
    meaning : str
        One phrase, shown by ``--help`` and the docs.
    choices : tuple
        The allowed values of a ``choice``.
    minimum, strict, least, maximum, allow_inf, allow_none
        The range of a number (see above).
    scale : str
        The scaling rule of a ``None`` default, in words.
    planners : tuple of str
        The planners that read it (derived from the ``reads`` of :data:`gridfield.planners.PLANNERS`).
    flag : bool
        Whether it gets its own command-line flag (all take ``--param name=value``).

    Examples
    --------
    >>> spec = REGISTRY["q_star"]
    >>> spec.group, spec.allowed()
    ('repulsion', 'a number > 0 (inf allowed)')
    >>> spec.check(2), spec.check(math.inf)
    (2.0, inf)
    >>> spec.check(0)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: q_star must be a number > 0 (inf allowed), got 0
    """

    name: str
    group: str
    kind: str
    default: Any
    meaning: str
    choices: tuple[Any, ...] = ()
    minimum: float | None = None
    strict: bool = False
    least: float | None = None
    maximum: float | None = None
    allow_inf: bool = False
    allow_none: bool = False
    scale: str = ""
    flag: bool = True

    @property
    def planners(self) -> tuple[str, ...]:
        """The planners that read it: those whose :data:`gridfield.planners.PLANNERS` entry lists it
        in ``reads`` (the planner table is the one place that says what a planner reads)."""
        return tuple(name for name, entry in PLANNERS.items() if self.name in entry.reads)

    def allowed(self) -> str:
        """The allowed values in words (``a number > 0``, ``one of 'a', 'b'``)."""
        if self.kind == "choice":
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.kind == "point":
            return "two numbers (x, y)"
        base = {"number": "a number" if self.allow_inf else "a finite number", "integer": "an integer",
                "alpha": "a finite number or a pair (ax, ay)"}[self.kind]
        if self.minimum is not None:
            base += f" {'>' if self.strict else '>='} {self.minimum:g}"
        if self.allow_inf:
            base += " (inf allowed)"
        return base

    def check(self, value: Any) -> Any:
        """``value`` validated and converted (``float``/``int``/``str``/tuple); raises ParameterError."""
        if value is None:
            if self.allow_none:
                return None
            raise ParameterError(f"{self.name} must be {self.allowed()}, got None")
        if self.kind == "choice":
            for c in self.choices:
                if value == c and type(value) is not bool and (isinstance(c, str) == isinstance(value, str)):
                    return c
            raise ParameterError(f"{self.name} must be {self.allowed()}; got {_short(value)}")
        if self.kind == "point":
            try:
                vals = [float(v) for v in value]
            except (TypeError, ValueError):
                vals = []
            if len(vals) != 2 or not all(math.isfinite(v) for v in vals) or isinstance(value, str):
                raise ParameterError(f"{self.name} must be {self.allowed()}, got {_short(value)}")
            return (vals[0], vals[1])
        if self.kind == "alpha" and isinstance(value, list | tuple):
            if len(value) != 2:
                raise ParameterError(f"{self.name} must be {self.allowed()}, got {_short(value)}")
            a, b = (self._number(v, value) for v in value)
            return a if a == b else (a, b)
        return self._number(value, value)

    def _number(self, v: Any, shown: Any) -> float | int:
        bad = ParameterError(f"{self.name} must be {self.allowed()}, got {_short(shown)}")
        if isinstance(v, bool) or (not isinstance(v, int | float) and not _is_numpy_number(v)):
            raise bad
        f = float(v)
        if math.isnan(f) or (math.isinf(f) and not self.allow_inf):
            raise bad
        if self.minimum is not None and (f < self.minimum or (self.strict and f == self.minimum)):
            raise bad
        if self.least is not None and f < self.least:
            raise ParameterError(f"{self.name} must be at least {self.least:g} ({self.allowed()}), got {_short(shown)}")
        if self.maximum is not None and f > self.maximum and not math.isinf(f):
            raise ParameterError(f"{self.name} must be at most {self.maximum:g} ({self.allowed()}), got {_short(shown)}")
        if self.kind == "integer":
            if not f.is_integer():
                raise bad
            return int(f)
        return f


@functools.lru_cache(maxsize=256)
def _argument_spec(name: str, argument: str | None, limits: tuple[tuple[str, Any], ...]) -> Spec:
    """The Spec that checks a function argument (see :func:`check`); built once per signature."""
    lim = dict(limits)
    base = REGISTRY.get(name)
    if base is None:
        kind = lim.pop("kind", "number")
        return Spec(name=argument or name, group="", kind=kind, default=None, meaning="", **lim)
    return dataclasses.replace(base, name=argument or name, allow_none=False, **lim)


def check(name: str, value: Any, *, argument: str | None = None, **limits: Any) -> Any:
    """A function argument checked by the registry's rules: the one argument checker.

    The functions that take a parameter as an argument (:func:`gridfield.following.descent.descend`, the
    arrays of :mod:`gridfield.fields.potential`, the samplers, ...) check it with the :class:`Spec` of
    the registry entry ``name``, so a value means the same everywhere and every message has the
    registry's wording (parameter, value, what is allowed). ``None`` is refused: a function
    argument holds a value, not "resolve the default".

    Parameters
    ----------
    name : str
        The registry entry (:data:`REGISTRY`); or, for an argument that is no planner parameter
        (``unit``, ``revisit_tolerance``), any name, with ``kind`` and the bounds in ``limits``.
    value : object
        The argument's value.
    argument : str, optional
        The argument's own name when it differs from the entry's (``mode`` for ``repulsion``);
        the message names it.
    **limits
        :class:`Spec` fields that override the entry's (``minimum``, ``strict``, ``allow_inf``,
        ``kind``, ``choices``).

    Returns
    -------
    object
        The value converted (``float``, ``int``, the option string, a pair as a tuple).

    Raises
    ------
    ParameterError
        naming the argument, the value and what is allowed.

    Examples
    --------
    >>> check("step", 0.5), check("max_iterations", 10.0), check("repulsion", "sum", argument="mode")
    (0.5, 10, 'sum')
    >>> check("unit", 0, minimum=0.0, strict=True)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: unit must be a finite number > 0, got 0
    >>> check("repulsion", "all", argument="mode")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: mode must be one of 'nearest', 'sum'; got 'all'
    """
    return _argument_spec(name, argument, tuple(sorted(limits.items()))).check(value)


def _is_numpy_number(v: Any) -> bool:
    import numbers

    return isinstance(v, numbers.Real)


def _short(v: Any, limit: int = 200) -> str:
    text = repr(v)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _p(group: str, kind: str, default: Any, meaning: str, **kw: Any) -> Any:
    """A dataclass field whose metadata is the parameter's :class:`Spec` (name filled in later)."""
    return field(default=default, metadata={"spec": dict(group=group, kind=kind, default=default,
                                                         meaning=meaning, **kw)})


@dataclass(frozen=True)
class Attraction:
    """The attractive potential (Choset et al. ch. 4): quadratic within ``d_star`` of the goal, conic beyond.

    Examples
    --------
    >>> validate({"zeta": 0.8, "d_star": 2}).group(Attraction)   # the attractive/repulsive exercise's chi and d*
    Attraction(zeta=0.8, d_star=2.0)
    """

    zeta: float = _p("attraction", "number", 1.0, "attractive gain", minimum=0.0)
    d_star: float | None = _p(
        "attraction", "number", None, "goal distance where the attraction turns from quadratic to conic "
        "(inf: quadratic everywhere)", minimum=0.0, allow_inf=True, allow_none=True,
        scale=f"{D_STAR_PER_Q_STAR:g} x q_star")


@dataclass(frozen=True)
class Repulsion:
    """The repulsive potential ``0.5 eta (1/D - 1/q_star)^2`` within ``q_star`` of an obstacle.

    Examples
    --------
    >>> r = validate({"eta": 0.8, "q_star": 2}).group(Repulsion)   # the attractive/repulsive exercise's eta and Q*
    >>> r.eta, r.q_star, r.repulsion
    (0.8, 2.0, 'nearest')
    """

    eta: float | None = _p("repulsion", "number", None, "repulsive gain", minimum=0.0, allow_none=True,
                           scale="balanced: the repulsion at q_star/2 equals the largest attraction "
                                 "zeta*min(d_star, 2 q_star)")
    q_star: float | None = _p("repulsion", "number", None, "obstacle distance of influence of the repulsion",
                              minimum=0.0, strict=True, allow_inf=True, allow_none=True,
                              scale=f"{Q_STAR_CELLS:g} cells")
    repulsive_power: float = _p("repulsion", "number", 2.0, "p in the repulsive force eta*(1/D - 1/q_star)/D**p "
                                "(2: the gradient of the classic potential)", minimum=0.0,
                                maximum=16.0)  # D**p overflows for p = 1e300
    repulsion: str = _p("repulsion", "choice", "nearest", "'nearest' (one brushfire distance D) or 'sum' (over "
                        "obstacles, each within q_star)", choices=("nearest", "sum"))
    metric: str = _p("repulsion", "choice", "euclidean", "brushfire metric behind D",
                     choices=("euclidean", "chessboard", "taxicab"))
    gradient: str = _p("repulsion", "choice", "analytic", "'analytic' (from the nearest-obstacle vector) or "
                       "'finite_difference' (numpy.gradient of U)", choices=("analytic", "finite_difference"))
    saturate: float | None = _p("repulsion", "number", None, "saturation radius of the distance (the saturated potential; "
                                "none: no saturation)", minimum=0.0, strict=True, allow_none=True, flag=False)


@dataclass(frozen=True)
class Model:
    """Which potential model the potential planner builds.

    Examples
    --------
    >>> Model().model, validate({"model": "vortex"}).group(Model).model
    (None, 'vortex')
    """

    model: str | None = _p(
        "model", "choice", None, "'khatib' (attractive + repulsive), 'vortex' (the vortex field), or a complete model "
        "(one minimum, the goal: gridfield.fields.navfield): 'nf1' (obstacle-aware distance to the goal), 'nf2' "
        "(Latombe's skeleton NF2, largest clearance), 'nf-blend' (nf1 slowed near obstacles within q_star)",
        choices=("khatib", "vortex", "nf1", "nf2", "nf-blend"), allow_none=True,
        scale="the potential planner: 'nf1'; build_field and the exact planner: 'khatib'", flag=False)


@dataclass(frozen=True)
class NavFunction:
    """The complete potential models (:mod:`gridfield.fields.navfield`: nf1, nf2, nf-blend).

    Examples
    --------
    >>> n = validate({"attraction": "octile", "clearance_gain": 2}).group(NavFunction)
    >>> n.attraction, n.clearance_gain
    ('octile', 2.0)
    """

    attraction: str = _p("navfunction", "choice", "eikonal", "nf1's distance to the goal: 'eikonal' (fast "
                         "marching, any-angle gradient paths) or 'octile' (the wavefront-octile values)",
                         choices=("eikonal", "octile"), flag=False)
    clearance_gain: float = _p("navfunction", "number", 1.0, "nf-blend: slowness 1 + clearance_gain*(q_star/D - 1)^2 "
                               "within q_star of an obstacle (0: the plain distance)", minimum=0.0, flag=False)
    clearance_band: float | None = _p("navfunction", "number", None, "nf1: width of the band along the obstacles "
                                      "where its front slows down, slowness 1 + band_gain*(1 - D/clearance_band)^2 "
                                      "for D < clearance_band, with attraction 'eikonal' (0: none, the plain distance "
                                      "to the goal)",
                                      minimum=0.0, allow_none=True, scale=f"{CLEARANCE_BAND_CELLS:g} cells", flag=False)
    band_gain: float = _p("navfunction", "number", 0.5, "nf1: the slowness added at an obstacle by the clearance band "
                          "(see clearance_band)", minimum=0.0, maximum=1000.0,
                          flag=False)  # the march's bucket queue grows with the largest slowness


@dataclass(frozen=True)
class Vortex:
    """The vortex field (charges on a lattice, with a rotational term).

    Examples
    --------
    >>> v = validate({"ko": 10}).group(Vortex)   # the vortex field's failing obstacle charge
    >>> v.ka, v.kr, v.ko
    (25.0, 30.0, 10.0)
    """

    ka: float = _p("vortex", "number", 25.0, "vortex model: attractive gain", minimum=0.0,
                   flag=False)
    kr: float = _p("vortex", "number", 30.0, "vortex model: repulsive charge at the start", minimum=0.0, flag=False)
    ko: float = _p("vortex", "number", 5.0, "vortex model: obstacle charge per boundary sample", minimum=0.0, flag=False)
    spacing: float | None = _p("vortex", "number", None, "vortex model: lattice spacing", minimum=0.0, strict=True,
                               allow_none=True, scale="the map's resolution", flag=False)
    sample_radius: float | None = _p("vortex", "number", None, "vortex model: radius of the circle the obstacle "
                                     "charges are sampled on", minimum=0.0, strict=True, allow_none=True,
                                     scale="1.05 x each circle's radius", flag=False)


@dataclass(frozen=True)
class Follower:
    """The gradient-descent follower: step and stop rules.

    Examples
    --------
    >>> f = validate({"step_rule": "scaled", "alpha": 2.1}).group(Follower)   # the star-world follower's alpha
    >>> f.step_rule, f.alpha, f.step
    ('scaled', 2.1, None)
    """

    step_rule: str = _p("follower", "choice", "normalized", "'normalized' (x += step*F/|F|) or 'scaled' "
                        "(x += alpha*F)", choices=("normalized", "scaled"))
    step: float | None = _p("follower", "number", None, "step length of the normalized follower", minimum=0.0,
                            strict=True, allow_none=True, scale=f"{STEP_CELLS:g} cell")
    alpha: float = _p("follower", "alpha", 0.1, "gain of the gradient-scaled follower", minimum=0.0, strict=True)
    min_speed: float = _p("follower", "number", 0.0, "minimum step length of the scaled follower",
                          minimum=0.0)
    tolerance: float | None = _p("follower", "number", None, "stop when within this distance of the goal",
                                 minimum=0.0, strict=True, allow_none=True,
                                 scale="step (normalized rule) or 1 cell (scaled rule)")
    max_iterations: int | None = _p("follower", "integer", None, "give up after this many steps", minimum=0,
                                    maximum=1e12, allow_none=True, scale="10000, or the number of free cells if larger "
                                    "(grid follower)")
    sampling: str = _p("follower", "choice", "bilinear", "sampling of the gradient arrays",
                       choices=("bilinear", "nearest"))
    gradient_threshold: float = _p("follower", "number", 0.0, "local minimum when |F| falls below this",
                                   minimum=0.0)
    progress_window: int = _p("follower", "integer", 200, "local minimum when the distance to the goal has not "
                              "improved over this many steps (0: off)", minimum=0)
    confine_window: int = _p("follower", "integer", 20, "local minimum when the last this many steps stayed within "
                             "a box of 2 steps (a jitter about an equilibrium; normalized rule only; 0: off)", minimum=0)


@dataclass(frozen=True)
class Escape:
    """What the follower does at a local minimum.

    Examples
    --------
    >>> e = Escape(escape="navigation")
    >>> e.escape, e.escape_tries
    ('navigation', 10)
    """

    escape: str = _p("escape", "choice", "none", "at a local minimum: 'none' (stop), 'random_walk' (random jumps), "
                     "'potential_increase' (climb the potential until it rises 25 %) or 'navigation' (follow the octile wavefront from "
                     "the goal until the descent resumes; reaches every reachable goal)",
                     choices=("none", "random_walk", "potential_increase", "navigation"))
    escape_tries: int = _p("escape", "integer", 10, "how many escapes to try", minimum=0)
    escape_radius: float | None = _p("escape", "number", None, "maximum jump length of the random-walk escape",
                                     minimum=0.0, strict=True, allow_none=True,
                                     scale=f"{ESCAPE_RADIUS_CELLS:g} cells")
    seed: int | None = _p("escape", "integer", 0, "random seed of the random-walk escape", minimum=0,
                          allow_none=True)


@dataclass(frozen=True)
class Navigation:
    """Navigation functions (wavefront, fmm, harmonic, sphere worlds).

    Examples
    --------
    >>> n = validate({"kappa": 3, "lambda": 1}).group(Navigation)   # the star-world navigation function's
    >>> n.kappa, n.lam, n.connectivity
    (3.0, 1.0, 8)
    """

    connectivity: int = _p("navigation", "choice", 8, "neighbourhood of the wavefront", choices=(4, 8), flag=False)
    clearance_weight: float = _p("navigation", "number", 0.0, "weight of the clearance cost of the clearance-aware "
                                 "wavefront (cost 1 + w * max(0, q_star - D) per cell)", minimum=0.0,
                                 maximum=1000.0, flag=False)  # the wavefront's bucket queue grows with w
    kappa: float | None = _p("navigation", "number", None, "sphere-world (sphere-nav) and star-world (star-nav) "
                             "navigation function exponent", minimum=0.0, strict=True, least=1e-3, allow_none=True,
                             scale="the smallest of a ladder (sphere-nav: 2, 3, 4, 6, 8, ...; star-nav: 3, 4, "
                                   "6, ...) that reaches the goal, or leaves no detected spurious minimum", flag=False)
    lam: float = field(default=10.0, metadata={"spec": dict(
        group="navigation", kind="number", default=10.0, name_override="lambda",
        meaning="star-nav: switch parameter of the star-to-sphere transformation (larger: closer to the "
                "identity away from the obstacles; too small folds the map; the star-world exercise: 1)",
        minimum=0.0, strict=True, flag=False)})
    workspace_center: tuple[float, float] | None = _p(
        "navigation", "point", None, "centre of the disc workspace of a sphere or star world", allow_none=True,
        scale="the centre of the world's bounds", flag=False)
    workspace_radius: float | None = _p(
        "navigation", "number", None, "radius of the disc workspace of a sphere or star world", minimum=0.0, strict=True,
        maximum=1e12, allow_none=True, scale="the disc inscribed in the world's bounds", flag=False)


@dataclass(frozen=True)
class NavFn:
    """Nav2's NavFn planner (``navfn``) and the inflated costmap it plans on (:mod:`gridfield.fields.costmap`).

    ``goal_tolerance`` is NavFn's ``tolerance`` (a world distance, not scaled to the map), named apart
    from the follower's ``tolerance``. The costmap options apply when the map is an occupancy grid;
    a costmap file (``gridfield costmap``) is planned on with the costs it holds.

    Examples
    --------
    >>> n = validate({"goal_tolerance": 0.25}).group(NavFn)
    >>> n.goal_tolerance, n.allow_unknown, n.inflation_radius, n.cost_scaling_factor
    (0.25, 'true', 0.55, 10.0)
    """

    allow_unknown: str = _p("navfn", "choice", "true", "navfn: unknown cells (cost 255) are traversable at NavFn cost "
                            "253 ('true', Nav2's default) or blocked ('false')", choices=("true", "false"), flag=False)
    goal_tolerance: float = _p("navfn", "number", 0.5, "navfn: NavFn's tolerance (world units): with an unreachable "
                               "goal, plan to the nearest reachable point of the square of this half-width round it",
                               minimum=0.0, flag=False)
    robot_radius: float = _p("navfn", "number", 0.1, "navfn on an occupancy map: the inscribed radius of the inflated "
                             "costmap (cost 253 within it)", minimum=0.0, flag=False)
    inflation_radius: float = _p("navfn", "number", 0.55, "navfn on an occupancy map: how far the costmap inflation "
                                 "spreads costs (>= robot_radius)", minimum=0.0, flag=False)
    cost_scaling_factor: float = _p("navfn", "number", 10.0, "navfn on an occupancy map: the exponential decay of the "
                                    "inflated costs (1 / world unit)", minimum=0.0, flag=False)
    lut_precision: int | None = _p("navfn", "integer", None, "navfn on an occupancy map: None evaluates the inflation "
                                   "on exact distances (legacy layer), 100 rounds them to 1/100 cell as the current "
                                   "Nav2 inflation layer", minimum=1, maximum=10000, allow_none=True,
                                   scale="exact distances", flag=False)  # the lookup table grows with it


#: The concerns, in the order help and docs list them.
GROUPS: tuple[type, ...] = (Attraction, Repulsion, Model, NavFunction, Vortex, Follower, Escape, Navigation, NavFn)


def _build() -> dict[str, Spec]:
    out: dict[str, Spec] = {}
    for cls in GROUPS:
        for f in dataclasses.fields(cls):
            meta = dict(f.metadata["spec"])
            name = meta.pop("name_override", f.name)  # ``lambda`` is a Python keyword: field ``lam``
            out[name] = Spec(name=name, **meta)
    return out


#: name -> Spec, every parameter a planner may read.
REGISTRY: dict[str, Spec] = _build()

#: The concerns of a potential field: what :func:`gridfield.fields.potential.build_field` reads and keeps, resolved,
#: in ``Field.params`` (:func:`gridfield.fields.potential.resolve_params`, :func:`gridfield.fields.vortex.vortex_field`).
FIELD_GROUPS: tuple[type, ...] = (Attraction, Repulsion, Model, Vortex)


def names(*groups: type) -> tuple[str, ...]:
    """The registry names of the parameters of these concerns, in their order.

    Parameters
    ----------
    *groups : type
        Concerns of :data:`GROUPS` (``Attraction``, ...).

    Returns
    -------
    tuple of str
        Their parameters' names (``lambda`` for ``Navigation.lam``).

    Examples
    --------
    >>> names(Attraction, Model)
    ('zeta', 'd_star', 'model')
    """
    return tuple(f.metadata["spec"].get("name_override", f.name) for cls in groups for f in dataclasses.fields(cls))

_KIND_TYPES = {"number": "float", "integer": "int", "alpha": "float or (float, float)", "point": "(float, float)"}


def _rst_text(text: str) -> str:
    """``text`` with the characters reStructuredText would read as markup escaped."""
    return text.replace("\\", "\\\\").replace("*", "\\*").replace("|", "\\|").replace("`", "\\`")


def _parameters_section(cls: type) -> str:
    """The numpydoc Parameters section of one concern, written from the registry (never out of date)."""
    lines = ["Parameters", "----------"]
    for f in dataclasses.fields(cls):
        name = f.metadata["spec"].get("name_override", f.name)
        s = REGISTRY[name]
        kind = "{" + ", ".join(repr(c) for c in s.choices) + "}" if s.kind == "choice" else _KIND_TYPES[s.kind]
        default = "None" if s.default is None else repr(s.default)
        lines.append(f"{f.name} : {kind}{' or None' if s.allow_none else ''}, default {default}")
        alias = f" (the parameter ``{name}``)" if name != f.name else ""
        scaled = f" None: {s.scale}." if s.default is None and s.scale else ""
        lines.append(f"    {_rst_text(s.meaning[0].upper() + s.meaning[1:])}{alias}.{_rst_text(scaled)} "
                     f"Read by: {', '.join(s.planners)}.")
    return "\n".join(lines)


def _document_groups() -> None:
    """Put each concern's Parameters section before its Examples (docstrings may be stripped by -OO)."""
    for cls in GROUPS:
        doc = cls.__doc__
        if doc is None:
            continue
        head, sep, examples = doc.partition("\n    Examples\n")
        section = _parameters_section(cls).replace("\n", "\n    ")
        cls.__doc__ = f"{head.rstrip()}\n\n    {section}\n{sep}{examples}"


_document_groups()


class Params(Mapping[str, Any]):
    """A validated, read-only mapping of parameter values (only the names given, or resolved).

    Built by :func:`validate`, which checks the values; the constructor does not.

    Parameters
    ----------
    values : mapping
        Parameter name -> checked value.

    Examples
    --------
    >>> p = validate({"eta": 2})
    >>> p["eta"], dict(p)
    (2.0, {'eta': 2.0})
    >>> p
    Params(eta=2.0)
    """

    __slots__ = ("_d",)

    def __init__(self, values: Mapping[str, Any]) -> None:
        self._d = dict(values)

    def __getitem__(self, key: str) -> Any:
        return self._d[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._d)

    def __len__(self) -> int:
        return len(self._d)

    def __repr__(self) -> str:
        return "Params(" + ", ".join(f"{k}={v!r}" for k, v in self._d.items()) + ")"

    def group(self, cls: type) -> Any:
        """The values of one concern as its frozen dataclass (defaults for names not given)."""
        return group(cls, self._d)


def group(cls: type, values: Mapping[str, Any]) -> Any:
    """The values of one concern (a dataclass of :data:`GROUPS`) taken from a parameter mapping.

    The typed view of already checked values (:func:`resolve`'s, a :class:`Params`): the names of
    ``cls`` found in ``values`` fill its fields, the others keep the registry's defaults.

    Parameters
    ----------
    cls : type
        A concern (``Follower``, ``Escape``, ...).
    values : mapping
        Parameter name -> value (other names are ignored).

    Returns
    -------
    object
        An instance of ``cls``.

    Examples
    --------
    >>> f = group(Follower, resolve({"step": 0.5}, unit=1.0))
    >>> f.step, f.tolerance, f.max_iterations
    (0.5, 0.5, 10000)
    """
    fields = {f.metadata["spec"].get("name_override", f.name): f.name for f in dataclasses.fields(cls)}
    return cls(**{fields[k]: v for k, v in values.items() if k in fields})


def _unknown(name: str) -> ParameterError:
    close = difflib.get_close_matches(name, REGISTRY, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return ParameterError(f"unknown parameter {_short(name, 60)}; {hint}known parameters: "
                          f"{', '.join(sorted(REGISTRY))}")


def validate(params: Mapping[str, Any] | None) -> Params:
    """Check names and values of ``params`` against :data:`REGISTRY`; return them converted.

    Parameters
    ----------
    params : mapping or None
        Parameter name -> value (numbers as numbers, options as strings).

    Returns
    -------
    Params
        The same names, values converted (``float``, ``int``, option strings, tuples).

    Raises
    ------
    ParameterError
        An unknown name (with a "did you mean"), or a value of the wrong type or out of range; the
        message names the parameter, the value and what is allowed.

    Examples
    --------
    >>> validate({"max_iterations": 10.0})["max_iterations"]
    10
    >>> validate({"max_iterations": "10"})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: max_iterations must be an integer >= 0, got '10'
    """
    if params is None:
        return Params({})
    if isinstance(params, Params):
        return params
    if not isinstance(params, Mapping):
        raise ParameterError(f"params must be a mapping of parameter names to values, got {type(params).__name__}")
    out: dict[str, Any] = {}
    for k, v in params.items():
        if not isinstance(k, str) or k not in REGISTRY:
            raise _unknown(str(k))
        out[k] = REGISTRY[k].check(v)
    return Params(out)


def known(record: Mapping[str, Any] | None) -> Params:
    """The registry's names of a parameter record, checked by :func:`validate`; its other keys left out.

    For the record a result keeps (``Field.params``, a follower's merged parameters), which may also
    name its construction (a navigation field's ``navigation``, ``costs``): read it as typed groups,
    ``known(field.params).group(Vortex)``, with the registry's defaults for the names it lacks.

    Parameters
    ----------
    record : mapping or None

    Returns
    -------
    Params

    Examples
    --------
    >>> known({"ka": 10, "navigation": "wavefront"}).group(Vortex).ka
    10.0
    """
    return validate({k: v for k, v in (record or {}).items() if k in REGISTRY})


def parse(name: str, text: str) -> Any:
    """A command-line string as the value parameter ``name`` takes (then checked).

    Parameters
    ----------
    name : str
        A name of :data:`REGISTRY`.
    text : str
        The value as typed: a number, an option, ``none`` (where allowed), ``ax,ay`` for ``alpha``,
        ``x,y`` for a point.

    Returns
    -------
    object
        The checked value (``float``, ``int``, ``str``, tuple or None).

    Raises
    ------
    ParameterError
        For an unknown name or a value the parameter does not allow.

    Examples
    --------
    >>> parse("q_star", "0.5"), parse("escape", "navigation"), parse("max_iterations", "20")
    (0.5, 'navigation', 20)
    >>> parse("kappa", "abc")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: kappa must be a finite number > 0, got 'abc'
    """
    if name not in REGISTRY:
        raise _unknown(name)
    spec = REGISTRY[name]
    t = text.strip()
    if t.lower() in ("none", "null") and spec.allow_none:
        return None
    value: Any = t
    if spec.kind in ("number", "integer", "alpha") or (spec.kind == "choice" and all(isinstance(c, int)
                                                                                     for c in spec.choices)):
        try:
            value = float(t)
            if value.is_integer() and spec.kind != "number":
                value = int(value)
        except ValueError:
            if spec.kind == "alpha" and "," in t:
                try:
                    value = [float(s) for s in t.split(",")]
                except ValueError:
                    value = t
    elif spec.kind == "point":
        try:
            value = [float(s) for s in t.split(",")]
        except ValueError:
            value = t
    return spec.check(value)


def resolve(params: Mapping[str, Any] | None, *, unit: float) -> dict[str, Any]:
    """Every parameter with its default, lengths scaled to the map's length ``unit``.

    Parameters
    ----------
    params : mapping or None
        Given values (validated here); they always win over defaults.
    unit : float
        The map's length unit: a grid map's cell size, or an exact planner's world resolution.

    Returns
    -------
    dict
        Every name of :data:`REGISTRY`; ``q_star``, ``d_star``, ``eta``, ``step``, ``tolerance`` and
        ``escape_radius`` resolved by the rules of the module docstring (the others keep ``None``
        where ``None`` is their meaning).

    Examples
    --------
    >>> r = resolve({"q_star": 2.0, "d_star": math.inf, "eta": 1.0}, unit=0.05)   # given: unchanged
    >>> r["q_star"], r["d_star"], r["eta"], r["step"]
    (2.0, inf, 1.0, 0.05)
    >>> r = resolve({}, unit=1.0)
    >>> r["eta"]   # zeta * d_star * q_star * (q_star / 2)**2 = 1 * 8 * 4 * 4
    128.0
    """
    if not (isinstance(unit, int | float) and math.isfinite(unit) and unit > 0):
        raise ParameterError(f"the map's length unit must be a finite number > 0, got {unit!r}")
    given = validate(params)
    p: dict[str, Any] = {name: spec.default for name, spec in REGISTRY.items()}
    p.update(given)
    if p["q_star"] is None:
        p["q_star"] = Q_STAR_CELLS * unit
    if p["d_star"] is None:
        p["d_star"] = D_STAR_PER_Q_STAR * p["q_star"] if math.isfinite(p["q_star"]) else math.inf
    if p["eta"] is None:
        p["eta"] = balanced_eta(p["zeta"], p["d_star"], p["q_star"], p["repulsive_power"], unit)
    if p["step"] is None:
        p["step"] = STEP_CELLS * unit
    if p["tolerance"] is None:
        p["tolerance"] = p["step"] if p["step_rule"] == "normalized" else unit
    if p["clearance_band"] is None:
        p["clearance_band"] = CLEARANCE_BAND_CELLS * unit
    if p["escape_radius"] is None:
        p["escape_radius"] = ESCAPE_RADIUS_CELLS * unit
    if p["max_iterations"] is None:
        p["max_iterations"] = MAX_ITERATIONS
    return p


def resolve_field(params: Mapping[str, Any] | None, *, unit: float) -> dict[str, Any]:
    """The parameters a potential field is built with: those of :data:`FIELD_GROUPS` resolved, the
    other names given kept, and a complete model's own (``attraction``, ``clearance_gain``).

    The one resolution behind :func:`gridfield.fields.potential.resolve_params` and the complete models of
    :mod:`gridfield.fields.navfield` (which cannot import ``potential``: it dispatches to them). ``model``
    unset stays ``None`` for the caller to choose.

    Parameters
    ----------
    params : mapping, optional
        Parameter names and values (checked by :func:`validate`).
    unit : float
        The map's length unit (cell size) the length defaults scale with.

    Returns
    -------
    dict
        The field parameters in :data:`FIELD_GROUPS` order, then the other names given.

    Examples
    --------
    >>> p = resolve_field({"model": "nf1", "step": 0.1}, unit=0.5)
    >>> p["q_star"], p["attraction"], p["step"]
    (2.0, 'eikonal', 0.1)
    """
    given = dict(validate(params))
    full = resolve(given, unit=unit)
    field_names = names(*FIELD_GROUPS)
    p = {k: full[k] for k in field_names}
    p.update(given)
    p.update({k: full[k] for k in field_names})
    if p["model"] in ("nf1", "nf2", "nf-blend"):  # the complete models' own parameters (NavFunction)
        p.update({k: full[k] for k in names(NavFunction)})
    return p


def balanced_eta(zeta: float, d_star: float, q_star: float, power: float, unit: float) -> float:
    """The repulsive gain whose force at ``q_star / 2`` equals the attraction ``zeta * min(d_star, 2 q_star)``.

    ``q_star = inf``: balanced at 2 units from the obstacle against ``zeta * min(d_star, 8 units)``.

    Examples
    --------
    >>> balanced_eta(1.0, 8.0, 4.0, 2.0, 1.0)   # eta * (1/2 - 1/4) / 2**2 = 8
    128.0
    """
    z = zeta if zeta > 0 else 1.0
    if math.isfinite(q_star):
        db, inv_q, cap = q_star / 2.0, 1.0 / q_star, 2.0 * q_star
    else:
        db, inv_q, cap = 2.0 * unit, 0.0, 8.0 * unit
    attraction = z * min(d_star, cap)
    try:
        eta = float(attraction / ((1.0 / db - inv_q) / db**power))
    except (ZeroDivisionError, OverflowError):
        eta = math.nan
    # q_star so small or large that (q_star/2)**p leaves the floats (no attraction: eta 0 balances it)
    if not (math.isfinite(eta) and (eta > 0 or (eta == 0 and attraction == 0))):
        raise ParameterError(f"q_star = {q_star:g} with repulsive_power {power:g}: the balanced eta (the repulsion "
                             f"at q_star/2 equal to the attraction) is not a finite positive number; give eta, or a "
                             f"q_star nearer the map's scale")
    return eta


def help_text(name: str) -> str:
    """One line for ``--help``: meaning, default (or scaling rule), allowed values, planners.

    Parameters
    ----------
    name : str
        A name of :data:`REGISTRY`.

    Returns
    -------
    str
        The line, with ``%`` doubled for argparse.

    Examples
    --------
    >>> help_text("q_star")
    'obstacle distance of influence of the repulsion; default: 4 cells; a number > 0 (inf allowed); ...'
    """
    s = REGISTRY[name]
    default = s.scale if (s.default is None and s.scale) else ("none" if s.default is None else repr(s.default))
    most = (f", at least {s.least:g}" if s.least is not None else "") + (
        f", at most {s.maximum:g}" if s.maximum is not None else "")
    text = f"{s.meaning}; default: {default}; {s.allowed()}{most}; read by: {', '.join(s.planners)}"
    return text.replace("%", "%%")
