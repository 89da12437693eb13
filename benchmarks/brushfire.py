"""Brushfire benchmark: gridfield's compiled distance maps beside SciPy and OpenCV, in one process.

Usage::

    python benchmarks/brushfire.py                                  # 512^2 ... 8192^2, several minutes
    python benchmarks/brushfire.py --sizes 512 1024 --repeat 3      # a quick run
    python benchmarks/brushfire.py --sizes 4096 --maps random --no-compile
    python benchmarks/brushfire.py --sizes 4096 --maps random --no-compile --compare-kernels /tmp/old.so

``--brief`` times only the rows of the kernels brief's target table (random map; OpenCV DIST_C and DIST_L2
precise, scipy edt + indices, gridfield chessboard distance and Euclidean + nearest), interleaved, and
reports each row's minimum **wall** time and minimum **thread CPU** time (``time.thread_time``: user +
system time of the calling thread, which excludes the time other jobs hold the core; every
single-threaded row runs on the calling thread). Use it on a shared machine.

``--compare-kernels FILE`` adds rows running ``brushfire`` on another build of the kernels (an extension
module compiled from an older ``_brushfire.pyx``, one from before it was split into ``_brushfire``,
``_chamfer`` and ``_edt``, under the name ``_kernels_brushfire_old``, so that both load in one process),
interleaved with the others.

For every map (``random``: ~20 % of the cells blocked at random; ``maze``: a perfect maze of 14-cell
corridors and 2-cell walls, ~13 % blocked, generated with vectorized numpy) and size, every method
runs once untimed, then ``--repeat`` rounds in which each method runs once (interleaved, so that load
from other jobs hits all alike). The table gives the median/min/max wall time, the throughput at the
median, the ratio of the median to the fastest method of that map and size (the streaming floor row
excluded), the threads the method used, and the peak of the extra resident memory one call needs
against the bytes of the arrays it returns. OpenCV rows are skipped (with a note) without ``cv2``
(``pip install opencv-python-headless``, the ``[bench]`` extra).

After the tables: the benchmark issue's targets, checked on this run's medians, and the cost of the
first call in a fresh process (the kernels are compiled at install; before, numba compiled them with an empty cache, then loaded them
from the cache in a second process).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import textwrap
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

from _common import Timing, machine_facts, markdown_table, peak_memory, round_robin  # noqa: E402

DENSITY = 0.2


# ----------------------------------------------------------------------------------------------
# maps
# ----------------------------------------------------------------------------------------------
def random_map(n: int, density: float = DENSITY, seed: int = 0) -> np.ndarray:
    """``n x n`` occupancy with each cell blocked with probability ``density``."""
    return np.random.default_rng(seed).random((n, n)) < density


def maze_map(n: int, corridor: int = 14, wall: int = 2, seed: int = 0) -> np.ndarray:
    """A perfect maze ("binary tree" algorithm: every maze cell opens towards +row or +col at random)
    of ``corridor``-wide passages and ``wall``-thick walls, built without Python loops over cells."""
    pitch = corridor + wall
    m = max(1, n // pitch)
    occ = np.ones((m, pitch, m, pitch), bool)  # [maze row, row in cell, maze col, col in cell]
    occ[:, wall:, :, wall:] = False  # cell interiors; each cell's walls are on its low sides
    rng = np.random.default_rng(seed)
    up = rng.random((m, m)) < 0.5  # open towards the next maze row, else towards the next column
    up[-1, :] = False
    up[:, -1] = True
    up[-1, -1] = False
    right = ~up
    right[-1, -1] = False
    occ[1:, :wall, :, wall:] &= ~up[:-1, None, :, None]  # the wall below cell (i + 1, j)
    occ[:, wall:, 1:, :wall] &= ~right[:, None, :-1, None]  # the wall left of cell (i, j + 1)
    grid = np.ones((n, n), bool)
    grid[: m * pitch, : m * pitch] = occ.reshape(m * pitch, m * pitch)
    return grid


MAPS: dict[str, Callable[[int], np.ndarray]] = {"random": random_map, "maze": maze_map}


# ----------------------------------------------------------------------------------------------
# candidates
# ----------------------------------------------------------------------------------------------
@dataclass
class Method:
    key: str
    label: str
    threads: str
    fn: Callable[[], Any]
    floor: bool = False  # a reference, not a distance transform


def load_old_kernels(path: str) -> Any:
    """The extension module at ``path`` (built under the name ``_kernels_brushfire_old``)."""
    import importlib.machinery
    import importlib.util

    loader = importlib.machinery.ExtensionFileLoader("_kernels_brushfire_old", path)
    spec = importlib.util.spec_from_file_location("_kernels_brushfire_old", path, loader=loader)
    assert spec is not None
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def methods(occ: np.ndarray, *, opencv: Any | None, old: Any | None = None) -> list[Method]:
    from scipy import ndimage

    import gridfield.distance.brushfire as gb
    from gridfield.core.grid import Grid, GridMap
    from gridfield.distance.brushfire import brushfire

    gm = GridMap(Grid(occ.shape, 1.0), occ)
    free = ~occ
    src = np.ones(occ.shape, np.float32)
    dst = np.empty_like(src)

    def bf(threads: int, **kw: Any) -> Callable[[], Any]:
        return lambda: brushfire(gm, threads=threads, **kw)

    helpers = ("_kernel_brushfire", "_kernel_chamfer", "_kernel_edt")

    def bf_old(threads: int, **kw: Any) -> Callable[[], Any]:
        # brushfire() asks gb._kernel_brushfire(), gb._kernel_chamfer() and gb._kernel_edt() for its modules
        # (each imports the compiled module beside it): swap all three for the one old module during the
        # call (a build from before the split of _brushfire.pyx into _brushfire, _chamfer and _edt holds
        # every kernel of the three)
        def run() -> Any:
            loaders = {name: getattr(gb, name) for name in helpers}
            for name in helpers:
                setattr(gb, name, lambda: old)
            try:
                return brushfire(gm, threads=threads, **kw)
            finally:
                for name, loader in loaders.items():
                    setattr(gb, name, loader)
        return run

    lean = {"compute_nearest": False, "compute_labels": False}
    out = [Method("floor", "stream a float32 grid once (np.copyto)", "1", lambda: np.copyto(dst, src), floor=True)]
    if opencv is not None:
        free8 = free.astype(np.uint8)

        def cv(kind: int, mask: int, threads: int) -> Callable[[], Any]:
            def run() -> Any:
                opencv.setNumThreads(threads)
                return opencv.distanceTransform(free8, kind, mask)
            return run

        out.append(Method("cv_c", "OpenCV distanceTransform DIST_C 3x3 (float32 distance)", "1",
                          cv(opencv.DIST_C, 3, 1)))
    out += [
        Method("cdt", "scipy distance_transform_cdt chessboard", "1",
               lambda: ndimage.distance_transform_cdt(free, metric="chessboard")),
        Method("gf_c", "gridfield chessboard: steps + distance", "1", bf(1, **lean)),
        Method("cdt_i", "scipy distance_transform_cdt chessboard + indices", "1",
               lambda: ndimage.distance_transform_cdt(free, metric="chessboard", return_indices=True)),
        Method("gf_c_n", "gridfield chessboard + nearest obstacle", "1", bf(1, compute_labels=False)),
        Method("gf_c_nl", "gridfield chessboard + nearest + labels", "2",
               bf(2, compute_gvd=False)),
        Method("gf_c_full", "gridfield chessboard, default call (+ GVD)", "2", bf(2)),
        Method("gf_t_full", "gridfield taxicab (4-connected), default call", "2", bf(2, connectivity=4)),
    ]
    if opencv is not None:
        out += [
            Method("cv_l2", "OpenCV DIST_L2 precise (float32 distance)", "1",
                   cv(opencv.DIST_L2, opencv.DIST_MASK_PRECISE, 1)),
            Method("cv_l2_2", "OpenCV DIST_L2 precise (float32 distance)", "2",
                   cv(opencv.DIST_L2, opencv.DIST_MASK_PRECISE, 2)),
        ]
    out += [
        Method("edt_i", "scipy distance_transform_edt + indices", "1",
               lambda: ndimage.distance_transform_edt(free, return_indices=True)),
        Method("gf_e_n1", "gridfield euclidean + nearest obstacle", "1",
               bf(1, metric="euclidean", compute_labels=False)),
        Method("gf_e_n", "gridfield euclidean + nearest obstacle", "2",
               bf(2, metric="euclidean", compute_labels=False)),
        Method("gf_e_full", "gridfield euclidean, default call (+ labels, GVD)", "2", bf(2, metric="euclidean")),
    ]
    if old is not None:
        out += [
            Method("old_c", "OLD kernels: chessboard: steps + distance", "1", bf_old(1, **lean)),
            Method("old_c_n", "OLD kernels: chessboard + nearest obstacle", "1", bf_old(1, compute_labels=False)),
            Method("old_e_n1", "OLD kernels: euclidean + nearest obstacle", "1",
                   bf_old(1, metric="euclidean", compute_labels=False)),
            Method("old_e_n", "OLD kernels: euclidean + nearest obstacle", "2",
                   bf_old(2, metric="euclidean", compute_labels=False)),
        ]
    return out


@dataclass
class Row:
    map: str
    n: int
    method: Method
    timing: Timing


def run_group(name: str, n: int, repeat: int, opencv: Any | None, old: Any | None = None) -> list[Row]:
    occ = MAPS[name](n)
    ms = methods(occ, opencv=opencv, old=old)
    timings = round_robin({m.key: m.fn for m in ms}, repeat=repeat)
    for m in ms:
        peak, size = peak_memory(m.fn)
        timings[m.key].peak_bytes, timings[m.key].result_bytes = peak, size
    return [Row(name, n, m, timings[m.key]) for m in ms]


def table(rows: list[Row]) -> str:
    n = rows[0].n
    fastest = min(r.timing.median_ms for r in rows if not r.method.floor)
    lines = []
    for r in rows:
        t = r.timing
        mem = ""
        if t.peak_bytes is not None and t.result_bytes:
            mem = f"{t.peak_bytes / 2**20:.0f} / {t.result_bytes / 2**20:.0f} ({t.peak_bytes / t.result_bytes:.2f}x)"
        lines.append([r.method.label, r.method.threads, f"{t.median_ms:.1f}", f"{t.min_ms:.1f}", f"{t.max_ms:.1f}",
                      f"{t.throughput(n * n):.0f}", f"{t.median_ms / fastest:.2f}", mem])
    return markdown_table(["method", "threads", "median ms", "min", "max", "Mcells/s", "x fastest",
                           "peak / returned MB"], lines)


def targets(rows: list[Row]) -> list[str]:
    """The benchmark issue's targets on this group's medians (skipped where a peer is missing)."""
    med = {r.method.key: r.timing.median_ms for r in rows}
    out = []

    def check(ok: bool, text: str) -> None:
        out.append(f"- [{'x' if ok else ' '}] {text}")

    if "cv_c" in med:
        ratio = med["cv_c"] / med["gf_c"]
        check(ratio >= 0.8, f"8-connected distance at >= 0.8x OpenCV DIST_C's throughput: {ratio:.2f}x "
                            f"({med['gf_c']:.0f} vs {med['cv_c']:.0f} ms)")
    for key, what in (("gf_c_nl", "nearest + labels"), ("gf_c_full", "nearest + labels + GVD (default call)")):
        ratio = med["cdt_i"] / med[key]
        check(ratio >= 2.5, f"chessboard with {what} >= 2.5x faster than scipy cdt + indices: {ratio:.2f}x "
                            f"({med[key]:.0f} vs {med['cdt_i']:.0f} ms)")
    for key, thr in (("gf_e_n1", "1 thread"), ("gf_e_n", "2 threads")):
        if "cv_l2" in med:
            ratio = med[key] / med["cv_l2"]
            check(ratio <= 1.5, f"euclidean + nearest ({thr}) within 1.5x of OpenCV DIST_L2 precise (1 thread): "
                                f"{ratio:.2f}x its time ({med[key]:.0f} vs {med['cv_l2']:.0f} ms)")
        ratio = med["edt_i"] / med[key]
        check(ratio >= 2.8, f"euclidean + nearest ({thr}) >= 2.8x faster than scipy edt + indices: {ratio:.2f}x "
                            f"({med[key]:.0f} vs {med['edt_i']:.0f} ms)")
    if "old_c" in med:
        out.append("")
        out.append("Brief's table (ratios of this run's medians; OLD = the --compare-kernels build):")
        out.append("")
        lines = []
        for what, new, old in (("DIST_C throughput / gf chessboard (higher is better)", ("cv_c", "gf_c"), ("cv_c", "old_c")),
                               ("gf eucl+nearest 1 thr time / DIST_L2 precise (lower is better)", ("gf_e_n1", "cv_l2"),
                                ("old_e_n1", "cv_l2")),
                               ("scipy edt+indices / gf eucl+nearest 1 thr (higher is better)", ("edt_i", "gf_e_n1"),
                                ("edt_i", "old_e_n1")),
                               ("scipy edt+indices / gf eucl+nearest 2 thr (higher is better)", ("edt_i", "gf_e_n"),
                                ("edt_i", "old_e_n"))):
            if all(k in med for k in new + old):
                lines.append([what, f"{med[old[0]] / med[old[1]]:.2f}", f"{med[new[0]] / med[new[1]]:.2f}"])
        out.append(markdown_table(["ratio", "OLD kernels", "this build"], lines))
        out.append("")
    worst = max((r.timing.peak_bytes / r.timing.result_bytes, r.method.label) for r in rows
                if r.method.key.startswith("gf_") and r.timing.peak_bytes is not None and r.timing.result_bytes)
    check(worst[0] <= 2.2, f"peak memory <= ~2x the returned arrays: worst {worst[0]:.2f}x ({worst[1]})")
    return out


def summary_table(groups: list[list[Row]]) -> str:
    """One line per map and size: the targets' ratios."""
    lines = []
    for rows in groups:
        med = {r.method.key: r.timing.median_ms for r in rows}
        worst = max(r.timing.peak_bytes / r.timing.result_bytes for r in rows
                    if r.method.key.startswith("gf_") and r.timing.peak_bytes is not None and r.timing.result_bytes)

        def ratio(a: str, b: str, med: dict[str, float] = med) -> str:
            return f"{med[a] / med[b]:.2f}" if a in med and b in med else "n/a"

        lines.append([rows[0].map, f"{rows[0].n}^2", ratio("cv_c", "gf_c"), ratio("cdt_i", "gf_c_nl"),
                      ratio("cdt_i", "gf_c_full"), ratio("gf_e_n1", "cv_l2"), ratio("gf_e_n", "cv_l2"),
                      ratio("edt_i", "gf_e_n1"), ratio("edt_i", "gf_e_n"), f"{worst:.2f}"])
    return markdown_table(
        ["map", "size", "DIST_C / gf distance (>= 0.8)", "cdt+idx / gf nearest+labels (>= 2.5)",
         "cdt+idx / gf default (>= 2.5)", "gf eucl+nearest 1 thr / DIST_L2 (<= 1.5)",
         "gf eucl+nearest 2 thr / DIST_L2 (<= 1.5)", "edt+idx / gf eucl 1 thr (>= 2.8)",
         "edt+idx / gf eucl 2 thr (>= 2.8)", "peak / returned (<= ~2)"], lines, align="llrrrrrrrr")


def brief_rows(n: int, repeat: int, opencv: Any, old: Any | None) -> str:
    """The brief's table: min wall and min thread-CPU time per row, interleaved, and their ratios."""
    import time

    ms = {m.key: m for m in methods(random_map(n), opencv=opencv, old=old)}
    keys = [k for k in ("cv_c", "gf_c", "old_c", "cv_l2", "edt_i", "gf_e_n1", "old_e_n1", "gf_e_n", "old_e_n")
            if k in ms]
    wall: dict[str, list[float]] = {k: [] for k in keys}
    cpu: dict[str, list[float]] = {k: [] for k in keys}
    for k in keys:
        ms[k].fn()
    for _ in range(repeat):
        for k in keys:
            w0, c0 = time.perf_counter(), time.thread_time()
            ms[k].fn()
            cpu[k].append((time.thread_time() - c0) * 1e3)
            wall[k].append((time.perf_counter() - w0) * 1e3)
    lines = [[ms[k].label, ms[k].threads, f"{min(wall[k]):.1f}", f"{statistics.median(wall[k]):.1f}",
              f"{min(cpu[k]):.1f}" if ms[k].threads == "1" else "n/a"] for k in keys]
    out = [markdown_table(["method", "threads", "min wall ms", "median wall ms", "min thread CPU ms"], lines), ""]
    wmin = {k: min(v) for k, v in wall.items()}
    cmin = {k: min(v) for k, v in cpu.items()}

    def ratio(a: str, b: str, d: dict[str, float]) -> str:
        return f"{d[a] / d[b]:.2f}" if a in d and b in d else "n/a"

    rows = []
    for what, (a, b), (oa, ob), clocks in (
            ("DIST_C throughput / gf chessboard distance (higher is better)", ("cv_c", "gf_c"), ("cv_c", "old_c"),
             "both"),
            ("gf Euclidean + nearest time / DIST_L2 precise, 1 thread (lower is better)", ("gf_e_n1", "cv_l2"),
             ("old_e_n1", "cv_l2"), "both"),
            ("scipy edt + indices / gf Euclidean + nearest, 1 thread (higher is better)", ("edt_i", "gf_e_n1"),
             ("edt_i", "old_e_n1"), "both"),
            ("scipy edt + indices / gf Euclidean + nearest, 2 threads (higher is better)", ("edt_i", "gf_e_n"),
             ("edt_i", "old_e_n"), "wall")):
        cells = [what, ratio(oa, ob, wmin), ratio(a, b, wmin)]
        cells += [ratio(oa, ob, cmin), ratio(a, b, cmin)] if clocks == "both" else ["n/a", "n/a"]
        rows.append(cells)
    out.append(markdown_table(["ratio (minima)", "old kernels, wall", "this build, wall", "old kernels, CPU",
                               "this build, CPU"], rows))
    return "\n".join(out)


# ----------------------------------------------------------------------------------------------
# first call in a fresh process (the kernels are compiled at install: nothing to compile or load)
# ----------------------------------------------------------------------------------------------
_FIRST_CALL = textwrap.dedent("""
    import json, sys, time
    t0 = time.perf_counter()
    import numpy as np
    from gridfield.distance.brushfire import brushfire
    from gridfield.core.grid import Grid, GridMap
    t1 = time.perf_counter()
    occ = np.zeros((64, 64), bool); occ[10, 10] = occ[40, 50] = True
    gm = GridMap(Grid((64, 64), 1.0, border="wall"), occ)
    out = {"import": t1 - t0}
    for name, kw in [("chessboard, default call", {}), ("euclidean, default call", {"metric": "euclidean"}),
                     ("distance only", {"compute_nearest": False, "compute_labels": False}),
                     ("saturate", {"saturate": 5.0})]:
        t = time.perf_counter(); brushfire(gm, **kw); out[name] = time.perf_counter() - t
    print(json.dumps(out))
""")


def first_call_times() -> list[tuple[str, dict[str, float]]]:
    """Seconds of the first calls in a fresh process, then in a second one (the extension modules are
    compiled at install, so the two should agree; a numba version compiled here on the first)."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(HERE.parent))
        runs = []
        for what in ("first process", "second process"):
            proc = subprocess.run([sys.executable, "-c", _FIRST_CALL], env=env, capture_output=True, text=True,
                                  check=True)
            runs.append((what, json.loads(proc.stdout.strip().splitlines()[-1])))
    return runs


def first_call_table(runs: list[tuple[str, dict[str, float]]]) -> str:
    keys = list(runs[0][1])
    rows = [[what] + [f"{t[k]:.2f}" for k in keys] + [f"{sum(t.values()):.2f}"] for what, t in runs]
    return markdown_table(["process"] + [f"{k} (s)" for k in keys] + ["total (s)"], rows)


# ----------------------------------------------------------------------------------------------
def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[512, 2048, 4096, 8192], help="grid sizes n (n x n)")
    parser.add_argument("--maps", nargs="+", choices=list(MAPS), default=list(MAPS))
    parser.add_argument("--repeat", type=int, default=5, help="timed rounds per map and size (default 5)")
    parser.add_argument("--no-opencv", action="store_true", help="leave OpenCV out even if it is installed")
    parser.add_argument("--no-compile", action="store_true", help="skip the first-call (compile/cache) timing")
    parser.add_argument("--brief", action="store_true", help="only the brief's target rows (random map, first size), "
                        "min wall and min thread-CPU times")
    parser.add_argument("--compare-kernels", metavar="FILE",
                        help="also time an older build of the kernels (module _kernels_brushfire_old at FILE)")
    args = parser.parse_args(argv)

    opencv = None
    note = ""
    if not args.no_opencv:
        try:
            import cv2 as opencv
        except ImportError:
            note = "OpenCV rows skipped: cv2 is not installed (pip install opencv-python-headless)."
    print(f"Machine: {machine_facts()}")
    print(f"Command: python benchmarks/brushfire.py {' '.join(argv if argv is not None else sys.argv[1:])}".rstrip())
    if note:
        print(note)
    print()
    if args.brief:
        if opencv is None:
            raise SystemExit("--brief needs OpenCV (pip install opencv-python-headless)")
        old = load_old_kernels(args.compare_kernels) if args.compare_kernels else None
        print(f"### Brief's rows: random map, {args.sizes[0]}x{args.sizes[0]}, {args.repeat} interleaved rounds")
        print()
        print(brief_rows(args.sizes[0], args.repeat, opencv, old))
        return 0
    all_rows: list[list[Row]] = []
    for n in args.sizes:
        for name in args.maps:
            rows = run_group(name, n, args.repeat, opencv,
                             load_old_kernels(args.compare_kernels) if args.compare_kernels else None)
            occupied = float(MAPS[name](min(n, 512)).mean())
            print(f"### {name} map, {n}x{n} ({n * n / 1e6:.1f} M cells, ~{occupied:.0%} blocked), "
                  f"medians of {args.repeat}")
            print()
            print(table(rows))
            print()
            tg = targets(rows)
            all_rows.append(rows)
            print("\n".join(tg))
            print()
    if len(all_rows) > 1:
        print("### Targets across sizes (ratios of medians; >= is better for speed-ups, <= for the others)")
        print()
        print(summary_table(all_rows))
        print()
    if not args.no_compile:
        print("### First call in a fresh process (64x64 map; kernels compiled at install)")
        print()
        print(first_call_table(first_call_times()))
        print()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
