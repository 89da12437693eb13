"""Small helpers shared by the benchmark scripts: timing, peak memory, machine facts, tables.

Timing (:func:`measure`, :func:`round_robin`): each candidate runs once untimed (warm-up: numba
kernels load from the cache, pages get mapped), then ``repeat`` timed runs; the result keeps every
run and reports the median, min and max in milliseconds. :func:`round_robin` interleaves the
candidates (one run of each per round) so that a burst of load from other jobs on the machine hits
all of them alike; compare candidates by their ratio within one such group.

Peak memory (:func:`peak_memory`): the extra resident memory one call needs at its peak, read from
``/proc/self/status`` (``VmHWM`` after resetting it through ``/proc/self/clear_refs``) so that it
also counts allocations made inside compiled code and in other threads; where that is not
available (not Linux), :mod:`tracemalloc` (numpy's allocations only).

Usage::

    from _common import round_robin, markdown_table
    res = round_robin({"a": f, "b": g}, repeat=5)
    print(markdown_table(["method", "ms"], [[k, f"{t.median_ms:.1f}"] for k, t in res.items()]))
"""

from __future__ import annotations

import gc
import os
import platform
import re
import statistics
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = [
    "Timing",
    "machine_facts",
    "markdown_table",
    "measure",
    "nbytes",
    "peak_memory",
    "round_robin",
]


@dataclass
class Timing:
    """Wall-clock seconds of each timed run (after the warm-up run)."""

    name: str
    seconds: list[float] = field(default_factory=list)
    peak_bytes: int | None = None  #: extra resident memory at the peak of one call, if measured
    result_bytes: int | None = None  #: bytes of the arrays the call returned, if measured
    note: str = ""

    @property
    def median_ms(self) -> float:
        return statistics.median(self.seconds) * 1e3

    @property
    def min_ms(self) -> float:
        return min(self.seconds) * 1e3

    @property
    def max_ms(self) -> float:
        return max(self.seconds) * 1e3

    def throughput(self, cells: int) -> float:
        """Million cells per second at the median time."""
        return cells / (self.median_ms * 1e-3) / 1e6


def _timed(fn: Callable[[], Any]) -> float:
    t0 = time.perf_counter()
    result = fn()
    dt = time.perf_counter() - t0
    del result
    return dt


def measure(fn: Callable[[], Any], *, repeat: int = 5, warmup: int = 1, name: str = "") -> Timing:
    """Run ``fn`` ``warmup`` times untimed, then ``repeat`` times timed."""
    for _ in range(warmup):
        fn()
    t = Timing(name)
    for _ in range(repeat):
        gc.collect()
        t.seconds.append(_timed(fn))
    return t


def round_robin(candidates: Mapping[str, Callable[[], Any]], *, repeat: int = 5, warmup: int = 1) -> dict[str, Timing]:
    """Time several candidates interleaved: a warm-up of each, then ``repeat`` rounds of one run each."""
    for _ in range(warmup):
        for fn in candidates.values():
            fn()
    out = {name: Timing(name) for name in candidates}
    for _ in range(repeat):
        for name, fn in candidates.items():
            gc.collect()
            out[name].seconds.append(_timed(fn))
    return out


def _status() -> dict[str, int] | None:
    try:
        with open("/proc/self/status") as f:
            text = f.read()
    except OSError:
        return None
    values = {}
    for key in ("VmRSS", "VmHWM"):
        m = re.search(rf"^{key}:\s+(\d+) kB", text, re.MULTILINE)
        if m is None:
            return None
        values[key] = int(m.group(1)) * 1024
    return values


def reset_peak_rss() -> bool:
    """Reset this process's VmHWM to its current RSS (``/proc/self/clear_refs``); False where unsupported."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        return False
    return True


def nbytes(obj: Any) -> int:
    """Total ``nbytes`` of the numpy arrays in ``obj`` (an array, a tuple/list of them, or an object
    whose attributes are arrays, such as a dataclass)."""
    import numpy as np

    if isinstance(obj, np.ndarray):
        return int(obj.nbytes)
    if isinstance(obj, list | tuple):
        return sum(nbytes(x) for x in obj)
    if hasattr(obj, "__dict__"):
        return sum(int(v.nbytes) for v in vars(obj).values() if isinstance(v, np.ndarray))
    return 0


def peak_memory(fn: Callable[[], Any]) -> tuple[int, int]:
    """``(peak extra bytes during one call of fn, bytes of the arrays it returned)``.

    The peak is the larger of two readings: the resident-set high-water mark (``VmHWM``, reset just
    before the call) minus the resident set before it, which counts every allocation (compiled code,
    other threads) but misses memory that the C allocator reuses without returning it to the OS
    (small arrays); and :mod:`tracemalloc`'s peak, which counts numpy's allocations only. It
    includes the returned arrays (they are alive at the end of the call).
    """
    import tracemalloc

    gc.collect()
    before = _status() if reset_peak_rss() else None
    tracemalloc.start()
    try:
        result = fn()
        _, traced = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    after = _status() if before is not None else None
    resident = max(0, after["VmHWM"] - before["VmRSS"]) if before is not None and after is not None else 0
    size = nbytes(result)
    del result
    gc.collect()
    return max(resident, traced), size


def machine_facts() -> str:
    """One line: CPU model and count, Python, numpy, the compiled kernels' threads, load average."""
    import numpy as np

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            m = re.search(r"^model name\s*:\s*(.+)$", f.read(), re.MULTILINE)
        if m:
            cpu = m.group(1).strip()
    except OSError:
        pass
    parts = [f"{cpu}, {os.cpu_count()} cores", f"Python {platform.python_version()}", f"numpy {np.__version__}"]
    from gridfield.fields import _potential as _kernels_potential

    parts.append(f"gridfield kernels compiled ahead of time (Cython, OpenMP {_kernels_potential.get_num_threads()} "
                 "threads)")
    try:
        load = os.getloadavg()
        parts.append(f"load average {load[0]:.1f} at start")
    except OSError:
        pass
    return "; ".join(parts)


def markdown_table(headers: Sequence[str], rows: Iterable[Sequence[Any]], align: str | None = None) -> str:
    """A markdown (GitHub) table. ``align``: one character per column, ``l`` or ``r`` (default: the
    first column left, the rest right)."""
    rows = [[str(x) for x in r] for r in rows]
    align = align or "l" + "r" * (len(headers) - 1)
    rule = ["---:" if a == "r" else "---" for a in align]
    lines = ["| " + " | ".join(headers) + " |", "|" + "|".join(rule) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


#: The external maps (Moving AI, ROS) the benchmarks run on by default: the test suite's copy in the
#: repository (tests/data/maps; its MANIFEST.md names each file's source and licence). ``--root`` /
#: ``--maps-root`` take any folder of the same layout, compressed (``.map.gz``) or not.
TEST_MAPS = Path(__file__).resolve().parents[1] / "tests" / "data" / "maps"


def map_and_scen(folder: Any) -> tuple[Any, Any]:
    """The Moving AI map and scenario file of ``folder`` (``NAME.map`` and its ``.scen``, either
    gzip-compressed or not)."""
    d = Path(folder)
    maps = sorted(d.glob("*.map")) + sorted(d.glob("*.map.gz"))
    scens = sorted(d.glob("*.scen")) + sorted(d.glob("*.scen.gz"))
    if not maps or not scens:
        raise FileNotFoundError(f"{d}: no Moving AI .map and .scen (or .map.gz, .scen.gz) in it")
    return maps[0], scens[0]
