"""``gridfield sweep``: run a batch of planner runs from a YAML spec."""

from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser("sweep", help="run a sweep of planners x maps x start/goal pairs x parameters",
                       description="Run every (map, start/goal pair, planner, parameter combination) of a sweep "
                                   "spec; write one CSV row per run and a summary. Rows already in the output "
                                   "are not recomputed (resume). len/opt is the mean length ratio to the scenario file's (octile) "
                                   "optimum, len/any to the exact any-angle optimum (spec key optimal_any_angle: true).")
    p.add_argument("spec", metavar="SPEC.yaml", help="sweep spec (see gridfield.sweep)")
    p.add_argument("--out", metavar="F", help="rows file (CSV; default: the spec's 'output')")
    p.add_argument("--workers", type=int, default=None, help="local processes (default: all cores)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="run on a Dask distributed scheduler instead")
    p.add_argument("--batch-size", type=int, default=None, metavar="N",
                   help="runs per task (default: a few tasks per worker and map, at most 256 runs each)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    from ._common import add_max_cells_argument

    add_max_cells_argument(p)
    return p


def run(args: argparse.Namespace) -> int:
    from ..core.errors import ParameterError
    from ..sweep import SweepInterrupted, load_spec, run_sweep, summarize

    if args.workers is not None and args.workers < 1:
        raise ParameterError(f"--workers must be at least 1, got {args.workers}")
    if args.batch_size is not None and args.batch_size < 1:
        raise ParameterError(f"--batch-size must be at least 1, got {args.batch_size}")
    runs, output = load_spec(args.spec, output=args.out)
    notes: list[str] = []
    try:
        rows = run_sweep(runs, output, workers=args.workers, scheduler=args.scheduler, batch_size=args.batch_size,
                         progress=not args.no_progress and sys.stderr.isatty(), notes=notes)
    except SweepInterrupted as e:
        import signal

        print(f"gridfield sweep: stopped by {signal.Signals(e.signum).name}; the rows written to {output} are kept: "
              "run the same command again to resume", file=sys.stderr)
        return 128 + e.signum
    finally:
        for note in notes:
            print(f"gridfield sweep: {note}", file=sys.stderr)
    summary = summarize(rows)
    summary_path = output.with_name(output.stem + ".summary.csv")
    with summary_path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(summary[0]) if summary else ["map"])
        w.writeheader()
        w.writerows(summary)
    print(f"{'map':30} {'planner':18} {'runs':>5} {'success':>8} {'len/opt':>8} {'len/any':>8} {'ms med':>8}  params")
    for s in summary:
        ratio, any_ratio = ("" if math.isnan(s[k]) else f"{s[k]:.4f}" for k in ("length_ratio", "length_ratio_any_angle"))
        print(f"{Path(s['map']).name[:30]:30} {s['planner']:18} {s['runs']:5d} {s['success_rate']:8.1%} "
              f"{ratio:>8} {any_ratio:>8} {s['ms_median']:8.2f}  {s['params']}")
    print(f"wrote {len(rows)} rows to {output} and the summary to {summary_path}")
    return 0
