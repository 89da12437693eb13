"""Figures tell the truth, checked on the matplotlib artists (not pixels): the hint box covers no part
of the map, the basin legend names a displaced goal sink and never says "0.0 %" or "100 %" for
less, a stall point outside the map is marked as such, ROS maps are titled by their folder and shown
by their known part, and ``field --plot`` says what the field is."""

from __future__ import annotations

import types

import matplotlib.pyplot as plt
import numpy as np
import pytest

from gridfield.core.grid import Grid, GridMap
from gridfield.core.path import Path
from gridfield.io import bundled_map, read
from gridfield.plot import plot_basins, plot_map


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def test_hint_box_covers_nothing_of_the_map() -> None:
    gm = GridMap(Grid((20, 20), 1.0), np.zeros((20, 20), bool))
    p = Path(np.array([[1.5, 1.5], [10.5, 1.2], [18.5, 0.8]]), "local_minimum", "potential",
             extra={"hint": "a long hint " * 30, "stall_point": [18.5, 0.8]})
    art = plot_map(gm, paths=[p])
    art.figure.canvas.draw()
    box = art.extra["hint"].get_bbox_patch().get_window_extent()
    axes = art.ax.get_window_extent()
    assert box.y1 <= axes.y0  # entirely below the axes: no stall point, path or end under it
    labels = art.ax.xaxis.label.get_window_extent()
    assert box.y1 <= labels.y0 + 1  # and below the x label


@pytest.mark.parametrize("shape", [(81, 65), (20, 20), (30, 120)])
def test_hint_box_lies_inside_the_figure(shape) -> None:
    # den312d (81 x 65) with --param model=khatib: the frame of the box was cut by the figure's lower edge
    gm = GridMap(Grid(shape, 1.0), np.zeros(shape, bool))
    p = Path(np.array([[1.5, 1.5], [10.5, 1.2]]), "local_minimum", "potential",
             extra={"hint": "a three-line hint " * 16, "stall_point": [10.5, 1.2]})
    art = plot_map(gm, paths=[p])
    art.figure.canvas.draw()
    box = art.extra["hint"].get_bbox_patch().get_window_extent()
    fig = art.figure.bbox
    assert fig.x0 <= box.x0 and box.x1 <= fig.x1 and fig.y0 <= box.y0 and box.y1 <= fig.y1


def test_basin_legend_names_a_displaced_goal_sink_and_small_shares() -> None:
    lab = np.ones((50, 100), int)
    lab[0, 0] = 2  # one cell of 5000: 0.02 %
    b = types.SimpleNamespace(label=lab, minima=np.array([[10.5, 10.5], [0.5, 0.5]]), goal_cell=(20, 20))
    texts = [t.get_text() for t in plot_basins(b, grid=Grid((50, 100), 1.0)).legend.get_texts()]
    assert not any(t.startswith("goal basin") for t in texts)  # the goal cell drains to (10.5, 10.5)
    assert any("sink is off the goal, at (10.5, 10.5)" in t and "> 99 %" in t for t in texts), texts
    assert any(t.startswith("minimum 1 (< 0.1 %)") for t in texts), texts
    assert not any("0.0 %" in t or "(100 %" in t for t in texts)


def test_basin_legend_says_when_the_sink_is_the_cell_beside_the_goal() -> None:
    """The goal (22, 12) on a cell corner, its sink in the diagonal neighbour (21.5, 11.5): shown to 4
    digits with "the cell beside the goal's" (to 3 digits the label read "off the goal, at (22, 12)"),
    and the legend goes where it is asked to."""
    b = types.SimpleNamespace(label=np.ones((20, 30), int), minima=np.array([[21.5, 11.5]]), goal_cell=(12, 22))
    art = plot_basins(b, grid=Grid((20, 30), 1.0), legend_loc="upper right")
    texts = [t.get_text() for t in art.legend.get_texts()]
    assert "the sink is off the goal, at (21.5, 11.5), the cell beside the goal's" in texts[0], texts
    assert art.legend._loc == 1  # matplotlib's code of "upper right"
    below = plot_basins(b, grid=Grid((20, 30), 1.0), legend_loc="below")
    below.figure.canvas.draw()
    assert below.legend.get_window_extent().y1 <= below.ax.get_window_extent().y0  # under the map, covering none
    far = types.SimpleNamespace(label=np.ones((20, 30), int), minima=np.array([[10.5, 10.5]]), goal_cell=(12, 22))
    assert "beside" not in plot_basins(far, grid=Grid((20, 30), 1.0)).legend.get_texts()[0].get_text()


def test_goal_basin_when_the_sink_is_the_goal_cell() -> None:
    b = types.SimpleNamespace(label=np.ones((4, 5), int), minima=np.array([[2.5, 1.5]]), goal_cell=(1, 2))
    texts = [t.get_text() for t in plot_basins(b, grid=Grid((4, 5), 1.0)).legend.get_texts()]
    assert texts[0] == "goal basin (100 %)"


def test_stall_point_outside_the_map_is_marked_so() -> None:
    gm = GridMap(Grid((10, 10), 1.0, origin=(-5.0, -5.0)), np.zeros((10, 10), bool))
    p = Path(np.array([[0.0, 4.0], [-0.8, -5.2]]), "local_minimum", "potential",
             extra={"stall_point": [-0.8, -5.2]})
    art = plot_map(gm, paths=[p])
    assert "stall" not in art.markers and "stall_outside" in art.markers
    assert "outside the map" in art.markers["stall_outside"].get_label()
    x0, y0, w, h = art.extra["map_edge"].get_bbox().bounds
    assert (x0, y0, x0 + w, y0 + h) == gm.grid.bounds


def test_ros_map_titled_by_folder_and_shown_by_its_known_part() -> None:
    gm = read(bundled_map("turtlebot3_world/map.yaml"))
    art = plot_map(gm)
    assert art.ax.get_title() == "turtlebot3_world"
    xmin, ymin, xmax, ymax = gm.grid.bounds
    (x0, x1), (y0, y1) = art.ax.get_xlim(), art.ax.get_ylim()
    assert (x1 - x0) < 0.5 * (xmax - xmin) and (y1 - y0) < 0.5 * (ymax - ymin)  # 384 x 384 cells, most unknown
    free = np.argwhere(~gm.occupied)
    pts = gm.grid.cell_to_world(free)
    assert x0 <= pts[:, 0].min() and pts[:, 0].max() <= x1 and y0 <= pts[:, 1].min() and pts[:, 1].max() <= y1


def test_field_plot_says_what_the_field_is(tmp_path, monkeypatch) -> None:
    from gridfield import plot as gplot
    from gridfield.cli import main

    titles = []
    real = gplot.plot_potential

    def spy(*a, **k):
        art = real(*a, **k)
        titles.append(art.ax.get_title())
        return art

    monkeypatch.setattr(gplot, "plot_potential", spy)
    assert main(["field", str(bundled_map("seed000.yaml")), "--goal", "22", "12", "--resolution", "0.5",
                 "--plot", str(tmp_path / "f.png")]) == 0
    assert titles and "seed000.yaml" in titles[0] and "khatib" in titles[0] and "goal (22, 12)" in titles[0]


def test_a_robots_plan_figure_says_it_shows_the_configuration_space(tmp_path, monkeypatch) -> None:
    # plan --robot-radius --plot draws the grown grid (the C-space): its title says so; a no_path's
    # legend gives no "length 0" (mdr_wrs20-arena with r = 0.2 read as a path of length 0)
    from gridfield.cli import main
    from gridfield.plot import results

    arts = []
    real = results.plot_map

    def spy(*a, **k):
        arts.append(real(*a, **k))
        return arts[-1]

    monkeypatch.setattr(results, "plot_map", spy)
    ros = str(bundled_map("turtlebot3_world/map.yaml"))
    assert main(["plan", ros, "--start", "-2", "-0.5", "--goal", "1.9", "0.5", "--robot-radius", "0.1",
                 "--planner", "wavefront", "--plot", str(tmp_path / "r.png")]) == 0
    assert arts[-1].ax.get_title() == "turtlebot3_world, configuration space of the robot (disc of radius 0.1)"
    assert main(["plan", ros, "--start", "-2", "-0.5", "--goal", "1.9", "0.5", "--planner", "wavefront",
                 "--plot", str(tmp_path / "p.png")]) == 0
    assert arts[-1].ax.get_title() == "turtlebot3_world"
    gm = GridMap(Grid((10, 10), 1.0), np.zeros((10, 10), bool))
    art = plot_map(gm, paths=[Path(np.array([[1.5, 1.5]]), "no_path", "wavefront")], goal=(8.5, 8.5))
    labels = [t.get_text() for t in art.legend.get_texts()]
    assert labels[0] == "wavefront: no_path (no path joins start and goal)" and not any("length" in t for t in labels)
