"""Argument helpers shared by the sub-commands: map loading and planner parameters."""

from __future__ import annotations

import argparse
import math
from typing import Any

from ..core.errors import ParameterError

__all__ = [
    "FIGURE_SUFFIXES",
    "add_map_arguments",
    "add_max_cells_argument",
    "add_occupancy_arguments",
    "add_param_arguments",
    "add_robot_arguments",
    "check_coarse_cells",
    "check_figure_file",
    "collect_params",
    "load_gridmap",
    "load_target",
    "occupancy_options",
    "robot_target",
    "warm_up",
]

#: File suffixes a figure option (``--plot F``) accepts: matplotlib's static formats.
FIGURE_SUFFIXES = (".png", ".pdf", ".svg", ".svgz", ".jpg", ".jpeg", ".tif", ".tiff", ".webp", ".eps", ".ps")


def _flags() -> dict[str, str]:
    """Parameter name -> help line, for the parameters that get their own flag (``--d-star``)."""
    from ..core.params import REGISTRY, help_text

    return {name: help_text(name) for name, spec in REGISTRY.items() if spec.flag}


def add_map_arguments(p: argparse.ArgumentParser, *, name: str = "MAP") -> None:
    """The positional map argument and the options that shape how it becomes a grid."""
    p.add_argument("map", metavar=name,
                   help="world YAML, ROS map YAML, bitmap (PNG/PGM/BMP), Moving AI .map, gridfield .npz, "
                        "TIFF/GeoTIFF, .npy or .zarr")
    p.add_argument("--resolution", type=float, default=None,
                   help="cell size used to rasterize a vector world (default: the world file's 'resolution')")
    p.add_argument("--unknown", choices=("occupied", "free"), default=None,
                   help="how unknown cells of a ROS map are treated (default: occupied)")
    add_occupancy_arguments(p)
    add_max_cells_argument(p)


#: ``--occupancy``'s choices: gridfield.io.OCCUPANCY_RULES, spelt out (building the parsers imports no reader).
OCCUPANCY_CHOICES = ("dark", "nonzero")


def add_occupancy_arguments(p: argparse.ArgumentParser) -> None:
    """``--occupancy {dark,nonzero}``, ``--threshold T``, ``--negate``: how an image or array's values become
    obstacles (the readers' ``occupancy``, ``threshold``, ``negate``; see :mod:`gridfield.io`)."""
    g = p.add_argument_group("occupancy of images and arrays (PNG, PGM, BMP, TIFF, .npy, Zarr arrays)")
    g.add_argument("--occupancy", choices=OCCUPANCY_CHOICES, default=None,
                   help="dark: grey levels, dark = occupied (the images' default); nonzero: any non-zero value is "
                        "an obstacle (label rasters; the default of .npy and Zarr arrays)")
    g.add_argument("--threshold", type=float, default=None, metavar="T",
                   help="dark rule: occupancy (white - v) / white above T is an obstacle (default 0.5)")
    g.add_argument("--negate", action="store_const", const=True, default=None,
                   help="dark rule: white is occupied, black free")


def occupancy_options(args: argparse.Namespace) -> dict[str, Any]:
    """The occupancy options given on the command line (only those given), for :func:`gridfield.io.read`."""
    return {key: getattr(args, key) for key in ("occupancy", "threshold", "negate")
            if getattr(args, key, None) is not None}


def _max_cells(text: str) -> int:
    from ..core.limits import parse_max_cells

    try:
        return parse_max_cells(text, "--max-cells")
    except ParameterError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def add_max_cells_argument(p: argparse.ArgumentParser) -> None:
    """``--max-cells N``: the size guard's limit (see :mod:`gridfield.core.limits`); the CLI applies it."""
    p.add_argument("--max-cells", type=_max_cells, default=None, metavar="N",
                   help="refuse grids of more than N cells (default: what a quarter of this machine's memory "
                        "holds; also GRIDFIELD_MAX_CELLS)")


def check_figure_file(file: str | None, option: str = "--plot") -> None:
    """Refuse a figure file name whose suffix matplotlib cannot write (before any work is done).

    Examples
    --------
    >>> check_figure_file("out.png")
    >>> check_figure_file("out")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: --plot out: the file name needs a figure suffix: .png, .pdf, ...
    """
    if file is None:
        return
    from pathlib import Path

    suffix = Path(file).suffix.lower()
    if suffix not in FIGURE_SUFFIXES:
        what = f"suffix {suffix!r} is not a figure format" if suffix else "the file name needs a figure suffix"
        raise ParameterError(f"{option} {file}: {what}: {', '.join(FIGURE_SUFFIXES)}")


def check_coarse_cells(world: Any, gridmap: Any, **points: Any) -> None:
    """A start or goal that is free in the vector ``world`` but whose cell of its rasterization
    ``gridmap`` is blocked: say that (not "inside an obstacle"), and what to do.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> from gridfield.geometry.rasterize import as_gridmap
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 4, 6, 6]}]})
    >>> check_coarse_cells(w, as_gridmap(w, 1.0), start=(2.5, 2.5))
    >>> check_coarse_cells(w, as_gridmap(w, 5.0), start=(2.5, 2.5))
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: start (2.5, 2.5) is free, but its cell of the 5 grid is blocked ...
    """
    for name, point in points.items():
        if point is None or not world.contains_free(point) or bool(gridmap.is_free([point])[0]):
            continue
        h = gridmap.grid.resolution
        raise ParameterError(
            f"{name} ({point[0]:g}, {point[1]:g}) is free, but its cell of the {h:g} grid is blocked (rasterizing "
            f"marks every cell an obstacle touches as occupied); use a finer --resolution, e.g. {h / 4:g}")


def warm_up(planner: str) -> float:
    """Run ``planner`` once on a tiny map (24 x 24 cells, or a 24 x 24 world with one disc) so that its
    one-time start-up (imports, loading the compiled kernels, thread pools) is not counted in the
    plan's time; returns the seconds it took, which the CLI prints apart ("+ N ms start-up")."""
    import time
    import warnings

    import numpy as np

    from ..core.errors import GridfieldError
    from ..core.grid import Grid, GridMap
    from ..geometry.world import world_from_dict
    from ..planners import PLANNERS, plan

    t0 = time.perf_counter()
    if PLANNERS[planner][2] == "grid":
        target: Any = GridMap(Grid((24, 24), 1.0, border="wall"), np.zeros((24, 24), bool))
    else:
        target = world_from_dict({"bounds": [0, 0, 24, 24], "border": "wall",
                                  "obstacles": [{"circle": {"center": [16, 8], "radius": 1}}]})
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # (a tiny map may be too small for some planner's defaults)
            plan(planner, target, (8.5, 8.5), (12.5, 12.5))  # a run that reaches: no hint to make
    except GridfieldError:
        pass
    return time.perf_counter() - t0


def load_target(args: argparse.Namespace, *, lazy: bool = False) -> Any:
    """Read the map named on the command line: a World or a GridMap. A map read by chunks (BigTIFF,
    ``.npy``, Zarr) is read whole (within the size guard) unless ``lazy`` (the chunked paths, ``--out``);
    a stored distance map or field stays lazy."""
    from ..core.chunkcache import LazyGridMap
    from ..core.results import DistanceMap, Field

    target = _read_target(args)
    if isinstance(target, DistanceMap | Field) and not (isinstance(target, Field) and args.command == "plan"):
        kind = "distance map" if isinstance(target, DistanceMap) else "potential field"
        use = "gridfield plan F.zarr --start X Y follows a field store" if isinstance(target, Field) else (
            "its grid and occupancy are read by gridfield.io.read(F.zarr).map")
        raise ParameterError(f"{args.map} is a stored {kind}, not a map for gridfield {args.command}; {use}")
    return target.to_gridmap() if isinstance(target, LazyGridMap) and not lazy else target


def _read_target(args: argparse.Namespace) -> Any:
    from ..io import read

    options: dict[str, Any] = occupancy_options(args)
    if getattr(args, "unknown", None) is not None:
        options["unknown"] = args.unknown
    if getattr(args, "resolution", None) is not None and str(args.map).lower().rstrip("/").endswith(
            (".png", ".pgm", ".bmp", ".npy", ".tif", ".tiff", ".zarr", ".ply", ".xyz")):
        options["resolution"] = args.resolution  # a raster's pixel size (a GeoTIFF's own overridden); a cloud's voxel
    try:
        return read(args.map, **options)
    except TypeError as e:  # an option the format's reader does not take
        raise ParameterError(f"{args.map}: {e}") from None


def load_gridmap(args: argparse.Namespace) -> Any:
    """Read the map and rasterize it if it is a vector world."""
    from ..geometry.rasterize import as_gridmap

    return as_gridmap(load_target(args), getattr(args, "resolution", None))


def add_param_arguments(p: argparse.ArgumentParser) -> None:
    """One flag per common planner parameter, plus ``--param KEY=VALUE`` for the rest; every help line
    (meaning, default or scaling rule, allowed values, planners) comes from :mod:`gridfield.core.params`."""
    from ..core.params import REGISTRY, help_text

    g = p.add_argument_group(
        "planner parameters (override the world file's 'params'; lengths in world units; defaults given "
        "in cells scale with the map's cell size)")
    for key, text in _flags().items():
        g.add_argument(f"--{key.replace('_', '-')}", dest=f"param_{key}", default=None, metavar=key.upper(),
                       help=text)
    others = "; ".join(f"{name}: {help_text(name)}" for name, spec in REGISTRY.items() if not spec.flag)
    g.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                   help=f"any other planner parameter: {others}")


def _finite_or_inf(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if math.isnan(v):
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}")
    return v


def collect_params(args: argparse.Namespace) -> dict[str, Any]:
    """The parameters given on the command line (only those given), parsed and checked by the registry."""
    from ..core.params import parse

    out: dict[str, Any] = {}
    for key in _flags():
        v = getattr(args, f"param_{key}", None)
        if v is not None:
            out[key] = parse(key, v)
    for item in getattr(args, "param", []) or []:
        if "=" not in item:
            raise ParameterError(f"--param expects KEY=VALUE, got {item!r}")
        k, v = item.split("=", 1)
        k = k.strip().replace("-", "_")
        out[k] = parse(k, v)
    return out


# -- the robot's shape -------------------------------------------------------------------
def add_robot_arguments(p: argparse.ArgumentParser) -> None:
    """``--robot-radius R`` and ``--robot X,Y X,Y ...``: plan in the robot's configuration space."""
    g = p.add_argument_group("robot shape (plan in its configuration space; default: the world file's "
                             "'robot', else a point)")
    mx = g.add_mutually_exclusive_group()
    mx.add_argument("--robot-radius", type=_finite_or_inf, default=None, metavar="R", help="a disc robot of radius R")
    mx.add_argument("--robot", nargs="+", default=None, metavar="X,Y",
                    help="a convex polygon robot, its vertices around the reference point (the point planned for); "
                         'quote them as one word when one starts with "-": --robot "-0.2,-0.1 0.3,-0.1 0.3,0.1"')
    g.add_argument("--headings", type=int, default=None, metavar="N",
                   help="a robot that turns: plan in (x, y, theta) over N heading bins (72: 5 degrees each; "
                        "--start X Y THETA in radians, --goal X Y [THETA]); 1 (default): it only translates")


def _robot_from_args(args: argparse.Namespace, target: Any) -> Any:
    from ..geometry.world import Robot

    radius = getattr(args, "robot_radius", None)
    words = getattr(args, "robot", None)
    if radius is not None:
        return Robot(radius=radius)
    if words:
        from ..geometry.cspace import check_robot_polygon

        vertices = []
        for word in " ".join(words).replace(";", " ").split():
            try:
                x, y = (float(v) for v in word.split(","))
            except ValueError:
                raise ParameterError(f"--robot expects vertices X,Y (e.g. 0,0 0.4,0 0,0.3), got {word!r}") from None
            if not (math.isfinite(x) and math.isfinite(y)):
                raise ParameterError(f"--robot vertices must be finite, got {word!r}")
            vertices.append((x, y))
        return Robot(vertices=check_robot_polygon(vertices, "--robot"))
    world = target if hasattr(target, "obstacles") else getattr(target, "world", None)
    return getattr(world, "robot", None)


def robot_target(args: argparse.Namespace, target: Any, **points: Any) -> Any:
    """The map's configuration space for the robot given on the command line (or in the world file).

    ``points`` (``start=(x, y)``, ``goal=...``; None skipped) are checked first: a start or goal
    at which the robot collides is an error naming the distance. Without a robot: ``target``.
    """
    headings = getattr(args, "headings", None)
    if headings is not None and headings != 1:
        from ..geometry.cspace import check_headings

        check_headings(headings)
        raise ParameterError(f"--headings {headings}: this command works on a robot that translates; "
                             "gridfield plan and gridfield info take --headings")
    robot = _robot_from_args(args, target)
    if robot is None:
        return target
    from ..geometry.cspace import apply_robot, check_robot_point

    cspace = apply_robot(target, robot)
    for name, point in points.items():
        if point is not None:
            check_robot_point(target, robot, name, point, cspace=cspace)
    return cspace


def check_point_args(args: argparse.Namespace, target: Any) -> None:
    """``--start`` and ``--goal`` as given: two numbers X Y on a map or world, three X Y Z on a voxel grid.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> vox = GridMap(Grid((2, 2, 2), 1.0), np.zeros((2, 2, 2), bool))
    >>> check_point_args(argparse.Namespace(start=[0.5, 0.5, 0.5], goal=None, map="v.3dmap"), vox)
    >>> check_point_args(argparse.Namespace(start=[0.5, 0.5], goal=None, map="v.3dmap"), vox)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: --start needs three numbers X Y Z on the voxel grid v.3dmap, got 2 (0.5 0.5)
    """
    grid = getattr(target, "grid", None)
    nd = grid.ndim if grid is not None else 2
    for name in ("start", "goal"):
        v = getattr(args, name, None)
        if v is not None and len(v) != nd:
            want = "three numbers X Y Z on the voxel grid" if nd == 3 else "two numbers X Y on the map"
            raise ParameterError(f"--{name} needs {want} {args.map}, got {len(v)} ({' '.join(f'{x:g}' for x in v)})")


def scenario3d(path: str, index: int | None, target: Any, map_name: str) -> tuple[list[float], list[float], float]:
    """Start, goal and optimal cost of line ``index`` of a Moving AI ``.3dscen`` file, as world points of
    the voxel grid ``target`` (voxel ``(x, y, z)`` at ``origin + (v + 0.5) * resolution``, no axis flipped).

    Read by :func:`gridfield.io.read_scen3d` (``start_voxel``/``goal_voxel``: voxel coordinates ``(x, y, z)``,
    checked to lie in the map; ``optimal``).
    """
    import numpy as np

    from ..io import read_scen3d

    grid = getattr(target, "grid", None)
    if grid is None or grid.ndim != 3:
        raise ParameterError(f"{path} is a voxel scenario (.3dscen); {map_name} is not a voxel map (.3dmap)")
    scen = read_scen3d(path, shape=grid.shape)
    n = len(scen.optimal)
    i = 0 if index is None else index
    if not 0 <= i < n:
        raise ParameterError(f"{path}: --index {i} is out of range; the file has {n} scenarios (0..{n - 1})")
    origin = np.asarray(grid.origin)
    pick = [np.asarray(v, dtype=float)[i] for v in (scen.start_voxel, scen.goal_voxel)]
    start, goal = ((v + 0.5) * grid.resolution + origin for v in pick)
    return start.tolist(), goal.tolist(), float(scen.optimal[i])
