"""``gridfield costmap``: a map's Nav2 inflated costmap (costmap_2d's inflation layer), written for map_server."""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any

from ._common import add_map_arguments, check_figure_file


def _number(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return v


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "costmap", help="Nav2 inflated costmap of a map (costmap_2d inflation layer), as a map_server YAML + PGM",
        description="Inflate a map's obstacles into ROS 2 Nav2's costmap costs (254 lethal, 253 within the robot "
                    "radius, 252 * exp(-K * (d - robot radius)) out to the inflation radius, 0 beyond), on exact "
                    "Euclidean distances. Prints a one-line summary; writes the costmap as a map_server YAML "
                    "(mode: raw) + PGM that 'gridfield plan COSTMAP.yaml --planner navfn' plans on and "
                    "gridfield reads back bit-exactly; optionally a figure and the costmap's values at a point.")
    add_map_arguments(p)
    p.add_argument("--robot-radius", type=_number, default=0.1, metavar="R",
                   help="inscribed radius of the robot, world units (default 0.1, Nav2's robot_radius)")
    p.add_argument("--inflation-radius", type=_number, default=0.55, metavar="R",
                   help="how far costs spread from the obstacles, world units (default 0.55)")
    p.add_argument("--cost-scaling-factor", type=_number, default=10.0, metavar="K",
                   help="exponential decay rate of the costs, 1 / world unit (default 10)")
    p.add_argument("--lut-precision", type=int, default=None, metavar="N",
                   help="round distances to 1/N cell first, as the current Nav2 inflation layer (N = 100); "
                        "default: exact distances (the legacy layer)")
    p.add_argument("--keep-unknown", action="store_true",
                   help="keep a ROS map's unknown cells as 255 (no information) unless inflated to 253 or more; "
                        "they are not obstacles")
    p.add_argument("--out", metavar="F.yaml", help="write the costmap: F.yaml and F.pgm beside it")
    p.add_argument("--plot", metavar="F", help="save a figure of the costs (PNG, PDF, SVG, ...)")
    p.add_argument("--query", nargs=2, type=_number, metavar=("X", "Y"),
                   help="print the cost, obstacle distance, gradient and nearest obstacle at the point (X, Y)")
    return p


def _load(args: argparse.Namespace) -> Any:
    import numpy as np

    from ..core.errors import ParameterError
    from ..fields.costmap import inflate
    from ..geometry.rasterize import as_gridmap
    from ..io import read, read_yaml, ros_occupancy_values
    from ._common import load_target, occupancy_options

    unknown = None
    gm: Any
    suffix = Path(args.map).suffix.lower()
    if args.keep_unknown:
        data = read_yaml(args.map) if suffix in (".yaml", ".yml") else None
        if not (isinstance(data, dict) and "image" in data and "costmap" not in data):
            raise ParameterError(f"{args.map}: --keep-unknown needs a ROS map YAML (one with unknown cells)")
        if args.unknown is not None:
            raise ParameterError("--keep-unknown and --unknown exclude each other (kept unknown cells are neither)")
        unknown = ros_occupancy_values(args.map) == -1
        gm = read(args.map, unknown="free", **occupancy_options(args))  # a ROS map: --occupancy is refused
    else:
        gm = as_gridmap(load_target(args), args.resolution)
    if unknown is not None and unknown.shape != gm.shape:  # pragma: no cover - same file
        raise ParameterError(f"{args.map}: the unknown cells do not match the map")
    return inflate(gm, robot_radius=args.robot_radius, inflation_radius=args.inflation_radius,
                   cost_scaling_factor=args.cost_scaling_factor, keep_unknown=args.keep_unknown,
                   unknown=None if unknown is None else np.asarray(unknown, bool), lut_precision=args.lut_precision)


def _save_plot(cm: Any, file: str) -> None:
    import numpy as np
    from matplotlib.figure import Figure

    from ..core.errors import GridfieldError

    g = cm.grid
    fig = Figure(figsize=(7.5, max(2.5, min(12.0, 6.5 * g.rows / g.cols + 1.0))), layout="constrained")
    ax = fig.add_subplot()
    shown = np.ma.masked_equal(cm.cost.astype(float), 255.0)
    im = ax.imshow(shown, origin="lower", extent=g.extent, cmap="magma_r", vmin=0, vmax=254, interpolation="nearest")
    fig.colorbar(im, ax=ax, label="Nav2 cost (254 lethal, 253 inscribed; unknown blank)")
    name = Path(cm.source).name if cm.source else "map"
    ax.set_title(f"{name}: inflated costmap")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    try:
        fig.savefig(file, dpi=110)
    except OSError as e:
        raise GridfieldError(f"{file}: cannot write: {e.strerror or e}") from None
    except ValueError as e:
        raise GridfieldError(f"{file}: {e}") from None


def summary(cm: Any, ms: float) -> str:
    """One line: shape, the inflation, the share of each cost class, time."""
    import numpy as np

    g = cm.grid
    c = cm.cost
    n = max(c.size, 1)
    share = {name: float(np.count_nonzero(mask)) / n for name, mask in (
        ("lethal", c == 254), ("inscribed", c == 253), ("inflated", (c > 0) & (c < 253)), ("free", c == 0),
        ("unknown", c == 255))}
    inf = cm.inflation
    parts = ", ".join(f"{v:.1%} {k}" for k, v in share.items() if v or k != "unknown")
    lut = f", LUT 1/{inf['lut_precision']} cell" if inf.get("lut_precision") else ""
    return (f"costmap {g.rows}x{g.cols} cells of {g.resolution:g} (robot radius {inf['robot_radius']:g}, inflation "
            f"radius {inf['inflation_radius']:g}, cost scaling {inf['cost_scaling_factor']:g}{lut}): {parts}, "
            f"{ms:.1f} ms")


def run(args: argparse.Namespace) -> int:
    from ..core.errors import GridfieldError

    check_figure_file(args.plot)
    if args.out is not None:
        out = Path(args.out)
        if out.suffix.lower() not in (".yaml", ".yml"):
            raise GridfieldError(f"--out {args.out}: the costmap is a map_server YAML: name it F.yaml")
        if not out.resolve().parent.is_dir():
            raise GridfieldError(f"{args.out}: the folder {out.parent} does not exist")
    t0 = time.perf_counter()
    cm = _load(args)
    ms = 1000 * (time.perf_counter() - t0)
    print(summary(cm, ms))
    if args.query is not None:
        x, y = args.query
        pt = [[x, y]]
        c = int(cm.cost_at(pt)[0])
        d = float(cm.distance(pt)[0])
        gx, gy = (float(v) for v in cm.gradient(pt)[0])
        ox, oy = (float(v) for v in cm.nearest_obstacle(pt)[0])
        print(f"at ({x:g}, {y:g}): cost {c}, obstacle distance {d:.6g}, gradient ({gx:.6g}, {gy:.6g}), "
              f"nearest obstacle ({ox:.6g}, {oy:.6g})")
    if args.out is not None:
        from ..io import write_costmap

        write_costmap(args.out, cm)
        print(f"wrote {args.out} and {Path(args.out).with_suffix('.pgm').name}")
    if args.plot is not None:
        _save_plot(cm, args.plot)
        print(f"wrote {args.plot}")
    return 0
