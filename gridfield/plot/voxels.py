"""Figures of voxel grids (3-D): orthogonal slices, a grid of x-y slices, a 3-D scene of isosurfaces.

Like every figure of :mod:`gridfield.plot`, these draw what they are given: a voxel
:class:`~gridfield.core.grid.GridMap` (its occupancy), a :class:`~gridfield.distance.brushfire.DistanceMap` (its distance) or a
:class:`~gridfield.fields.potential.Field` (its potential), paths of ``(n, 3)`` points.

- :func:`plot_voxel_slices` draws slices of the array as images in world units, the 2-D figures'
  conventions on each plane (``origin="lower"``, extent from the grid): an x-y slice at a height z,
  an x-z slice at a y and a y-z slice at an x (through the path's start by default, else through the
  goal, else through the middle of the grid), or with ``zs`` a grid of x-y slices at several
  heights. Obstacles are drawn over the values, paths as their projections onto each plane.
- :func:`plot_voxel_scene` draws a 3-D view (:mod:`mpl_toolkits.mplot3d`) of the obstacles'
  isosurface (or of a distance level's), with paths as 3-D lines and start and goal markers.
- :func:`plot_voxel_surface` draws one x-y slice of a potential as a surface, as
  :func:`~gridfield.plot.plot_surface` draws a 2-D potential.
- :func:`save_voxel_figure` writes what ``gridfield brushfire|field|plan --plot F`` write for a voxel
  map: one figure, the three slices on the left and the 3-D scene on the right.

**The isosurface is a drawing step.** :func:`skimage.measure.marching_cubes` turns the given array
into triangles, the way a contour plot turns a 2-D array into lines: the occupancy padded by one
free voxel on every side (so that the surface closes on the grid's faces) at level 0.5, which puts
the surface half-way between the centres of an occupied and a free voxel (on the voxels' shared
face, at a face of the grid for an obstacle touching it), or the distance at a level ``d`` (the
surface at distance ``d`` from the obstacles). The voxel spacing is the resolution and the vertices
are shifted by the origin, so that they are world coordinates ``(x, y, z)``. A wall border's shell
is not drawn (it would hide everything inside). **Large grids** are downsampled first, so that the
array handed to marching cubes has at most ``max_voxels`` voxels along each axis: blocks of ``k``
voxels per axis are reduced by a max-pool of the occupancy (a block holding any obstacle voxel is an
obstacle: thin walls survive, and gaps narrower than a block close in the picture) or a min-pool of
the distance; the vertices are clipped to the grid's bounds. With the default (64) a 256^3 grid is
drawn from 64^3 blocks of 4^3 voxels in a few seconds.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import GridfieldError, ParameterError
from ..core.grid import Grid, GridMap
from ..core.path import Path
from ..core.results import DistanceMap, Field
from ._layers import (
    FREE_COLOR,
    OCCUPIED_COLOR,
    PATH_COLORS,
    Artists,
    PathLike,
    _check_figure_file,
    _legend,
    _path_label,
    _pool,
    _save,
    title_of,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure

__all__ = ["plot_voxel_scene", "plot_voxel_slices", "plot_voxel_surface", "save_voxel_figure", "voxel_isosurface"]

#: The planes :func:`plot_voxel_slices` draws: name, the world axes across and up the image, and the
#: axis the slice is taken at (0 = x, 1 = y, 2 = z).
PLANES = (("x-y", 0, 1, 2), ("x-z", 0, 2, 1), ("y-z", 1, 2, 0))
#: The colour of the obstacles' isosurface.
SURFACE_COLOR = "0.55"
_AXES = "xyz"

Target = GridMap | DistanceMap | Field


# ----------------------------------------------------------------------------------------------
# inputs
# ----------------------------------------------------------------------------------------------
def _voxel_map(target: object, what: str) -> GridMap:
    """The voxel GridMap of a GridMap, DistanceMap or Field, or a ParameterError naming the problem."""
    gm = target if isinstance(target, GridMap) else getattr(target, "map", None)
    if not isinstance(target, GridMap | DistanceMap | Field) or not isinstance(gm, GridMap):
        raise ParameterError(f"{what} needs a voxel GridMap, DistanceMap or Field, got {type(target).__name__}")
    if gm.grid.ndim != 3:
        raise ParameterError(f"{what} draws voxel grids (3-D); this map is {gm.grid.ndim}-D "
                             "(draw it with plot_map, plot_brushfire or plot_potential)")
    return gm


def _point3(p: ArrayLike | None, name: str) -> NDArray[np.float64] | None:
    if p is None:
        return None
    try:
        a = np.asarray(p, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a point (x, y, z) of three finite numbers, got {p!r}") from None
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ParameterError(f"{name} must be a point (x, y, z) of three finite numbers, got {p!r}")
    return a


def _paths3(paths: Path | Iterable[Path]) -> list[Path]:
    out = [paths] if isinstance(paths, Path) else list(paths)
    for i, p in enumerate(out):
        if not isinstance(p, Path):
            raise ParameterError(f"paths must be gridfield Path objects, got {type(p).__name__} at position {i}")
        if p.points.shape[1] != 3:
            raise ParameterError(f"path {i} ({p.planner}) has points of shape {p.points.shape}; a voxel grid's "
                                 "paths hold (x, y, z) points, shape (n, 3)")
    return out


def _endpoints(target: object, paths: Sequence[Path], start: ArrayLike | None, goal: ArrayLike | None
               ) -> tuple[NDArray[np.float64] | None, NDArray[np.float64] | None]:
    """The start and goal to mark: given, else the first path's first point and its recorded goal (or
    the field's goal, or the end of a path that reached it)."""
    s, g = _point3(start, "start"), _point3(goal, "goal")
    first = next((p for p in paths if len(p.points)), None)
    if s is None and first is not None:
        s = first.points[0].copy()
    if g is None and isinstance(target, Field):
        g = _point3(target.goal, "the field's goal")
    if g is None and first is not None:
        rec = first.extra.get("goal") if isinstance(first.extra, Mapping) else None
        if rec is not None:
            g = _point3(rec, "path.extra['goal']")
        elif first.reached:
            g = first.points[-1].copy()
    return s, g


def _values(target: Target, gm: GridMap, cap: float | None, clim: tuple[float, float] | None
            ) -> tuple[NDArray[np.float64] | None, NDArray[np.bool_], tuple[float, float], str]:
    """What the slices colour: the distance or the potential (``None`` for a GridMap: its occupancy),
    where it is shown (finite, free), its colour range and the colour bar's label."""
    occ = np.asarray(gm.occupied, dtype=bool)
    if isinstance(target, GridMap):
        return None, ~occ, (0.0, 1.0), ""
    if isinstance(target, DistanceMap):
        arr, label = np.asarray(target.distance, dtype=float), f"distance ({target.metric})"
    else:
        arr, label = np.asarray(target.potential, dtype=float), "potential U"
    if arr.shape != gm.grid.shape:
        what = "distance" if isinstance(target, DistanceMap) else "potential"
        raise GridfieldError(f"{what} has shape {arr.shape}, but the grid has shape {gm.grid.shape}")
    valid = np.isfinite(arr) & ~occ
    if clim is not None:
        lo, hi = (float(v) for v in clim)
        if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
            raise ParameterError(f"clim must be two finite numbers (low, high) with high > low, got {clim!r}")
        return arr, valid, (lo, hi), label
    vals = arr[valid]
    if isinstance(target, DistanceMap):
        hi = float(vals.max()) if vals.size else 1.0
        return arr, valid, (0.0, hi if hi > 0 else 1.0), label
    if not vals.size:
        raise GridfieldError("the potential has no finite value on a free voxel; nothing to plot")
    lo = float(vals.min())
    hi = float(np.percentile(vals, 95.0)) if cap is None else float(cap)
    if not math.isfinite(hi):
        raise ParameterError(f"cap must be a finite potential value, got {cap!r}")
    if cap is not None and hi > lo:
        label += f" (clipped at {hi:.4g})"
    return arr, valid, (lo, hi if hi > lo else lo + 1.0), label


def _cell_at(grid: Grid, point: NDArray[np.float64]) -> tuple[int, int, int]:
    """The voxel ``(layer, row, col)`` holding ``point``, or a ParameterError for a point outside the grid."""
    cell = grid.cell_of(*point)
    if cell is None:
        b = grid.bounds
        spans = ", ".join(f"{a} in [{b[i]:g}, {b[i + 3]:g})" for i, a in enumerate(_AXES))
        raise ParameterError(f"the slices' point ({', '.join(f'{v:g}' for v in point)}) lies outside the grid, "
                             f"which covers {spans}")
    return int(cell[0]), int(cell[1]), int(cell[2])


def _layers_of(grid: Grid, zs: int | Sequence[float]) -> list[int]:
    """The layers of a slice grid: ``n`` evenly spaced ones, or those holding the heights ``zs``."""
    if isinstance(zs, bool) or not isinstance(zs, int | np.integer | Sequence | np.ndarray):
        raise ParameterError(f"zs must be a number of slices or a sequence of heights z, got {zs!r}")
    if isinstance(zs, int | np.integer):
        n = int(zs)
        if not 1 <= n <= grid.layers:
            raise ParameterError(f"zs must be between 1 and the grid's {grid.layers} layers, got {n}")
        return [int(k) for k in (np.arange(n) + 0.5) * grid.layers // n]  # the middle layers of n equal stacks
    z = np.asarray(zs, dtype=float).reshape(-1)
    if z.size == 0 or not np.all(np.isfinite(z)):
        raise ParameterError(f"zs must hold finite heights z, got {zs!r}")
    k = np.floor((z - grid.origin[2]) / grid.resolution).astype(np.int64)
    bad = (k < 0) | (k >= grid.layers)
    if bad.any():
        b = grid.bounds
        raise ParameterError(f"zs: the height {z[bad][0]:g} lies outside the grid, which covers z in "
                             f"[{b[2]:g}, {b[5]:g})")
    return [int(v) for v in k]


# ----------------------------------------------------------------------------------------------
# slices
# ----------------------------------------------------------------------------------------------
def _plane_extent(grid: Grid, across: int, up: int) -> tuple[float, float, float, float]:
    b = grid.bounds
    return (b[across], b[across + 3], b[up], b[up + 3])


def _take(arr: NDArray[Any], cut: int, index: int) -> NDArray[Any]:
    """The 2-D slice of a ``[z, y, x]`` array at ``index`` along world axis ``cut``, rows along the
    plane's upward axis: x-y ``arr[k]``, x-z ``arr[:, r, :]``, y-z ``arr[:, :, c]``."""
    return arr[(slice(None),) * (2 - cut) + (index,)]


def _draw_slice(ax: Axes, art: Artists, gm: GridMap, values: NDArray[np.float64] | None, valid: NDArray[np.bool_],
                plane: tuple[str, int, int, int], index: int, clim: tuple[float, float], cmap: str) -> None:
    """One slice as an image (the values masked off obstacles and non-finite cells, or the occupancy) and
    the obstacles over it."""
    from matplotlib.colors import ListedColormap

    _, across, up, cut = plane
    grid = gm.grid
    ext = _plane_extent(grid, across, up)
    occ = _take(np.asarray(gm.occupied, dtype=bool), cut, index)
    if values is None:
        art.image = ax.imshow(occ.astype(np.uint8), origin="lower", extent=ext, interpolation="nearest",
                              cmap=ListedColormap([FREE_COLOR, OCCUPIED_COLOR]), vmin=-0.5, vmax=1.5, zorder=0)
        art.obstacles.append(art.image)
    else:
        shown = np.ma.masked_array(_take(values, cut, index), mask=~_take(valid, cut, index))
        art.image = ax.imshow(shown, origin="lower", extent=ext, interpolation="nearest", cmap=cmap,
                              vmin=clim[0], vmax=clim[1], zorder=0)
        if occ.any():
            art.obstacles.append(ax.imshow(np.ma.masked_array(np.ones(occ.shape), mask=~occ), origin="lower",
                                           extent=ext, interpolation="nearest", cmap=ListedColormap([OCCUPIED_COLOR]),
                                           vmin=0.5, vmax=1.5, zorder=1))
    art.mappable = art.image


def _draw_projections(ax: Axes, art: Artists, paths: Sequence[Path], plane: tuple[str, int, int, int],
                      lo: float, hi: float, start: NDArray[np.float64] | None, goal: NDArray[np.float64] | None
                      ) -> None:
    """Each path projected onto the plane (``ax.lines`` holds exactly these), its points inside the
    slice (``lo <= coordinate < hi`` along the cut axis) as dots, start and goal markers."""
    _, across, up, cut = plane
    for i, p in enumerate(paths):
        color = PATH_COLORS[i % len(PATH_COLORS)]
        (line,) = ax.plot(p.points[:, across], p.points[:, up], color=color, linewidth=1.8, zorder=5,
                          label=_path_label(p))
        art.paths.append(line)
        inside = (p.points[:, cut] >= lo) & (p.points[:, cut] < hi)
        art.extra.setdefault("in_slice", []).append(
            ax.scatter(p.points[inside, across], p.points[inside, up], s=14, color=color, edgecolor="white",
                       linewidth=0.5, zorder=5.5))
    if start is not None:
        art.markers["start"] = ax.scatter([start[across]], [start[up]], marker="o", s=50, color="tab:green",
                                          edgecolor="black", zorder=6, label="start")
    if goal is not None:
        art.markers["goal"] = ax.scatter([goal[across]], [goal[up]], marker="*", s=130, color="gold",
                                         edgecolor="black", zorder=6, label="goal")


def _frame(ax: Axes, grid: Grid, across: int, up: int, title: str) -> None:
    x0, x1, y0, y1 = _plane_extent(grid, across, up)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel(_AXES[across])
    ax.set_ylabel(_AXES[up])
    ax.set_title(title, fontsize=9)


def _guides(ax: Axes, art: Artists, grid: Grid, across: int, up: int, centre: NDArray[np.float64],
            color: str) -> None:
    """Dashed lines where the other two slices cut this one (a line collection: ``ax.lines`` stays the paths')."""
    from matplotlib.collections import LineCollection

    x0, x1, y0, y1 = _plane_extent(grid, across, up)
    a, b = float(centre[across]), float(centre[up])
    art.extra["guides"] = ax.add_collection(LineCollection([[(a, y0), (a, y1)], [(x0, b), (x1, b)]], colors=color,
                                                           linewidths=0.8, linestyles="--", alpha=0.8, zorder=4))


def _new_figure(fig: Figure | SubFigure | None, size: tuple[float, float]) -> Figure | SubFigure:
    if fig is not None:
        return fig
    import matplotlib.pyplot as plt

    return plt.figure(figsize=size, layout="constrained")


def plot_voxel_slices(
    target: Target,
    fig: Figure | SubFigure | None = None,
    *,
    at: ArrayLike | None = None,
    zs: int | Sequence[float] | None = None,
    ncols: int | None = None,
    paths: Path | Iterable[Path] = (),
    start: ArrayLike | None = None,
    goal: ArrayLike | None = None,
    cap: float | None = None,
    clim: tuple[float, float] | None = None,
    cmap: str = "viridis",
    colorbar: bool = True,
    legend: bool = True,
    title: str | None = None,
) -> list[Artists]:
    """Orthogonal slices of a voxel grid's distance, potential or occupancy, or a grid of x-y slices.

    Each slice is an image in world units (``origin="lower"``, the plane's extent from the grid), the
    obstacles drawn over the values in dark grey, each path as its projection onto the plane (its points
    inside the slice's voxels as dots), the start and goal marked.

    Parameters
    ----------
    target : GridMap, DistanceMap or Field
        On a voxel grid. A DistanceMap's ``distance`` or a Field's ``potential`` is coloured (masked on
        obstacles and where it is not finite); a GridMap's occupancy is drawn alone.
    fig : Figure or SubFigure, optional
        Drawn into (its panels are added); default: a new figure.
    at : (x, y, z), optional
        The point the three orthogonal slices pass through (an x-y slice at its z, an x-z slice at its y,
        a y-z slice at its x; each through the voxels holding it). Default: the start (given, or the
        first path's first point), else the goal, else the centre of the grid. Dashed lines on each
        slice show where the other two cut it.
    zs : int or sequence of float, optional
        A slice grid instead: x-y slices at ``zs`` evenly spaced layers (the middle layers of ``zs``
        equal stacks of layers), or at the layers holding the heights ``zs`` (world units), in a grid
        of panels.
    ncols : int, optional
        Panels per row of a slice grid (default: about the square root of their number).
    paths : Path or iterable of Path
        Paths of ``(n, 3)`` points, drawn projected onto each plane (``ax.lines`` holds exactly these).
    start, goal : (x, y, z), optional
        Marked points; default: the first path's first point, and its recorded goal
        (``path.extra["goal"]``), the field's goal, or the end of a path that reached it.
    cap : float, optional
        A potential's colour range ends at ``cap`` (default: the 95th percentile of its finite values on
        free voxels; higher values are drawn in the top colour).
    clim : (float, float), optional
        The colour range, overriding the default (distance: 0 to the largest finite distance).
    cmap : str
    colorbar : bool
        One colour bar for all panels (not for a GridMap).
    legend : bool
        A legend in the first panel (when paths or endpoints are drawn).
    title : str, optional
        The figure's title; default: what is drawn and the map's name.

    Returns
    -------
    list of Artists
        One per panel: the x-y, x-z and y-z slices, or the slice grid's panels from the lowest z.
        ``image`` holds the slice (``image.get_array()`` is ``distance[k]``, ``distance[:, r, :]``,
        ``distance[:, :, c]``, masked), ``obstacles``, ``paths``, ``markers`` (``start``, ``goal``),
        ``extra["slice"]`` (``(axis, index, coordinate)``: ``("z", k, z)``), ``extra["in_slice"]`` (per
        path, the dots of its points inside the slice), ``extra["guides"]``, ``colorbar`` (first panel).

    Raises
    ------
    ParameterError
        A 2-D map, a point or height outside the grid, a path whose points are not ``(n, 3)``.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy import ndimage
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.core.results import DistanceMap
    >>> occ = np.zeros((4, 6, 8), bool); occ[:, 2:4, 3] = True
    >>> d = ndimage.distance_transform_edt(~occ) * 0.5
    >>> dm = DistanceMap(GridMap(Grid((4, 6, 8), 0.5), occ), 8, "euclidean", None, d, None, None, None, None)
    >>> arts = plot_voxel_slices(dm, at=(1.1, 1.6, 0.3))
    >>> [a.extra["slice"] for a in arts]
    [('z', 0, 0.25), ('y', 3, 1.75), ('x', 2, 1.25)]
    >>> bool((arts[1].image.get_array().data == d[:, 3, :]).all()), arts[0].image.get_extent()
    (True, [0.0, 4.0, 0.0, 3.0])
    >>> len(plot_voxel_slices(dm, zs=[0.2, 1.9])), len(plot_voxel_slices(dm, zs=3))
    (2, 3)
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    gm = _voxel_map(target, "plot_voxel_slices")
    grid = gm.grid
    plist = _paths3(paths)
    s, g = _endpoints(target, plist, start, goal)
    values, valid, lims, label = _values(target, gm, cap, clim)
    centre = _point3(at, "at")
    if centre is None:
        inside = [q for q in (s, g) if q is not None and grid.cell_of(*q) is not None]
        centre = inside[0] if inside else np.array([(grid.bounds[a] + grid.bounds[a + 3]) / 2 for a in range(3)])
    if zs is None:
        cell = _cell_at(grid, centre)
        index = {0: cell[2], 1: cell[1], 2: cell[0]}  # along x, y, z
        planes: list[tuple[tuple[str, int, int, int], int]] = [(pl, index[pl[3]]) for pl in PLANES]
        nrows, ncol = 1, 3
    else:
        if ncols is not None and (isinstance(ncols, bool) or not isinstance(ncols, int | np.integer) or ncols < 1):
            raise ParameterError(f"ncols must be a positive number of panels, got {ncols!r}")
        layers = _layers_of(grid, zs)
        ncol = int(ncols) if ncols is not None else math.ceil(math.sqrt(len(layers)))
        ncol = min(ncol, len(layers))
        nrows = math.ceil(len(layers) / ncol)
        planes = [(PLANES[0], k) for k in layers]
    spans = [grid.bounds[a + 3] - grid.bounds[a] for a in range(3)]
    width = 3.6 * ncol + (1.0 if colorbar and values is not None else 0.0)
    panel_h = 3.6 * max(spans[1] / max(spans[0], 1e-300) if zs is not None else
                        max(spans[2] / max(spans[0], 1e-300), spans[2] / max(spans[1], 1e-300),
                            spans[1] / max(spans[0], 1e-300)), 0.35)
    fig = _new_figure(fig, (width, min(4.5 * nrows, max(2.6, panel_h * nrows + 0.9))))
    arts: list[Artists] = []
    for i, (plane, k) in enumerate(planes):
        name, across, up, cut = plane
        ax = fig.add_subplot(nrows, ncol, i + 1)
        art = Artists(ax)
        _draw_slice(ax, art, gm, values, valid, plane, k, lims, cmap)
        coord = float(grid.cell_centers()[cut][k])
        art.extra["slice"] = (_AXES[cut], k, coord)
        if zs is None:
            _guides(ax, art, grid, across, up, grid.cell_to_world([[index[2], index[1], index[0]]])[0],
                    "0.55" if values is None else "white")
        lo = grid.origin[cut] + k * grid.resolution
        _draw_projections(ax, art, plist, plane, lo, lo + grid.resolution, s, g)
        _frame(ax, grid, across, up, f"{name} at {_AXES[cut]} = {coord:.4g} ({('column', 'row', 'layer')[cut]} {k})")
        arts.append(art)
    if colorbar and values is not None:
        arts[0].colorbar = fig.colorbar(arts[0].image, ax=[a.ax for a in arts], shrink=0.85, label=label)
    if legend and arts:
        _legend(arts[0].ax, arts[0], fontsize=7)
    what = "occupancy" if values is None else label.split(" (")[0]
    name = title_of(gm)
    if title is None:
        title = f"{what}{f' of {name}' if name else ''}: {'x-y slices' if zs is not None else 'orthogonal slices'}"
    if title:
        fig.suptitle(title, fontsize=10)
    return arts


# ----------------------------------------------------------------------------------------------
# isosurfaces
# ----------------------------------------------------------------------------------------------
def _triangles(volume: NDArray[np.floating[Any]], level: float, grid: Grid, k: int
               ) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """Marching cubes on ``volume`` (``[z, y, x]`` of blocks of ``k`` voxels, padded by one block on every
    side) at ``level``: vertices in world ``(x, y, z)`` (clipped to the grid's bounds) and faces."""
    from skimage.measure import marching_cubes

    h = grid.resolution * k
    verts, faces, _, _ = marching_cubes(volume, level=level, spacing=(h, h, h), allow_degenerate=False)
    # padded index i is block i - 1, whose centre is at origin + (i - 1 + 0.5) * h
    xyz = verts[:, ::-1] + np.asarray(grid.origin) - 0.5 * h
    b = grid.bounds
    xyz = np.clip(xyz, b[:3], b[3:])
    return xyz, faces


def voxel_isosurface(target: Target, level: float | None = None, *, max_voxels: int = 64
               ) -> tuple[NDArray[np.float64], NDArray[np.intp], int]:
    """The triangles :func:`plot_voxel_scene` draws: the obstacles' isosurface, or a distance level's.

    A drawing step (see the module's docstring): marching cubes on the occupancy padded by one free
    voxel at level 0.5, or on the distance (padded with a value above every finite one) at ``level``;
    blocks of ``k`` voxels per axis first (occupancy max-pooled, distance min-pooled) so that no axis
    has more than ``max_voxels``.

    Parameters
    ----------
    target : GridMap, DistanceMap or Field
        A voxel grid's map (``level`` needs a DistanceMap, or a Field with its ``distance``).
    level : float, optional
        A distance (world units); default: the obstacles' surface.
    max_voxels : int
        At most this many voxels (blocks) along each axis.

    Returns
    -------
    vertices : ndarray, shape (n, 3)
        World coordinates ``(x, y, z)``, within the grid's bounds.
    faces : ndarray of int, shape (m, 3)
        Triangles, indices into ``vertices`` (none when there is no surface: no obstacle, or a level
        outside the distances).
    k : int
        The block size (1: every voxel).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((4, 4, 4), bool); occ[1:3, 1:3, 1:3] = True
    >>> v, f, k = voxel_isosurface(GridMap(Grid((4, 4, 4), 0.5, origin=(1.0, 0.0, 0.0)), occ))
    >>> v.min(axis=0).tolist(), v.max(axis=0).tolist(), k
    ([1.5, 0.5, 0.5], [2.5, 1.5, 1.5], 1)
    """
    gm = _voxel_map(target, "voxel_isosurface")
    if isinstance(max_voxels, bool) or not isinstance(max_voxels, int | np.integer) or max_voxels < 2:
        raise ParameterError(f"max_voxels must be an integer of at least 2, got {max_voxels!r}")
    grid = gm.grid
    k = max(1, math.ceil(max(grid.shape) / int(max_voxels)))
    if level is None:
        occ = _pool(np.asarray(gm.occupied, dtype=bool), k, False, np.any)
        if not occ.any():
            return np.empty((0, 3)), np.empty((0, 3), np.intp), k
        volume = np.pad(occ.astype(np.float32), 1, constant_values=0.0)
        return (*_triangles(volume, 0.5, grid, k), k)
    dm = target if isinstance(target, DistanceMap) else getattr(target, "distance", None)
    if not isinstance(dm, DistanceMap):
        raise ParameterError("a distance level needs a DistanceMap (or a Field that holds its distance map)")
    lv = float(level)
    if not (math.isfinite(lv) and lv > 0):
        raise ParameterError(f"level must be a positive finite distance, got {level!r}")
    d = np.asarray(dm.distance, dtype=float)
    finite = np.isfinite(d)
    top = float(d[finite].max()) if finite.any() else 0.0
    if lv >= top:
        return np.empty((0, 3)), np.empty((0, 3), np.intp), k
    high = 2.0 * max(top, lv) + 1.0  # above every finite distance: the surface closes inside the grid
    vol = _pool(np.where(finite, d, high), k, high, np.min)
    volume = np.pad(vol.astype(np.float64), 1, constant_values=high)
    return (*_triangles(volume, lv, grid, k), k)


def _shaded(verts: NDArray[np.float64], faces: NDArray[np.intp], color: Any, alpha: float) -> NDArray[np.float64]:
    """Face colours lit by the faces' normals (a light from above and the viewer's side; two-sided)."""
    from matplotlib.colors import to_rgba

    tri = verts[faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    light = np.array([-0.4, -0.6, 0.7])
    light /= np.linalg.norm(light)
    shade = 0.45 + 0.55 * np.abs(n @ light)
    rgba = np.tile(np.asarray(to_rgba(color), dtype=float), (len(faces), 1))
    rgba[:, :3] *= shade[:, None]
    rgba[:, 3] = alpha
    return rgba


def plot_voxel_scene(
    target: Target,
    ax: Axes | None = None,
    *,
    level: float | None = None,
    paths: Path | Iterable[Path] = (),
    start: ArrayLike | None = None,
    goal: ArrayLike | None = None,
    max_voxels: int = 64,
    color: Any = None,
    alpha: float = 0.35,
    view: tuple[float, float] = (28.0, -58.0),
    legend: bool = True,
    title: str | None = None,
) -> Artists:
    """A 3-D view of a voxel grid: the obstacles' isosurface (or a distance level's), paths as 3-D lines.

    The surface is a :class:`~mpl_toolkits.mplot3d.art3d.Poly3DCollection` of the triangles of
    :func:`voxel_isosurface` (marching cubes, a drawing step: see the module's docstring), semi-transparent
    and lit by its faces' normals; paths are drawn over it (``ax.computed_zorder`` is off: surfaces
    below, paths and markers on top), the axes span the grid's bounds with equal scales.

    Parameters
    ----------
    target : GridMap, DistanceMap or Field
        On a voxel grid.
    ax : Axes, optional
        A 3-D axes (``fig.add_subplot(projection="3d")``); default: a new figure.
    level : float, optional
        Draw the surface at this distance from the obstacles (needs a DistanceMap, or a Field with its
        ``distance``) instead of the obstacles' own.
    paths : Path or iterable of Path
        Paths of ``(n, 3)`` points, drawn as 3-D lines (``ax.lines`` holds exactly these).
    start, goal : (x, y, z), optional
        Marked points (default as :func:`plot_voxel_slices`).
    max_voxels : int
        Downsampling: at most this many voxels along each axis go to marching cubes (blocks of ``k``
        voxels, max-pooled: thin walls survive).
    color : colour, optional
        Of the surface (default grey for the obstacles, blue for a distance level).
    alpha : float
        The surface's opacity.
    view : (float, float)
        Elevation and azimuth of the view, in degrees.
    legend : bool
    title : str, optional

    Returns
    -------
    Artists
        ``surface`` (the Poly3DCollection; ``None`` when there is no surface), ``paths`` (Line3D),
        ``markers`` (``start``, ``goal``), ``extra["vertices"]``, ``extra["faces"]``, ``extra["stride"]``
        (the block size ``k``).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((6, 6, 6), bool); occ[2:4, :, 2:4] = True
    >>> gm = GridMap(Grid((6, 6, 6), 1.0), occ)
    >>> p = Path(np.array([[0.5, 0.5, 0.5], [5.5, 5.5, 5.5]]), "reached", "demo")
    >>> art = plot_voxel_scene(gm, paths=p)
    >>> art.ax.name, len(art.ax.lines), art.extra["stride"], len(art.extra["faces"]) > 0
    ('3d', 1, 1, True)
    >>> import matplotlib.pyplot as plt; plt.close(art.figure)
    """
    gm = _voxel_map(target, "plot_voxel_scene")
    a = float(alpha)
    if not 0.0 <= a <= 1.0:
        raise ParameterError(f"alpha must be between 0 and 1, got {alpha!r}")
    grid = gm.grid
    plist = _paths3(paths)
    s, g = _endpoints(target, plist, start, goal)
    verts, faces, k = voxel_isosurface(target, level, max_voxels=max_voxels)
    if ax is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(7.0, 6.0), layout="constrained")
        ax = fig.add_subplot(projection="3d")
    elif getattr(ax, "name", "") != "3d":
        raise ParameterError("plot_voxel_scene needs a 3-D axes: create it with fig.add_subplot(projection='3d')")
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # type: ignore[import-untyped]

    ax3: Any = ax  # a 3-D Axes (matplotlib's stubs know the 2-D one)
    ax3.computed_zorder = False
    art = Artists(ax)
    art.extra.update(vertices=verts, faces=faces, stride=k)
    if len(faces):
        c = color if color is not None else (SURFACE_COLOR if level is None else "tab:blue")
        art.surface = ax3.add_collection3d(Poly3DCollection(verts[faces], facecolors=_shaded(verts, faces, c, a),
                                                            edgecolors="none", zorder=1))
        if art.surface is None:  # matplotlib < 3.10 returns nothing
            art.surface = ax3.collections[-1]
    for i, p in enumerate(plist):
        (line,) = ax3.plot(p.points[:, 0], p.points[:, 1], p.points[:, 2], color=PATH_COLORS[i % len(PATH_COLORS)],
                           linewidth=2.2, zorder=5, label=_path_label(p))
        art.paths.append(line)
    if s is not None:
        art.markers["start"] = ax3.scatter([s[0]], [s[1]], [s[2]], marker="o", s=50, color="tab:green",
                                           edgecolor="black", depthshade=False, zorder=6, label="start")
    if g is not None:
        art.markers["goal"] = ax3.scatter([g[0]], [g[1]], [g[2]], marker="*", s=140, color="gold",
                                          edgecolor="black", depthshade=False, zorder=6, label="goal")
    b = grid.bounds
    ax3.set_xlim(b[0], b[3])
    ax3.set_ylim(b[1], b[4])
    ax3.set_zlim(b[2], b[5])
    ax3.set_box_aspect([b[i + 3] - b[i] for i in range(3)])
    for axis in "xyz":  # a flat grid's short axis keeps its ticks apart
        ax3.locator_params(axis=axis, nbins=max(2, min(6, round(6 * (b["xyz".index(axis) + 3] - b["xyz".index(axis)])
                                                               / max(b[i + 3] - b[i] for i in range(3))))))
    ax3.view_init(elev=view[0], azim=view[1])
    ax3.set_xlabel("x")
    ax3.set_ylabel("y")
    ax3.set_zlabel("z")
    what = "obstacles" if level is None else f"distance {float(level):g} from the obstacles"
    thinned = f", blocks of {k}^3 voxels" if k > 1 else ""
    ax3.set_title(title if title is not None else f"{what}{thinned}", fontsize=9)
    if legend and (art.paths or art.markers):
        art.legend = ax3.legend(fontsize=7, loc="upper left")
    return art


# ----------------------------------------------------------------------------------------------
# a slice of a potential as a surface
# ----------------------------------------------------------------------------------------------
def plot_voxel_surface(
    field: Field,
    ax: Axes | None = None,
    *,
    z: float | None = None,
    path: Path | None = None,
    cap: float | None = None,
    max_cells: int = 90,
    title: str | None = None,
) -> Artists:
    """One x-y slice of a voxel field's potential as a 3-D surface (:func:`~gridfield.plot.plot_surface`).

    Parameters
    ----------
    field : Field
        On a voxel grid.
    ax : Axes, optional
        A 3-D axes; default: a new figure.
    z : float, optional
        The slice's height (the layer holding it); default: the goal's.
    path : Path, optional
        Drawn projected onto the slice (its x and y, at the slice's potential).
    cap, max_cells
        As :func:`~gridfield.plot.plot_surface`.
    title : str, optional

    Returns
    -------
    Artists
        As :func:`~gridfield.plot.plot_surface`; ``extra["slice"]`` is ``("z", layer, z)``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> g = Grid((3, 8, 8), 1.0)
    >>> zs, ys, xs = np.meshgrid(*g.cell_centers()[::-1], indexing="ij")   # [z, y, x] arrays
    >>> u = np.hypot(xs - 4.5, ys - 4.5)
    >>> gx, gy, gz = np.gradient(u, axis=2), np.gradient(u, axis=1), np.zeros_like(u)
    >>> f = Field(GridMap(g, np.zeros((3, 8, 8), bool)), u, gx, gy, (4.5, 4.5, 1.5), {}, grad_z=gz)
    >>> art = plot_voxel_surface(f)
    >>> art.ax.name, art.extra["slice"]
    ('3d', ('z', 1, 1.5))
    >>> import matplotlib.pyplot as plt; plt.close(art.figure)
    """
    from .figures import plot_surface

    gm = _voxel_map(field, "plot_voxel_surface")
    if not isinstance(field, Field):
        raise ParameterError(f"plot_voxel_surface draws a Field's potential, got {type(field).__name__}")
    grid = gm.grid
    height = float(np.asarray(field.goal, dtype=float)[2]) if z is None else float(z)
    k = _layers_of(grid, [height])[0]
    flat = Grid((grid.rows, grid.cols), grid.resolution, origin=grid.origin[:2], border=grid.border)
    sl = Field(GridMap(flat, np.asarray(gm.occupied, dtype=bool)[k], source=gm.source, meta=dict(gm.meta)),
               np.asarray(field.potential)[k], np.asarray(field.grad_x)[k], np.asarray(field.grad_y)[k],
               (float(field.goal[0]), float(field.goal[1])), dict(field.params))
    flat_path = None
    if path is not None:
        flat_path = Path(_paths3(path)[0].points[:, :2], path.status, path.planner)
    zc = float(grid.cell_centers()[2][k])
    art = plot_surface(sl, ax, cap=cap, max_cells=max_cells, path=flat_path,
                       title=title if title is not None else f"potential at z = {zc:.4g} (layer {k})")
    art.extra["slice"] = ("z", k, zc)
    return art


# ----------------------------------------------------------------------------------------------
# the command line's figure
# ----------------------------------------------------------------------------------------------
def save_voxel_figure(
    file: PathLike,
    target: Target,
    *,
    paths: Path | Iterable[Path] = (),
    start: ArrayLike | None = None,
    goal: ArrayLike | None = None,
    title: str | None = None,
    max_voxels: int = 64,
    dpi: int = 110,
) -> FsPath:
    """Write the figure ``gridfield brushfire|field|plan --plot F`` write for a voxel map: one file, the
    three orthogonal slices (:func:`plot_voxel_slices`, through the start, else the goal, else the middle) on the left
    and the 3-D scene of the obstacles with the paths (:func:`plot_voxel_scene`) on the right.

    Parameters
    ----------
    file : path
        The format follows the suffix (``.png``, ``.pdf``, ``.svg``, ``.jpg``); the folder must exist.
    target : GridMap, DistanceMap or Field
        On a voxel grid: the slices show its occupancy, distance or potential.
    paths, start, goal
        As :func:`plot_voxel_slices`.
    title : str, optional
        The figure's title.
    max_voxels : int
        The scene's downsampling (:func:`plot_voxel_scene`).
    dpi : int
        Resolution of raster formats.

    Returns
    -------
    pathlib.Path
        The file written.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((4, 5, 6), bool); occ[:2, 2, :] = True
    >>> with tempfile.TemporaryDirectory() as d:
    ...     out = save_voxel_figure(os.path.join(d, "voxels.png"), GridMap(Grid((4, 5, 6), 1.0), occ), dpi=30)
    ...     out.name, out.stat().st_size > 0
    ('voxels.png', True)
    """
    import matplotlib.pyplot as plt

    p = _check_figure_file(file)
    _voxel_map(target, "save_voxel_figure")
    fig = plt.figure(figsize=(16.0, 5.0), layout="constrained")
    try:
        subs: Any = fig.subfigures(1, 2, width_ratios=(2.9, 1.3))
        left, right = subs[0], subs[1]
        plot_voxel_slices(target, left, paths=paths, start=start, goal=goal, title="")
        scene = plot_voxel_scene(target, right.add_subplot(projection="3d"), paths=paths, start=start, goal=goal,
                                 max_voxels=max_voxels, legend=False)
        b = scene.ax.get_xlim3d(), scene.ax.get_ylim3d(), scene.ax.get_zlim3d()
        scene.ax.set_box_aspect([hi - lo for lo, hi in b], zoom=0.85)  # room for the z label
        if title:
            import textwrap

            fig.suptitle("\n".join(textwrap.wrap(title, 150)), fontsize=11)
    except BaseException:
        plt.close(fig)
        raise
    _save(fig, p, dpi)
    return p
