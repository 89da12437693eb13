"""Figures of voxel grids (gridfield.plot.voxels): the arrays the slices show, the isosurface's
triangles, the paths' lines, the files written (never pixels).

The inputs are built here from independent references: the distance map from
``scipy.ndimage.distance_transform_edt``, a potential (the distance to the goal), paths through
voxel centres; the isosurface is checked against the voxels' faces written out plainly.
"""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image
from scipy import ndimage

from gridfield import plot
from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.core.path import Path
from gridfield.core.results import DistanceMap, Field

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _dmap(gm: GridMap) -> DistanceMap:
    """The exact Euclidean distance map of scipy, in the DistanceMap's fields."""
    d, idx = ndimage.distance_transform_edt(~gm.occupied, return_indices=True)
    return DistanceMap(gm, 26, "euclidean", None, d * gm.grid.resolution, idx[1].astype(np.int32),
                       idx[2].astype(np.int32), None, None, nearest_layer=idx[0].astype(np.int32))


def _field(gm: GridMap, goal: tuple[float, float, float]) -> Field:
    """The distance to the goal (inf on obstacles) and its np.gradient."""
    zs, ys, xs = np.meshgrid(*gm.grid.cell_centers()[::-1], indexing="ij")
    u = np.sqrt((xs - goal[0]) ** 2 + (ys - goal[1]) ** 2 + (zs - goal[2]) ** 2)
    gz, gy, gx = np.gradient(u, gm.grid.resolution)
    u = np.where(gm.occupied, np.inf, u)
    return Field(gm, u, gx, gy, goal, {}, _dmap(gm), grad_z=gz)


@pytest.fixture(scope="module")
def world() -> GridMap:
    """10 layers x 12 rows x 16 cols at 0.5 from (-1, 2, 3): a floor slab with a hole, a pillar."""
    occ = np.zeros((10, 12, 16), bool)
    occ[4:6] = True
    occ[4:6, 2:5, 10:14] = False  # the hole
    occ[6:, 7:9, 3:5] = True  # a pillar upstairs
    return GridMap(Grid((10, 12, 16), 0.5, origin=(-1.0, 2.0, 3.0)), occ, source="maps/two_floors.npy")


@pytest.fixture(scope="module")
def route(world: GridMap) -> Path:
    """A path through free voxel centres from downstairs, up the hole, to upstairs."""
    cells = [(1, 1, 1), (1, 3, 6), (2, 3, 11), (4, 3, 11), (5, 3, 11), (6, 4, 11), (8, 9, 10)]
    pts = world.grid.cell_to_world(np.array(cells))
    assert world.is_free(pts).all()
    return Path(pts, "reached", "demo", extra={"goal": tuple(pts[-1])})


# ----------------------------------------------------------------------------------------------
# the slices hold the given arrays
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["gridmap", "dmap", "field"])
def test_figures_build_for_each_input(world: GridMap, route: Path, kind: str, tmp_path) -> None:
    target = {"gridmap": world, "dmap": _dmap(world), "field": _field(world, (5.25, 6.25, 6.75))}[kind]
    arts = plot.plot_voxel_slices(target, paths=route)
    assert len(arts) == 3 and all(len(a.ax.lines) == 1 for a in arts)
    assert (arts[0].colorbar is None) == (kind == "gridmap")
    grid_arts = plot.plot_voxel_slices(target, zs=4, paths=[route, route])
    assert len(grid_arts) == 4 and all(len(a.ax.lines) == 2 for a in grid_arts)
    scene = plot.plot_voxel_scene(target, paths=route)
    assert scene.ax.name == "3d" and scene.surface is not None
    out = plot.save_voxel_figure(tmp_path / f"{kind}.png", target, paths=route, dpi=40)
    assert out.read_bytes()[:8] == PNG
    with Image.open(out) as im:
        assert im.size[0] > 2 * im.size[1]  # slices on the left, the scene on the right


def _cell(grid: Grid, p) -> tuple[int, int, int]:
    """(layer, row, col) of a point, written out plainly."""
    h = grid.resolution
    return tuple(int(math.floor((p[a] - grid.origin[a]) / h)) for a in (2, 1, 0))  # type: ignore[return-value]


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.floats(0, 1), st.floats(0, 1), st.floats(0, 1))
def test_orthogonal_slices_hold_the_distance_slices(world: GridMap, fx: float, fy: float, fz: float) -> None:
    g = world.grid
    b = g.bounds
    at = [b[a] + min(f, 0.999) * (b[a + 3] - b[a]) for a, f in zip(range(3), (fx, fy, fz), strict=True)]
    k, r, c = _cell(g, at)
    dm = _dmap(world)
    d = dm.distance
    arts = plot.plot_voxel_slices(dm, at=at)
    want = [d[k], d[:, r, :], d[:, :, c]]
    occ = world.occupied
    masks = [occ[k], occ[:, r, :], occ[:, :, c]]
    extents = [[b[0], b[3], b[1], b[4]], [b[0], b[3], b[2], b[5]], [b[1], b[4], b[2], b[5]]]
    for art, w, m, e in zip(arts, want, masks, extents, strict=True):
        a = art.image.get_array()
        assert np.array_equal(np.ma.getdata(a), w)
        assert np.array_equal(np.ma.getmaskarray(a), m)  # obstacles masked (distance 0 there)
        assert art.image.origin == "lower" and art.image.get_extent() == pytest.approx(e)
    assert [a.extra["slice"][:2] for a in arts] == [("z", k), ("y", r), ("x", c)]
    # the obstacles drawn over the values: exactly the occupied voxels of each slice
    for art, m in zip(arts, masks, strict=True):
        if m.any():
            assert np.array_equal(~np.ma.getmaskarray(art.obstacles[0].get_array()), m)
    plt.close("all")  # hypothesis runs the examples in one test


def test_slice_grid_holds_the_layers_of_the_heights(world: GridMap) -> None:
    f = _field(world, (5.25, 6.25, 6.75))
    zs = [3.1, 5.2, 7.9]
    arts = plot.plot_voxel_slices(f, zs=zs, ncols=2)
    layers = [int(math.floor((z - 3.0) / 0.5)) for z in zs]
    assert [a.extra["slice"][1] for a in arts] == layers
    for art, k in zip(arts, layers, strict=True):
        assert np.array_equal(np.ma.getdata(art.image.get_array()), f.potential[k])
        assert np.array_equal(np.ma.getmaskarray(art.image.get_array()), world.occupied[k])
    assert arts[0].ax.get_subplotspec().get_gridspec().get_geometry() == (2, 2)
    # evenly spaced layers: the middle ones of equal stacks, all different
    for n in range(1, 11):
        ks = [a.extra["slice"][1] for a in plot.plot_voxel_slices(f, zs=n)]
        assert ks == [int((i + 0.5) * 10 / n) for i in range(n)] and len(set(ks)) == n
        plt.close("all")


def test_gridmap_slices_are_the_occupancy(world: GridMap) -> None:
    arts = plot.plot_voxel_slices(world, at=(2.1, 3.1, 5.3))
    k, r, c = _cell(world.grid, (2.1, 3.1, 5.3))
    occ = world.occupied.astype(np.uint8)
    for art, w in zip(arts, [occ[k], occ[:, r, :], occ[:, :, c]], strict=True):
        assert np.array_equal(np.asarray(art.image.get_array()), w)


def test_default_slices_pass_through_the_start_then_the_goal(world: GridMap, route: Path) -> None:
    start = route.points[0]
    arts = plot.plot_voxel_slices(world, paths=route)
    k, r, c = _cell(world.grid, start)
    assert [a.extra["slice"][1] for a in arts] == [k, r, c]
    f = _field(world, (5.25, 6.25, 6.75))
    arts = plot.plot_voxel_slices(f)
    assert [a.extra["slice"][1] for a in arts] == list(_cell(world.grid, (5.25, 6.25, 6.75)))
    assert "goal" in arts[0].markers and "start" not in arts[0].markers


def test_path_projections_and_3d_line_are_the_path(world: GridMap, route: Path) -> None:
    p = route.points
    arts = plot.plot_voxel_slices(world, paths=route)
    for art, (i, j) in zip(arts, [(0, 1), (0, 2), (1, 2)], strict=True):
        (line,) = art.ax.lines
        assert np.array_equal(line.get_xdata(), p[:, i]) and np.array_equal(line.get_ydata(), p[:, j])
        assert art.markers["start"].get_offsets().tolist() == [[p[0, i], p[0, j]]]
        assert art.markers["goal"].get_offsets().tolist() == [[p[-1, i], p[-1, j]]]
        # the dots: the points whose voxel lies in the slice, along the cut axis
        cut = 3 - i - j
        k = art.extra["slice"][1]
        inside = np.floor((p[:, cut] - world.grid.origin[cut]) / world.grid.resolution) == k
        (dots,) = art.extra["in_slice"]
        assert np.array_equal(dots.get_offsets(), p[inside][:, [i, j]])
    scene = plot.plot_voxel_scene(world, paths=route)
    (line,) = scene.ax.lines
    assert np.array_equal(np.asarray(line.get_data_3d()).T, p)
    assert scene.paths == [line]


# ----------------------------------------------------------------------------------------------
# the isosurface separates the obstacles from free space
# ----------------------------------------------------------------------------------------------
def _boundary_edges(occ: np.ndarray) -> set[tuple[int, int, int, int]]:
    """Every pair of face-neighbouring voxels of which one is occupied, the grid padded with free voxels:
    (axis, layer, row, col) of the lower voxel of the pair, in padded indices."""
    pad = np.pad(occ, 1)
    out = set()
    for axis in range(3):
        lo = [slice(None)] * 3
        hi = [slice(None)] * 3
        lo[axis] = slice(0, -1)
        hi[axis] = slice(1, None)
        diff = pad[tuple(lo)] != pad[tuple(hi)]
        out |= {(axis, *map(int, ix)) for ix in np.argwhere(diff)}
    return out


def _vertex_edges(verts: np.ndarray, occ: np.ndarray, grid: Grid) -> set[tuple[int, int, int, int]]:
    """The lattice edge (between two voxel centres) each vertex lies on, as in _boundary_edges. Lewiner's
    marching cubes also puts a vertex at the centre of a lattice cube whose eight voxels are mixed (to
    resolve an ambiguous cube): such a vertex is checked to be one and left out."""
    pad = np.pad(occ, 1)
    u = (verts - np.asarray(grid.origin)) / grid.resolution - 0.5 + 1.0  # padded voxel-centre coordinates, x y z
    u = u[:, ::-1]  # layer, row, col
    out = set()
    for q in u:
        frac = np.abs(q - np.round(q))
        halves = np.abs(frac - 0.5) < 1e-5  # float32 vertices
        assert (halves | (frac < 1e-5)).all()  # on the lattice of voxel centres and their midpoints
        if halves.sum() == 1:  # half-way between two centres along one axis: a lattice edge
            axis = int(np.argmax(halves))
            lower = np.round(q).astype(int)
            lower[axis] = int(math.floor(q[axis]))
            out.add((axis, *map(int, lower)))
        else:
            assert halves.all()  # a cube's centre: its eight voxels are occupied and free
            lo = np.floor(q).astype(int)
            cube = pad[lo[0]:lo[0] + 2, lo[1]:lo[1] + 2, lo[2]:lo[2] + 2]
            assert cube.any() and not cube.all()
    return out


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 5), st.integers(1, 5), st.integers(1, 5), st.integers(0, 2**32 - 1),
       st.floats(0.1, 3.0), st.floats(-10, 10), st.floats(-10, 10), st.floats(-10, 10))
def test_isosurface_lies_on_the_faces_between_occupied_and_free(L, R, C, seed, h, x0, y0, z0) -> None:
    occ = np.random.default_rng(seed).random((L, R, C)) < 0.4
    gm = GridMap(Grid((L, R, C), h, origin=(x0, y0, z0)), occ)
    verts, faces, k = plot.voxel_isosurface(gm)
    assert k == 1
    if not occ.any():
        assert len(verts) == 0 and len(faces) == 0
        return
    b = gm.grid.bounds
    assert (verts >= np.asarray(b[:3]) - 1e-9).all() and (verts <= np.asarray(b[3:]) + 1e-9).all()
    # every vertex on an edge between an occupied and a free voxel, and every such edge has its vertex
    assert _vertex_edges(verts, occ, gm.grid) == _boundary_edges(occ)
    assert faces.min() >= 0 and faces.max() < len(verts)


def test_a_thin_wall_survives_downsampling() -> None:
    occ = np.zeros((40, 40, 40), bool)
    occ[:, 17, :] = True  # one voxel thick, at y in [8.5, 9)
    gm = GridMap(Grid((40, 40, 40), 0.5), occ)
    verts, faces, k = plot.voxel_isosurface(gm, max_voxels=10)
    assert k == 4 and len(faces) > 0
    # the block holding the wall spans rows 16..19: y in [8, 10)
    assert verts[:, 1].min() == pytest.approx(8.0) and verts[:, 1].max() == pytest.approx(10.0)
    assert (verts >= 0).all() and (verts <= 20.0).all()
    art = plot.plot_voxel_scene(gm, max_voxels=10)
    assert art.extra["stride"] == 4 and "blocks of 4^3" in art.ax.get_title()


def test_distance_level_is_a_sphere_around_one_voxel() -> None:
    occ = np.zeros((21, 21, 21), bool)
    occ[10, 10, 10] = True
    gm = GridMap(Grid((21, 21, 21), 0.25, origin=(1.0, 2.0, 3.0)), occ)
    centre = gm.grid.cell_to_world([[10, 10, 10]])[0]
    verts, faces, _ = plot.voxel_isosurface(_dmap(gm), 1.5)
    r = np.linalg.norm(verts - centre, axis=1)
    # linear interpolation between voxel centres: within a voxel's diagonal chord error of the radius
    assert len(faces) > 100 and np.abs(r - 1.5).max() < 0.25 * 0.25
    assert len(plot.voxel_isosurface(_dmap(gm), 100.0)[1]) == 0  # beyond every distance: no surface


def test_scene_without_obstacles_has_no_surface(route: Path) -> None:
    gm = GridMap(Grid((10, 12, 16), 0.5, origin=(-1.0, 2.0, 3.0)), np.zeros((10, 12, 16), bool))
    art = plot.plot_voxel_scene(gm, paths=route)
    assert art.surface is None and len(art.ax.lines) == 1


# ----------------------------------------------------------------------------------------------
# the surface of a slice, bad input
# ----------------------------------------------------------------------------------------------
def test_voxel_surface_is_the_layers_potential(world: GridMap, route: Path) -> None:
    f = _field(world, (5.25, 6.25, 6.75))
    art = plot.plot_voxel_surface(f, z=7.4, path=route, max_cells=100)
    assert art.extra["slice"] == ("z", 8, 7.25)
    assert art.ax.name == "3d" and len(art.paths) == 1
    assert np.array_equal(art.paths[0].get_data_3d()[0], route.points[:, 0])


def test_bad_input_names_the_problem(world: GridMap, route: Path) -> None:
    flat = GridMap(Grid((4, 4), 1.0), np.zeros((4, 4), bool))
    with pytest.raises(ParameterError, match=r"voxel grids \(3-D\); this map is 2-D"):
        plot.plot_voxel_slices(flat)
    with pytest.raises(ParameterError, match="needs a voxel GridMap"):
        plot.plot_voxel_scene(np.zeros((3, 3, 3)))  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"lies outside the grid, which covers x in \[-1, 7\)"):
        plot.plot_voxel_slices(world, at=(9.0, 3.0, 4.0))
    with pytest.raises(ParameterError, match="the height 20 lies outside"):
        plot.plot_voxel_slices(world, zs=[20.0])
    with pytest.raises(ParameterError, match="zs must be between 1 and the grid's 10 layers"):
        plot.plot_voxel_slices(world, zs=11)
    with pytest.raises(ParameterError, match=r"shape \(2, 2\); a voxel grid's paths"):
        plot.plot_voxel_slices(world, paths=Path(np.zeros((2, 2)), "reached", "demo"))
    with pytest.raises(ParameterError, match="start must be a point"):
        plot.plot_voxel_scene(world, start=(1.0, 2.0))
    with pytest.raises(ParameterError, match="needs a 3-D axes"):
        plot.plot_voxel_scene(world, ax=plt.figure().add_subplot())
    with pytest.raises(ParameterError, match="a distance level needs a DistanceMap"):
        plot.plot_voxel_scene(world, level=1.0)
    with pytest.raises(ParameterError, match="max_voxels must be"):
        plot.voxel_isosurface(world, max_voxels=1)
    with pytest.raises(ParameterError, match="unknown figure format"):
        plot.save_voxel_figure("out.gif", world)
    bad = DistanceMap(world, 26, "euclidean", None, np.zeros((2, 2, 2)), None, None, None, None)
    with pytest.raises(GridfieldError, match="distance has shape"):
        plot.plot_voxel_slices(bad)


# ----------------------------------------------------------------------------------------------
# the command line
# ----------------------------------------------------------------------------------------------
def test_brushfire_and_plan_figures_of_a_voxel_map(world: GridMap, route: Path, tmp_path) -> None:
    from gridfield.cli import brushfire as cli_brushfire

    out = tmp_path / "dist.png"
    cli_brushfire._save_plot(_dmap(world), str(out))  # what brushfire --plot writes
    plan_png = plot.save_plan_figure(tmp_path / "plan.png", world, route)  # what plan --plot writes
    for f in (out, plan_png):
        assert f.read_bytes()[:8] == PNG
        with Image.open(f) as im:
            assert im.size[0] > 2 * im.size[1]  # the slices and the 3-D scene


@pytest.mark.parametrize("command", ["brushfire", "field", "plan"])
def test_cli_writes_a_png_for_a_voxel_map(command: str, world: GridMap, tmp_path, monkeypatch) -> None:
    """``gridfield brushfire|field|plan MAP --plot F`` on a voxel map: the slices and the 3-D scene in one
    PNG (``field --surface F`` too). The map comes through the commands' reader, ``gridfield.io.read``,
    replaced here by one returning the voxel map (the voxel readers are tested with the io)."""
    import gridfield.io
    from gridfield.cli import main

    monkeypatch.setattr(gridfield.io, "read", lambda *a, **k: world)
    start, goal = ["-0.25", "2.75", "3.25"], ["5.25", "6.25", "6.75"]
    argv = {"brushfire": ["brushfire", "floors.npy"],
            "field": ["field", "floors.npy", "--goal", *goal, "--surface", str(tmp_path / "surface.png")],
            "plan": ["plan", "floors.npy", "--start", *start, "--goal", *goal]}[command]
    out = tmp_path / f"{command}.png"
    assert main([*argv, "--plot", str(out)]) == 0
    assert out.read_bytes()[:8] == PNG
    with Image.open(out) as im:
        assert im.size[0] > 2 * im.size[1]  # the slices and the 3-D scene
    if command == "field":
        assert (tmp_path / "surface.png").read_bytes()[:8] == PNG


def test_cli_plots_a_bundled_voxel_map_read_from_its_file(tmp_path) -> None:
    """The same through the voxel reader: a Moving AI 3-D map of the test data and its first scenario."""
    from pathlib import Path as FsPath

    from gridfield.cli import main

    data = FsPath(__file__).parent / "data" / "maps" / "voxel"
    for argv, out in [(["brushfire", str(data / "building.3dmap.gz")], tmp_path / "b.png"),
                      (["plan", str(data / "building.3dmap.gz"), "--scenario",
                        str(data / "building.3dmap.3dscen.gz"), "--index", "0"], tmp_path / "p.png")]:
        assert main([*argv, "--plot", str(out)]) == 0
        with Image.open(out) as im:
            assert im.size[0] > 2 * im.size[1]
