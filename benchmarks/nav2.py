"""Nav2 interop: planners on inflated costmaps, NavFn's speed at 4000², costmap point queries.

Run ``python benchmarks/nav2.py [--maps-root tests/data/maps] [--per-map 8] [--big 4000] [--repeat 3]
[--points 1000000]``.

1. **Planners on the same costmaps.** For each ROS map (turtlebot3_world, nav2_depot,
   nav2_smoothers_world) its Nav2 costmap (:func:`gridfield.fields.costmap.inflate`, Nav2's defaults:
   robot radius 0.1, inflation radius 0.55, cost scaling 10), and ``--per-map`` pairs of free cells
   (cost < 253, in one 4-connected component of them) drawn with ``numpy.random.default_rng(0)``.
   Every planner plans on that :class:`Costmap` through ``gridfield.planners.plan`` (one cache per
   map and planner): ``potential`` (defaults), ``wavefront-octile``, ``fmm`` and ``navfn`` (on the
   costs); the others see its blocked cells (cost >= 253). Columns: reached share, the path length
   over the any-angle optimum (``plan("visibility", costmap, ...)``, the taut path among the blocked
   cells; median over the reached queries), the smallest clearance to a blocked cell (median), ms per
   query (median, the cache warm).
2. **NavFn at 4000².** The planner benchmark map ``100by100_10`` (2000², tiled 2 x 2 to 4000 x 4000
   cells when ``--big 4000``), its costmap, one query from near one corner to near the opposite one;
   ``navfn`` and ``wavefront-octile`` timed round-robin (``--repeat`` runs, medians) on the same
   Costmap; the target is navfn <= 1.5x wavefront-octile.
3. **Queries.** ``--points`` uniform random points over the depot costmap: ``cost_at``, ``distance``,
   ``gradient``, ``nearest_obstacle`` (medians of ``--repeat``; the target is <= 0.2 s per million).

Prints markdown tables, with the machine's load at the start (the development machine is shared:
absolute times scale with it, the ratios less).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import TEST_MAPS

from gridfield.core.grid import Grid
from gridfield.fields.costmap import Costmap, inflate
from gridfield.io import read
from gridfield.planners import plan

PLANNERS = ("potential", "wavefront-octile", "fmm", "navfn")
MAPS = ("turtlebot3_world/map.yaml", "nav2_depot/depot.yaml", "nav2_smoothers_world/smoothers_world.yaml")


def _pairs(cm: Costmap, n: int, rng: np.random.Generator) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    from scipy.ndimage import label

    free = cm.cost < 253
    lab, _k = label(free)
    sizes = np.bincount(lab.ravel())
    sizes[0] = 0
    big = lab == int(np.argmax(sizes))
    cells = np.argwhere(big)
    xs, ys = cm.grid.cell_centers()
    out = []
    while len(out) < n:
        a, b = cells[rng.integers(len(cells), size=2)]
        if np.hypot(*(a - b)) < 30:
            continue
        out.append(((float(xs[a[1]]), float(ys[a[0]])), (float(xs[b[1]]), float(ys[b[0]]))))
    return out


def planners_table(root: Path, per_map: int) -> str:
    rows = []
    rng = np.random.default_rng(0)
    stats: dict[str, dict[str, list[float]]] = {p: {"reached": [], "ratio": [], "clear": [], "ms": []} for p in PLANNERS}
    for rel in MAPS:
        cm = inflate(read(root / "ros_maps" / rel))
        queries = _pairs(cm, per_map, rng)
        caches: dict[str, dict] = {p: {} for p in (*PLANNERS, "visibility")}
        for s, g in queries:
            opt = plan("visibility", cm, s, g, cache=caches["visibility"]).length
            for p in PLANNERS:
                plan(p, cm, s, g, cache=caches[p])  # warm the cache (brushfire, inflation, graph)
                t0 = time.perf_counter()
                path = plan(p, cm, s, g, cache=caches[p])
                ms = 1000 * (time.perf_counter() - t0)
                ok = path.status == "reached"
                stats[p]["reached"].append(float(ok))
                stats[p]["ms"].append(ms)
                if ok:
                    stats[p]["ratio"].append(path.length / opt)
                    stats[p]["clear"].append(path.min_clearance)
    for p in PLANNERS:
        st = stats[p]
        def med(v):
            return (statistics.median(v) if v else float("nan"))
        rows.append(f"| `{p}` | {100 * statistics.mean(st['reached']):.0f} % | {med(st['ratio']):.3f} | "
                    f"{med(st['clear']):.3f} | {med(st['ms']):.1f} |")
    head = ("| planner | reached | length / any-angle optimum | min clearance (m) | ms per query |\n"
            "|---|---|---|---|---|")
    return (f"Planners on Nav2 costmaps ({len(MAPS)} ROS maps x {per_map} queries)\n\n" + head + "\n"
            + "\n".join(rows))


def big_table(root: Path, size: int, repeat: int) -> str:
    base = read(root / "ros_maps" / "nav2_planner_benchmark_100by100_10" / "100by100_10.yaml")
    occ = base.occupied
    reps = max(1, size // occ.shape[0])
    occ = np.tile(occ, (reps, reps))
    from gridfield.core.grid import GridMap

    gm = GridMap(Grid(occ.shape, base.grid.resolution, base.grid.origin, "open"), occ)
    t0 = time.perf_counter()
    cm = inflate(gm)
    t_inflate = time.perf_counter() - t0
    free = np.argwhere(cm.cost < 253)
    xs, ys = cm.grid.cell_centers()
    n = occ.shape[0]
    a = free[np.argmin(np.hypot(free[:, 0] - 0.05 * n, free[:, 1] - 0.05 * n))]
    b = free[np.argmin(np.hypot(free[:, 0] - 0.95 * n, free[:, 1] - 0.95 * n))]
    s, g = (float(xs[a[1]]), float(ys[a[0]])), (float(xs[b[1]]), float(ys[b[0]]))
    times: dict[str, list[float]] = {"navfn": [], "wavefront-octile": []}
    status = {}
    for _ in range(repeat):
        for p in times:
            t0 = time.perf_counter()
            path = plan(p, cm, s, g)
            times[p].append(time.perf_counter() - t0)
            status[p] = (path.status, path.length)
    nf, wf = (statistics.median(times[p]) for p in ("navfn", "wavefront-octile"))
    return (f"NavFn at {occ.shape[0]}x{occ.shape[1]} (inflation {t_inflate:.2f} s; query {s} -> {g})\n\n"
            "| planner | status | length | s (median of %d) |\n|---|---|---|---|\n" % repeat
            + "\n".join(f"| `{p}` | {status[p][0]} | {status[p][1]:.2f} | {statistics.median(times[p]):.2f} |"
                        for p in times)
            + f"\n\nnavfn / wavefront-octile = **{nf / wf:.2f}** (target <= 1.5)")


def queries_table(root: Path, n: int, repeat: int) -> str:
    cm = inflate(read(root / "ros_maps" / "nav2_depot" / "depot.yaml"))
    rng = np.random.default_rng(1)
    x0, x1, y0, y1 = cm.grid.extent
    pts = np.stack([rng.uniform(x0, x1, n), rng.uniform(y0, y1, n)], axis=1)
    cm.distance(pts[:4])
    cm.gradient(pts[:4])  # the distance map and the unit gradient are computed once per costmap
    lines = []
    for name in ("cost_at", "distance", "gradient", "nearest_obstacle"):
        f = getattr(cm, name)
        ts, cpu = [], []
        for _ in range(repeat):
            t0, c0 = time.perf_counter(), time.process_time()
            f(pts)
            ts.append(time.perf_counter() - t0)
            cpu.append(time.process_time() - c0)
        lines.append((name, statistics.median(ts) * 1e6 / n, statistics.median(cpu) * 1e6 / n))
    # the reference: one numpy gather of a random cell per point (each bilinear query gathers 4 or 8)
    d = cm._nearest[0].ravel()
    idx = rng.integers(0, d.size, n)
    ts, cpu = [], []
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        np.take(d, idx)
        ts.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    ref = statistics.median(ts) * 1e6 / n
    rows = [f"| `{name}` | {t:.3f} | {c:.3f} | {t / ref:.1f} |" for name, t, c in lines]
    rows.append(f"| reference: `np.take` of one random float64 cell per point | {ref:.3f} | "
                f"{statistics.median(cpu) * 1e6 / n:.3f} | 1.0 |")
    return (f"Costmap queries ({n} points, depot {cm.shape[0]}x{cm.shape[1]}; CPU: process time, which a loaded "
            "machine inflates less than the wall clock)\n\n"
            "| query | s per million points | CPU s per million | ratio to one numpy gather |\n|---|---|---|---|\n"
            + "\n".join(rows))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--maps-root", default=str(TEST_MAPS))
    ap.add_argument("--per-map", type=int, default=8)
    ap.add_argument("--big", type=int, default=4000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--only", choices=("planners", "big", "queries"), default=None)
    a = ap.parse_args()
    root = Path(a.maps_root)
    print(f"load average at start: {os.getloadavg()[0]:.2f} ({os.cpu_count()} CPUs)\n")
    if a.only in (None, "queries"):
        print(queries_table(root, a.points, a.repeat), "\n")
    if a.only in (None, "planners"):
        print(planners_table(root, a.per_map), "\n")
    if a.only in (None, "big"):
        print(big_table(root, a.big, a.repeat))


if __name__ == "__main__":
    main()
