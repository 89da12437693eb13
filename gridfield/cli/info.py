"""``gridfield info``: describe a map or world file (shape, resolution, origin, border, obstacles)."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from ._common import add_robot_arguments, robot_target


def add_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "info",
        help="describe a map: shape, resolution, origin, border, occupied fraction, obstacle count",
        description="Load a map or world file and describe its occupancy grid.",
    )
    p.add_argument("map", metavar="MAP",
                   help="world YAML, ROS map YAML, bitmap (PNG/PGM/BMP), Moving AI .map or gridfield .npz")
    p.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    p.add_argument("--npz", metavar="F", help="also write the occupancy grid to the .npz file F")
    p.add_argument("--resolution", type=float, default=None,
                   help="cell size: rasterizes a vector world (default: the world file's 'resolution'); "
                        "for a bitmap, the size of one pixel (default 1)")
    p.add_argument("--unknown", choices=("occupied", "free"), default=None,
                   help="how unknown (ROS) or transparent (bitmap) cells are treated (default: occupied)")
    from ._common import add_max_cells_argument

    add_max_cells_argument(p)
    add_robot_arguments(p)
    return p


def describe(args: argparse.Namespace) -> tuple[dict[str, Any], Any]:
    """Load the map named by ``args`` and return (the description, the GridMap)."""
    import numpy as np
    from scipy import ndimage

    from ..io import read
    from ..world import World

    suffix = str(args.map).lower().rsplit(".", 1)[-1]
    options: dict[str, Any] = {"unknown": args.unknown}
    if suffix in ("png", "pgm", "bmp"):
        options["resolution"] = args.resolution
    workspace = read(args.map, **options)
    target = robot_target(args, workspace)
    if isinstance(target, World):
        from ..rasterize import as_gridmap

        gm = as_gridmap(target, args.resolution)
        fmt, obstacles = "world", len(target.obstacles)
    else:
        if args.resolution is not None and suffix not in ("png", "pgm", "bmp"):
            from ..errors import ParameterError

            raise ParameterError(
                f"{args.map}: --resolution applies to world files and bitmaps; this "
                f"{target.meta.get('format', 'map')} map has its own resolution {target.grid.resolution:g}"
            )
        gm = target
        fmt = str(gm.meta.get("format", "grid"))
        _, obstacles = ndimage.label(gm.occupied, structure=np.ones((3, 3), dtype=bool))
    grid = gm.grid
    info = {
        "shape": [int(grid.rows), int(grid.cols)],
        "resolution": float(grid.resolution),
        "origin": [float(grid.origin[0]), float(grid.origin[1])],
        "border": grid.border,
        "occupied_fraction": float(gm.occupied_fraction),
        "obstacles": int(obstacles),
        "source": str(args.map),
        "format": fmt,
    }
    if target is not workspace:
        from ._common import _robot_from_args

        robot = _robot_from_args(args, workspace)
        info["robot"] = robot.describe() if robot is not None else "point"
    return info, gm


def run(args: argparse.Namespace) -> int:
    info, gm = describe(args)
    if args.npz:
        from ..io import write_npz

        write_npz(args.npz, {"occupied": gm.occupied}, gm.grid)
    if args.json:
        json.dump(info, sys.stdout)
        sys.stdout.write("\n")
        return 0
    xmin, ymin, xmax, ymax = gm.grid.bounds
    rows, cols = info["shape"]
    what = "vector obstacles" if info["format"] == "world" else "8-connected obstacle regions"
    print(f"source:            {info['source']}")
    print(f"format:            {info['format']}")
    print(f"shape:             {rows} rows x {cols} cols")
    print(f"resolution:        {info['resolution']:g}")
    print(f"origin:            ({info['origin'][0]:g}, {info['origin'][1]:g})")
    print(f"bounds:            x [{xmin:g}, {xmax:g}], y [{ymin:g}, {ymax:g}]")
    print(f"border:            {info['border']}")
    print(f"occupied fraction: {info['occupied_fraction']:.4f}")
    print(f"obstacles:         {info['obstacles']} ({what})")
    if "robot" in info:
        print(f"robot:             {info['robot']} (the grid is its configuration space)")
    if args.npz:
        print(f"wrote:             {args.npz}")
    return 0
