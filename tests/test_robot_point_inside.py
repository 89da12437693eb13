"""A start or goal inside an obstacle, with a robot: the error says the point is inside an obstacle and
names a free place where the robot fits, not "make the robot smaller" (no robot size helps there; the
message used to read "is 0 from the nearest occupied cell, within the robot ... make the robot smaller").
The suggested place is checked against a brute-force distance from its centre to every occupied square."""

from __future__ import annotations

import re

import numpy as np
import pytest

from gridfield.cli import main
from gridfield.core.errors import GridfieldError
from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.cspace import check_robot_point
from gridfield.io import bundled_map, read_world


def _square_distance(occ: np.ndarray, x: float, y: float) -> float:
    """Distance from (x, y) to the nearest occupied unit cell square (row 0 at the bottom)."""
    rows, cols = np.nonzero(occ)
    dx = np.maximum(np.abs(x - (cols + 0.5)) - 0.5, 0.0)
    dy = np.maximum(np.abs(y - (rows + 0.5)) - 0.5, 0.0)
    return float(np.hypot(dx, dy).min())


def test_a_grid_point_inside_an_obstacle_is_named_so_with_a_place_the_robot_fits(tmp_path, capsys):
    occ = np.zeros((10, 12), bool)
    occ[4:6, 0:8] = True
    occ[8, 3] = True
    np.save(tmp_path / "m.npy", occ)
    code = main(["plan", str(tmp_path / "m.npy"), "--start", "2.5", "4.5", "--goal", "10.5", "8.5",
                 "--robot-radius", "0.6"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert "start (2.5, 4.5) lies inside an obstacle" in err and "smaller" not in err, err
    x, y = map(float, re.search(r"centre is \(([-\d.]+), ([-\d.]+)\)", err).groups())
    assert _square_distance(occ, x, y) >= 0.6  # the robot fits there
    assert _square_distance(occ, 2.5, 4.5) == 0.0


def test_a_world_point_inside_an_obstacle_is_named_so():
    world = read_world(bundled_map("seed000.yaml"))
    inside = world.obstacles[0].geometry.representative_point()
    assert world.obstacles[0].geometry.contains(inside)
    with pytest.raises(GridfieldError, match=r"^start \(8, 14\) lies inside obstacle 1$"):
        check_robot_point(world, 0.5, "start", (inside.x, inside.y))


def test_a_point_beside_an_obstacle_still_gets_the_robot_message():
    occ = np.zeros((10, 12), bool)
    occ[4:6, 0:8] = True
    gm = GridMap(Grid((10, 12), 1.0), occ)
    with pytest.raises(GridfieldError, match=r"within the robot .* make the robot smaller"):
        check_robot_point(gm, 0.6, "goal", (2.5, 3.5))
