"""One entry point for every planner: :func:`plan`, and the registry :data:`PLANNERS`.

A planner is a function ``fn(target, start, goal, params) -> Path`` where ``target`` is a
:class:`~gridfield.core.grid.GridMap` for grid planners and a :class:`~gridfield.geometry.world.World` for
exact-geometry planners, ``start``/``goal`` are world points ``(2,)`` already checked to be free,
and ``params`` a plain mapping of the parameter names in :data:`PARAMETERS` (a planner uses the
names it knows and ignores the others). Planners are imported only when used.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping
from types import ModuleType
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .core.coords import as_xy
from .core.errors import ArgumentTypeError, GridfieldError, ParameterError, shorten
from .core.grid import GridMap
from .core.params import REGISTRY, validate
from .core.path import Path, PathExtra
from .core.planner_table import PLANNERS as _PLANNERS
from .core.planner_table import Planner

if TYPE_CHECKING:  # shapely (via world) is imported only when a plan is made: `gridfield --help` stays light
    from .fields.potential import Field
    from .geometry.world import World

__all__ = ["PARAMETERS", "PLANNERS", "Plan", "Planner", "check_params", "get_planner", "plan", "plan_with_field"]

#: name -> :class:`Planner` ``(module, function, kind, reads)``: kind "grid"
#: needs a GridMap, "world" a World; ``reads``, the parameters it reads. (The table is the leaf module
#: ``gridfield.core.planner_table``, which :mod:`gridfield.core.params` reads too; adding a planner is one
#: entry there and its module.)
PLANNERS = _PLANNERS

#: World planners with their own implementation on grid maps (used when a grid map has no vector
#: world): name -> (module, function), called like a grid planner.
GRID_VARIANTS: dict[str, tuple[str, str]] = {
    "visibility": ("gridfield.exact.anyangle", "plan_anyangle"),
}

#: Grid planners that build a potential field and can return it with the path (:func:`plan_with_field`):
#: name -> (module, function), ``fn(gridmap, start, goal, params, cache=...) -> (Path, Field or None)``.
FIELD_PLANNERS: dict[str, tuple[str, str]] = {
    "potential": ("gridfield.following.follower", "plan_potential_with_field"),
}

#: The planners that plan on a voxel grid (a 3-D GridMap); the others refuse one.
VOXEL_PLANNERS = ("potential", "wavefront-octile")

#: Every parameter name a planner may read, with its meaning (generated from :data:`gridfield.core.params.REGISTRY`).
PARAMETERS: dict[str, str] = {name: spec.meaning for name, spec in REGISTRY.items()}


def _module(name: str) -> ModuleType:
    """The module implementing a planner of the tables above, imported on first use: one import statement
    per implementing module, so that tools (grimp, import-linter) see every arrow."""
    if name == "gridfield.following.follower":
        from .following import follower

        return follower
    if name == "gridfield.exact.continuous":
        from .exact import continuous

        return continuous
    if name == "gridfield.exact.visibility":
        from .exact import visibility

        return visibility
    if name == "gridfield.exact.anyangle":
        from .exact import anyangle

        return anyangle
    if name == "gridfield.fields.navigation":
        from .fields import navigation

        return navigation
    if name == "gridfield.fields.navfn":
        from .fields import navfn

        return navfn
    # a table entry naming a module this function does not import: the table's bug
    raise ModuleNotFoundError(f"PLANNERS names the module {name}, which gridfield.planners._module does not "
                                  "import: add its import line there", name=name)


def check_params(params: Mapping[str, Any] | None) -> dict[str, Any]:
    """Check names and values against the registry (:func:`gridfield.core.params.validate`); return a plain dict.

    Parameters
    ----------
    params : mapping or None
        Parameter name -> value.

    Returns
    -------
    dict
        The names given, values converted (an empty dict for None).

    Raises
    ------
    ParameterError
        For an unknown name (with a "did you mean") or a value out of range.

    Examples
    --------
    >>> check_params({"zeta": 1, "step": 0.1})
    {'zeta': 1.0, 'step': 0.1}
    >>> check_params({"zetta": 1.0})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: unknown parameter 'zetta'; did you mean 'zeta'? ...
    """
    return dict(validate(params))


def get_planner(name: str) -> tuple[Callable[..., Path], str]:
    """The planner function registered as ``name`` and its kind ("grid" or "world").

    Parameters
    ----------
    name : str
        A key of :data:`PLANNERS`.

    Returns
    -------
    function : callable
        ``fn(target, start, goal, params) -> Path``, imported on this call.
    kind : {"grid", "world"}
        What it plans on: a GridMap or a World.

    Raises
    ------
    ParameterError
        For a name not in :data:`PLANNERS`.
    GridfieldError
        When the planner's module needs an optional third-party package that is not installed
        ("not available in this installation", naming the package): :func:`gridfield.compare.batch_compare`
        reports such planners as skipped.
    ImportError
        When importing the planner's module fails inside gridfield itself (a bug, raised as it is).
    AttributeError
        When the registry entry names a function its module does not define (a bug in :data:`PLANNERS`).

    Examples
    --------
    >>> fn, kind = get_planner("potential")
    >>> fn.__name__, kind
    ('plan_potential', 'grid')
    >>> get_planner("visibility")[1]
    'world'
    """
    if name not in PLANNERS:
        raise ParameterError(f"unknown planner {name!r}; expected one of {', '.join(PLANNERS)}")
    module, func, kind, _ = PLANNERS[name]
    try:
        mod = _module(module)
    except ImportError as e:
        missing = e.name or ""
        if not missing or missing == "gridfield" or missing.startswith("gridfield."):
            raise  # gridfield's own import failed (or the failure names no module): a bug, not a missing extra
        raise GridfieldError(f"planner {name!r} is not available in this installation (install the package "
                             f"providing {missing.partition('.')[0]!r}: {e})") from None
    try:
        fn = getattr(mod, func)
    except AttributeError as e:
        raise AttributeError(f"PLANNERS[{name!r}] names {module}.{func}, which {module} does not define "
                             f"(a bug in the planner registry)") from e
    return fn, kind


class Plan(NamedTuple):
    """A path and the potential field it followed (:func:`plan_with_field`).

    Attributes
    ----------
    path : Path
        As :func:`plan` returns it.
    field : Field or None
        The :class:`~gridfield.fields.potential.Field` the ``potential`` planner built and followed (its ``map``
        is the grid planned on); ``None`` for the other planners and when no field was built (a goal
        found unreachable at once).

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> w = read_world(bundled_map("seed003_circles.yaml"))
    >>> path, field = plan_with_field("potential", w, w.start, w.goal, {"ko": 5.0})
    >>> path.status, field.goal == tuple(w.goal)
    ('reached', True)
    """

    path: Path
    field: Field | None


def plan_with_field(planner: str, target: World | GridMap, start: ArrayLike, goal: ArrayLike,
                    params: Mapping[str, Any] | None = None, *, resolution: float | None = None,
                    cache: dict[Any, Any] | None = None) -> Plan:
    """:func:`plan`, and the field the path followed, for a caller who draws it (so that it builds nothing again).

    Parameters
    ----------
    planner, target, start, goal, params, resolution, cache
        As for :func:`plan`.

    Returns
    -------
    Plan
        ``(path, field)``: the same path as :func:`plan` gives, and the ``potential`` planner's field
        (``None`` for the other planners).

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> gm = GridMap(Grid((1, 4), 1.0), np.zeros((1, 4), bool))
    >>> plan_with_field("wavefront", gm, (0.5, 0.5), (3.5, 0.5)).field is None
    True
    """
    return Plan(*_plan(planner, target, start, goal, params, resolution=resolution, cache=cache, want_field=True))


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
    the map's blocked cells as exact polygons (:func:`gridfield.geometry.gridpoly.grid_world`; on those,
    ``visibility`` is the any-angle optimum of :mod:`gridfield.exact.anyangle`, its graph cached per map).
    With a ``cache`` dict (kept by the caller across calls on the same ``target`` object), the
    rasterized grid and the planner's own per-map work (the brushfire of ``potential``, the graph of
    ``visibility``; every planner function takes ``cache=None``) are computed once and reused.

    Parameters
    ----------
    planner : str
        A name of :data:`PLANNERS`.
    target : World or GridMap
        The map or world planned on.
    start, goal : (x, y)
        World points; checked to be free.
    params : mapping, optional
        Parameter names and values (:data:`PARAMETERS`), over the world file's ``params``.
    resolution : float, optional
        Cell size a grid planner rasterizes a world at (default: the world's own).
    cache : dict, optional
        Per-map work kept by the caller across calls on the same ``target``.

    Returns
    -------
    Path
        The path; ``extra`` records the query's ``start`` and ``goal`` and its ``field_seconds`` /
        ``follow_seconds``.

    Raises
    ------
    ParameterError
        An unknown planner or parameter, a bad value, or a start or goal that is not two numbers.
    GridfieldError
        A start or goal outside the map or inside an obstacle.

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> w = read_world(bundled_map("seed000.yaml"))
    >>> exact = plan("visibility", w, w.start, w.goal)   # shortest path among the polygons
    >>> exact.status, round(exact.length, 3)
    ('reached', 22.387)
    >>> grid = plan("potential", w, w.start, w.goal, resolution=0.5)
    >>> grid.status, grid.length >= exact.length
    ('reached', True)
    >>> plan("nonsense", w, w.start, w.goal)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: unknown planner 'nonsense'; expected one of ...
    """
    return _plan(planner, target, start, goal, params, resolution=resolution, cache=cache)[0]


def _plan(
    planner: str,
    target: World | GridMap,
    start: ArrayLike,
    goal: ArrayLike,
    params: Mapping[str, Any] | None,
    *,
    resolution: float | None,
    cache: dict[Any, Any] | None,
    want_field: bool = False,
) -> tuple[Path, Any]:
    """The dispatch behind :func:`plan` and :func:`plan_with_field`: the path, and the field the
    planner followed when ``want_field`` and the planner builds one (:data:`FIELD_PLANNERS`), else None."""
    from .geometry.world import World

    fn, kind = get_planner(planner)
    from .geometry.cspace import PoseMap

    if isinstance(target, PoseMap):  # a turning robot's pose grid (apply_robot(..., headings=N))
        return _plan_poses(planner, target, start, goal, params)
    if not isinstance(target, World | GridMap):
        raise ArgumentTypeError(
            f"target must be a World (a vector world, e.g. gridfield.io.read_world) or a GridMap, "
            f"got {type(target).__name__}"
        )
    if params is not None and not isinstance(params, Mapping):
        raise ArgumentTypeError(f"params must be a mapping of parameter names to values, got {type(params).__name__}")
    given = validate(params)
    if isinstance(target, GridMap) and target.grid.ndim == 3 and planner not in VOXEL_PLANNERS:
        raise ParameterError(f"planner {planner!r} plans on 2-D maps; a voxel grid (3-D) is planned by "
                             f"{' or '.join(repr(v) for v in VOXEL_PLANNERS)}")
    nd = target.grid.ndim if isinstance(target, GridMap) else 2
    start, goal = _point("start", start, nd), _point("goal", goal, nd)
    base = dict(target.params) if isinstance(target, World) else (
        dict(target.world.params) if isinstance(target.world, World) else {})
    merged = dict(validate(base))
    merged.update(given)
    if kind == "grid":
        from .geometry.rasterize import as_gridmap

        if cache is None:
            gm = as_gridmap(target, resolution)
        else:
            key = ("gridmap", target, resolution)
            if key not in cache:
                cache[key] = as_gridmap(target, resolution)
            gm = cache[key]
        from .core.limits import check_grid

        check_grid(gm.grid.shape, f"plan:{planner}", f"plan {planner} on {gm.source or 'the grid map'}")  # bytes
        s, g = gm.check_point("start", start), gm.check_point("goal", goal)
        t0 = time.perf_counter()
        if want_field and planner in FIELD_PLANNERS:
            module, func = FIELD_PLANNERS[planner]
            path, field = getattr(_module(module), func)(gm, s, g, merged, cache=cache)
            return _corner(_with_endpoints(path, s, g, t0), gm, s, g), field
        return _corner(_with_endpoints(fn(gm, s, g, merged, cache=cache), s, g, t0), gm, s, g), None
    world = target if isinstance(target, World) else target.world
    if not isinstance(world, World) and planner in GRID_VARIANTS:
        assert isinstance(target, GridMap)  # a World is its own world
        _guard_seconds(planner, target, merged, cache)
        module, func = GRID_VARIANTS[planner]
        fn = getattr(_module(module), func)
        s, g = target.check_point("start", start), target.check_point("goal", goal)
        t0 = time.perf_counter()
        return _corner(_with_endpoints(fn(target, s, g, merged, cache=cache), s, g, t0), target, s, g), None
    if not isinstance(world, World):
        # a bitmap / ROS / Moving AI map: its blocked cells as exact polygons (gridfield.geometry.gridpoly),
        # built once per map object; "visibility" then runs on the grid itself (gridfield.exact.anyangle)
        assert isinstance(target, GridMap)  # a World is its own world
        _guard_seconds(planner, target, merged, cache)  # the stages' summed estimate, before the polygons
        world = _grid_world(target, cache)
        s, g = target.check_point("start", start), target.check_point("goal", goal)
    else:
        s, g = world.check_point("start", start), world.check_point("goal", goal)
    t0 = time.perf_counter()
    path = _with_endpoints(fn(world, np.asarray(s), np.asarray(g), merged, cache=cache), s, g, t0)
    return (_corner(path, target, s, g) if isinstance(target, GridMap) and target.world is None else path), None


def _plan_poses(planner: str, pm: Any, start: ArrayLike, goal: ArrayLike,
                params: Mapping[str, Any] | None) -> tuple[Path, Any]:
    """:func:`plan` on a :class:`~gridfield.geometry.cspace.PoseMap`: the pose planners of
    :mod:`gridfield.following.posefollow` (``potential``, ``wavefront-octile``)."""
    from .following.posefollow import plan_poses

    if planner not in ("potential", "wavefront-octile"):
        raise ParameterError(f"planner {planner!r} does not plan for a turning robot (a PoseMap); use 'potential' "
                             "or 'wavefront-octile'")
    given = validate(params)
    return plan_poses(pm, start, goal, given, planner=planner)


def _corner(path: Path, gridmap: GridMap, start: Any, goal: Any) -> Path:
    """A run that did not reach on a disc robot's configuration space whose only way is a diagonal through
    a corner (:attr:`GridMap.diagonals`, taken only by the grid planners' discrete steps): the hint says so
    (:func:`gridfield.following.diagnose.with_corner_passage`, which decides; imported only for such a map)."""
    if gridmap.diagonals is None:
        return path
    from .following.diagnose import with_corner_passage

    return with_corner_passage(path, gridmap, start, goal)


def _point(name: str, value: Any, ndim: int = 2) -> np.ndarray:
    """A start/goal point as a float array of shape (2,) (on a voxel grid, ``ndim`` 3: (3,)), or a
    ParameterError saying what was expected."""
    if ndim == 2:
        return np.array(as_xy(value, name))
    try:
        raw = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raw = None
    if raw is None or raw.size != 3 or not np.isfinite(raw).all():
        raise ParameterError(f"{name} must be three numbers X Y Z (finite) on a voxel grid, got {shorten(value)}")
    return raw


def search_stages(planner: str, gm: GridMap, params: Mapping[str, Any] | None = None
                  ) -> list[tuple[str, dict[str, float]]]:
    """The searches a world planner runs on a grid map, with their units of work (:mod:`gridfield.core.limits`).

    Counted on the blocked cells without building anything (:func:`gridfield.core.limits.grid_map_work`):
    the any-angle graph for ``visibility`` when :data:`gridfield.exact.anyangle.SEARCH` is ``"graph"`` (none
    for the default Polyanya search, whose navigation mesh is linear in the cells), the exact polygons and the descent among them for
    ``exact-potential`` (at most ``max_iterations`` follower steps), the polygons for the
    navigation functions; none for the grid planners (their cost is their cells: the size guard).

    Parameters
    ----------
    planner : str
    gm : GridMap
    params : mapping, optional
        ``max_iterations`` is read.

    Returns
    -------
    list of (str, dict)
        Stage names and work, for :func:`gridfield.core.limits.check_stages`.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((4, 5), bool); occ[1:3, 1:3] = True
    >>> search_stages("visibility", GridMap(Grid((4, 5), 1.0), occ))  # Polyanya: no per-map graph
    []
    >>> [name for name, _ in search_stages("exact-potential", GridMap(Grid((4, 5), 1.0), occ))]
    ['exact polygons', 'exact potential']
    """
    from .core.limits import grid_map_work
    from .core.params import MAX_ITERATIONS

    kind = get_planner(planner)[1]
    if kind == "grid":
        return []
    work = grid_map_work(gm.occupied)
    if planner == "visibility":
        from .exact.anyangle import SEARCH

        # the default search (Polyanya) builds a navigation mesh in milliseconds; only the graph search's
        # visibility graph grows with the map's detail
        return [("any-angle graph", {"convex corner": work["convex corner"]})] if SEARCH == "graph" else []
    stages = [("exact polygons", {"blocked run": work["blocked run"]})]
    if planner == "exact-potential":
        steps = (params or {}).get("max_iterations")
        stages.append(("exact potential", {"obstacle vertex": work["obstacle vertex"],
                                           "follower step among grid polygons": MAX_ITERATIONS if steps is None
                                           else float(steps)}))
    return stages


def _guard_seconds(planner: str, gm: GridMap, params: Mapping[str, Any], cache: dict[Any, Any] | None) -> None:
    """Refuse up front a world planner on a grid map whose searches together would take too long."""
    from .core.limits import check_stages

    key = ("search_stages", planner, gm, params.get("max_iterations"))
    if cache is not None and key in cache:  # already checked (a batch of pairs on one map)
        return
    check_stages(search_stages(planner, gm, params), f"{planner} on {gm.source or 'the grid map'}")
    if cache is not None:
        cache[key] = True


def _grid_world(gm: GridMap, cache: dict[Any, Any] | None) -> World:
    from .geometry.gridpoly import grid_world

    if cache is None:
        return grid_world(gm)
    key = ("grid_world", gm)
    if key not in cache:
        cache[key] = grid_world(gm)
    world: World = cache[key]
    return world


def _with_endpoints(path: Path, start: np.ndarray, goal: np.ndarray, t0: float) -> Path:
    """Record the query in ``path.extra`` (``start``, ``goal``) so figures need not guess the goal, and
    its times: ``seconds`` becomes the whole query after loading (fields + following), with
    ``extra["field_seconds"]`` (building the fields) and ``extra["follow_seconds"]`` (the planner's
    own time) beside it."""
    total = time.perf_counter() - t0
    extra: PathExtra = dict(path.extra)  # type: ignore[assignment]  # the planner's keys, checked by Path
    extra.setdefault("start", tuple(float(v) for v in start))  # type: ignore[typeddict-item]  # (x, y) or (x, y, z)
    extra.setdefault("goal", tuple(float(v) for v in goal))  # type: ignore[typeddict-item]
    build = float(extra.get("build_seconds", 0.0))
    extra["field_seconds"] = build
    extra["follow_seconds"] = float(path.seconds)
    # a new Path (replace: the points are a float (N, 2) array already, so they are not copied)
    return dataclasses.replace(path, extra=extra, seconds=max(total, build + float(path.seconds)))
