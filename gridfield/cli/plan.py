"""``gridfield plan``: plan one path and report it (text or the JSON of README.md)."""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from ._common import (
    add_map_arguments,
    add_param_arguments,
    add_robot_arguments,
    collect_params,
    load_target,
    robot_target,
)

if TYPE_CHECKING:
    from ..core.path import Path
    from ..core.results import Field


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    from ..planners import PLANNERS

    p = sub.add_parser("plan", help="plan a path from start to goal",
                       description="Plan a path from START to GOAL on a map or world and report it.")
    add_map_arguments(p)
    p.add_argument("--start", nargs="+", type=float, metavar="X",
                   help="start point X Y (X Y Z on a voxel grid, X Y THETA with --headings; default: the world "
                        "file's start)")
    p.add_argument("--goal", nargs="+", type=float, metavar="X",
                   help="goal point X Y (X Y Z on a voxel grid, X Y [THETA] with --headings; default: the world "
                        "file's goal)")
    p.add_argument("--scenario", metavar="FILE",
                   help="a Moving AI .scen file: take start and goal from its line --index (y flipped to "
                        "gridfield's y-up), and report the scenario's optimal length; a .3dscen file for a "
                        "voxel map (.3dmap): its voxels' centres, no axis flipped")
    p.add_argument("--index", type=int, default=None, metavar="N",
                   help="which scenario of --scenario (0 = the first; default 0)")
    p.add_argument("--planner", default="potential", choices=list(PLANNERS), help="planner (default: potential)")
    p.add_argument("--json", action="store_true", help="print one JSON object (the plan contract in README.md)")
    p.add_argument("--plot", metavar="F", help="save a figure of the map and the path (a voxel map: orthogonal "
                                               "slices and a 3-D view)")
    p.add_argument("--animate", metavar="F", help="save an animation of the follower (.gif, or .mp4 with ffmpeg)")
    add_robot_arguments(p)
    add_param_arguments(p)
    return p


def scenario(args: argparse.Namespace, target: object) -> tuple[list[float], list[float], float] | None:
    """Start, goal and optimal length of ``--scenario FILE --index N``, checked against the map's size."""
    from ..core.errors import ParameterError

    if args.scenario is None:
        if args.index is not None:
            raise ParameterError("--index needs --scenario FILE")
        return None
    if args.start is not None or args.goal is not None:
        raise ParameterError("give either --scenario or --start/--goal, not both")
    if str(args.scenario).lower().endswith((".3dscen", ".3dscen.gz")):
        from ._common import scenario3d

        return scenario3d(args.scenario, args.index, target, args.map)
    from ..io import read_scen

    grid = getattr(target, "grid", None)
    height = grid.rows if grid is not None else None
    scen = read_scen(args.scenario, map_height=height)
    i = 0 if args.index is None else args.index
    if not 0 <= i < len(scen):
        raise ParameterError(f"{args.scenario}: --index {i} is out of range; the file has {len(scen)} scenarios "
                             f"(0..{len(scen) - 1})")
    if grid is not None and int(scen.width[i]) != grid.cols:
        raise ParameterError(f"{args.scenario}: scenario {i} is for a map {int(scen.width[i])} wide, but {args.map} "
                             f"is {grid.cols} wide")
    return scen.start_xy[i].tolist(), scen.goal_xy[i].tolist(), float(scen.optimal[i])


def endpoints(args: argparse.Namespace, target: object) -> tuple[list[float], list[float]]:
    """Start and goal from the command line, else from the world file."""
    from ..core.errors import ParameterError

    world = getattr(target, "world", None) or target
    start = args.start if args.start is not None else getattr(world, "start", None)
    goal = args.goal if args.goal is not None else getattr(world, "goal", None)
    if start is None or goal is None:
        missing = "--start X Y" if start is None else "--goal X Y"
        raise ParameterError(f"{args.map} names no {missing.split()[0][2:]}; pass {missing}")
    return list(start), list(goal)


def run(args: argparse.Namespace) -> int:
    from ..geometry.world import World
    from ..planners import PLANNERS, plan_with_field
    from ._common import check_figure_file

    check_figure_file(args.plot)
    workspace = load_target(args)
    params = collect_params(args)
    other = _other_kind(args, workspace, params)
    if other is not None:
        return other
    scen = scenario(args, workspace)
    if scen is not None:
        start, goal, optimal = scen
    else:
        from ._common import check_point_args

        check_point_args(args, workspace)
        start, goal = endpoints(args, workspace)
    target = robot_target(args, workspace, start=start, goal=goal)
    robot = target is not workspace
    resolution = args.resolution
    if PLANNERS[args.planner][2] == "grid" and isinstance(target, World):
        from ..geometry.rasterize import as_gridmap

        # rasterized once, here: the grid planner plans on it and --plot/--animate draw it
        world, target, resolution = target, as_gridmap(target, resolution), None
        from ._common import check_coarse_cells

        check_coarse_cells(world, target, start=start, goal=goal)
    from ._common import warm_up

    startup = warm_up(args.planner)  # one-time start-up, reported apart from the plan's own time
    # the field the potential planner followed comes back with the path: the figures draw it, not rebuild it
    path, field = plan_with_field(args.planner, target, start, goal, params, resolution=resolution)
    if robot and path.status == "no_path":
        path = _robot_no_path(args, path, workspace, start, goal, params, resolution)
    if scen is not None:
        path = replace(path, extra={**path.extra, "optimal": optimal})
    if robot and path.status != "no_path":
        from ..geometry.cspace import robot_clearance, workspace_clearance
        from ._common import _robot_from_args

        clearance = workspace_clearance(workspace, path.points)
        body = robot_clearance(workspace, _robot_from_args(args, workspace), path.points)
    elif robot:  # no path: nothing to measure (the start alone is no path's clearance)
        clearance, body = float("nan"), None
    if args.json:
        out = path.to_json()
        out["startup_seconds"] = startup
        if robot:
            out["robot"] = _robot_text(args, workspace)
            out["workspace_clearance"] = _json_number(clearance, "workspace_clearance", out)
            out["robot_clearance"] = None if body is None else _json_number(body, "robot_clearance", out)
        json.dump(out, sys.stdout)
        sys.stdout.write("\n")
    else:
        end = ", ".join(f"{v:.4g}" for v in path.end)  # (x, y), or (x, y, z) on a voxel grid
        opt = f" (octile optimum {path.extra['optimal']:.4g})" if "optimal" in path.extra else ""
        # no path has no clearance: the line leaves it out rather than print "nan"
        cl = "" if path.status == "no_path" else f"min clearance {path.min_clearance:.4g}, "
        print(f"{path.planner}: {path.status} after {path.iterations} iterations, length {path.length:.4g}{opt}, "
              f"end ({end}), {cl}{path.seconds * 1e3:.1f} ms "
              f"(+ {startup * 1e3:.0f} ms start-up)")
        if path.extra.get("hint"):
            print(f"hint: {path.extra['hint']}")
        if robot and path.status != "no_path":
            extra = "" if body is None else f", the robot's body {body:.4g}"
            print(f"robot {_robot_text(args, workspace)}: clearance of the path {clearance:.4g}{extra}")
    if args.plot or args.animate:
        from .. import plot as gplot

        if args.plot:
            gplot.save_plan_figure(args.plot, target, path)
            print(f"wrote {args.plot}", file=sys.stderr if args.json else sys.stdout)
        if args.animate:
            gplot.save_plan_animation(args.animate, target, path, field=field)
            print(f"wrote {args.animate}", file=sys.stderr if args.json else sys.stdout)
    return 0


def _robot_no_path(args: argparse.Namespace, path: Path, workspace: Any, start: list[float], goal: list[float],
                   params: dict[str, Any], resolution: float | None) -> Path:
    """A robot's ``no_path``: the same search for a point on the workspace says whether the robot closes the passage."""
    from ..following.diagnose import robot_no_path
    from ..geometry.world import World
    from ..planners import PLANNERS, plan_with_field

    point_target = workspace
    if PLANNERS[args.planner][2] == "grid" and isinstance(workspace, World):
        from ..geometry.rasterize import as_gridmap

        point_target, resolution = as_gridmap(workspace, args.resolution), None
    point, _ = plan_with_field(args.planner, point_target, start, goal, params, resolution=resolution)
    return robot_no_path(path, point, _robot_text(args, workspace), start, goal)


def _other_kind(args: argparse.Namespace, workspace: Any, params: dict[str, Any]) -> int | None:
    """Plans that are not a point's on a map: a field store (``gridfield field ... --out F.zarr``, followed
    by chunks) and a robot that turns (``--headings N``, on its pose grid); None for the others."""
    if _is_stored_field(workspace):
        return _follow_stored(args, workspace, params)
    from .turning import run_plan, wants_turning

    if wants_turning(args):
        return run_plan(args, workspace, params)
    return None


def _is_stored_field(target: object) -> bool:
    from ..core.chunkcache import is_lazy
    from ..core.results import Field

    return isinstance(target, Field) and is_lazy(target)


def _follow_stored(args: argparse.Namespace, field: Field, params: dict[str, object]) -> int:
    """``plan F.zarr --start X Y``: the follower on a stored field, reading only the chunks it crosses (a store
    at a URL too: its tiles are fetched as the path crosses them)."""
    from ..core.errors import ParameterError
    from ..following.follower import follow
    from ..io import redact

    if args.planner != "potential":
        raise ParameterError(f"{args.map} holds a potential field: it is followed by the potential planner, "
                             f"not --planner {args.planner}")
    for opt in ("plot", "animate", "scenario"):
        if getattr(args, opt, None) is not None:
            raise ParameterError(f"--{opt} does not apply to a field store ({args.map} is read by chunks)")
    if args.start is None:
        raise ParameterError(f"{args.map} names no start; pass --start X Y")
    gx, gy = field.goal
    grid = field.map.grid
    if args.goal is not None and grid.cell_of(*args.goal) != grid.cell_of(gx, gy):  # the goal's cell, as built
        raise ParameterError(f"{args.map} is the field of the goal ({gx:g}, {gy:g}); --goal "
                             f"{args.goal[0]:g} {args.goal[1]:g} asks for another (build its field first)")
    path = replace(follow(field, args.start, params=params), planner="potential")
    cache = field.map.occupied.cache  # type: ignore[attr-defined]
    if args.json:
        out = path.to_json()
        out["chunks_read"] = cache.reads
        json.dump(out, sys.stdout)
        sys.stdout.write("\n")
    else:
        x, y = path.end
        print(f"{path.planner}: {path.status} after {path.iterations} iterations, length {path.length:.4g}, "
              f"end ({x:.4g}, {y:.4g}), min clearance {path.min_clearance:.4g}, {path.seconds * 1e3:.1f} ms; "
              f"read {cache.reads} chunk tiles of {redact(args.map)}")
        if path.extra.get("hint"):
            print(f"hint: {path.extra['hint']}")
    return 0


def _robot_text(args: argparse.Namespace, workspace: object) -> str:
    from ._common import _robot_from_args

    robot = _robot_from_args(args, workspace)
    return robot.describe() if robot is not None else "point"


def _json_number(v: float, key: str, out: dict[str, object]) -> float | None:
    """A float for JSON the way Path.to_json writes them: not finite as null, an infinity noted in
    ``out["infinite"]`` under ``key`` (1 for +inf, -1 for -inf)."""
    import math

    v = float(v)
    if math.isinf(v):
        out.setdefault("infinite", {})[key] = 1 if v > 0 else -1  # type: ignore[index]
    return v if math.isfinite(v) else None
