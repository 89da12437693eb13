"""Benchmark: building the attractive + repulsive potential and its gradient arrays.

Run ``python benchmarks/potential.py`` (options: ``--sizes``, ``--repeat``, ``--blocks``,
``--threads``, ``--seed``). For each size, a square grid (resolution 1) with random rectangular
obstacles, its Euclidean brushfire computed once (not timed), then, round-robin for ``--repeat``
rounds (medians reported, because one run is noise on the shared 2-core machine):

- ``build_field`` with ``repulsion="nearest"`` (one fused numba pass; fresh output arrays),
- the fused kernel alone, writing into preallocated arrays,
- ``build_field`` with ``repulsion="sum"`` and ``repulsive_power=3`` (seed 000's model),
- the same potential written as plain numpy expressions (temporaries), as a contrast,
- the reference: streaming the three float64 output arrays once (``np.copyto`` into preallocated
  arrays), and a fresh copy of them (allocation and first touch included).

Ratios are to the ``np.copyto`` reference measured in the same process.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from collections.abc import Callable

import numpy as np

from gridfield.core.grid import Grid, GridMap
from gridfield.distance.brushfire import brushfire
from gridfield.fields import _potential as _kp
from gridfield.fields._potential import _khatib_kernel
from gridfield.fields.potential import _threads_for, build_field


def blocks(n: int, count: int, seed: int) -> GridMap:
    rng = np.random.default_rng(seed)
    occ = np.zeros((n, n), bool)
    for _ in range(count):
        h, w = rng.integers(n // 100 + 1, n // 20 + 2, 2)
        r, c = rng.integers(0, n - h), rng.integers(0, n - w)
        occ[r:r + h, c:c + w] = True
    return GridMap(Grid((n, n), 1.0), occ)


def numpy_version(gm: GridMap, d, goal, zeta, eta, q):
    """The nearest-mode potential (p = 2, quadratic attraction) as plain numpy expressions."""
    rows, cols = gm.shape
    r, c = np.indices((rows, cols))
    x, y = c + 0.5, r + 0.5
    dx, dy = x - goal[0], y - goal[1]
    vr, vc = (r - d.nearest_row).astype(float), (c - d.nearest_col).astype(float)
    dist = np.hypot(vr, vc)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(dist < q, 1 / dist - 1 / q, 0.0)
        m = eta * s / dist**3
        U = 0.5 * zeta * (dx**2 + dy**2) + 0.5 * eta * s**2
        gx = zeta * dx - m * vc
        gy = zeta * dy - m * vr
    U[gm.occupied] = np.inf
    gx[gm.occupied] = 0.0
    gy[gm.occupied] = 0.0
    return U, gx, gy


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1024, 4096])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--blocks", type=int, default=60, help="random rectangular obstacles")
    ap.add_argument("--threads", type=int, default=None, help="numba threads (default: numba's)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    if args.threads:
        _kp.set_num_threads(args.threads)
    print(f"kernel threads: {_kp.get_num_threads()}, median of {args.repeat} rounds")
    print("| grid | what | median ms | ratio to np.copyto |")
    print("|---|---|---|---|")
    for n in args.sizes:
        for what, ms, ratio in bench_size(n, args.blocks, args.seed, args.repeat):
            print(f"| {n}^2 | {what} | {ms:.1f} | {ratio:.2f} |")


def bench_size(n: int, count: int, seed: int, repeat: int) -> list[tuple[str, float, float]]:
    gm = blocks(n, count, seed)
    d = brushfire(gm, metric="euclidean")
    free = np.argwhere(~gm.occupied)
    goal = tuple(float(v) + 0.5 for v in free[len(free) // 2][::-1])
    q = n / 40
    p_near = {"zeta": 1.0, "d_star": math.inf, "eta": 1.0, "q_star": q}
    p_sum = {**p_near, "repulsion": "sum", "repulsive_power": 3}
    f = build_field(gm, goal, p_near, dmap=d)  # warm-up (compiles or loads the kernels)
    build_field(gm, goal, p_sum, dmap=d)
    ref = numpy_version(gm, d, goal, 1.0, 1.0, q)
    arrays = (f.potential, f.grad_x, f.grad_y)
    for a, b in zip(ref, arrays, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-12)
    U, GX, GY = (np.empty((n, n)) for _ in range(3))
    out = [np.empty((n, n)) for _ in range(3)]

    def kernel() -> None:
        with _threads_for(n * n):  # as build_field runs it
            _khatib_kernel(gm.occupied, d.nearest_row, d.nearest_col, 0.0, 0.0, 1.0, goal[0], goal[1], 1.0,
                           math.inf, False, 0, 1.0, q, 2, math.inf, math.inf, U, GX, GY)

    reference = "np.copyto of the 3 output arrays (reference)"
    cases: dict[str, Callable[[], object]] = {
        reference: lambda: [np.copyto(o, a) for o, a in zip(out, arrays, strict=True)],
        "fresh copy of the 3 output arrays": lambda: [a.copy() for a in arrays],
        "build_field, nearest, p=2": lambda: build_field(gm, goal, p_near, dmap=d),
        "fused kernel alone, preallocated outputs": kernel,
        f"build_field, sum over {count} obstacles, p=3": lambda: build_field(gm, goal, p_sum, dmap=d),
        "plain numpy expressions (temporaries)": lambda: numpy_version(gm, d, goal, 1.0, 1.0, q),
    }
    times: dict[str, list[float]] = {k: [] for k in cases}
    for _ in range(repeat):
        for k, fn in cases.items():
            t0 = time.perf_counter()
            fn()
            times[k].append(time.perf_counter() - t0)
    med = {k: statistics.median(v) for k, v in times.items()}
    return [(k, v * 1e3, v / med[reference]) for k, v in med.items()]


if __name__ == "__main__":
    main()
