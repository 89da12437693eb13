"""``gridfield info``: describe a map or world file (shape, resolution, origin, border, occupancy rule, occupied and
unknown cells, obstacles)."""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

from ._common import add_robot_arguments, robot_target


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "info",
        help="describe a map: shape, resolution, origin, border, occupancy rule, occupied fraction and cells "
             "(unknown ones named), obstacle count",
        description="Load a map or world file and describe its occupancy grid.",
    )
    p.add_argument("map", metavar="MAP",
                   help="world YAML, ROS map YAML, bitmap (PNG/PGM/BMP), Moving AI .map, gridfield .npz, "
                        "TIFF/GeoTIFF, .npy or .zarr; voxel maps: Moving AI .3dmap, .binvox, 3-D .npy/.npz, "
                        ".ply/.xyz point clouds (with --resolution)")
    p.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    p.add_argument("--npz", metavar="F", help="also write the occupancy grid to the .npz file F")
    p.add_argument("--resolution", type=float, default=None,
                   help="cell size: rasterizes a vector world (default: the world file's 'resolution'); "
                        "for a bitmap, the size of one pixel (default 1); for a point cloud (.ply, .xyz), the "
                        "voxel size (required)")
    p.add_argument("--unknown", choices=("occupied", "free"), default=None,
                   help="how unknown (ROS) or transparent (bitmap) cells are treated (default: occupied)")
    from ._common import add_max_cells_argument, add_occupancy_arguments

    add_occupancy_arguments(p)
    add_max_cells_argument(p)
    add_robot_arguments(p)
    return p


def describe(args: argparse.Namespace) -> tuple[dict[str, Any], Any]:
    """Load the map named by ``args`` and return (the description, the GridMap or None).

    A vector world is described from its vectors: bounds, obstacles by kind, robot, start and goal,
    and the raster it would give at ``--resolution`` or its own ``resolution`` (shape from the
    bounds, before any allocation); only with a resolution is it rasterized, for the occupied
    fraction (and ``--npz``). Without one, the raster keys are None and nothing is refused
    (``--npz`` alone needs a resolution).
    """
    import numpy as np
    from scipy import ndimage

    from ..core.errors import ParameterError
    from ..geometry.world import World
    from ..io import read

    suffix = str(args.map).lower().rsplit(".", 1)[-1]
    from ._common import occupancy_options

    options: dict[str, Any] = {"unknown": args.unknown, **occupancy_options(args)}
    resolution_formats = ("png", "pgm", "bmp", "ply", "xyz")  # a point cloud's voxel size too
    if suffix in resolution_formats:
        options["resolution"] = args.resolution
    workspace = read(args.map, **options)
    from ..core.chunkcache import LazyGridMap

    workspace = getattr(workspace, "map", workspace) if str(args.map).rstrip("/").endswith(".zarr") else workspace
    if isinstance(workspace, LazyGridMap):  # a map read by chunks (or a store's map): read whole, size-guarded
        workspace = workspace.to_gridmap()
    target = robot_target(args, workspace)
    if isinstance(target, World):
        return _describe_world(args, workspace, target)
    if args.resolution is not None and suffix not in resolution_formats:
        raise ParameterError(
            f"{args.map}: --resolution applies to world files and bitmaps; this "
            f"{target.meta.get('format', 'map')} map has its own resolution {target.grid.resolution:g}"
        )
    gm = target
    fmt = str(gm.meta.get("format", "grid"))
    _, obstacles = ndimage.label(gm.occupied, structure=np.ones((3,) * gm.occupied.ndim, dtype=bool))
    grid = gm.grid
    info = {
        "shape": [int(n) for n in grid.shape],  # (rows, cols); a voxel map (layers, rows, cols)
        "resolution": float(grid.resolution),
        "origin": [float(o) for o in grid.origin],
        "border": grid.border,
        "occupied_fraction": float(gm.occupied_fraction),
        "obstacles": int(obstacles),
        "source": str(args.map),
        "format": fmt,
        "occupancy_rule": occupancy_rule(gm),
        **_cell_counts(gm, args.unknown),
    }
    if grid.ndim == 3:  # a voxel map: its bounds (xmin, ymin, zmin, xmax, ymax, zmax) in the JSON too
        info["bounds"] = [float(v) for v in grid.bounds]
    if target is not workspace:
        from ._common import _robot_from_args

        robot = _robot_from_args(args, workspace)
        info["robot"] = robot.describe() if robot is not None else "point"
    return info, gm


#: A vector world's rule (:mod:`gridfield.rasterize`).
WORLD_RULE = "vector obstacles; rasterized, a cell an obstacle touches (its closed square) is occupied"


def occupancy_rule(gm: Any) -> str:
    """Which values of the map's source are obstacles, in words: what its reader recorded
    (``meta["occupancy_rule"]``), else that of an occupied array.

    Parameters
    ----------
    gm : GridMap

    Returns
    -------
    str

    Examples
    --------
    >>> from gridfield.io import bundled_map, read
    >>> occupancy_rule(read(bundled_map("arena/arena.map")))
    "'.', 'G', 'S' free; the rest blocked"
    """
    rule = gm.meta.get("occupancy_rule")
    if rule is None:
        rule = "the map's occupied array (True = obstacle)"  # a GridMap built in Python
    return str(rule)


def _cell_counts(gm: Any, unknown: str | None) -> dict[str, Any]:
    """``occupied_cells`` and, for a map with unknown cells (ROS, transparent bitmap pixels, an
    OccupancyGrid), ``unknown_cells`` (of the map as read, before any robot) and ``unknown_as`` (how they
    are treated: ``"occupied"``, the readers' default, or ``"free"``); both None for a map without them."""
    import numpy as np

    cells = int(gm.occupied.size)
    fraction = gm.meta.get("unknown_fraction")
    counts: dict[str, Any] = {"occupied_cells": int(np.count_nonzero(gm.occupied)), "unknown_cells": None,
                              "unknown_as": None}
    if fraction is not None:  # the readers record the mean of the unknown mask: count / cells, exactly recoverable
        counts["unknown_cells"] = round(float(fraction) * cells)
        counts["unknown_as"] = unknown or "occupied"
    return counts


def _describe_world(args: argparse.Namespace, workspace: Any, target: Any) -> tuple[dict[str, Any], Any]:
    """A vector world's description (see :func:`describe`); the raster only when a resolution is set."""
    from ..core.errors import ParameterError
    from ..core.grid import Grid
    from ._common import _robot_from_args

    resolution = args.resolution if args.resolution is not None else target.resolution
    kinds: dict[str, int] = {}
    for ob in workspace.obstacles:  # the world as written (with a robot, the raster is of its C-space)
        kinds[ob.kind] = kinds.get(ob.kind, 0) + 1
    robot = _robot_from_args(args, workspace)
    info: dict[str, Any] = {
        "shape": None,
        "resolution": None,
        "origin": [float(target.bounds[0]), float(target.bounds[1])],
        "border": target.border,
        "occupied_fraction": None,
        "obstacles": len(workspace.obstacles),
        "source": str(args.map),
        "format": "world",
        "occupancy_rule": WORLD_RULE,
        "bounds": [float(v) for v in target.bounds],
        "obstacle_kinds": dict(sorted(kinds.items())),
        "start": None if target.start is None else [float(v) for v in target.start],
        "goal": None if target.goal is None else [float(v) for v in target.goal],
        "occupied_cells": None,  # set below when the world is rasterized
        "unknown_cells": None,
        "unknown_as": None,
    }
    if robot is not None or target is not workspace:
        info["robot"] = robot.describe() if robot is not None else "point"
    gm = None
    if resolution is None:
        if args.npz:
            raise ParameterError(f"{args.map}: the world sets no resolution; pass --resolution R to write --npz")
        return info, None
    grid = Grid.covering(target.bounds, resolution, border=target.border)  # sized by the guard, nothing allocated
    info["shape"], info["resolution"] = [int(grid.rows), int(grid.cols)], float(grid.resolution)
    from ..geometry.rasterize import as_gridmap

    gm = as_gridmap(target, resolution)
    info["occupied_fraction"] = float(gm.occupied_fraction)
    info.update(_cell_counts(gm, None))
    return info, gm


def run(args: argparse.Namespace) -> int:
    from ._common import load_target
    from .turning import run_info, wants_turning

    if wants_turning(args):  # --headings N: the pose grid of a turning robot
        return run_info(args, load_target(args))
    info, gm = describe(args)
    if args.npz:
        from ..io import write_npz

        write_npz(args.npz, {"occupied": gm.occupied}, gm.grid, diagonals=gm.diagonals)
    if args.json:
        json.dump(info, sys.stdout)
        sys.stdout.write("\n")
        return 0
    world = info["format"] == "world"
    bounds = info["bounds"] if world else gm.grid.bounds
    nd = len(bounds) // 2
    what = "vector obstacles" if world else "8-connected obstacle regions" if nd == 2 else "26-connected obstacle regions"
    print(f"source:            {info['source']}")
    print(f"format:            {info['format']}")
    print(f"occupancy rule:    {info['occupancy_rule']}")
    if info["shape"] is None:
        print("shape:             none: the world sets no resolution (pass --resolution R to rasterize it)")
    else:
        names = ("layers", "rows", "cols")[-len(info["shape"]):]
        print(f"shape:             {' x '.join(f'{n} {k}' for n, k in zip(info['shape'], names, strict=True))}")
        print(f"resolution:        {info['resolution']:g}")
    print(f"origin:            ({', '.join(f'{o:g}' for o in info['origin'])})")
    print(f"bounds:            {', '.join(f'{a} [{bounds[i]:g}, {bounds[i + nd]:g}]' for i, a in enumerate('xyz'[:nd]))}")
    print(f"border:            {info['border']}")
    if info["occupied_fraction"] is not None:
        print(f"occupied fraction: {info['occupied_fraction']:.4f}")
    if info.get("occupied_cells") is not None:
        unknown, treated = info.get("unknown_cells"), info.get("unknown_as")
        cells = f"{info['occupied_cells']} of {math.prod(info['shape'])}"
        if unknown and treated == "occupied":
            cells += f" (of which unknown {unknown}, treated as occupied)"
        print(f"occupied cells:    {cells}")
        if unknown and treated == "free":
            print(f"unknown cells:     {unknown}, treated as free (--unknown free)")
    print(f"obstacles:         {info['obstacles']} ({what})")
    if world:
        kinds = ", ".join(f"{n} {k}{'s' if n != 1 else ''}" for k, n in info["obstacle_kinds"].items())
        print(f"obstacle kinds:    {kinds or 'none'}")
        for key in ("start", "goal"):
            point = info[key]
            print(f"{key + ':':<19}{'none' if point is None else f'({point[0]:g}, {point[1]:g})'}")
    if "robot" in info:
        extra = " (the grid is its configuration space)" if info["robot"] != "point" else ""
        print(f"robot:             {info['robot']}{extra}")
    if args.npz:
        print(f"wrote:             {args.npz}")
    return 0
