"""The sweep spec: reading it, checking all of it, and expanding it to the list of runs (:func:`load_spec`).

Everything is validated before the first run starts, because a sweep may run for hours on a
cluster: a typo in the last map entry must not surface then. So this module reads every map
(sizing its grid against the memory limit), every scenario file, every parameter combination of
every planner, and the rows file's lock, and says which key of which file is at fault.
"""

from __future__ import annotations

import itertools
import json
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path as FsPath
from typing import Any

import numpy as np

from ..core.errors import GridfieldError, MapFormatError, ParameterError, check_positive, shorten
from ._journal import _Journal
from ._run import Run, _with_robot

#: Keys of a spec's top level and of one ``maps`` entry.
SPEC_KEYS = ("output", "maps", "planners", "params", "robot", "robot_radius", "optimal_any_angle")
MAP_KEYS = ("path", "resolution", "pairs", "random_pairs", "scenarios", "limit", "robot", "robot_radius",
            "optimal_any_angle")

#: Exact planners that also run on grid maps (on the blocked cells as exact polygons, gridfield.geometry.gridpoly).
GRID_MAP_EXACT = ("visibility", "exact-potential")

#: Most runs one spec may expand to (each run is a row and a few hundred bytes of memory).
MAX_RUNS = 10**8

#: Memory of one expanded run (a :class:`Run` with its tuples, measured: about 480 bytes) and its pair, rounded up.
RUN_BYTES = 1024


def _run_limit() -> int:
    """The most runs a spec may expand to: :data:`MAX_RUNS`, or fewer if their memory (:data:`RUN_BYTES` each)
    would exceed the size guard's budget (``max_cells() * BYTES_PER_CELL`` bytes, see :mod:`gridfield.core.limits`)."""
    from ..core.limits import BYTES_PER_CELL, max_cells

    return int(min(MAX_RUNS, max_cells() * BYTES_PER_CELL // RUN_BYTES))


def _known_pairs(entry: Any) -> int:
    """The pairs a map entry asks for that are known without reading a file: its ``pairs`` and its
    ``random_pairs.n`` (and a ``limit`` on its scenarios); malformed values count 0 (the full check reports them)."""
    if not isinstance(entry, Mapping):
        return 0
    n = len(entry["pairs"]) if isinstance(entry.get("pairs"), list) else 0
    rp = entry.get("random_pairs")
    if isinstance(rp, Mapping):
        k = rp.get("n", 10)
        n += k if isinstance(k, int) and not isinstance(k, bool) and k > 0 else 0
    lim = entry.get("limit")
    if entry.get("scenarios") is not None and isinstance(lim, int) and not isinstance(lim, bool) and lim > 0:
        n += lim
    return n


def _too_many(where: str, n_runs: int, detail: str) -> MapFormatError:
    limit = _run_limit()
    why = "" if limit == MAX_RUNS else f" (what {RUN_BYTES} bytes per run allow in the memory limit; see --max-cells)"
    return MapFormatError(f"{where}: the spec expands to {n_runs:.4g} runs ({detail}), more than {limit:g}{why}; "
                          "sweep fewer values, pairs or maps, or split the sweep")


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
    (:func:`gridfield.core.params.validate`), then the potential's cross-parameter rules
    (:func:`gridfield.fields.potential.resolve_params`). Raises :class:`ParameterError` naming the
    parameter and its value.

    Examples
    --------
    >>> _validate_params("potential", {"eta": 2.0})
    {'eta': 2.0}
    >>> _validate_params("potential", {"eta": -1})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: eta must be a finite number >= 0, got -1
    """
    from ..fields.potential import resolve_params
    from ..planners import check_params

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
    from ..core.limits import job_planners
    from ..io import read_yaml
    from ..planners import PLANNERS

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
    planners = _spec_planners(spec, where)
    combos = _spec_combos(spec, planners, where)
    job_planners([p for p in planners if PLANNERS[p][2] == "grid"])  # each map below is sized for them

    any_angle_all = _flag(spec, "optimal_any_angle", where)
    maps = _need(spec, "maps", where)
    if not isinstance(maps, list) or not maps:
        raise MapFormatError(f"{where}: maps must be a non-empty list")
    runs: list[Run] = []
    for i, entry in enumerate(maps):
        runs += _map_runs(entry, f"{where}: maps[{i}]", spec, base, planners, combos, len(runs), any_angle_all)
    return runs, output


def _spec_planners(spec: Mapping[str, Any], where: str) -> list[str]:
    """The spec's ``planners`` (a name or a non-empty list of known names)."""
    from ..planners import PLANNERS

    planners = spec.get("planners", ["potential"])
    if isinstance(planners, str):
        planners = [planners]
    if not isinstance(planners, list) or not planners:
        raise MapFormatError(f"{where}: planners must be a planner name or a non-empty list of them")
    for p in planners:
        if not isinstance(p, str) or p not in PLANNERS:
            raise MapFormatError(f"{where}: planners: unknown planner {shorten(p)}; expected one of {', '.join(PLANNERS)}")
    return planners


def _spec_combos(spec: Mapping[str, Any], planners: list[str], where: str) -> list[dict[str, Any]]:
    """Every combination of the spec's ``params`` values, validated for every planner (after the run
    count is bounded arithmetically, before anything is expanded)."""
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
    # count the runs arithmetically before expanding or validating anything (scenario files: their limit, if any)
    raw_maps = spec.get("maps")
    known = sum(max(_known_pairs(e), 1) for e in raw_maps) if isinstance(raw_maps, list) else 1
    if n_combos * len(planners) * known > _run_limit():
        raise _too_many(where, n_combos * len(planners) * known,
                        f"{len(planners)} planners x {n_combos:.4g} parameter combinations x {known:.4g} start/goal "
                        "pairs")
    combos = []
    for combo in itertools.product(*values):
        params = dict(zip(names, combo, strict=True))
        for planner in planners:
            try:
                _validate_params(planner, params)
            except ParameterError as e:
                raise MapFormatError(f"{where}: params ({planner}): {e}") from None
        combos.append(params)
    return combos


def _map_runs(entry: Any, w: str, spec: Mapping[str, Any], base: FsPath, planners: list[str],
              combos: list[dict[str, Any]], before: int, any_angle_all: bool) -> list[Run]:
    """The runs of one ``maps`` entry (``before``: the runs of the entries before it)."""
    from ..geometry.world import World

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
    target, gm = _map_target(entry, w, map_path, resolution, robot, planners)
    pairs = _pairs(entry, w)
    pairs += _random_entry_pairs(entry, w, gm, len(pairs), before, len(planners) * len(combos))
    pairs += _scenario_pairs(entry, w, base, map_path, gm)
    if not pairs and isinstance(target, World) and target.start and target.goal:
        pairs.append((target.start, target.goal, math.nan))
    if not pairs:
        raise MapFormatError(f"{w}: no start/goal pairs (give pairs, random_pairs or scenarios)")
    if before + len(planners) * len(combos) * len(pairs) > _run_limit():
        raise _too_many(w, before + len(planners) * len(combos) * len(pairs), f"up to {w}")
    any_angle = _flag(entry, "optimal_any_angle", w, default=any_angle_all)
    return [Run(str(map_path), resolution, planner, tuple(sorted(params.items())), s, g, opt, robot, any_angle)
            for planner, params, (s, g, opt) in itertools.product(planners, combos, pairs)]


def _map_target(entry: Mapping[str, Any], w: str, map_path: FsPath, resolution: float | None,
                robot: tuple[Any, ...], planners: list[str]) -> tuple[Any, Any]:
    """The entry's map (read, the robot applied) and the grid the grid planners will use, sized against
    the memory limit before anything runs (None when no grid is needed yet)."""
    from ..core.grid import Grid, GridMap
    from ..geometry.rasterize import as_gridmap
    from ..geometry.world import World
    from ..io import read
    from ..planners import PLANNERS

    try:
        target = _with_robot(read(map_path), robot)
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
    return target, gm


def _random_entry_pairs(entry: Mapping[str, Any], w: str, gm: Any, given: int, before: int,
                        per_pair: int) -> list[Any]:
    """The entry's ``random_pairs`` (none when absent); ``given`` pairs listed, ``per_pair`` runs each."""
    rp = entry.get("random_pairs")
    if rp is None:
        return []
    if not isinstance(rp, Mapping):
        raise MapFormatError(f"{w}.random_pairs: expected a mapping {{n: N, seed: S}}, got {shorten(rp)}")
    _unknown_keys(rp, ("n", "seed"), f"{w}.random_pairs")
    n = _integer(rp.get("n", 10), f"{w}.random_pairs.n", minimum=1)
    if n > MAX_RUNS:
        raise MapFormatError(f"{w}.random_pairs.n: {n} pairs exceed {MAX_RUNS:g} runs")
    if before + per_pair * (given + n) > _run_limit():
        raise _too_many(w, before + per_pair * (given + n), f"with this entry's {n} random pairs")
    seed = _integer(rp.get("seed", 0), f"{w}.random_pairs.seed", minimum=0)
    try:
        return _random_pairs(gm, n, seed)
    except GridfieldError as e:
        raise MapFormatError(f"{w}.random_pairs: {e}") from None


def _scenario_pairs(entry: Mapping[str, Any], w: str, base: FsPath, map_path: FsPath, gm: Any) -> list[Any]:
    """The entry's Moving AI ``scenarios`` (up to ``limit``, the solvable ones), checked against the map's size."""
    from ..io import read_scen

    if entry.get("limit") is not None and not entry.get("scenarios"):
        raise MapFormatError(f"{w}.limit: limits the scenarios, but the entry has no 'scenarios'")
    if entry.get("scenarios") is None:
        return []
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
    return [(tuple(scen.start_xy[k]), tuple(scen.goal_xy[k]), float(scen.optimal[k])) for k in idx]


def _flag(mapping: Mapping[str, Any], key: str, where: str, *, default: bool = False) -> bool:
    """A true/false spec value (``default`` when absent); anything else is a MapFormatError."""
    value = mapping.get(key, default)
    if not isinstance(value, bool):
        raise MapFormatError(f"{where}: {key} must be true or false, got {shorten(value)}")
    return value


def _robot_key(entry: Mapping[str, Any], spec: Mapping[str, Any], where: str) -> tuple[Any, ...]:
    """A map entry's robot (``robot:`` or ``robot_radius:``, else the spec's) as plain hashable data."""
    from ..geometry.world import robot_from_value

    source = entry if ("robot" in entry or "robot_radius" in entry) else spec
    value = source.get("robot", source.get("robot_radius"))
    if value is None:
        return ()
    r = robot_from_value(value, f"{where}: robot")
    if r.radius is not None:
        return ("radius", r.radius)
    assert r.vertices is not None
    return ("polygon", tuple(map(tuple, r.vertices.tolist())))



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
