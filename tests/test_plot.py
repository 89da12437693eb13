"""Figures and animations: the artists drawn and the files written (never pixels)."""

from __future__ import annotations

import math
import shutil
import types

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.collections import LineCollection, PatchCollection
from PIL import Image

from gridfield import plot
from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.core.path import Path
from gridfield.distance.brushfire import brushfire
from gridfield.io import bundled_map, read_world

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def corridor() -> GridMap:
    """A 30 x 40 grid at 0.5 (15 x 20 world units) from (-2, 1): walls left and right, a block."""
    occ = np.zeros((30, 40), bool)
    occ[:, 0] = occ[:, -1] = True
    occ[10:20, 15:25] = True
    return GridMap(Grid((30, 40), 0.5, origin=(-2.0, 1.0)), occ, source="corridor")


@pytest.fixture(scope="module")
def seed000():
    return read_world(bundled_map("seed000.yaml"))


def straight(a, b, n=20, status="reached", planner="test", **extra) -> Path:
    t = np.linspace(0.0, 1.0, n)[:, None]
    return Path(np.asarray(a) + t * (np.asarray(b) - np.asarray(a)), status, planner, iterations=n - 1, extra=extra)


def fake_field(gm: GridMap, goal=(8.0, 14.0)) -> types.SimpleNamespace:
    """Attractive bowl plus a repulsive bump, +inf on obstacles (the Field contract)."""
    xs, ys = gm.grid.cell_centers()
    X, Y = np.meshgrid(xs, ys)
    u = 0.5 * ((X - goal[0]) ** 2 + (Y - goal[1]) ** 2) + 50.0 / (1.0 + (X - 3) ** 2 + (Y - 8) ** 2)
    gx, gy = X - goal[0], Y - goal[1]
    u[gm.occupied] = np.inf
    gx[gm.occupied] = 0.0
    gy[gm.occupied] = 0.0
    return types.SimpleNamespace(map=gm, potential=u, grad_x=gx, grad_y=gy, goal=goal, params={}, distance=None)


# ----------------------------------------------------------------------------------------------
# plot_map
# ----------------------------------------------------------------------------------------------
def test_plot_map_grid_image_in_world_coordinates(corridor):
    paths = [straight((-1.0, 2.0), (10.0, 14.0)), straight((-1.0, 2.0), (15.0, 3.0), status="collision")]
    art = plot.plot_map(corridor, paths=paths, start=(-1.0, 2.0), goal=(10.0, 14.0))
    assert art.image.origin == "lower"
    assert tuple(art.image.get_extent()) == corridor.grid.extent == (-2.0, 18.0, 1.0, 16.0)
    # row 0 of the array is drawn at the bottom: the image data is the occupancy itself, unflipped
    assert np.array_equal(np.asarray(art.image.get_array()), corridor.occupied.astype(np.uint8))
    assert art.image.get_clim() == (-0.5, 1.5)
    assert len(art.ax.lines) == 2 and list(art.ax.lines) == art.paths
    texts = [t.get_text() for t in art.legend.get_texts()]
    assert any("reached" in t for t in texts) and any("collision" in t for t in texts)
    assert "start" in texts and "goal" in texts
    assert np.allclose(art.markers["start"].get_offsets(), [[-1.0, 2.0]])
    assert np.allclose(art.markers["goal"].get_offsets(), [[10.0, 14.0]])
    assert art.ax.get_xlim() == (-2.0, 18.0) and art.ax.get_ylim() == (1.0, 16.0)


def test_plot_map_world_outlines_and_rasterized_image(seed000):
    from gridfield.geometry.rasterize import as_gridmap

    art = plot.plot_map(as_gridmap(seed000, 0.25))
    assert tuple(art.image.get_extent()) == (0.0, 25.0, 0.0, 20.0)
    assert art.image.get_array().shape == (80, 100)
    polys = [a for a in art.obstacles if isinstance(a, PatchCollection)]
    assert len(polys) == 1 and len(polys[0].get_paths()) == 3
    # the world's own start and goal are marked by default
    assert np.allclose(art.markers["start"].get_offsets(), [seed000.start])
    assert np.allclose(art.markers["goal"].get_offsets(), [seed000.goal])
    assert len(art.ax.lines) == 0


def test_plot_map_draws_a_world_as_outlines_and_rasterizes_nothing(seed000, monkeypatch):
    import gridfield.geometry.rasterize as rasterize

    def no(*_a, **_k):
        raise AssertionError("plot_map rasterized the world")

    monkeypatch.setattr(rasterize, "as_gridmap", no)
    monkeypatch.setattr(rasterize, "rasterize", no)
    art = plot.plot_map(seed000)
    assert art.image is None and not art.ax.images
    polys = [a for a in art.obstacles if isinstance(a, PatchCollection)]
    assert len(polys) == 1 and len(polys[0].get_paths()) == 3
    assert art.ax.get_xlim() == (0.0, 25.0) and art.ax.get_ylim() == (0.0, 20.0)


def test_plot_map_segments_circles_and_stall_points():
    w = read_world(bundled_map("seed000_segment.yaml"))
    stalled = straight(w.start, (16.97, 9.03), status="local_minimum", planner="potential")
    art = plot.plot_map(w, paths=stalled)  # a single Path is accepted
    segs = [a for a in art.obstacles if isinstance(a, LineCollection)]
    assert len(segs) == 1 and np.allclose(segs[0].get_segments()[0], [[17.5, 10.0], [17.5, 8.0]])
    assert np.allclose(art.markers["stall"].get_offsets(), [[16.97, 9.03]])
    circles = read_world(bundled_map("seed003_circles.yaml"))
    art = plot.plot_map(circles)
    patches = next(a for a in art.obstacles if isinstance(a, PatchCollection))
    assert len(patches.get_paths()) == 2


def test_plot_map_stall_points_from_extra_and_into_a_given_axes(corridor):
    _, (a1, a2) = plt.subplots(1, 2)
    p = straight((-1.0, 2.0), (5.0, 5.0), status="local_minimum", local_minima=[[3.0, 3.0], [5.0, 5.0]])
    art = plot.plot_map(corridor, a2, paths=[p, straight((0.0, 2.0), (9.0, 2.0))], legend=False)
    assert art.ax is a2 and len(a1.lines) == 0 and len(a2.lines) == 2
    assert art.legend is None
    assert np.allclose(art.markers["stall"].get_offsets(), [[3.0, 3.0], [5.0, 5.0]])


def test_plot_map_widens_the_view_for_paths_leaving_an_open_grid(corridor):
    art = plot.plot_map(corridor, paths=[straight((0.0, 2.0), (25.0, 2.0))])
    assert art.ax.get_xlim()[1] > 25.0 and art.ax.get_xlim()[0] == -2.0


def test_plot_map_rejects_other_targets():
    with pytest.raises(ParameterError, match="World or a GridMap"):
        plot.plot_map(np.zeros((3, 3), bool))
    with pytest.raises(ParameterError, match="Path"):
        plot.plot_map(GridMap(Grid((2, 2), 1.0), np.zeros((2, 2), bool)), paths=[np.zeros((2, 2))])


# ----------------------------------------------------------------------------------------------
# plot_brushfire
# ----------------------------------------------------------------------------------------------
def test_plot_brushfire_heat_map_contours_gvd(corridor):
    d = brushfire(corridor, metric="euclidean")
    art = plot.plot_brushfire(d, levels=5)
    assert art.image.origin == "lower" and tuple(art.image.get_extent()) == corridor.grid.extent
    free = ~corridor.occupied
    assert art.image.get_clim() == (0.0, pytest.approx(d.distance[free].max()))
    assert np.array_equal(np.ma.getmaskarray(art.image.get_array()), corridor.occupied)
    assert len(art.contours.levels) == 5
    assert np.all((art.contours.levels > 0) & (art.contours.levels < d.distance[free].max()))
    gvd = art.extra["gvd"]
    assert tuple(gvd.get_extent()) == corridor.grid.extent
    assert gvd.get_array().count() == d.gvd.sum() > 0
    assert art.colorbar is not None
    assert "labels" not in art.extra


def test_plot_brushfire_requested_clim_labels_and_no_colorbar(corridor):
    d = brushfire(corridor)
    art = plot.plot_brushfire(d, clim=(0.0, 2.0), labels=True, gvd=False, colorbar=False, levels=[1.0, 2.0])
    assert art.image.get_clim() == (0.0, 2.0)
    assert art.colorbar is None and "gvd" not in art.extra
    lab = art.extra["labels"]
    assert lab.get_array().count() == int((~corridor.occupied).sum())
    assert list(art.contours.levels) == [1.0, 2.0]


def test_plot_brushfire_without_obstacles_draws_no_contours():
    gm = GridMap(Grid((5, 5), 1.0), np.zeros((5, 5), bool))
    art = plot.plot_brushfire(brushfire(gm))
    assert art.contours is None and art.image.get_array().count() == 0


# ----------------------------------------------------------------------------------------------
# plot_potential
# ----------------------------------------------------------------------------------------------
def test_plot_potential_log_scale_cap_quiver_stall(corridor):
    f = fake_field(corridor)
    u = f.potential[np.isfinite(f.potential)]
    art = plot.plot_potential(f, cap=40.0, quiver_step=4, stall_points=[[3.0, 8.0]])
    lo, hi = art.mappable.get_clim()
    assert hi == pytest.approx(40.0 - u.min())  # log colours show U - min U, clipped at the cap
    assert 0 < lo < hi
    assert art.mappable.norm.__class__.__name__ == "LogNorm"
    assert art.colorbar is not None and all(t > 0 for t in art.colorbar.get_ticks())
    # the obstacle overlay sits on the grid
    assert art.image.origin == "lower" and tuple(art.image.get_extent()) == corridor.grid.extent
    # arrows: unit -grad U on the free cells of a 4-cell lattice
    q = art.quiver
    rr, cc = np.meshgrid(np.arange(2, 30, 4), np.arange(2, 40, 4), indexing="ij")
    assert len(q.U) == int((~corridor.occupied[rr, cc]).sum())
    assert np.allclose(np.hypot(q.U, q.V), 1.0)
    assert np.allclose(art.markers["stall"].get_offsets(), [[3.0, 8.0]])
    assert np.allclose(art.markers["goal"].get_offsets(), [f.goal])


def test_plot_potential_linear_scale_and_path(corridor):
    f = fake_field(corridor)
    u = f.potential[np.isfinite(f.potential)]
    p = straight((-1.0, 2.0), (6.0, 9.0), status="local_minimum", planner="potential", stall_point=[6.0, 9.0])
    art = plot.plot_potential(f, log=False, cap=30.0, quiver=False, path=p, colorbar=False)
    assert art.mappable.get_clim() == (pytest.approx(u.min()), 30.0)
    assert art.quiver is None and art.colorbar is None
    assert len(art.ax.lines) == 1 and art.paths[0] is art.ax.lines[0]
    assert np.allclose(art.markers["stall"].get_offsets(), [[6.0, 9.0]])
    assert np.allclose(art.markers["start"].get_offsets(), [[-1.0, 2.0]])


def test_plot_potential_of_a_real_field(seed000):
    import gridfield.fields.potential as potential
    from gridfield.geometry.rasterize import as_gridmap

    gm = as_gridmap(seed000, 0.25)
    f = potential.build_field(gm, seed000.goal, dict(seed000.params))
    art = plot.plot_potential(f)
    assert art.contours is not None and art.quiver is not None
    assert tuple(art.image.get_extent()) == gm.grid.extent


def test_plot_potential_errors(corridor):
    f = fake_field(corridor)
    bad = types.SimpleNamespace(**{**vars(f), "potential": np.full(corridor.shape, np.inf)})
    with pytest.raises(GridfieldError, match="no finite value"):
        plot.plot_potential(bad)
    with pytest.raises(ParameterError, match="cap"):
        plot.plot_potential(f, cap=math.inf)
    with pytest.raises(ParameterError, match="quiver_step"):
        plot.plot_potential(f, quiver_step=0)


# ----------------------------------------------------------------------------------------------
# plot_surface
# ----------------------------------------------------------------------------------------------
def test_plot_surface_caps_decimates_and_draws_the_path(corridor):
    f = fake_field(corridor)
    u = f.potential[np.isfinite(f.potential)]
    p = straight((-1.0, 2.0), (8.0, 14.0))
    art = plot.plot_surface(f, path=p, cap=60.0, max_cells=10)
    assert art.ax.name == "3d"
    assert art.extra["stride"] == 4  # ceil(40 / 10)
    assert art.surface.get_clim() == (pytest.approx(u.min()), 60.0)
    assert art.ax.get_zlim()[1] == pytest.approx(60.0)
    assert len(art.paths) == 1
    xs, _, zs = art.paths[0].get_data_3d()
    assert len(xs) == len(p.points) and np.all(zs <= 60.0 + 0.6)


def test_plot_surface_default_cap_and_axes_check(corridor):
    f = fake_field(corridor)
    art = plot.plot_surface(f)
    assert art.extra["stride"] == 1 and art.paths == []
    _, ax = plt.subplots()
    with pytest.raises(ParameterError, match="3-D axes"):
        plot.plot_surface(f, ax)
    with pytest.raises(ParameterError, match="max_cells"):
        plot.plot_surface(f, max_cells=1)


# ----------------------------------------------------------------------------------------------
# plot_basins
# ----------------------------------------------------------------------------------------------
def test_plot_basins_colours_and_legend():
    lab = np.array([[0, 1, 1, 2], [3, 3, 1, 2], [3, 3, 0, 0]])
    b = types.SimpleNamespace(grid=Grid((3, 4), 1.0), label=lab, goal_cell=(0, 1),
                              minima=np.array([[1.5, 0.5], [3.5, 1.5], [0.5, 2.5]]))
    art = plot.plot_basins(b)
    assert art.image.origin == "lower" and tuple(art.image.get_extent()) == (0.0, 4.0, 0.0, 3.0)
    assert art.image.get_clim() == (-0.5, 3.5)
    # row 0 of minima is the goal's own sink: only the two local minima are marked
    assert np.allclose(art.markers["minima"].get_offsets(), [[3.5, 1.5], [0.5, 2.5]])
    assert np.allclose(art.markers["goal"].get_offsets(), [[1.5, 0.5]])
    texts = [t.get_text() for t in art.legend.get_texts()]
    assert texts[0].startswith("goal basin (33 %)")
    assert sum(t.startswith("minimum") for t in texts) == 2


def test_plot_basins_of_a_real_field(seed000):
    import gridfield.fields.potential as potential
    import gridfield.following.follower as follow
    from gridfield.geometry.rasterize import as_gridmap

    w = read_world(bundled_map("seed000_segment.yaml"))
    gm = as_gridmap(w, 0.25)
    b = follow.basins(potential.build_field(gm, w.goal, dict(w.params)))
    art = plot.plot_basins(b)
    assert tuple(art.image.get_extent()) == gm.grid.extent
    assert art.image.get_clim() == (-0.5, b.label.max() + 0.5)


def test_plot_basins_rejects_wrong_shapes():
    b = types.SimpleNamespace(label=np.ones((2, 2), int), minima=np.empty((0, 2)))
    with pytest.raises(GridfieldError, match="shape"):
        plot.plot_basins(b, grid=Grid((3, 3), 1.0))


# ----------------------------------------------------------------------------------------------
# comparison and convergence
# ----------------------------------------------------------------------------------------------
def test_plot_comparison(seed000):
    a = straight(seed000.start, seed000.goal, planner="potential")
    b = Path(a.points + np.array([0.0, 0.3]), "reached", "exact-potential")
    art = plot.plot_comparison(seed000, a, b, deviation=0.3)
    assert len(art.ax.lines) == 2 and art.paths[1].get_linestyle() == "--"
    assert art.extra["deviation"] == 0.3 and "max deviation 0.3" in art.ax.get_title()
    # the figure computes nothing: without a deviation, the title has the lengths only
    bare = plot.plot_comparison(seed000, a, b)
    assert math.isnan(bare.extra["deviation"]) and "deviation" not in bare.ax.get_title()


def test_plot_convergence_log_log_and_rows():
    art = plot.plot_convergence([0.4, 0.1, 0.2], {"length": [0.4, 0.1, 0.2], "end": [0.0, np.nan, 0.5]},
                                slopes=(1.0, 2.0))
    assert art.ax.get_xscale() == art.ax.get_yscale() == "log"
    assert len(art.paths) == 2 and len(art.extra["reference"]) == 2
    assert list(art.paths[0].get_xdata()) == [0.1, 0.2, 0.4]  # sorted by resolution
    # zero and NaN have no logarithm: left out
    assert list(art.paths[1].get_xdata()) == [0.2] and list(art.paths[1].get_ydata()) == [0.5]
    rows = [{"resolution": 0.2, "length_error": 0.05, "end_error": 0.1, "planner": "potential"},
            {"resolution": 0.1, "length_error": 0.02, "end_error": 0.04, "planner": "potential"}]
    art = plot.plot_convergence(rows, slopes=())
    assert [ln.get_label() for ln in art.paths] == ["length_error", "end_error"]


def test_plot_convergence_errors():
    with pytest.raises(ParameterError, match="2 resolutions"):
        plot.plot_convergence([0.1, 0.2], {"e": [1.0]})
    with pytest.raises(ParameterError, match="positive"):
        plot.plot_convergence([0.0, 0.2], {"e": [1.0, 2.0]})
    with pytest.raises(ParameterError, match="row dicts"):
        plot.plot_convergence([0.1, 0.2])
    art = plot.plot_convergence([0.1, 0.2], {"e": [0.0, -1.0]})
    assert art.paths == []


# ----------------------------------------------------------------------------------------------
# files
# ----------------------------------------------------------------------------------------------
def test_save_plan_figure_writes_a_png(tmp_path, corridor):
    out = plot.save_plan_figure(tmp_path / "plan.png", corridor, straight((-1.0, 2.0), (10.0, 14.0)))
    assert out.read_bytes()[:8] == PNG
    assert plt.get_fignums() == []  # the figure was closed
    with Image.open(out) as im:
        assert im.size[0] > 300


def test_save_plan_figure_errors(tmp_path, corridor):
    p = straight((-1.0, 2.0), (10.0, 14.0))
    with pytest.raises(ParameterError, match="unknown figure format"):
        plot.save_plan_figure(tmp_path / "plan.bmpx", corridor, p)
    with pytest.raises(GridfieldError, match="does not exist"):
        plot.save_plan_figure(tmp_path / "missing" / "plan.png", corridor, p)


def test_save_plan_animation_gif_over_the_map(tmp_path, corridor):
    p = straight((-1.0, 2.0), (10.0, 14.0), n=50)
    out = plot.save_plan_animation(tmp_path / "run.gif", corridor, p, max_frames=12, fps=10)
    data = out.read_bytes()
    assert data[:6] in (b"GIF87a", b"GIF89a")
    with Image.open(out) as im:
        assert im.n_frames == 12
        assert im.info["duration"] == 100
    assert plt.get_fignums() == []


def test_save_plan_animation_over_the_field_the_caller_has(tmp_path, seed000, monkeypatch):
    import gridfield.fields.potential as potential
    from gridfield.planners import plan_with_field

    path, field = plan_with_field("potential", seed000, seed000.start, seed000.goal, resolution=0.25)
    assert field is not None and field.map.grid.resolution == 0.25

    def no(*_a, **_k):
        raise AssertionError("the animation rebuilt the field")

    monkeypatch.setattr(potential, "build_field", no)
    out = plot.save_plan_animation(tmp_path / "run.gif", field.map, path, field=field, max_frames=8)
    with Image.open(out) as im:
        assert im.n_frames == min(8, len(path.points))


def test_save_plan_animation_short_path_keeps_every_point(tmp_path, corridor):
    p = straight((-1.0, 2.0), (3.0, 4.0), n=5)
    out = plot.save_plan_animation(tmp_path / "short.gif", corridor, p, max_frames=100)
    with Image.open(out) as im:
        assert im.n_frames == 5


def test_save_plan_animation_formats(tmp_path, corridor):
    p = straight((-1.0, 2.0), (3.0, 4.0), n=5)
    with pytest.raises(ParameterError, match=r"\.gif"):
        plot.save_plan_animation(tmp_path / "run.avi", corridor, p)
    import importlib.util

    # an ffmpeg: the system's, or the one imageio-ffmpeg ships (the [video] extra)
    if shutil.which("ffmpeg") is None and importlib.util.find_spec("imageio_ffmpeg") is None:
        with pytest.raises(GridfieldError, match="ffmpeg"):
            plot.save_plan_animation(tmp_path / "run.mp4", corridor, p)
    else:
        out = plot.save_plan_animation(tmp_path / "run.mp4", corridor, p, max_frames=5)
        assert out.stat().st_size > 0
    with pytest.raises(ParameterError, match="max_frames"):
        plot.save_plan_animation(tmp_path / "run.gif", corridor, p, max_frames=0)
    with pytest.raises(GridfieldError, match="no points"):
        plot.save_plan_animation(tmp_path / "run.gif", corridor, Path(np.empty((0, 2)), "no_path", "x"))


def test_animate_brushfire(tmp_path, corridor):
    d = brushfire(corridor)
    out = plot.animate_brushfire(d, tmp_path / "bf.gif", max_frames=6)
    with Image.open(out) as im:
        assert im.n_frames == 6
    empty = brushfire(GridMap(Grid((3, 3), 1.0), np.zeros((3, 3), bool)))
    with pytest.raises(GridfieldError, match="no wavefront"):
        plot.animate_brushfire(empty, tmp_path / "none.gif")
    with pytest.raises(GridfieldError, match="compute_steps=False"):
        plot.animate_brushfire(brushfire(corridor, compute_steps=False), tmp_path / "nosteps.gif")


def test_cli_plan_plot_and_animate(tmp_path, capsys):
    from gridfield.cli import main

    fig, gif = tmp_path / "plan.png", tmp_path / "plan.gif"
    rc = main(["plan", str(bundled_map("seed000.yaml")), "--resolution", "0.25", "--plot", str(fig),
               "--animate", str(gif)])
    assert rc == 0, capsys.readouterr().err
    assert fig.read_bytes()[:8] == PNG
    with Image.open(gif) as im:
        assert im.n_frames > 1


def _count_build_field(monkeypatch):
    """Count the calls of gridfield.fields.potential.build_field (looked up at call time by its users)."""
    import gridfield.fields.potential as potential

    calls = []
    real = potential.build_field

    def counting(*a, **k):
        calls.append(a[0].grid.shape)  # the shape of the map it is built on
        return real(*a, **k)

    monkeypatch.setattr(potential, "build_field", counting)
    return calls


def test_cli_plan_plot_and_animate_build_the_field_once(tmp_path, capsys, monkeypatch):
    from gridfield.cli import main

    calls = _count_build_field(monkeypatch)
    fig, gif = tmp_path / "plan.png", tmp_path / "plan.gif"
    rc = main(["plan", str(bundled_map("seed000.yaml")), "--resolution", "0.5", "--plot", str(fig),
               "--animate", str(gif)])
    assert rc == 0, capsys.readouterr().err
    # once on the plan's map (the CLI's warm-up may build one on its own 24 x 24 map first, to time the
    # start-up apart; seed000's world asks for the classic field, the warm-up plans with the default)
    assert len([c for c in calls if c != (24, 24)]) == 1, calls
    assert fig.stat().st_size > 0 and gif.stat().st_size > 0


def test_plan_with_field_is_the_field_followed_and_changes_no_path(seed000):
    import gridfield.fields.potential as potential
    from gridfield.geometry.rasterize import as_gridmap
    from gridfield.planners import Plan, plan, plan_with_field

    gm = as_gridmap(seed000, 0.5)
    alone = plan("potential", gm, seed000.start, seed000.goal)
    got = plan_with_field("potential", gm, seed000.start, seed000.goal)
    assert isinstance(got, Plan) and isinstance(alone, type(got.path))
    path, field = got
    assert np.array_equal(path.points, alone.points) and path.status == alone.status
    # an independent rebuild with the path's own (resolved) parameters gives the same arrays
    ref = potential.build_field(gm, seed000.goal, dict(seed000.params))
    assert field.map is gm
    assert np.array_equal(field.potential, ref.potential) and np.array_equal(field.grad_x, ref.grad_x)
    # other planners build no potential: None
    assert plan_with_field("wavefront-octile", gm, seed000.start, seed000.goal).field is None
    # a cache the caller keeps does not keep the field afterwards
    cache: dict = {}
    plan_with_field("potential", gm, seed000.start, seed000.goal, cache=cache)
    assert "field" not in cache
    # plan returns one type: the old return_field=True (deprecated for one release) is gone
    with pytest.raises(TypeError, match="return_field"):
        plan("potential", gm, seed000.start, seed000.goal, return_field=True)


def test_the_deprecated_plot_aliases_are_gone():
    """gridfield.plot.layers and the figures module's aliases of the results figures were removed (CHANGELOG):
    import them from gridfield.plot."""
    import gridfield.plot
    import gridfield.plot.figures as figures

    with pytest.raises(ModuleNotFoundError):
        import gridfield.plot.layers
    assert not hasattr(figures, "plot_comparison")
    assert gridfield.plot.Artists.__module__ == "gridfield.plot._layers"
