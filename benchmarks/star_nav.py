"""Benchmark: star-nav on random spiky star worlds (reach rate, not speed).

Run ``python benchmarks/star_nav.py`` (options: ``--worlds``, ``--starts``, ``--obstacles``,
``--lambdas``, ``--seed``, ``--mode``). Prints markdown tables.

The worlds are drawn here, independently of the tests: in the disc workspace of ``[0, 20]^2``,
``--obstacles`` (2-4) disjoint polygons star-shaped about a given centre, each with 6-24 vertices at
jittered angles and radii drawn from [0.25, 2.6] (spiky: neighbouring radii differ by up to 10x,
so the kernels are thin and many vertices are reflex), at least 0.4 apart and 0.4 inside the
workspace circle; a random free goal and ``--starts`` random free starts (0.05 from every boundary).

``--mode planner`` (default) runs the planner as a user does (``plan("star-nav", ...)``: kappa chosen
from the ladder, the planner's own retries) and counts the final status of each start;
``--mode lambda`` runs the batch follower with the kappa the planner would choose, for each lambda
of ``--lambdas``, and counts reached starts and worlds whose sampled Jacobian folds.
Statuses: ``reached``, ``local_minimum`` (stalled), ``collision`` (never expected: the follower
checks every segment exactly), ``max_iterations``; ``error`` = the planner raised.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings
from collections import Counter
from typing import Any

import numpy as np
from shapely.geometry import Point, Polygon

from gridfield.fields import navigation as star  # the star-world names (gridfield.star is a deprecated alias)
from gridfield.geometry.world import world_from_dict
from gridfield.planners import plan

C0, R0 = np.array([10.0, 10.0]), 10.0


def spiky_polygon(rng: np.random.Generator, center: np.ndarray) -> np.ndarray:
    n = int(rng.integers(6, 25))
    ang = (np.arange(n) + rng.uniform(0.15, 0.85, n)) * 2 * np.pi / n
    rad = rng.uniform(0.25, 2.6, n)
    return center + np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])


def spiky_world(seed: int, m: int) -> tuple[Any, list[Polygon], np.random.Generator]:
    rng = np.random.default_rng(seed)
    entries: list[dict[str, Any]] = []
    shapes: list[Polygon] = []
    while len(shapes) < m:
        c = C0 + rng.uniform(-6.5, 6.5, 2)
        v = spiky_polygon(rng, c)
        poly = Polygon(v)
        if (np.hypot(*(v - C0).T).max() > R0 - 0.4 or not poly.is_valid
                or any(poly.distance(s) < 0.4 for s in shapes)):
            continue
        shapes.append(poly)
        entries.append({"polygon": {"vertices": v.tolist(), "center": c.tolist()}})
    w = world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": entries})
    return w, shapes, rng


def free_points(rng: np.random.Generator, shapes: list[Polygon], k: int, margin: float) -> np.ndarray:
    out: list[np.ndarray] = []
    while len(out) < k:
        p = C0 + rng.uniform(-R0, R0, 2)
        if math.dist(p, C0) < R0 - margin and all(s.distance(Point(p)) > margin for s in shapes):
            out.append(p)
    return np.array(out)


def run_planner(worlds: int, starts: int, obstacles: tuple[int, ...], seed: int, verbose: bool = False) -> None:
    counts: Counter[str] = Counter()
    worlds_all = 0
    t0 = time.perf_counter()
    per_world_fail = 0
    for wi in range(worlds):
        m = obstacles[wi % len(obstacles)]
        w, shapes, rng = spiky_world(seed + wi, m)
        goal = free_points(rng, shapes, 1, 0.3)[0]
        pts = free_points(rng, shapes, starts, 0.05)
        failed = False
        for s in pts:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    p = plan("star-nav", w, s, goal)
                    status = p.status
                except Exception as e:  # counted and reported
                    status = f"error: {type(e).__name__}"
            counts[status] += 1
            failed |= status != "reached"
            if status != "reached" and verbose:
                print(f"  world seed {seed + wi} ({m} obstacles), start {np.round(s, 3).tolist()}, goal "
                      f"{np.round(goal, 3).tolist()}: {status}"
                      + (f", kappa tried {p.extra['followed']}" if status[:5] != "error" else ""), flush=True)
        per_world_fail += failed
        worlds_all += 1
    dt = time.perf_counter() - t0
    total = sum(counts.values())
    print(f"\n#### planner: {worlds_all} worlds x {starts} starts ({total} plans), obstacles {obstacles}, "
          f"seeds {seed}..{seed + worlds - 1}; {dt:.0f} s")
    print("| status | starts | share |\n|---|---|---|")
    for k, v in counts.most_common():
        print(f"| {k} | {v} | {100 * v / total:.1f} % |")
    print(f"| worlds with a start not reached | {per_world_fail} of {worlds_all} | |")


def run_lambda(worlds: int, starts: int, obstacles: tuple[int, ...], seed: int, lambdas: list[float]) -> None:
    rows = []
    cases = []
    for wi in range(worlds):
        m = obstacles[wi % len(obstacles)]
        w, shapes, rng = spiky_world(seed + wi, m)
        goal = free_points(rng, shapes, 1, 0.3)[0]
        cases.append((star.star_world(w, goal), free_points(rng, shapes, starts, 0.05)))
    for lam in lambdas:
        t0 = time.perf_counter()
        reached = folded = worlds_ok = 0
        kappas: Counter[float] = Counter()
        for sw, pts in cases:
            folded += len(star.folds(sw, lam=lam)) > 0
            kappa, _ = star.choose_kappa(sw, None, lam)
            kappas[kappa] += 1
            step = sw.workspace_radius / 200
            res = star.follow_star_nav(sw, pts, kappa=kappa, lam=lam, step=step, tolerance=step,
                                       max_iterations=50 * int(2 * sw.workspace_radius / step) + 1000)
            r = sum(s == "reached" for _, s, _ in res)
            reached += r
            worlds_ok += r == len(pts)
        rows.append((lam, reached, worlds_ok, folded, dict(sorted(kappas.items())), time.perf_counter() - t0))
    n = worlds * starts
    print(f"\n#### lambda: {worlds} worlds x {starts} starts, obstacles {obstacles}, seeds {seed}..{seed + worlds - 1}"
          " (batch follower, kappa as the planner chooses it)")
    print("| lambda | starts reached | worlds all reached | worlds with folds | kappa chosen (kappa: worlds) | s |")
    print("|---|---|---|---|---|---|")
    for lam, r, wok, f, ks, dt in rows:
        print(f"| {lam:g} | {r} / {n} ({100 * r / n:.1f} %) | {wok} / {worlds} | {f} | "
              f"{', '.join(f'{k:g}: {v}' for k, v in ks.items())} | {dt:.0f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--worlds", type=int, default=30)
    ap.add_argument("--starts", type=int, default=20)
    ap.add_argument("--obstacles", type=int, nargs="+", default=[2, 3, 4])
    ap.add_argument("--seed", type=int, default=1000)
    ap.add_argument("--mode", choices=("planner", "lambda"), default="planner")
    ap.add_argument("--verbose", action="store_true", help="print each start not reached")
    ap.add_argument("--lambdas", type=float, nargs="+", default=[1, 3, 10, 30, 100, 300, 1000])
    a = ap.parse_args()
    if a.mode == "planner":
        run_planner(a.worlds, a.starts, tuple(a.obstacles), a.seed, a.verbose)
    else:
        run_lambda(a.worlds, a.starts, tuple(a.obstacles), a.seed, a.lambdas)


if __name__ == "__main__":
    main()
