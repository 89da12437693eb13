"""``--headings N``: the commands for a robot that turns, planning in ``(x, y, theta)``.

``gridfield plan MAP --robot ... --headings N --start X Y THETA --goal X Y [THETA]`` plans on the pose
grid (:class:`~gridfield.geometry.cspace.PoseMap`) with ``potential`` (default) or
``wavefront-octile``; ``gridfield info MAP --robot ... --headings N`` describes that pose grid.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

from ..core.errors import ParameterError

__all__ = ["TURNING_PLANNERS", "pose_space", "run_info", "run_plan", "wants_turning"]

#: The planners that plan on a pose grid.
TURNING_PLANNERS = ("potential", "wavefront-octile")


def wants_turning(args: argparse.Namespace) -> bool:
    """Whether the command line asks for a turning robot (``--headings`` of 2 or more)."""
    n = getattr(args, "headings", None)
    return n is not None and n != 1


def pose_space(args: argparse.Namespace, workspace: Any) -> Any:
    """The pose grid of the workspace for the robot and ``--headings`` of the command line."""
    from ..geometry.cspace import apply_robot
    from ..geometry.world import World
    from ._common import _robot_from_args

    robot = _robot_from_args(args, workspace)
    if robot is None:
        raise ParameterError("--headings needs the robot's shape: --robot X,Y ... or --robot-radius R")
    if isinstance(workspace, World) and getattr(args, "resolution", None) is not None:
        import dataclasses

        workspace = dataclasses.replace(workspace, resolution=args.resolution)  # apply_robot rasterizes at it
    return apply_robot(workspace, robot, headings=args.headings)


def _endpoints(args: argparse.Namespace, workspace: Any) -> tuple[list[float], list[float]]:
    world = getattr(workspace, "world", None) or workspace
    start = args.start if args.start is not None else None
    goal = args.goal if args.goal is not None else getattr(world, "goal", None)
    if start is None or len(start) != 3:
        got = "none" if start is None else f"{len(start)} ({' '.join(f'{v:g}' for v in start)})"
        raise ParameterError(f"--headings needs --start X Y THETA (theta in radians, counter-clockwise from x), got {got}")
    if goal is None or len(goal) not in (2, 3):
        got = "none" if goal is None else f"{len(goal)} numbers"
        raise ParameterError(f"--headings needs --goal X Y (any heading) or X Y THETA, got {got}")
    return list(start), list(goal)


def run_plan(args: argparse.Namespace, workspace: Any, params: dict[str, Any]) -> int:
    """``gridfield plan ... --headings N``."""
    from ..following.posefollow import plan_poses

    if args.planner not in TURNING_PLANNERS:
        raise ParameterError(f"--planner {args.planner} does not plan for a turning robot; with --headings use "
                             f"{' or '.join(TURNING_PLANNERS)}")
    if getattr(args, "scenario", None) is not None:
        raise ParameterError("--scenario gives points, not poses: with --headings give --start X Y THETA")
    start, goal = _endpoints(args, workspace)
    pm = pose_space(args, workspace)
    path, _ = plan_poses(pm, start, goal, params, planner=args.planner)
    turned = float(sum(abs(math.remainder(b - a, 2 * math.pi))
                       for a, b in zip(path.poses[:-1, 2], path.poses[1:, 2], strict=True))) if path.poses is not None else 0.0
    if args.json:
        out = path.to_json()
        out["robot"] = pm.robot.describe()
        out["headings"] = pm.headings
        out["turned"] = turned
        json.dump(out, sys.stdout)
        sys.stdout.write("\n")
    else:
        end = ", ".join(f"{v:.4g}" for v in (path.poses[-1] if path.poses is not None and len(path.poses) else path.end))
        print(f"{path.planner}: {path.status} after {path.iterations} poses, length {path.length:.4g}, "
              f"turned {math.degrees(turned):.0f} degrees, end ({end}), {path.seconds * 1e3:.1f} ms")
        print(f"robot {pm.robot.describe()} over {pm.headings} headings ({360 / pm.headings:g} degrees each); "
              f"a turn by one costs {pm.turn_cost:.4g} (the arc of its farthest point)")
    if args.plot or args.animate:
        from ..plot.poses import save_pose_animation, save_pose_figure

        if args.plot:
            save_pose_figure(args.plot, pm, path)
            print(f"wrote {args.plot}", file=sys.stderr if args.json else sys.stdout)
        if args.animate:
            save_pose_animation(pm, path, args.animate)
            print(f"wrote {args.animate}", file=sys.stderr if args.json else sys.stdout)
    return 0


def run_info(args: argparse.Namespace, workspace: Any) -> int:
    """``gridfield info ... --headings N``: the pose grid's size and how much of it is free."""
    import numpy as np

    pm = pose_space(args, workspace)
    free = ~pm.occupied
    per = free.reshape(pm.headings, -1).mean(axis=1)
    anywhere = free.any(axis=0).mean()
    info = {"source": args.map, "robot": pm.robot.describe(), "headings": pm.headings,
            "shape": list(pm.shape), "resolution": pm.grid.resolution, "turn_cost": pm.turn_cost,
            "free": float(free.mean()), "free_at_some_heading": float(anywhere),
            "free_per_heading": [float(v) for v in per]}
    if getattr(args, "json", False):
        json.dump(info, sys.stdout)
        sys.stdout.write("\n")
        return 0
    k = int(np.argmin(per))
    print(f"{args.map}: pose grid {pm.headings} headings x {pm.grid.rows} x {pm.grid.cols} for the robot "
          f"{pm.robot.describe()}")
    print(f"free poses {free.mean():.1%}; cells free at some heading {anywhere:.1%}, at every heading "
          f"{free.all(axis=0).mean():.1%}; least free heading {360 * k / pm.headings:g} degrees ({per[k]:.1%})")
    print(f"a turn by one heading bin costs {pm.turn_cost:.4g}")
    return 0
