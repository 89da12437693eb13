"""``gridfield compare``: a grid planner against the exact-geometry planner on a vector world or a
grid map (bitmap, ROS, Moving AI: the exact planners run on its blocked cells as exact polygons, the
grid planner at the map's resolution and on conservatively block-downsampled copies).

Two modes:

- convergence (default): the grid planner at every ``--resolutions`` cell size against the exact
  planner, one table row per resolution, and the observed order of each error;
- ``--batch N``: N random start/goal pairs at ``--resolution``: success rates of the grid and
  exact potential fields and of the octile wavefront, length ratios to the visibility optimum.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Mapping, Sequence
from typing import Any

from ._common import (
    add_map_arguments,
    add_param_arguments,
    add_robot_arguments,
    collect_params,
    load_target,
    robot_target,
)

DEFAULT_RESOLUTIONS = (0.4, 0.2, 0.1, 0.05)
#: On a grid map: the map's resolution times these factors (coarsest first, like the default): block-
#: downsampled above 1, subdivided below (the same free space, so a finer grid always runs where the
#: coarse ones block the start's or goal's cell); the finest only while the grid stays within
#: :data:`GRID_MAX_CELLS`.
GRID_FACTORS = (4, 2, 1, 0.5, 0.25)
#: The most cells a default resolution of a grid map may have (2048 x 2048).
GRID_MAX_CELLS = 1 << 22


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    from ..planners import PLANNERS

    grid_planners = [k for k, v in PLANNERS.items() if v[2] == "grid"] + ["visibility"]
    world_planners = [k for k, v in PLANNERS.items() if v[2] == "world"]
    p = sub.add_parser("compare", help="compare a grid planner with the exact planner (convergence, batch)",
                       description="Run a grid planner at several resolutions against the exact-geometry "
                                   "planner on a vector world or a grid map (exact polygons of its blocked cells; "
                                   "the grid at its resolution, block-downsampled x2, x4 and subdivided x1/2, x1/4) and report path length "
                                   "ratios, Hausdorff and "
                                   "Frechet distances, stall-point errors and clearances; or, with --batch N, "
                                   "success rates and length ratios over N random start/goal pairs.")
    add_map_arguments(p, name="MAP")
    p.add_argument("--start", nargs=2, type=float, metavar=("X", "Y"),
                   help="start point (default: the world file's start)")
    p.add_argument("--goal", nargs=2, type=float, metavar=("X", "Y"),
                   help="goal point (default: the world file's goal)")
    p.add_argument("--scenario", metavar="FILE",
                   help="a Moving AI .scen file: take start and goal from its line --index (as gridfield plan does)")
    p.add_argument("--index", type=int, default=None, metavar="N",
                   help="which scenario of --scenario (0 = the first; default 0)")
    p.add_argument("--resolutions", nargs="+", type=float, metavar="R", default=None,
                   help=f"cell sizes of the convergence study (default: {' '.join(map(str, DEFAULT_RESOLUTIONS))}; on a "
                        f"grid map its resolution times {', '.join(f'{k:g}' for k in GRID_FACTORS)}: coarser "
                        "grids block-downsampled, finer ones subdivided)")
    p.add_argument("--planner", default="potential", choices=grid_planners,
                   help="grid planner (default: potential)")
    p.add_argument("--exact-planner", default=None, choices=world_planners,
                   help="exact planner (default: the exact counterpart of --planner: exact-potential for the "
                        "classic potential field (model khatib), visibility, the exact shortest path, for the "
                        "complete models and the navigation functions, whose paths converge to it)")
    p.add_argument("--batch", type=int, metavar="N", default=None,
                   help="compare on N random start/goal pairs at --resolution instead")
    p.add_argument("--pair-seed", type=int, default=0, metavar="S", help="random seed of the --batch pairs")
    p.add_argument("--no-progress", action="store_true", help="no progress bar in --batch mode")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="F", help="save error vs resolution on log-log axes (convergence mode)")
    add_robot_arguments(p)
    add_param_arguments(p)
    return p


def _clean(v: Any, infinite: dict[str, int] | None = None, where: str = "") -> Any:
    """JSON-safe values: numbers stay numbers, a value that is not finite is null (an infinity is
    noted in ``infinite`` under its place, 1 for +inf and -1 for -inf, as ``plan --json`` does);
    numpy scalars -> Python.

    Examples
    --------
    >>> notes = {}
    >>> _clean({"rows": [{"len": float("inf")}], "n": 2.0}, notes), notes
    ({'rows': [{'len': None}], 'n': 2.0}, {'rows[0].len': 1})
    """
    import numpy as np

    if isinstance(v, bool | np.bool_):
        return bool(v)
    if isinstance(v, int | np.integer):
        return int(v)
    if isinstance(v, float | np.floating):
        f = float(v)
        if math.isinf(f) and infinite is not None:
            infinite[where] = 1 if f > 0 else -1
        return f if math.isfinite(f) else None
    if isinstance(v, Mapping):
        return {str(k): _clean(x, infinite, f"{where}.{k}" if where else str(k)) for k, x in v.items()}
    if isinstance(v, list | tuple | np.ndarray):
        return [_clean(x, infinite, f"{where}[{i}]") for i, x in enumerate(v)]
    return v


def _json(doc: Mapping[str, Any]) -> None:
    infinite: dict[str, int] = {}
    out = _clean(doc, infinite)
    if infinite:
        out["infinite"] = infinite
    json.dump(out, sys.stdout)
    sys.stdout.write("\n")


def _fmt(v: Any, spec: str) -> str:
    if isinstance(v, float) and math.isnan(v):
        width = spec.split(".")[0]
        return "-".rjust(int(width) if width.isdigit() else 1)
    return format(v, spec)


def _print_table(rows: Sequence[Mapping[str, Any]], orders: Mapping[str, float], header: str) -> None:
    print(header)
    print(f"{'resolution':>10} {'cells':>9} {'build ms':>9} {'plan ms':>8} {'status':>14} {'exact':>14} "
          f"{'len/exact':>9} {'len/opt':>8} {'Hausdorff':>9} {'Frechet':>8} {'stall err':>9} {'clearance':>9}")
    from ..compare import no_path_at_resolution

    notes = []
    for r in rows:
        status = r["status"]
        errors = [r["hausdorff"], r["frechet"], r["end_error"]]
        if ":" in status:  # "skipped: why" / "error: why": the word in the table, the reason below it
            word, why = status.split(":", 1)
            notes.append(f"  resolution {r['resolution']:g}: {word}: {why.strip()}")
            status = word
        elif no_path_at_resolution(r):  # its start-only path measures no discretization error
            notes.append(f"  resolution {r['resolution']:g}: no_path: the grid at this resolution (conservative: a "
                         f"cell is blocked if any obstacle touches it) closes the way the exact planner takes; left "
                         f"out of the observed order")
            errors = [math.nan] * 3
        print(f"{r['resolution']:>10g} {r['cells']:>9d} {r['build_ms']:>9.1f} {_fmt(r['plan_ms'], '8.1f')} "
              f"{status:>14} {r['exact_status']:>14} {_fmt(r['length_ratio'], '9.4f')} "
              f"{_fmt(r['length_ratio_optimal'], '8.4f')} {_fmt(errors[0], '9.4f')} {_fmt(errors[1], '8.4f')} "
              f"{_fmt(errors[2], '9.4f')} {_fmt(r['min_clearance'], '9.4f')}"
              + ("  COLLIDES" if r["collides"] else ""))
    for note in notes:
        print(note)
    ran = [r for r in rows if ":" not in r["status"] and not no_path_at_resolution(r)]
    if len(ran) < 2:
        print(f"observed order (error ~ h^p): needs two resolutions that found a path, {len(ran)} did")
        return
    shown = ", ".join(f"{k} {v:.2f}" if not math.isnan(v) else f"{k} - (fewer than two positive errors)"
                      for k, v in orders.items())
    print(f"observed order (error ~ h^p): {shown}")


def _plot(file: str, rows: Sequence[Mapping[str, Any]], title: str) -> str:
    """Draw the errors of the resolutions that ran into ``file`` (one resolution is drawn too, without a
    slope); return the line to print: ``wrote F``, or, when no resolution ran, why nothing was written."""
    import matplotlib.pyplot as plt

    from ..compare import no_path_at_resolution, study_errors
    from ..plot import plot_convergence

    names = {"hausdorff": "Hausdorff", "frechet": "Frechet", "end_error": "stall/end point",
             "length_error": "|length ratio - 1|"}
    from ..core.errors import GridfieldError

    # skipped and failed resolutions have no errors, nor those whose grid closes the way
    ran = [r for r in rows if ":" not in r["status"] and not no_path_at_resolution(r)]
    if not ran:
        return (f"no plot written to {file}: none of the {len(rows)} resolutions ran (see the table); give "
                "--resolutions at which start and goal are free")
    errors = {names[k]: v for k, v in study_errors(ran).items()}
    h = [r["resolution"] for r in ran]

    art = plot_convergence(h, errors, title=title)
    try:
        art.figure.savefig(file, dpi=110, bbox_inches="tight")
    except OSError as e:
        raise GridfieldError(f"{file}: cannot write: {e.strerror or e}") from None
    finally:
        plt.close(art.figure)
    return f"wrote {file}" + (" (one resolution ran: its errors, no order)" if len(ran) == 1 else "")


def _print_batch(result: Mapping[str, Any]) -> None:
    print(f"{result['world'] or 'world'}: {result['pairs']} random pairs at resolution {result['resolution']:g} "
          f"(seed {result['seed']})")
    print(f"{'planner':18} {'success':>8} {'len/opt mean':>12} {'median':>8} {'max':>8}  statuses")
    for name, s in result["planners"].items():
        lr = s["length_ratio"]
        agree = f"  agrees with exact: {s['agreement_with_exact']:.0%}" if "agreement_with_exact" in s else ""
        print(f"{name:18} {s['success_rate']:8.1%} {_fmt(lr['mean'], '12.4f')} {_fmt(lr['median'], '8.4f')} "
              f"{_fmt(lr['max'], '8.4f')}  {s['statuses']}{agree}")
    for name, why in result["skipped"].items():
        print(f"{name:18} skipped: {why}")


def run(args: argparse.Namespace) -> int:
    from ..compare import batch_compare, convergence_study, study_orders
    from ..core.errors import ParameterError
    from ..geometry.world import World
    from ._common import check_figure_file
    from .plan import endpoints

    check_figure_file(args.plot)
    target = load_target(args)
    grid_res = None if isinstance(target, World) or isinstance(target.world, World) else target.grid.resolution
    params = collect_params(args)
    if args.batch is not None:
        target = robot_target(args, target)
        if args.batch < 1:
            raise ParameterError(f"--batch must be a positive number of pairs, got {args.batch}")
        if args.plot:
            raise ParameterError("--plot draws the convergence study; leave it out with --batch")
        resolution = args.resolution if args.resolution is not None else (
            grid_res if grid_res is not None else target.resolution)
        if resolution is None:
            raise ParameterError(f"{args.map} sets no resolution; pass --resolution R with --batch")
        result = batch_compare(target, args.batch, resolution=resolution, params=params, seed=args.pair_seed,
                               progress=not args.no_progress)
        if args.json:
            out = dict(result)
            out["world"] = args.map
            _json(out)
        else:
            _print_batch(result)
        return 0

    from .plan import scenario

    scen = scenario(args, target)
    start, goal = (scen[0], scen[1]) if scen is not None else endpoints(args, target)
    target = robot_target(args, target, start=start, goal=goal)
    if args.resolutions is not None:
        resolutions = args.resolutions
    elif grid_res is not None:  # a grid map: its own resolution, block-downsampled and subdivided copies
        cells = target.grid.rows * target.grid.cols
        resolutions = [grid_res * k for k in GRID_FACTORS if k >= 1 or cells / (k * k) <= GRID_MAX_CELLS]
    else:
        resolutions = list(DEFAULT_RESOLUTIONS)
    if args.exact_planner is None:
        args.exact_planner = exact_counterpart(args.planner, target, params)
    rows = convergence_study(target, start, goal, resolutions, params=params, grid_planner=args.planner,
                             exact_planner=args.exact_planner)
    orders = study_orders(rows)
    if args.json:
        _json({"world": args.map, "start": list(start), "goal": list(goal), "planner": args.planner,
               "exact_planner": args.exact_planner, "rows": rows, "order": orders,
               **({"optimal": scen[2]} if scen is not None else {})})
    else:
        opt = f", scenario's octile optimum {scen[2]:.4g}" if scen is not None else ""
        _print_table(rows, orders, f"{args.map}: {args.planner} (grid) vs {args.exact_planner} (exact), "
                                   f"start ({start[0]:g}, {start[1]:g}) goal ({goal[0]:g}, {goal[1]:g}){opt}")
    if args.plot:
        print(_plot(args.plot, rows, f"{args.planner} vs {args.exact_planner}"),
              file=sys.stderr if args.json else sys.stdout)
    return 0


def exact_counterpart(planner: str, target: Any, params: dict[str, Any]) -> str:
    """The exact planner a grid planner converges to: ``exact-potential`` for the classic potential field
    (the potential planner with ``model`` khatib or vortex, from the command line or the world file),
    ``visibility`` (the shortest path) for the complete models, the potential planner's default, and the
    navigation functions.

    Examples
    --------
    >>> exact_counterpart("potential", None, {"model": "khatib"}), exact_counterpart("potential", None, {})
    ('exact-potential', 'visibility')
    """
    from ..geometry.world import World

    if planner != "potential":
        return "visibility"
    world = target if isinstance(target, World) else getattr(target, "world", None)
    base = dict(world.params) if isinstance(world, World) else {}
    model = {**base, **params}.get("model")
    return "exact-potential" if model in ("khatib", "vortex") else "visibility"

