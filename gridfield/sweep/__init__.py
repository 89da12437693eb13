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
visibility graph of :mod:`gridfield.exact.anyangle`, on a vector world its visibility graph
(:mod:`gridfield.exact.visibility`). The graph is built once per map and worker process and shared with
the ``visibility`` planner's runs on that map; each (start, goal) is solved once, whatever the
planners and parameters. NaN where not asked for or where the goal cannot be reached. The summary
then gives ``length_ratio_any_angle`` beside ``length_ratio``. Exact planners run on grid maps too
(``visibility``, ``exact-potential``: on the map's blocked cells as exact polygons).

The whole spec is validated before anything runs: unknown keys (with a "did you mean"), the
types and ranges of every value, every parameter combination (:func:`_validate_params`), each
map's grid size against the memory limit (:mod:`gridfield.core.limits`), scenario files against their
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

Layout of the package (one job per module; the submodules are private: import from
``gridfield.sweep``): ``_spec`` reads and validates a spec and expands it to runs (:func:`load_spec`);
``_run`` is one run in a worker (:class:`Run`, :func:`run_one`, :func:`run_batch`, the per-process map
cache, the any-angle optimum column); ``_journal`` owns the rows file (:data:`COLUMNS`, lock, repair,
whole-row appends, the upgrade of an older header); ``_backends`` executes the batches (local pool,
Dask, signals) and drives them (:func:`run_sweep`); ``_summary`` is :func:`summarize`. Worker
processes and Dask pickle :func:`run_batch` and the pool initializer by their module path
(``gridfield.sweep._run``, ``gridfield.sweep._backends``).
"""

from __future__ import annotations

# Besides __all__, the names of the single-file module stay importable from here (``X as X`` marks a
# re-export): the spec's key lists and limits, the executors' settings, and the private helpers tests
# and ARCHITECTURE.md name (``_validate_params``, ``_Journal``). Patch a private name where it is
# looked up: ``gridfield.sweep._run.run_one`` (what run_batch calls), ``gridfield.sweep._run._CACHE``.
from ._backends import POOL_RESTARTS as POOL_RESTARTS
from ._backends import SCHEDULER_TIMEOUT as SCHEDULER_TIMEOUT
from ._backends import SweepInterrupted, run_sweep
from ._journal import COLUMNS as _COLUMNS
from ._journal import _Journal as _Journal
from ._run import STATUS_LIMIT as STATUS_LIMIT
from ._run import Run, run_batch, run_one
from ._spec import GRID_MAP_EXACT as GRID_MAP_EXACT
from ._spec import MAP_KEYS as MAP_KEYS
from ._spec import MAX_RUNS as MAX_RUNS
from ._spec import SPEC_KEYS as SPEC_KEYS
from ._spec import _validate_params as _validate_params
from ._spec import load_spec
from ._summary import summarize

#: Columns of the rows file, in order (owned by ``_journal``; assigned here to document it on this page).
COLUMNS = _COLUMNS

__all__ = ["COLUMNS", "Run", "SweepInterrupted", "load_spec", "run_batch", "run_one", "run_sweep", "summarize"]
