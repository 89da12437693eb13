"""Benchmark: the gradient-descent follower on a 1024 x 1024 field; follow_many on 1000 starts.

Run ``python benchmarks/follow.py`` (options: ``--size``, ``--starts``, ``--repeat``, ``--seed``,
``--escapes N`` to also measure escape success rates over N seeds on the seed 000 segment world).

Prints, as medians of ``--repeat`` runs:

- the grid follower (:func:`gridfield.following.follower.follow`, bilinear sampling, cell-walk blocking):
  steps per second, over 20 starts;
- :func:`gridfield.following.follower.follow_many` on ``--starts`` points at once: point-steps per second;
- the exact planner (:func:`gridfield.exact.continuous.plan_exact_potential`) on seed 000: steps per second;
- ``--descend-only``: the CPU time per step of :func:`gridfield.following.descent.descend` alone (its
  step and stop rules, on an analytic bowl), best of ``--repeat`` runs;
- a reference measured in the same process: a bare Python loop making one call per step to a
  no-op function taking a point, i.e. the floor of any Python-driven step loop; the follower's
  cost per step is reported as a ratio to it.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from gridfield.exact.continuous import plan_exact_potential
from gridfield.fields.potential import build_field
from gridfield.following.follower import follow, follow_many, plan_potential
from gridfield.geometry.rasterize import rasterize
from gridfield.geometry.world import world_from_dict
from gridfield.io import bundled_map, read_world


def circle_world(size: float, n: int, seed: int) -> dict:
    """``n`` random circles (radius 0.5-2 % of the map) on a ``size`` x ``size`` open world."""
    rng = np.random.default_rng(seed)
    obstacles = []
    for c, r in zip(rng.uniform(0.05 * size, 0.95 * size, (n, 2)), rng.uniform(0.005, 0.02, n) * size, strict=True):
        obstacles.append({"circle": {"center": c.tolist(), "radius": float(r)}})
    return {"bounds": [0, 0, size, size], "obstacles": obstacles}


def median_time(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def reference_per_call(n: int = 200_000) -> float:
    """Seconds per iteration of a Python loop calling a no-op on a point tuple."""

    def noop(p: tuple[float, float]) -> tuple[float, float]:
        return p

    x = 0.0
    t0 = time.perf_counter()
    for _ in range(n):
        x += noop((x, 1.0))[1]
    return (time.perf_counter() - t0) / n


def descend_rules(repeat: int, steps: int = 60_000) -> float:
    """Seconds of CPU per step of :func:`gridfield.following.descent.descend` alone: an analytic bowl and a
    pure-Python ``blocked`` that never blocks, so what is timed is the step and stop rules. (Takes
    an older gridfield too, whose ``descend`` returned a tuple: ``--descend-only`` runs this
    alone, for side-by-side runs of two checkouts.)"""
    from gridfield.following.descent import descend

    def force(p: tuple[float, float]) -> tuple[float, float]:
        return 1000.0 - p[0], 0.3 - p[1]

    def never(p: tuple[float, float], q: tuple[float, float]) -> bool:
        return False

    times, n = [], 0
    for _ in range(repeat):
        t0 = time.process_time()
        out = descend(force, (0.0, 0.0), (1000.0, 0.3), step=0.01, tolerance=0.01, max_iterations=steps,
                      blocked=never)
        times.append(time.process_time() - t0)
        n = out.iterations if hasattr(out, "iterations") else out[2]
    return min(times) / n


def escape_rates(n_seeds: int) -> None:
    w = read_world(bundled_map("seed000_segment.yaml"))
    gm = rasterize(w, 0.05)
    field = build_field(gm, w.goal, w.params)
    for planner in ("exact", "grid h=0.05"):
        for escape, tries in (("random_walk", 1), ("random_walk", 10), ("potential_increase", 1),
                              ("potential_increase", 10)):
            seeds = range(n_seeds) if escape == "random_walk" else range(1)  # potential_increase is deterministic
            reached = tried = ok = 0
            for s in seeds:
                params = {**w.params, "escape": escape, "escape_tries": tries, "seed": s}
                if planner == "exact":
                    p = plan_exact_potential(w, w.start, w.goal, params)
                else:
                    p = follow(field, w.start, params=params)
                reached += p.status == "reached"
                tried += p.extra["escapes_tried"]
                ok += p.extra["escapes_succeeded"]
            print(f"  {planner:12s} {escape:18s} tries<={tries:2d}: runs reaching the goal {reached}/{len(seeds)}, "
                  f"escapes succeeded {ok}/{tried}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=1024, help="grid cells per side (resolution 1)")
    ap.add_argument("--starts", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--escapes", type=int, default=0, metavar="N", help="measure escape success over N seeds")
    ap.add_argument("--descend-only", action="store_true",
                    help="only the CPU time per step of descend's rules (best of --repeat runs of 60000 steps)")
    args = ap.parse_args()
    if args.descend_only:
        print(f"descend's rules: {descend_rules(args.repeat) * 1e6:.2f} us/step (CPU, best of {args.repeat})")
        return

    size = float(args.size)
    world = world_from_dict(circle_world(size, 40, args.seed))
    gm = rasterize(world, 1.0)
    goal = (0.9 * size, 0.9 * size)
    while not gm.is_free([goal])[0]:
        goal = (goal[0] - 3.0, goal[1])
    params = {"zeta": 1.0, "d_star": 0.05 * size, "eta": 5000.0, "q_star": 0.03 * size, "step": 0.5,
              "max_iterations": 50_000}
    t0 = time.perf_counter()
    field = build_field(gm, goal, params)
    build = time.perf_counter() - t0
    rng = np.random.default_rng(args.seed)
    cand = rng.uniform(0.02 * size, 0.6 * size, (4 * args.starts, 2))
    starts = cand[gm.is_free(cand)][: args.starts]

    ref = reference_per_call()
    follow(field, starts[0], params=params)  # compile / warm up

    def single() -> tuple[int, float]:
        steps, secs = 0, 0.0
        for s in starts[:20]:
            p = follow(field, s, params=params)
            steps += p.iterations
            secs += p.seconds
        return steps, secs

    runs = [single() for _ in range(args.repeat)]
    per_step = statistics.median(secs / steps for steps, secs in runs)
    steps_single = runs[0][0]

    follow_many(field, starts[:4], params=params)
    t_many, paths = median_time(lambda: follow_many(field, starts, params=params), args.repeat)
    point_steps = sum(p.iterations for p in paths)  # type: ignore[union-attr]
    n_steps_batch = max(p.iterations for p in paths)  # type: ignore[union-attr]
    statuses = {s: sum(p.status == s for p in paths) for s in ("reached", "local_minimum", "collision")}  # type: ignore[union-attr]

    w0 = read_world(bundled_map("seed000.yaml"))
    plan_exact_potential(w0, w0.start, w0.goal, w0.params)
    t_exact, pe = median_time(lambda: plan_exact_potential(w0, w0.start, w0.goal, w0.params), args.repeat)
    gm0 = rasterize(w0, 0.05)
    t_grid0, pg = median_time(lambda: plan_potential(gm0, w0.start, w0.goal, w0.params), args.repeat)

    print(f"field {args.size}x{args.size} ({gm.occupied_fraction:.1%} occupied) built in {build * 1e3:.0f} ms")
    print(f"reference: Python loop with one call per step: {ref * 1e6:.3f} us/step")
    print(f"follow (bilinear, 20 starts, {steps_single} steps): {per_step * 1e6:.2f} us/step = "
          f"{1 / per_step / 1e3:.0f} k steps/s (ratio to reference {per_step / ref:.1f})")
    print(f"follow_many ({len(starts)} starts, {n_steps_batch} batch steps, {point_steps} point-steps, "
          f"{statuses}): {t_many * 1e3:.0f} ms = {point_steps / t_many / 1e6:.2f} M point-steps/s "
          f"({t_many / point_steps * 1e6:.3f} us per point-step, ratio to reference {t_many / point_steps / ref:.2f})")
    print(f"seed 000 exact planner: {pe.iterations} steps in {t_exact * 1e3:.1f} ms = "  # type: ignore[union-attr]
          f"{t_exact / pe.iterations * 1e6:.1f} us/step")  # type: ignore[union-attr]
    print(f"seed 000 grid planner h=0.05 (build + follow): {t_grid0 * 1e3:.1f} ms, follow {pg.seconds * 1e3:.2f} ms "  # type: ignore[union-attr]
          f"for {pg.iterations} steps")  # type: ignore[union-attr]
    if args.escapes:
        print(f"escape success on the seed 000 segment world ({args.escapes} seeds for the random walk):")
        escape_rates(args.escapes)


if __name__ == "__main__":
    main()
