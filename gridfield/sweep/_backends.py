"""Where the runs execute: a local process pool or a Dask cluster, and :func:`run_sweep` that drives them.

Runs are grouped by map into batches (one task each) so that a worker loads each map once. The
local pool uses ``spawn`` (the potential kernels' OpenMP thread pool does not survive ``fork``) and
is replaced when a worker dies; on Dask the submitter reads each map once and scatters it, so
workers need not share its filesystem. :func:`run_sweep` writes every row to the journal as it
arrives and turns SIGINT/SIGTERM into :class:`SweepInterrupted` with the rows file resumable.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Iterator, Sequence
from pathlib import Path as FsPath
from typing import Any

from ..core.errors import GridfieldError, ParameterError, shorten
from ._journal import _Journal
from ._run import Run, _one_line, _with_robot, run_batch

#: How often a local pool whose worker died is replaced before the sweep gives up.
POOL_RESTARTS = 3

#: Seconds to wait for a Dask scheduler to answer.
SCHEDULER_TIMEOUT = 10

#: Seconds a Dask cluster may have no worker at all (all dead, none restarted) before the sweep ends.
NO_WORKER_TIMEOUT = 120.0


class SweepInterrupted(KeyboardInterrupt):
    """The sweep was stopped by a signal (SIGINT or SIGTERM); the rows written so far are kept."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


def _batches(runs: Sequence[Run], workers: int, batch_size: int | None) -> list[list[Run]]:
    """Runs grouped by map, cut into batches (a few per worker per map, at most 256 runs each)."""
    groups: dict[tuple[Any, ...], list[Run]] = {}
    for r in runs:
        groups.setdefault((r.map, r.resolution, r.robot), []).append(r)
    out = []
    for group in groups.values():
        size = batch_size or max(1, min(256, math.ceil(len(group) / (4 * max(workers, 1)))))
        out += [group[k:k + size] for k in range(0, len(group), size)]
    return out


def _worker_init(max_cells: int, parent: int) -> None:
    import signal
    import threading

    from ..core import limits

    # Ctrl-C reaches the whole process group: the parent stops the workers, they need not say so.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    limits._OVERRIDE.append(max_cells)  # the submitter's size limit (e.g. its --max-cells)

    # A parent killed outright (SIGKILL, a crash) cannot stop its workers, and they would wait on the
    # task queue forever (each holds a writing end of it): they watch the parent and leave with it.
    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="gridfield-parent-watch", daemon=True).start()


def _stop_pool(pool: Any) -> None:
    pool.shutdown(wait=False, cancel_futures=True)
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:
        if p.is_alive():
            p.terminate()
    for p in procs:
        p.join(timeout=5)
        if p.is_alive():  # pragma: no cover - a worker stuck in a kernel ignoring SIGTERM
            p.kill()
            p.join(timeout=5)


def _local_results(batches: Sequence[list[Run]], workers: int) -> Iterator[list[dict[str, Any]]]:
    if workers <= 1 or len(batches) <= 1:
        yield from map(run_batch, batches)
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    # "spawn", not fork: the potential kernels start an OpenMP thread pool, and a process that
    # forks after that can hang or abort ("fork() called from a process already using GNU OpenMP").
    ctx = multiprocessing.get_context("spawn")
    from ..core.limits import max_cells

    pending = list(batches)
    for _ in range(POOL_RESTARTS + 1):
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_worker_init,
                                   initargs=(max_cells(), os.getpid()))
        unfinished: list[list[Run]] = []
        try:
            futures = {pool.submit(run_batch, b): b for b in pending}
            for fut in as_completed(futures):
                try:
                    rows = fut.result()
                except BrokenProcessPool:  # a worker died: every batch not yet back is redone in a new pool
                    unfinished.append(futures[fut])
                    continue
                yield rows
        except BaseException:
            _stop_pool(pool)
            raise
        if not unfinished:
            pool.shutdown(wait=True)
            return
        _stop_pool(pool)
        pending = unfinished
    raise GridfieldError(
        f"worker processes died {POOL_RESTARTS + 1} time(s) (killed, or out of memory?); the rows written so far "
        "are kept: run the sweep again to resume (with fewer --workers if memory is short)"
    )


def _dask_results(batches: Sequence[list[Run]], scheduler: Any) -> Iterator[list[dict[str, Any]]]:
    try:
        from distributed import Client
    except ImportError:
        raise GridfieldError("--scheduler needs Dask: pip install 'gridfield[dask]'") from None
    from ..io import read

    if isinstance(scheduler, Client):
        client = scheduler
    else:
        try:
            client = Client(scheduler, timeout=SCHEDULER_TIMEOUT, set_as_default=False)
        except (OSError, ValueError, TypeError) as e:  # TimeoutError is an OSError
            raise GridfieldError(f"cannot connect to the Dask scheduler {shorten(scheduler)}: "
                                 f"{_one_line(str(e) or type(e).__name__, 200)}") from None
    futures: list[Any] = []
    try:
        # The map's content travels with the tasks (workers need not see the submitter's files):
        # each map is read here once and replicated to the workers, and each task is a batch of its runs.
        try:
            shipped: dict[tuple[Any, ...], Any] = {}
            for b in batches:
                key = (b[0].map, b[0].resolution, b[0].robot)
                if key not in shipped:
                    try:
                        target = _with_robot(read(b[0].map), b[0].robot)
                    except GridfieldError:
                        target = None  # every run of the map reports the error in its row
                    shipped[key] = client.scatter(target, broadcast=True, hash=False) if target is not None else None
                futures.append(client.submit(run_batch, b, shipped[key], pure=False))
            for fut in _completed(client, futures):
                yield fut.result()
        except _cluster_failures() as e:  # raised here, never by the caller's row writing (that is not thrown in)
            raise GridfieldError(
                f"the Dask cluster failed ({type(e).__name__}: {_one_line(str(e) or 'no message', 160)}); the "
                "rows written so far are kept: run the sweep again to resume") from None
    finally:
        # Cancel and close apart: when the scheduler is gone, cancelling fails, and a client left open would
        # stay the process's default Dask client (a later ``compute()`` would wait on the dead scheduler).
        if futures:
            try:
                client.cancel(futures)
            except _cluster_failures():
                pass  # the scheduler is gone: nothing left to cancel
        if client is not scheduler:
            try:
                client.close()
            except _cluster_failures():
                pass


def _completed(client: Any, futures: list[Any]) -> Iterator[Any]:
    """The futures as they finish; a cluster left without any worker for :data:`NO_WORKER_TIMEOUT` seconds
    (all of them dead, none restarted) raises a TimeoutError instead of waiting for ever."""
    import time

    from distributed import as_completed
    from distributed.comm.core import CommClosedError

    ac = as_completed(futures, loop=client.loop)  # the client need not be the default one
    idle_since: float | None = None
    checked = time.monotonic()
    while not ac.is_empty():
        if ac.has_ready():
            yield from ac.next_batch(block=False)
            idle_since = None
            continue
        time.sleep(0.02)
        now = time.monotonic()
        if now - checked < 1.0:
            continue
        checked = now
        if client.status in ("closing", "closed"):
            raise CommClosedError(f"the client lost the scheduler (client {client.status})")
        if client.scheduler_info().get("workers"):
            idle_since = None
        elif idle_since is None:
            idle_since = now
        elif now - idle_since >= NO_WORKER_TIMEOUT:
            raise TimeoutError(f"no worker for {NO_WORKER_TIMEOUT:g} s (all died, none restarted)")


def _cluster_failures() -> tuple[type[BaseException], ...]:
    """What a failing cluster raises from a task's result: a task whose workers all died (KilledWorker), the
    scheduler gone (cancelled futures, closed comms, timeouts); a run's own error is a row, never one of these."""
    import asyncio
    import concurrent.futures

    from distributed.client import ClosedClientError
    from distributed.comm.core import CommClosedError
    from distributed.scheduler import KilledWorker

    return (KilledWorker, CommClosedError, ClosedClientError, asyncio.CancelledError,
            concurrent.futures.CancelledError, OSError, TimeoutError)


def run_sweep(
    runs: Sequence[Run],
    output: str | os.PathLike[str],
    *,
    workers: int | None = None,
    scheduler: Any = None,
    progress: bool = True,
    batch_size: int | None = None,
    notes: list[str] | None = None,
) -> list[dict[str, Any]]:
    """Run the sweep, appending one row per run to ``output`` (CSV); skip runs already there.

    The rows file is locked while the sweep runs (a second sweep on it stops at once), repaired
    when opened (a partial last line from a crash is removed and its run done again), and each
    row is written whole. SIGINT and SIGTERM stop the workers and raise :class:`SweepInterrupted`
    with the file resumable.

    Parameters
    ----------
    runs : the runs (from :func:`load_spec`)
    output : CSV file of rows; created with a header if missing
    workers : local processes (default: all cores)
    scheduler : a Dask scheduler address (or ``distributed.Client``) to run on instead
    progress : show a tqdm progress bar (on a terminal)
    batch_size : runs per task (default: a few tasks per worker and map, at most 256 runs each)
    notes : if given, what the repair of the rows file did is appended here (one line each)

    Returns
    -------
    list of dict : every row of ``output`` after the sweep (old and new), one per run

    Examples
    --------
    >>> import tempfile
    >>> from gridfield.io import bundled_map
    >>> runs = [Run(bundled_map("arena/arena.map"), None, "wavefront-octile", (), (1.5, 37.5), (1.5, 38.5 + k))
    ...         for k in range(3)]
    >>> with tempfile.TemporaryDirectory() as d:
    ...     rows = run_sweep(runs, FsPath(d) / "rows.csv", workers=1, progress=False)
    ...     again = run_sweep(runs, FsPath(d) / "rows.csv", workers=1, progress=False)  # resumed: nothing to do
    >>> [r["length"] for r in rows], again == rows
    (['1.0', '2.0', '3.0'], True)
    """
    import signal
    import threading

    if batch_size is not None and (isinstance(batch_size, bool) or not isinstance(batch_size, int) or batch_size < 1):
        raise ParameterError(f"batch_size must be a positive integer, got {shorten(batch_size)}")
    journal = _Journal(FsPath(output))
    if notes is not None:
        notes += [f"{output}: {n}" for n in journal.notes]
    handlers: dict[int, Any] = {}

    def stop(signum: int, frame: Any) -> None:
        raise SweepInterrupted(signum)

    if threading.current_thread() is threading.main_thread():
        for sig in (signal.SIGINT, signal.SIGTERM):
            handlers[sig] = signal.signal(sig, stop)
    try:
        seen: set[tuple[str, ...]] = set()
        todo = []
        for r in runs:
            if r.key not in journal.keys and r.key not in seen:
                seen.add(r.key)
                todo.append(r)
        if todo:
            n_workers = workers or os.cpu_count() or 1
            batches = _batches(todo, n_workers, batch_size)
            results = (_dask_results(batches, scheduler) if scheduler is not None
                       else _local_results(batches, n_workers))
            from tqdm.auto import tqdm

            with tqdm(total=len(todo), desc="sweep", unit="run", disable=not progress, leave=False) as bar:
                try:
                    for rows in results:
                        for row in rows:
                            journal.append(row)
                        bar.update(len(rows))
                finally:
                    close = getattr(results, "close", None)
                    if close is not None:
                        close()  # stops the workers now if the loop ended early
        return [dict(r) for r in journal.rows]
    finally:
        for signum, old in handlers.items():
            signal.signal(signum, old)
        journal.close()
