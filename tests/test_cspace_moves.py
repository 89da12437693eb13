"""The move rule of a disc robot on a grid map (issue 30): a move between neighbouring cells that the grid
planners make on the configuration space of :func:`gridfield.geometry.cspace.apply_robot` is one the robot fits
along, checked against exact geometry (shapely: the distance from the segment between the two cell
centres to the union of the occupied cell squares, and the wall, is more than the radius).

Which moves the planners make is read from the planners themselves, not from a copy of their rule: the
octile wavefront from a free cell gives each 8-neighbour the cost of one step (``h`` or ``h sqrt 2``)
exactly when that step is allowed (any other route to a neighbour costs at least ``2h``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from gridfield.core.grid import Grid, GridMap
from gridfield.fields.navigation import wavefront
from gridfield.geometry.cspace import apply_robot
from gridfield.planners import plan

STEPS = [(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if (dr, dc) != (0, 0)]


def obstacles(gridmap: GridMap) -> shapely.Geometry:
    """The union of the occupied closed cell squares and, with ``border="wall"``, the wall around the grid."""
    grid = gridmap.grid
    x0, y0 = grid.origin
    h = grid.resolution
    cells = np.argwhere(gridmap.occupied)
    union = shapely.union_all(shapely.box(x0 + cells[:, 1] * h, y0 + cells[:, 0] * h,
                                          x0 + (cells[:, 1] + 1) * h, y0 + (cells[:, 0] + 1) * h))
    if grid.border == "wall":
        xmin, ymin, xmax, ymax = grid.bounds
        ring = shapely.box(xmin - 9 * h, ymin - 9 * h, xmax + 9 * h, ymax + 9 * h).difference(shapely.box(*grid.bounds))
        union = union.union(ring)
    return union


def moves(cspace: GridMap) -> dict[tuple[tuple[int, int], tuple[int, int]], bool]:
    """Every pair (free cell, 8-neighbour inside the grid) -> whether the planners' wavefront steps along it."""
    grid = cspace.grid
    h = grid.resolution
    out = {}
    for r, c in np.argwhere(~cspace.occupied):
        centre = grid.cell_to_world(np.array([[r, c]]))[0]
        value = wavefront(cspace, centre, costs="octile").value
        for dr, dc in STEPS:
            rr, cc = r + dr, c + dc
            if 0 <= rr < grid.rows and 0 <= cc < grid.cols:
                step = h * (math.sqrt(2) if dr and dc else 1.0)
                out[(int(r), int(c)), (int(rr), int(cc))] = bool(abs(value[rr, cc] - step) <= 1e-9 * h)
    return out


def clearance(grid: Grid, union: shapely.Geometry, a: tuple[int, int], b: tuple[int, int]) -> float:
    """Exact distance from the segment between the centres of cells ``a`` and ``b`` to the obstacles."""
    pa, pb = grid.cell_to_world(np.array([a, b]))
    return float(shapely.distance(shapely.LineString([pa, pb]), union))


def test_a_small_robot_never_takes_a_diagonal_past_an_occupied_corner():
    """Cells (0, 0) and (1, 1) are free and the robot fits at both centres (half a cell from the occupied
    square (0, 1)), but the diagonal between them passes that square's corner at distance 0."""
    occ = np.zeros((3, 3), bool)
    occ[0, 1] = True
    workspace = GridMap(Grid((3, 3), 1.0), occ)
    cspace = apply_robot(workspace, 0.3)
    union = obstacles(workspace)
    assert not cspace.occupied[0, 0] and not cspace.occupied[1, 1]
    assert clearance(workspace.grid, union, (0, 0), (0, 0)) == pytest.approx(0.5)
    assert clearance(workspace.grid, union, (0, 0), (1, 1)) == 0.0  # the robot does not fit along it
    allowed = moves(cspace)
    assert not allowed[(0, 0), (1, 1)] and not allowed[(1, 1), (0, 0)]
    assert allowed[(0, 0), (1, 0)] and allowed[(1, 0), (1, 1)]  # round the corner instead
    for planner in ("wavefront", "wavefront-octile"):
        path = plan(planner, cspace, (0.5, 0.5), (2.5, 2.5))
        assert path.status == "reached"
        segments = shapely.linestrings(np.stack([path.points[:-1], path.points[1:]], axis=1))
        assert float(np.min(shapely.distance(segments, union))) > 0.3, planner


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), radius=st.floats(0.0, 1.6), h=st.sampled_from([0.5, 1.0]),
       wall=st.booleans())
@example(seed=0, radius=0.45, h=1.0, wall=False)
@example(seed=3, radius=0.5, h=1.0, wall=True)
@example(seed=7, radius=0.7, h=0.5, wall=False)
@example(seed=11, radius=1.45, h=1.0, wall=False)  # squares only the middle of a diagonal reaches
@example(seed=5, radius=0.6, h=1.0, wall=True)
def test_property_the_planners_make_a_move_exactly_when_the_robot_fits_along_it(seed, radius, h, wall):
    """Sound (every move made keeps the robot clear) and complete (every move the robot fits along,
    between two free cells, is made: diagonals whose side cells are blocked in the C-space included)."""
    rng = np.random.default_rng(seed)
    grid = Grid((6, 7), h, origin=(-0.5, 1.0), border="wall" if wall else "open")
    workspace = GridMap(grid, rng.random(grid.shape) < 0.2)
    union = obstacles(workspace)
    r = radius * h
    cspace = apply_robot(workspace, r)
    allowed = moves(cspace)
    d = {pair: clearance(grid, union, *pair) for pair in allowed}
    assume(not any(math.isclose(v, r, rel_tol=1e-7) for v in d.values()))  # no exact tie
    for pair, ok in allowed.items():
        if ok:
            assert d[pair] > r, f"move {pair} allowed, but the robot (radius {r:g}) is {d[pair]:.4g} from an obstacle"
        else:  # (a blocked end cell is within r of an obstacle: d <= r)
            assert d[pair] <= r, f"move {pair} refused, but the robot (radius {r:g}) keeps {d[pair]:.4g} along it"
    if r < h / 2:  # below half a cell the robot behaves like a point: the same cells and the same moves
        np.testing.assert_array_equal(cspace.occupied, workspace.occupied)
        assert cspace.diagonals is None
        assert allowed == moves(workspace)


def test_a_robot_of_half_a_cell_or_more_takes_a_diagonal_it_fits_along():
    """Free cells (0, 1) and (1, 2) (the robot fits at both centres, 0.707 from the nearest square) are
    joined only by their diagonal, along which the robot keeps 0.707 > 0.6: a path exists."""
    occ = np.zeros((2, 4), bool)
    occ[1, 0] = occ[0, 3] = True
    workspace = GridMap(Grid((2, 4), 1.0), occ)
    cspace = apply_robot(workspace, 0.6)
    assert np.argwhere(~cspace.occupied).tolist() == [[0, 1], [1, 2]]
    assert clearance(workspace.grid, obstacles(workspace), (0, 1), (1, 2)) == pytest.approx(math.sqrt(0.5))
    assert plan("wavefront-octile", cspace, (1.5, 0.5), (2.5, 1.5)).status == "reached"


# Two rooms of a wall-bordered 8x8 map that a disc of radius 0.6 joins only through corners of its
# configuration space (rows top first, as in the file): it fits along the diagonals, 0.707 from the squares.
CORNER_MAP = ["........", "........", "........", "........", "@@@.....", ".....@@@", "........", "........"]
CORNER_START, CORNER_GOAL, CORNER_RADIUS = (2.5, 1.5), (4.5, 5.5), 0.6
DISCRETE = ("wavefront", "wavefront-octile")


def corner_workspace() -> GridMap:
    occ = np.array([[ch == "@" for ch in row] for row in CORNER_MAP[::-1]])
    return GridMap(Grid(occ.shape, 1.0, border="wall"), occ)


def test_the_corner_passage_map_is_joined_only_through_corners_the_robot_fits_along():
    workspace = corner_workspace()
    cspace = apply_robot(workspace, CORNER_RADIUS)
    plain = cspace.with_occupied(cspace.occupied, diagonals=None)
    assert cspace.diagonals is not None
    assert plan("wavefront-octile", plain, CORNER_START, CORNER_GOAL).status == "no_path"  # the Moving AI rule alone
    path = plan("wavefront-octile", cspace, CORNER_START, CORNER_GOAL)
    assert path.status == "reached"
    segments = shapely.linestrings(np.stack([path.points[:-1], path.points[1:]], axis=1))
    assert float(np.min(shapely.distance(segments, obstacles(workspace)))) > CORNER_RADIUS


@pytest.mark.parametrize("planner", ["potential", "exact-potential", "visibility", "wavefront", "wavefront-octile",
                                     "fmm", "harmonic", "navfn"])
def test_every_grid_planner_takes_the_corner_diagonal_or_says_why_not(planner):
    """The discrete planners step along the diagonals; the continuous ones end without reaching and say that the
    robot passes only along a diagonal through a corner, and which planners take it."""
    workspace = corner_workspace()
    cspace = apply_robot(workspace, CORNER_RADIUS)
    path = plan(planner, cspace, CORNER_START, CORNER_GOAL)
    if planner in DISCRETE:
        assert path.status == "reached"
        assert float(np.min(shapely.distance(shapely.linestrings(np.stack([path.points[:-1], path.points[1:]], axis=1)),
                                             obstacles(workspace)))) > CORNER_RADIUS
    else:
        assert path.status != "reached"
        assert path.extra["diagnosis"]["corner_passage"] is True
        assert "only along diagonals through the corners" in path.hint
        assert "wavefront and wavefront-octile take them" in path.hint


@pytest.mark.parametrize("planner", ["wavefront-octile", "fmm", "potential"])
def test_the_cli_plans_a_disc_robot_through_a_corner_or_says_why_not(tmp_path, capsys, planner):
    from gridfield.cli import main

    f = tmp_path / "corner.map"
    f.write_text("type octile\nheight 8\nwidth 8\nmap\n" + "\n".join(CORNER_MAP) + "\n")
    argv = ["plan", str(f), "--planner", planner, "--robot-radius", str(CORNER_RADIUS),
            "--start", *map(str, CORNER_START), "--goal", *map(str, CORNER_GOAL)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    if planner in DISCRETE:
        assert f"{planner}: reached" in out, out
    else:
        assert "reached" not in out.splitlines()[0], out
        assert "only along diagonals through the corners" in out and "closes the passage" not in out, out


def test_the_diagonals_belong_to_the_occupancy_they_were_built_for():
    """A copy with the same occupancy keeps them; a map made from another occupancy (inflated again, cropped,
    downsampled, subdivided) has none, so no stale diagonal survives a transformation that does not know them."""
    from gridfield.geometry.gridpoly import block_downsample, subdivide

    cspace = apply_robot(corner_workspace(), CORNER_RADIUS)
    assert cspace.with_occupied(cspace.occupied, source="copy").diagonals is cspace.diagonals
    assert cspace.with_occupied(cspace.occupied.copy()).diagonals is None
    assert block_downsample(cspace, 2).diagonals is None
    assert subdivide(cspace, 2).diagonals is None
    with pytest.raises(Exception, match="diagonals has shape"):
        GridMap(cspace.grid, cspace.occupied, diagonals=np.zeros((2, 2), np.uint8))
