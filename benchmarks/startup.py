"""Start-up: wall time of every command in a fresh process, first call and warm, against the floor.

The floor is ``python -c "import numpy, scipy.ndimage, shapely, yaml"``: the libraries any command
needs, nothing of gridfield. Each command runs ``--repeat`` times in a new process (the
``gridfield`` script beside this Python, else ``python -m gridfield``); "first" is the first of
those runs (run this right after ``pip install .`` for the first call after install: with the
kernels compiled ahead of time there is no compile or cache to fill), "warm" the median of the
others. Ratios are to the floor's warm median, measured in the same run (interleaved rounds, so
that a busy machine slows all alike).

Usage: ``python benchmarks/startup.py [--repeat 5] [--no-demo]``; prints a Markdown table.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
MAP = str(REPO / "maps" / "seed000.yaml")
FLOOR = [sys.executable, "-c", "import numpy, scipy.ndimage, shapely, yaml"]


def _gridfield() -> list[str]:
    script = Path(sys.executable).parent / "gridfield"
    return [str(script)] if script.exists() else [sys.executable, "-m", "gridfield"]


def commands(out: Path, demo: bool) -> dict[str, list[str]]:
    g = _gridfield()
    cmds = {
        "plan (potential) --json": [*g, "plan", MAP, "--json"],
        "plan --planner wavefront-octile": [*g, "plan", MAP, "--json", "--planner", "wavefront-octile"],
        "plan --planner harmonic": [*g, "plan", MAP, "--json", "--planner", "harmonic"],
        "brushfire": [*g, "brushfire", MAP, "--npz", str(out / "b.npz")],
        "field": [*g, "field", MAP, "--npz", str(out / "f.npz")],
        "compare": [*g, "compare", MAP],
        "info": [*g, "info", MAP],
        "--help": [*g, "--help"],
    }
    if demo:
        cmds["demo"] = [*g, "demo", "--out", str(out / "demo")]
    return cmds


def _run(cmd: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=REPO)
    return time.perf_counter() - t0


def measure(repeat: int, demo: bool, only: tuple[str, ...] | None = None) -> tuple[float, dict[str, tuple[float, float]]]:
    """The floor's warm median and, per command (those named in ``only``, default all), (first, warm
    median) seconds."""
    out = Path(tempfile.mkdtemp(prefix="gridfield-startup-"))
    try:
        cmds = {k: v for k, v in commands(out, demo).items() if only is None or k in only}
        times: dict[str, list[float]] = {name: [] for name in ["floor", *cmds]}
        for i in range(repeat):
            times["floor"].append(_run(FLOOR))
            for name, cmd in cmds.items():
                if name == "demo" and i >= 2:  # 10+ s each: first and one warm run
                    continue
                times[name].append(_run(cmd))
    finally:
        shutil.rmtree(out, ignore_errors=True)
    floor = statistics.median(times["floor"][1:] or times["floor"])
    return floor, {name: (ts[0], statistics.median(ts[1:] or ts)) for name, ts in times.items() if name != "floor"}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="runs per command (default 5; the demo runs twice)")
    ap.add_argument("--no-demo", action="store_true", help="leave out `gridfield demo` (about 15 s a run)")
    args = ap.parse_args(argv)
    floor, rows = measure(max(2, args.repeat), not args.no_demo)
    print(f"Floor (`import numpy, scipy.ndimage, shapely, yaml`): {floor:.2f} s (warm median)\n")
    print("| command | first (s) | warm (s) | first / floor | warm / floor | first / warm |")
    print("|---|---|---|---|---|---|")
    for name, (first, warm) in rows.items():
        print(f"| `gridfield {name}` | {first:.2f} | {warm:.2f} | {first / floor:.2f} | {warm / floor:.2f} "
              f"| {first / warm:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
