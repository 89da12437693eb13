"""Legends never cover the map or a path (issue 30): in the figures gridfield lays out, the legend sits
beside the axes (below or right), checked on the drawn artists of real maps (their window extents in
display coordinates after a draw), not on pixels; every marker stays inside the axes."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

from gridfield.fields.potential import build_field
from gridfield.io import read, read_movingai_map, read_scen
from gridfield.planners import plan
from gridfield.plot import plot_comparison, plot_convergence, plot_map, plot_potential

#: (map under tests/data/maps, start, goal): wide, square and tall maps, ROS (mostly unknown) and Moving AI.
MAPS = [
    ("ros_maps/nav2_depot/depot.yaml", (3.0, 3.0), (27.0, 12.0)),
    ("ros_maps/turtlebot3_world/map.yaml", (-2.0, -0.5), (1.8, 0.5)),
    ("movingai/arena/arena.map.gz", (1.5, 37.5), (45.5, 3.5)),
    ("ros_maps/nav2_warehouse/warehouse.yaml", (-3.0, -20.0), (5.0, 15.0)),
]


def dense(points: np.ndarray, n: int = 50) -> np.ndarray:
    """Points along every segment of a polyline (``n`` per segment), its vertices included."""
    t = np.linspace(0.0, 1.0, n)[None, :, None]
    return (points[:-1, None, :] * (1 - t) + points[1:, None, :] * t).reshape(-1, 2)


def check_legend_beside_the_map(art, paths: list[np.ndarray]) -> str:
    """The legend overlaps neither the axes (the map), nor any other axes (a colour bar), nor a path, and
    lies in the figure; every start/goal/stall marker is inside the axes. Returns the side it is on."""
    fig = art.figure
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legend = art.legend.get_window_extent(renderer)
    axes = art.ax.get_window_extent(renderer)
    assert not legend.overlaps(axes), (legend, axes)
    for other in fig.axes:
        if other is not art.ax:
            assert not legend.overlaps(other.get_window_extent(renderer))
    assert not legend.overlaps(art.ax.xaxis.get_tightbbox(renderer))  # nor the x tick labels
    assert fig.bbox.x0 <= legend.x0 and legend.x1 <= fig.bbox.x1 and fig.bbox.y0 <= legend.y0 and legend.y1 <= fig.bbox.y1
    for pts in paths:
        d = art.ax.transData.transform(dense(pts))
        under = (d[:, 0] >= legend.x0) & (d[:, 0] <= legend.x1) & (d[:, 1] >= legend.y0) & (d[:, 1] <= legend.y1)
        assert not under.any(), f"the legend covers {int(under.sum())} points of a path"
    for name, marker in art.markers.items():
        d = art.ax.transData.transform(np.asarray(marker.get_offsets()))
        assert np.all((d[:, 0] >= axes.x0) & (d[:, 0] <= axes.x1) & (d[:, 1] >= axes.y0) & (d[:, 1] <= axes.y1)), name
    return "below" if legend.y1 <= axes.y0 else "right" if legend.x0 >= axes.x1 else "elsewhere"


@pytest.mark.parametrize(("name", "start", "goal"), MAPS, ids=[m[0].split("/")[1] for m in MAPS])
def test_plan_and_potential_figures_put_the_legend_beside_the_map(test_maps, name, start, goal):
    gm = read(test_maps / name)
    path = plan("wavefront-octile", gm, start, goal)
    assert path.status == "reached"
    sides = []
    for draw in (lambda: plot_map(gm, paths=[path], start=start, goal=goal),
                 lambda: plot_potential(build_field(gm, goal), path=path)):
        art = draw()
        try:
            sides.append(check_legend_beside_the_map(art, [path.points]))
        finally:
            plt.close(art.figure)
    assert set(sides) <= {"below", "right"}


def test_wide_maps_get_the_legend_below_and_tall_ones_on_the_right(test_maps):
    sides = {}
    for name, start, goal in (MAPS[0], MAPS[3]):
        gm = read(test_maps / name)
        path = plan("wavefront-octile", gm, start, goal)
        art = plot_map(gm, paths=[path], start=start, goal=goal)
        try:
            sides[name] = check_legend_beside_the_map(art, [path.points])
        finally:
            plt.close(art.figure)
    assert sides == {MAPS[0][0]: "below", MAPS[3][0]: "right"}


def test_a_stalled_run_gets_the_legend_under_its_hint(test_maps):
    """The classic field stalls on arena's longest scenario; the hint box is below the axes, so the legend
    (path, stall point, goal) goes under it, overlapping neither the map, nor the hint, nor the path."""
    arena = test_maps / "movingai" / "arena"
    gm = read_movingai_map(arena / "arena.map.gz")
    scen = read_scen(arena / "arena.map.scen.gz", map_height=gm.shape[0])
    i = int(np.argmax(scen.optimal))
    path = plan("potential", gm, scen.start_xy[i], scen.goal_xy[i], {"model": "khatib"})
    assert path.status == "local_minimum" and path.extra.get("hint")
    for art in (plot_map(gm, paths=[path], goal=scen.goal_xy[i]), plot_potential(build_field(gm, scen.goal_xy[i]),
                                                                                  path=path)):
        try:
            assert "stall" in art.markers
            assert check_legend_beside_the_map(art, [path.points]) == "below"
            renderer = art.figure.canvas.get_renderer()
            legend, hint = art.legend.get_window_extent(renderer), art.extra["hint"].get_window_extent(renderer)
            assert legend.y1 <= hint.y0, (legend, hint)
        finally:
            plt.close(art.figure)


def test_comparison_and_convergence_legends_are_beside_their_axes(test_maps):
    gm = read(test_maps / "movingai" / "arena" / "arena.map.gz")
    start, goal = (1.5, 37.5), (45.5, 3.5)
    grid, exact = plan("wavefront-octile", gm, start, goal), plan("visibility", gm, start, goal)
    art = plot_comparison(gm, grid, exact)
    try:
        check_legend_beside_the_map(art, [grid.points, exact.points])
    finally:
        plt.close(art.figure)
    art = plot_convergence([2.0, 1.0, 0.5], {"Hausdorff": [1.0, 0.5, 0.26], "Frechet": [1.2, 0.6, 0.3]})
    try:
        lines = [np.column_stack([ln.get_xdata(), ln.get_ydata()]) for ln in art.paths]
        check_legend_beside_the_map(art, [])
        renderer = art.figure.canvas.get_renderer()
        box = art.legend.get_window_extent(renderer)
        for pts in lines:  # the error points themselves (log axes: vertices only)
            d = art.ax.transData.transform(pts)
            assert not np.any((d[:, 0] >= box.x0) & (d[:, 0] <= box.x1) & (d[:, 1] >= box.y0) & (d[:, 1] <= box.y1))
    finally:
        plt.close(art.figure)


@pytest.mark.parametrize("layout", ["none", "two panels"])
def test_an_axes_laid_out_otherwise_keeps_the_legend_inside_off_the_path(test_maps, layout):
    """Without room made beside the axes (a figure without constrained layout, or one of several panels)
    the legend stays inside (matplotlib's "best"), and on this map still off the path."""
    gm = read(test_maps / "movingai" / "arena" / "arena.map.gz")
    path = plan("wavefront-octile", gm, (1.5, 37.5), (45.5, 3.5))
    fig, axs = plt.subplots(1, 2) if layout == "two panels" else plt.subplots()
    if layout == "two panels":
        fig.set_layout_engine("constrained")
    ax = axs[0] if layout == "two panels" else axs
    try:
        art = plot_map(gm, ax, paths=[path])
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        legend, axes = art.legend.get_window_extent(renderer), ax.get_window_extent(renderer)
        assert axes.x0 <= legend.x0 and legend.x1 <= axes.x1 and axes.y0 <= legend.y0 and legend.y1 <= axes.y1
        d = ax.transData.transform(dense(path.points))
        assert not np.any((d[:, 0] >= legend.x0) & (d[:, 0] <= legend.x1) & (d[:, 1] >= legend.y0)
                          & (d[:, 1] <= legend.y1))
    finally:
        plt.close(fig)


def test_a_legend_under_a_hint_box_makes_the_figure_taller_not_the_title_fall_out():
    """The demo's stalled seed 000 + segment run: the hint box and, under it, the legend below the map.
    gridfield's own figure grows by the legend's height, so the title, the map and the colour bar stay
    inside it (with a fixed height the constrained layout pushed the title out of the top)."""
    from gridfield.geometry.rasterize import as_gridmap
    from gridfield.io import bundled_map, read_world
    from gridfield.planners import plan_with_field

    w = read_world(bundled_map("seed000_segment.yaml"))
    gm = as_gridmap(w, 0.1)
    path, field = plan_with_field("potential", gm, w.start, w.goal, w.params)
    assert path.status == "local_minimum" and path.hint
    art = plot_potential(field, path=path, title="seed 000 + segment")
    try:
        assert check_legend_beside_the_map(art, [path.points]) == "below"
        fig = art.figure
        renderer = fig.canvas.get_renderer()
        assert fig.get_size_inches()[1] > 5.6  # taller than the default figure
        for box in (art.ax.title.get_window_extent(renderer), art.ax.get_tightbbox(renderer),
                    art.extra["hint"].get_window_extent(renderer)):
            assert fig.bbox.y0 <= box.y0 and box.y1 <= fig.bbox.y1 + 0.5, (box, fig.bbox)
    finally:
        plt.close(art.figure)


def test_a_legend_beside_the_map_fits_the_saved_figure(test_maps):
    """A long label on a square map (legend right of it) stays inside the figure as saved, after the one
    layout pass a save makes (it ran past the figure's edge: 'potential: reached, length 36' on 8room_000)."""
    import io

    d = test_maps / "movingai" / "8room_000"
    gm = read_movingai_map(next(d.glob("*.map.gz")))
    start, goal = (380.5, 325.5), (282.5, 42.5)
    path = plan("potential", gm, start, goal)
    assert path.status == "reached"
    art = plot_map(gm, paths=[path], start=start, goal=goal)
    try:
        art.figure.savefig(io.BytesIO(), format="png", dpi=110)
        legend, fig = art.legend.get_window_extent(), art.figure.bbox
        assert legend.x0 >= art.ax.get_window_extent().x1  # beside the map, on the right
        assert fig.x0 <= legend.x0 and legend.x1 <= fig.x1 and fig.y0 <= legend.y0 and legend.y1 <= fig.y1, (legend, fig)
    finally:
        plt.close(art.figure)
