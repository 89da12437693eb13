"""The ``potential`` planner on real maps: Moving AI scenarios and ROS maps (issue 12).

Run ``python benchmarks/potential_real.py [--maps-root tests/data/maps] [--per-map 20] [--workers 2]
[--label before|after] [--out FILE.md] [--json FILE.json]``.

Every query goes through the public entry point ``gridfield.planners.plan("potential", gridmap,
start, goal, params, cache=cache)`` (one ``cache`` dict per map, as a batch user would keep it: the
brushfire is computed once per map; ``--no-cache``: none), once per variant:

- ``defaults``: ``params={}``;
- ``random_walk``: ``{"model": "khatib", "escape": "random_walk"}`` (the escapes are the classic field's:
  the complete models never stall);
- ``navigation``: ``{"model": "khatib", "escape": "navigation"}``; where the installed gridfield does not know this
  escape (it raises ``ParameterError`` naming the value) the variant is reported as "n/a";
- ``khatib``: ``{"model": "khatib"}`` (the classic field, the default before the complete models);
  ``nf1``, ``nf1_plain`` (``clearance_band: 0``: nf1 without its clearance band, the default
  before issue 25), ``nf1_octile`` (``attraction: octile``), ``nf2``, ``nf_blend`` (``model: nf-blend``): the
  complete models of :mod:`gridfield.fields.navfield` (reported "n/a" where the installed gridfield does
  not know them).

The quality table (``--quality``, default on) adds per variant and map kind: reached / reachable,
the length ratio to the **any-angle optimum** (``gridfield.exact.anyangle.plan_anyangle``, the
``visibility`` planner on the same grid map; median, p95; computed on maps of at most
``--any-angle-max-cells`` cells, its graph being costly on the largest) and to the octile optimum
(median, p95), the path's minimum clearance in cells (median; ``Path.min_clearance``), its margin
to the query's **bottleneck clearance** (the largest minimum clearance any 4-connected path of
free cells from start to goal can keep, found by bisection over the clearance values with
``scipy.ndimage.label``; median of ``min_clearance - bottleneck``, in cells), and the median time
per query of the variant and of ``wavefront-octile`` on the same queries in the same run (the
API, warm cache: one cache per map).

Queries:

- **Moving AI** (``MAPS_ROOT/movingai/*/``, one ``.map`` + one ``.scen`` each, read with
  :func:`gridfield.io.read_movingai_map` and :func:`gridfield.io.read_scen`, which converts the
  scenario cells to world points): ``--per-map`` scenarios spread evenly over the file in bucket
  order (the same sample on every run), plus every GPPC "no path" marker of the file (unreachable
  queries). The optimum is the scenario's octile length.
- **ROS** (``MAPS_ROOT/ros_maps/*/*.yaml``, read with :func:`gridfield.io.read`, its defaults:
  unknown space is occupied): ``--per-map`` pairs of free cell centres drawn with
  ``numpy.random.default_rng(0)``; with ``--ros-pairs same`` (default) the goal is drawn from the
  start's 4-connected free component (the cells an octile path without corner cutting can reach),
  with ``any`` anywhere (a pair in two components is then an unreachable query). In addition
  ``--ros-unreachable`` pairs (default 2) whose ends lie in different components, where the map
  has more than one. The optimum is the length of ``plan("wavefront-octile", ...)`` on the same
  query, which also says whether the goal is reachable.

Each run records the status (``reached``, ``local_minimum``, ``collision``, ``max_iterations``,
``no_path``, or ``error`` with the exception's one-line message: any exception, a gridfield error
or a traceback-worthy one, counts as an error), the path length and its ratio to the optimum
(Moving AI: a potential path moves at any angle, so it can be up to ~8 % shorter than the octile
optimum: ratios below 1 are expected), and whether ``path.extra`` carries a ``"hint"``.

Output: one markdown table per variant, aggregated per map family (MANIFEST: dao, bg512, sc1,
GPPC, rooms, random, maze, street, MAPF; ROS) and overall, then one row per map; with ``--json``
every run (non-finite numbers, e.g. an unreachable optimum or ``d_star=inf``, as null). The header
names the gridfield checkout that was imported and its ``git describe --always --dirty``.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import statistics
import subprocess
import sys
import time
from collections import Counter
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _common import map_and_scen as _map_and_scen  # noqa: E402

DEFAULT_ROOT = HERE.parent / "tests" / "data" / "maps"

#: variant name -> the params given to plan()
VARIANTS: dict[str, dict[str, Any]] = {
    "defaults": {},
    "random_walk": {"model": "khatib", "escape": "random_walk"},
    "navigation": {"model": "khatib", "escape": "navigation"},
    # the classic field and the complete models (gridfield.fields.navfield); "defaults" is nf1 since they came
    "khatib": {"model": "khatib"},
    "nf1": {"model": "nf1"},
    "nf1_plain": {"model": "nf1", "clearance_band": 0},  # nf1 without its clearance band (the default before)
    "nf1_octile": {"model": "nf1", "attraction": "octile"},
    "nf2": {"model": "nf2"},
    "nf_blend": {"model": "nf-blend"},
}
#: The variants run when ``--variants`` is not given (issue 12's three, as before the models came).
DEFAULT_VARIANTS = ("defaults", "random_walk", "navigation")
STATUS_COLUMNS = ("reached", "local_minimum", "collision", "max_iterations", "no_path", "error")
NOT_AVAILABLE = "n/a"
#: resolved parameters kept per run in the JSON dump (the ones issue 12 makes scale with the map)
RESOLVED = ("zeta", "d_star", "eta", "q_star", "step", "tolerance", "escape_radius", "max_iterations")

#: Moving AI map folder -> family (MANIFEST.md §1); anything else is "movingai".
FAMILIES = {
    **dict.fromkeys(["arena", "den312d", "brc202d", "lak303d", "ost003d", "orz100d", "arena2", "isound1"], "dao"),
    "AR0011SR": "bg512",
    "Aurora": "sc1", "AcrosstheCape": "sc1",
    "rmtst01": "gppc",
    **dict.fromkeys(["16room_000", "64room_000", "8room_000"], "rooms"),
    "random512-10-0": "random",
    "maze512-32-9": "maze",
    "Berlin_0_256": "street",
    **dict.fromkeys(["mapf_maze-32-32-2", "mapf_room-64-64-8", "mapf_empty-48-48", "mapf_ht_chantry",
                     "mapf_random-32-32-10"], "mapf"),
}
FAMILY_ORDER = ("dao", "bg512", "sc1", "gppc", "rooms", "random", "maze", "street", "mapf", "movingai", "ros",
                "generated")
#: The generated maps (``--generated N``: the first N, each ``kind:seed``): rooms joined by doors of 1-4
#: cells, random rectangles and thin walls, and end_to_end.py's squares and discs (an open border, 0.39 m
#: cells). Queries as on the ROS maps (``--per-map`` pairs in one free component, ``default_rng(0)``).
GENERATED = ("rooms:1", "blocks:2", "discs:3", "rooms:4", "blocks:5", "discs:6", "rooms:7", "blocks:8")


def generated_map(spec: str) -> Any:
    """The generated map ``kind:seed`` of :data:`GENERATED` (256 x 256 cells), deterministic."""
    from gridfield.core.grid import Grid, GridMap

    kind, seed = spec.split(":")
    rng = np.random.default_rng(int(seed))
    n = 256
    if kind == "discs":
        from end_to_end import synthetic_map  # benchmarks/ is on sys.path

        return synthetic_map(n, seed=int(seed))
    occ = np.zeros((n, n), bool)
    if kind == "rooms":  # 8 x 8 rooms of 32 cells, walls 1-2 cells thick, one door of 1-4 cells per wall
        for k in range(0, n + 1, 32):
            t = int(rng.integers(1, 3))
            occ[max(k - t // 2, 0):min(k + 1, n), :] = True
            occ[:, max(k - t // 2, 0):min(k + 1, n)] = True
        for k in range(32, n, 32):
            for j in range(0, n, 32):
                for horizontal in (True, False):
                    w = int(rng.integers(1, 5))
                    o = j + int(rng.integers(3, 29 - w))
                    if horizontal:
                        occ[k - 1:k + 1, o:o + w] = False
                    else:
                        occ[o:o + w, k - 1:k + 1] = False
        for _ in range(60):  # furniture
            r, c, h, w = rng.integers(2, n - 8), rng.integers(2, n - 8), rng.integers(2, 7), rng.integers(2, 7)
            occ[r:r + h, c:c + w] = True
    elif kind == "blocks":  # random rectangles and thin walls
        for _ in range(70):
            r, c = rng.integers(0, n, 2)
            h, w = (rng.integers(1, 3), rng.integers(10, 60)) if rng.random() < 0.3 else rng.integers(3, 30, 2)
            if rng.random() < 0.5:
                h, w = w, h
            occ[r:r + h, c:c + w] = True
    else:
        raise ValueError(f"unknown generated map kind {kind!r}")
    return GridMap(Grid((n, n), 1.0, border="wall"), occ, source=f"generated {spec}")


# ----------------------------------------------------------------------------------------------
# Queries
# ----------------------------------------------------------------------------------------------
def movingai_sample(bucket: np.ndarray, no_path: np.ndarray, n: int) -> np.ndarray:
    """``n`` scenario indices spread evenly over the file in bucket order, plus every "no path" marker."""
    order = np.lexsort((np.arange(len(bucket)), bucket))
    k = min(n, len(bucket))
    idx = order[np.linspace(0, len(bucket) - 1, k).round().astype(int)] if k > 0 else np.empty(0, int)
    return np.union1d(idx, np.flatnonzero(no_path))


def ros_pairs(free: np.ndarray, n: int, mode: str, n_unreachable: int,
              seed: int = 0) -> list[tuple[tuple[int, int], tuple[int, int], str]]:
    """Start and goal cells ``((row, col), (row, col), kind)`` drawn with ``default_rng(seed)``.

    ``kind`` is "reachable" (same 4-connected free component) or "unreachable". ``mode`` "same":
    the goal is drawn from the start's component (another cell of it); "any": uniformly over the
    free cells. Then ``n_unreachable`` pairs in different components (none if there is only one).
    """
    from scipy import ndimage

    labels, count = ndimage.label(free)  # 4-connected: what octile moves without corner cutting connect
    cells = np.argwhere(free)
    if len(cells) < 2:
        return []
    lab = labels[cells[:, 0], cells[:, 1]]
    sizes = np.bincount(lab, minlength=count + 1)
    rng = np.random.default_rng(seed)
    out: list[tuple[tuple[int, int], tuple[int, int], str]] = []
    multi = np.flatnonzero(sizes[lab] >= 2)  # cells whose component has another cell
    for _ in range(n):
        if mode == "same":
            if multi.size == 0:
                break
            i = int(multi[rng.integers(multi.size)])
            members = np.flatnonzero(lab == lab[i])
            j = i
            while j == i:
                j = int(members[rng.integers(members.size)])
        else:
            i = int(rng.integers(len(cells)))
            j = i
            while j == i:
                j = int(rng.integers(len(cells)))
        kind = "reachable" if lab[i] == lab[j] else "unreachable"
        out.append((tuple(map(int, cells[i])), tuple(map(int, cells[j])), kind))  # type: ignore[arg-type]
    if count >= 2:
        for _ in range(n_unreachable):
            i = int(rng.integers(len(cells)))
            others = np.flatnonzero(lab != lab[i])
            j = int(others[rng.integers(others.size)])
            out.append((tuple(map(int, cells[i])), tuple(map(int, cells[j])), "unreachable"))  # type: ignore[arg-type]
    return out


# ----------------------------------------------------------------------------------------------
# One run
# ----------------------------------------------------------------------------------------------
def one_line(e: BaseException) -> str:
    text = str(e).strip().splitlines()
    return f"{type(e).__name__}: {text[0] if text else ''}"[:300]


def small_extras(extra: Any) -> dict[str, Any]:
    """The scalar entries of ``path.extra`` (and points / short number tuples) for the JSON dump:
    ``stop_reason``, ``collision_at``, ``stall_point``, escape counts, and whatever diagnosis a
    later gridfield adds; arrays and logs are left out."""
    out: dict[str, Any] = {}
    for k, v in dict(extra).items():
        if k in ("start", "goal"):
            continue
        if isinstance(v, str | bool | int | float | np.generic) or v is None:
            out[str(k)] = v.item() if isinstance(v, np.generic) else v
        elif isinstance(v, tuple | list | np.ndarray) and 0 < len(v) <= 4 and all(
                isinstance(x, int | float | np.number) for x in v):
            out[str(k)] = [float(x) for x in v]
    return out


def _plain(v: Any) -> Any:
    if isinstance(v, np.generic):
        return v.item()
    return v if isinstance(v, str | bool | int | float) or v is None else str(v)


def run_query(gm: Any, start: np.ndarray, goal: np.ndarray, variant: str, params: dict[str, Any],
              optimal: float, cache: dict[Any, Any] | None) -> dict[str, Any]:
    from gridfield.core.errors import ParameterError
    from gridfield.planners import plan

    rec: dict[str, Any] = {"variant": variant, "status": None, "length": None, "ratio": None, "hint": None,
                           "iterations": None, "stop_reason": None, "end": None, "message": None, "seconds": None}
    t0 = time.perf_counter()
    try:
        path = plan("potential", gm, start, goal, params, cache=cache)  # cache None: a fresh plan() per query
    except ParameterError as e:
        rec["seconds"] = time.perf_counter() - t0
        esc = params.get("escape")
        model = params.get("model")
        if (esc is not None and repr(esc) in str(e) and "escape" in str(e)) or (
                model is not None and repr(model) in str(e) and "model" in str(e)):
            rec["status"], rec["message"] = NOT_AVAILABLE, one_line(e)
        else:
            rec["status"], rec["message"] = "error", one_line(e)
        return rec
    except Exception as e:  # a benchmark counts every failure, it does not stop on one
        rec["seconds"] = time.perf_counter() - t0
        rec["status"], rec["message"] = "error", one_line(e)
        return rec
    rec["seconds"] = time.perf_counter() - t0
    rec["status"] = path.status
    rec["length"] = float(path.length)
    rec["min_clearance"] = float(path.min_clearance) if path.min_clearance is not None else None
    rec["model"] = _plain((path.params or {}).get("model"))
    rec["iterations"] = int(path.iterations)
    extra = path.extra or {}
    rec["stop_reason"] = str(extra.get("stop_reason")) if extra.get("stop_reason") is not None else None
    rec["end"] = [float(v) for v in path.end] if len(path.points) else None
    rec["extra"] = small_extras(extra)
    rec["resolved"] = {k: _plain(path.params[k]) for k in RESOLVED if k in (path.params or {})}
    hint = extra.get("hint")
    rec["hint"] = str(hint) if hint else None
    if path.status == "reached" and np.isfinite(optimal) and optimal > 0:
        rec["ratio"] = float(path.length) / optimal
    rec["vertices"] = len(path.points)
    rec["exact_collision"] = exact_collision(gm, path.points)
    return rec


def exact_collision(gm: Any, points: np.ndarray) -> bool:
    """Whether the polyline crosses a blocked cell by exact geometry (shapely, independent of
    gridfield's own checks): a segment meets a blocked square's interior, or passes through a
    grid vertex between two diagonal blocked squares (a pinch; touching one square's boundary is
    free, as for the any-angle optimum), or leaves a wall-bordered grid."""
    import shapely

    g = gm.grid
    res = float(g.resolution)
    occ = np.asarray(gm.occupied, dtype=bool)
    pts = (np.asarray(points, dtype=float).reshape(-1, 2) - np.asarray(g.origin, dtype=float)) / res  # cell units
    if len(pts) == 0:
        return False
    if g.border == "wall" and ((pts < 0).any() or (pts[:, 0] > occ.shape[1]).any() or (pts[:, 1] > occ.shape[0]).any()):
        return True
    for a, b in pairwise(pts):
        c0, r0 = np.floor(np.minimum(a, b)).astype(int) - 1
        c1, r1 = np.floor(np.maximum(a, b)).astype(int) + 2
        c0, r0 = max(c0, 0), max(r0, 0)
        rr, cc = np.nonzero(occ[r0:r1, c0:c1])
        if rr.size == 0:
            continue
        rr, cc = rr + r0, cc + c0
        # squares whose centre lies within sqrt(2)/2 of the segment may meet it (a cheap filter)
        d = b - a
        t = np.clip(((cc + 0.5 - a[0]) * d[0] + (rr + 0.5 - a[1]) * d[1]) / max(float(d @ d), 1e-300), 0.0, 1.0)
        near = np.hypot(cc + 0.5 - (a[0] + t * d[0]), rr + 0.5 - (a[1] + t * d[1])) <= 0.7072
        if not near.any():
            continue
        boxes = shapely.box(cc[near], rr[near], cc[near] + 1.0, rr[near] + 1.0)
        line = shapely.LineString([a, b]) if float(d @ d) > 0 else shapely.Point(a)
        if shapely.relate_pattern(boxes, line, "T********").any():
            return True
        touched = boxes[shapely.intersects(boxes, line)]
        if len(touched) >= 2:
            meet = shapely.intersection(touched, line)
            spots = [(round(m.x, 9), round(m.y, 9)) for m in meet if m.geom_type == "Point"]
            if len(spots) != len(set(spots)):  # two squares touched at one vertex: a pinch
                return True
    return False


def run_map(task: dict[str, Any]) -> dict[str, Any]:
    """All queries and variants of one map (a worker's unit of work)."""
    from gridfield.io import read, read_movingai_map, read_scen
    from gridfield.planners import plan

    t_map = time.perf_counter()
    d = Path(task["path"])
    variants = {v: VARIANTS[v] for v in task["variants"]}
    queries: list[dict[str, Any]] = []
    cache: dict[Any, Any] | None = None if task["no_cache"] else {}
    info: dict[str, Any] = {"name": task["name"], "kind": task["kind"], "family": task["family"]}
    try:
        if task["kind"] == "movingai":
            map_file, scen_file = _map_and_scen(d)
            gm = read_movingai_map(map_file)
            scen = read_scen(scen_file, map_height=gm.shape[0])
            for i in movingai_sample(scen.bucket, scen.no_path, task["per_map"]).tolist():
                queries.append({"query": f"scen {i}", "start": scen.start_xy[i], "goal": scen.goal_xy[i],
                                "optimal": float("inf") if scen.no_path[i] else float(scen.optimal[i]),
                                "kind": "unreachable" if scen.no_path[i] else "reachable", "bucket": int(scen.bucket[i])})
        else:
            gm = generated_map(task["path"]) if task["kind"] == "generated" else read(d)
            pairs = ros_pairs(~gm.occupied, task["per_map"], task["ros_pairs"], task["ros_unreachable"])
            for k, (s, g, kind) in enumerate(pairs):
                start, goal = gm.grid.cell_to_world([s, g])
                q = {"query": f"pair {k}", "start": start, "goal": goal, "kind": kind, "start_cell": s, "goal_cell": g}
                try:
                    ref = plan("wavefront-octile", gm, start, goal, {}, cache=cache)
                    q["optimal"] = float(ref.length) if ref.status == "reached" else float("inf")
                    q["reference_status"] = ref.status
                except Exception as e:
                    q["optimal"], q["reference_status"] = float("nan"), "error: " + one_line(e)
                # the wavefront decides reachability; the component labelling must agree with it
                q["components_agree"] = (kind == "reachable") == bool(np.isfinite(q["optimal"]))
                q["kind"] = "reachable" if np.isfinite(q["optimal"]) else "unreachable"
                queries.append(q)
    except Exception as e:
        info.update(shape=None, resolution=None, runs=[], error=one_line(e), seconds=time.perf_counter() - t_map)
        return info
    info["shape"] = list(gm.shape)
    info["resolution"] = float(gm.grid.resolution)
    if task.get("quality", True):
        _quality_refs(gm, queries, cache, task)
    runs = []
    for q in queries:
        for v, params in variants.items():
            rec = run_query(gm, q["start"], q["goal"], v, params, q["optimal"], cache)
            rec.update({k: (val.tolist() if isinstance(val, np.ndarray) else val) for k, val in q.items()})
            rec["map"], rec["family"] = task["name"], task["family"]
            runs.append(rec)
    info["runs"] = runs
    info["seconds"] = time.perf_counter() - t_map
    return info


def bottleneck_clearance(dist: np.ndarray, free: np.ndarray, s: tuple[int, int], g: tuple[int, int]) -> float:
    """The largest ``t`` such that start and goal cells are joined by 4-connected free cells of
    clearance ``>= t`` (bisection over the distinct clearance values; ``nan`` if never joined)."""
    from scipy import ndimage

    vals = np.unique(dist[free & np.isfinite(dist)])
    vals = vals[vals <= min(dist[s], dist[g])]
    lo, hi, best = 0, len(vals) - 1, float("nan")
    while lo <= hi:
        mid = (lo + hi) // 2
        lab = ndimage.label(free & (dist >= vals[mid]))[0]
        if lab[s] != 0 and lab[s] == lab[g]:
            best, lo = float(vals[mid]), mid + 1
        else:
            hi = mid - 1
    return best


def _quality_refs(gm: Any, queries: list[dict[str, Any]], cache: dict[Any, Any] | None, task: dict[str, Any]) -> None:
    """Per query: the any-angle optimum, the bottleneck clearance (cells) and the time of
    ``wavefront-octile`` (the API, this map's cache), in place."""
    from gridfield.distance.brushfire import brushfire
    from gridfield.planners import plan

    free = ~np.asarray(gm.occupied, dtype=bool)
    res = float(gm.grid.resolution)
    dist = brushfire(gm, metric="euclidean").distance / res
    any_angle = gm.occupied.size <= task.get("any_angle_max_cells", 1 << 20)
    aa_cache: dict[Any, Any] = {}
    for q in queries:
        q["any_angle"] = q["bottleneck"] = q["octile_seconds"] = None
        if q["kind"] != "reachable":
            continue
        try:
            t0 = time.perf_counter()
            plan("wavefront-octile", gm, q["start"], q["goal"], {}, cache=cache)
            q["octile_seconds"] = time.perf_counter() - t0
            if any_angle:
                from gridfield.exact.anyangle import plan_anyangle

                p = plan_anyangle(gm, q["start"], q["goal"], cache=aa_cache)
                q["any_angle"] = float(p.length) if p.status == "reached" else None
            s = gm.grid.cell_of(*q["start"])
            g = gm.grid.cell_of(*q["goal"])
            q["bottleneck"] = bottleneck_clearance(dist, free, s, g)
        except Exception as e:  # a reference that fails is left out, and said
            q["reference_error"] = one_line(e)


def _pq(vals: list[float], q: float) -> float | None:
    return float(np.quantile(vals, q)) if vals else None


def quality(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """The quality figures of one group of runs (one variant, one map kind)."""
    reach = [r for r in runs if r["kind"] == "reachable"]
    ok = [r for r in reach if r["status"] == "reached"]
    aa = [r["length"] / r["any_angle"] for r in ok if r.get("any_angle")]
    octile = [r["ratio"] for r in ok if r.get("ratio") is not None]
    clear = [r["min_clearance"] / r["resolution"] for r in ok if r.get("min_clearance") is not None
             and np.isfinite(r["min_clearance"])]
    margin = [r["min_clearance"] / r["resolution"] - r["bottleneck"] for r in ok
              if r.get("min_clearance") is not None and r.get("bottleneck") is not None
              and np.isfinite(r["min_clearance"]) and np.isfinite(r["bottleneck"])]
    ms = [1000 * r["seconds"] for r in reach if r.get("seconds") is not None]
    ref = [1000 * r["octile_seconds"] for r in reach if r.get("octile_seconds") is not None]
    return {"reached": len(ok), "reachable": len(reach), "aa_med": _pq(aa, 0.5), "aa_p95": _pq(aa, 0.95), "aa_n": len(aa),
            "oct_med": _pq(octile, 0.5), "oct_p95": _pq(octile, 0.95), "clear_med": _pq(clear, 0.5),
            "margin_med": _pq(margin, 0.5), "ms_med": _pq(ms, 0.5), "ref_ms_med": _pq(ref, 0.5),
            "escapes": sum(int((r.get("extra") or {}).get("escapes_tried") or 0) for r in reach),
            "collisions": sum(r["status"] == "collision" for r in runs),
            "no_path_unreachable": f"{sum(r['status'] == 'no_path' for r in runs if r['kind'] == 'unreachable')}/"
                                   f"{sum(r['kind'] == 'unreachable' for r in runs)}"}


QUALITY_HEADERS = ["variant", "maps", "reached / reachable", "no_path / unreachable", "collisions", "escapes",
                   "any-angle ratio median", "p95", "(n)", "octile ratio median", "p95 ", "min clearance median (cells)",
                   "min clearance - bottleneck, median (cells)", "ms / query median", "wavefront-octile ms median",
                   "time ratio"]


def map_kind(family: str) -> str:
    """``movingai``, ``ros`` or ``generated``, from a run's map family."""
    return family if family in ("ros", "generated") else "movingai"


#: Issue 46's targets for the default: length / any-angle optimum median, p95, max; time per query
#: against ``wavefront-octile``'s on the same query (median of the per-query ratios).
SHORT_TARGETS = {"median": 1.03, "p95": 1.10, "max": 1.25, "time": 3.0}


def short_paths_report(results: list[dict[str, Any]], variants: Sequence[str]) -> list[str]:
    """Issue 46's table: per variant and map kind (and all maps), reached / reachable, escapes, runs
    crossing a blocked cell by exact geometry (:func:`exact_collision`), the length over the any-angle
    optimum (median, p95, max) and the time per query beside ``wavefront-octile``'s on the same
    queries (medians, and the per-query ratio's median and p90)."""
    all_runs = [r for m in results for r in m["runs"]]
    rows = []
    for v in variants:
        for kind, label in (("movingai", "Moving AI"), ("ros", "ROS"), ("generated", "generated"), (None, "**all**")):
            runs = [r for r in all_runs if r["variant"] == v and r["kind"] == "reachable"
                    and (kind is None or map_kind(r["family"]) == kind)]
            if not runs or all(r["status"] == NOT_AVAILABLE for r in runs):
                continue
            ok = [r for r in runs if r["status"] == "reached"]
            aa = np.array([r["length"] / r["any_angle"] for r in ok if r.get("any_angle")])
            timed = [r for r in runs if r.get("seconds") is not None and r.get("octile_seconds")]
            ms = np.array([1000 * r["seconds"] for r in timed])
            ref = np.array([1000 * r["octile_seconds"] for r in timed])
            ratio = ms / ref if len(timed) else np.array([np.nan])
            esc = sum(int((r.get("extra") or {}).get("escapes_tried") or 0) for r in runs)
            coll = sum(bool(r.get("exact_collision")) for r in runs)
            vals = (np.median(aa), np.quantile(aa, 0.95), aa.max()) if aa.size else (np.nan,) * 3
            met = (aa.size and vals[0] <= SHORT_TARGETS["median"] and vals[1] <= SHORT_TARGETS["p95"]
                   and vals[2] <= SHORT_TARGETS["max"] and len(ok) == len(runs) and esc == 0 and coll == 0
                   and np.median(ratio) <= SHORT_TARGETS["time"])
            rows.append([f"`{v}`", label, str(aa.size), f"{len(ok)}/{len(runs)}", str(esc), str(coll),
                         f"{vals[0]:.3f}", f"{vals[1]:.3f}", f"{vals[2]:.3f}",
                         f"{np.median(ms):.1f}" if ms.size else "-", f"{np.median(ref):.1f}" if ref.size else "-",
                         f"{np.median(ratio):.2f}", f"{np.quantile(ratio, 0.9):.2f}",
                         ("yes" if met else "no") if kind is None else ""])
    if not rows:
        return []
    t = SHORT_TARGETS
    return ["### Short paths (issue 46): length over the any-angle optimum, exact collisions, time", "",
            f"Targets over all maps: median <= {t['median']}, p95 <= {t['p95']}, max <= {t['max']}, every query "
            f"reached without escape, no exact collision, median per-query time <= {t['time']:g} x `wavefront-octile`.",
            "",
            markdown_table(["variant", "maps", "queries (any-angle)", "reached / reachable", "escapes",
                            "exact collisions", "median", "p95", "max", "ms / query median",
                            "wavefront-octile ms median", "time ratio median (per query)", "p90", "targets met"],
                           rows, left=2), ""]


def quality_report(results: list[dict[str, Any]], variants: Sequence[str]) -> list[str]:
    def f(v: float | None, d: int = 3) -> str:
        return "-" if v is None else f"{v:.{d}f}"

    lines: list[str] = []
    all_runs = [r for m in results for r in m["runs"]]
    for m in results:
        for r in m["runs"]:
            r["resolution"] = m["resolution"]
    for kind, label in (("movingai", "Moving AI"), ("ros", "ROS"), ("generated", "generated")):
        rows = []
        maps = [m for m in results if m["kind"] == kind and not m.get("error")]
        for v in variants:
            runs = [r for r in all_runs if r["variant"] == v and map_kind(r["family"]) == kind]
            if not runs or all(r["status"] == NOT_AVAILABLE for r in runs):
                continue
            q = quality(runs)
            ratio = q["ms_med"] / q["ref_ms_med"] if q["ms_med"] and q["ref_ms_med"] else None
            rows.append([v, str(len(maps)), f"{q['reached']}/{q['reachable']}", q["no_path_unreachable"],
                         str(q["collisions"]), str(q["escapes"]), f(q["aa_med"]), f(q["aa_p95"]), str(q["aa_n"]),
                         f(q["oct_med"]), f(q["oct_p95"]), f(q["clear_med"], 2), f(q["margin_med"], 2),
                         f(q["ms_med"], 1), f(q["ref_ms_med"], 1), f(ratio, 2)])
        if rows:
            lines += [f"### Quality: {label}", "", markdown_table(QUALITY_HEADERS, rows), ""]
    return lines


def time_report(results: list[dict[str, Any]], variants: Sequence[str]) -> list[str]:
    """The time target of issue 25 on the 512 x 512 Moving AI maps: per variant, the median over the
    reachable queries of the plan's time, of ``wavefront-octile``'s on the same query (the API, the
    map's warm cache, timed just before), and of the per-query ratio (with its 90th percentile)."""
    maps = [m for m in results if m["kind"] == "movingai" and not m.get("error") and list(m.get("shape") or []) == [512, 512]]
    names = {m["name"] for m in maps}
    rows = []
    for v in variants:
        runs = [r for m in maps for r in m["runs"] if r["variant"] == v and r["kind"] == "reachable"
                and r.get("seconds") is not None and r.get("octile_seconds")]
        if not runs or all(r["status"] == NOT_AVAILABLE for r in runs):
            continue
        ms = [1000 * r["seconds"] for r in runs]
        ref = [1000 * r["octile_seconds"] for r in runs]
        ratio = [a / b for a, b in zip(ms, ref, strict=True)]
        med, rmed = float(np.median(ms)), float(np.median(ratio))
        rows.append([v, str(len(names)), str(len(runs)), f"{med:.1f}", f"{np.median(ref):.1f}", f"{rmed:.2f}",
                     f"{np.quantile(ratio, 0.9):.2f}", "yes" if med <= 10.0 and rmed <= 3.0 else "no"])
    if not rows:
        return []
    return ["### Time: the 512 x 512 Moving AI maps", "",
            "Target (issue 25): median <= 10 ms per query and median per-query ratio to `wavefront-octile` <= 3.", "",
            markdown_table(["variant", "maps", "queries", "ms / query median", "wavefront-octile ms median",
                            "ratio median (per query)", "ratio p90", "target met"], rows), ""]


# ----------------------------------------------------------------------------------------------
# Tables
# ----------------------------------------------------------------------------------------------
def pct(k: int, n: int) -> str:
    return f"{100.0 * k / n:.1f}% ({k})" if n else "-"


def summarize(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """Counts and shares of one group of runs (one variant)."""
    n = len(runs)
    na = sum(r["status"] == NOT_AVAILABLE for r in runs)
    counts = Counter(r["status"] for r in runs)
    failures = [r for r in runs if r["status"] not in ("reached", NOT_AVAILABLE)]
    reachable = [r for r in runs if r["kind"] == "reachable"]
    unreachable = [r for r in runs if r["kind"] == "unreachable"]
    ratios = [r["ratio"] for r in runs if r["ratio"] is not None]
    return {
        "runs": n, "n/a": na, "counts": {s: counts.get(s, 0) for s in STATUS_COLUMNS},
        "other": {s: c for s, c in counts.items() if s not in STATUS_COLUMNS and s != NOT_AVAILABLE},
        "reachable": len(reachable), "reached_of_reachable": sum(r["status"] == "reached" for r in reachable),
        "unreachable": len(unreachable), "no_path_of_unreachable": sum(r["status"] == "no_path" for r in unreachable),
        "median_ratio": statistics.median(ratios) if ratios else None,
        "failures": len(failures), "failures_with_hint": sum(bool(r["hint"]) for r in failures),
    }


def summary_row(label: str, maps: int, s: dict[str, Any]) -> list[str]:
    n = s["runs"]
    if n and s["n/a"] == n:
        return [label, str(maps), str(n)] + [NOT_AVAILABLE] * (len(SUMMARY_HEADERS) - 3)
    other = sum(s["other"].values())
    row = [label, str(maps), str(n)]
    row += [pct(s["counts"][c], n) for c in STATUS_COLUMNS]
    row[-1] += f" +{other} other" if other else ""
    row.append(f"{s['reached_of_reachable']}/{s['reachable']}")
    row.append(f"{s['no_path_of_unreachable']}/{s['unreachable']}" if s["unreachable"] else "-")
    row.append(f"{s['median_ratio']:.3f}" if s["median_ratio"] is not None else "-")
    row.append(f"{s['failures_with_hint']}/{s['failures']}")
    row.append(str(s["failures"] - s["failures_with_hint"]))
    return row


def markdown_table(headers: Sequence[str], rows: Sequence[Sequence[str]], left: int = 1) -> str:
    """A markdown table: the first ``left`` columns left-aligned, the others right-aligned."""
    rule = ["---"] * left + ["---:"] * (len(headers) - left)
    lines = ["| " + " | ".join(headers) + " |", "|" + "|".join(rule) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


SUMMARY_HEADERS = ["family", "maps", "runs", "reached", "local_minimum", "collision", "max_iterations", "no_path",
                   "error", "reached / reachable", "no_path / unreachable", "median length ratio (reached)",
                   "failures with hint", "failures without hint"]


def resolved_in_cells(runs: list[dict[str, Any]], resolution: float) -> str:
    """The resolved ``q_star / step / tolerance`` of the map's runs in cells ("a-b" when they vary)."""
    parts = []
    for k in ("q_star", "step", "tolerance"):
        vals = sorted({r["resolved"][k] / resolution for r in runs
                       if isinstance((r.get("resolved") or {}).get(k), int | float)})
        parts.append("-" if not vals else f"{vals[0]:.3g}" if vals[0] == vals[-1] else f"{vals[0]:.3g}-{vals[-1]:.3g}")
    return " / ".join(parts)


def report(results: list[dict[str, Any]], variants: Sequence[str]) -> list[str]:
    lines: list[str] = []
    all_runs = [r for m in results for r in m["runs"]]
    for v in variants:
        runs = [r for r in all_runs if r["variant"] == v]
        rows = []
        for fam in FAMILY_ORDER:
            fam_maps = [m for m in results if m["family"] == fam]
            if fam_maps:
                rows.append(summary_row(fam, len(fam_maps), summarize([r for r in runs if r["family"] == fam])))
        mai = [m for m in results if m["kind"] == "movingai"]
        ros = [m for m in results if m["kind"] == "ros"]
        if mai:
            rows.append(summary_row("**all Moving AI**", len(mai),
                                    summarize([r for r in runs if map_kind(r["family"]) == "movingai"])))
        if ros:
            rows.append(summary_row("**all ROS**", len(ros), summarize([r for r in runs if r["family"] == "ros"])))
        rows.append(summary_row("**overall**", len(results), summarize(runs)))
        lines += [f"### `{v}`: params={json.dumps(VARIANTS[v])}", "", markdown_table(SUMMARY_HEADERS, rows), ""]
        na = [r for r in runs if r["status"] == NOT_AVAILABLE]
        if na:
            lines += [f"n/a: {na[0]['message']}", ""]
        errors = Counter(r["message"] for r in runs if r["status"] == "error")
        if errors:
            lines += ["Errors (most frequent first):", ""]
            lines += [f"- {c} x `{msg}`" for msg, c in errors.most_common(8)]
            lines.append("")
    # one row per map, every variant side by side
    headers = ["map", "family", "W x H", "resolution", "queries", "seconds"]
    headers += [f"{v}: reached / lm / coll / maxit / no_path / err" for v in variants]
    headers.append("resolved q_star / step / tolerance, in cells")
    rows = []
    for m in sorted(results, key=lambda m: (FAMILY_ORDER.index(m["family"]), m["name"].lower())):
        if m.get("error"):
            rows.append([m["name"], m["family"], "-", "-", "-", f"{m['seconds']:.1f}", f"map error: {m['error']}"]
                        + [""] * len(variants))
            continue
        nq = len({r["query"] for r in m["runs"]})
        row = [m["name"], m["family"], f"{m['shape'][1]}x{m['shape'][0]}", f"{m['resolution']:g}", str(nq),
               f"{m['seconds']:.1f}"]
        for v in variants:
            s = summarize([r for r in m["runs"] if r["variant"] == v])
            if s["runs"] and s["n/a"] == s["runs"]:
                row.append(NOT_AVAILABLE)
            else:
                row.append(" / ".join(str(s["counts"][c]) for c in STATUS_COLUMNS))
        row.append(resolved_in_cells(m["runs"], m["resolution"]))
        rows.append(row)
    lines += ["### Per map", "", markdown_table(headers, rows, left=2), ""]
    disagree = [r for r in all_runs if r.get("components_agree") is False]
    if disagree:
        lines += [f"Warning: {len({(r['map'], r['query']) for r in disagree})} ROS queries where the 4-connected "
                  "component labelling and the octile wavefront disagree on reachability (the wavefront decides).", ""]
    return lines


# ----------------------------------------------------------------------------------------------
# Main
# ----------------------------------------------------------------------------------------------
def gridfield_checkout() -> tuple[str, str]:
    """The folder of the imported gridfield package's checkout and its ``git describe --always --dirty``."""
    import gridfield

    root = Path(gridfield.__file__).resolve().parent.parent
    try:
        out = subprocess.run(["git", "-C", str(root), "describe", "--always", "--dirty"], capture_output=True,
                             text=True, timeout=30)
        desc = out.stdout.strip() if out.returncode == 0 else f"unknown (git: {out.stderr.strip()[:80]})"
    except (OSError, subprocess.SubprocessError) as e:
        desc = f"unknown ({e})"
    return str(root), desc


def find_tasks(root: Path, args: argparse.Namespace) -> list[dict[str, Any]]:
    tasks = []
    common = {"per_map": args.per_map, "variants": args.variants, "ros_pairs": args.ros_pairs,
              "ros_unreachable": args.ros_unreachable, "no_cache": args.no_cache, "quality": args.quality,
              "any_angle_max_cells": args.any_angle_max_cells}
    mai = root / "movingai"
    if mai.is_dir():
        for d in sorted(p for p in mai.iterdir() if p.is_dir() and (any(p.glob("*.map")) or any(p.glob("*.map.gz")))):
            size = sum(f.stat().st_size for f in d.iterdir())
            tasks.append({"name": d.name, "path": str(d), "kind": "movingai", "family": FAMILIES.get(d.name, "movingai"),
                          "size": size, **common})
    ros = root / "ros_maps"
    if ros.is_dir():
        for y in sorted(ros.glob("*/*.yaml")):
            size = sum(f.stat().st_size for f in y.parent.iterdir())
            tasks.append({"name": y.parent.name, "path": str(y), "kind": "ros", "family": "ros", "size": size, **common})
    for spec in GENERATED[: args.generated]:
        tasks.append({"name": "gen_" + spec.replace(":", "_"), "path": spec, "kind": "generated", "family": "generated",
                      "size": 1 << 16, **common})
    if args.maps:
        tasks = [t for t in tasks if t["name"] in args.maps]
    if args.limit_maps is not None:  # the smallest maps of each kind first: quick runs
        tasks = sorted(tasks, key=lambda t: t["size"])
        kept = [t for t in tasks if t["kind"] == "movingai"][: args.limit_maps]
        kept += [t for t in tasks if t["kind"] == "ros"][: args.limit_maps]
        kept += [t for t in tasks if t["kind"] == "generated"][: args.limit_maps]
        tasks = kept
    return tasks


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--maps-root", type=Path, default=DEFAULT_ROOT,
                    help="folder holding movingai/ and ros_maps/ (default: tests/data/maps, the test suite's copy)")
    ap.add_argument("--per-map", type=int, default=20, help="scenarios (Moving AI) or random pairs (ROS) per map")
    ap.add_argument("--variants", nargs="+", default=list(DEFAULT_VARIANTS), choices=list(VARIANTS),
                    help=f"default: {' '.join(DEFAULT_VARIANTS)} (the variants of issue 12; the models: khatib nf1 "
                         "nf1_plain nf1_octile nf2 nf_blend)")
    ap.add_argument("--workers", type=int, default=2, help="worker processes (spawn), one map each at a time")
    ap.add_argument("--limit-maps", type=int, default=None,
                    help="only the N smallest Moving AI and the N smallest ROS maps (quick runs)")
    ap.add_argument("--maps", nargs="*", default=None, help="map folder names (default: all)")
    ap.add_argument("--ros-pairs", choices=("same", "any"), default="same",
                    help="ROS pairs: goal in the start's free component (same) or anywhere (any)")
    ap.add_argument("--ros-unreachable", type=int, default=2,
                    help="extra ROS pairs per map with start and goal in different free components")
    ap.add_argument("--no-cache", action="store_true",
                    help="no plan() cache: every query builds its field from scratch, brushfire included (slower)")
    ap.add_argument("--quality", action=argparse.BooleanOptionalAction, default=True,
                    help="the quality table: any-angle optimum, bottleneck clearance, wavefront-octile time per query")
    ap.add_argument("--any-angle-max-cells", type=int, default=1 << 20,
                    help="compute the any-angle optimum only on maps with at most this many cells")
    ap.add_argument("--generated", type=int, default=0,
                    help=f"also the first N generated maps of GENERATED (at most {len(GENERATED)}; ROS-like pairs)")
    ap.add_argument("--label", default="", help="written into the header, e.g. before or after")
    ap.add_argument("--out", type=Path, default=None, help="also write the markdown report to this file")
    ap.add_argument("--json", type=Path, default=None, help="write every run to this JSON file")
    args = ap.parse_args(argv)
    if args.per_map < 0 or args.workers < 1 or args.ros_unreachable < 0:
        ap.error("--per-map and --ros-unreachable must be >= 0, --workers >= 1")
    if not args.maps_root.is_dir():
        ap.error(f"maps root {args.maps_root} does not exist")
    tasks = find_tasks(args.maps_root, args)
    if not tasks:
        ap.error(f"no Moving AI map+scenario folders or ROS map YAMLs under {args.maps_root}")
    tasks.sort(key=lambda t: -t["size"])  # largest first, so that the pool stays busy
    from _common import machine_facts  # benchmarks/ is on sys.path when this runs as a script

    checkout, describe = gridfield_checkout()
    t0 = time.perf_counter()
    if args.workers > 1:
        ctx = multiprocessing.get_context("spawn")  # no fork after numba / OpenMP threads
        with ProcessPoolExecutor(args.workers, mp_context=ctx) as pool:
            results = list(pool.map(run_map, tasks))
    else:
        results = [run_map(t) for t in tasks]
    wall = time.perf_counter() - t0
    runs = [r for m in results for r in m["runs"]]
    cpu = sum(m["seconds"] for m in results)
    plan_s = Counter()
    for r in runs:
        plan_s[r["variant"]] += r["seconds"] or 0.0
    header = [
        f"## Potential planner on real maps{f' ({args.label})' if args.label else ''}", "",
        f"- gridfield: `{describe}` imported from `{checkout}`",
        f"- command: `python benchmarks/potential_real.py {' '.join(argv if argv is not None else sys.argv[1:])}`",
        f"- date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {os.cpu_count()} cores, "
        f"{args.workers} worker process(es); {machine_facts()}",
        f"- maps: {sum(m['kind'] == 'movingai' for m in results)} Moving AI, {sum(m['kind'] == 'ros' for m in results)} "
        f"ROS under `{args.maps_root}`, {sum(m['kind'] == 'generated' for m in results)} generated; {args.per_map} scenarios / pairs per map (ROS pairs: {args.ros_pairs} "
        f"component, + {args.ros_unreachable} in different components), {len({(r['map'], r['query']) for r in runs})} "
        f"queries, {len(runs)} runs",
        f"- time: {wall:.0f} s wall, {cpu:.0f} s in the workers (reading, sampling, wavefront references, plans); "
        "plan() seconds per variant: " + ", ".join(f"{v} {plan_s[v]:.0f} s" for v in args.variants),
        "",
        "Shares are of all runs of the variant; `reached / reachable`: runs whose goal the octile wavefront reaches "
        "that reached it; `median length ratio`: path length / optimal octile length over reached runs (Moving AI: "
        "the scenario's optimum; ROS: `wavefront-octile`); `failures with hint`: runs not reaching the goal whose "
        "`path.extra` carries a `hint`. Per-map cells: reached / local_minimum / collision / max_iterations / "
        "no_path / error.",
        "",
    ]
    lines = header + ((short_paths_report(results, args.variants) + quality_report(results, args.variants)
                       + time_report(results, args.variants)) if args.quality else [])
    lines += report(results, args.variants)
    text = "\n".join(lines).rstrip() + "\n"
    print(text, end="")
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(text)
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        meta = {"label": args.label, "gridfield": describe, "checkout": checkout, "wall_seconds": wall,
                "args": {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items()}}
        maps = [{k: v for k, v in m.items() if k != "runs"} for m in results]
        def dump(x: Any) -> str:
            return json.dumps(_finite(x), default=_jsonable, allow_nan=False)

        # one run per line: small, and diffs of two dumps stay readable
        args.json.write_text(f'{{"meta": {dump(meta)},\n"maps": [\n' + ",\n".join(dump(m) for m in maps)
                             + '\n],\n"runs": [\n' + ",\n".join(dump(r) for r in runs) + "\n]}\n")
    return 0


def _finite(x: Any) -> Any:
    """``x`` with every non-finite float replaced by None (strict JSON; an unreachable optimum is null)."""
    if isinstance(x, float | np.floating):
        return float(x) if np.isfinite(x) else None
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_finite(v) for v in x]
    if isinstance(x, np.ndarray):
        return _finite(x.tolist())
    return x


def _jsonable(x: Any) -> Any:
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)


if __name__ == "__main__":
    raise SystemExit(main())
