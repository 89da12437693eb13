"""The chunked brushfire (gridfield.chunked) on a local Dask cluster, side by side with the in-memory kernel.

Runs, each printed as a row of one markdown table (and written to ``--out``):

- ``compare N``: the in-memory ``brushfire`` (Euclidean, nearest obstacle, 1 thread) against
  ``gridfield.chunked.distance(..., return_nearest=True)`` on a ``distributed.LocalCluster`` of
  ``--workers`` processes of 1 thread, written to an uncompressed Zarr store with ``dask.array.store``
  (the results stream to disk, never to this process). Throughput is cells per second per core; the
  ratio is chunked-per-core over in-memory-1-thread. Beside the wall times, the CPU seconds of the
  in-memory call and of the workers (psutil, summed over the worker processes), whose ratio depends less
  on what else runs on the machine. The store is read back and compared with ``np.array_equal``.
- ``big N``: the chunked computation alone (distance + nearest to Zarr), with a worker memory limit below
  the map's arrays; the table gives the workers' peak RSS (sampled every 20 ms in each worker
  process), the limit, and how many workers were restarted (0 = none exceeded its limit).

The passes meet (``--passes``) through a temporary store next to the output store (``distance(...,
scratch=)`` inside ``chunked.scratch_dir``: the default) or by dask's task rechunk in worker memory
(``rechunk``: ``distance()`` without ``scratch``, the code before the store). The occupancy is
generated on the workers chunk by chunk (``dask.array.random``, seeded: the same map on every run),
density ``--density``, inside the timed run; ``--input zarr`` writes it to a Zarr store first (untimed)
and the run reads it from there, as the CLI reads a map from disk. ``--sink discard`` drops the results
instead of writing them (the in-memory side writes nothing either). Per-chunk cost: the time per task of
each phase is printed from the scheduler's task stream (for the extrapolation in benchmarks/README.md,
"Chunked"), with each task's peak RSS increment over the worker's RSS when it started (a worker plugin
sampling every 5 ms while a task runs; 1 thread per worker, so one task at a time); the table gives the
largest.

- ``--s3``: each ``big N`` twice, first with the output store and the passes' temporary store on local
  disk, then both on S3 (``s3://bench/out.zarr`` and ``s3://bench/out.zarr.scratch``; moto's S3 server on
  127.0.0.1 started here, the workers given its address through the usual AWS variables): the rows'
  note gives the S3/local time ratio, and the per-task memory columns compare the two.

Usage::

    python benchmarks/chunked.py --compare 8192 --big 16384 --chunk 1024 --workers 2 --memory-limit 2GiB
    python benchmarks/chunked.py --big 16384 --chunk 1024 --memory-limit 3GiB --s3
    python benchmarks/chunked.py --big 32768 --chunk 2048 --memory-limit 6GiB --store /tmp/big.zarr
"""

from __future__ import annotations

import argparse
import collections
import contextlib
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


from distributed.diagnostics.plugin import WorkerPlugin  # noqa: E402


class TaskMemory(WorkerPlugin):
    """A worker plugin: each task's peak RSS increment over the RSS when it started (1 thread per worker:
    one task at a time), sampled every 5 ms while a task runs (the sampler waits while none does: ~1 %
    of a core), and the worker's RSS before the run."""

    name = "gf-task-memory"

    def setup(self, worker) -> None:
        self.page = os.sysconf("SC_PAGE_SIZE")
        self.fd = os.open("/proc/self/statm", os.O_RDONLY)
        self.base = self.peak = self.idle = self._rss()
        self.running = threading.Event()
        self.records: list[tuple[str, int]] = []
        self.stop = False
        threading.Thread(target=self._loop, daemon=True).start()

    def _rss(self) -> int:
        return int(os.pread(self.fd, 128, 0).split()[1]) * self.page

    def _loop(self) -> None:
        while not self.stop:
            self.running.wait(1.0)
            if self.running.is_set():
                self.peak = max(self.peak, self._rss())
                time.sleep(0.005)

    def transition(self, key, start, finish, **kwargs) -> None:
        if finish == "executing":
            self.base = self.peak = self._rss()
            self.running.set()
        elif start == "executing":
            self.running.clear()
            self.peak = max(self.peak, self._rss())
            name = key[0] if isinstance(key, tuple) else str(key)
            self.records.append((name, self.peak - self.base))

    def teardown(self, worker) -> None:
        self.stop = True


def _task_memory(dask_worker=None, reset: bool = False):
    plugin = dask_worker.plugins.get(TaskMemory.name)
    if plugin is None:
        return [], -1
    out = list(plugin.records)
    if reset:
        plugin.records.clear()
        plugin.idle = plugin._rss()
    return out, plugin.idle


def _cpu_seconds(dask_worker=None) -> float:
    import psutil

    t = psutil.Process().cpu_times()
    return t.user + t.system


def _read_sampler(dask_worker=None) -> int:
    state = getattr(dask_worker, "_gf_sampler", None)
    return -1 if state is None else int(state["peak"])


def _warm_up(dask_worker=None) -> None:
    import zarr  # noqa: F401



class Discard:
    """A ``dask.array.store`` target that drops what it is given (``--sink discard``: the computation
    without the output store's writes)."""

    def __init__(self, shape, dtype) -> None:
        self.shape, self.dtype, self.ndim = shape, np.dtype(dtype), len(shape)

    def __setitem__(self, key, value) -> None:
        pass


def occupancy(n: int, chunk: int, density: float, seed: int, source: Path | None = None):
    """The seeded random map, generated lazily, or read from the Zarr array ``source`` (written if missing)."""
    import dask.array as da

    occ = da.random.default_rng(seed).random((n, n), chunks=chunk) < density
    if source is None:
        return occ
    if not source.exists():
        occ.to_zarr(str(source))
    return da.from_zarr(str(source))


def _s3_server():
    """moto's S3 server on 127.0.0.1 (a free port), named to this process and the workers it starts by the
    usual AWS variables, with the bucket ``bench``."""
    import logging

    from moto.server import ThreadedMotoServer

    logging.getLogger("werkzeug").setLevel(logging.ERROR)
    server = ThreadedMotoServer(ip_address="127.0.0.1", port=0, verbose=False)
    server.start()
    host, port = server.get_host_and_port()
    os.environ.update(AWS_ACCESS_KEY_ID="bench", AWS_SECRET_ACCESS_KEY="bench", AWS_DEFAULT_REGION="us-east-1",
                      AWS_ENDPOINT_URL=f"http://{host}:{port}", AWS_EC2_METADATA_DISABLED="true")
    import s3fs

    s3fs.S3FileSystem().mkdir("bench")
    return server


def run_chunked(client, n: int, chunk: int, density: float, store: Path, seed: int = 27, compress: bool = False,
                passes: str = "store", source: Path | None = None, sink: str = "zarr"):
    import dask.array as da
    import zarr
    from distributed import get_task_stream

    from gridfield import chunked

    occ = occupancy(n, chunk, density, seed, source)
    if isinstance(store, str):  # a URL (--s3)
        import fsspec

        fs = fsspec.core.url_to_fs(store)[0]
        for old in (store, store + ".scratch"):
            if fs.exists(old):
                fs.rm(old, recursive=True)
    elif store.exists():
        shutil.rmtree(store)
    root = zarr.open_group(str(store), mode="w")
    names = ("distance", "nearest_row", "nearest_col")
    targets = [root.create_array(name, shape=(n, n), chunks=(chunk, chunk), dtype=dtype,
                                  **({} if compress else {"compressors": None})) if sink == "zarr"
               else Discard((n, n), dtype)
               for name, dtype in zip(names, ("float64", "int32", "int32"), strict=True)]
    client.run(_start_sampler)
    client.run(_task_memory, reset=True)
    where = f"{store}.scratch" if isinstance(store, str) else store.with_name(store.name + ".scratch")
    scratch = chunked.scratch_dir(where) if passes == "store" else contextlib.nullcontext(None)
    cpu0 = sum(client.run(_cpu_seconds).values())
    t0 = time.perf_counter()  # the graph is built inside: building the store's graph makes its directory
    with scratch as s, get_task_stream(client) as ts:
        d, nr, nc = chunked.distance(occ, return_nearest=True, **({} if s is None else {"scratch": s}))
        da.store([d, nr, nc], targets, lock=False)
    elapsed = time.perf_counter() - t0
    cpu = sum(client.run(_cpu_seconds).values()) - cpu0
    peaks = client.run(_read_sampler)
    return elapsed, peaks, ts.data, root, cpu


def per_task_costs(stream) -> dict[str, tuple[int, float]]:
    """Task prefix -> (count, mean seconds of compute) from a task stream."""
    out: dict[str, list[float]] = collections.defaultdict(list)
    for rec in stream:
        for s in rec.get("startstops", []):
            if s["action"] == "compute":
                out[rec["key"][0] if isinstance(rec["key"], tuple) else str(rec["key"])].append(s["stop"] - s["start"])
    return {k.rsplit("-", 1)[0]: (len(v), float(np.mean(v))) for k, v in out.items()}


def _collect(client, task_mem: list, idle: list[int]) -> int:
    """Append the workers' per-task RSS increments of the last run and their RSS before it; the largest."""
    got = client.run(_task_memory, reset=True)
    recs = [r for out, _ in got.values() for r in out]
    task_mem += recs
    idle += [b for _, b in got.values()]
    return max((v for _, v in recs), default=0)


def task_increments(records) -> dict[str, int]:
    """Task prefix -> the largest peak RSS increment of its tasks (the prefixes of :func:`per_task_costs`)."""
    out: dict[str, int] = {}
    for name, v in records:
        k = name.rsplit("-", 1)[0]
        out[k] = max(out.get(k, 0), v)
    return out


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
    ap.add_argument("--passes", choices=("store", "rechunk"), default="store",
                    help="how the column and row passes meet: a temporary Zarr store next to --store (default), or "
                         "dask's task rechunk in worker memory (distance() without scratch=)")
    ap.add_argument("--input", choices=("random", "zarr"), default="random",
                    help="generate the occupancy inside the timed run (default), or read it from a Zarr store "
                         "written before (untimed)")
    ap.add_argument("--sink", choices=("zarr", "discard"), default="zarr",
                    help="write the results to the Zarr store (default) or drop them (the computation alone; "
                         "no equality check)")
    ap.add_argument("--out", type=Path, default=None, help="also write the table to this markdown file")
    ap.add_argument("--s3", action="store_true",
                    help="run each --big size on local disk, then with the stores on S3 (moto's server on 127.0.0.1)")
    args = ap.parse_args(argv)
    server = _s3_server() if args.s3 else None

    from distributed import Client, LocalCluster

    from gridfield.core.grid import Grid, GridMap
    from gridfield.distance.brushfire import brushfire

    tmp = Path(tempfile.mkdtemp(prefix="gf-chunked-"))
    store = args.store or tmp / "out.zarr"
    rows = []
    streams: list = []
    load = os.getloadavg()
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, host="127.0.0.1", dashboard_address=":0",
                      memory_limit=args.memory_limit, local_directory=str(tmp)) as cluster, Client(cluster) as client:
        client.run(_warm_up)
        client.register_plugin(TaskMemory())
        run_chunked(client, 4 * args.chunk, args.chunk, args.density, store, passes=args.passes)  # warm-up (untimed)
        if args.s3:  # and on S3: the workers' first s3fs session is not a task's memory
            run_chunked(client, 4 * args.chunk, args.chunk, args.density, "s3://bench/out.zarr", passes=args.passes)
        task_mem: list = []
        idle: list[int] = []
        for n in args.compare:
            source = tmp / f"occ{n}.zarr" if args.input == "zarr" else None
            occ_np = occupancy(n, args.chunk, args.density, 27, source).compute()
            gm = GridMap(Grid((n, n), 1.0, border="wall"), occ_np)
            t0, c0 = time.perf_counter(), time.process_time()
            ref = brushfire(gm, metric="euclidean", threads=1, compute_labels=False, compute_steps=False)
            t_mem, cpu_mem = time.perf_counter() - t0, time.process_time() - c0
            t_chk, peaks, stream, root, cpu = run_chunked(client, n, args.chunk, args.density, store, passes=args.passes,
                                                          source=source, sink=args.sink)
            streams += stream
            inc = _collect(client, task_mem, idle)
            equal = args.sink == "zarr" and (np.array_equal(root["distance"][...], ref.distance)
                     and np.array_equal(root["nearest_row"][...], ref.nearest_row)
                     and np.array_equal(root["nearest_col"][...], ref.nearest_col))
            del ref, occ_np, gm
            per_core_mem = n * n / t_mem
            per_core_chk = n * n / t_chk / args.workers
            rows.append([f"compare {n}", args.chunk, f"{t_mem:.2f}", f"{t_chk:.2f}",
                         f"{per_core_chk / per_core_mem:.2f}", f"{cpu_mem:.2f}", f"{cpu:.2f}", f"{cpu_mem / cpu:.2f}", f"{max(peaks.values()) / 2**20:.0f}",
                         f"{max(idle) / 2**20:.0f}", f"{inc / 2**20:.1f}",
                         f"{args.chunk ** 2 * 16 / 2**20:.0f}",
                         ("yes" if equal else "NO") if args.sink == "zarr" else "(discarded)"])
            print(rows[-1], flush=True)
        for n in args.big:
            local_s = None
            for place in (store, "s3://bench/out.zarr") if args.s3 else (store,):
                workers_before = set(client.scheduler_info()["workers"])
                t_chk, peaks, stream, _, cpu = run_chunked(client, n, args.chunk, args.density, place,
                                                           compress=args.compress, passes=args.passes)
                streams += stream
                inc = _collect(client, task_mem, idle)
                workers_after = set(client.scheduler_info()["workers"])
                restarted = len(workers_before - workers_after)
                remote = isinstance(place, str)
                note = f"restarted workers: {restarted}"
                if remote and local_s:
                    note += f"; S3 / local {t_chk / local_s:.2f}x"
                local_s = local_s or t_chk
                label = f"big {n}" + ((" S3" if remote else " local disk") if args.s3 else "")
                rows.append([label, args.chunk, "-", f"{t_chk:.2f}", "-", "-", f"{cpu:.2f}", "-",
                             f"{max(peaks.values()) / 2**20:.0f}", f"{max(idle) / 2**20:.0f}", f"{inc / 2**20:.1f}",
                             f"{args.chunk ** 2 * 16 / 2**20:.0f}", note])
                print(rows[-1], flush=True)
        costs = per_task_costs(streams)
    shutil.rmtree(tmp, ignore_errors=True)
    if server is not None:
        server.stop()
    table = markdown_table(["run", "chunk", "in-memory 1 thread s", f"chunked {args.workers}x1 s",
                            "per-core ratio", "in-memory CPU s", "workers' CPU s", "CPU ratio", "peak worker RSS MiB", "worker RSS before MiB",
                            "max task RSS increment MiB", "one chunk's outputs MiB", "equal / note"], rows)
    head = (f"workers {args.workers} x 1 thread, memory limit {args.memory_limit}, density {args.density}, "
            f"passes meet by {args.passes}, input {args.input}, sink {args.sink}, "
            f"load average before {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}, after "
            f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    mem = task_increments(task_mem)
    cost_table = markdown_table(["task", "count", "mean s", "max RSS increment MiB"],
                                [[k, c, f"{m:.4f}", f"{mem.get(k, float('nan')) / 2**20:.1f}"]
                                 for k, (c, m) in sorted(costs.items())])
    text = f"{head}\n\n{table}\n\nPer task (all runs):\n\n{cost_table}\n"
    print(text)
    if args.out:
        args.out.write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
