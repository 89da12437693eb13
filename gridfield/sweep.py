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
    planners: [potential, wavefront-octile]
    params:                       # every combination is run
      q_star: [1.0, 2.0]
      eta: [1.0]

Each map is loaded and rasterized once per worker process and its brushfire distance map
computed once, not per run. Runs go to a local process pool (all cores) by default, or to a
Dask cluster (``scheduler=ADDRESS``, needs ``pip install gridfield[dask]``). Rows are appended
to the CSV as runs finish; an interrupted sweep started again skips the runs already written.
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

from .errors import GridfieldError, MapFormatError, ParameterError

__all__ = ["COLUMNS", "Run", "load_spec", "run_one", "run_sweep", "summarize"]

#: Columns of the rows file, in order.
COLUMNS = ("map", "planner", "params", "start_x", "start_y", "goal_x", "goal_y", "status", "length",
           "optimal", "steps", "ms")


@dataclass(frozen=True)
class Run:
    """One planner run of a sweep (plain data, cheap to send to a worker)."""

    map: str
    resolution: float | None
    planner: str
    params: tuple[tuple[str, Any], ...]
    start: tuple[float, float]
    goal: tuple[float, float]
    optimal: float = math.nan

    @property
    def params_json(self) -> str:
        return json.dumps(dict(self.params), sort_keys=True)

    @property
    def key(self) -> tuple[str, str, str, str, str, str, str]:
        """Identity of the run in the rows file (used to resume)."""
        return (self.map, self.planner, self.params_json, *(f"{v:.9g}" for v in (*self.start, *self.goal)))


# ----------------------------------------------------------------------------------------
# Spec
# ----------------------------------------------------------------------------------------
def _need(mapping: Mapping[str, Any], key: str, where: str) -> Any:
    if key not in mapping:
        raise MapFormatError(f"{where}: missing key {key!r}")
    return mapping[key]


def load_spec(path: str | os.PathLike[str]) -> tuple[list[Run], FsPath]:
    """Read a sweep spec; return the list of runs and the output path.

    Raises :class:`MapFormatError` naming the spec file and the key at fault.
    """
    from .grid import GridMap
    from .io import read, read_scen, read_yaml
    from .world import World

    spec_path = FsPath(path)
    spec = read_yaml(spec_path)
    where = str(spec_path)
    if not isinstance(spec, Mapping):
        raise MapFormatError(f"{where}: a sweep spec must be a YAML mapping with maps, planners and params")
    base = spec_path.parent
    output = FsPath(spec.get("output", spec_path.with_suffix(".csv").name))
    if not output.is_absolute():
        output = base / output
    planners = spec.get("planners", ["potential"])
    if isinstance(planners, str):
        planners = [planners]
    from .planners import PLANNERS, check_params

    for p in planners:
        if p not in PLANNERS:
            raise MapFormatError(f"{where}: planners: unknown planner {p!r}; expected one of {', '.join(PLANNERS)}")
    grid = spec.get("params") or {}
    if not isinstance(grid, Mapping):
        raise MapFormatError(f"{where}: params must map parameter names to a value or a list of values")
    names = sorted(grid)
    values = [v if isinstance(v, list) else [v] for v in (grid[n] for n in names)]
    try:
        combos = [check_params(dict(zip(names, combo, strict=True))) for combo in itertools.product(*values)]
    except ParameterError as e:
        raise MapFormatError(f"{where}: params: {e}") from None

    maps = _need(spec, "maps", where)
    if not isinstance(maps, list) or not maps:
        raise MapFormatError(f"{where}: maps must be a non-empty list")
    runs: list[Run] = []
    for i, entry in enumerate(maps):
        w = f"{where}: maps[{i}]"
        if isinstance(entry, str):
            entry = {"path": entry}
        map_path = FsPath(_need(entry, "path", w))
        if not map_path.is_absolute():
            map_path = base / map_path
        resolution = entry.get("resolution")
        target = read(map_path)
        pairs: list[tuple[tuple[float, float], tuple[float, float], float]] = []
        for j, pair in enumerate(entry.get("pairs") or []):
            try:
                (sx, sy), (gx, gy) = pair
                pairs.append(((float(sx), float(sy)), (float(gx), float(gy)), math.nan))
            except (TypeError, ValueError):
                raise MapFormatError(f"{w}.pairs[{j}]: expected [[sx, sy], [gx, gy]], got {pair!r}") from None
        if entry.get("random_pairs"):
            rp = entry["random_pairs"]
            pairs += _random_pairs(target, resolution, int(rp.get("n", 10)), int(rp.get("seed", 0)))
        if entry.get("scenarios"):
            scen_path = FsPath(entry["scenarios"])
            if not scen_path.is_absolute():
                scen_path = base / scen_path
            scen = read_scen(scen_path)
            keep = ~scen.no_path
            idx = np.flatnonzero(keep)[: int(entry.get("limit", len(scen.optimal)))]
            pairs += [(tuple(scen.start_xy[k]), tuple(scen.goal_xy[k]), float(scen.optimal[k])) for k in idx]
        if not pairs and isinstance(target, World) and target.start and target.goal:
            pairs.append((target.start, target.goal, math.nan))
        if not pairs:
            raise MapFormatError(f"{w}: no start/goal pairs (give pairs, random_pairs or scenarios)")
        if not isinstance(target, World | GridMap):  # pragma: no cover - read() returns one of the two
            raise MapFormatError(f"{w}: not a map")
        for planner, params, (s, g, opt) in itertools.product(planners, combos, pairs):
            runs.append(Run(str(map_path), resolution, planner, tuple(sorted(params.items())), s, g, opt))
    return runs, output


def _random_pairs(target: Any, resolution: float | None, n: int, seed: int) -> list[Any]:
    """``n`` random start/goal pairs in free cells of the map (reproducible with ``seed``)."""
    from .rasterize import as_gridmap

    gm = as_gridmap(target, resolution)
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
_CACHE: dict[Any, Any] = {}


def _target(run: Run) -> Any:
    """The run's map, loaded (and for grid planners rasterized) once per process."""
    key = (run.map, run.resolution)
    if key not in _CACHE:
        from .io import read

        _CACHE[key] = read(run.map)
    return _CACHE[key]


def run_one(run: Run) -> dict[str, Any]:
    """Run one planner call; return its row. Bad input of a run becomes status ``error:...``."""
    from .planners import plan

    t0 = time.perf_counter()
    try:
        path = plan(run.planner, _target(run), run.start, run.goal, dict(run.params), resolution=run.resolution,
                    cache=_CACHE)
        status, length, steps = path.status, path.length, path.iterations
    except GridfieldError as e:
        status, length, steps = f"error: {e}", math.nan, 0
    ms = (time.perf_counter() - t0) * 1e3
    return {
        "map": run.map, "planner": run.planner, "params": run.params_json,
        "start_x": run.start[0], "start_y": run.start[1], "goal_x": run.goal[0], "goal_y": run.goal[1],
        "status": status, "length": length, "optimal": run.optimal, "steps": steps, "ms": round(ms, 3),
    }


def _done_keys(output: FsPath) -> set[tuple[str, ...]]:
    if not output.exists():
        return set()
    with output.open(newline="") as f:
        return {
            (r["map"], r["planner"], r["params"],
             *(f"{float(r[k]):.9g}" for k in ("start_x", "start_y", "goal_x", "goal_y")))
            for r in csv.DictReader(f)
        }


def _local_results(runs: Sequence[Run], workers: int) -> Iterator[dict[str, Any]]:
    if workers <= 1 or len(runs) <= 1:
        yield from map(run_one, runs)
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    # Runs of the same map go to the same chunk, so each worker loads few maps.
    chunk = max(1, len(runs) // (workers * 4))
    # "spawn", not fork: the potential kernels start an OpenMP thread pool, and a process that
    # forks after that can hang or abort ("fork() called from a process already using GNU OpenMP").
    ctx = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as pool:
        yield from pool.map(run_one, runs, chunksize=chunk)


def _dask_results(runs: Sequence[Run], scheduler: Any) -> Iterator[dict[str, Any]]:
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise GridfieldError("--scheduler needs Dask: pip install 'gridfield[dask]'") from None
    client = scheduler if isinstance(scheduler, Client) else Client(scheduler)
    try:
        futures = client.map(run_one, list(runs), pure=False)
        for fut in as_completed(futures):
            yield fut.result()
    finally:
        if client is not scheduler:
            client.close()


def run_sweep(
    runs: Sequence[Run],
    output: str | os.PathLike[str],
    *,
    workers: int | None = None,
    scheduler: Any = None,
    progress: bool = True,
) -> list[dict[str, Any]]:
    """Run the sweep, appending one row per run to ``output`` (CSV); skip runs already there.

    Parameters
    ----------
    runs : the runs (from :func:`load_spec`)
    output : CSV file of rows; created with a header if missing
    workers : local processes (default: all cores)
    scheduler : a Dask scheduler address (or ``distributed.Client``) to run on instead
    progress : show a tqdm progress bar (on a terminal)

    Returns
    -------
    list of dict : every row of ``output`` after the sweep (old and new)
    """
    out = FsPath(output)
    done = _done_keys(out)
    todo = [r for r in runs if r.key not in done]
    out.parent.mkdir(parents=True, exist_ok=True)
    new_file = not out.exists()
    if todo:
        results = (_dask_results(todo, scheduler) if scheduler is not None
                   else _local_results(todo, workers or os.cpu_count() or 1))
        from tqdm.auto import tqdm

        bar = tqdm(total=len(todo), desc="sweep", unit="run", disable=not progress, leave=False)
        with out.open("a", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=COLUMNS)
            if new_file:
                writer.writeheader()
            for row in results:
                writer.writerow(row)
                f.flush()
                bar.update()
        bar.close()
    elif new_file:
        with out.open("w", newline="") as f:
            csv.DictWriter(f, fieldnames=COLUMNS).writeheader()
    with out.open(newline="") as f:
        return list(csv.DictReader(f))


def summarize(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Success rate and length ratio (to the optimal where known) per map, planner and params.

    Examples
    --------
    >>> rows = [{"map": "m", "planner": "p", "params": "{}", "status": "reached", "length": "11", "optimal": "10",
    ...          "ms": "1"},
    ...         {"map": "m", "planner": "p", "params": "{}", "status": "local_minimum", "length": "3",
    ...          "optimal": "nan", "ms": "3"}]
    >>> s = summarize(rows)[0]
    >>> s["runs"], s["success_rate"], s["length_ratio"], s["ms_median"]
    (2, 0.5, 1.1, 2.0)
    """
    groups: dict[tuple[str, str, str], list[Mapping[str, Any]]] = {}
    for r in rows:
        groups.setdefault((r["map"], r["planner"], r["params"]), []).append(r)
    out = []
    for (m, p, par), rs in groups.items():
        reached = [r for r in rs if r["status"] == "reached"]
        ratios = [float(r["length"]) / float(r["optimal"]) for r in reached
                  if math.isfinite(float(r["optimal"])) and float(r["optimal"]) > 0]
        out.append({
            "map": m, "planner": p, "params": par, "runs": len(rs),
            "success_rate": len(reached) / len(rs),
            "length_ratio": float(np.mean(ratios)) if ratios else math.nan,
            "ms_median": float(np.median([float(r["ms"]) for r in rs])),
        })
    return out
