"""A robot that turns: every planned motion checked with exact geometry (shapely places the robot
polygon, turned and moved, along the path), the door passed only with rotation, start and goal headings."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.cspace import apply_robot, wrap_angle
from gridfield.geometry.world import Robot

pytest.importorskip("gridfield.fields.navigation3d")
import itertools

from gridfield.following.posefollow import plan_poses

CART = Robot(vertices=[[-0.8, -0.25], [0.8, -0.25], [0.8, 0.25], [-0.8, 0.25]])


def door_map(door=1.0, h=0.1, size=10.0):
    """A wall across y = size/2 with a door of width ``door`` centred at x = size/2."""
    n = round(size / h)
    occ = np.zeros((n, n), bool)
    xs = (np.arange(n) + 0.5) * h
    wall = round(size / 2 / h)
    occ[wall - 1:wall + 1, np.abs(xs - size / 2) > door / 2] = True
    return GridMap(Grid((n, n), h, border="wall"), occ)


def obstacles(gm: GridMap):
    cells = np.argwhere(gm.occupied)
    h = gm.grid.resolution
    c = gm.grid.cell_to_world(cells)
    return shapely.union_all(shapely.box(c[:, 0] - h / 2, c[:, 1] - h / 2, c[:, 0] + h / 2, c[:, 1] + h / 2))


def placed(robot: Robot, poses: np.ndarray):
    v = robot.vertices
    c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
    ring = np.stack([poses[:, :1] + c * v[:, 0] - s * v[:, 1], poses[:, 1:2] + s * v[:, 0] + c * v[:, 1]], axis=2)
    return shapely.polygons(ring)


def assert_motion_clear(gm: GridMap, robot: Robot, poses: np.ndarray, step_cells: float = 0.05):
    """The robot moved along every segment of the path (x, y linear, the heading along the shortest turn)
    touches no occupied cell square and stays inside the bounds (a wall border): sampled so finely that
    the convex hull of two consecutive placements covers the motion between them."""
    obs = obstacles(gm)
    h = gm.grid.resolution
    r = float(np.hypot(*robot.vertices.T).max())
    xmin, ymin, xmax, ymax = gm.grid.bounds
    inside = shapely.box(xmin, ymin, xmax, ymax)
    for a, b in itertools.pairwise(poses):
        dth = float(wrap_angle(b[2] - a[2]))
        length = math.hypot(b[0] - a[0], b[1] - a[1]) + r * abs(dth)
        n = max(2, math.ceil(length / (step_cells * h)) + 1)
        t = np.linspace(0.0, 1.0, n)[:, None]
        q = np.column_stack([a[:2] + t * (b[:2] - a[:2]), a[2] + t[:, 0] * dth])
        shapes = placed(robot, q)
        hulls = shapely.convex_hull(shapely.union(shapes[:-1], shapes[1:]))
        assert not shapely.intersects(hulls, obs).any(), f"the robot touches an obstacle between {a} and {b}"
        if gm.grid.border == "wall":
            assert shapely.within(shapes, inside).all(), f"the robot leaves the map between {a} and {b}"


def test_door_narrower_than_the_cart_is_passed_by_turning():
    gm = door_map(door=1.0)  # 1.0 m: wider than the cart's 0.5 m width, narrower than its 1.6 m length
    pm = apply_robot(gm, CART, headings=72)
    path, _ = plan_poses(pm, (5.0, 2.0, 0.0), (5.0, 8.0, 0.0))
    assert path.status == "reached"
    assert_motion_clear(gm, CART, path.poses)
    # where it crosses the wall's middle the cart is lengthwise (within the door's play)
    p = path.poses
    i = int(np.flatnonzero((p[:-1, 1] - 5.0) * (p[1:, 1] - 5.0) <= 0)[0])
    t = (5.0 - p[i, 1]) / (p[i + 1, 1] - p[i, 1])
    theta = p[i, 2] + t * float(wrap_angle(p[i + 1, 2] - p[i, 2]))
    assert abs(abs(float(wrap_angle(theta))) - math.pi / 2) < 0.35
    # without turning (the translating C-space: the cart at heading 0) there is no way
    trans = apply_robot(gm, CART)
    from gridfield.planners import plan

    assert plan("wavefront-octile", trans, (5.0, 2.0), (5.0, 8.0)).status == "no_path"


def test_door_narrower_than_the_width_is_refused():
    pm = apply_robot(door_map(door=0.45), CART, headings=36)
    path, _ = plan_poses(pm, (5.0, 2.0, 0.0), (5.0, 8.0, 0.0))
    assert path.status == "no_path"


@pytest.mark.parametrize("planner", ["potential", "wavefront-octile"])
@pytest.mark.parametrize("goal_heading", [0.0, 2.0, -1.2, None])
def test_headings_honoured_and_motion_clear(planner, goal_heading):
    gm = door_map(door=1.2, h=0.125)
    pm = apply_robot(gm, CART, headings=48)
    start = (3.0, 2.0, 0.7)
    goal = (6.5, 7.5) if goal_heading is None else (6.5, 7.5, goal_heading)
    path, _ = plan_poses(pm, start, goal, planner=planner)
    assert path.status == "reached"
    assert np.allclose(path.poses[0], start)
    assert np.allclose(path.poses[-1, :2], goal[:2])
    if goal_heading is not None:
        assert math.isclose(path.poses[-1, 2], wrap_angle(goal_heading), abs_tol=1e-9)
    assert_motion_clear(gm, CART, path.poses)
    assert path.to_json()["poses"][0] == pytest.approx(list(start))


@pytest.mark.parametrize("seed", range(4))
def test_random_clutter_motion_clear(seed):
    rng = np.random.default_rng(seed)
    occ = np.zeros((60, 60), bool)
    for _ in range(14):
        r, c = rng.integers(0, 56, 2)
        occ[r:r + rng.integers(1, 5), c:c + rng.integers(1, 5)] = True
    gm = GridMap(Grid((60, 60), 0.1, border="wall"), occ)
    robot = Robot(vertices=[[-0.4, -0.15], [0.5, -0.15], [0.5, 0.15], [-0.4, 0.15]])
    pm = apply_robot(gm, robot, headings=36)
    free = np.argwhere(~pm.occupied)
    for _ in range(3):
        a, b = free[rng.integers(len(free), size=2)]
        sp, gp = pm.pose_of_cell([a])[0], pm.pose_of_cell([b])[0]
        path, _ = plan_poses(pm, sp, gp)
        if path.status == "reached":
            assert_motion_clear(gm, robot, path.poses)


def test_bad_poses_name_the_pose_and_the_obstacle():
    pm = apply_robot(door_map(door=1.0), CART, headings=36)
    with pytest.raises(GridfieldError, match=r"start \(5, 4.8, 0\): the robot .* touches the occupied cell at"):
        plan_poses(pm, (5.0, 4.8, 0.0), (5.0, 8.0))
    with pytest.raises(GridfieldError, match="lies inside an obstacle"):
        plan_poses(pm, (1.0, 5.0, 0.0), (5.0, 8.0))
    with pytest.raises(ParameterError, match="three finite numbers"):
        plan_poses(pm, (1.0, 2.0), (5.0, 8.0))
    with pytest.raises(ParameterError, match="headings must be"):
        apply_robot(door_map(), CART, headings=10_000)
    with pytest.raises(ParameterError, match="point robot does not turn"):
        apply_robot(door_map(), None, headings=8)


def _gap_png(tmp_path, door_cells=10):
    from PIL import Image

    img = np.full((100, 100), 255, np.uint8)
    img[49:51, :] = 0
    img[49:51, 50 - door_cells // 2:50 + door_cells // 2] = 255
    img[0, :] = img[-1, :] = img[:, 0] = img[:, -1] = 0  # a frame: no way round the wall
    f = tmp_path / "gap.png"
    Image.fromarray(img).save(f)
    return str(f)


def test_cli_plan_with_headings(tmp_path, capsys):
    import json

    from gridfield.cli import main

    f = _gap_png(tmp_path)
    robot = "-0.8,-0.25 0.8,-0.25 0.8,0.25 -0.8,0.25"
    base = [f, "--resolution", "0.1", "--robot", robot]
    # translating, the cart cannot pass the 1.0 m door (the frame closes the way round)
    assert main(["plan", *base, "--start", "5", "2", "--goal", "5", "8", "--json"]) == 0
    j0 = json.loads(capsys.readouterr().out)
    assert j0["status"] == "no_path" and "--headings N" in j0["hint"]
    out_png = tmp_path / "p.png"
    assert main(["plan", *base, "--headings", "72", "--start", "5", "2", "0", "--goal", "5", "8", "1.2",
                 "--json", "--plot", str(out_png)]) == 0
    j = json.loads(capsys.readouterr().out)
    assert j["status"] == "reached" and j["headings"] == 72 and out_png.stat().st_size > 0
    poses = np.array(j["poses"])
    assert np.allclose(poses[0], [5, 2, 0]) and np.allclose(poses[-1], [5, 8, 1.2])
    gm = GridMap(Grid((100, 100), 0.1), _read_gap(f))
    assert_motion_clear(gm, CART, poses)
    # bad input: one line on stderr, exit code 2
    for extra, msg in [(["--headings", "0"], "headings must be a whole number"),
                       (["--headings", "72", "--planner", "visibility"], "does not plan for a turning robot")]:
        assert main(["plan", *base, *extra, "--start", "5", "2", "0", "--goal", "5", "8"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and msg in err[0]
    assert main(["info", *base, "--headings", "36", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["shape"] == [36, 100, 100] and 0 < info["free"] < 1


def _read_gap(f):
    from gridfield.io import read

    return read(f, resolution=0.1).occupied
