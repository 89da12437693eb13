"""Nav2 costmaps: inflation against the formula on scipy's exact distance, I/O round trips, OccupancyGrid,
queries against brute force, bad input."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.ndimage import distance_transform_edt

from gridfield.core.errors import GridfieldError, MapFormatError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.fields.costmap import Costmap, inflate
from gridfield.io import from_occupancy_grid, read, read_costmap, read_ros_map, to_occupancy_grid, write_costmap

from mapdata import TEST_MAPS

ROOT = Path(__file__).resolve().parents[1]
MAPS = TEST_MAPS
ROS_YAMLS = sorted((MAPS / "ros_maps").glob("*/*.yaml")) + sorted((MAPS / "ros_map_fixtures").glob("*/*.yaml"))


def _reference(occupied: np.ndarray, res: float, robot: float, big_r: float, k: float,
               lut: int | None = None) -> np.ndarray:
    """costmap_2d's computeCost written out directly (Python scalars per distinct distance) on scipy's EDT."""
    if not occupied.any():
        return np.zeros(occupied.shape, np.uint8)
    d = distance_transform_edt(~occupied)
    reach = math.ceil(big_r / res)

    def cost(dist: float) -> int:
        if dist == 0:
            return 254
        if dist * res <= robot:
            return 253
        return int(252 * math.exp(-1.0 * k * (dist * res - robot)))

    out = np.zeros(occupied.shape, np.uint8)
    values, inverse = np.unique(d, return_inverse=True)
    table = np.zeros(len(values), np.uint8)
    for i, v in enumerate(values):
        if v > reach:
            continue
        if lut is None:
            table[i] = cost(float(v))
        else:
            scaled = min(int(np.float32(np.sqrt(np.float32(v * v))) * np.float32(lut) + np.float32(0.5)),
                         reach * lut + 1)
            table[i] = cost(scaled / lut)
    out[...] = table[inverse.reshape(d.shape)]
    return out


@pytest.mark.parametrize("yaml_path", ROS_YAMLS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_inflation_is_the_formula_on_the_exact_distance_on_every_cell_of_every_ros_map(yaml_path):
    try:
        m = read_ros_map(yaml_path)
    except MapFormatError as e:  # a rotated origin (the fixture testmap): the same values on an unrotated grid
        assert "yaw" in str(e)
        from gridfield.io import read_yaml, ros_occupancy_values

        v = ros_occupancy_values(yaml_path)
        m = from_occupancy_grid(v.reshape(-1), v.shape[1], v.shape[0], float(read_yaml(yaml_path)["resolution"]),
                                (0.0, 0.0))
    res = m.grid.resolution
    for robot, big_r, k in ((0.1, 0.55, 10.0), (0.22, 1.0, 3.0)):
        cm = inflate(m, robot_radius=robot, inflation_radius=big_r, cost_scaling_factor=k)
        np.testing.assert_array_equal(cm.cost, _reference(m.occupied, res, robot, big_r, k), err_msg=str(yaml_path))
    if m.shape[0] * m.shape[1] <= 500_000:
        cm = inflate(m, lut_precision=100)
        np.testing.assert_array_equal(cm.cost, _reference(m.occupied, res, 0.1, 0.55, 10.0, lut=100))


def test_the_cost_classes_and_the_cut_off():
    occ = np.zeros((1, 30), bool)
    occ[0, 0] = True
    cm = inflate(GridMap(Grid((1, 30), 0.05), occ), robot_radius=0.1, inflation_radius=0.55)
    c = cm.cost[0]
    assert c[0] == 254 and (c[1:3] == 253).all()  # d * res <= 0.1
    assert c[3] == int(252 * math.exp(-10 * (0.15 - 0.1)))
    assert (np.diff(c[3:12].astype(int)) <= 0).all()
    assert (c[12:] == 0).all()  # beyond ceil(0.55 / 0.05) = 11 cells
    assert cm.occupied[0].tolist()[:4] == [True, True, True, False]


def test_the_map_edge_is_no_obstacle_and_unknown_cells_are_kept():
    occ = np.zeros((5, 5), bool)
    cm = inflate(GridMap(Grid((5, 5), 1.0, border="wall"), occ))
    assert (cm.cost == 0).all()
    unknown = np.zeros((1, 8), bool)
    unknown[0, 5:] = True
    occ = np.zeros((1, 8), bool)
    occ[0, 3] = True
    cm = inflate(GridMap(Grid((1, 8), 0.05), occ), keep_unknown=True, unknown=unknown, robot_radius=0.1)
    # the unknown cell at 2 cells is inflated to 253 (>= inscribed: Nav2 writes it), the farther ones stay 255
    assert cm.cost[0].tolist() == [152, 253, 253, 254, 253, 253, 255, 255]


def test_bad_inflation_parameters_are_one_clear_error():
    m = GridMap(Grid((3, 3), 0.05), np.eye(3, dtype=bool))
    with pytest.raises(ParameterError, match=r"inflation_radius \(0.1\) is smaller than robot_radius \(0.2\)"):
        inflate(m, robot_radius=0.2, inflation_radius=0.1)
    for kw, name in (({"cost_scaling_factor": -1.0}, "cost_scaling_factor"), ({"robot_radius": -0.1}, "robot_radius"),
                     ({"inflation_radius": math.nan}, "inflation_radius"), ({"lut_precision": 0}, "lut_precision")):
        with pytest.raises(ParameterError, match=name):
            inflate(m, **kw)
    with pytest.raises(ParameterError, match="keep_unknown needs"):
        inflate(m, keep_unknown=True)


# ----------------------------------------------------------------------------------------------
# I/O
# ----------------------------------------------------------------------------------------------
def test_write_read_round_trip_is_bit_exact(tmp_path):
    rng = np.random.default_rng(3)
    cost = rng.integers(0, 256, size=(37, 53)).astype(np.uint8)
    cost[0, :4] = [0, 100, 101, 255]
    cm = Costmap.from_costs(Grid((37, 53), 0.03, origin=(-15.1, -25.0)), cost, {"robot_radius": 0.2})
    back = read(write_costmap(tmp_path / "cm.yaml", cm))
    assert isinstance(back, Costmap) and isinstance(back, GridMap)
    np.testing.assert_array_equal(back.cost, cost)
    assert back.grid.resolution == 0.03 and back.grid.origin == (-15.1, -25.0)
    assert back.inflation["robot_radius"] == 0.2
    np.testing.assert_array_equal(back.occupied, cost >= 253)


def test_a_written_costmap_is_what_nav2_map_server_reads_in_raw_mode(tmp_path):
    """map_io.cpp raw mode: the grey level is the value, levels above 100 are unknown (-1); the image is
    stored top row first. gridfield's own Nav2 raw-mode reader sees the same."""
    from gridfield.io import ros_occupancy_values

    cost = np.array([[0, 50, 100], [101, 254, 255]], np.uint8)
    cm = Costmap.from_costs(Grid((2, 3), 0.05), cost)
    p = write_costmap(tmp_path / "cm.yaml", cm)
    raw = (tmp_path / "cm.pgm").read_bytes()
    assert raw.startswith(b"P5\n3 2\n255\n") and raw[-6:] == bytes([101, 254, 255, 0, 50, 100])
    assert ros_occupancy_values(p).tolist() == [[0, 50, 100], [-1, -1, -1]]


def test_a_costmap_yaml_in_another_mode_is_refused(tmp_path):
    cm = Costmap.from_costs(Grid((2, 2), 0.05), np.zeros((2, 2), np.uint8))
    p = write_costmap(tmp_path / "cm.yaml", cm)
    p.write_text(p.read_text().replace("mode: raw", "mode: trinary"))
    with pytest.raises(MapFormatError, match="must say 'mode: raw'"):
        read(p)
    with pytest.raises(MapFormatError, match="not a costmap YAML"):
        read_costmap(MAPS / "ros_maps" / "turtlebot3_world" / "map.yaml")


def test_occupancy_grid_round_trip():
    rng = np.random.default_rng(5)
    data = rng.choice([-1, 0, 0, 0, 37, 100], size=6 * 9).astype(np.int8)
    m = from_occupancy_grid(data, 9, 6, 0.05, (1.5, -2.0, 0.0))
    assert m.shape == (6, 9) and m.grid.origin == (1.5, -2.0)
    grid = data.reshape(6, 9)
    np.testing.assert_array_equal(m.occupied, (grid == 100) | (grid == -1))  # row 0 = the first row of data
    back = to_occupancy_grid(m)
    np.testing.assert_array_equal(back["data"], data)
    assert (back["width"], back["height"], back["resolution"], back["origin"]) == (9, 6, 0.05, (1.5, -2.0, 0.0))
    m2 = from_occupancy_grid(**back)
    np.testing.assert_array_equal(m2.occupied, m.occupied)
    free = from_occupancy_grid(data, 9, 6, 0.05, (0, 0), unknown="free")
    np.testing.assert_array_equal(free.occupied, grid == 100)


def test_a_ros_map_through_an_occupancy_grid_is_the_same_map():
    from gridfield.io import ros_occupancy_values

    y = MAPS / "ros_maps" / "turtlebot3_world" / "map.yaml"
    v = ros_occupancy_values(y)
    m = from_occupancy_grid(v.reshape(-1), v.shape[1], v.shape[0], 0.05, (-10.0, -10.0, 0.0))
    np.testing.assert_array_equal(m.occupied, read_ros_map(y).occupied)


def test_a_costmap_as_occupancy_grid_uses_the_costmap_publisher_table():
    cm = Costmap.from_costs(Grid((1, 6), 1.0), np.array([[0, 1, 252, 253, 254, 255]], np.uint8))
    assert to_occupancy_grid(cm)["data"].tolist() == [0, 1, 98, 99, 100, -1]


def test_bad_occupancy_grids_are_one_clear_error():
    with pytest.raises(ParameterError, match=r"has 5 values, but width \* height = 3 \* 2 = 6"):
        from_occupancy_grid([0] * 5, 3, 2, 0.05, (0, 0))
    with pytest.raises(ParameterError, match=r"data\[2\] = 101"):
        from_occupancy_grid([0, 0, 101, 0], 2, 2, 0.05, (0, 0))
    with pytest.raises(ParameterError, match="yaw"):
        from_occupancy_grid([0] * 4, 2, 2, 0.05, (0, 0, 0.5))
    with pytest.raises(GridfieldError):
        from_occupancy_grid([0] * 4, 2, 2, -1.0, (0, 0))


# ----------------------------------------------------------------------------------------------
# queries
# ----------------------------------------------------------------------------------------------
def _brute_nearest(cm: Costmap, pts: np.ndarray, unique: bool = False):
    r, c = np.nonzero(cm.cost == 254)
    ox, oy = cm.grid.origin[0] + (c + 0.5) * cm.grid.resolution, cm.grid.origin[1] + (r + 0.5) * cm.grid.resolution
    d2 = (pts[:, None, 0] - ox[None]) ** 2 + (pts[:, None, 1] - oy[None]) ** 2
    if unique:  # also whether the nearest obstacle cell is the only one at that distance
        two = np.sqrt(np.partition(d2, 1, axis=1)[:, :2])
        return two[:, 0], two[:, 1] > two[:, 0] + 1e-9
    return np.sqrt(d2.min(axis=1))


def test_queries_against_brute_force():
    rng = np.random.default_rng(11)
    occ = rng.random((25, 31)) < 0.05
    cm = inflate(GridMap(Grid((25, 31), 0.1, origin=(-1.0, 2.0)), occ), robot_radius=0.1, inflation_radius=0.5)
    xs, ys = cm.grid.cell_centers()
    cx, cy = np.meshgrid(xs, ys)
    centres = np.stack([cx.ravel(), cy.ravel()], axis=1)
    # exact at the cell centres: the distance, the nearest obstacle, the unit gradient, the cost
    exact, single = _brute_nearest(cm, centres, unique=True)
    np.testing.assert_allclose(cm.distance(centres), exact, rtol=1e-12, atol=1e-12)
    near = cm.nearest_obstacle(centres)
    np.testing.assert_allclose(np.hypot(*(near - centres).T), exact, rtol=1e-12, atol=1e-12)
    g = cm.gradient(centres)
    away = centres - near
    with np.errstate(invalid="ignore"):
        unit = away / np.hypot(*away.T)[:, None]
    ok = (exact > 0) & single  # on a tie (the medial axis) the gradient takes one of the nearest
    assert ok.sum() > 0.8 * len(ok)
    np.testing.assert_allclose(g[ok], unit[ok], atol=1e-12)
    np.testing.assert_array_equal(cm.cost_at(centres), cm.cost.ravel())
    # between the centres: bilinear in the exact distances (within a cell of the brute-force distance)
    pts = np.stack([rng.uniform(-1.0, 2.1, 4000), rng.uniform(2.0, 4.5, 4000)], axis=1)
    d = cm.distance(pts)
    assert np.abs(d - _brute_nearest(cm, pts)).max() <= cm.grid.resolution * math.sqrt(2) / 2 + 1e-12
    n = cm.nearest_obstacle(pts)
    assert (np.hypot(*(n - pts).T) <= _brute_nearest(cm, pts) + cm.grid.resolution * math.sqrt(2) + 1e-12).all()
    # outside
    assert np.isnan(cm.distance([[100.0, 100.0]])).all() and cm.cost_at([[100.0, 100.0]]).tolist() == [255]


# ----------------------------------------------------------------------------------------------
# CLI
# ----------------------------------------------------------------------------------------------
def _cli(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gridfield", *args], capture_output=True, text=True, cwd=cwd,
                          env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})


def test_cli_costmap_writes_a_costmap_that_plan_navfn_plans_on(tmp_path):
    y = MAPS / "ros_maps" / "turtlebot3_world" / "map.yaml"
    res = _cli("costmap", str(y), "--out", "cm.yaml", "--query", "-1", "0.5", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert res.stdout.startswith("costmap 384x384 cells of 0.05") and "at (-1, 0.5): cost " in res.stdout
    cm = read(tmp_path / "cm.yaml")
    np.testing.assert_array_equal(cm.cost, inflate(read_ros_map(y)).cost)
    res = _cli("plan", "cm.yaml", "--planner", "navfn", "--start", "-2", "-0.5", "--goal", "1.5", "0.5", cwd=tmp_path)
    assert res.returncode == 0 and res.stdout.startswith("navfn: reached"), res.stdout + res.stderr


@pytest.mark.parametrize("args, message", [
    (["--robot-radius", "0.6", "--inflation-radius", "0.5"], "inflation_radius (0.5) is smaller than robot_radius"),
    (["--cost-scaling-factor", "-2"], "cost_scaling_factor must be a finite number >= 0"),
    (["--out", "cm.txt"], "name it F.yaml"),
])
def test_cli_bad_input_is_one_line_and_exit_2(tmp_path, args, message):
    res = _cli("costmap", str(MAPS / "ros_maps" / "turtlebot3_world" / "map.yaml"), *args, cwd=tmp_path)
    assert res.returncode == 2 and message in res.stderr and len(res.stderr.strip().splitlines()) == 1, res.stderr


def test_cli_plan_on_a_costmap_yaml_in_another_mode_is_exit_2(tmp_path):
    cm = inflate(read_ros_map(MAPS / "ros_maps" / "turtlebot3_world" / "map.yaml"))
    p = write_costmap(tmp_path / "cm.yaml", cm)
    p.write_text(p.read_text().replace("mode: raw", "mode: scale"))
    res = _cli("plan", "cm.yaml", "--planner", "navfn", "--start", "-2", "-0.5", "--goal", "1.5", "0.5", cwd=tmp_path)
    assert res.returncode == 2 and "must say 'mode: raw'" in res.stderr and len(res.stderr.strip().splitlines()) == 1


def test_cli_keep_unknown_and_the_navfn_field(tmp_path):
    y = MAPS / "ros_maps" / "turtlebot3_world" / "map.yaml"
    res = _cli("costmap", str(y), "--keep-unknown", "--lut-precision", "100", "--out", "cm.yaml", cwd=tmp_path)
    assert res.returncode == 0 and "unknown" in res.stdout, res.stderr
    cm = read(tmp_path / "cm.yaml")
    assert (cm.cost == 255).mean() > 0.5 and cm.inflation["lut_precision"] == 100
    res = _cli("field", "cm.yaml", "--planner", "navfn", "--goal", "1.5", "0.5", cwd=tmp_path)
    assert res.returncode == 0 and "navfn navigation function" in res.stdout, res.stderr
    res = _cli("costmap", str(MAPS / "movingai" / "arena" / "arena.map.gz"), "--keep-unknown", cwd=tmp_path)
    assert res.returncode == 2 and "--keep-unknown needs a ROS map YAML" in res.stderr


def _echo_yaml(path: Path, data, width: int, height: int, res: float = 0.05, origin=(1.0, -2.0), qz: float = 0.0):
    """An OccupancyGrid message as `ros2 topic echo --once /map` prints it (YAML)."""
    import yaml

    msg = {"header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": "map"},
           "info": {"map_load_time": {"sec": 0, "nanosec": 0}, "resolution": res, "width": width, "height": height,
                    "origin": {"position": {"x": origin[0], "y": origin[1], "z": 0.0},
                               "orientation": {"x": 0.0, "y": 0.0, "z": qz, "w": 1.0}}},
           "data": [int(v) for v in data]}
    path.write_text(yaml.safe_dump(msg))
    return path


def test_an_echoed_occupancy_grid_message_is_read_and_planned_on(tmp_path):
    rng = np.random.default_rng(2)
    data = np.where(rng.random(40 * 30) < 0.1, 100, 0)
    data[:5] = -1
    p = _echo_yaml(tmp_path / "msg.yaml", data, 40, 30)
    m = read(p)
    assert m.shape == (30, 40) and m.grid.origin == (1.0, -2.0)
    np.testing.assert_array_equal(to_occupancy_grid(m)["data"], data)
    np.testing.assert_array_equal(read(p, unknown="free").occupied.reshape(-1), data == 100)
    res = _cli("costmap", "msg.yaml", "--unknown", "free", cwd=tmp_path)
    assert res.returncode == 0 and res.stdout.startswith("costmap 30x40 cells"), res.stderr


def test_an_occupancy_grid_message_of_the_wrong_length_or_rotated_is_exit_2(tmp_path):
    _echo_yaml(tmp_path / "short.yaml", [0] * 11, 4, 3)
    res = _cli("costmap", "short.yaml", cwd=tmp_path)
    assert res.returncode == 2 and len(res.stderr.strip().splitlines()) == 1
    assert "has 11 values, but width * height = 4 * 3 = 12" in res.stderr
    with pytest.raises(MapFormatError, match="rotated"):
        read(_echo_yaml(tmp_path / "rot.yaml", [0] * 12, 4, 3, qz=0.3))
    with pytest.raises(MapFormatError, match=r"data\[1\] = 120"):
        read(_echo_yaml(tmp_path / "bad.yaml", [0, 120, 0, 0], 2, 2))


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 18), st.integers(1, 18), st.integers(0, 2**32 - 1), st.sampled_from([0.03, 0.05, 0.1, 0.5, 1.0]),
       st.floats(0.0, 1.0), st.floats(0.0, 2.0), st.floats(0.0, 20.0), st.sampled_from([None, 100, 7]))
def test_inflation_matches_the_formula_on_random_grids(rows, cols, seed, res, robot, extra, k, lut):
    occ = np.random.default_rng(seed).random((rows, cols)) < 0.15
    big_r = robot + extra
    cm = inflate(GridMap(Grid((rows, cols), res), occ), robot_radius=robot, inflation_radius=big_r,
                 cost_scaling_factor=k, lut_precision=lut)
    np.testing.assert_array_equal(cm.cost, _reference(occ, res, robot, big_r, k, lut))
