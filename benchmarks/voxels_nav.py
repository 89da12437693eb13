"""Benchmark: the voxel (3-D) wavefront (``gridfield.fields.navigation3d``) against scikit-image.

Run ``python benchmarks/voxels_nav.py`` (options: ``--sizes``, ``--repeat``, ``--fraction``). Prints a
markdown table; every time is a median over ``--repeat`` rounds in which the candidates run
round-robin on the same voxels in the same process (one run is noise on the shared 2-core machine).

The row: :func:`gridfield.fields.navigation3d.voxel_wavefront` (Dijkstra over the 26-neighbourhood with
costs 1, sqrt 2, sqrt 3 under the bounding-box rule, a circular bucket queue) against
``skimage.graph.MCP_Geometric(costs, fully_connected=True).find_costs([goal])`` on the same voxels
(costs 1 free / inf blocked), the whole field from the grid's centre, on random occupancy
(``--fraction``, 20 %). ``MCP_Geometric`` does **not** apply the bounding-box rule (a diagonal needs only
its target voxel free) and its step costs are the same lengths, so only the times are compared on
random voxels; the values are compared where the rule cannot bind, on an empty grid (the largest
difference is printed: 0 means equal to the last bit).

The function :func:`wavefront_row` is the table's row (benchmarks/voxels.py, the voxel benchmarks'
module, may call it).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import machine_facts, markdown_table, round_robin

from gridfield.core.grid import Grid, GridMap
from gridfield.fields.navigation3d import voxel_wavefront


def wavefront_row(n: int, fraction: float = 0.2, repeat: int = 3, seed: int = 0) -> list[Any]:
    """One row: size, reached voxels, gridfield and MCP median ms, the ratio, the empty grid's largest
    value difference."""
    from skimage.graph import MCP_Geometric

    rng = np.random.default_rng(seed)
    occ = rng.random((n, n, n)) < fraction
    goal = (n // 2, n // 2, n // 2)
    occ[goal] = False
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    gxyz = gm.grid.cell_to_world([goal])[0]
    costs = np.where(occ, np.inf, 1.0)
    t = round_robin({"gridfield": lambda: voxel_wavefront(gm, gxyz),
                     "mcp": lambda: MCP_Geometric(costs, fully_connected=True).find_costs([goal])},
                    repeat=repeat, warmup=0)
    reached = int(np.isfinite(voxel_wavefront(gm, gxyz)).sum())
    empty = GridMap(Grid(occ.shape, 1.0), np.zeros(occ.shape, bool))
    ours = voxel_wavefront(empty, gxyz)
    theirs, _ = MCP_Geometric(np.ones(occ.shape), fully_connected=True).find_costs([goal])
    diff = float(np.abs(ours - theirs).max())
    g, m = t["gridfield"].median_ms, t["mcp"].median_ms
    return [f"{n}^3", f"{reached:,}", f"{g:.0f}", f"{m:.0f}", f"{m / g:.1f}x", f"{diff:.1g}"]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[128, 256])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--fraction", type=float, default=0.2)
    a = ap.parse_args(argv)
    print(machine_facts())
    print()
    rows = [wavefront_row(n, a.fraction, a.repeat) for n in a.sizes]
    print(markdown_table(["voxels", "reached", "gridfield ms", "MCP_Geometric ms", "speed-up", "empty: max |diff|"],
                         rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
