"""The chunked brushfire (gridfield.chunked) on a local Dask cluster, side by side with the in-memory kernel.

Runs, each printed as a row of one markdown table (and written to ``--out``):

- ``compare N``: the in-memory ``brushfire`` (Euclidean, nearest obstacle, 1 thread) against
  ``gridfield.chunked.distance(..., return_nearest=True)`` on a ``distributed.LocalCluster`` of
  ``--workers`` processes of 1 thread, written to an uncompressed Zarr store with ``dask.array.store``
  (the results stream to disk, never to this process). Throughput is cells per second per core; the
  ratio is chunked-per-core over in-memory-1-thread. The store is read back and compared with
  ``np.array_equal``.
- ``big N``: the chunked computation alone (distance + nearest to Zarr), with a worker memory limit below
  the map's arrays; the table gives the workers' peak RSS (sampled every 20 ms in each worker
  process), the limit, and how many workers were restarted (0 = none exceeded its limit).

The occupancy is generated on the workers chunk by chunk (``dask.array.random``, seeded: the same map
on every run), density ``--density``. Per-chunk cost: the time per task of each phase is printed
from the scheduler's task stream (for the extrapolation in benchmarks/README.md, "Chunked").

Usage::

    python benchmarks/chunked.py --compare 8192 --big 16384 --chunk 1024 --workers 2 --memory-limit 2GiB
    python benchmarks/chunked.py --big 32768 --chunk 2048 --memory-limit 6GiB --store /tmp/big.zarr
"""

from __future__ import annotations

import argparse
import collections
import os
import shutil
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

from _common import markdown_table  # noqa: E402


def _start_sampler(dask_worker=None) -> None:  # runs in each worker process
    import psutil

    proc = psutil.Process()
    state = {"peak": proc.memory_info().rss, "stop": False}

    def loop() -> None:
        while not state["stop"]:
            state["peak"] = max(state["peak"], proc.memory_info().rss)
            time.sleep(0.02)

    old = getattr(dask_worker, "_gf_sampler", None)
    if old is not None:
        old["stop"] = True
    threading.Thread(target=loop, daemon=True).start()
    dask_worker._gf_sampler = state


def _read_sampler(dask_worker=None) -> int:
    state = getattr(dask_worker, "_gf_sampler", None)
    return -1 if state is None else int(state["peak"])


def _warm_up(dask_worker=None) -> None:
    import zarr  # noqa: F401

    import gridfield._kernels_brushfire
    import gridfield._kernels_chunked
    import gridfield.chunked._distance  # noqa: F401


def occupancy(n: int, chunk: int, density: float, seed: int):
    import dask.array as da

    return da.random.default_rng(seed).random((n, n), chunks=chunk) < density


def run_chunked(client, n: int, chunk: int, density: float, store: Path, seed: int = 27, compress: bool = False):
    import dask.array as da
    import zarr
    from distributed import get_task_stream

    from gridfield.chunked import distance

    occ = occupancy(n, chunk, density, seed)
    d, nr, nc = distance(occ, return_nearest=True)
    if store.exists():
        shutil.rmtree(store)
    root = zarr.open_group(str(store), mode="w")
    targets = [root.create_array(name, shape=(n, n), chunks=(chunk, chunk), dtype=a.dtype,
                                  **({} if compress else {"compressors": None}))
               for name, a in (("distance", d), ("nearest_row", nr), ("nearest_col", nc))]
    client.run(_start_sampler)
    t0 = time.perf_counter()
    with get_task_stream(client) as ts:
        da.store([d, nr, nc], targets, lock=False)
    elapsed = time.perf_counter() - t0
    peaks = client.run(_read_sampler)
    return elapsed, peaks, ts.data, root


def per_task_costs(stream) -> dict[str, tuple[int, float]]:
    """Task prefix -> (count, mean seconds of compute) from a task stream."""
    out: dict[str, list[float]] = collections.defaultdict(list)
    for rec in stream:
        for s in rec.get("startstops", []):
            if s["action"] == "compute":
                out[rec["key"][0] if isinstance(rec["key"], tuple) else str(rec["key"])].append(s["stop"] - s["start"])
    return {k.rsplit("-", 1)[0]: (len(v), float(np.mean(v))) for k, v in out.items()}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--compare", type=int, nargs="*", default=[], help="sizes to compare with the in-memory kernel")
    ap.add_argument("--big", type=int, nargs="*", default=[], help="sizes to run chunked only (out of core)")
    ap.add_argument("--chunk", type=int, default=1024)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--memory-limit", default="2GiB")
    ap.add_argument("--density", type=float, default=0.001)
    ap.add_argument("--store", type=Path, default=None, help="Zarr store path (default: a temporary folder)")
    ap.add_argument("--compress", action="store_true", help="zarr's default compressor for the --big runs")
    ap.add_argument("--out", type=Path, default=None, help="also write the table to this markdown file")
    args = ap.parse_args(argv)

    from distributed import Client, LocalCluster

    from gridfield.brushfire import brushfire
    from gridfield.grid import Grid, GridMap

    tmp = Path(tempfile.mkdtemp(prefix="gf-chunked-"))
    store = args.store or tmp / "out.zarr"
    rows = []
    streams: list = []
    load = os.getloadavg()
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, host="127.0.0.1", dashboard_address=None,
                      memory_limit=args.memory_limit, local_directory=str(tmp)) as cluster, Client(cluster) as client:
        client.run(_warm_up)
        run_chunked(client, 4 * args.chunk, args.chunk, args.density, store)  # warm-up (untimed)
        for n in args.compare:
            occ_np = occupancy(n, args.chunk, args.density, 27).compute()
            gm = GridMap(Grid((n, n), 1.0, border="wall"), occ_np)
            t0 = time.perf_counter()
            ref = brushfire(gm, metric="euclidean", threads=1, compute_labels=False, compute_steps=False)
            t_mem = time.perf_counter() - t0
            t_chk, peaks, stream, root = run_chunked(client, n, args.chunk, args.density, store)
            streams += stream
            equal = (np.array_equal(root["distance"][...], ref.distance)
                     and np.array_equal(root["nearest_row"][...], ref.nearest_row)
                     and np.array_equal(root["nearest_col"][...], ref.nearest_col))
            del ref, occ_np, gm
            per_core_mem = n * n / t_mem
            per_core_chk = n * n / t_chk / args.workers
            rows.append([f"compare {n}", args.chunk, f"{t_mem:.2f}", f"{t_chk:.2f}",
                         f"{per_core_chk / per_core_mem:.2f}", f"{max(peaks.values()) / 2**20:.0f}",
                         f"{args.chunk ** 2 * 16 / 2**20:.0f}", "yes" if equal else "NO"])
            print(rows[-1], flush=True)
        for n in args.big:
            workers_before = set(client.scheduler_info()["workers"])
            t_chk, peaks, stream, _ = run_chunked(client, n, args.chunk, args.density, store, compress=args.compress)
            streams += stream
            workers_after = set(client.scheduler_info()["workers"])
            restarted = len(workers_before - workers_after)
            rows.append([f"big {n}", args.chunk, "-", f"{t_chk:.2f}", "-", f"{max(peaks.values()) / 2**20:.0f}",
                         f"{args.chunk ** 2 * 16 / 2**20:.0f}", f"restarted workers: {restarted}"])
            print(rows[-1], flush=True)
        costs = per_task_costs(streams)
    shutil.rmtree(tmp, ignore_errors=True)
    table = markdown_table(["run", "chunk", "in-memory 1 thread s", f"chunked {args.workers}x1 s",
                            "per-core ratio", "peak worker RSS MiB", "one chunk's outputs MiB", "equal / note"], rows)
    head = (f"workers {args.workers} x 1 thread, memory limit {args.memory_limit}, density {args.density}, "
            f"load average before {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}, after "
            f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    cost_table = markdown_table(["task", "count", "mean s"], [[k, c, f"{m:.4f}"] for k, (c, m) in sorted(costs.items())])
    text = f"{head}\n\n{table}\n\nPer task (all runs):\n\n{cost_table}\n"
    print(text)
    if args.out:
        args.out.write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
