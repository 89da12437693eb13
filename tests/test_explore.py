"""The interactive explorer, headless: synthetic mouse events, widget callbacks, the CLI snapshot."""

from __future__ import annotations

import os

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.backend_bases import KeyEvent, MouseEvent

from gridfield.cli import main
from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.explore import Explorer, available_planners
from gridfield.io import bundled_map, read_world


@pytest.fixture
def explorer():
    ex = Explorer(read_world(bundled_map("seed000.yaml")), resolution=0.25)
    yield ex
    ex.close()


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def click(ex: Explorer, x: float, y: float, button: int = 1) -> None:
    """Send a mouse press at world point (x, y) through the canvas' callback registry."""
    dx, dy = ex.ax.transData.transform((x, y))
    event = MouseEvent("button_press_event", ex.figure.canvas, dx, dy, button=button)
    ex.figure.canvas.callbacks.process("button_press_event", event)


def path_xy(ex: Explorer) -> np.ndarray:
    return np.column_stack(ex.path_line.get_data()).astype(float)


def test_initial_state_plans_the_world_start_to_goal(explorer):
    assert explorer.start == (1.0, 10.0) and explorer.goal == (22.0, 12.0)
    assert explorer.path is not None and explorer.path.status == "reached"
    xy = path_xy(explorer)
    assert len(xy) == len(explorer.path.points) and np.allclose(xy[0], (1.0, 10.0))
    assert explorer.message.startswith("potential: reached")
    # the map layer is in world coordinates with row 0 at the bottom
    img = explorer.occupancy_image
    assert img.origin == "lower" and list(img.get_extent()) == [0.0, 25.0, 0.0, 20.0]


def test_clicks_set_start_then_goal_and_the_path_follows(explorer):
    before = path_xy(explorer)
    n = explorer.n_updates
    click(explorer, 2.0, 2.0)
    assert explorer.start == pytest.approx((2.0, 2.0))
    assert explorer.n_updates == n + 1
    after_start = path_xy(explorer)
    assert not np.array_equal(before, after_start)
    assert np.allclose(after_start[0], (2.0, 2.0))
    click(explorer, 20.0, 3.0)
    assert explorer.goal == pytest.approx((20.0, 3.0))
    assert np.allclose(explorer.goal_marker.get_offsets()[0], (20.0, 3.0))
    assert explorer.path.status == "reached"
    assert np.allclose(path_xy(explorer)[-1], (20.0, 3.0), atol=0.2)
    # the third click sets the start again
    click(explorer, 3.0, 15.0)
    assert explorer.start == pytest.approx((3.0, 15.0))


def test_click_inside_an_obstacle_is_refused_with_a_message(explorer):
    before = path_xy(explorer)
    click(explorer, 9.0, 6.0)  # inside the triangle
    assert explorer.start == (1.0, 10.0)
    assert "inside an obstacle" in explorer.message and "start" in explorer.message
    assert np.array_equal(before, path_xy(explorer))


def test_clicks_outside_the_map_axes_and_right_clicks_are_ignored(explorer):
    n = explorer.n_updates
    click(explorer, 2.0, 2.0, button=3)
    slider_ax = explorer.sliders["eta"].ax
    x, y = slider_ax.transAxes.transform((0.5, 0.5))
    explorer.figure.canvas.callbacks.process("button_press_event",
                                             MouseEvent("button_press_event", explorer.figure.canvas, x, y, button=1))
    assert explorer.start == (1.0, 10.0)
    assert explorer.n_updates == n + 1  # only the slider reacted to its own click (eta moved)


def test_slider_set_val_recomputes(explorer):
    n = explorer.n_updates
    before = path_xy(explorer)
    explorer.sliders["q_star"].set_val(4.0)
    assert explorer.params["q_star"] == pytest.approx(4.0)
    assert explorer.n_updates == n + 1
    assert explorer.path.params["q_star"] == pytest.approx(4.0)
    assert not np.array_equal(before, path_xy(explorer))


def test_d_star_slider_end_means_inf(explorer):
    s = explorer.sliders["d_star"]
    assert np.isinf(explorer.params["d_star"]) and s.val == s.valmax and s.valtext.get_text() == "inf"
    s.set_val(3.0)
    assert explorer.params["d_star"] == pytest.approx(3.0) and s.valtext.get_text() == "3"
    explorer.set_param("d_star", float("inf"))
    assert np.isinf(explorer.params["d_star"]) and s.val == s.valmax


def test_sliders_show_the_values_in_use():
    occ = np.zeros((40, 40), bool)
    occ[:, :2] = True
    ex = Explorer(GridMap(Grid((40, 40), 0.5), occ), start=(3.0, 3.0), goal=(17.0, 17.0), params={"eta": 3.0})
    try:
        vals = {k: s.val for k, s in ex.sliders.items()}
        assert vals["eta"] == 3.0 and vals["zeta"] == 1.0 and vals["q_star"] == 2.0 and vals["step"] == 0.5
        assert ex.path.params["q_star"] == 2.0 and ex.path.params["step"] == 0.5
    finally:
        ex.close()


def test_set_param_checks_names_and_ranges(explorer):
    with pytest.raises(ParameterError, match="zetta"):
        explorer.set_param("zetta", 1.0)
    with pytest.raises(ParameterError, match="outside the slider range"):
        explorer.set_param("eta", 1e6)


def test_drawing_a_polygon_adds_an_obstacle_and_replans(explorer):
    n_obstacles = len(explorer.world.obstacles)
    occupied_before = explorer.gridmap.occupied.sum()
    explorer.toggle_drawing()
    assert explorer.drawing
    for v in [(19.5, 9.0), (21.0, 9.0), (21.0, 15.0), (19.5, 15.0)]:
        click(explorer, *v)
    assert explorer.start == (1.0, 10.0)  # clicks while drawing add vertices, not endpoints
    assert len(explorer.draft_line.get_xdata()) == 4
    n = explorer.n_updates
    click(explorer, 20.0, 12.0, button=3)  # right click closes the polygon
    assert not explorer.drawing
    assert len(explorer.world.obstacles) == n_obstacles + 1
    assert explorer.world.obstacles[-1].kind == "polygon"
    assert explorer.gridmap.occupied.sum() > occupied_before
    assert explorer.n_updates == n + 1
    assert len(explorer.draft_line.get_xdata()) == 0
    # the wall between start and goal changes the path: it no longer runs straight through x = 20
    assert explorer.path is not None
    pts = explorer.path.points
    assert not np.any((pts[:, 0] > 19.6) & (pts[:, 0] < 20.9) & (pts[:, 1] > 9.1) & (pts[:, 1] < 14.9))


def test_drawing_with_too_few_vertices_is_discarded(explorer):
    n_obstacles = len(explorer.world.obstacles)
    explorer.toggle_drawing()
    click(explorer, 20.0, 2.0)
    click(explorer, 21.0, 2.0)
    explorer.toggle_drawing()  # the button again finishes drawing
    assert len(explorer.world.obstacles) == n_obstacles
    assert "at least 3 vertices" in explorer.message


def test_self_intersecting_polygon_is_refused(explorer):
    with pytest.raises(GridfieldError, match="not simple"):
        explorer.add_polygon([(20, 2), (22, 4), (22, 2), (20, 4)])


def test_key_d_toggles_drawing(explorer):
    canvas = explorer.figure.canvas
    canvas.callbacks.process("key_press_event", KeyEvent("key_press_event", canvas, "d"))
    assert explorer.drawing
    canvas.callbacks.process("key_press_event", KeyEvent("key_press_event", canvas, "escape"))
    assert not explorer.drawing


def test_planner_radio_lists_installed_planners(explorer):
    labels = [t.get_text() for t in explorer.radio.labels]
    assert labels == available_planners()
    assert "potential" in labels
    for name in labels:
        explorer.set_planner(name)
        assert explorer.planner == name
        assert explorer.radio.value_selected == name
        assert explorer.path is not None, explorer.message
        assert explorer.path.planner == name


def test_radio_click_switches_planner(explorer):
    labels = [t.get_text() for t in explorer.radio.labels]
    assert len(labels) >= 2, labels
    explorer.radio.set_active(labels.index(labels[1]))
    assert explorer.planner == labels[1]
    assert explorer.path is not None and explorer.path.planner == labels[1]


def test_grid_map_without_world_burns_polygons_into_the_occupancy():
    occ = np.zeros((40, 40), bool)
    occ[:, :2] = True
    gm = GridMap(Grid((40, 40), 0.5), occ)
    ex = Explorer(gm, start=(3.0, 3.0), goal=(17.0, 17.0), params={"q_star": 2.0, "step": 0.2})
    try:
        assert ex.world is None and ex.path is not None
        ex.add_polygon([(8, 8), (12, 8), (12, 12), (8, 12)])
        assert ex.gridmap.occupied[20, 20]  # centre (10.25, 10.25)
        assert ex.gridmap.occupied.sum() > occ.sum()
    finally:
        ex.close()


def test_vortex_world_tracks_the_start_charge():
    ex = Explorer(read_world(bundled_map("seed003_circles.yaml")))
    try:
        assert ex.field is not None
        assert ex.field_image.get_extent() == list(ex.field.map.grid.extent)
        assert ex.set_start(-3.0, 4.0)
        assert ex.world.start == (-3.0, 4.0)
        assert ex.path is not None and np.allclose(ex.path.points[0], (-3.0, 4.0))
    finally:
        ex.close()


def test_explicit_endpoints_replace_the_world_ones():
    ex = Explorer(read_world(bundled_map("seed003_circles.yaml")), start=(3.0, 4.0), goal=(-3.0, -4.0))
    try:
        assert ex.world.start == (3.0, 4.0) and ex.world.goal == (-3.0, -4.0)
        assert ex.path is not None and np.allclose(ex.path.points[0], (3.0, 4.0))
    finally:
        ex.close()


def test_bad_arguments():
    w = read_world(bundled_map("seed000.yaml"))
    with pytest.raises(ParameterError, match="planner must be one of"):
        Explorer(w, planner="dijkstra")
    with pytest.raises(ParameterError, match="World or a GridMap"):
        Explorer("seed000.yaml")  # type: ignore[arg-type]


def test_cli_explore_snapshot(tmp_path, capsys):
    out = tmp_path / "explore.png"
    assert main(["explore", str(bundled_map("seed000.yaml")), "--resolution", "0.25", "--eta", "2",
                 "--save", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "wrote" in capsys.readouterr().out


def test_cli_explore_needs_an_interactive_backend(capsys):
    assert main(["explore", str(bundled_map("seed000.yaml"))]) == 2
    err = capsys.readouterr().err
    assert "cannot open a window" in err and "--save" in err


def test_an_update_builds_the_potential_once(monkeypatch):
    """The background field is the one the planner followed (plan_with_field(...))."""
    import gridfield.fields.potential as potential

    calls = []
    real = potential.build_field

    def counting(*a, **k):
        calls.append(1)
        return real(*a, **k)

    monkeypatch.setattr(potential, "build_field", counting)
    ex = Explorer(read_world(bundled_map("seed000.yaml")), resolution=0.5)
    assert len(calls) == 1 and ex.n_updates == 1
    ex.set_param("zeta", 2.0)
    assert len(calls) == 2 and ex.n_updates == 2
    # the background shows the very field the path followed: its potential, at the path's params
    assert ex.field.params["zeta"] == 2.0 and ex.path.params["zeta"] == 2.0
    assert ex.field_image.get_visible()
    ex.set_planner("wavefront-octile")  # no potential: no build, no background
    assert len(calls) == 2 and ex.field is None and not ex.field_image.get_visible()
    ex.close()


def test_sliders_show_the_values_the_plan_uses():
    """On a map without parameters every slider starts at the value the planner then uses: the
    registry's defaults scaled to the map (q_star 4 cells, d_star 2 q_star, balanced eta, step 1 cell)."""
    from gridfield.core.params import resolve
    from gridfield.explore import PLANNER_SLIDERS
    from gridfield.planners import PLANNERS

    occ = np.zeros((40, 40), bool)
    occ[15:25, 18:22] = True
    e = Explorer(GridMap(Grid(occ.shape, 0.25), occ))
    try:
        want = resolve({}, unit=0.25)
        shown = {n: e.sliders[n].val for n in ("zeta", "eta", "q_star", "d_star", "step")}
        assert shown == pytest.approx({n: want[n] for n in shown})
        assert (shown["q_star"], shown["d_star"], shown["step"]) == pytest.approx((1.0, 2.0, 0.25))
        e.set_start(1.1, 1.1)
        e.set_goal(8.9, 8.9)
        assert e.path is not None
        for n, v in shown.items():
            assert e.path.params[n] == pytest.approx(v), n
    finally:
        e.close()
    for planner, names in PLANNER_SLIDERS.items():  # a planner's sliders are parameters it reads
        assert set(names) <= set(PLANNERS[planner].reads), planner


def test_the_default_complete_model_offers_only_the_sliders_it_reads():
    """On a map without parameters the potential planner's field is nf1, which reads none of the classic
    field's gains: zeta, eta, q_star and d_star sliders moved nothing (seen on den312d); they are shown for
    the classic field, and nf-blend gets q_star (its repulsion's reach). Checked by moving a hidden
    parameter: the path does not change, where a shown one's does."""
    occ = np.zeros((40, 40), bool)
    occ[15:25, 18:22] = True
    e = Explorer(GridMap(Grid(occ.shape, 0.25), occ))
    try:
        shown = lambda: {n for n, s in e.sliders.items() if s.ax.get_visible()}  # noqa: E731
        assert shown() == {"step"}
        e.set_start(1.1, 1.1)
        e.set_goal(8.9, 8.9)
        before = e.path.points.copy()
        e.params["eta"] = 500.0  # a classic gain: nf1 ignores it
        e.recompute()
        assert np.array_equal(e.path.points, before)
        e.set_param("model", "khatib")
        assert shown() == {"zeta", "eta", "q_star", "d_star", "step"}
        e.set_param("model", "nf-blend")
        assert shown() == {"q_star", "step"}
    finally:
        e.close()
