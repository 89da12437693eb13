"""One run of a sweep and what it needs in a worker process: :class:`Run`, :func:`run_one`, :func:`run_batch`.

A :class:`Run` is plain data (cheap to pickle to a worker). A worker keeps the last few maps it
was given, each with its plan cache (brushfire distance map, any-angle graph, ...), so that the
runs of one map, which the executors send together, load and rasterize it once. :func:`run_batch`
is the task every executor submits (a spawned pool and Dask pickle it by its module path, so it
stays a module-level function here). Every failure of a run becomes its row's ``error: ...``
status: one bad run never stops a sweep.
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.errors import GridfieldError


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


#: Per process: (map, resolution, identity of a shipped map or None) -> {"target": the map, ...the
#: plan cache of that map}, the most recently used last; only the last :data:`_CACHE_MAPS` are kept.
_CACHE: dict[Any, Any] = {}
_CACHE_MAPS = 4

#: Longest error status written to a row.
STATUS_LIMIT = 300


def _with_robot(target: Any, robot: tuple[Any, ...]) -> Any:
    if not robot:
        return target
    from ..geometry.cspace import apply_robot

    return apply_robot(target, robot[1] if robot[0] == "radius" else list(robot[1]))



def _map_cache(run: Run, target: Any = None) -> dict[Any, Any]:
    """The plan cache of the run's map, holding the map (loaded here from its path unless shipped).

    A shipped map is keyed by its identity too: a long-lived cluster may see two sweeps whose maps
    share a (relative) path but not their content. The cache holds the map, so the identity stays unique.
    """
    key = (run.map, run.resolution, run.robot, None if target is None else id(target))
    cache: dict[Any, Any] | None = _CACHE.pop(key, None)
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
    except MemoryError as e:  # one clear line naming the run (numpy's _ArrayMemoryError is a MemoryError)
        from ..core.limits import out_of_memory

        what = f"{run.planner} on {os.path.basename(str(run.map))}" + (f" at resolution {run.resolution:g}"
                                                                  if run.resolution is not None else "")
        status, length, steps = f"error: {out_of_memory(e, what)}", math.nan, 0
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
    and so is the graph (:func:`gridfield.compare.optimum_solver` with that cache), which the
    ``visibility`` planner's runs on the map share.
    """
    try:
        cache = _map_cache(run, target)
        key = ("optimal_any_angle", run.start, run.goal)
        if key not in cache:
            solver = cache.get("optimal_any_angle_solver")
            if solver is None:
                from ..compare import optimum_solver

                solver = cache["optimal_any_angle_solver"] = optimum_solver(cache["target"], cache=cache)
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
