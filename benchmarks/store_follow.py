"""The follower on a Zarr field store (issue 27) against the same field in memory: time, chunks read, agreement.

A khatib field is built in memory on an N x N map with a few walls, written to a store with chunks of C
cells, read back lazily, and followed from the same starts both ways. Printed: the following time of
each (side by side in one process), the chunk tiles the store's cache decoded out of all the chunks of
the arrays, and whether the paths are identical.

    PYTHONPATH=. python benchmarks/store_follow.py --size 2048 --chunks 256 --starts 4
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=2048)
    ap.add_argument("--chunks", type=int, default=256)
    ap.add_argument("--starts", type=int, default=4)
    args = ap.parse_args(argv)

    from gridfield.core.grid import Grid, GridMap
    from gridfield.fields.potential import build_field
    from gridfield.following.follower import follow
    from gridfield.io import read, write_store

    n, c = args.size, args.chunks
    occ = np.zeros((n, n), bool)
    occ[n // 4:n // 4 + n // 64, n // 8:n // 2] = True
    occ[n // 2:3 * n // 4, 5 * n // 8:5 * n // 8 + n // 64] = True
    gm = GridMap(Grid((n, n), 1.0), occ)
    goal = (0.9 * n, 0.9 * n)
    f = build_field(gm, goal, {"model": "khatib"})
    arrays = {"occupied": occ, "U": f.potential, "dUdx": f.grad_x, "dUdy": f.grad_y, "distance": f.distance.distance}
    with tempfile.TemporaryDirectory() as d:
        t0 = time.perf_counter()
        p = write_store(os.path.join(d, "f.zarr"), arrays, gm.grid, kind="field", chunks=c, scheduler="threads",
                        attrs={"goal": goal, "params": f.params, "metric": f.distance.metric})
        t_write = time.perf_counter() - t0
        rng = np.random.default_rng(0)
        starts = rng.uniform(0.02 * n, 0.3 * n, size=(args.starts, 2))
        per_array = (-(-n // c)) ** 2
        print("| map | chunks | start | status | points | memory s | store s | ratio | tiles read | of | same path |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for s in starts:
            lf = read(p)
            t0 = time.perf_counter()
            a = follow(f, s)
            t1 = time.perf_counter()
            b = follow(lf, s)
            t2 = time.perf_counter()
            reads = lf.map.occupied.cache.reads
            same = a.status == b.status and np.array_equal(a.points, b.points)
            print(f"| {n}^2 | {c} | ({s[0]:.0f}, {s[1]:.0f}) | {b.status} | {len(b.points)} | {t1 - t0:.3f} | "
                  f"{t2 - t1:.3f} | {(t2 - t1) / max(t1 - t0, 1e-9):.1f} | {reads} | {len(arrays) * per_array} | {same} |")
        print(f"\nwrite_store: {t_write:.2f} s for {len(arrays)} arrays of {per_array} chunks")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
