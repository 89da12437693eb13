"""``gridfield explore``: the interactive explorer (click start/goal, draw obstacles, move sliders)."""

from __future__ import annotations

import argparse
import sys

from ._common import add_map_arguments, add_param_arguments, collect_params, load_target


def add_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "explore", help="open the interactive explorer on a map",
        description="Open an interactive window: left clicks set the start and then the goal; the "
                    "'draw obstacle' button lets clicks add polygon vertices (right click closes the polygon); "
                    "sliders set zeta, eta, q_star, d_star and step; radio buttons switch the planner. "
                    "Needs an interactive matplotlib backend (e.g. MPLBACKEND=TkAgg or QtAgg).")
    add_map_arguments(p)
    p.add_argument("--start", nargs=2, type=float, metavar=("X", "Y"), help="start point (default: the world's)")
    p.add_argument("--goal", nargs=2, type=float, metavar=("X", "Y"), help="goal point (default: the world's)")
    # checked in run(): importing gridfield.explore here would load shapely for every `gridfield --help`
    p.add_argument("--planner", default="potential",
                   help="planner shown first: potential (default), exact-potential or wavefront-octile")
    p.add_argument("--save", metavar="F",
                   help="do not open a window: save a snapshot of the explorer (PNG) and exit (works headless)")
    add_param_arguments(p)
    return p


def _interactive_backend() -> bool:
    import matplotlib
    from matplotlib.backends import BackendFilter, backend_registry

    backend = matplotlib.get_backend().lower()
    return backend not in backend_registry.list_builtin(BackendFilter.NON_INTERACTIVE) and not backend.startswith(
        "module://matplotlib_inline")


def run(args: argparse.Namespace) -> int:
    from ..errors import GridfieldError, ParameterError
    from ..explore import EXPLORER_PLANNERS, Explorer

    if args.planner not in EXPLORER_PLANNERS:
        raise ParameterError(f"--planner must be one of {', '.join(EXPLORER_PLANNERS)}, got {args.planner!r}")
    from ._common import check_figure_file

    check_figure_file(args.save, "--save")
    target = load_target(args)
    if args.save is None and not _interactive_backend():
        import matplotlib

        raise GridfieldError(
            f"matplotlib's backend {matplotlib.get_backend()!r} cannot open a window; set MPLBACKEND to an "
            "interactive one (TkAgg, QtAgg) or pass --save F to write a snapshot instead")
    explorer = Explorer(target, params=collect_params(args), planner=args.planner, resolution=args.resolution,
                        start=args.start, goal=args.goal)
    if args.save is not None:
        try:
            explorer.figure.savefig(args.save, dpi=100)
        except (OSError, ValueError) as e:
            explorer.close()
            raise GridfieldError(f"{args.save}: cannot write the snapshot: {e}") from None
        explorer.close()
        print(f"wrote {args.save}: {explorer.message}")
        return 0
    import matplotlib.pyplot as plt

    print(explorer.message, file=sys.stderr)
    plt.show()
    return 0
