"""Benchmark: navigation functions (``gridfield.fields.navigation``).

Run ``python benchmarks/navigation.py`` (options: ``--sizes``, ``--repeat``, ``--maps``, ``--skip``).
Prints markdown tables; every time is a median over ``--repeat`` rounds in which the candidates run
round-robin on the same map in the same process (one run is noise on the shared 2-core machine).

1. **Octile wavefront** (the exact shortest-path cost field to a goal, no corner cutting) against
   scikit-image's ``MCP_Geometric(costs).find_costs([goal])``, the closest library equivalent (an
   8-connected minimum-cost-path field with octile step lengths and a binary heap). Note that
   ``MCP_Geometric`` *does* cut corners (a diagonal step only needs its target cell free), so its
   values are a little lower than the Moving AI metric's; the table gives the number of cells where
   the two fields differ. On every Moving AI map, and on synthetic square maps of ``--sizes`` (random
   10 % obstacles, and a perfect maze of 1-cell corridors), beside:

   - the unit-cost 8-connected wavefront (a plain BFS, the floor for any exact wavefront),
   - at sizes <= 1024: alternating raster sweeps (fast-sweeping style Bellman-Ford, iterated until no
     value changes; exact) and scipy's ``csgraph.dijkstra`` (binary heap, graph built beforehand).

2. **Harmonic** potential (``harmonic``): solve time, shells and conjugate-gradient iterations at
   1024 x 1024 (empty, random 10 %, maze with 8-cell corridors) and on the largest Moving AI maps.
3. **Fast marching** (``fmm``, scikit-fmm) beside the octile wavefront, and the path followers.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numba import njit

from gridfield.core.grid import Grid, GridMap
from gridfield.fields.navigation import extract_path, fmm, harmonic, wavefront

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _common import TEST_MAPS, map_and_scen  # noqa: E402

#: rounds of four raster sweeps after which the sweeping candidate gives up (mazes need thousands)
SWEEP_CAP = 100
MOVINGAI = TEST_MAPS / "movingai"


# ----------------------------------------------------------------------------------------------
# maps
# ----------------------------------------------------------------------------------------------
def random_map(n: int, p: float = 0.1, seed: int = 0) -> GridMap:
    occ = np.random.default_rng(seed).random((n, n)) < p
    return GridMap(Grid((n, n), 1.0), occ)


@njit(cache=True)
def _backtracker(k, draws):  # pragma: no cover - compiled
    """Spanning tree of a k x k lattice of rooms by randomized depth-first search (``draws``: uniform
    random numbers, one per step): returns for each room whether it opens north and east."""
    t = 0
    north = np.zeros((k, k), np.bool_)
    east = np.zeros((k, k), np.bool_)
    seen = np.zeros((k, k), np.bool_)
    stack = np.empty((k * k, 2), np.int64)
    stack[0, 0] = 0
    stack[0, 1] = 0
    seen[0, 0] = True
    top = 1
    opts = np.empty(4, np.int64)
    while top > 0:
        i, j = stack[top - 1, 0], stack[top - 1, 1]
        m = 0
        if i + 1 < k and not seen[i + 1, j]:
            opts[m] = 0
            m += 1
        if i > 0 and not seen[i - 1, j]:
            opts[m] = 1
            m += 1
        if j + 1 < k and not seen[i, j + 1]:
            opts[m] = 2
            m += 1
        if j > 0 and not seen[i, j - 1]:
            opts[m] = 3
            m += 1
        if m == 0:
            top -= 1
            continue
        o = opts[min(int(draws[t % draws.shape[0]] * m), m - 1)]
        t += 1
        if o == 0:
            north[i, j] = True
            i += 1
        elif o == 1:
            i -= 1
            north[i, j] = True
        elif o == 2:
            east[i, j] = True
            j += 1
        else:
            j -= 1
            east[i, j] = True
        seen[i, j] = True
        stack[top, 0] = i
        stack[top, 1] = j
        top += 1
    return north, east


def maze_map(n: int, corridor: int = 1, seed: int = 0) -> GridMap:
    """A perfect maze (recursive backtracker: long winding corridors, one path between any two cells)
    with corridors ``corridor`` cells wide and walls 1 cell thick."""
    pitch = corridor + 1
    k = (n - 1) // pitch
    north, east = _backtracker(k, np.random.default_rng(seed).random(2 * k * k))
    occ = np.ones((n, n), bool)
    for a in range(corridor):
        for b in range(corridor):
            occ[1 + a:1 + k * pitch:pitch, 1 + b:1 + k * pitch:pitch] = False
    ii, jj = np.nonzero(north)
    for b in range(corridor):  # passage north of room (i, j)
        occ[1 + ii * pitch + corridor, 1 + jj * pitch + b] = False
    ii, jj = np.nonzero(east)
    for a in range(corridor):  # passage east of room (i, j)
        occ[1 + ii * pitch + a, 1 + jj * pitch + corridor] = False
    return GridMap(Grid((n, n), 1.0), occ)


def movingai_maps(names: list[str] | None) -> list[tuple[str, GridMap]]:
    from gridfield.io import read_movingai_map

    out = []
    for d in sorted(p for p in MOVINGAI.iterdir() if p.is_dir()) if MOVINGAI.is_dir() else []:
        if names and d.name not in names:
            continue
        out.append((d.name, read_movingai_map(map_and_scen(d)[0])))
    return out


def central_free_cell(gm: GridMap) -> tuple[int, int]:
    """The free cell of the largest 4-connected component nearest to the map's centre."""
    from scipy import ndimage

    lab, n = ndimage.label(~gm.occupied)
    big = np.argmax(np.bincount(lab.ravel())[1:]) + 1 if n else 0
    cells = np.argwhere(lab == big)
    rows, cols = gm.shape
    k = np.argmin(np.hypot(cells[:, 0] - rows / 2, cells[:, 1] - cols / 2))
    return int(cells[k, 0]), int(cells[k, 1])


# ----------------------------------------------------------------------------------------------
# other exact wavefronts, for the comparison only
# ----------------------------------------------------------------------------------------------
@njit(cache=True, error_model="numpy", boundscheck=False)
def sweep_wavefront(free, gr, gc, diag, max_iterations):  # pragma: no cover - compiled
    """Octile no-corner-cutting distance by alternating raster sweeps (four scan orders), repeated until
    no value changes (Gauss-Seidel Bellman-Ford; exact at convergence) or ``max_iterations`` rounds of
    four sweeps. Returns (dist, iterations, converged)."""
    rows, cols = free.shape
    w = cols + 2
    f = np.zeros((rows + 2) * w, np.uint8)
    for r in range(rows):
        for c in range(cols):
            f[(r + 1) * w + c + 1] = free[r, c]
    d = np.full((rows + 2) * w, np.inf)
    d[(gr + 1) * w + gc + 1] = 0.0
    it = 0
    changed = True
    while changed and it < max_iterations:
        changed = False
        it += 1
        for sy in (1, -1):
            for sx in (1, -1):
                r0 = 1 if sy == 1 else rows
                c0 = 1 if sx == 1 else cols
                for rr in range(rows):
                    r = r0 + sy * rr
                    for cc in range(cols):
                        u = r * w + c0 + sx * cc
                        if not f[u]:
                            continue
                        best = d[u]
                        a = u - sy * w
                        b = u - sx
                        if f[a] and d[a] + 1.0 < best:
                            best = d[a] + 1.0
                        if f[b] and d[b] + 1.0 < best:
                            best = d[b] + 1.0
                        e = u - sy * w - sx
                        if f[a] and f[b] and f[e] and d[e] + diag < best:
                            best = d[e] + diag
                        e = u - sy * w + sx
                        if f[a] and f[u + sx] and f[e] and d[e] + diag < best:
                            best = d[e] + diag
                        if best < d[u]:
                            d[u] = best
                            changed = True
    out = np.empty((rows, cols))
    for r in range(rows):
        for c in range(cols):
            out[r, c] = d[(r + 1) * w + c + 1]
    return out, it, not changed


def octile_graph(free: np.ndarray) -> Any:
    from scipy.sparse import coo_matrix

    rows, cols = free.shape
    ids = np.arange(rows * cols).reshape(rows, cols)
    src, dst, wts = [], [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        c0, c1 = max(0, -dc), cols - max(0, dc)
        a, b = (slice(0, rows - dr), slice(c0, c1)), (slice(dr, rows), slice(c0 + dc, c1 + dc))
        ok = free[a] & free[b]
        if dr and dc:
            ok &= free[dr:rows, c0:c1] & free[0:rows - dr, c0 + dc:c1 + dc]
        src.append(ids[a][ok])
        dst.append(ids[b][ok])
        wts.append(np.full(int(ok.sum()), math.sqrt(2) if dr and dc else 1.0))
    return coo_matrix((np.concatenate(wts), (np.concatenate(src), np.concatenate(dst))),
                      shape=(rows * cols,) * 2).tocsr()


# ----------------------------------------------------------------------------------------------
# timing
# ----------------------------------------------------------------------------------------------
def medians(cands: dict[str, Callable[[], Any]], repeat: int) -> tuple[dict[str, float], dict[str, Any]]:
    """Round-robin: every candidate once per round, after one untimed warm-up call each (numba compile
    or cache load); median seconds per candidate, and the last result."""
    times: dict[str, list[float]] = {k: [] for k in cands}
    last: dict[str, Any] = {k: fn() for k, fn in cands.items()}
    for _ in range(repeat):
        for name, fn in cands.items():
            t0 = time.perf_counter()
            last[name] = fn()
            times[name].append(time.perf_counter() - t0)
    return {k: statistics.median(v) for k, v in times.items()}, last


def fmt_ms(s: float) -> str:
    ms = s * 1e3
    return f"{ms:.3f}" if ms < 1 else (f"{ms:.1f}" if ms < 1e4 else f"{ms:.0f}")


def wavefront_rows(name: str, gm: GridMap, repeat: int, extra: bool) -> list[str]:
    from skimage.graph import MCP_Geometric

    free = ~gm.occupied
    goal_cell = central_free_cell(gm)
    goal = gm.grid.cell_to_world([goal_cell])[0]
    costs = np.where(free, 1.0, np.inf)
    cands: dict[str, Callable[[], Any]] = {
        "octile": lambda: wavefront(gm, goal, costs="octile").value,
        "mcp": lambda: MCP_Geometric(costs).find_costs([goal_cell])[0],
        "bfs": lambda: wavefront(gm, goal, costs="unit").value,
    }
    if extra:
        from scipy.sparse.csgraph import dijkstra

        graph = octile_graph(free)
        ids = goal_cell[0] * gm.shape[1] + goal_cell[1]
        cands["sweep"] = lambda: sweep_wavefront(free, goal_cell[0], goal_cell[1], math.sqrt(2), SWEEP_CAP)
        cands["heap"] = lambda: dijkstra(graph, directed=False, indices=ids)
    t, res = medians(cands, repeat)
    oct_v = res["octile"]
    mcp_v = np.where(free, res["mcp"], np.inf)
    reach = np.isfinite(oct_v)
    differ = int(np.sum(reach & ~np.isclose(mcp_v, oct_v, rtol=0, atol=1e-9)))
    cells = gm.occupied.size
    row = (f"| {name} | {gm.shape[1]}x{gm.shape[0]} | {fmt_ms(t['octile'])} | {cells / t['octile'] / 1e6:.0f} "
           f"| {fmt_ms(t['mcp'])} | **{t['mcp'] / t['octile']:.1f}** | {fmt_ms(t['bfs'])} | ")
    if extra:
        sweep_v, its, converged = res["sweep"]
        heap_v = res["heap"].reshape(gm.shape)
        ok = np.allclose(heap_v[reach], oct_v[reach], atol=1e-9) and np.array_equal(np.isinf(heap_v), ~reach)
        if converged:
            ok &= np.array_equal(np.isinf(sweep_v), ~reach) and np.allclose(sweep_v[reach], oct_v[reach], atol=1e-9)
            sweep = f"{fmt_ms(t['sweep'])} ({its} it)"
        else:
            sweep = f"> {fmt_ms(t['sweep'])} (not converged in {its} it)"
        row += f"{sweep} | {fmt_ms(t['heap'])} | {'yes' if ok else 'NO'} | "
    else:
        row += "- | - | - | "
    row += f"{differ} |"
    return [row]


def section_wavefront(sizes: list[int], maps: list[tuple[str, GridMap]], repeat: int) -> list[str]:
    lines = ["## Octile wavefront vs scikit-image MCP_Geometric", "",
             "Field from a goal near the map centre; medians of round-robin runs. `Mcells/s` counts all "
             "cells of the map. `MCP / gridfield` is the speed-up. Extra columns at sizes <= 1024: raster "
             f"sweeps (rounds of four sweeps in brackets; stopped after {SWEEP_CAP}) and scipy's binary-heap "
             "Dijkstra on a prebuilt graph; `exact` says they equal the bucket-queue field. `MCP differs` counts reachable cells where "
             "MCP_Geometric's value differs (it cuts corners).", "",
             "| map | W x H | gridfield octile ms | Mcells/s | MCP_Geometric ms | MCP / gridfield | unit BFS ms "
             "| sweeps ms | heap Dijkstra ms | exact | MCP differs |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, gm in maps:
        lines += wavefront_rows(name, gm, repeat, extra=gm.occupied.size <= 1024 * 1024)
        print(lines[-1], file=sys.stderr, flush=True)
    for n in sizes:
        for kind, gm in (("random 10 %", random_map(n)), ("maze, 1-cell corridors", maze_map(n))):
            lines += wavefront_rows(f"{kind} {n}^2", gm, repeat if n < 4096 else max(1, min(repeat, 3)),
                                    extra=n <= 1024)
            print(lines[-1], file=sys.stderr, flush=True)
    return [*lines, ""]


def section_harmonic(maps: list[tuple[str, GridMap]], repeat: int) -> list[str]:
    lines = ["## Harmonic potential", "",
             "`harmonic(gridmap, goal)` (MIC(0)-preconditioned CG, tau = 1e-6, band = 64), goal near the "
             "centre; median of the runs. Shells = linear solves (1 = the plain global harmonic function "
             "resolves everywhere); iterations = CG iterations summed over shells.", "",
             "| map | W x H | free cells | seconds | shells | CG iterations (first shell) |", "|---|---|---|---|---|---|"]
    cases = [("empty 1024^2", GridMap(Grid((1024, 1024), 1.0), np.zeros((1024, 1024), bool))),
             ("random 10 % 1024^2", random_map(1024)), ("maze, 8-cell corridors, 1024^2", maze_map(1024, 8))]
    cases += [(n, gm) for n, gm in maps if n in ("Aurora", "AcrosstheCape", "maze512-32-9", "random512-10-0")]
    for name, gm in cases:
        goal = gm.grid.cell_to_world([central_free_cell(gm)])[0]
        t, res = medians({"h": lambda gm=gm, goal=goal: harmonic(gm, goal)}, max(1, min(repeat, 3) - 1))
        nav = res["h"]
        its = nav.aux["iterations"]
        lines.append(f"| {name} | {gm.shape[1]}x{gm.shape[0]} | {int((~gm.occupied).sum())} | {t['h']:.2f} | "
                     f"{nav.aux['shells']} | {sum(its)} ({its[0]}) |")
        print(lines[-1], file=sys.stderr, flush=True)
    return [*lines, ""]


def section_fmm(sizes: list[int], repeat: int) -> list[str]:
    lines = ["## Fast marching and path following", "",
             "Same goal; `fmm` is scikit-fmm's second-order fast marching on the free cells. Paths from the "
             "far corner region: `extract_path` descent on the octile field, gradient following (step half "
             "a cell) on the fmm field.", "",
             "| map | octile field ms | fmm field ms | fmm / octile | octile path ms (length) | "
             "fmm path ms (length) |", "|---|---|---|---|---|---|"]
    for n in sizes:
        gm = random_map(n)
        goal = gm.grid.cell_to_world([central_free_cell(gm)])[0]
        cells = np.argwhere(~gm.occupied)
        start = gm.grid.cell_to_world([cells[np.argmin(cells.sum(axis=1))]])[0]
        rep = repeat if n < 4096 else max(1, min(repeat, 3))
        t, res = medians({"oct": lambda gm=gm, goal=goal: wavefront(gm, goal, costs="octile"),
                          "fmm": lambda gm=gm, goal=goal: fmm(gm, goal)}, rep)
        tp, paths = medians({"op": lambda r=res, s=start: extract_path(r["oct"], s),
                             "fp": lambda r=res, s=start: extract_path(r["fmm"], s)}, rep)
        lines.append(f"| random 10 % {n}^2 | {fmt_ms(t['oct'])} | {fmt_ms(t['fmm'])} | {t['fmm'] / t['oct']:.1f} | "
                     f"{fmt_ms(tp['op'])} ({paths['op'].length:.1f}) | {fmt_ms(tp['fp'])} ({paths['fp'].length:.1f}) |")
        print(lines[-1], file=sys.stderr, flush=True)
    return [*lines, ""]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="*", default=[512, 1024, 4096], help="synthetic map sizes")
    ap.add_argument("--repeat", type=int, default=5, help="rounds per measurement (medians)")
    ap.add_argument("--maps", nargs="*", default=None, help="Moving AI map names (default: all)")
    ap.add_argument("--skip", nargs="*", default=[], choices=["wavefront", "harmonic", "fmm"],
                    help="sections to leave out")
    args = ap.parse_args(argv)
    maps = movingai_maps(args.maps)
    import platform

    import numba
    import scipy
    import skimage

    out = [f"# gridfield navigation benchmarks ({time.strftime('%Y-%m-%d')}, {platform.machine()}, "
           f"numpy {np.__version__}, scipy {scipy.__version__}, numba {numba.__version__}, "
           f"scikit-image {skimage.__version__})", ""]
    if "wavefront" not in args.skip:
        out += section_wavefront(args.sizes, maps, args.repeat)
    if "harmonic" not in args.skip:
        out += section_harmonic(maps, args.repeat)
    if "fmm" not in args.skip:
        out += section_fmm([n for n in args.sizes if n <= 4096], args.repeat)
    print("\n".join(out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
