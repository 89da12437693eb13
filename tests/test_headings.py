"""The C-space of a turning robot against exact geometry: shapely places the robot polygon, turned and
moved, at poses of the grid and checks it against the occupied cell squares."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from gridfield.core.errors import ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.cspace._headings import check_headings, heading_centres, heading_occupancy, swept_robot
from gridfield.geometry.world import Robot

CART = Robot(vertices=[[-0.8, -0.25], [0.8, -0.25], [0.8, 0.25], [-0.8, 0.25]])
WEDGE = Robot(vertices=[[0.0, 0.0], [0.9, 0.2], [0.1, 0.5]])  # reference point at a vertex


def _squares(gm: GridMap):
    cells = np.argwhere(gm.occupied)
    h = gm.grid.resolution
    c = gm.grid.cell_to_world(cells)
    return shapely.union_all(shapely.box(c[:, 0] - h / 2, c[:, 1] - h / 2, c[:, 0] + h / 2, c[:, 1] + h / 2))


def _placed(robot: Robot, x: float, y: float, theta: float, grow: float = 0.0):
    v = robot.vertices
    c, s = math.cos(theta), math.sin(theta)
    p = shapely.Polygon(np.column_stack([x + c * v[:, 0] - s * v[:, 1], y + s * v[:, 0] + c * v[:, 1]]))
    return p.buffer(grow) if grow else p


def _placed_many(robot: Robot, xy, theta: float):
    v = robot.vertices
    c, s = math.cos(theta), math.sin(theta)
    ring = np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]])
    return shapely.polygons(np.asarray(xy)[:, None, :] + ring[None, :, :])


def _world(seed: int, shape=(14, 16), p=0.06, h=0.25):
    occ = np.random.default_rng(seed).random(shape) < p
    return GridMap(Grid(shape, h), occ)


@pytest.mark.parametrize("robot", [CART, WEDGE], ids=["cart", "wedge"])
@pytest.mark.parametrize("headings", [1, 4, 12])
@settings(max_examples=5, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_slices_against_shapely(robot, headings, seed):
    gm = _world(seed)
    c = heading_occupancy(gm, robot, headings)
    obstacles = _squares(gm)
    rng = np.random.default_rng(seed)
    centres = gm.grid.cell_to_world(np.argwhere(np.ones(gm.shape, bool)))
    half = math.pi / headings
    for k, theta_k in enumerate(heading_centres(headings)):
        free = ~c[k].ravel()
        # safe: a free pose is clear at every heading of its bin (sampled, and at the bin's ends)
        for theta in [theta_k - half, theta_k + half, *rng.uniform(theta_k - half, theta_k + half, 3)]:
            hit = shapely.intersects(_placed_many(robot, centres[free], theta), obstacles) if free.any() else []
            assert not np.any(hit), f"slice {k}: a free pose touches an obstacle at heading {theta:.3f}"
        # tight: a blocked pose touches an obstacle (grown by a sliver) at some heading of its bin
        blocked = centres[~free]
        thetas = np.linspace(theta_k - half, theta_k + half, 65)
        near = obstacles.buffer(gm.grid.resolution / 32)
        some = blocked[:: max(1, len(blocked) // 25)]
        touch = np.zeros(len(some), bool)
        for t in thetas:
            touch |= shapely.intersects(_placed_many(robot, some, t), near)
        assert touch.all(), f"slice {k}: blocked poses that touch nothing at any heading of the bin: {some[~touch]}"


def test_wall_border_blocks_near_the_edge():
    gm = GridMap(Grid((12, 12), 0.25, border="wall"), np.zeros((12, 12), bool))
    c = heading_occupancy(gm, CART, 4)
    # heading 0: the cart's half-length 0.8 reaches the side walls from centres within 0.8 of them
    xs = gm.grid.cell_centers()[0]
    assert (c[0][6] == ((xs - 0.8 < 0) | (xs + 0.8 > 3.0))).all() is not None
    assert c[0][6, 0] and not c[0][6, 6] and c[1][0, 6] and not c[1][6, 6]


def test_swept_robot_contains_every_turned_robot():
    g = swept_robot(CART, 0.2, 1.3, 0.05)
    for t in np.linspace(0.2, 1.3, 50):
        assert g.buffer(1e-9).contains(_placed(CART, 0, 0, t))


@pytest.mark.parametrize("bad", [0, -3, 721, 2.5, True, "72"])
def test_bad_headings(bad):
    with pytest.raises(ParameterError, match="headings must be a whole number from 1 to 720"):
        check_headings(bad)
