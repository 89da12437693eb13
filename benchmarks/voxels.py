"""Voxel-grid (3-D) benchmark: gridfield's distance maps of voxel grids beside SciPy and seung-lab's ``edt``.

Usage::

    PYTHONPATH=. python benchmarks/voxels.py --sizes 256 512            # every row
    PYTHONPATH=. python benchmarks/voxels.py --sizes 256 --rows euclid-nearest chessboard --repeat 5

Maps: ``n^3`` voxels, 20 % of them blocked at random (seed 0), open border. Each row is one function
(:data:`ROWS`; later issues add theirs): its candidates run once untimed, then ``--repeat`` interleaved
rounds (one run of each per round, so that load from other jobs hits all alike); the table gives each
candidate's minimum and median wall time and the ratio of the reference's minimum to the candidate's
(> 1: gridfield is faster). Rows:

``euclid-nearest``
    ``brushfire(metric="euclidean", compute_steps=False, compute_labels=False)`` (distance + nearest
    voxel) against ``scipy.ndimage.distance_transform_edt(~occ, return_indices=True)``; target >= 3x.
``euclid-distance``
    the same with ``compute_nearest=False`` against ``edt.edt(~occ, parallel=1)`` (both on one thread;
    target: no slower), and both on all cores (``threads=None`` / ``parallel=0``) for information.
``chessboard``
    ``brushfire(connectivity=26)`` without labels, distance only and with the nearest voxel, against
    ``scipy.ndimage.distance_transform_cdt(~occ, metric="chessboard")``; target >= 2x (distance only).
``wavefront``
    :func:`gridfield.fields.navigation3d.voxel_wavefront` (the 26-neighbour wavefront of ``wavefront-octile``
    under the bounding-box rule, from the centre voxel, the whole field) against
    ``skimage.graph.MCP_Geometric(costs, fully_connected=True).find_costs([goal])`` (costs 1 free / inf
    blocked); target >= 5x. MCP does not apply the bounding-box rule (a diagonal needs only its target
    free), so on random voxels only the times compare; the row's last line compares the values on an
    empty grid, where the rule cannot bind (the largest difference; 0: equal to the last bit).
``rss``
    the peak resident memory of a whole fresh process (``VmHWM`` of ``/proc/self/status``; ``ru_maxrss``
    elsewhere, which on Linux keeps the forking parent's high-water mark) that
    builds the map and makes one call: gridfield's Euclidean + nearest against SciPy's EDT + indices,
    and a process that only builds the map (the floor); target: gridfield within 2.5 GiB at 512^3.
    Runs only for the largest of ``--sizes``.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import machine_facts, markdown_table, round_robin

from gridfield.core.grid import Grid, GridMap
from gridfield.core.limits import override
from gridfield.distance.brushfire import brushfire

GiB = 1 << 30


def random_occupancy(n: int, fraction: float = 0.2, seed: int = 0) -> np.ndarray:
    """``n^3`` voxels, ``fraction`` of them blocked (layer by layer: no ``n^3`` float64 temporary)."""
    rng = np.random.default_rng(seed)
    occ = np.empty((n, n, n), bool)
    for z in range(n):
        occ[z] = rng.random((n, n)) < fraction
    return occ


def _ours(occ: np.ndarray, **kw: Any) -> Callable[[], Any]:
    with override(10**10):  # the benchmark's grids, whatever the size guard's default
        gm = GridMap(Grid(occ.shape, 1.0), occ)

    def run() -> Any:
        with override(10**10):
            return brushfire(gm, compute_labels=False, **kw)

    return run


def _table(n: int, results: dict[str, Any], reference: str) -> list[list[str]]:
    ref = results[reference].min_ms
    return [[f"{n}^3", name, f"{t.min_ms:.0f}", f"{t.median_ms:.0f}", f"{ref / t.min_ms:.2f}x"]
            for name, t in results.items()]


def row_euclid_nearest(n: int, occ: np.ndarray, repeat: int) -> list[list[str]]:
    from scipy import ndimage

    free = ~occ
    res = round_robin({
        "scipy distance_transform_edt(return_indices=True)": lambda: ndimage.distance_transform_edt(
            free, return_indices=True),
        "gridfield euclidean + nearest, 1 thread": _ours(occ, metric="euclidean", compute_steps=False, threads=1),
        "gridfield euclidean + nearest, all cores": _ours(occ, metric="euclidean", compute_steps=False),
    }, repeat=repeat)
    return _table(n, res, "scipy distance_transform_edt(return_indices=True)")


def row_euclid_distance(n: int, occ: np.ndarray, repeat: int) -> list[list[str]]:
    try:
        import edt
    except ImportError:
        return [[f"{n}^3", "edt not installed (pip install edt, the [bench] extra): row skipped", "", "", ""]]
    free = ~occ
    res = round_robin({
        "edt.edt(parallel=1)": lambda: edt.edt(free, parallel=1),
        "gridfield euclidean distance only, 1 thread": _ours(occ, metric="euclidean", compute_steps=False,
                                                             compute_nearest=False, threads=1),
        "edt.edt(parallel=0), all cores": lambda: edt.edt(free, parallel=0),
        "gridfield euclidean distance only, all cores": _ours(occ, metric="euclidean", compute_steps=False,
                                                              compute_nearest=False),
    }, repeat=repeat)
    return _table(n, res, "edt.edt(parallel=1)")


def row_chessboard(n: int, occ: np.ndarray, repeat: int) -> list[list[str]]:
    from scipy import ndimage

    free = ~occ
    res = round_robin({
        "scipy distance_transform_cdt(chessboard)": lambda: ndimage.distance_transform_cdt(free, metric="chessboard"),
        "gridfield chessboard distance + steps": _ours(occ, compute_nearest=False, threads=1),
        "gridfield chessboard + nearest": _ours(occ, threads=1),
    }, repeat=repeat)
    return _table(n, res, "scipy distance_transform_cdt(chessboard)")


_RSS = """
import resource, sys
import numpy as np
sys.path.insert(0, {bench!r})
from voxels import random_occupancy
occ = random_occupancy({n})
method = {method!r}
if method == "gridfield":
    from gridfield.core.grid import Grid, GridMap
    from gridfield.core.limits import override
    from gridfield.distance.brushfire import brushfire
    with override(10**10):
        d = brushfire(GridMap(Grid(occ.shape, 1.0), occ), metric="euclidean", compute_steps=False,
                      compute_labels=False)
elif method == "scipy":
    from scipy import ndimage
    d = ndimage.distance_transform_edt(~occ, return_indices=True)
# VmHWM: this process's own peak (ru_maxrss keeps the high-water mark of the parent it was forked from)
try:
    hwm = [ln for ln in open("/proc/self/status") if ln.startswith("VmHWM:")][0]
    print(int(hwm.split()[1]) * 1024)
except OSError:
    print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)
"""


def _peak_rss(n: int, method: str) -> int:
    code = textwrap.dedent(_RSS).format(bench=str(Path(__file__).resolve().parent), n=n, method=method)
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    return int(out.stdout.split()[-1])


def row_rss(n: int, occ: np.ndarray, repeat: int) -> list[list[str]]:
    del occ, repeat
    floor = _peak_rss(n, "floor")
    rows = [[f"{n}^3", "the map alone (numpy, the occupancy)", f"{floor / GiB:.2f} GiB", "", ""]]
    for method, name in [("scipy", "scipy distance_transform_edt(return_indices=True)"),
                         ("gridfield", "gridfield euclidean + nearest (int16 indices)")]:
        peak = _peak_rss(n, method)
        rows.append([f"{n}^3", name, f"{peak / GiB:.2f} GiB", f"{(peak - floor) / GiB:.2f} GiB",
                     "within 2.5 GiB" if peak <= 2.5 * GiB else "over 2.5 GiB"])
    return rows


def row_wavefront(n: int, occ: np.ndarray, repeat: int) -> list[list[str]]:
    from skimage.graph import MCP_Geometric

    from gridfield.fields.navigation3d import voxel_wavefront

    goal = (n // 2, n // 2, n // 2)
    occ = occ.copy()
    occ[goal] = False
    with override(10**10):
        gm = GridMap(Grid(occ.shape, 1.0), occ)
        empty = GridMap(Grid(occ.shape, 1.0), np.zeros(occ.shape, bool))
    xyz = gm.grid.cell_to_world([goal])[0]
    costs = np.where(occ, np.inf, 1.0)

    def ours(m: GridMap) -> Callable[[], Any]:
        def run() -> Any:
            with override(10**10):
                return voxel_wavefront(m, xyz)
        return run

    mcp = "skimage MCP_Geometric(fully_connected=True).find_costs (no bounding-box rule)"
    res = round_robin({mcp: lambda: MCP_Geometric(costs, fully_connected=True).find_costs([goal]),
                       "gridfield voxel_wavefront (26 neighbours, bounding-box rule)": ours(gm)}, repeat=repeat)
    diff = float(np.abs(ours(empty)() - MCP_Geometric(np.ones(occ.shape), fully_connected=True).find_costs([goal])[0]).max())
    return [*_table(n, res, mcp), [f"{n}^3", f"empty grid: largest difference of the values gridfield - MCP = {diff:.1g}", "", "", ""]]


#: The rows by name, each ``f(n, occupancy, repeat) -> table rows``.
ROWS: dict[str, Callable[[int, np.ndarray, int], list[list[str]]]] = {
    "euclid-nearest": row_euclid_nearest,
    "euclid-distance": row_euclid_distance,
    "chessboard": row_chessboard,
    "wavefront": row_wavefront,
    "rss": row_rss,
}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sizes", type=int, nargs="+", default=[256], help="edge lengths n of the n^3 maps (default 256)")
    p.add_argument("--rows", nargs="+", choices=sorted(ROWS), default=list(ROWS), help="rows to run (default all)")
    p.add_argument("--repeat", type=int, default=3, help="timed rounds per row (default 3)")
    args = p.parse_args(argv)
    print(machine_facts())
    timing: list[list[str]] = []
    memory: list[list[str]] = []
    for n in args.sizes:
        occ = random_occupancy(n)
        for name in args.rows:
            if name == "rss":
                continue
            timing += ROWS[name](n, occ, args.repeat)
            print(f"  {n}^3 {name} done", file=sys.stderr, flush=True)
        del occ
    if timing:
        print(markdown_table(["map", "method", "min ms", "median ms", "reference / this (min)"], timing))
    if "rss" in args.rows:
        memory = row_rss(max(args.sizes), np.zeros(0, bool), 1)
        print()
        print(markdown_table(["map", "method (one fresh process each)", "peak RSS", "over the map alone", ""], memory))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
