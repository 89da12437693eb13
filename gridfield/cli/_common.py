"""Argument helpers shared by the sub-commands: map loading and planner parameters."""

from __future__ import annotations

import argparse
import math
from typing import Any

from ..errors import ParameterError

__all__ = ["add_map_arguments", "add_param_arguments", "add_robot_arguments", "collect_params", "load_gridmap",
           "load_target", "parse_value", "robot_target"]

#: Planner parameters that get their own flag (``--d-star`` for ``d_star``); others via ``--param K=V``.
PARAM_FLAGS: dict[str, type] = {
    "zeta": float,
    "d_star": float,
    "eta": float,
    "q_star": float,
    "repulsive_power": float,
    "repulsion": str,
    "metric": str,
    "gradient": str,
    "step_rule": str,
    "step": float,
    "alpha": float,
    "min_speed": float,
    "tolerance": float,
    "max_iterations": int,
    "sampling": str,
    "escape": str,
    "escape_tries": int,
    "escape_radius": float,
    "seed": int,
}


def add_map_arguments(p: argparse.ArgumentParser, *, name: str = "MAP") -> None:
    """The positional map argument and the options that shape how it becomes a grid."""
    p.add_argument("map", metavar=name,
                   help="world YAML, ROS map YAML, bitmap (PNG/PGM/BMP), Moving AI .map or gridfield .npz")
    p.add_argument("--resolution", type=float, default=None,
                   help="cell size used to rasterize a vector world (default: the world file's 'resolution')")
    p.add_argument("--unknown", choices=("occupied", "free"), default=None,
                   help="how unknown cells of a ROS map are treated (default: occupied)")


def load_target(args: argparse.Namespace) -> Any:
    """Read the map named on the command line: a World or a GridMap."""
    from ..io import read

    options: dict[str, Any] = {}
    if getattr(args, "unknown", None) is not None:
        options["unknown"] = args.unknown
    if getattr(args, "resolution", None) is not None and str(args.map).lower().endswith((".png", ".pgm", ".bmp")):
        options["resolution"] = args.resolution  # a bitmap's pixel size
    try:
        return read(args.map, **options)
    except TypeError as e:  # an option the format's reader does not take
        raise ParameterError(f"{args.map}: {e}") from None


def load_gridmap(args: argparse.Namespace) -> Any:
    """Read the map and rasterize it if it is a vector world."""
    from ..rasterize import as_gridmap

    return as_gridmap(load_target(args), getattr(args, "resolution", None))


def parse_value(text: str) -> Any:
    """Parse a ``--param`` value: int, float (``inf`` allowed), bool, or string.

    Examples
    --------
    >>> parse_value("3"), parse_value("0.5"), parse_value("inf"), parse_value("sum")
    (3, 0.5, inf, 'sum')
    """
    low = text.strip().lower()
    if low in ("true", "false"):
        return low == "true"
    try:
        return int(text)
    except ValueError:
        pass
    try:
        v = float(text)
    except ValueError:
        return text
    if math.isnan(v):
        raise ParameterError(f"parameter value must not be NaN, got {text!r}")
    return v


def add_param_arguments(p: argparse.ArgumentParser) -> None:
    """One flag per common planner parameter, plus ``--param KEY=VALUE`` for the rest."""
    g = p.add_argument_group("planner parameters (override the world file's 'params')")
    for key, typ in PARAM_FLAGS.items():
        g.add_argument(f"--{key.replace('_', '-')}", dest=f"param_{key}", type=typ if typ is not float else _finite_or_inf,
                       default=None, metavar=key.upper())
    g.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                   help="any other planner parameter, e.g. --param kappa=3")


def _finite_or_inf(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if math.isnan(v):
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}")
    return v


def collect_params(args: argparse.Namespace) -> dict[str, Any]:
    """The parameters given on the command line (only those given)."""
    out: dict[str, Any] = {}
    for key in PARAM_FLAGS:
        v = getattr(args, f"param_{key}", None)
        if v is not None:
            out[key] = v
    for item in getattr(args, "param", []) or []:
        if "=" not in item:
            raise ParameterError(f"--param expects KEY=VALUE, got {item!r}")
        k, v = item.split("=", 1)
        out[k.strip().replace("-", "_")] = parse_value(v)
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


def _robot_from_args(args: argparse.Namespace, target: Any) -> Any:
    from ..world import Robot

    radius = getattr(args, "robot_radius", None)
    words = getattr(args, "robot", None)
    if radius is not None:
        return Robot(radius=radius)
    if words:
        from ..cspace import check_robot_polygon

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
    robot = _robot_from_args(args, target)
    if robot is None:
        return target
    from ..cspace import apply_robot, check_robot_point

    cspace = apply_robot(target, robot)
    for name, point in points.items():
        if point is not None:
            check_robot_point(target, robot, name, point, cspace=cspace)
    return cspace
