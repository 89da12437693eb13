"""Seed 004's workflow in the explorer, headless (Agg): draw robot, C-space, start/goal, calculate
path, movie, 3-D, undo/clear, colour bar, the planner's own sliders only."""

from __future__ import annotations

import os

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
import shapely
from matplotlib import animation
from matplotlib.backend_bases import KeyEvent, MouseEvent
from PIL import Image

from gridfield.cli import main
from gridfield.core.grid import Grid, GridMap
from gridfield.explore import BUTTONS, PLANNER_SLIDERS, Explorer
from gridfield.fields.potential import build_field
from gridfield.geometry.rasterize import as_gridmap
from gridfield.io import bundled_map, read_world


@pytest.fixture
def ex():
    e = Explorer(read_world(bundled_map("seed000.yaml")), resolution=0.25)
    yield e
    e.close()


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def click(e: Explorer, x: float, y: float, button: int = 1) -> None:
    dx, dy = e.ax.transData.transform((x, y))
    e.figure.canvas.callbacks.process("button_press_event",
                                      MouseEvent("button_press_event", e.figure.canvas, dx, dy, button=button))


def press_button(e: Explorer, method: str) -> None:
    """Click a button widget through the canvas (press and release at its centre)."""
    ax = e.buttons[method].ax
    x, y = ax.transAxes.transform((0.5, 0.5))
    canvas = e.figure.canvas
    for kind in ("button_press_event", "button_release_event"):
        canvas.callbacks.process(kind, MouseEvent(kind, canvas, x, y, button=1))


def key(e: Explorer, k: str) -> None:
    canvas = e.figure.canvas
    canvas.callbacks.process("key_press_event", KeyEvent("key_press_event", canvas, k))


def test_seed004_workflow_draw_robot_compute_cspace_set_goal_calculate_path(ex, tmp_path):
    # draw a triangular robot with its reference point (first vertex) at (2, 10)
    press_button(ex, "toggle_robot_drawing")
    assert ex.drawing and ex.draw_mode == "robot"
    tri = [(2.0, 10.0), (2.6, 10.0), (2.0, 10.5)]
    for v in tri:
        click(ex, *v)
    click(ex, 2.2, 10.2, button=3)
    assert not ex.drawing
    np.testing.assert_allclose(ex.robot.vertices, np.asarray(tri) - tri[0])
    assert ex.start == (2.0, 10.0)  # the reference point is the start configuration
    assert ex.robot_patch.get_visible()
    np.testing.assert_allclose(ex.reference_marker.get_offsets()[0], (2.0, 10.0))
    assert not ex.cspace_on and ex.cgridmap is ex.gridmap
    # compute the C-space: the C-obstacles O ⊕ (−R), drawn beside the workspace obstacles
    press_button(ex, "compute_cspace")
    assert ex.cspace_on
    for ob, cob in zip(ex.world.obstacles, ex.cworld.obstacles, strict=False):
        ref = shapely.convex_hull(shapely.multipoints(
            (shapely.get_coordinates(ob.geometry)[:, None, :] - ex.robot.vertices[None]).reshape(-1, 2)))
        assert cob.geometry.symmetric_difference(ref).area < 1e-9
    grown = ex.cgridmap.occupied & ~ex.gridmap.occupied
    assert grown.any()
    np.testing.assert_array_equal(~ex.cspace_image.get_array().mask, grown)
    assert len(ex.cspace_outlines) == 1
    # set the goal through the button, then calculate the path
    press_button(ex, "arm_goal")
    click(ex, 22.0, 12.0)
    assert ex.goal == pytest.approx((22.0, 12.0))
    ex.set_planner("wavefront-octile")
    n = ex.n_updates
    press_button(ex, "calculate_path")
    assert ex.n_updates == n + 1 and ex.path is not None and ex.path.status == "reached"
    # the path keeps the triangle off the workspace obstacles: every placement is collision-free
    placed = shapely.polygons(ex.path.points[:, None, :] + ex.robot.vertices[None])
    assert not shapely.intersects(placed, ex.world.union()).any()


def test_a_start_where_the_robot_collides_is_refused_with_the_distance(ex):
    ex.set_robot(0.5)
    ex.compute_cspace()
    assert not ex.set_start(9.0, 10.4)  # 0.4 above the triangle's apex (9, 10): within 0.5
    assert "start not set" in ex.message and "is 0.4 from obstacle 2, within the robot (disc of radius 0.5)" in ex.message
    assert ex.start == (1.0, 10.0)


def test_non_convex_robot_is_discarded_with_a_message(ex):
    ex.toggle_robot_drawing()
    for v in [(2, 2), (4, 2), (3, 2.5), (3, 4)]:
        ex.add_vertex(*v)
    assert not ex.close_polygon()
    assert "robot discarded" in ex.message and "convex" in ex.message and ex.robot is None


def test_compute_cspace_without_a_robot_says_so(ex):
    assert not ex.compute_cspace()
    assert "draw a robot first" in ex.message and not ex.cspace_on


def test_undo_restores_the_obstacles_occupancy_robot_and_cspace(ex):
    states = []

    def snap():
        return (len(ex.world.obstacles), ex.gridmap.occupied.copy(), ex.cgridmap.occupied.copy(), ex.robot,
                ex.cspace_on, ex.start)

    states.append(snap())
    ex.add_polygon([(19.5, 9.0), (21.0, 9.0), (21.0, 15.0), (19.5, 15.0)])
    states.append(snap())
    ex.set_robot(0.4)
    ex.compute_cspace()
    states.append(snap())
    ex.add_polygon([(2, 2), (4, 2), (4, 4)])
    assert ex.cgridmap.occupied.sum() > states[-1][2].sum()
    for expected in reversed(states):
        if expected is states[1]:
            assert ex.undo() and ex.undo()  # compute_cspace and set_robot are two steps
        else:
            assert ex.undo()
        got = snap()
        assert got[0] == expected[0] and got[3] is expected[3] and got[4] == expected[4]
        np.testing.assert_array_equal(got[1], expected[1])
        np.testing.assert_array_equal(got[2], expected[2])
    assert not ex.undo() and "nothing to undo" in ex.message


def test_clear_goes_back_to_the_loaded_map_and_is_undoable(ex):
    occ0 = ex.gridmap.occupied.copy()
    ex.add_polygon([(19.5, 9.0), (21.0, 9.0), (21.0, 15.0), (19.5, 15.0)])
    ex.set_robot(0.3)
    ex.compute_cspace()
    ex.set_goal(20.0, 3.0)
    occ1, n1 = ex.gridmap.occupied.copy(), len(ex.world.obstacles)
    key(ex, "n")
    assert len(ex.world.obstacles) == 3 and ex.robot is None and not ex.cspace_on
    np.testing.assert_array_equal(ex.gridmap.occupied, occ0)
    assert ex.goal == (22.0, 12.0) and ex.path.status == "reached"
    key(ex, "u")
    assert len(ex.world.obstacles) == n1 and ex.cspace_on and ex.goal == (20.0, 3.0)
    np.testing.assert_array_equal(ex.gridmap.occupied, occ1)


def test_undo_on_a_grid_map_without_a_world():
    occ = np.zeros((40, 40), bool)
    occ[:, :2] = True
    e = Explorer(GridMap(Grid((40, 40), 0.5), occ), start=(3.0, 3.0), goal=(17.0, 17.0))
    try:
        e.add_polygon([(8, 8), (12, 8), (12, 12), (8, 12)])
        e.set_robot([[0, 0], [1, 0], [0, 1]])
        assert e.compute_cspace() and e.path is not None
        assert e.cgridmap.occupied.sum() > e.gridmap.occupied.sum()
        assert e.undo() and e.undo() and not e.cspace_on and e.robot is None
        assert e.undo()
        np.testing.assert_array_equal(e.gridmap.occupied, occ)
    finally:
        e.close()


def test_colour_bar_shows_the_potential_range_and_hides_for_the_wavefront(ex):
    assert ex.cax.get_visible()
    field = build_field(as_gridmap(ex.world, 0.25), np.asarray(ex.goal), ex.params)
    u = field.potential[np.isfinite(field.potential) & ~field.map.occupied]
    norm = ex.colorbar.mappable.norm
    assert norm.vmax == pytest.approx(u.max() - u.min())
    assert 0 < norm.vmin < norm.vmax
    ex.set_planner("wavefront-octile")
    assert not ex.cax.get_visible() and ex.field is None


def test_only_the_planners_own_sliders_are_shown_and_react(ex):
    assert all(s.ax.get_visible() for s in ex.sliders.values())
    ex.set_planner("wavefront-octile")
    assert PLANNER_SLIDERS["wavefront-octile"] == ()
    assert not any(s.ax.get_visible() or s.get_active() for s in ex.sliders.values())
    before = dict(ex.params)
    x, y = ex.sliders["eta"].ax.transAxes.transform((0.9, 0.5))
    ex.figure.canvas.callbacks.process("button_press_event",
                                       MouseEvent("button_press_event", ex.figure.canvas, x, y, button=1))
    assert ex.params == before
    ex.set_planner("potential")
    assert all(s.ax.get_visible() and s.get_active() for s in ex.sliders.values())


def test_3d_toggle_shows_the_potential_surface_with_the_path(ex):
    press_button(ex, "toggle_3d")
    assert ex.show_3d and ex.ax3d.get_visible() and not ex.ax.get_visible()
    assert ex.surface is not None and ex.surface.surface in ex.ax3d.collections
    (line,) = ex.surface.paths
    xs, ys, _ = line.get_data_3d()
    np.testing.assert_allclose(np.column_stack([xs, ys]), ex.path.points)
    # the surface follows a new goal
    ex.set_goal(20.0, 3.0)
    xs, ys, _ = ex.surface.paths[0].get_data_3d()
    np.testing.assert_allclose((xs[-1], ys[-1]), ex.path.points[-1])
    assert not ex.cax.get_visible()  # the surface has its own height axis
    key(ex, "3")
    assert not ex.show_3d and ex.ax.get_visible() and not ex.ax3d.get_visible() and ex.cax.get_visible()
    assert "off" in ex.buttons["toggle_3d"].label.get_text()


def test_movie_toggle_writes_the_next_run_and_turns_itself_off(ex, tmp_path):
    ex.set_robot(0.3)
    ex.compute_cspace()
    target = tmp_path / "run.gif"
    assert ex.toggle_movie(target)
    assert "on" in ex.buttons["toggle_movie"].label.get_text()
    ex.calculate_path()
    assert not ex.movie and "off" in ex.buttons["toggle_movie"].label.get_text()
    assert target.exists() and str(target) in ex.message
    with Image.open(target) as im:
        assert im.format == "GIF" and im.n_frames > 10
    assert (tmp_path / "run.mp4").exists() == animation.writers.is_available("ffmpeg")
    target.unlink()
    ex.calculate_path()
    assert not target.exists()  # only the next run is recorded


def test_movie_of_exact_potential_on_a_grid_map_draws_the_map_it_planned_on(tmp_path):
    """exact-potential on a map without a vector world plans on the grid's exact polygons; its movie
    draws that grid map (it used to assert a vector world was there)."""
    occ = np.zeros((16, 16), bool)
    occ[6:10, 7:9] = True
    e = Explorer(GridMap(Grid(occ.shape, 0.5), occ), planner="exact-potential")
    try:
        target = tmp_path / "grid.gif"
        assert e.toggle_movie(target)
        e.set_start(1.25, 1.25)
        e.set_goal(6.75, 6.75)
        assert e.path is not None and e.path.status == "reached", e.message
        assert target.exists() and str(target) in e.message
    finally:
        e.close()


def test_every_button_has_a_key_and_a_method(ex):
    assert len({k for _, k in BUTTONS.values()}) == len(BUTTONS)
    for method in BUTTONS:
        assert callable(getattr(ex, method))
    key(ex, "d")
    assert ex.drawing and ex.draw_mode == "obstacle"
    key(ex, "escape")
    key(ex, "b")
    assert ex.drawing and ex.draw_mode == "robot"
    key(ex, "escape")
    key(ex, "2")
    click(ex, 20.0, 3.0)
    assert ex.goal == pytest.approx((20.0, 3.0))


def test_cli_explore_with_a_robot_snapshot(tmp_path, capsys):
    out = tmp_path / "explore.png"
    assert main(["explore", str(bundled_map("seed000.yaml")), "--resolution", "0.25", "--robot-radius", "0.4",
                 "--save", str(out)]) == 0
    assert "robot disc of radius 0.4" in capsys.readouterr().out
    assert main(["explore", str(bundled_map("seed000.yaml")), "--web", "--save", str(out)]) == 2
    assert "give one of them" in capsys.readouterr().err
