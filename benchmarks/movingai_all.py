"""Every Moving AI scenario against the octile wavefront (``gridfield.fields.navigation.wavefront``).

Run ``python benchmarks/movingai_all.py [--root tests/data/maps/movingai] [--processes 2] [--maps NAME ...]``.
For each scenario: one wavefront from the goal (8-connected, octile costs, no corner cutting), its value
at the start compared with the file's optimal length, and the path extracted from it checked (it
costs exactly the value, and no step cuts a corner). Prints one markdown row per map:

- ``agree``: within the issue's tolerances (MANIFEST §5.1): 6 significant digits 1e-3 absolute
  (5e-3 for lengths >= 1000), 2 decimals 0.005 (+1e-9), 8 decimals 1e-6; "no path" markers
  (length 0 with start != goal) must be unreachable;
- ``agree (io)``: within ``Scenarios.tolerance()`` of :mod:`gridfield.io` (half a unit in the last
  printed place + 1e-5 * length);
- ``max |err|``: largest absolute difference on reachable scenarios;
- ``paths ok``: extracted paths that reach the goal, cost the value (1e-9) and never cut a corner.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _common import TEST_MAPS, map_and_scen  # noqa: E402

DEFAULT_ROOT = TEST_MAPS / "movingai"


def issue_tolerance(precision: str, digits: int, optimal: np.ndarray) -> np.ndarray:
    if precision == "decimals" and digits == 2:
        return np.full(optimal.shape, 0.005 + 1e-9)
    if precision == "decimals":
        return np.full(optimal.shape, 1e-6)
    return np.where(optimal >= 1000, 5e-3, 1e-3)


def chain_ok(free: np.ndarray, cells: np.ndarray, value: float) -> bool:
    step = np.diff(cells, axis=0)
    if not free[cells[:, 0], cells[:, 1]].all() or np.abs(step).max(initial=0) > 1:
        return False
    diag = (step[:, 0] != 0) & (step[:, 1] != 0)
    a, s = cells[:-1][diag], step[diag]
    if not (free[a[:, 0] + s[:, 0], a[:, 1]].all() and free[a[:, 0], a[:, 1] + s[:, 1]].all()):
        return False
    return abs(np.where(diag, np.sqrt(2.0), 1.0).sum() - value) <= 1e-9 * max(1.0, value)


def run_map(directory: str) -> dict[str, Any]:
    from gridfield.fields.navigation import extract_path, wavefront
    from gridfield.io import read_movingai_map, read_scen

    d = Path(directory)
    map_file, scen_file = map_and_scen(d)
    gm = read_movingai_map(map_file)
    scen = read_scen(scen_file, map_height=gm.shape[0])
    free = ~gm.occupied
    n = len(scen)
    values = np.empty(n)
    paths_ok = 0
    t0 = time.perf_counter()
    for i in range(n):
        nav = wavefront(gm, scen.goal_xy[i], costs="octile")
        v = float(nav.value_at(scen.start_xy[i])[0])
        values[i] = v
        p = extract_path(nav, scen.start_xy[i])
        if np.isinf(v):
            paths_ok += p.status == "no_path"
        else:
            paths_ok += p.status == "reached" and chain_ok(free, p.extra["cells"], v)
    seconds = time.perf_counter() - t0
    reach = ~scen.no_path
    err = np.abs(values - scen.optimal)
    tol = issue_tolerance(scen.precision, scen.digits, scen.optimal)
    ok = np.where(reach, err <= tol, np.isinf(values))
    ok_io = np.where(reach, err <= scen.tolerance(), np.isinf(values))
    worst = int(np.argmax(np.where(reach, err, -1))) if reach.any() else -1
    return {"name": d.name, "shape": gm.shape, "n": n, "ok": int(ok.sum()), "ok_io": int(ok_io.sum()),
            "no_path": int(scen.no_path.sum()), "no_path_ok": int(np.isinf(values[scen.no_path]).sum()),
            "max_err": float(err[reach].max()) if reach.any() else 0.0, "worst": worst,
            "paths_ok": paths_ok, "seconds": seconds, "format": f"{scen.precision} {scen.digits}",
            "failures": [(int(i), float(scen.optimal[i]), float(values[i])) for i in np.flatnonzero(~ok)[:5]]}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, default=DEFAULT_ROOT, help="folder of Moving AI map folders")
    ap.add_argument("--processes", type=int, default=2, help="worker processes (one map each at a time)")
    ap.add_argument("--maps", nargs="*", default=None, help="map folder names (default: all)")
    args = ap.parse_args(argv)
    dirs = sorted(p for p in args.root.iterdir() if p.is_dir() and (not args.maps or p.name in args.maps))
    # largest first, so that the pool stays busy
    dirs.sort(key=lambda p: -sum(f.stat().st_size for f in p.iterdir()))
    t0 = time.perf_counter()
    if args.processes > 1:
        ctx = multiprocessing.get_context("spawn")  # no fork after numba / OpenMP threads
        with ProcessPoolExecutor(args.processes, mp_context=ctx) as pool:
            results = list(pool.map(run_map, [str(d) for d in dirs]))
    else:
        results = [run_map(str(d)) for d in dirs]
    wall = time.perf_counter() - t0
    results.sort(key=lambda r: r["name"].lower())
    print("| map | W x H | scenarios | length format | agree | agree (io) | no-path markers unreachable "
          "| max abs err | paths ok | seconds |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        rows, cols = r["shape"]
        nop = f"{r['no_path_ok']}/{r['no_path']}" if r["no_path"] else "-"
        print(f"| {r['name']} | {cols}x{rows} | {r['n']} | {r['format']} | {r['ok']}/{r['n']} | {r['ok_io']}/{r['n']} "
              f"| {nop} | {r['max_err']:.2g} | {r['paths_ok']}/{r['n']} | {r['seconds']:.1f} |")
        for f in r["failures"]:
            print(f"|   disagreement: scenario {f[0]}: reference {f[1]!r}, wavefront {f[2]!r} | | | | | | | | | |")
    tot = {k: sum(r[k] for r in results) for k in ("n", "ok", "ok_io", "paths_ok", "no_path", "no_path_ok")}
    cpu = sum(r["seconds"] for r in results)
    print(f"| **all {len(results)} maps** | | {tot['n']} | | **{tot['ok']}/{tot['n']}** | {tot['ok_io']}/{tot['n']} "
          f"| {tot['no_path_ok']}/{tot['no_path']} | | {tot['paths_ok']}/{tot['n']} | {cpu:.0f} |")
    print(f"\n{tot['n']} wavefronts + path extractions in {wall:.0f} s wall ({args.processes} processes), "
          f"{cpu / max(tot['n'], 1) * 1e3:.1f} ms per scenario.", file=sys.stdout)
    return 0 if tot["ok"] == tot["n"] and tot["paths_ok"] == tot["n"] else 1


if __name__ == "__main__":
    raise SystemExit(main())
