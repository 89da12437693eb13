"""The robot's shape on every command: configuration spaces against shapely's exact geometry,
path clearance in the workspace, endpoint errors, the world file's ``robot:`` key, the CLI flags."""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from shapely.geometry import Point

from gridfield.cli import main
from gridfield.core.errors import GridfieldError, MapFormatError
from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.cspace import apply_robot, check_robot_point, conservative_footprint, workspace_clearance
from gridfield.geometry.rasterize import as_gridmap
from gridfield.geometry.world import Robot, world_from_dict
from gridfield.io import bundled_map, read, read_world
from gridfield.sweep import load_spec, run_sweep

H = 0.5  # cell size of the random grids (exact in binary)


def cell_boxes(grid: Grid, cells: np.ndarray) -> np.ndarray:
    """Closed cell squares as shapely boxes."""
    x0, y0 = grid.origin
    h = grid.resolution
    return shapely.box(x0 + cells[:, 1] * h, y0 + cells[:, 0] * h, x0 + (cells[:, 1] + 1) * h,
                       y0 + (cells[:, 0] + 1) * h)


def swept(boxes: np.ndarray, robot: np.ndarray) -> np.ndarray:
    """``box ⊕ R`` for each box: every place the robot's points reach from a configuration in the box."""
    corners = shapely.get_coordinates(boxes).reshape(len(boxes), 5, 2)[:, :4]
    pts = (corners[:, :, None, :] + robot[None, None]).reshape(len(boxes), -1, 2)
    return shapely.convex_hull(shapely.multipoints(pts.reshape(-1, 2), indices=np.repeat(np.arange(len(boxes)),
                                                                                          pts.shape[1])))


def random_polygon_robot(rng: np.random.Generator) -> np.ndarray:
    """A random convex polygon around (near) the origin."""
    pts = rng.uniform(-0.9, 0.9, size=(7, 2)) + rng.uniform(-0.3, 0.3, size=2)
    hull = shapely.convex_hull(shapely.multipoints(pts))
    return np.asarray(hull.exterior.coords)[:-1]


# ----------------------------------------------------------------------------------------
# grids: the dilation is exactly the conservative rasterization of the exact C-space
# ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("border", ["open", "wall"])
def test_grid_disc_cspace_is_every_cell_whose_centre_is_within_the_radius_of_an_occupied_square(seed, border):
    rng = np.random.default_rng(seed)
    grid = Grid((11, 13), H, origin=(-1.0, 2.0), border=border)
    occ = rng.random(grid.shape) < 0.06
    radius = float(rng.uniform(0.05, 1.6))
    out = apply_robot(GridMap(grid, occ), radius).occupied
    allc = np.argwhere(np.ones(grid.shape, bool))
    union = shapely.union_all(cell_boxes(grid, np.argwhere(occ)))
    if border == "wall":
        xmin, ymin, xmax, ymax = grid.bounds
        union = union.union(shapely.box(xmin - 5, ymin - 5, xmax + 5, ymax + 5).difference(shapely.box(*grid.bounds)))
    ref = shapely.distance(shapely.points(grid.cell_to_world(allc)), union) <= radius  # decided at cell centres
    np.testing.assert_array_equal(out[allc[:, 0], allc[:, 1]], ref)


@pytest.mark.parametrize("seed", range(6))
def test_grid_polygon_cspace_is_every_cell_from_which_the_robot_can_touch_an_occupied_square(seed):
    rng = np.random.default_rng(100 + seed)
    grid = Grid((12, 11), H, origin=(0.0, 0.0))
    occ = rng.random(grid.shape) < 0.05
    robot = random_polygon_robot(rng)
    m = GridMap(grid, occ, obstacle_id=np.where(occ, 1 + (np.arange(occ.size).reshape(occ.shape) % 3), 0))
    out = apply_robot(m, robot)
    allc = np.argwhere(np.ones(grid.shape, bool))
    union = shapely.union_all(cell_boxes(grid, np.argwhere(occ)))
    ref = shapely.intersects(swept(cell_boxes(grid, allc), robot), union)
    np.testing.assert_array_equal(out.occupied[allc[:, 0], allc[:, 1]], ref)
    assert np.array_equal(out.obstacle_id > 0, out.occupied)  # ids follow the grown cells


def test_footprint_of_a_point_robot_changes_nothing_and_a_disc_below_half_a_cell_is_a_point():
    assert conservative_footprint(Robot(radius=0.0), 1.0).shape == (1, 1)
    occ = np.zeros((5, 5), bool)
    occ[2, 2] = True
    m = GridMap(Grid((5, 5), 1.0), occ)
    assert apply_robot(m, 0.0) is m
    # a disc of radius 1e-3 at a neighbouring cell's centre is half a cell from the occupied square
    assert apply_robot(m, 1e-3).occupied.sum() == 1 and apply_robot(m, 0.49).occupied.sum() == 1
    assert apply_robot(m, 0.5).occupied.sum() == 5  # touching at the 4-neighbours' centres counts


# ----------------------------------------------------------------------------------------
# vector worlds: the rasterized C-space contains the exact one and exceeds it by at most a cell
# ----------------------------------------------------------------------------------------
def random_world(rng: np.random.Generator, border: str = "open"):
    obstacles = []
    for _ in range(4):
        c = rng.uniform(1.5, 8.5, size=2)
        pts = c + rng.uniform(-1.2, 1.2, size=(6, 2))
        obstacles.append({"polygon": np.asarray(shapely.convex_hull(shapely.multipoints(pts)).exterior.coords)[:-1]
                         .tolist()})
    obstacles.append({"circle": {"center": rng.uniform(2, 8, size=2).tolist(), "radius": float(rng.uniform(0.3, 1))}})
    obstacles.append({"segment": rng.uniform(1, 9, size=(2, 2)).tolist()})
    return world_from_dict({"bounds": [0, 0, 10, 10], "border": border, "obstacles": obstacles})


def box_distances(world, boxes):
    """Exact distance from each closed box to each obstacle (circles analytic), shape (boxes, obstacles)."""
    cols = []
    for ob in world.obstacles:
        if ob.kind == "circle":
            cols.append(np.maximum(shapely.distance(boxes, Point(ob.center)) - ob.radius, 0.0))
        else:
            cols.append(shapely.distance(boxes, ob.geometry))
    return np.stack(cols, axis=1)


@pytest.mark.parametrize("seed", range(4))
def test_world_disc_cspace_grid_contains_the_exact_cspace_and_exceeds_it_by_at_most_one_cell(seed):
    rng = np.random.default_rng(seed)
    world = random_world(rng)
    radius = float(rng.uniform(0.1, 0.8))
    h = 0.2
    gm = as_gridmap(apply_robot(world, radius), h)
    allc = np.argwhere(np.ones(gm.shape, bool))
    d = box_distances(world, cell_boxes(gm.grid, allc)).min(axis=1)
    occ = gm.occupied[allc[:, 0], allc[:, 1]]
    # contains: a cell holding a colliding configuration (box within the radius) is occupied
    assert occ[d <= radius * (1 - 1e-9)].all()
    # exceeds by at most one cell: an occupied cell's square is within the radius (+ the 0.12 %
    # of the circumscribed outlines at polygon vertices)
    assert (d[occ] <= radius / math.cos(math.pi / 64) + 1e-9).all()
    assert occ.sum() > (d <= radius).sum() * 0.9  # and the test sees a real C-space


@pytest.mark.parametrize("seed", range(4))
def test_world_polygon_cspace_grid_contains_the_exact_cspace_and_exceeds_it_by_at_most_one_cell(seed):
    rng = np.random.default_rng(50 + seed)
    world = random_world(rng, border="wall")
    robot = random_polygon_robot(rng)
    h = 0.25
    gm = as_gridmap(apply_robot(world, robot), h)
    allc = np.argwhere(np.ones(gm.shape, bool))
    reach = swept(cell_boxes(gm.grid, allc), robot)
    d = box_distances(world, reach).min(axis=1)
    xmin, ymin, xmax, ymax = world.bounds
    b = shapely.bounds(reach)
    wall = np.minimum.reduce([b[:, 0] - xmin, xmax - b[:, 2], b[:, 1] - ymin, ymax - b[:, 3]])
    occ = gm.occupied[allc[:, 0], allc[:, 1]]
    inside = np.all(gm.grid.cell_to_world(allc) < (xmax, ymax), axis=1)  # cells of the grid within the bounds
    colliding = (d <= 0) | (wall <= 0)
    assert occ[colliding & inside].all()
    # an occupied cell: the robot from some point of it touches an obstacle, up to the circles'
    # circumscribed outline (0.12 % of their radius), or the wall
    circle_tol = max(ob.radius for ob in world.obstacles if ob.kind == "circle") * (1 / math.cos(math.pi / 64) - 1)
    assert ((d[occ & inside] <= circle_tol + 1e-9) | (wall[occ & inside] <= 1e-9)).all()


def test_exact_planner_on_the_cspace_keeps_the_radius_in_the_workspace():
    world = read_world(bundled_map("seed000.yaml"))
    from gridfield.planners import plan

    path = plan("visibility", apply_robot(world, 0.5), world.start, world.goal)
    assert path.status == "reached"
    line = shapely.LineString(path.points)
    exact = min(float(shapely.distance(ob.geometry, line)) for ob in world.obstacles)
    assert 0.5 - 1e-9 <= exact < 0.5 + 0.01  # the shortest path hugs the grown obstacles


# ----------------------------------------------------------------------------------------
# planned paths: the clearance in the workspace is the robot's radius (less one cell)
# ----------------------------------------------------------------------------------------
def run_json(args, capsys):
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


def test_cli_plan_seed000_with_a_robot_radius_keeps_the_clearance(capsys):
    out = run_json(["plan", str(bundled_map("seed000.yaml")), "--robot-radius", "0.3", "--json"], capsys)
    assert out["status"] == "reached"
    world = read_world(bundled_map("seed000.yaml"))
    line = shapely.LineString(out["path"])
    exact = min(float(shapely.distance(ob.geometry, line)) for ob in world.obstacles)
    assert exact >= 0.3 - 0.05
    assert out["robot"] == "disc of radius 0.3" and out["workspace_clearance"] == pytest.approx(exact)


def square_distance_to_occupied(gm: GridMap, pts: np.ndarray) -> np.ndarray:
    """Brute force: distance from each point to the nearest occupied closed cell square."""
    cells = np.argwhere(gm.occupied)
    c = gm.grid.cell_to_world(cells)
    h = gm.grid.resolution
    out = np.empty(len(pts))
    for i in range(0, len(pts), 16):
        p = pts[i:i + 16]
        dx = np.maximum(np.abs(p[:, None, 0] - c[None, :, 0]) - h / 2, 0)
        dy = np.maximum(np.abs(p[:, None, 1] - c[None, :, 1]) - h / 2, 0)
        out[i:i + 16] = np.hypot(dx, dy).min(axis=1)
    return out


@pytest.mark.parametrize("planner", ["wavefront-octile", "potential"])
def test_cli_plan_on_the_ros_map_with_a_robot_radius_keeps_the_clearance(planner, capsys):
    ros = bundled_map("turtlebot3_world/map.yaml")
    args = ["plan", str(ros), "--robot-radius", "0.3", "--start", "-2", "-0.5", "--goal", "2", "0.5",
            "--planner", planner, "--json"]
    if planner == "potential":
        args += ["--eta", "0.05", "--q-star", "0.35", "--d-star", "1", "--step", "0.02", "--tolerance", "0.05",
                 "--max-iterations", "3000"]
    out = run_json(args, capsys)
    pts = np.asarray(out["path"], dtype=float)
    assert len(pts) > (1 if planner == "potential" else 5)  # the potential path is pulled taut (issue 46)
    if planner == "wavefront-octile":
        assert out["status"] == "reached"
    gm = read(ros)
    d = square_distance_to_occupied(gm, pts)
    assert d.min() >= 0.3 - gm.grid.resolution
    assert out["workspace_clearance"] == pytest.approx(d.min())
    dense = np.vstack([np.linspace(a, b, 25) for a, b in itertools.pairwise(pts)])  # between the points too
    assert square_distance_to_occupied(gm, dense).min() >= 0.3 - gm.grid.resolution


def test_workspace_clearance_on_a_grid_is_the_brute_force_distance():
    rng = np.random.default_rng(7)
    gm = GridMap(Grid((20, 25), 0.3, origin=(1.0, -2.0)), rng.random((20, 25)) < 0.05)
    pts = rng.uniform((1.0, -2.0), (8.5, 4.0), size=(200, 2))
    assert workspace_clearance(gm, pts) == pytest.approx(square_distance_to_occupied(gm, pts).min(), abs=1e-12)


# ----------------------------------------------------------------------------------------
# a start or goal that collides is an error naming the distance
# ----------------------------------------------------------------------------------------
def test_colliding_start_is_a_one_line_error_naming_the_distance(capsys):
    rc = main(["plan", str(bundled_map("seed000.yaml")), "--robot-radius", "4"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1
    assert "start (1, 10) is 3.61 from obstacle 1, within the robot (disc of radius 4)" in err


def test_colliding_goal_of_a_polygon_robot_on_a_grid_is_named(capsys):
    rc = main(["plan", str(bundled_map("arena/arena.map")), "--robot", "0,0 3,0 3,0.5",
               "--start", "24.5", "24.5", "--goal", "47", "24"])
    err = capsys.readouterr().err
    assert rc == 2 and "goal" in err and "overlaps occupied cells" in err, err


def test_check_robot_point_polygon_in_a_world_and_the_wall():
    w = world_from_dict({"bounds": [0, 0, 10, 10], "border": "wall",
                         "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}]})
    tri = [[0, 0], [1.5, 0], [0, 0.5]]
    check_robot_point(w, tri, "start", (2.0, 5.0))  # the triangle ends at x = 3.5 < 4
    with pytest.raises(GridfieldError, match="overlaps obstacle 1"):
        check_robot_point(w, tri, "start", (2.6, 5.0))
    with pytest.raises(GridfieldError, match="touches the wall"):
        check_robot_point(w, tri, "goal", (9.0, 1.0))


# ----------------------------------------------------------------------------------------
# the world file's robot: key and the other commands
# ----------------------------------------------------------------------------------------
def seed_world_with(tmp_path: Path, robot_yaml: str) -> Path:
    text = bundled_map("seed000.yaml").read_text()
    p = tmp_path / "world.yaml"
    p.write_text(text + f"\nrobot: {robot_yaml}\n")
    return p


def test_world_file_robot_key_is_used_and_the_flag_overrides_it(tmp_path, capsys):
    p = seed_world_with(tmp_path, "{radius: 0.6}")
    assert read_world(p).robot.radius == 0.6
    out = run_json(["plan", str(p), "--planner", "visibility", "--json"], capsys)
    assert out["robot"] == "disc of radius 0.6" and out["workspace_clearance"] >= 0.6 - 1e-9
    out = run_json(["plan", str(p), "--planner", "visibility", "--robot-radius", "0.2", "--json"], capsys)
    assert out["workspace_clearance"] == pytest.approx(0.2, abs=0.01)


@pytest.mark.parametrize(("robot", "message"), [
    ("{radius: -1}", "robot: the robot's radius must be a finite number >= 0"),
    ("{polygon: [[0, 0], [2, 0], [1, 0.5], [1, 2]]}", "robot.polygon must be a convex polygon"),
    ("{square: 1}", "robot must be {radius: R} or {polygon"),
])
def test_bad_robot_keys_name_the_problem(tmp_path, robot, message):
    with pytest.raises(MapFormatError, match=message.replace("[", r"\[").replace("{", r"\{")):
        read_world(seed_world_with(tmp_path, robot))


def test_bad_robot_flags_are_one_line_errors(capsys):
    assert main(["plan", str(bundled_map("seed000.yaml")), "--robot", "0,0", "1;0"]) == 2
    assert "--robot expects vertices X,Y" in capsys.readouterr().err
    assert main(["plan", str(bundled_map("seed000.yaml")), "--robot", "0,0 2,0 1,0.5 1,2"]) == 2
    assert "convex" in capsys.readouterr().err
    assert main(["plan", str(bundled_map("seed000.yaml")), "--robot-radius", "1", "--robot", "0,0"]) == 2


def test_brushfire_and_field_plan_on_the_grown_map(tmp_path, capsys):
    seed = str(bundled_map("seed000.yaml"))
    for radius in ("0", "0.5"):
        assert main(["brushfire", seed, "--resolution", "0.25", "--robot-radius", radius,
                     "--npz", str(tmp_path / f"b{radius}.npz")]) == 0
    capsys.readouterr()
    a, b = np.load(tmp_path / "b0.npz"), np.load(tmp_path / "b0.5.npz")
    ref = as_gridmap(apply_robot(read_world(seed), 0.5), 0.25).occupied
    np.testing.assert_array_equal(b["occupied"], ref)
    assert b["occupied"].sum() > a["occupied"].sum()
    assert main(["field", seed, "--resolution", "0.25", "--robot-radius", "0.5", "--npz", str(tmp_path / "f.npz")]) == 0
    np.testing.assert_array_equal(np.load(tmp_path / "f.npz")["occupied"], ref)
    assert main(["field", seed, "--robot-radius", "5"]) == 2
    assert "goal (22, 12)" in capsys.readouterr().err


def test_compare_with_a_robot_compares_on_the_cspace(capsys):
    out = run_json(["compare", str(bundled_map("seed000.yaml")), "--robot-radius", "0.4", "--resolutions", "0.25",
                    "--planner", "wavefront-octile", "--exact-planner", "visibility", "--json"], capsys)
    plain = run_json(["compare", str(bundled_map("seed000.yaml")), "--resolutions", "0.25",
                      "--planner", "wavefront-octile", "--exact-planner", "visibility", "--json"], capsys)
    key = next(k for k in out["rows"][0] if "exact" in k and "length" in k)
    assert out["rows"][0][key] > plain["rows"][0][key]  # the grown obstacles make the exact path longer


def test_sweep_spec_robot_key(tmp_path):
    import shutil

    shutil.copy(bundled_map("seed000.yaml"), tmp_path / "seed000.yaml")
    spec = tmp_path / "spec.yaml"
    spec.write_text("output: runs.csv\nmaps:\n  - path: seed000.yaml\n    resolution: 0.25\n    robot_radius: 0.5\n"
                    "  - path: seed000.yaml\n    resolution: 0.25\nplanners: [wavefront-octile]\n")
    runs, output = load_spec(spec)
    assert [r.robot for r in runs] == [("radius", 0.5), ()]
    assert json.loads(runs[0].params_json)["robot"] == {"radius": 0.5}
    rows = run_sweep(runs, output, workers=1, progress=False)
    by_robot = {json.loads(r["params"]).get("robot", {}).get("radius", 0): r for r in rows}
    assert by_robot[0.5]["status"] == "reached" and float(by_robot[0.5]["length"]) > float(by_robot[0]["length"])


def test_a_polygon_robot_on_the_exact_shortest_path_touches_but_never_overlaps(capsys):
    tri = np.array([[-0.3, -0.2], [0.3, -0.2], [0.0, 0.4]])
    out = run_json(["plan", str(bundled_map("seed000.yaml")), "--planner", "visibility", "--robot",
                    "-0.3,-0.2 0.3,-0.2 0,0.4", "--json"], capsys)
    assert out["status"] == "reached" and out["robot_clearance"] == pytest.approx(0.0, abs=1e-9)
    pts = np.asarray(out["path"], dtype=float)
    # densify the path: the body between vertices must stay out too
    t = np.linspace(0, 1, 20)[:, None, None]
    dense = (pts[:-1][None] * (1 - t) + pts[1:][None] * t).reshape(-1, 2)
    bodies = shapely.polygons(dense[:, None, :] + tri[None])
    union = read_world(bundled_map("seed000.yaml")).union()
    assert shapely.area(shapely.intersection(bodies, union)).max() < 1e-9


def test_robot_clearance_of_a_disc_on_a_grid_is_the_path_clearance_less_the_radius():
    from gridfield.geometry.cspace import robot_clearance

    rng = np.random.default_rng(3)
    gm = GridMap(Grid((20, 25), 0.3), rng.random((20, 25)) < 0.05)
    pts = rng.uniform((0.0, 0.0), (7.5, 6.0), size=(50, 2))
    d = square_distance_to_occupied(gm, pts).min()
    assert robot_clearance(gm, 0.1, pts) == pytest.approx(max(d - 0.1, 0.0))
    assert robot_clearance(gm, [[0, 0], [1, 0], [0, 1]], pts) is None


def test_info_describes_the_configuration_space(capsys):
    arena = bundled_map("arena/arena.map")
    out = run_json(["info", str(arena), "--robot-radius", "1", "--json"], capsys)
    assert out["robot"] == "disc of radius 1"
    assert out["occupied_fraction"] == pytest.approx(apply_robot(read(arena), 1.0).occupied.mean())
    assert "robot" not in run_json(["info", str(arena), "--json"], capsys)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), radius=st.floats(0.01, 2.0), h=st.sampled_from([0.25, 0.5, 1.0]),
       wall=st.booleans())
def test_property_disc_cspace_grid_is_the_exact_one_at_cell_centres(seed, radius, h, wall):
    rng = np.random.default_rng(seed)
    grid = Grid((7, 9), h, origin=(0.5, -1.0), border="wall" if wall else "open")
    occ = rng.random(grid.shape) < 0.1
    allc = np.argwhere(np.ones(grid.shape, bool))
    union = shapely.union_all(cell_boxes(grid, np.argwhere(occ)))
    if wall:
        xmin, ymin, xmax, ymax = grid.bounds
        union = union.union(shapely.box(xmin - 9, ymin - 9, xmax + 9, ymax + 9).difference(shapely.box(*grid.bounds)))
    d = shapely.distance(shapely.points(grid.cell_to_world(allc)), union)
    assume(not np.any(np.isclose(d, radius, rtol=1e-7)))  # no exact tie (the tolerance decides those)
    out = apply_robot(GridMap(grid, occ), radius).occupied[allc[:, 0], allc[:, 1]]
    np.testing.assert_array_equal(out, d <= radius)
