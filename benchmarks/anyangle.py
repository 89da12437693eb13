"""Any-angle optimum on Moving AI maps (``gridfield.exact.anyangle``) beside the octile wavefront.

Run ``python benchmarks/anyangle.py [--root tests/data/maps/movingai] [--maps NAME ...] [--queries 50]
[--no-lazy] [--compare-numba OLD.py]``.
For each map: the per-map part (convex corners, their buckets, the blocked runs: all the lazy search
needs), then the visibility graph, then the navigation mesh of the Polyanya search are built once in
this process (each timed; kernels warmed up on a tiny map first; wall-clock and process CPU seconds, the latter less sensitive to other jobs on
a shared machine), then ``--queries`` scenarios spread evenly over the ``.scen`` file are answered,
each by

- ``graph query``: :meth:`AnyAngleGraph.shortest_path` with ``search="graph"``, the graph cached
  (the two visibility passes from start and goal, then A* over the graph);
- ``lazy query`` (unless ``--no-lazy``): ``search="lazy"``, A* over the corners whose visible
  neighbours are found when a corner is expanded (no graph); checked against the graph search's
  length (1e-9 relative) and for free segments (``lazy failed``);
- ``polyanya query``: ``search="polyanya"`` (the default), Polyanya over the navigation mesh (built
  once per map beforehand, timed as ``mesh build``; its polygons counted), with the nodes it expanded
  (median); checked against the graph search's length (1e-9 relative) and for free segments
  (``polyanya failed``);
- ``plan('visibility')``: the public call on the map with a cache (query + result checks + clearance;
  the default search, Polyanya);
- ``plan('wavefront-octile')``: the octile wavefront from the goal and its descent, the same query.

They run interleaved query by query, so that load from other jobs on the machine hits them
alike. Every answer is checked: never longer than the file's octile optimum (within the file's
printed precision), never shorter than the straight line, every path segment free
(:meth:`AnyAngleGraph.visible`). Prints one markdown row per map; the numbers of the committed run
are in ``benchmarks/README.md`` ("Any-angle optimum on grid maps").

``--compare-numba OLD.py``: then, per map, the graph build (``--rounds`` times, alternated) and the
same queries (interleaved query by query) with the compiled kernels and with the numba kernels of an
older checkout (``git show 3fd2f69:gridfield/_kernels_anyangle.py > /tmp/old.py``; needs numba, in the
``bench`` extra), side by side; the two graphs must have the same edges and the two answers the same
length, bit for bit.
"""

from __future__ import annotations

import argparse
import itertools
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _common import TEST_MAPS, map_and_scen  # noqa: E402

DEFAULT_ROOT = TEST_MAPS / "movingai"
DEFAULT_MAPS = ("AR0011SR", "16room_000", "random512-10-0")
#: The functions of gridfield.exact.anyangle that return its kernel modules (segment walk, occlusion-culled
#: visibility, A*): --compare-numba swaps all of them for the one old module, which holds every kernel.
KERNEL_HELPERS = ("_kernel_anyangle", "_kernel_occlusion", "_kernel_astar")


def _warm_up() -> None:
    from gridfield.core.grid import Grid, GridMap
    from gridfield.exact.anyangle import grid_graph
    from gridfield.planners import plan

    occ = np.zeros((12, 12), bool)
    occ[3:9, 5] = True
    gm = GridMap(Grid((12, 12), 1.0, border="wall"), occ)
    g = grid_graph(gm, cache={})
    for search in ("graph", "lazy", "polyanya"):
        g.shortest_path((0.5, 5.5), (11.5, 5.5), search=search)
    plan("wavefront-octile", gm, (0.5, 5.5), (11.5, 5.5))


def bench_map(folder: Path, n_queries: int, lazy: bool = True) -> dict:
    from gridfield.exact.anyangle import grid_graph
    from gridfield.io import read_movingai_map, read_scen
    from gridfield.planners import plan

    map_file, scen_file = map_and_scen(folder)
    scen = read_scen(scen_file)
    m = read_movingai_map(map_file)
    cache: dict = {}
    t0, c0 = time.perf_counter(), time.process_time()
    graph = grid_graph(m, cache=cache)
    prep, prep_cpu = time.perf_counter() - t0, time.process_time() - c0
    graph.edges  # noqa: B018  (the visibility graph: built on first use)
    build, build_cpu = time.perf_counter() - t0, time.process_time() - c0
    t0, c0 = time.perf_counter(), time.process_time()
    polygons = graph.mesh.n_polygons  # the navigation mesh of the Polyanya search: built on first use
    mesh, mesh_cpu = time.perf_counter() - t0, time.process_time() - c0
    ok_idx = np.flatnonzero(~scen.no_path & (scen.optimal > 0))
    idx = ok_idx[np.linspace(0, len(ok_idx) - 1, min(n_queries, len(ok_idx))).astype(int)]
    tol = scen.tolerance()
    t_q, t_plan, t_oct, ratios, t_lazy, t_poly, expanded = [], [], [], [], [], [], []
    bad = bad_lazy = bad_poly = 0
    for k in idx:
        s, g = scen.start_xy[k], scen.goal_xy[k]
        t0 = time.perf_counter()
        pts, length = graph.shortest_path(s, g, search="graph")
        t_q.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        ppts, plen, pexp = graph._search(s, g, "polyanya")  # shortest_path's body, with the expansions
        t_poly.append(time.perf_counter() - t0)
        expanded.append(pexp)
        if not (abs(plen - length) <= 1e-9 * length and all(graph.visible(a, b) for a, b in itertools.pairwise(ppts))):
            bad_poly += 1
        if lazy:
            t0 = time.perf_counter()
            lpts, llen = graph.shortest_path(s, g, search="lazy")
            t_lazy.append(time.perf_counter() - t0)
            if not (abs(llen - length) <= 1e-9 * length and all(graph.visible(a, b) for a, b in itertools.pairwise(lpts))):
                bad_lazy += 1
        t0 = time.perf_counter()
        p = plan("visibility", m, s, g, cache=cache)
        t_plan.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        o = plan("wavefront-octile", m, s, g, cache=cache)
        t_oct.append(time.perf_counter() - t0)
        opt = float(scen.optimal[k])
        segs_ok = all(graph.visible(a, b) for a, b in itertools.pairwise(pts))
        if not (math.isfinite(length) and length <= opt + tol[k] and length >= math.dist(s, g) - 1e-9
                and segs_ok and abs(p.length - length) <= 1e-9 * length and o.status == "reached"):
            bad += 1
        ratios.append(opt / length)
    ms = lambda v: statistics.median(v) * 1e3  # noqa: E731
    return {
        "map": folder.name, "shape": m.shape, "corners": graph.n_nodes, "edges": graph.n_edges, "build_s": build,
        "build_cpu_s": build_cpu, "prep_s": prep, "prep_cpu_s": prep_cpu,
        "lazy_ms": ms(t_lazy) if t_lazy else math.nan, "lazy_max_ms": max(t_lazy) * 1e3 if t_lazy else math.nan,
        "bad_lazy": bad_lazy,
        "polygons": polygons, "mesh_s": mesh, "mesh_cpu_s": mesh_cpu, "poly_ms": ms(t_poly),
        "poly_max_ms": max(t_poly) * 1e3, "poly_expanded": statistics.median(expanded), "bad_poly": bad_poly,
        "queries": len(idx), "query_ms": ms(t_q), "query_max_ms": max(t_q) * 1e3, "plan_ms": ms(t_plan),
        "octile_ms": ms(t_oct), "ratio_median": statistics.median(ratios), "ratio_max": max(ratios), "bad": bad,
    }


def load_numba(path: Path):
    """The numba kernel module of an older checkout, loaded from ``path`` inside the package."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"gridfield._old_{path.stem}", path)
    if spec is None or spec.loader is None:
        raise SystemExit(f"error: cannot load {path}")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def compare_numba(folder: Path, n_queries: int, old, rounds: int) -> dict:
    """Build and query times with the compiled kernels (``None``) and ``old``, side by side."""
    import gridfield.exact.anyangle as aa
    from gridfield.io import read_movingai_map, read_scen

    own = {name: getattr(aa, name) for name in KERNEL_HELPERS}

    def use(k) -> None:
        for name, loader in own.items():
            setattr(aa, name, loader if k is None else (lambda: k))

    map_file, scen_file = map_and_scen(folder)
    m, scen = read_movingai_map(map_file), read_scen(scen_file)
    build: dict = {None: [], "old": []}
    graphs = {}
    try:
        pair = ((None, None), ("old", old))
        for r in range(rounds):  # alternating order: the second run of a pair finds warm caches
            for key, k in (pair if r % 2 == 0 else pair[::-1]):
                use(k)
                c0 = time.process_time()
                graphs[key] = aa._build(m)
                graphs[key].edges  # noqa: B018  (the graph is built on first use)
                build[key].append(time.process_time() - c0)
        if not np.array_equal(graphs[None].edges, graphs["old"].edges):
            raise SystemExit(f"error: {folder.name}: the two graphs differ")
        graph = graphs[None]
        ok_idx = np.flatnonzero(~scen.no_path & (scen.optimal > 0))
        idx = ok_idx[np.linspace(0, len(ok_idx) - 1, min(n_queries, len(ok_idx))).astype(int)]
        query: dict = {None: [], "old": []}
        for i, kq in enumerate(idx):
            s, g = scen.start_xy[kq], scen.goal_xy[kq]
            lengths = []
            for key, k in (pair if i % 2 == 0 else pair[::-1]):
                use(k)
                t0 = time.perf_counter()
                lengths.append(graph.shortest_path(s, g, search="graph")[1])
                query[key].append(time.perf_counter() - t0)
            if lengths[0] != lengths[1]:
                raise SystemExit(f"error: {folder.name}: query {kq} lengths differ: {lengths}")
    finally:
        use(None)
    med = statistics.median
    return {"map": folder.name, "build": med(build[None]), "build_old": med(build["old"]),
            "query_ms": med(query[None]) * 1e3, "query_old_ms": med(query["old"]) * 1e3, "queries": len(idx)}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, default=DEFAULT_ROOT, help="folder of the Moving AI map folders")
    ap.add_argument("--maps", nargs="+", default=list(DEFAULT_MAPS), help="map folder names")
    ap.add_argument("--queries", type=int, default=50, help="scenarios per map (spread over the file)")
    ap.add_argument("--no-lazy", action="store_true", help="do not run the lazy search (search='lazy')")
    ap.add_argument("--compare-numba", type=Path, default=None, metavar="OLD.py",
                    help="also time this numba _kernels_anyangle.py side by side (needs numba)")
    ap.add_argument("--rounds", type=int, default=3, help="graph builds per kernel module with --compare-numba")
    args = ap.parse_args(argv)
    _warm_up()
    old = None if args.compare_numba is None else load_numba(args.compare_numba)
    print("| map | size | convex corners | graph edges | per-map part s (wall / CPU) | graph build s (wall / CPU) "
          "| mesh polygons | mesh build s (wall / CPU) | queries "
          "| graph query ms (median / max) | polyanya query ms (median / max) | polyanya expanded (median) "
          "| lazy query ms (median / max) "
          "| plan('visibility') ms | plan('wavefront-octile') ms | octile / any-angle (median / max) | failed checks "
          "| polyanya failed | lazy failed |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    failed = 0
    for name in args.maps:
        r = bench_map(args.root / name, args.queries, lazy=not args.no_lazy)
        failed += r["bad"] + r["bad_lazy"] + r["bad_poly"]
        print(f"| {r['map']} | {r['shape'][1]} x {r['shape'][0]} | {r['corners']} | {r['edges']} "
              f"| {r['prep_s']:.3f} / {r['prep_cpu_s']:.3f} | {r['build_s']:.2f} / {r['build_cpu_s']:.2f} "
              f"| {r['polygons']} | {r['mesh_s']:.3f} / {r['mesh_cpu_s']:.3f} "
              f"| {r['queries']} | {r['query_ms']:.2f} / {r['query_max_ms']:.1f} | {r['poly_ms']:.2f} / {r['poly_max_ms']:.1f} "
              f"| {r['poly_expanded']:.0f} | {r['lazy_ms']:.2f} / {r['lazy_max_ms']:.1f} "
              f"| {r['plan_ms']:.2f} | {r['octile_ms']:.1f} | {r['ratio_median']:.4f} / {r['ratio_max']:.4f} | {r['bad']} "
              f"| {r['bad_poly']} | {r['bad_lazy']} |", flush=True)
    if old is not None:
        import gridfield.exact.anyangle as aa

        own = {name: getattr(aa, name) for name in KERNEL_HELPERS}
        for name in KERNEL_HELPERS:  # warm-up (numba cache load) of the old kernels
            setattr(aa, name, lambda: old)
        _warm_up()
        for name, loader in own.items():
            setattr(aa, name, loader)
        print(f"\ncompiled kernels vs numba ({args.compare_numba}), side by side: graph build (CPU s, median of "
              f"{args.rounds}) and query (ms, median, interleaved; both in alternating order)\n")
        print("| map | build compiled | build numba | ratio | queries | query compiled | query numba | ratio |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        for name in args.maps:
            r = compare_numba(args.root / name, args.queries, old, args.rounds)
            print(f"| {r['map']} | {r['build']:.3f} | {r['build_old']:.3f} | {r['build'] / r['build_old']:.2f} "
                  f"| {r['queries']} | {r['query_ms']:.3f} | {r['query_old_ms']:.3f} "
                  f"| {r['query_ms'] / r['query_old_ms']:.2f} |", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
