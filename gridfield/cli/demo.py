"""``gridfield demo``: run the bundled maps through the pipeline and write figures and a summary."""

from __future__ import annotations

import argparse


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    from ..demo import DEMO_PARTS

    p = sub.add_parser(
        "demo", help="run the bundled maps and worlds through every planner and write figures",
        description="Load every bundled map and world, run the brushfire, the potential field, the follower, "
                    "the exact and wavefront planners, and write PNG figures, a GIF and a summary table "
                    "(summary.md, summary.csv) to DIR.")
    p.add_argument("--out", metavar="DIR", default="gridfield-demo",
                   help="output folder, created if missing (default: ./gridfield-demo)")
    p.add_argument("--quick", action="store_true", help="coarser grids and fewer frames (a few seconds faster)")
    p.add_argument("--part", action="append", choices=list(DEMO_PARTS), dest="parts", metavar="PART",
                   help=f"run only this part (repeatable): {', '.join(DEMO_PARTS)}")
    return p


def run(args: argparse.Namespace) -> int:
    from ..demo import demo, format_table

    result = demo(args.out, quick=args.quick, parts=args.parts, log=print)
    print()
    print(format_table(result.rows))
    print()
    if result.skipped:
        print(f"{len(result.skipped)} step(s) skipped (see above and summary.md)")
    print(f"wrote {len(result.files)} files to {result.out_dir.resolve()} in {result.seconds:.1f} s "
          f"(open {result.out_dir / 'summary.md'})")
    return 0
