"""One entry point for every planner: :func:`plan`, and the registry :data:`PLANNERS`.

A planner is a function ``fn(target, start, goal, params) -> Path`` where ``target`` is a
:class:`~gridfield.grid.GridMap` for grid planners and a :class:`~gridfield.world.World` for
exact-geometry planners, ``start``/``goal`` are world points ``(2,)`` already checked to be free,
and ``params`` a plain mapping of the parameter names in :data:`PARAMETERS` (a planner uses the
names it knows and ignores the others). Planners are imported only when used.
"""

from __future__ import annotations

import functools
import importlib
import inspect
import math
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from .errors import GridfieldError, ParameterError
from .grid import GridMap
from .path import Path

if TYPE_CHECKING:  # shapely (via world) is imported only when a plan is made: `gridfield --help` stays light
    from .world import World

__all__ = ["PARAMETERS", "PLANNERS", "check_params", "get_planner", "plan"]

#: name -> (module, function, kind) where kind is "grid" (needs a GridMap) or "world" (needs a World).
PLANNERS: dict[str, tuple[str, str, str]] = {
    "potential": ("gridfield.follow", "plan_potential", "grid"),
    "exact-potential": ("gridfield.exact", "plan_exact_potential", "world"),
    "visibility": ("gridfield.visibility", "plan_visibility", "world"),
    "wavefront": ("gridfield.navigation", "plan_wavefront", "grid"),
    "wavefront-octile": ("gridfield.navigation", "plan_wavefront_octile", "grid"),
    "fmm": ("gridfield.navigation", "plan_fmm", "grid"),
    "harmonic": ("gridfield.navigation", "plan_harmonic", "grid"),
    "sphere-nav": ("gridfield.navigation", "plan_sphere_nav", "world"),
}

#: World planners with their own implementation on grid maps (used when a grid map has no vector
#: world): name -> (module, function), called like a grid planner.
GRID_VARIANTS: dict[str, tuple[str, str]] = {
    "visibility": ("gridfield.anyangle", "plan_anyangle"),
}

#: Every parameter name a planner may read, with its meaning (DESIGN "Names").
PARAMETERS: dict[str, str] = {
    # potentials (Choset et al. ch. 4)
    "zeta": "attractive gain",
    "d_star": "goal distance where the attractive potential turns from quadratic to conic (inf: quadratic)",
    "eta": "repulsive gain",
    "q_star": "obstacle distance of influence",
    "repulsive_power": "p in the repulsive force eta*(1/D - 1/q_star)/D**p (2: gradient of the classic potential)",
    "repulsion": "'nearest' (one brushfire distance D) or 'sum' (sum over obstacles, each within q_star)",
    "metric": "brushfire metric behind D: euclidean (default), chessboard or taxicab",
    "gradient": "'analytic' (from the nearest-obstacle vector) or 'finite_difference' (numpy.gradient)",
    "saturate": "saturation radius of the distance (seed 004)",
    "model": "'khatib' (attractive + repulsive, default) or 'vortex' (seed 003)",
    "ka": "vortex model: attractive gain",
    "kr": "vortex model: repulsive charge at the start",
    "ko": "vortex model: obstacle charge per boundary sample",
    "spacing": "vortex model: lattice spacing of the sampled field",
    "sample_radius": "vortex model: radius of the circle the obstacle charges are sampled on",
    # follower
    "step_rule": "'normalized' (x += step*F/|F|) or 'scaled' (x += alpha*F)",
    "step": "fixed step length of the normalized follower",
    "alpha": "gain of the gradient-scaled follower",
    "min_speed": "minimum step length of the scaled follower (seed 004)",
    "tolerance": "stop when within this distance of the goal",
    "max_iterations": "give up after this many steps",
    "sampling": "'bilinear' (default) or 'nearest' sampling of the gradient arrays",
    "gradient_threshold": "local minimum when |F| falls below this (seed 004)",
    "progress_window": "local minimum when the distance to the goal has not improved over this many steps",
    "escape": "'none', 'random_walk' or 'potential_increase' (seed 000 bonus)",
    "escape_tries": "how many escape jumps to try",
    "escape_radius": "maximum jump length a of the random-walk escape",
    "seed": "random seed of the escape",
    # navigation functions
    "connectivity": "4 or 8 for the wavefront",
    "clearance_weight": "weight of the clearance cost of the clearance-aware wavefront",
    "kappa": "sphere-world navigation function exponent",
}


def check_params(params: Mapping[str, Any]) -> dict[str, Any]:
    """Reject unknown parameter names and NaN values; return a plain dict.

    Examples
    --------
    >>> check_params({"zeta": 1.0, "step": 0.1})
    {'zeta': 1.0, 'step': 0.1}
    >>> check_params({"zetta": 1.0})
    Traceback (most recent call last):
    ...
    gridfield.errors.ParameterError: unknown parameter 'zetta'; did you mean 'zeta'? ...
    """
    out = {}
    for k, v in params.items():
        if k not in PARAMETERS:
            import difflib

            close = difflib.get_close_matches(k, PARAMETERS, n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise ParameterError(f"unknown parameter {k!r}; {hint}known parameters: {', '.join(sorted(PARAMETERS))}")
        if isinstance(v, float) and math.isnan(v):
            raise ParameterError(f"parameter {k} must not be NaN")
        out[k] = v
    return out


def get_planner(name: str) -> tuple[Callable[..., Path], str]:
    """The planner function registered as ``name`` and its kind ("grid" or "world")."""
    if name not in PLANNERS:
        raise ParameterError(f"unknown planner {name!r}; expected one of {', '.join(PLANNERS)}")
    module, func, kind = PLANNERS[name]
    try:
        fn = getattr(importlib.import_module(module), func)
    except (ImportError, AttributeError) as e:
        raise GridfieldError(f"planner {name!r} is not available in this installation ({e})") from None
    return fn, kind


def plan(
    planner: str,
    target: World | GridMap,
    start: ArrayLike,
    goal: ArrayLike,
    params: Mapping[str, Any] | None = None,
    *,
    resolution: float | None = None,
    cache: dict[Any, Any] | None = None,
) -> Path:
    """Plan a path from ``start`` to ``goal`` with the named planner.

    A grid planner given a :class:`World` rasterizes it at ``resolution`` (or the world's own);
    an exact planner given a :class:`GridMap` uses the world it was rasterized from, if any, else
    the map's blocked cells as exact polygons (:func:`gridfield.gridpoly.grid_world`; on those,
    ``visibility`` is the any-angle optimum of :mod:`gridfield.anyangle`, its graph cached per map).
    With a ``cache`` dict (kept by the caller across calls on the same ``target`` object), the
    rasterized grid, and for planners that take a ``cache`` their per-map work (the brushfire),
    are computed once and reused.

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> w = read_world(bundled_map("seed000.yaml"))
    >>> plan("nonsense", w, w.start, w.goal)
    Traceback (most recent call last):
    ...
    gridfield.errors.ParameterError: unknown planner 'nonsense'; expected one of ...
    """
    from .world import World

    fn, kind = get_planner(planner)
    merged = dict(target.params) if isinstance(target, World) else (
        dict(target.world.params) if isinstance(target.world, World) else {})
    merged.update(params or {})
    merged = check_params(merged)
    if kind == "grid":
        from .rasterize import as_gridmap

        if cache is None:
            gm = as_gridmap(target, resolution)
        else:
            key = ("gridmap", target, resolution)
            if key not in cache:
                cache[key] = as_gridmap(target, resolution)
            gm = cache[key]
        s, g = gm.check_point("start", start), gm.check_point("goal", goal)
        if cache is not None and _takes_cache(fn):
            return _with_endpoints(fn(gm, s, g, merged, cache=cache), s, g)
        return _with_endpoints(fn(gm, s, g, merged), s, g)
    world = target if isinstance(target, World) else target.world
    if not isinstance(world, World) and planner in GRID_VARIANTS:
        module, func = GRID_VARIANTS[planner]
        fn = getattr(importlib.import_module(module), func)
        s, g = target.check_point("start", start), target.check_point("goal", goal)
        return _with_endpoints(fn(target, s, g, merged, cache=cache), s, g)
    if not isinstance(world, World):
        # a bitmap / ROS / Moving AI map: its blocked cells as exact polygons (gridfield.gridpoly),
        # built once per map object; "visibility" then runs on the grid itself (gridfield.anyangle)
        assert isinstance(target, GridMap)  # a World is its own world
        world = _grid_world(target, cache)
        s, g = target.check_point("start", start), target.check_point("goal", goal)
    else:
        s, g = world.check_point("start", start), world.check_point("goal", goal)
    if cache is not None and _takes_cache(fn):
        return _with_endpoints(fn(world, np.asarray(s), np.asarray(g), merged, cache=cache), s, g)
    return _with_endpoints(fn(world, np.asarray(s), np.asarray(g), merged), s, g)


def _grid_world(gm: GridMap, cache: dict[Any, Any] | None) -> World:
    from .gridpoly import grid_world

    if cache is None:
        return grid_world(gm)
    key = ("grid_world", gm)
    if key not in cache:
        cache[key] = grid_world(gm)
    return cache[key]


@functools.cache
def _takes_cache(fn: Callable[..., Path]) -> bool:
    return "cache" in inspect.signature(fn).parameters


def _with_endpoints(path: Path, start: np.ndarray, goal: np.ndarray) -> Path:
    """Record the query in ``path.extra`` (``start``, ``goal``) so figures need not guess the goal."""
    extra = dict(path.extra)
    extra.setdefault("start", (float(start[0]), float(start[1])))
    extra.setdefault("goal", (float(goal[0]), float(goal[1])))
    object.__setattr__(path, "extra", extra)  # the planner's own new Path: no copy (dataclasses.replace re-validates)
    return path
