"""Benchmark: end-to-end ``plan`` (brushfire, potential, gradients, follower) on large maps in memory.

Run ``python benchmarks/end_to_end.py`` (options: ``--sizes`` (default 1024 4096 8192), ``--repeat``
(default 3), ``--no-tracemalloc``, ``--json``, ``--model khatib|default``).

The map is the same 100 m x 100 m world at every size (resolution ``100 / n``): 40 rectangles and
discs laid out by a fixed seed (about 11 % occupied), start (5, 5) and goal (95, 95) in its free
corners. It is built in memory (no file I/O); what is timed is one call of
``gridfield.planners.plan("potential", gridmap, start, goal, params)``. With ``--model khatib`` (the
default here, and what the end-to-end targets of ``benchmarks/run.py`` were set on) that computes the
Euclidean brushfire, the fused attractive + repulsive potential and its gradients, and follows them.
``--model default`` leaves the model to the planner, whose default since issue 25 is the complete
field ``nf1`` (:mod:`gridfield.fields.navfield`: the brushfire, the clearance band's slowness, a weighted-A*
fast march from the goal towards the start, its upwind gradient, the follower): a different and
heavier computation, reported beside the classic one by ``run.py``.

Each size runs in its own fresh Python process, so that numbers do not depend on what ran before:

- **time**: after a warm-up plan on a 64 x 64 map (compiles or loads the numba kernels) and a
  first plan on the big map, ``--repeat`` rounds, each running once (interleaved, so that a burst
  of load from other jobs hits all alike): the plan; OpenCV's ``cv2.distanceTransform(DIST_C, 3)``
  alone on the same map (the reference of the 3x target); the brushfire alone as ``plan`` calls
  it (``field_distance_map``: Euclidean distance and nearest obstacle, no wavefront steps, labels
  or GVD, which no potential reads). Then, for context, the full brushfire (all of them), timed
  after the rounds: its larger arrays would change the memory the others get back from the
  allocator (on this VM, memory the process has not touched lately costs up to several times more
  to write: the first plan on a big map takes 3-5x a later one). Medians / min / max; ``ratio``
  is plan / DIST_C.
- **peak memory**: the child process's peak resident set size, ``VmHWM`` from /proc/self/status
  (not ``ru_maxrss``: on Linux a child's ``ru_maxrss``, as read with ``RUSAGE_CHILDREN`` or
  ``os.wait4``, starts from its parent's peak at fork and survives exec, so it reports a big
  parent's memory; the wait4 value is kept in ``--json`` output). It includes the interpreter,
  numpy/scipy/numba and the map; the peak before the first plan is reported beside it. The first
  plan runs before any other measurement, so the peak is the plan's. With tracemalloc (default
  on) one more plan is traced after the timed ones: the peak of memory allocated *during*
  ``plan`` (numpy allocations are traced by tracemalloc; the map was allocated before tracing).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

#: World side in metres; the grid has ``n`` cells per side at resolution ``WORLD / n``.
WORLD = 100.0
START = (5.0, 5.0)
GOAL = (95.0, 95.0)
#: Planner parameters: a conic attraction beyond 2 m so that the attraction does not swamp the
#: repulsion far from the goal; the other potential parameters are gridfield's defaults.
PARAMS: dict[str, Any] = {"d_star": 2.0, "eta": 1.0, "q_star": 2.0}
#: The field models ``--model`` takes: ``khatib`` (the classic field, set explicitly: the pipeline the
#: end-to-end targets were set on) and ``default`` (no ``model``: the planner's default, ``nf1``).
MODELS = ("khatib", "default")
DEFAULT_SIZES = (1024, 4096, 8192)
GiB = 2**30


# ----------------------------------------------------------------------------------------------
# Timing helper shared by run.py and peers.py
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Timing:
    """Wall times of repeated runs of one function, in seconds."""

    median: float
    min: float
    max: float
    n: int

    @property
    def ms(self) -> str:
        """``median (min-max)`` in milliseconds, for tables."""
        return f"{self.median * 1e3:.4g} ({self.min * 1e3:.4g}-{self.max * 1e3:.4g})"


def timed(fn: Callable[[], Any], repeat: int, *, warmup: int = 1, budget: float = 60.0) -> tuple[Timing, Any]:
    """Run ``fn`` ``warmup`` times untimed, then ``repeat`` times timed; return the timing and the last result.

    A function whose warm-up took longer than ``budget / repeat`` seconds is timed fewer times (at
    least once) so that one line of a table never costs much more than ``budget`` seconds; the
    returned ``Timing.n`` says how many runs were timed. The previous result is dropped before
    each run, so that two results never coexist in memory.
    """
    out: Any = None
    t_warm = 0.0
    for _ in range(warmup):
        out = None
        t0 = time.perf_counter()
        out = fn()
        t_warm = time.perf_counter() - t0
    n = repeat
    if warmup and t_warm * repeat > budget:
        n = max(1, int(budget / max(t_warm, 1e-9)))
    times = []
    for _ in range(n):
        out = None
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return Timing(statistics.median(times), min(times), max(times), len(times)), out


# ----------------------------------------------------------------------------------------------
# The map
# ----------------------------------------------------------------------------------------------
def synthetic_occupancy(n: int, *, seed: int = 0, obstacles: int = 40) -> np.ndarray:
    """Boolean occupancy ``(n, n)`` of the benchmark world, ``True`` = obstacle.

    Obstacles are axis-aligned squares and discs with centres in ``[0.12, 0.88]`` of the side and
    half-sizes of 1-4 % of it, defined in unit coordinates so that every ``n`` rasterizes the same
    world. Row 0 is the lowest y (gridfield's convention).
    """
    rng = np.random.default_rng(seed)
    cx, cy = rng.uniform(0.12, 0.88, obstacles), rng.uniform(0.12, 0.88, obstacles)
    half = rng.uniform(0.01, 0.04, obstacles)
    occ = np.zeros((n, n), bool)
    centres = (np.arange(n) + 0.5) / n
    for i in range(obstacles):
        r0, r1 = max(int((cy[i] - half[i]) * n), 0), min(int((cy[i] + half[i]) * n) + 1, n)
        c0, c1 = max(int((cx[i] - half[i]) * n), 0), min(int((cx[i] + half[i]) * n) + 1, n)
        ys, xs = centres[r0:r1, None], centres[None, c0:c1]
        if i % 2:
            occ[r0:r1, c0:c1] |= (xs - cx[i]) ** 2 + (ys - cy[i]) ** 2 <= half[i] ** 2
        else:
            occ[r0:r1, c0:c1] |= (np.abs(xs - cx[i]) <= half[i]) & (np.abs(ys - cy[i]) <= half[i])
    return occ


def synthetic_map(n: int, *, seed: int = 0) -> Any:
    """The benchmark world as a :class:`gridfield.core.grid.GridMap` with ``n x n`` cells (open border)."""
    from gridfield.core.grid import Grid, GridMap

    return GridMap(Grid((n, n), WORLD / n), synthetic_occupancy(n, seed=seed), source=f"synthetic {n}x{n}")


def plan_params(n: int, model: str = "khatib") -> dict[str, Any]:
    """``PARAMS`` plus a step budget large enough to cross the map at one cell per step, and the
    field ``model`` unless it is ``"default"`` (the planner's own default)."""
    extra = {} if model == "default" else {"model": model}
    return {**PARAMS, **extra, "max_iterations": 4 * n}


# ----------------------------------------------------------------------------------------------
# One size, in this process (the child)
# ----------------------------------------------------------------------------------------------
def _peak_rss_bytes() -> int:
    """This process's peak resident set size in bytes: ``VmHWM`` of /proc/self/status.

    Not ``ru_maxrss``: on Linux a child's ``ru_maxrss`` (and so ``RUSAGE_CHILDREN`` / ``wait4``) starts
    from the parent's peak at ``fork`` and survives ``exec``, so a child spawned by a big parent
    reports the parent's peak. ``VmHWM`` belongs to the child's own address space.
    """
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: KiB


def round_robin(candidates: dict[str, Callable[[], Any]], repeat: int) -> dict[str, Timing]:
    """Time each candidate ``repeat`` times, interleaved (one run of each per round), so that a burst
    of load from other jobs hits all alike. Candidates are assumed warmed up already."""
    runs: dict[str, list[float]] = {k: [] for k in candidates}
    for _ in range(repeat):
        for k, fn in candidates.items():
            t0 = time.perf_counter()
            out = fn()
            runs[k].append(time.perf_counter() - t0)
            del out
    return {k: Timing(statistics.median(v), min(v), max(v), len(v)) for k, v in runs.items()}


def measure_size(n: int, repeat: int, *, trace: bool = True, model: str = "khatib") -> dict[str, Any]:
    """Measure one size in the current process (meant to be a fresh one); a JSON-able dict."""
    try:
        import cv2
    except ImportError:  # opencv-python-headless is in the [bench] extra only
        cv2 = None
    from gridfield.distance.brushfire import brushfire
    from gridfield.fields.potential import field_distance_map
    from gridfield.planners import plan

    small = synthetic_map(64)
    plan("potential", small, START, GOAL, plan_params(64, model))  # load the kernels
    brushfire(small, metric="euclidean")
    gm = synthetic_map(n)
    params = plan_params(n, model)
    rss_before = _peak_rss_bytes()

    # the first plan runs before anything else, so the peak RSS after it is the plan's
    t0 = time.perf_counter()
    path = plan("potential", gm, START, GOAL, params)
    first = time.perf_counter() - t0
    rss_plan = _peak_rss_bytes()
    info = {"status": path.status, "iterations": int(path.iterations), "length": float(path.length),
            "model": str(path.params.get("model")),
            "follow_s": float(path.seconds), "build_s": float(path.extra.get("build_seconds", float("nan")))}
    del path

    builds: list[float] = []
    follows: list[float] = []

    def one_plan() -> None:
        p = plan("potential", gm, START, GOAL, params)
        builds.append(float(p.extra.get("build_seconds", float("nan"))))
        follows.append(float(p.seconds))

    candidates: dict[str, Callable[[], Any]] = {
        "plan": one_plan,
        "brushfire": lambda: field_distance_map(gm, params),
    }
    if cv2 is not None:
        free8 = np.ascontiguousarray(~gm.occupied, dtype=np.uint8)
        cv2.distanceTransform(free8, cv2.DIST_C, 3)  # warm-up
        candidates["dist_c"] = lambda: cv2.distanceTransform(free8, cv2.DIST_C, 3)
    times = round_robin(candidates, repeat)
    t_plan, t_bf = times["plan"], times["brushfire"]
    # context, timed after the rounds: its larger arrays would change the memory the others reuse
    t_bf_full = round_robin({"full": lambda: brushfire(gm, metric="euclidean")}, repeat)["full"]
    t_distc = times.get("dist_c")

    traced = None
    if trace:
        import tracemalloc

        tracemalloc.start()
        p = plan("potential", gm, START, GOAL, params)
        traced = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        del p
    return {
        "n": n, "occupied": float(gm.occupied.mean()), "first_plan_s": first,
        "plan": asdict(t_plan), "dist_c": asdict(t_distc) if t_distc else None, "brushfire": asdict(t_bf),
        "brushfire_full": asdict(t_bf_full),
        "build_median_s": statistics.median(builds), "follow_median_s": statistics.median(follows),
        "rss_before_plan": rss_before, "rss_after_first_plan": rss_plan, "rss_peak_self": _peak_rss_bytes(),
        "traced_peak": traced, **info,
    }


# ----------------------------------------------------------------------------------------------
# Every size, each in a fresh process (the parent)
# ----------------------------------------------------------------------------------------------
def run_child(n: int, repeat: int, *, trace: bool = True, model: str = "khatib") -> dict[str, Any]:
    """Measure size ``n`` in a fresh interpreter; ``rss_peak`` is its VmHWM in bytes (``ru_maxrss_wait4``,
    the child's rusage from ``os.wait4``, is kept for comparison: it cannot be lower than the parent's
    peak at fork)."""
    cmd = [sys.executable, os.path.abspath(__file__), "--child", str(n), "--repeat", str(repeat), "--model", model]
    if not trace:
        cmd.append("--no-tracemalloc")
    t0 = time.monotonic()
    with tempfile.TemporaryFile("w+") as err:
        # the size guard's estimate (gridfield.core.limits: the CLI's worst case per cell, with a failed run's
        # diagnosis) is not what is measured here: a cell limit of the map's size replaces it, as in memory.py
        env = {**os.environ, "GRIDFIELD_MAX_CELLS": str(max(n * n, 1 << 20))}  # the warm-up map too
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=err, text=True, env=env)
        assert proc.stdout is not None
        out = proc.stdout.read()  # until the child closes stdout (it exits)
        proc.stdout.close()
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)  # reaped here, not by Popen
        err.seek(0)
        message = (err.read().strip().splitlines() or ["(no message)"])[-1]
    wall = time.monotonic() - t0
    if proc.returncode != 0 or not out.strip():
        return {"n": n, "error": f"child exited with {proc.returncode}: {message}"}
    result = json.loads(out.strip().splitlines()[-1])
    result["rss_peak"] = result["rss_peak_self"]  # VmHWM (see _peak_rss_bytes)
    result["ru_maxrss_wait4"] = usage.ru_maxrss * 1024  # includes the parent's peak at fork
    result["child_wall_s"] = wall
    return result


def measure(sizes: Sequence[int] = DEFAULT_SIZES, repeat: int = 3, *, trace: bool = True,
            model: str = "khatib") -> list[dict[str, Any]]:
    """Measure every size, each in a fresh process, with the field ``model`` (:data:`MODELS`)."""
    return [run_child(n, repeat, trace=trace, model=model) for n in sizes]


def _mb(b: float | None) -> str:
    return "-" if b is None else f"{b / 2**20:,.0f}"


def table(results: Sequence[dict[str, Any]]) -> str:
    """Markdown tables of :func:`measure`'s results."""
    lines = [
        "| size | plan ms median (min-max) | n | OpenCV DIST_C ms | plan / DIST_C | brushfire ms (as plan: distance "
        "+ nearest) | brushfire ms (full: + steps, labels, GVD) | build ms (brushfire + potential) | follow ms "
        "| status, steps | model |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        if "error" in r:
            lines.append(f"| {r['n']}^2 | failed: {r['error']} | | | | | | | | | |")
            continue
        p, d = r["plan"], r["dist_c"]
        dc = f"{d['median'] * 1e3:,.1f} | **{p['median'] / d['median']:.2f}**" if d else "not installed | -"
        lines.append(
            f"| {r['n']}^2 | {p['median'] * 1e3:,.0f} ({p['min'] * 1e3:,.0f}-{p['max'] * 1e3:,.0f}) | {p['n']} "
            f"| {dc} | {r['brushfire']['median'] * 1e3:,.0f} "
            f"| {r['brushfire_full']['median'] * 1e3:,.0f} | {r['build_median_s'] * 1e3:,.0f} "
            f"| {r['follow_median_s'] * 1e3:,.1f} | {r['status']}, {r['iterations']} | {r.get('model', '-')} |"
        )
    lines += [
        "",
        "| size | peak RSS MiB (whole process, VmHWM) | peak RSS before plan MiB | plan's own allocations, "
        "tracemalloc peak MiB | within 4 GiB |",
        "|---|---|---|---|---|",
    ]
    for r in results:
        if "error" in r:
            continue
        lines.append(
            f"| {r['n']}^2 | {_mb(r['rss_peak'])} | {_mb(r['rss_before_plan'])} | {_mb(r.get('traced_peak'))} "
            f"| {'yes' if r['rss_peak'] <= 4 * GiB else 'NO'} |"
        )
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=list(DEFAULT_SIZES), help="cells per side")
    ap.add_argument("--repeat", type=int, default=3, help="timed plans per size (median reported)")
    ap.add_argument("--no-tracemalloc", action="store_true", help="skip the traced plan")
    ap.add_argument("--json", action="store_true", help="print the raw results as JSON")
    ap.add_argument("--model", choices=MODELS, default="khatib",
                    help="the field: khatib (the classic one, default here) or default (the planner's: nf1)")
    ap.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(measure_size(args.child, args.repeat, trace=not args.no_tracemalloc, model=args.model)))
        return 0
    results = measure(args.sizes, args.repeat, trace=not args.no_tracemalloc, model=args.model)
    print(json.dumps(results, indent=1) if args.json else table(results))
    return 1 if any("error" in r for r in results) else 0


if __name__ == "__main__":
    raise SystemExit(main())
