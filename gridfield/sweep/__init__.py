"""Batch sweeps: many planner runs over maps, start/goal pairs and parameter grids.

A sweep spec (YAML) names maps, the start/goal pairs on each (listed, random, or Moving AI
scenarios), the planners and a grid of parameter values (the Cartesian product is run)::

    output: runs.csv              # one row per run; summary goes to runs.summary.csv
    maps:
      - path: maps/seed000.yaml   # relative to the spec file
        resolution: 0.1
        pairs: [[[1, 10], [22, 12]]]
        random_pairs: {n: 20, seed: 0}
      - path: maps/arena/arena.map
        scenarios: maps/arena/arena.map.scen
        limit: 40
        robot_radius: 0.5         # or robot: {polygon: [[x, y], ...]}; also allowed at the top level
    planners: [potential, wavefront-octile]
    params:                       # every combination is run
      q_star: [1.0, 2.0]
      eta: [1.0]
    optimal_any_angle: true       # optional, here or per map entry: the column optimal_any_angle

With ``optimal_any_angle: true`` (top level: every map; in a map entry: that map) each row also
gets the exact any-angle (Euclidean) optimum of its query in the column ``optimal_any_angle``,
beside ``optimal`` (the octile optimum of a Moving AI scenario file): on a grid map the taut
visibility graph of :mod:`gridfield.anyangle`, on a vector world its visibility graph
(:mod:`gridfield.visibility`). The graph is built once per map and worker process and shared with
the ``visibility`` planner's runs on that map; each (start, goal) is solved once, whatever the
planners and parameters. NaN where not asked for or where the goal cannot be reached. The summary
then gives ``length_ratio_any_angle`` beside ``length_ratio``. Exact planners run on grid maps too
(``visibility``, ``exact-potential``: on the map's blocked cells as exact polygons).

The whole spec is validated before anything runs: unknown keys (with a "did you mean"), the
types and ranges of every value, every parameter combination (:func:`_validate_params`), each
map's grid size against the memory limit (:mod:`gridfield.limits`), scenario files against their
map's size.

Runs of one map are grouped into batches (one task each). Each map is loaded and rasterized once
per worker process and its brushfire distance map computed once, not per run. Batches go to a
local process pool (all cores) by default, or to a Dask cluster (``scheduler=ADDRESS``, needs
``pip install gridfield[dask]``), where the submitter reads each map once and ships it to the
workers (they need not share its filesystem). A worker lost mid-sweep (killed, out of memory) has
its unfinished batches redone: by Dask on a cluster, in a fresh pool locally (up to
:data:`POOL_RESTARTS` times).

The rows file is a journal: locked while a sweep writes it, each row written whole (one write of
one line, flushed), repaired when opened (a partial last line left by a crash is cut off and its
run done again; damaged or duplicate lines are dropped). An interrupted sweep (SIGINT, SIGTERM, a
crash at any byte) started again therefore ends with exactly one row per run. Any failure of one
run becomes that run's ``error: ...`` row.
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import os
import time
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path as FsPath
from typing import Any

import numpy as np

from ..errors import GridfieldError, MapFormatError, ParameterError, check_positive, shorten

__all__ = ["COLUMNS", "Run", "SweepInterrupted", "load_spec", "run_batch", "run_one", "run_sweep", "summarize"]

#: Columns of the rows file, in order.
COLUMNS = ("map", "planner", "params", "start_x", "start_y", "goal_x", "goal_y", "status", "length",
           "optimal", "steps", "ms", "optimal_any_angle")

#: Columns of rows files written before ``optimal_any_angle`` existed (resumed: the column is added).
_OLD_COLUMNS = COLUMNS[:-1]


@dataclass(frozen=True)
class Run:
    """One planner run of a sweep (plain data, cheap to send to a worker).

    Attributes
    ----------
    map : str
        The map file.
    resolution : float or None
        Cell size for rasterizing a vector world (None: the world's own).
    planner : str
        A name of :data:`gridfield.planners.PLANNERS`.
    params : tuple of (str, value) pairs
        The parameter combination, sorted by name.
    start, goal : tuple of float
        The query (world coordinates).
    optimal : float
        The scenario file's (octile) optimum, NaN when not known.
    robot : tuple
        ``()`` a point robot, ``("radius", r)`` or ``("polygon", ((x, y), ...))``.
    any_angle : bool
        Whether the row gets the ``optimal_any_angle`` column (not part of :attr:`key`).

    Examples
    --------
    >>> r = Run("maps/seed000.yaml", 0.5, "potential", (("q_star", 2.0),), (1.0, 10.0), (22.0, 12.0))
    >>> r.params_json, r.key[3:]
    ('{"q_star": 2.0}', ('1', '10', '22', '12'))
    """

    map: str
    resolution: float | None
    planner: str
    params: tuple[tuple[str, Any], ...]
    start: tuple[float, float]
    goal: tuple[float, float]
    optimal: float = math.nan
    robot: tuple[Any, ...] = ()  # () a point, ("radius", r) or ("polygon", ((x, y), ...))
    any_angle: bool = False  # fill the optimal_any_angle column (not part of the run's identity)

    @property
    def params_json(self) -> str:
        d: dict[str, Any] = dict(self.params)
        if self.robot:
            d["robot"] = {self.robot[0]: self.robot[1] if self.robot[0] == "radius" else
                          [list(v) for v in self.robot[1]]}
        return json.dumps(d, sort_keys=True)

    @property
    def key(self) -> tuple[str, ...]:
        """Identity of the run in the rows file (used to resume)."""
        return (self.map, self.planner, self.params_json, *(f"{v:.9g}" for v in (*self.start, *self.goal)))


# ----------------------------------------------------------------------------------------
# Spec
# ----------------------------------------------------------------------------------------
#: Keys of a spec's top level and of one ``maps`` entry.
SPEC_KEYS = ("output", "maps", "planners", "params", "robot", "robot_radius", "optimal_any_angle")
MAP_KEYS = ("path", "resolution", "pairs", "random_pairs", "scenarios", "limit", "robot", "robot_radius",
            "optimal_any_angle")

#: Exact planners that also run on grid maps (on the blocked cells as exact polygons, gridfield.gridpoly).
GRID_MAP_EXACT = ("visibility", "exact-potential")

#: Most runs one spec may expand to (each run is a row and a few hundred bytes of memory).
MAX_RUNS = 10**8


def _need(mapping: Mapping[str, Any], key: str, where: str) -> Any:
    if key not in mapping:
        raise MapFormatError(f"{where}: missing key {key!r}")
    return mapping[key]


def _unknown_keys(mapping: Mapping[Any, Any], known: Sequence[str], where: str) -> None:
    import difflib

    for key in mapping:
        if key not in known:
            close = difflib.get_close_matches(str(key), known, n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise MapFormatError(f"{where}: unknown key {shorten(key)}; {hint}expected one of {', '.join(known)}")


def _integer(value: Any, where: str, *, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise MapFormatError(f"{where}: must be an integer >= {minimum}, got {shorten(value)}")
    return value


def _spec_path(value: Any, base: FsPath, where: str) -> FsPath:
    if not isinstance(value, str) or not value.strip():
        raise MapFormatError(f"{where}: must be a file name, got {shorten(value)}")
    p = FsPath(value)
    return p if p.is_absolute() else base / p


def _validate_params(planner: str, params: Mapping[str, Any]) -> dict[str, Any]:
    """Check one planner's parameter combination (names and values) before any run starts.

    The one place a sweep validates parameters: names and values through the parameter registry
    (:func:`gridfield.params.validate`), then the potential's cross-parameter rules
    (:func:`gridfield.potential.resolve_params`). Raises :class:`ParameterError` naming the
    parameter and its value.

    Examples
    --------
    >>> _validate_params("potential", {"eta": 2.0})
    {'eta': 2.0}
    >>> _validate_params("potential", {"eta": -1})
    Traceback (most recent call last):
    ...
    gridfield.errors.ParameterError: eta must be a finite number >= 0, got -1
    """
    from ..planners import check_params
    from ..potential import resolve_params

    p = check_params(params)
    resolve_params(p)
    try:
        json.dumps(p, sort_keys=True, allow_nan=True)
    except (TypeError, ValueError):
        raise ParameterError(f"parameter values must be numbers, strings or booleans, got {shorten(p)}") from None
    return p


def _pairs(entry: Mapping[str, Any], w: str) -> list[tuple[tuple[float, float], tuple[float, float], float]]:
    raw = entry.get("pairs") or []
    if not isinstance(raw, list):
        raise MapFormatError(f"{w}.pairs: expected a list of [[sx, sy], [gx, gy]], got {shorten(raw)}")
    pairs = []
    for j, pair in enumerate(raw):
        try:
            (sx, sy), (gx, gy) = pair
            xy = [v if not isinstance(v, bool) else math.nan for v in (sx, sy, gx, gy)]
            sx, sy, gx, gy = (float(v) for v in xy)
            if not all(math.isfinite(v) for v in (sx, sy, gx, gy)):
                raise ValueError
        except (TypeError, ValueError):
            raise MapFormatError(f"{w}.pairs[{j}]: expected [[sx, sy], [gx, gy]] (finite numbers), "
                                 f"got {shorten(pair)}") from None
        pairs.append(((sx, sy), (gx, gy), math.nan))
    return pairs


def load_spec(path: str | os.PathLike[str], *, output: str | os.PathLike[str] | None = None
              ) -> tuple[list[Run], FsPath]:
    """Read and fully validate a sweep spec; return the list of runs and the output path.

    ``output`` replaces the spec's ``output``. If another sweep is writing the output, this stops
    at once (before any map is read).

    Everything is checked before a single run starts: unknown keys (with a "did you mean"),
    types and ranges of every value, every parameter combination for every planner, each map
    (read, and its grid sized against the memory limit), pairs, scenario files against their
    map's size, and planners that need a vector world against grid maps.

    Parameters
    ----------
    path : str or path-like
        The YAML spec (relative paths in it are relative to its folder).
    output : str or path-like, optional
        The rows file, instead of the spec's ``output`` (default ``SPEC.csv`` beside the spec).

    Returns
    -------
    runs : list of Run
        Every (map, pair, planner, parameter combination), maps in spec order.
    output : pathlib.Path
        The rows file.

    Raises
    ------
    MapFormatError
        Naming the spec file and the key at fault.

    Examples
    --------
    >>> from gridfield.io import bundled_map
    >>> runs, output = load_spec(bundled_map("sweep_example.yaml"))
    >>> len(runs), output.name, sorted({r.planner for r in runs}), sum(r.any_angle for r in runs)
    (80, 'sweep_example.csv', ['potential', 'wavefront-octile'], 40)
    """
    from ..grid import Grid, GridMap
    from ..io import read, read_scen, read_yaml
    from ..planners import PLANNERS
    from ..rasterize import as_gridmap
    from ..world import World

    spec_path = FsPath(path)
    spec = read_yaml(spec_path)
    where = str(spec_path)
    if not isinstance(spec, Mapping):
        raise MapFormatError(f"{where}: a sweep spec must be a YAML mapping with maps, planners and params")
    _unknown_keys(spec, SPEC_KEYS, where)
    base = spec_path.parent
    if output is None:
        output = _spec_path(spec.get("output", spec_path.with_suffix(".csv").name), base, f"{where}: output")
    output = FsPath(output)
    _Journal.check_unlocked(output)
    planners = spec.get("planners", ["potential"])
    if isinstance(planners, str):
        planners = [planners]
    if not isinstance(planners, list) or not planners:
        raise MapFormatError(f"{where}: planners must be a planner name or a non-empty list of them")
    for p in planners:
        if not isinstance(p, str) or p not in PLANNERS:
            raise MapFormatError(f"{where}: planners: unknown planner {shorten(p)}; expected one of {', '.join(PLANNERS)}")
    grid = spec.get("params") or {}
    if not isinstance(grid, Mapping):
        raise MapFormatError(f"{where}: params must map parameter names to a value or a list of values")
    names = sorted(grid, key=str)
    values = [v if isinstance(v, list) else [v] for v in (grid[n] for n in names)]
    for n, v in zip(names, values, strict=True):
        if not v:
            raise MapFormatError(f"{where}: params.{n}: an empty list of values gives no runs")
    n_combos = math.prod(len(v) for v in values)
    if n_combos * len(planners) > MAX_RUNS:
        raise MapFormatError(f"{where}: params: {n_combos:.3g} combinations x {len(planners)} planners exceed "
                             f"{MAX_RUNS:g} runs; sweep fewer values")
    combos = []
    for combo in itertools.product(*values):
        params = dict(zip(names, combo, strict=True))
        for planner in planners:
            try:
                _validate_params(planner, params)
            except ParameterError as e:
                raise MapFormatError(f"{where}: params ({planner}): {e}") from None
        combos.append(params)

    any_angle_all = _flag(spec, "optimal_any_angle", where)
    maps = _need(spec, "maps", where)
    if not isinstance(maps, list) or not maps:
        raise MapFormatError(f"{where}: maps must be a non-empty list")
    runs: list[Run] = []
    for i, entry in enumerate(maps):
        w = f"{where}: maps[{i}]"
        if isinstance(entry, str):
            entry = {"path": entry}
        if not isinstance(entry, Mapping):
            raise MapFormatError(f"{w}: expected a map file name or a mapping with 'path', got {shorten(entry)}")
        _unknown_keys(entry, MAP_KEYS, w)
        map_path = _spec_path(_need(entry, "path", w), base, f"{w}.path")
        resolution = entry.get("resolution")
        robot = _robot_key(entry, spec, w)
        if resolution is not None:
            try:
                resolution = check_positive("resolution", resolution if isinstance(resolution, int | float) and not  # type: ignore[arg-type]  # "" is rejected by check_positive on purpose
                                            isinstance(resolution, bool) else "")
            except ParameterError:
                raise MapFormatError(f"{w}.resolution: must be a positive finite number, got {shorten(resolution)}") from None
        try:
            target = _with_robot(read(map_path), robot)
            # the grid every grid planner will use, sized against the memory limit before anything runs
            gm = as_gridmap(target, resolution) if isinstance(target, GridMap) or entry.get("random_pairs") or (
                entry.get("scenarios")) else None
            if gm is None and isinstance(target, World):
                res = resolution if resolution is not None else target.resolution
                if res is not None:
                    Grid.covering(target.bounds, res)
                elif any(PLANNERS[p][2] == "grid" for p in planners):
                    raise MapFormatError(f"{map_path}: a world without 'resolution'; give the map entry a resolution")
        except GridfieldError as e:
            raise MapFormatError(f"{w}: {e}") from None
        if not isinstance(target, World) and not isinstance(getattr(target, "world", None), World):
            exact = [p for p in planners if PLANNERS[p][2] == "world" and p not in GRID_MAP_EXACT]
            if exact:
                raise MapFormatError(f"{w}: planner {exact[0]!r} needs a vector world, but {map_path.name} is a grid map")
        pairs = _pairs(entry, w)
        rp = entry.get("random_pairs")
        if rp is not None:
            if not isinstance(rp, Mapping):
                raise MapFormatError(f"{w}.random_pairs: expected a mapping {{n: N, seed: S}}, got {shorten(rp)}")
            _unknown_keys(rp, ("n", "seed"), f"{w}.random_pairs")
            n = _integer(rp.get("n", 10), f"{w}.random_pairs.n", minimum=1)
            if n > MAX_RUNS:
                raise MapFormatError(f"{w}.random_pairs.n: {n} pairs exceed {MAX_RUNS:g} runs")
            seed = _integer(rp.get("seed", 0), f"{w}.random_pairs.seed", minimum=0)
            try:
                pairs += _random_pairs(gm, n, seed)
            except GridfieldError as e:
                raise MapFormatError(f"{w}.random_pairs: {e}") from None
        if entry.get("limit") is not None and not entry.get("scenarios"):
            raise MapFormatError(f"{w}.limit: limits the scenarios, but the entry has no 'scenarios'")
        if entry.get("scenarios") is not None:
            scen_path = _spec_path(entry["scenarios"], base, f"{w}.scenarios")
            try:
                scen = read_scen(scen_path)
            except GridfieldError as e:
                raise MapFormatError(f"{w}.scenarios: {e}") from None
            assert gm is not None
            wrong = np.flatnonzero((scen.width != gm.shape[1]) | (scen.height != gm.shape[0]))
            if wrong.size:
                k = int(wrong[0])
                raise MapFormatError(
                    f"{w}.scenarios: {scen_path.name}: scenario {k + 1} is for a {scen.width[k]} x {scen.height[k]} "
                    f"map (width x height), but {map_path.name} is {gm.shape[1]} x {gm.shape[0]} cells"
                )
            limit = _integer(entry.get("limit", len(scen)), f"{w}.limit", minimum=1)
            idx = np.flatnonzero(~scen.no_path)[:limit]
            pairs += [(tuple(scen.start_xy[k]), tuple(scen.goal_xy[k]), float(scen.optimal[k])) for k in idx]
        if not pairs and isinstance(target, World) and target.start and target.goal:
            pairs.append((target.start, target.goal, math.nan))
        if not pairs:
            raise MapFormatError(f"{w}: no start/goal pairs (give pairs, random_pairs or scenarios)")
        if len(runs) + len(planners) * len(combos) * len(pairs) > MAX_RUNS:
            raise MapFormatError(f"{w}: the spec expands to more than {MAX_RUNS:g} runs; split the sweep")
        any_angle = _flag(entry, "optimal_any_angle", w, default=any_angle_all)
        for planner, params, (s, g, opt) in itertools.product(planners, combos, pairs):
            runs.append(Run(str(map_path), resolution, planner, tuple(sorted(params.items())), s, g, opt, robot,
                            any_angle))
    return runs, output


def _flag(mapping: Mapping[str, Any], key: str, where: str, *, default: bool = False) -> bool:
    """A true/false spec value (``default`` when absent); anything else is a MapFormatError."""
    value = mapping.get(key, default)
    if not isinstance(value, bool):
        raise MapFormatError(f"{where}: {key} must be true or false, got {shorten(value)}")
    return value


def _robot_key(entry: Mapping[str, Any], spec: Mapping[str, Any], where: str) -> tuple[Any, ...]:
    """A map entry's robot (``robot:`` or ``robot_radius:``, else the spec's) as plain hashable data."""
    from ..world import robot_from_value

    source = entry if ("robot" in entry or "robot_radius" in entry) else spec
    value = source.get("robot", source.get("robot_radius"))
    if value is None:
        return ()
    r = robot_from_value(value, f"{where}: robot")
    if r.radius is not None:
        return ("radius", r.radius)
    assert r.vertices is not None
    return ("polygon", tuple(map(tuple, r.vertices.tolist())))


def _with_robot(target: Any, robot: tuple[Any, ...]) -> Any:
    if not robot:
        return target
    from ..cspace import apply_robot

    return apply_robot(target, robot[1] if robot[0] == "radius" else list(robot[1]))


def _random_pairs(gm: Any, n: int, seed: int) -> list[Any]:
    """``n`` random start/goal pairs in free cells of the grid map (reproducible with ``seed``)."""
    free = np.flatnonzero(~gm.occupied.ravel())
    if free.size < 2:
        raise GridfieldError(f"{gm.source}: fewer than two free cells; cannot draw random start/goal pairs")
    rng = np.random.default_rng(seed)
    cells = rng.choice(free, size=(n, 2), replace=True)
    rows, cols = np.unravel_index(cells, gm.shape)
    pts = gm.grid.cell_to_world(np.stack([rows.ravel(), cols.ravel()], axis=1)).reshape(n, 2, 2)
    return [(tuple(p[0]), tuple(p[1]), math.nan) for p in pts.tolist()]


# ----------------------------------------------------------------------------------------
# Running
# ----------------------------------------------------------------------------------------
#: Per process: (map, resolution, identity of a shipped map or None) -> {"target": the map, ...the
#: plan cache of that map}, the most recently used last; only the last :data:`_CACHE_MAPS` are kept.
_CACHE: dict[Any, Any] = {}
_CACHE_MAPS = 4

#: How often a local pool whose worker died is replaced before the sweep gives up.
POOL_RESTARTS = 3

#: Seconds to wait for a Dask scheduler to answer.
SCHEDULER_TIMEOUT = 10

#: Longest error status written to a row.
STATUS_LIMIT = 300


def _map_cache(run: Run, target: Any = None) -> dict[Any, Any]:
    """The plan cache of the run's map, holding the map (loaded here from its path unless shipped).

    A shipped map is keyed by its identity too: a long-lived cluster may see two sweeps whose maps
    share a (relative) path but not their content. The cache holds the map, so the identity stays unique.
    """
    key = (run.map, run.resolution, run.robot, None if target is None else id(target))
    cache = _CACHE.pop(key, None)
    if cache is None:
        if target is None:
            from ..io import read

            target = _with_robot(read(run.map), run.robot)
        cache = {"target": target}
    _CACHE[key] = cache  # most recently used last
    while len(_CACHE) > _CACHE_MAPS:
        _CACHE.pop(next(iter(_CACHE)))
    return cache


def _one_line(text: str, limit: int = STATUS_LIMIT) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def run_one(run: Run, target: Any = None) -> dict[str, Any]:
    """Run one planner call; return its row. Any failure of the run becomes its status ``error: ...``.

    Parameters
    ----------
    run : Run
        The run.
    target : World or GridMap, optional
        The run's map when it is shipped with the task (a cluster); by default the map is read
        from ``run.map`` (once per process, with its plan cache).

    Returns
    -------
    dict
        The row: a value per name of :data:`COLUMNS` (``ms`` is the planner call's time; the
        any-angle optimum, when asked for, is computed after it).

    Examples
    --------
    >>> from gridfield.io import bundled_map
    >>> row = run_one(Run(bundled_map("arena/arena.map"), None, "wavefront-octile", (), (1.5, 37.5), (4.5, 36.5),
    ...                   3.41421, any_angle=True))
    >>> row["status"], round(row["length"], 5), round(row["optimal_any_angle"], 5)   # octile, then straight
    ('reached', 3.41421, 3.16228)
    """
    from ..planners import plan

    t0 = time.perf_counter()
    try:
        cache = _map_cache(run, target)
        path = plan(run.planner, cache["target"], run.start, run.goal, dict(run.params),
                    resolution=run.resolution, cache=cache)
        status, length, steps = path.status, path.length, path.iterations
    except GridfieldError as e:
        status, length, steps = f"error: {e}", math.nan, 0
    except Exception as e:  # a bug or a resource problem in one run must not abort the sweep
        status, length, steps = f"error: {type(e).__name__}: {e}", math.nan, 0
    ms = (time.perf_counter() - t0) * 1e3
    return {
        "map": run.map, "planner": run.planner, "params": run.params_json,
        "start_x": run.start[0], "start_y": run.start[1], "goal_x": run.goal[0], "goal_y": run.goal[1],
        "status": _one_line(status), "length": length, "optimal": run.optimal, "steps": steps, "ms": round(ms, 3),
        "optimal_any_angle": _any_angle_optimum(run, target) if run.any_angle else math.nan,
    }


def _any_angle_optimum(run: Run, target: Any = None) -> float:
    """The exact any-angle optimum of the run's query (NaN when there is none or it cannot be computed).

    Solved once per (map, start, goal) and process: the result is kept in the map's plan cache,
    and so is the graph (:func:`gridfield.compare._optimum_fn` with that cache), which the
    ``visibility`` planner's runs on the map share.
    """
    try:
        cache = _map_cache(run, target)
        key = ("optimal_any_angle", run.start, run.goal)
        if key not in cache:
            solver = cache.get("optimal_any_angle_solver")
            if solver is None:
                from ..compare import _optimum_fn

                solver = cache["optimal_any_angle_solver"] = _optimum_fn(cache["target"], cache=cache)
            cache[key] = solver(np.asarray(run.start, dtype=float), np.asarray(run.goal, dtype=float))
        value = float(cache[key])
    except Exception:  # the column is a reference beside the run: a failure leaves it empty, not the sweep
        return math.nan
    return value if math.isfinite(value) else math.nan


def run_batch(runs: Sequence[Run], target: Any = None) -> list[dict[str, Any]]:
    """Rows of several runs of one map (one task of a pool or a cluster).

    Parameters
    ----------
    runs : runs of one map (and resolution)
    target : the map itself when shipped with the task (default: read from ``runs[k].map``)

    Returns
    -------
    list of dict : one row per run (see :func:`run_one`), in order

    Examples
    --------
    >>> from gridfield.io import bundled_map
    >>> m = bundled_map("arena/arena.map")
    >>> rows = run_batch([Run(m, None, p, (), (1.5, 37.5), (1.5, 36.5)) for p in ("wavefront-octile", "visibility")])
    >>> [(r["planner"], r["status"], r["length"]) for r in rows]
    [('wavefront-octile', 'reached', 1.0), ('visibility', 'reached', 1.0)]
    """
    return [run_one(r, target) for r in runs]


# ----------------------------------------------------------------------------------------
# The journal: the rows file, locked, repaired on open, appended one whole row at a time
# ----------------------------------------------------------------------------------------
def _row_key(fields: Mapping[str, str]) -> tuple[str, ...]:
    return (fields["map"], fields["planner"], fields["params"],
            *(f"{float(fields[k]):.9g}" for k in ("start_x", "start_y", "goal_x", "goal_y")))


def _format_row(row: Mapping[str, Any]) -> bytes:
    import io as _io

    buf = _io.StringIO()
    values = [row.get(c, math.nan if c == "optimal_any_angle" else "") for c in COLUMNS]  # an optional column
    csv.writer(buf, lineterminator="\n").writerow([" ".join(v.split()) if isinstance(v, str) else v for v in values])
    return buf.getvalue().encode("utf-8")


def _parse_row(line: str, columns: Sequence[str] = COLUMNS) -> dict[str, str] | None:
    """The row on one complete line (of a file with these ``columns``; the columns it lacks are
    ``nan``), or None when the line is damaged."""
    try:
        fields = next(csv.reader([line]))
    except (csv.Error, StopIteration):
        return None
    if len(fields) != len(columns):
        return None
    row = dict.fromkeys(COLUMNS, "nan")
    row.update(zip(columns, fields, strict=True))
    try:
        _row_key(row)
        float(row["length"]), float(row["optimal"]), int(row["steps"]), float(row["ms"])
        float(row["optimal_any_angle"])
        json.loads(row["params"])
    except (ValueError, TypeError):
        return None
    if not row["status"] or not row["planner"]:
        return None
    return row


class _Journal:
    """The rows file of a sweep, held locked while the sweep runs.

    On open it is repaired: a partial last line (a crash mid-write) is cut off, damaged or
    duplicate lines are dropped (their runs are done again), and the header is written if
    missing. Each row is then appended with a single ``write`` of the whole line to a file opened
    in append mode, so that a crash at any byte leaves at most one partial last line.
    """

    def __init__(self, path: FsPath) -> None:
        self.path = path
        self.notes: list[str] = []
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            self.fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_APPEND | getattr(os, "O_BINARY", 0), 0o644)
        except OSError as e:
            raise GridfieldError(f"{path}: cannot open the rows file: {e.strerror or e}") from None
        try:
            self._lock()
            self.rows, self.keys = self._recover()
        except BaseException:
            os.close(self.fd)
            raise
        self._synced = time.monotonic()

    @staticmethod
    def check_unlocked(path: FsPath) -> None:
        """Raise now if another sweep holds the lock on ``path`` (the lock itself is taken later)."""
        try:
            fd = os.open(path, os.O_RDONLY | getattr(os, "O_BINARY", 0))
        except OSError:
            return  # no file yet (or unreadable: opening it for the sweep will say so)
        try:
            _Journal._lock_fd(fd, path)
        finally:
            os.close(fd)

    def _lock(self) -> None:
        self._lock_fd(self.fd, self.path)

    @staticmethod
    def _lock_fd(fd: int, path: FsPath) -> None:
        busy = GridfieldError(
            f"{path}: another sweep is writing this rows file (it is locked); wait for it to finish, "
            "or give this sweep another --out"
        )
        try:
            import fcntl
        except ImportError:  # pragma: no cover - Windows
            import msvcrt

            try:
                msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)  # type: ignore[attr-defined]  # msvcrt: Windows only
            except OSError:
                raise busy from None
            return
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            raise busy from None

    def _read_all(self) -> bytes:
        size = os.fstat(self.fd).st_size
        chunks, pos = [], 0
        while pos < size:
            chunk = os.pread(self.fd, min(size - pos, 1 << 24), pos)
            if not chunk:
                break
            chunks.append(chunk)
            pos += len(chunk)
        return b"".join(chunks)

    def _write(self, data: bytes) -> None:
        view = memoryview(data)
        while view:
            n = os.write(self.fd, view)
            view = view[n:]

    def _recover(self) -> tuple[list[dict[str, str]], set[tuple[str, ...]]]:
        data = self._read_all()
        end = data.rfind(b"\n") + 1
        if end < len(data):  # a partial last line: the run it belonged to is done again
            os.ftruncate(self.fd, end)
            self.notes.append(f"removed a partial last line ({len(data) - end} bytes) left by an interrupted write")
            data = data[:end]
        header = ",".join(COLUMNS)
        if not data:
            self._write((header + "\n").encode())
            return [], set()
        text = data.decode("utf-8", errors="replace")
        lines = [ln[:-1] if ln.endswith("\r") else ln for ln in text.split("\n")[:-1]]
        # a rows file of an earlier version (no optimal_any_angle column) is rewritten with the column
        old = lines[0] == ",".join(_OLD_COLUMNS)
        if lines[0] != header and not old:
            raise GridfieldError(
                f"{self.path}: not a rows file of this sweep version (its first line is {shorten(lines[0][:200])}, "
                f"expected {header!r}); give another --out"
            )
        columns = _OLD_COLUMNS if old else COLUMNS
        rows: list[dict[str, str]] = []
        keys: set[tuple[str, ...]] = set()
        damaged = duplicate = 0
        for ln in lines[1:]:
            row = _parse_row(ln, columns)
            if row is None:
                damaged += 1
                continue
            key = _row_key(row)
            if key in keys:
                duplicate += 1
                continue
            keys.add(key)
            rows.append(row)
        if damaged or duplicate or old or data.endswith(b"\r\n"):
            # rewrite the file with the good rows only (a crash here loses rows, which are then redone)
            os.ftruncate(self.fd, 0)
            self._write(b"".join([(header + "\n").encode(), *(_format_row(r) for r in rows)]))
            os.fsync(self.fd)
            if old:
                self.notes.append("added the column optimal_any_angle (nan in the rows written before it)")
            if damaged:
                self.notes.append(f"dropped {damaged} damaged line(s); their runs are done again")
            if duplicate:
                self.notes.append(f"dropped {duplicate} duplicate row(s)")
        return rows, keys

    def append(self, row: Mapping[str, Any]) -> bool:
        """Write one row (whole, in one write); False if a row of that run is already there."""
        line = _format_row(row)
        parsed = _parse_row(line.decode("utf-8")[:-1])
        if parsed is None:  # pragma: no cover - run_one always makes well-formed rows
            raise GridfieldError(f"internal error: a sweep row cannot be written: {shorten(row)}")
        key = _row_key(parsed)
        if key in self.keys:
            return False
        self._write(line)
        self.keys.add(key)
        self.rows.append(parsed)
        if time.monotonic() - self._synced > 1.0:
            os.fsync(self.fd)
            self._synced = time.monotonic()
        return True

    def close(self) -> None:
        if self.fd >= 0:
            try:
                os.fsync(self.fd)
            finally:
                os.close(self.fd)  # releases the lock
                self.fd = -1


class SweepInterrupted(KeyboardInterrupt):
    """The sweep was stopped by a signal (SIGINT or SIGTERM); the rows written so far are kept."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


# ----------------------------------------------------------------------------------------
# Executors
# ----------------------------------------------------------------------------------------
def _batches(runs: Sequence[Run], workers: int, batch_size: int | None) -> list[list[Run]]:
    """Runs grouped by map, cut into batches (a few per worker per map, at most 256 runs each)."""
    groups: dict[tuple[Any, ...], list[Run]] = {}
    for r in runs:
        groups.setdefault((r.map, r.resolution, r.robot), []).append(r)
    out = []
    for group in groups.values():
        size = batch_size or max(1, min(256, math.ceil(len(group) / (4 * max(workers, 1)))))
        out += [group[k:k + size] for k in range(0, len(group), size)]
    return out


def _worker_init(max_cells: int, parent: int) -> None:
    import signal
    import threading

    from .. import limits

    # Ctrl-C reaches the whole process group: the parent stops the workers, they need not say so.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    limits._OVERRIDE.append(max_cells)  # the submitter's size limit (e.g. its --max-cells)

    # A parent killed outright (SIGKILL, a crash) cannot stop its workers, and they would wait on the
    # task queue forever (each holds a writing end of it): they watch the parent and leave with it.
    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="gridfield-parent-watch", daemon=True).start()


def _stop_pool(pool: Any) -> None:
    pool.shutdown(wait=False, cancel_futures=True)
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:
        if p.is_alive():
            p.terminate()
    for p in procs:
        p.join(timeout=5)
        if p.is_alive():  # pragma: no cover - a worker stuck in a kernel ignoring SIGTERM
            p.kill()
            p.join(timeout=5)


def _local_results(batches: Sequence[list[Run]], workers: int) -> Iterator[list[dict[str, Any]]]:
    if workers <= 1 or len(batches) <= 1:
        yield from map(run_batch, batches)
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    # "spawn", not fork: the potential kernels start an OpenMP thread pool, and a process that
    # forks after that can hang or abort ("fork() called from a process already using GNU OpenMP").
    ctx = multiprocessing.get_context("spawn")
    from ..limits import max_cells

    pending = list(batches)
    for _ in range(POOL_RESTARTS + 1):
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_worker_init,
                                   initargs=(max_cells(), os.getpid()))
        unfinished: list[list[Run]] = []
        try:
            futures = {pool.submit(run_batch, b): b for b in pending}
            for fut in as_completed(futures):
                try:
                    rows = fut.result()
                except BrokenProcessPool:  # a worker died: every batch not yet back is redone in a new pool
                    unfinished.append(futures[fut])
                    continue
                yield rows
        except BaseException:
            _stop_pool(pool)
            raise
        if not unfinished:
            pool.shutdown(wait=True)
            return
        _stop_pool(pool)
        pending = unfinished
    raise GridfieldError(
        f"worker processes died {POOL_RESTARTS + 1} time(s) (killed, or out of memory?); the rows written so far "
        "are kept: run the sweep again to resume (with fewer --workers if memory is short)"
    )


def _dask_results(batches: Sequence[list[Run]], scheduler: Any) -> Iterator[list[dict[str, Any]]]:
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise GridfieldError("--scheduler needs Dask: pip install 'gridfield[dask]'") from None
    from ..io import read

    if isinstance(scheduler, Client):
        client = scheduler
    else:
        try:
            client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
        except (OSError, ValueError, TypeError) as e:  # TimeoutError is an OSError
            raise GridfieldError(f"cannot connect to the Dask scheduler {shorten(scheduler)}: "
                                 f"{_one_line(str(e) or type(e).__name__, 200)}") from None
    futures: list[Any] = []
    try:
        # The map's content travels with the tasks (workers need not see the submitter's files):
        # each map is read here once and replicated to the workers, and each task is a batch of its runs.
        shipped: dict[tuple[Any, ...], Any] = {}
        for b in batches:
            key = (b[0].map, b[0].resolution, b[0].robot)
            if key not in shipped:
                try:
                    target = _with_robot(read(b[0].map), b[0].robot)
                except GridfieldError:
                    target = None  # every run of the map reports the error in its row
                shipped[key] = client.scatter(target, broadcast=True, hash=False) if target is not None else None
            futures.append(client.submit(run_batch, b, shipped[key], pure=False))
        for fut in as_completed(futures):
            yield fut.result()
    finally:
        if futures:
            client.cancel(futures)
        if client is not scheduler:
            client.close()


def run_sweep(
    runs: Sequence[Run],
    output: str | os.PathLike[str],
    *,
    workers: int | None = None,
    scheduler: Any = None,
    progress: bool = True,
    batch_size: int | None = None,
    notes: list[str] | None = None,
) -> list[dict[str, Any]]:
    """Run the sweep, appending one row per run to ``output`` (CSV); skip runs already there.

    The rows file is locked while the sweep runs (a second sweep on it stops at once), repaired
    when opened (a partial last line from a crash is removed and its run done again), and each
    row is written whole. SIGINT and SIGTERM stop the workers and raise :class:`SweepInterrupted`
    with the file resumable.

    Parameters
    ----------
    runs : the runs (from :func:`load_spec`)
    output : CSV file of rows; created with a header if missing
    workers : local processes (default: all cores)
    scheduler : a Dask scheduler address (or ``distributed.Client``) to run on instead
    progress : show a tqdm progress bar (on a terminal)
    batch_size : runs per task (default: a few tasks per worker and map, at most 256 runs each)
    notes : if given, what the repair of the rows file did is appended here (one line each)

    Returns
    -------
    list of dict : every row of ``output`` after the sweep (old and new), one per run

    Examples
    --------
    >>> import tempfile
    >>> from gridfield.io import bundled_map
    >>> runs = [Run(bundled_map("arena/arena.map"), None, "wavefront-octile", (), (1.5, 37.5), (1.5, 38.5 + k))
    ...         for k in range(3)]
    >>> with tempfile.TemporaryDirectory() as d:
    ...     rows = run_sweep(runs, FsPath(d) / "rows.csv", workers=1, progress=False)
    ...     again = run_sweep(runs, FsPath(d) / "rows.csv", workers=1, progress=False)  # resumed: nothing to do
    >>> [r["length"] for r in rows], again == rows
    (['1.0', '2.0', '3.0'], True)
    """
    import signal
    import threading

    if batch_size is not None and (isinstance(batch_size, bool) or not isinstance(batch_size, int) or batch_size < 1):
        raise ParameterError(f"batch_size must be a positive integer, got {shorten(batch_size)}")
    journal = _Journal(FsPath(output))
    if notes is not None:
        notes += [f"{output}: {n}" for n in journal.notes]
    handlers: dict[int, Any] = {}

    def stop(signum: int, frame: Any) -> None:
        raise SweepInterrupted(signum)

    if threading.current_thread() is threading.main_thread():
        for sig in (signal.SIGINT, signal.SIGTERM):
            handlers[sig] = signal.signal(sig, stop)
    try:
        seen: set[tuple[str, ...]] = set()
        todo = []
        for r in runs:
            if r.key not in journal.keys and r.key not in seen:
                seen.add(r.key)
                todo.append(r)
        if todo:
            n_workers = workers or os.cpu_count() or 1
            batches = _batches(todo, n_workers, batch_size)
            results = (_dask_results(batches, scheduler) if scheduler is not None
                       else _local_results(batches, n_workers))
            from tqdm.auto import tqdm

            with tqdm(total=len(todo), desc="sweep", unit="run", disable=not progress, leave=False) as bar:
                try:
                    for rows in results:
                        for row in rows:
                            journal.append(row)
                        bar.update(len(rows))
                finally:
                    close = getattr(results, "close", None)
                    if close is not None:
                        close()  # stops the workers now if the loop ended early
        return [dict(r) for r in journal.rows]
    finally:
        for signum, old in handlers.items():
            signal.signal(signum, old)
        journal.close()


def summarize(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Success rate and length ratios (to the optimal where known) per map, planner and params.

    Parameters
    ----------
    rows : sequence of mapping
        Rows of a sweep (:func:`run_sweep`; values may be strings, as read back from the file).

    Returns
    -------
    list of dict
        Per (map, planner, params): ``runs``, ``success_rate``, ``length_ratio`` (mean of length /
        ``optimal`` over the reached runs where it is known), ``length_ratio_any_angle`` (the same
        with ``optimal_any_angle``; NaN where none is known) and ``ms_median``.

    Examples
    --------
    >>> rows = [{"map": "m", "planner": "p", "params": "{}", "status": "reached", "length": "11", "optimal": "10",
    ...          "optimal_any_angle": "8.8", "ms": "1"},
    ...         {"map": "m", "planner": "p", "params": "{}", "status": "local_minimum", "length": "3",
    ...          "optimal": "nan", "ms": "3"}]
    >>> s = summarize(rows)[0]
    >>> s["runs"], s["success_rate"], s["length_ratio"], s["length_ratio_any_angle"], s["ms_median"]
    (2, 0.5, 1.1, 1.25, 2.0)
    """
    groups: dict[tuple[str, str, str], list[Mapping[str, Any]]] = {}
    for r in rows:
        groups.setdefault((r["map"], r["planner"], r["params"]), []).append(r)
    out = []
    for (m, p, par), rs in groups.items():
        reached = [r for r in rs if r["status"] == "reached"]
        ratios = _ratios(reached, "optimal")
        any_ratios = _ratios(reached, "optimal_any_angle")
        out.append({
            "map": m, "planner": p, "params": par, "runs": len(rs),
            "success_rate": len(reached) / len(rs),
            "length_ratio": float(np.mean(ratios)) if ratios else math.nan,
            "length_ratio_any_angle": float(np.mean(any_ratios)) if any_ratios else math.nan,
            "ms_median": float(np.median([float(r["ms"]) for r in rs])),
        })
    return out


def _ratios(rows: Sequence[Mapping[str, Any]], column: str) -> list[float]:
    """``length / column`` of the rows where that reference is known (finite, positive)."""
    out = []
    for r in rows:
        ref = float(r.get(column) or "nan")
        if math.isfinite(ref) and ref > 0:
            out.append(float(r["length"]) / ref)
    return out
