"""Issue 30: a ``no_path`` that the robot's size causes says so (the robot closes the passage, a point reaches).

Maps: ROS maps of tests/data/maps (the Nav2 smoothers world, the mdr WRS 2020 arena). The premise of each
case is checked independently of the planners: scipy's connected components join start and goal on the
map's free cells (a point) and part them on the cells where the disc touches no occupied cell square
(the robot), computed here from a Euclidean distance transform.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy import ndimage

from gridfield.cli import main
from gridfield.core.path import Path
from gridfield.following.diagnose import robot_no_path
from gridfield.io import read_ros_map

from mapdata import ROS_MAPS as MAPS

SMOOTHERS = MAPS / "nav2_smoothers_world" / "smoothers_world.yaml"
MDR = MAPS / "mdr_wrs20-arena" / "map.yaml"

#: (map, robot radius, start, goal): the goal lies in a region the disc fits in but cannot enter
CASES = [
    (SMOOTHERS, 0.4, (9.975, 10.975), (1.075, 13.875)),
    (MDR, 0.2, (0.775, 3.625), (0.025, 1.825)),
]


def _components(free: np.ndarray, grid, start, goal) -> tuple[int, int]:
    lab = ndimage.label(free)[0]  # 4-connected
    return lab[grid.cell_of(*start)], lab[grid.cell_of(*goal)]


@pytest.mark.parametrize(("map_file", "radius", "start", "goal"), CASES, ids=["smoothers", "mdr"])
def test_the_premise_a_point_reaches_the_disc_does_not(map_file, radius, start, goal):
    gm = read_ros_map(map_file)
    a, b = _components(~gm.occupied, gm.grid, start, goal)
    assert a != 0 and a == b  # a point: one free region
    # the disc at a cell centre touches the square of the cell (di, dj) cells away iff the distance from
    # the centre to that square, hypot(max(|di| h - h/2, 0), max(|dj| h - h/2, 0)), is below the radius
    h = gm.grid.resolution
    k = int(np.ceil(radius / h)) + 1
    di, dj = np.mgrid[-k:k + 1, -k:k + 1]
    reach = np.hypot(np.maximum(np.abs(di) * h - h / 2, 0), np.maximum(np.abs(dj) * h - h / 2, 0)) < radius
    free = ~ndimage.binary_dilation(gm.occupied, structure=reach)
    a, b = _components(free, gm.grid, start, goal)
    assert a != 0 and b != 0 and a != b  # the disc fits at both ends, but no free region joins them


@pytest.mark.parametrize("planner", ["potential", "wavefront-octile"])
@pytest.mark.parametrize(("map_file", "radius", "start", "goal"), CASES, ids=["smoothers", "mdr"])
def test_cli_no_path_names_the_robot(map_file, radius, start, goal, planner, capsys):
    args = ["plan", str(map_file), "--start", *map(str, start), "--goal", *map(str, goal),
            "--robot-radius", str(radius), "--planner", planner]
    assert main(args) == 0
    out = capsys.readouterr().out
    head, hint = out.splitlines()[:2]
    assert head.startswith(f"{planner}: no_path")
    assert hint.startswith(f"hint: the robot (disc of radius {radius:g}) closes the passage")
    assert "but a point reaches it" in hint
    assert main([*args, "--json"]) == 0
    j = json.loads(capsys.readouterr().out)
    assert j["status"] == "no_path" and j["hint"] == hint.removeprefix("hint: ")
    # the point's length quoted is the planner's own on the map without the robot
    assert main([*args[:-4], "--planner", planner, "--json"]) == 0
    point = json.loads(capsys.readouterr().out)
    assert point["status"] == "reached" and f"length {point['length']:.4g})" in hint


@pytest.mark.parametrize(("map_file", "radius", "start", "goal"), CASES[1:], ids=["mdr"])
def test_cli_no_path_prints_no_clearance(map_file, radius, start, goal, capsys):
    # no path has no clearance: neither "min clearance nan" nor the start's distance called the path's clearance
    args = ["plan", str(map_file), "--start", *map(str, start), "--goal", *map(str, goal), "--robot-radius", str(radius)]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "nan" not in out and "clearance of the path" not in out
    assert f"the goal ({goal[0]:g}, {goal[1]:g})" in out  # the end points as given (1.825, not 1.82)
    assert main([*args, "--json"]) == 0
    j = json.loads(capsys.readouterr().out)
    assert j["status"] == "no_path"
    assert j["min_clearance"] is None and j["workspace_clearance"] is None and j["robot_clearance"] is None


def test_robot_no_path_leaves_other_runs_alone():
    s = np.array([[1.0, 2.0]])
    blocked = Path(s, "no_path", "wavefront", extra={"reason": "the goal is unreachable from the start"})
    also_blocked = Path(s, "no_path", "wavefront")
    assert robot_no_path(blocked, also_blocked, "disc of radius 1", (1, 2), (3, 2)) is blocked
    reached = Path(np.array([[1.0, 2.0], [3.0, 2.0]]), "reached", "wavefront")
    assert robot_no_path(reached, reached, "disc of radius 1", (1, 2), (3, 2)) is reached
    stalled = Path(np.array([[1.0, 2.0], [2.0, 2.0]]), "local_minimum", "potential")
    p = robot_no_path(blocked, stalled, "disc of radius 1", (1, 2), (3, 2))
    assert "closes the passage" in p.hint and "a point reaches" not in p.hint and "ends local_minimum" in p.hint
    assert p.extra["diagnosis"] == {"reachable": False, "robot_closes_passage": True, "point_status": "local_minimum"}
