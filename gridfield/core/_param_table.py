"""The parameter registry's tables: the concerns (:class:`Attraction`, :class:`Repulsion`, ...), one
frozen dataclass each, whose fields carry their parameter's :class:`~gridfield.core.params.Spec` fields
in their metadata, and the cell counts behind the scaled length defaults.

:mod:`gridfield.core.params` builds :data:`~gridfield.core.params.REGISTRY` from them, documents them
(each concern's Parameters section is written from the registry) and re-exports them; adding a
parameter is one field in one dataclass here. Private to :mod:`gridfield.core`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

#: Cells (of the map's length unit) behind the scaled defaults.
Q_STAR_CELLS = 4.0
#: nf1's clearance band (issue 25): chosen on the test maps (tests/data/maps) with band_gain 0.5 for paths that keep off
#: the walls (ROS median minimum clearance 3.6-3.8 cells) within the length targets (benchmarks/README.md).
CLEARANCE_BAND_CELLS = 6.0
STEP_CELLS = 1.0
ESCAPE_RADIUS_CELLS = 6.0
D_STAR_PER_Q_STAR = 2.0
MAX_ITERATIONS = 10_000


def _p(group: str, kind: str, default: Any, meaning: str, **kw: Any) -> Any:
    """A dataclass field whose metadata is the parameter's :class:`Spec` (name filled in later)."""
    return field(default=default, metadata={"spec": dict(group=group, kind=kind, default=default,
                                                         meaning=meaning, **kw)})


@dataclass(frozen=True)
class Attraction:
    """The attractive potential (Choset et al. ch. 4): quadratic within ``d_star`` of the goal, conic beyond.

    Examples
    --------
    >>> from gridfield.core.params import validate
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
    >>> from gridfield.core.params import validate
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
    >>> from gridfield.core.params import validate
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
    >>> from gridfield.core.params import validate
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
    >>> from gridfield.core.params import validate
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
    >>> from gridfield.core.params import validate
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
    >>> from gridfield.core.params import validate
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
    >>> from gridfield.core.params import validate
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
