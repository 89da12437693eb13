"""Incremental brushfire (:class:`gridfield.distance.incremental.IncrementalBrushfire`) beside a full brushfire.

Run ``python benchmarks/incremental.py [--size 4096] [--maps maze random] [--blocks 1 2 5 10 20 40 80]
[--placements 8] [--repeat 3] [--plot benchmarks/incremental.png] [--compare-numba OLD.py]``.

On each map (``n x n``, wall border) a square block of ``k x k`` cells is made occupied at a random
place and then freed again, ``placements`` places per block size; every update is timed, and so is
a full Euclidean :func:`gridfield.distance.brushfire.brushfire` of the same map (distance + nearest obstacle,
no labels: what the incremental updates keep), in the same run, interleaved round by round, so the
ratios compare like with like. The block's cells that were already occupied are left out.
Reported: the median (and largest) time per update and the median number of cells whose nearest
obstacle changed, against the block size, as a table, and the cost of every update against the
cells it changed as a plot.

Then the costs the distance updates do not cover: the labels and GVD of a map without world ids
(in place when no component is renumbered, else recomputed over the grid when read, see
:mod:`gridfield.distance.incremental`), the same with world ids (updated in the window), and the potential field window update (:func:`update_field`) beside a full
:func:`gridfield.fields.potential.build_field`.

``--compare-numba OLD.py``: also time the numba kernels of an older checkout (e.g.
``git show 3fd2f69:gridfield/_kernels_incremental.py > /tmp/old.py``; needs numba, in the ``bench``
extra) on the same updates, interleaved update by update with the compiled ones, and print the two
side by side.

Targets (the issue): on 4096^2 maps a 20 x 20 block updates distance + nearest obstacle at least
50 times faster than a full brushfire, and a 1-cell change at least 500 times faster.
"""

from __future__ import annotations

import argparse
import gc
import statistics
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

from _common import machine_facts, markdown_table  # noqa: E402
from brushfire import maze_map  # noqa: E402

import gridfield.distance.incremental as incremental  # noqa: E402
from gridfield.core.grid import Grid, GridMap  # noqa: E402
from gridfield.distance.brushfire import brushfire  # noqa: E402
from gridfield.distance.incremental import IncrementalBrushfire  # noqa: E402
from gridfield.fields.incremental import update_field  # noqa: E402
from gridfield.fields.potential import build_field  # noqa: E402


def random_map(n: int, seed: int = 0) -> np.ndarray:
    """Scattered obstacles: 2% of the cells blocked, at random."""
    return np.random.default_rng(seed).random((n, n)) < 0.02


MAPS: dict[str, Callable[[int], np.ndarray]] = {"maze": maze_map, "random": random_map}


def _ms(fn: Callable[[], Any]) -> float:
    t0 = time.perf_counter()
    fn()
    return (time.perf_counter() - t0) * 1e3


def block(n: int, k: int, rng: np.random.Generator) -> np.ndarray:
    r, c = rng.integers(0, n - k + 1, 2)
    rr, cc = np.mgrid[r:r + k, c:c + k]
    return np.stack([rr.ravel(), cc.ravel()], 1)


def load_numba(path: Path) -> Any:
    """The numba kernel module of an older checkout, loaded from ``path`` inside the package (its
    relative imports resolve to the compiled modules)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"gridfield._old_{path.stem}", path)
    if spec is None or spec.loader is None:
        raise SystemExit(f"error: cannot load {path}")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def use(kernels: Any) -> None:
    """Make :mod:`gridfield.distance.incremental` call ``kernels`` (None: its own compiled module)."""
    incremental._KERNELS = kernels


def run_map(name: str, n: int, blocks: Sequence[int], placements: int, repeat: int,
            old: Any = None) -> dict[str, Any]:
    occ = MAPS[name](n)
    gm = GridMap(Grid((n, n), 0.05, border="wall"), occ)
    ib = IncrementalBrushfire(gm, compute_labels=False)

    def full() -> Any:
        return brushfire(ib.gridmap, metric="euclidean", compute_steps=False, compute_labels=False)

    full()  # warm-up (kernels loaded, pages mapped)
    rng = np.random.default_rng(1)
    cells = {k: [block(n, k, rng) for _ in range(placements)] for k in blocks}
    cells = {k: [c[~occ[c[:, 0], c[:, 1]]] for c in v] for k, v in cells.items()}  # the free ones
    variants = [None] if old is None else [None, old]
    for v in variants:
        use(v)
        ib.update(occupied=cells[blocks[0]][0])  # warm-up of the update kernels
        ib.update(freed=cells[blocks[0]][0])
    full_ms: list[float] = []
    ins: dict[int, list[float]] = {k: [] for k in blocks}
    rem: dict[int, list[float]] = {k: [] for k in blocks}
    old_ins: dict[int, list[float]] = {k: [] for k in blocks}
    old_rem: dict[int, list[float]] = {k: [] for k in blocks}
    changed_ins: dict[int, list[int]] = {k: [] for k in blocks}
    changed_rem: dict[int, list[int]] = {k: [] for k in blocks}
    flip = False
    for _ in range(repeat):  # one full recompute, then every update, per round
        gc.collect()
        full_ms.append(_ms(full))
        for k in blocks:
            for c in cells[k]:
                if not len(c):
                    continue
                # the same update with each kernel module, back to back, in alternating order (the
                # second one finds the window's memory in the cache: ~10-20 % faster)
                flip = not flip
                for v in (variants[::-1] if flip else variants):
                    use(v)
                    ti = _ms(lambda c=c: ib.update(occupied=c))
                    ci = ib.last_changed
                    tr = _ms(lambda c=c: ib.update(freed=c))
                    cr = ib.last_changed
                    if v is None:
                        ins[k].append(ti)
                        rem[k].append(tr)
                        changed_ins[k].append(ci)
                        changed_rem[k].append(cr)
                    else:
                        old_ins[k].append(ti)
                        old_rem[k].append(tr)
    use(None)
    # the map is back to where it started: check it once against a full recompute
    ref = full()
    assert np.array_equal(ref.distance, ib.distance_map.distance)
    rows = []
    med_full = statistics.median(full_ms)
    for k in blocks:
        if not ins[k]:
            continue
        mi, mr = statistics.median(ins[k]), statistics.median(rem[k])
        rows.append({"k": k, "cells": int(statistics.median([len(c) for c in cells[k] if len(c)])),
                     "changed_ins": int(statistics.median(changed_ins[k])),
                     "changed_rem": int(statistics.median(changed_rem[k])),
                     "ins_ms": mi, "rem_ms": mr, "ins_max": max(ins[k]), "rem_max": max(rem[k]),
                     "x_ins": med_full / mi, "x_rem": med_full / mr,
                     "old_ins": statistics.median(old_ins[k]) if old_ins[k] else None,
                     "old_rem": statistics.median(old_rem[k]) if old_rem[k] else None})
    return {"name": name, "n": n, "blocked": float(occ.mean()), "full_ms": med_full, "full_min": min(full_ms),
            "full_max": max(full_ms), "rows": rows,
            "points": [(ci, t, "insert") for k in blocks for ci, t in zip(changed_ins[k], ins[k], strict=True)]
            + [(ci, t, "remove") for k in blocks for ci, t in zip(changed_rem[k], rem[k], strict=True)]}


def extras(n: int, repeat: int) -> list[list[str]]:
    """Labels/GVD and the potential field, 20 x 20 block on the maze map."""
    occ = maze_map(n)
    rng = np.random.default_rng(2)
    blocks = [block(n, 20, rng) for _ in range(max(8, repeat))]
    blocks = [b[~occ[b[:, 0], b[:, 1]]] for b in blocks]
    out: list[list[str]] = []

    gm = GridMap(Grid((n, n), 0.05, border="wall"), occ)
    full_lab = [_ms(lambda: brushfire(gm, metric="euclidean", compute_steps=False)) for _ in range(repeat)]
    ib = IncrementalBrushfire(gm)
    ib.update(occupied=blocks[0]), ib.distance_map, ib.update(freed=blocks[0]), ib.distance_map  # warm-up
    ti: list[float] = []
    tr: list[float] = []
    kept = [0, 0]  # updates that kept the component numbers in place (insert, remove)

    def timed(**change: Any) -> float:
        t0 = time.perf_counter()
        ib.update(**change)
        kept[0 if "occupied" in change else 1] += not ib._labels_dirty
        _ = ib.distance_map  # labels and GVD up to date (relabelled here if the change renumbered)
        return (time.perf_counter() - t0) * 1e3

    for b in blocks:
        ti.append(timed(occupied=b))
        tr.append(timed(freed=b))
    full_med = statistics.median(full_lab)
    for what, t, nk in (("insert", ti, kept[0]), ("remove", tr, kept[1])):
        out.append([f"labels + GVD, components, {what} + read ({nk} of {len(blocks)} kept the numbers)",
                    f"{statistics.median(t):.1f}", f"{full_med:.1f}", f"{full_med / statistics.median(t):.0f}x"])

    ids = np.where(occ, 1, 0).astype(np.int32)
    gmi = GridMap(Grid((n, n), 0.05, border="wall"), occ, ids)
    full_ids = [_ms(lambda: brushfire(gmi, metric="euclidean", compute_steps=False)) for _ in range(repeat)]
    ib = IncrementalBrushfire(gmi)
    ib.update(occupied=blocks[0]), ib.update(freed=blocks[0])  # warm-up
    t = []
    for b in blocks:
        t.append(_ms(lambda b=b: (ib.update(occupied=b), ib.distance_map)))
        ib.update(freed=b)
    out.append(["labels + GVD, world obstacle ids (window)", f"{statistics.median(t):.2f}",
                f"{statistics.median(full_ids):.1f}", f"{statistics.median(full_ids) / statistics.median(t):.0f}x"])

    ib = IncrementalBrushfire(gm, compute_labels=False)
    free = np.argwhere(~occ)
    gr, gc_ = free[len(free) // 2]
    goal = (0.05 * (gc_ + 0.5), 0.05 * (gr + 0.5))
    params = {"q_star": 0.5}
    field = build_field(ib.gridmap, goal, params, dmap=ib.distance_map)
    update_field(field, ib, ib.update(occupied=[[0, 0]]))  # warm-up
    update_field(field, ib, ib.update(freed=[[0, 0]]))
    t, tf = [], []
    for b in blocks:
        b = b[(b[:, 0] != gr) | (b[:, 1] != gc_)]
        t.append(_ms(lambda b=b: update_field(field, ib, ib.update(occupied=b))))
        tf.append(_ms(lambda: build_field(ib.gridmap, goal, params, dmap=ib.distance_map)))
        update_field(field, ib, ib.update(freed=b))
    out.append(["distance + potential field (update + update_field vs build_field on the new map)",
                f"{statistics.median(t):.2f}", f"{statistics.median(tf):.1f}",
                f"{statistics.median(tf) / statistics.median(t):.0f}x"])
    return out


def plot(results: list[dict[str, Any]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=110)
    colors = {"maze": "tab:blue", "random": "tab:orange"}
    for res in results:
        col = colors.get(res["name"], "tab:gray")
        for kind, marker in (("insert", "o"), ("remove", "x")):
            pts = np.array([(c, t) for c, t, k in res["points"] if k == kind and c > 0], float).reshape(-1, 2)
            ax.loglog(pts[:, 0], pts[:, 1], marker, color=col, ms=3.5, alpha=0.7, linestyle="none",
                      label=f"{res['name']}: {kind}")
        ax.axhline(res["full_ms"], color=col, lw=1, ls="--", label=f"{res['name']}: full brushfire")
    ax.set_xlabel("cells whose nearest obstacle changed")
    ax.set_ylabel("time per update [ms]")
    ax.set_title(f"incremental Euclidean brushfire, {results[0]['n']}x{results[0]['n']} maps")
    ax.legend(fontsize=7, ncol=2, loc="center left")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def extras_side_by_side(n: int, repeat: int, old: Any, rounds: int = 3) -> list[list[str]]:
    """:func:`extras` with the compiled and the old kernels, alternated ``rounds`` times (medians)."""
    got: dict[int, list[list[list[str]]]] = {0: [], 1: []}
    for r in range(rounds):
        for i, v in (((0, None), (1, old)) if r % 2 == 0 else ((1, old), (0, None))):
            use(v)
            got[i].append(extras(n, repeat))
    use(None)
    out = []
    for j, row in enumerate(got[0][0]):
        new = statistics.median(float(r[j][1]) for r in got[0])
        was = statistics.median(float(r[j][1]) for r in got[1])
        out.append([row[0].split(" (")[0], f"{new:.2f}", f"{was:.2f}", f"{new / was:.2f}"])
    return out


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", type=int, default=4096)
    ap.add_argument("--maps", nargs="+", default=list(MAPS), choices=list(MAPS))
    ap.add_argument("--blocks", type=int, nargs="+", default=[1, 2, 5, 10, 20, 40, 80])
    ap.add_argument("--placements", type=int, default=8)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--plot", type=Path, default=None, help="write the cost plot here (PNG)")
    ap.add_argument("--no-extras", action="store_true", help="skip the labels and field rows")
    ap.add_argument("--compare-numba", type=Path, default=None, metavar="OLD.py",
                    help="also time this numba _kernels_incremental.py side by side (needs numba)")
    a = ap.parse_args(argv)
    old = None if a.compare_numba is None else load_numba(a.compare_numba)
    results = [run_map(m, a.size, a.blocks, a.placements, a.repeat, old) for m in a.maps]
    print(f"machine: {machine_facts()}\n")
    for res in results:
        print(f"#### {res['name']} map, {res['n']}x{res['n']} ({res['blocked']:.0%} blocked), wall border; "
              f"full brushfire (distance + nearest) {res['full_ms']:.0f} ms "
              f"(min {res['full_min']:.0f}, max {res['full_max']:.0f})\n")
        print(markdown_table(
            ["block", "cells set", "changed (insert)", "insert ms (max)", "x full", "changed (remove)",
             "remove ms (max)", "x full"],
            [[f"{r['k']}x{r['k']}", str(r["cells"]), str(r["changed_ins"]), f"{r['ins_ms']:.3f} ({r['ins_max']:.2f})",
              f"{r['x_ins']:.0f}", str(r["changed_rem"]), f"{r['rem_ms']:.3f} ({r['rem_max']:.2f})",
              f"{r['x_rem']:.0f}"]
             for r in res["rows"]]))
        print()
    if not a.no_extras:
        print(f"#### labels, GVD and the potential field ({a.size}x{a.size} maze, 20x20 block, medians)\n")
        print(markdown_table(["what", "incremental ms", "full ms", "speed-up"], extras(a.size, a.repeat)))
        print()
    if old is not None:
        print(f"#### compiled kernels vs numba ({a.compare_numba}), same updates, interleaved in alternating order; medians in ms\n")
        table = [[res["name"], f"{r['k']}x{r['k']}", f"{r['ins_ms']:.3f}", f"{r['old_ins']:.3f}",
                  f"{r['ins_ms'] / r['old_ins']:.2f}", f"{r['rem_ms']:.3f}", f"{r['old_rem']:.3f}",
                  f"{r['rem_ms'] / r['old_rem']:.2f}"] for res in results for r in res["rows"]]
        print(markdown_table(["map", "block", "insert", "insert numba", "ratio", "remove", "remove numba", "ratio"],
                             table))
        print()
        if not a.no_extras:
            print(markdown_table(["what (20x20 block, maze)", "compiled ms", "numba ms", "ratio"],
                                 extras_side_by_side(a.size, a.repeat, old)))
            print()
    print("#### targets\n")
    for res in results:
        for r in res["rows"]:
            for k, need in ((1, 500), (20, 50)):
                if r["k"] == k:
                    ok = min(r["x_ins"], r["x_rem"]) >= need
                    print(f"- {'PASS' if ok else 'FAIL'} {res['name']} {k}x{k}: insert {r['x_ins']:.0f}x, "
                          f"remove {r['x_rem']:.0f}x faster than a full brushfire (need >= {need}x)")
    if a.plot is not None:
        plot(results, a.plot)
        print(f"\nplot: {a.plot}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
