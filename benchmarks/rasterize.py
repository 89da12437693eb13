"""Benchmark: conservative rasterization of ~100 random obstacles onto a 4096 x 4096 grid.

Run ``python benchmarks/rasterize.py`` (options: ``--size``, ``--obstacles``, ``--repeat``,
``--seed``). Prints the median wall time of ``--repeat`` runs (default 5) of
:func:`gridfield.geometry.rasterize.rasterize`, the time of one full-grid reference operation measured in
the same process (``np.zeros`` + one boolean OR over the grid), and their ratio.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from gridfield.geometry.rasterize import rasterize
from gridfield.geometry.world import world_from_dict


def random_world(size: float, n: int, seed: int) -> dict:
    """World data with ``n`` obstacles: one third each random polygons (star-shaped, up to 12
    vertices, up to 6 % of the map across), circles and segments (up to 12 % of the map long)."""
    rng = np.random.default_rng(seed)
    obstacles = []
    for i in range(n):
        c = rng.uniform(0.05 * size, 0.95 * size, 2)
        kind = i % 3
        if kind == 0:
            k = int(rng.integers(3, 13))
            ang = (np.arange(k) + rng.uniform(0.0, 0.8, k)) * (2 * np.pi / k)  # star-shaped: simple
            rad = rng.uniform(0.2, 1.0, k) * rng.uniform(0.005, 0.03) * size
            pts = c + np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=1)
            obstacles.append({"polygon": pts.tolist()})
        elif kind == 1:
            obstacles.append({"circle": {"center": c.tolist(), "radius": float(rng.uniform(0.002, 0.03) * size)}})
        else:
            d = rng.normal(size=2)
            d *= rng.uniform(0.01, 0.12) * size / np.hypot(*d)
            obstacles.append({"segment": [c.tolist(), (c + d).tolist()]})
    return {"bounds": [0, 0, size, size], "obstacles": obstacles}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=4096, help="grid cells per side (resolution 1)")
    ap.add_argument("--obstacles", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()

    world = world_from_dict(random_world(float(args.size), args.obstacles, args.seed))
    rasterize(world, 1.0)  # warm-up
    times = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        m = rasterize(world, 1.0)
        times.append(time.perf_counter() - t0)
    ref = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        a = np.zeros((args.size, args.size), bool)
        a |= m.occupied
        ref.append(time.perf_counter() - t0)
    med, med_ref = statistics.median(times), statistics.median(ref)
    print(f"rasterize {args.size}x{args.size}, {len(world.obstacles)} obstacles "
          f"({m.occupied_fraction:.1%} occupied): median of {args.repeat} = {med * 1e3:.1f} ms "
          f"(reference full-grid op {med_ref * 1e3:.2f} ms, ratio {med / med_ref:.1f})")


if __name__ == "__main__":
    main()
