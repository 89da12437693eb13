"""Peak memory per cell of each command and grid planner: the figures behind ``gridfield.core.limits.JOB_BYTES_PER_CELL``.

Each (job, size) runs in a fresh Python process (so that one run's freed memory does not hide the
next one's): the benchmark world of ``end_to_end.synthetic_map`` at ``n x n`` cells is written to an
``.npz``, then the job runs through the command line's ``main`` (the same code path a user runs),
measured by ``_common.peak_memory`` (the resident high-water mark, reset before the call, and
tracemalloc's peak: whichever is larger). The size guard is switched off in the child
(``GRIDFIELD_MAX_CELLS`` set high), so the guard's own estimate does not refuse the measurement.

The table reports, per job, the least-squares slope of the peak over the cell count (bytes per cell)
and the intercept; ``limits.JOB_BYTES_PER_CELL`` holds the slopes rounded up (with a margin for
the sizes between the measured ones). Usage::

    python benchmarks/memory.py                 # sizes 512 1024 1448 (0.26, 1, 2.1 M cells)
    python benchmarks/memory.py --sizes 256 512 --jobs brushfire plan:potential
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

#: job -> the command line after ``gridfield`` (MAP, START, GOAL filled in).
JOBS: dict[str, list[str]] = {
    "info": ["info", "{map}"],
    "brushfire": ["brushfire", "{map}"],
    "field": ["field", "{map}", "--goal", "{gx}", "{gy}"],
    "plan:potential": ["plan", "{map}", "--planner", "potential", "--start", "{sx}", "{sy}", "--goal", "{gx}", "{gy}"],
    "plan:potential:classic": ["plan", "{map}", "--planner", "potential", "--param", "model=khatib", "--start", "{sx}",
                               "{sy}", "--goal", "{gx}", "{gy}"],
    "plan:wavefront": ["plan", "{map}", "--planner", "wavefront", "--start", "{sx}", "{sy}", "--goal", "{gx}", "{gy}"],
    "plan:wavefront-octile": ["plan", "{map}", "--planner", "wavefront-octile", "--start", "{sx}", "{sy}", "--goal",
                              "{gx}", "{gy}"],
    "plan:fmm": ["plan", "{map}", "--planner", "fmm", "--start", "{sx}", "{sy}", "--goal", "{gx}", "{gy}"],
    "plan:harmonic": ["plan", "{map}", "--planner", "harmonic", "--start", "{sx}", "{sy}", "--goal", "{gx}", "{gy}"],
    "compare": ["compare", "{map}", "--start", "{sx}", "{sy}", "--goal", "{gx}", "{gy}", "--json"],
}

_CHILD = r"""
import contextlib, io, json, os, sys
sys.path.insert(0, {bench!r})
from _common import peak_memory
from end_to_end import GOAL, START, synthetic_map
from gridfield.cli import main
from gridfield.io import write_npz
n, path, argv = {n}, {path!r}, {argv!r}
gm = synthetic_map(n)
write_npz(path, {{"occupied": gm.occupied}}, gm.grid)
del gm
subst = dict(map=path, sx=START[0], sy=START[1], gx=GOAL[0], gy=GOAL[1])
argv = [a.format(**subst) for a in argv]
out = io.StringIO()
with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
    peak, _ = peak_memory(lambda: main(argv))
print(json.dumps({{"peak": peak}}))
"""


def measure(job: str, n: int, tmp: Path) -> int:
    """Peak extra bytes of ``job`` on the ``n x n`` benchmark map, in a fresh process."""
    path = tmp / f"mem_{n}.npz"
    code = _CHILD.format(bench=str(HERE), n=n, path=str(path), argv=JOBS[job])
    env = {**os.environ, "GRIDFIELD_MAX_CELLS": "1e12", "PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=ROOT, check=True)
    return int(json.loads(out.stdout.strip().splitlines()[-1])["peak"])


def fit(cells: list[int], peaks: list[int]) -> tuple[float, float]:
    """Least-squares slope (bytes per cell) and intercept of peak over cells."""
    m = len(cells)
    mx, my = sum(cells) / m, sum(peaks) / m
    sxx = sum((c - mx) ** 2 for c in cells)
    slope = sum((c - mx) * (p - my) for c, p in zip(cells, peaks, strict=True)) / sxx if sxx else my / mx
    return slope, my - slope * mx


def main(argv: list[str] | None = None) -> int:
    import tempfile

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[512, 1024, 1448])
    ap.add_argument("--jobs", nargs="+", default=list(JOBS), choices=list(JOBS))
    args = ap.parse_args(argv)
    print("| job | " + " | ".join(f"peak at {n}^2 (MB)" for n in args.sizes) + " | bytes/cell (slope) | intercept (MB) |")
    print("|---|" + "---|" * len(args.sizes) + "---|---|")
    with tempfile.TemporaryDirectory() as d:
        for job in args.jobs:
            peaks = [measure(job, n, Path(d)) for n in args.sizes]
            slope, icpt = fit([n * n for n in args.sizes], peaks)
            print(f"| {job} | " + " | ".join(f"{p / 1e6:.1f}" for p in peaks) + f" | {slope:.1f} | {icpt / 1e6:.1f} |",
                  flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
