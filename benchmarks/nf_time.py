"""Time per query of the ``potential`` planner's default (nf1) beside ``wavefront-octile`` (issue 25).

Run ``PYTHONPATH=. python benchmarks/nf_time.py [--maps-root tests/data/maps] [--per-map 20]
[--maps 16room_000,64room_000,...] [--params '{"model": "nf1"}'] [--repeat 3] [--plain]
[--weight W]``.

For every Moving AI map given (default: the six 512x512 maps of the issue's target), ``--per-map``
scenarios spread evenly over the file in bucket order (``potential_real.movingai_sample``, reachable
ones only). Each query goes through the public entry point with one warm cache per map (the
brushfire computed once, as a batch user keeps it): ``plan("potential", gm, s, g, params,
cache=cache)`` and ``plan("wavefront-octile", gm, s, g, {}, cache=cache)``, alternately
(``_common.round_robin``: one run of each per round, ``--repeat`` rounds, the median per query), so
that load from other jobs hits both alike. Reported per map: the median over the queries of the
potential planner's time, of the wavefront's, and the median of the per-query ratios; and how many
potential paths reached. The issue's target: ratio <= 3 and potential <= 10 ms. ``--plain`` adds a
third candidate to the same rounds: the potential planner with ``gridfield.fields.navfield.ASTAR_WEIGHT``
set to 0 (the plain, Dijkstra-ordered truncated march: the behaviour before the A* order).

The machine's load average is printed with the table; compare ratios within one run.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import TEST_MAPS, map_and_scen, markdown_table, round_robin
from potential_real import movingai_sample

MAPS = ("16room_000", "64room_000", "8room_000", "AR0011SR", "maze512-32-9", "random512-10-0")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--maps-root", default=str(TEST_MAPS))
    ap.add_argument("--maps", default=",".join(MAPS))
    ap.add_argument("--per-map", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--params", default="{}", help="JSON params of the potential planner (default: {})")
    ap.add_argument("--plain", action="store_true", help="also time the plain-order truncated march (ASTAR_WEIGHT 0)")
    ap.add_argument("--weight", type=float, default=None,
                    help="run the potential planner with gridfield.fields.navfield.ASTAR_WEIGHT set to this (default: the "
                         "library's, 1.25; it was 0.7, then 1.0, during stop 38)")
    args = ap.parse_args(argv)

    from gridfield.fields import navfield
    from gridfield.io import read_movingai_map, read_scen
    from gridfield.planners import plan

    if args.weight is not None:
        navfield.ASTAR_WEIGHT = args.weight
    weight = navfield.ASTAR_WEIGHT

    def plain(gm, s, g, params, cache):
        navfield.ASTAR_WEIGHT = 0.0
        try:
            return plan("potential", gm, s, g, params, cache=cache)
        finally:
            navfield.ASTAR_WEIGHT = weight

    params = json.loads(args.params)
    rows = []
    all_ratios: list[float] = []
    all_ms: list[float] = []
    for name in args.maps.split(","):
        d = Path(args.maps_root) / "movingai" / name
        map_file, scen_file = map_and_scen(d)
        gm = read_movingai_map(map_file)
        scen = read_scen(scen_file, map_height=gm.shape[0])
        idx = [i for i in movingai_sample(scen.bucket, scen.no_path, args.per_map).tolist() if not scen.no_path[i]]
        cache: dict = {}
        tp, tw, tq, ratios, reached = [], [], [], [], 0
        for i in idx:
            s, g = scen.start_xy[i], scen.goal_xy[i]
            reached += plan("potential", gm, s, g, params, cache=cache).status == "reached"
            cands = {"potential": lambda s=s, g=g, gm=gm, c=cache: plan("potential", gm, s, g, params, cache=c),
                     "wavefront-octile": lambda s=s, g=g, gm=gm, c=cache: plan("wavefront-octile", gm, s, g, {}, cache=c)}
            if args.plain:
                cands["plain"] = lambda s=s, g=g, gm=gm, c=cache: plain(gm, s, g, params, c)
            res = round_robin(cands, repeat=args.repeat)
            a, b = res["potential"].median_ms, res["wavefront-octile"].median_ms
            if args.plain:
                tq.append(res["plain"].median_ms)
            tp.append(a)
            tw.append(b)
            ratios.append(a / b)
        all_ratios += ratios
        all_ms += tp
        rows.append([name, "x".join(map(str, gm.shape)), f"{len(idx)}", f"{reached}/{len(idx)}",
                     f"{statistics.median(tp):.1f}", f"{statistics.median(tw):.1f}", f"{statistics.median(ratios):.2f}"]
                    + ([f"{statistics.median(tq):.1f}", f"{statistics.median(np.array(tq) / np.array(tw)):.2f}"]
                       if args.plain else []))
        print(*rows[-1], flush=True, file=sys.stderr)
    print(f"params: {json.dumps(params)}; ASTAR_WEIGHT {weight:g}; load average: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    print(markdown_table(["map", "shape", "queries", "reached", "potential ms (median)", "wavefront-octile ms (median)",
                          "ratio (median per query)"]
                         + (["plain order ms (median)", "plain ratio (median per query)"] if args.plain else []), rows))
    print(f"\nall maps: median ratio {statistics.median(all_ratios):.2f}, p90 {np.percentile(all_ratios, 90):.2f}; "
          f"potential ms per query median {statistics.median(all_ms):.1f}, p90 {np.percentile(all_ms, 90):.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
