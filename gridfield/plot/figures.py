"""Figures of maps and fields: maps, distance maps, potentials, surfaces, star worlds, basins.

Each figure function takes the result it draws (a :class:`~gridfield.core.grid.GridMap` or
:class:`~gridfield.geometry.world.World`, a :class:`~gridfield.distance.brushfire.DistanceMap`, a
:class:`~gridfield.fields.potential.Field`, :class:`~gridfield.following.follower.Basins`, paths) and computes nothing
from it: a World is drawn as its vector outlines, occupancy only when a GridMap is given, and a
potential only when the caller passes the field it already has. The figures of results (grid vs
exact, convergence, a plan written to a file) are in :mod:`gridfield.plot.results` (which builds on this module; :mod:`gridfield.plot` re-exports
both).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import GridfieldError, ParameterError
from ..core.grid import Grid, GridMap
from ..core.path import Path
from ..core.results import GradientField
from ..geometry.world import World
from ._layers import (
    GOAL_BASIN_COLOR,
    MINIMUM_COLORS,
    OCCUPIED_COLOR,
    Artists,
    _decimated_quiver,
    _draw_endpoints,
    _draw_paths,
    _finite_levels,
    _grid_of,
    _gridmap_of,
    _known_bounds,
    _legend,
    _log_ticks,
    _new_axes,
    _occupancy_layer,
    _path_label,
    _point_or_none,
    _points_or_empty,
    _share,
    _world_of,
    draw_outlines,
    frame_axes,
    potential_scale,
    title_of,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "plot_basins",
    "plot_brushfire",
    "plot_map",
    "plot_potential",
    "plot_star_world",
    "plot_surface",
]


# ----------------------------------------------------------------------------------------------
# maps
# ----------------------------------------------------------------------------------------------
def plot_map(
    target: World | GridMap,
    ax: Axes | None = None,
    *,
    paths: Path | Iterable[Path] = (),
    start: ArrayLike | None = None,
    goal: ArrayLike | None = None,
    outlines: bool = True,
    legend: bool = True,
    title: str | None = None,
    path_styles: Sequence[Mapping[str, Any]] | None = None,
) -> Artists:
    """Occupancy grid in world coordinates, vector obstacles outlined, start/goal and paths drawn.

    Parameters
    ----------
    target : World or GridMap
        A grid map is drawn as its occupancy (and, when it came from a world, that world's
        obstacles outlined); a vector world as its obstacles' outlines alone. Nothing is
        rasterized here: to show a world's cells, pass the grid map the planner used
        (:func:`gridfield.geometry.rasterize.as_gridmap`).
    ax : Axes, optional
        Draw into this axes; default: a new figure.
    paths : Path or iterable of Path
        Drawn as lines (``ax.lines`` holds exactly these), labelled with planner and status;
        stall points (``path.extra['local_minima']`` / ``['stall_point']``, or the end of
        a ``local_minimum`` path) are marked.
    start, goal : (x, y), optional
        Marked points; default: the world's start and goal, if any.
    outlines : bool
        Outline the vector obstacles (polygons, circles, segments, points).
    legend : bool
    title : str, optional
        Default: the map's file name.
    path_styles : sequence of dict, optional
        Line properties per path (e.g. ``[{"linestyle": "--"}]``).

    Returns
    -------
    Artists
        ``image`` (occupancy; ``None`` for a vector world), ``obstacles``, ``paths``,
        ``markers`` (``start``, ``goal``, ``stall``), ``legend``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((4, 6), bool); occ[0, :] = True
    >>> m = GridMap(Grid((4, 6), 0.5, origin=(1.0, 0.0)), occ)
    >>> p = Path(np.array([[1.2, 1.2], [3.5, 1.7]]), "reached", "demo")
    >>> art = plot_map(m, paths=[p], goal=(3.5, 1.7))
    >>> art.image.get_extent(), len(art.ax.lines)
    ([1.0, 4.0, 0.0, 2.0], 1)
    >>> import matplotlib.pyplot as plt; plt.close(art.figure)
    """
    if isinstance(paths, Path):
        paths = [paths]
    paths = list(paths)
    if not isinstance(target, World | GridMap):
        raise ParameterError(f"plot_map needs a World or a GridMap, got {type(target).__name__}")
    ax = _new_axes(ax)
    art = Artists(ax)
    gm = target if isinstance(target, GridMap) else None
    world = _world_of(target)
    if gm is not None:
        art.image = _occupancy_layer(ax, gm)
        art.mappable = art.image
        art.obstacles.append(art.image)
    if outlines and world is not None:
        art.obstacles += draw_outlines(ax, world)
    if world is not None:
        start = world.start if start is None else start
        goal = world.goal if goal is None else goal
    map_bounds = gm.grid.bounds if gm is not None else world.bounds  # type: ignore[union-attr]
    _draw_paths(ax, paths, art, styles=path_styles, bounds=map_bounds)
    _draw_endpoints(ax, art, _point_or_none(start, "start"), _point_or_none(goal, "goal"))
    # a ROS map is mostly unknown space: show its known part (and every path, start and goal)
    bounds = _known_bounds(gm, map_bounds)
    ends = [q for q in (_point_or_none(start, "start"), _point_or_none(goal, "goal")) if q is not None]
    frame_axes(ax, bounds, [p.points for p in paths] + ([np.asarray(ends)] if ends else []))
    ax.set_title(title_of(target) if title is None else title)
    if legend:
        _legend(ax, art)
    return art


# ----------------------------------------------------------------------------------------------
# brushfire
# ----------------------------------------------------------------------------------------------
def plot_brushfire(
    dmap: Any,
    ax: Axes | None = None,
    *,
    levels: int | Sequence[float] = 8,
    gvd: bool = True,
    labels: bool = False,
    cmap: str = "viridis",
    clim: tuple[float, float] | None = None,
    colorbar: bool = True,
    title: str | None = None,
) -> Artists:
    """Distance to the nearest obstacle as a heat map, with iso-distance contours and the GVD.

    Parameters
    ----------
    dmap : DistanceMap
        Result of :func:`gridfield.distance.brushfire.brushfire`.
    levels : int or sequence of float
        Number of iso-distance lines (evenly spaced inside the distance range) or their values.
    gvd : bool
        Overlay the generalized Voronoi diagram cells (``dmap.gvd``) in red.
    labels : bool
        Overlay the nearest-obstacle labels as translucent colours.
    clim : (float, float), optional
        Colour range of the distance image (default: 0 to the largest finite distance).
    colorbar : bool

    Returns
    -------
    Artists
        ``image`` (distance; obstacles and cells without an obstacle masked), ``contours``,
        ``obstacles`` (the occupancy overlay), ``extra['gvd']``, ``extra['labels']``, ``colorbar``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.distance.brushfire import brushfire
    >>> occ = np.zeros((20, 30), bool); occ[:, 0] = occ[:, -1] = True
    >>> art = plot_brushfire(brushfire(GridMap(Grid((20, 30), 0.1), occ), metric="euclidean"))
    >>> art.image.get_extent(), art.image.get_clim()
    ([0.0, 3.0, 0.0, 2.0], (0.0, 1.4...))
    >>> bool(art.extra["gvd"].get_array()[:, 14:16].count() > 0)   # the GVD runs down the middle
    True
    >>> import matplotlib.pyplot as plt; plt.close(art.figure)
    """
    from matplotlib.colors import ListedColormap

    grid = _grid_of(dmap)
    gm = _gridmap_of(dmap)
    dist = np.asarray(dmap.distance, dtype=float)
    if dist.shape != grid.shape:
        raise GridfieldError(f"distance has shape {dist.shape}, but the grid has shape {grid.shape}")
    occ = gm.occupied if gm is not None else dist <= 0
    ax = _new_axes(ax)
    art = Artists(ax)
    valid = np.isfinite(dist) & ~occ
    shown = np.ma.masked_array(np.where(valid, dist, 0.0), mask=~valid)
    dmax = float(dist[valid].max()) if valid.any() else 1.0
    if clim is None:
        clim = (0.0, dmax if dmax > 0 else 1.0)
    art.image = ax.imshow(shown, origin="lower", extent=grid.extent, cmap=cmap, vmin=clim[0], vmax=clim[1],
                          interpolation="nearest", zorder=0)
    art.mappable = art.image
    if gm is not None and occ.any():
        art.obstacles.append(_occupancy_layer(ax, gm, free_color=None, zorder=1))
    if labels:
        lab = np.asarray(dmap.label)
        uniq, inv = np.unique(lab, return_inverse=True)
        inv = inv.reshape(lab.shape)
        import matplotlib as mpl

        base = mpl.colormaps["tab20"].colors  # type: ignore[attr-defined]  # a ListedColormap
        lcmap = ListedColormap([base[i % len(base)] for i in range(len(uniq))])
        art.extra["labels"] = ax.imshow(np.ma.masked_array(inv, mask=occ | (lab == 0)), origin="lower",
                                        extent=grid.extent, cmap=lcmap, vmin=-0.5, vmax=len(uniq) - 0.5,
                                        interpolation="nearest", alpha=0.45, zorder=1.5)
    xs, ys = grid.cell_centers()
    lv = _finite_levels(0.0, dmax, levels) if isinstance(levels, int) else np.asarray(levels, dtype=float)
    lv = lv[(lv > 0) & (lv < dmax)] if valid.any() else np.empty(0)
    if len(lv) and min(grid.shape) >= 2:
        art.contours = ax.contour(xs, ys, shown, levels=lv, colors="white", linewidths=0.7, alpha=0.8, zorder=2)
    if gvd:
        g = np.asarray(dmap.gvd, dtype=bool)
        art.extra["gvd"] = ax.imshow(np.ma.masked_array(np.ones(g.shape), mask=~g), origin="lower",
                                     extent=grid.extent, cmap=ListedColormap(["red"]), vmin=0.5, vmax=1.5,
                                     interpolation="nearest", zorder=3)
    if colorbar:
        art.colorbar = ax.figure.colorbar(art.image, ax=ax, shrink=0.85, label=f"distance ({dmap.metric})")
    frame_axes(ax, _known_bounds(gm, grid.bounds))  # a ROS map: its known part
    ax.set_title(title if title is not None else f"brushfire {title_of(gm) if gm is not None else ''}".strip())
    return art


# ----------------------------------------------------------------------------------------------
# potentials
# ----------------------------------------------------------------------------------------------
def plot_potential(
    field: GradientField,
    ax: Axes | None = None,
    *,
    cap: float | None = None,
    log: bool = True,
    quiver: bool = True,
    quiver_step: int | None = None,
    stall_points: ArrayLike | None = None,
    path: Path | None = None,
    levels: int = 24,
    cmap: str = "viridis",
    colorbar: bool = True,
    title: str | None = None,
) -> Artists:
    """Potential as filled contours, the negative gradient as arrows, stall points and a path.

    Parameters
    ----------
    field : Field
        From :func:`gridfield.fields.potential.build_field`: ``potential`` (``+inf`` on obstacles),
        ``grad_x``, ``grad_y``, ``goal`` and ``map``.
    cap : float, optional
        Potential values above ``cap`` are drawn as ``cap`` (default: the largest finite value with
        ``log``, else the 95th percentile, so that the repulsive spikes do not flatten the rest).
    log : bool
        Colour ``U - min U`` on a logarithmic scale (the repulsive part explodes near obstacles);
        otherwise ``U`` on a linear scale from ``min U`` to ``cap``.
    quiver : bool
        Draw the direction of ``-grad U`` (unit arrows) on a decimated lattice of free cells.
    quiver_step : int, optional
        Lattice spacing in cells (default: about 28 arrows along the longer side).
    stall_points : (N, 2) array, optional
        Points where a follower stalled; default: those of ``path`` (see :func:`plot_map`).
    path : Path, optional
    levels : int
        Number of filled-contour levels.

    Returns
    -------
    Artists
        ``contours`` and ``mappable`` (the filled contour set; ``get_clim()`` is the colour range),
        ``image`` (the obstacle overlay), ``quiver``, ``paths``, ``markers`` (``goal``, ``stall``).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.fields.potential import build_field
    >>> occ = np.zeros((10, 12), bool); occ[4:6, 5:7] = True
    >>> f = build_field(GridMap(Grid((10, 12), 0.5), occ), (5.0, 4.0))
    >>> art = plot_potential(f, log=False, quiver_step=3)
    >>> art.quiver is not None, art.markers["goal"].get_offsets().tolist()
    (True, [[5.0, 4.0]])
    >>> import matplotlib.pyplot as plt; plt.close(art.figure)
    """
    grid = _grid_of(field)
    finite = _potential_free_cells(field, grid, levels)
    z, lo, hi, label = potential_scale(np.asarray(field.potential, dtype=float), finite, cap, log)
    ax = _new_axes(ax)
    art = Artists(ax)
    _draw_potential_shading(ax, art, grid, z, lo, hi, log, levels, cmap)
    _draw_potential_obstacles(ax, art, grid, finite, _world_of(field))
    if quiver:
        art.quiver = _decimated_quiver(ax, grid, np.asarray(field.grad_x, dtype=float),
                                       np.asarray(field.grad_y, dtype=float), finite, quiver_step)
    _draw_potential_run(ax, art, field, grid, path, stall_points)
    if colorbar:
        art.colorbar = ax.figure.colorbar(art.mappable, ax=ax, shrink=0.85, label=label)
        if log:
            art.colorbar.set_ticks(_log_ticks(lo, hi))
    shown = [path.points] if path is not None else []
    if stall_points is not None:
        shown.append(_points_or_empty(stall_points, "stall_points"))
    frame_axes(ax, _known_bounds(_gridmap_of(field), grid.bounds), shown)  # a ROS map: its known part
    ax.set_title(title if title is not None else "potential")
    if path is not None or "stall" in art.markers:
        _legend(ax, art)
    return art


def _potential_free_cells(field: GradientField, grid: Grid, levels: int) -> NDArray[np.bool_]:
    """plot_potential, phase 1: check the input; the free cells with a finite potential."""
    gm = _gridmap_of(field)
    u = np.asarray(field.potential, dtype=float)
    if u.shape != grid.shape:
        raise GridfieldError(f"potential has shape {u.shape}, but the grid has shape {grid.shape}")
    finite: NDArray[np.bool_] = np.isfinite(u)
    if gm is not None:
        finite &= ~gm.occupied
    if not finite.any():
        raise GridfieldError("the potential has no finite value on a free cell; nothing to plot")
    if levels < 2:
        raise ParameterError(f"levels must be at least 2, got {levels}")
    return finite


def _draw_potential_shading(ax: Axes, art: Artists, grid: Grid, z: NDArray[np.float64], lo: float, hi: float,
                            log: bool, levels: int, cmap: str) -> None:
    """plot_potential, phase 2: the potential as filled contours (an image on a single row or column)."""
    from matplotlib.colors import LogNorm, Normalize

    # Obstacle cells hold the top of the colour range (the potential is +inf there) instead of
    # being masked, so that the filled contours reach the obstacle overlay without white gaps.
    if log:
        lv = np.geomspace(lo, hi, levels)
        norm: Any = LogNorm(vmin=lo, vmax=hi)
    else:
        lv = np.linspace(lo, hi, levels)
        norm = Normalize(vmin=lo, vmax=hi)
    if min(grid.shape) >= 2:
        # Contour on the cell centres plus the grid's outer edges (edge values repeated), so that
        # the filled contours cover the whole extent like the images do.
        xs, ys = grid.cell_centers()
        xe = np.concatenate([[grid.bounds[0]], xs, [grid.bounds[2]]])
        ye = np.concatenate([[grid.bounds[1]], ys, [grid.bounds[3]]])
        art.contours = ax.contourf(xe, ye, np.pad(z, 1, mode="edge"), levels=lv, norm=norm, cmap=cmap, zorder=0)
        art.mappable = art.contours
    else:  # a single row or column cannot be contoured
        art.mappable = ax.imshow(z, origin="lower", extent=grid.extent, cmap=cmap, norm=norm,
                                 interpolation="nearest", zorder=0)


def _draw_potential_obstacles(ax: Axes, art: Artists, grid: Grid, finite: NDArray[np.bool_], world: Any) -> None:
    """plot_potential, phase 3: the obstacle overlay (cells without a finite potential) and the world's outlines."""
    occ = ~finite
    if occ.any():
        from matplotlib.colors import ListedColormap

        data = np.ma.masked_array(np.ones(grid.shape), mask=~occ)
        art.image = ax.imshow(data, origin="lower", extent=grid.extent, cmap=ListedColormap([OCCUPIED_COLOR]),
                              vmin=0.5, vmax=1.5, interpolation="nearest", zorder=1)
        art.obstacles.append(art.image)
    if world is not None:
        art.obstacles += draw_outlines(ax, world, color="white", zorder=2)


def _draw_potential_run(ax: Axes, art: Artists, field: GradientField, grid: Grid, path: Path | None,
                        stall_points: ArrayLike | None) -> None:
    """plot_potential, phase 4: the path (with its stall points), explicit stall points, start and goal."""
    world = _world_of(field)
    if path is not None:
        # the map is the world's bounds where there is a world (a vortex lattice reaches beyond them)
        _draw_paths(ax, [path], art, styles=[{"color": "tab:red"}],
                    bounds=world.bounds if world is not None else grid.bounds)
    if stall_points is not None:
        s = _points_or_empty(stall_points, "stall_points")
        if "stall" in art.markers:
            art.markers["stall"].remove()
        art.markers.pop("stall", None)
        if len(s):
            art.markers["stall"] = ax.scatter(s[:, 0], s[:, 1], marker="X", s=90, color="red", edgecolor="white",
                                              linewidth=0.8, zorder=8, label="stall point")
    start = path.points[0] if path is not None and len(path.points) else None
    goal = getattr(field, "goal", None)
    _draw_endpoints(ax, art, _point_or_none(start, "start"), _point_or_none(goal, "goal"))


def plot_surface(
    field: GradientField,
    ax: Axes | None = None,
    *,
    path: Path | None = None,
    cap: float | None = None,
    max_cells: int = 150,
    cmap: str = "viridis",
    title: str | None = None,
) -> Artists:
    """The potential as a 3-D surface (capped, decimated), with a path drawn on it.

    Parameters
    ----------
    field : Field
    ax : Axes3D, optional
        Must be a 3-D axes (``projection="3d"``); default: a new figure.
    path : Path, optional
        Drawn on the surface (heights sampled at the nearest cell).
    cap : float, optional
        Heights above ``cap`` (and obstacles) are drawn at ``cap``; default: the 90th percentile of
        the finite potential, which keeps the repulsive walls from dwarfing the attractive bowl.
    max_cells : int
        At most this many samples along each side: larger grids are decimated by a whole stride.

    Returns
    -------
    Artists
        ``surface`` (also ``mappable``; ``get_clim()`` is the height range), ``paths``,
        ``extra['stride']``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.fields.potential import build_field
    >>> f = build_field(GridMap(Grid((20, 20), 0.5), np.zeros((20, 20), bool)), (5.0, 5.0))
    >>> art = plot_surface(f, max_cells=10)
    >>> art.ax.name, art.extra["stride"]
    ('3d', 2)
    >>> import matplotlib.pyplot as plt; plt.close(art.figure)
    """
    if int(max_cells) < 2:
        raise ParameterError(f"max_cells must be at least 2, got {max_cells}")
    grid = _grid_of(field)
    gm = _gridmap_of(field)
    u = np.asarray(field.potential, dtype=float)
    finite = np.isfinite(u)
    if gm is not None:
        finite &= ~gm.occupied
    if not finite.any():
        raise GridfieldError("the potential has no finite value on a free cell; nothing to plot")
    vals = u[finite]
    umin = float(vals.min())
    if cap is None:
        cap = float(np.percentile(vals, 90.0))
    cap = float(cap)
    if not np.isfinite(cap):
        raise ParameterError(f"cap must be a finite potential value, got {cap!r}")
    if cap <= umin:
        cap = umin + 1.0
    if ax is None:
        ax = _new_axes(None, projection="3d", figsize=(7.5, 6.0))
        ax.view_init(elev=38, azim=-62)  # type: ignore[attr-defined]  # a 3-D Axes
    elif getattr(ax, "name", "") != "3d":
        raise ParameterError("plot_surface needs a 3-D axes: create it with fig.add_subplot(projection='3d')")
    art = Artists(ax)
    stride = max(1, math.ceil(max(grid.shape) / int(max_cells)))
    xs, ys = grid.cell_centers()
    z = np.clip(np.where(finite, u, cap), umin, cap)[::stride, ::stride]
    x, y = np.meshgrid(xs[::stride], ys[::stride])
    art.surface = ax.plot_surface(x, y, z, cmap=cmap, vmin=umin, vmax=cap, linewidth=0, antialiased=False,  # type: ignore[attr-defined]  # matplotlib stubs: a 3-D Axes / Agg canvas / Polygon patch at runtime
                                  rstride=1, cstride=1, alpha=0.9)
    art.mappable = art.surface
    art.extra["stride"] = stride
    if path is not None and len(path.points):
        cells, _ = grid.world_to_cell(path.points)
        r = np.clip(cells[:, 0], 0, grid.rows - 1)
        c = np.clip(cells[:, 1], 0, grid.cols - 1)
        pz = np.clip(np.where(finite[r, c], u[r, c], cap), umin, cap) + 0.01 * (cap - umin)
        (line,) = ax.plot(path.points[:, 0], path.points[:, 1], pz, color="tab:red", linewidth=2.2, zorder=10,
                          label=_path_label(path))
        art.paths.append(line)
    ax.set_zlim(umin, cap)  # type: ignore[attr-defined]  # matplotlib stubs: a 3-D Axes / Agg canvas / Polygon patch at runtime
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("U")  # type: ignore[attr-defined]  # matplotlib stubs: a 3-D Axes / Agg canvas / Polygon patch at runtime
    ax.set_title(title if title is not None else "potential surface")
    return art


def plot_star_world(
    data: Mapping[str, Any],
    fig: Figure | None = None,
    *,
    path: Path | None = None,
    max_cells: int = 90,
    title: str | None = None,
) -> list[Artists]:
    """Seed 002's star-world figures, in one figure of four panels.

    1. the obstacle functions as "humps" (``-beta_i`` where positive: one per obstacle, 3-D);
    2. the attractive part ``gamma**kappa`` (3-D), its minimum at the goal;
    3. the mapped space: lattice lines of the free space mapped by ``h_lambda`` onto the model
       sphere world, with the model circles and the workspace circle;
    4. the navigation function ``phi(h_lambda(q))`` as a surface (3-D), with ``path`` on it.

    Parameters
    ----------
    data : mapping
        What :func:`gridfield.fields.navigation.star_figure_data` returns (this function draws it, computing nothing).
    fig : Figure, optional
        Drawn into (cleared first); default: a new figure.
    path : Path, optional
        Drawn on the navigation-function surface (heights: the nearest lattice value).
    max_cells : int
        At most this many samples along each side of the 3-D surfaces.

    Returns
    -------
    list of Artists
        One per panel, in the order above.

    Examples
    --------
    >>> import numpy as np
    >>> x, y = np.meshgrid(np.linspace(-2, 2, 9), np.linspace(-2, 2, 9))
    >>> r2 = x**2 + y**2
    >>> data = {"x": x, "y": y, "kappa": 3.0, "lambda": 1.0, "humps": np.maximum(0.25 - r2, 0),
    ...         "attractive": r2, "phi": r2 / (1 + r2), "mapped_lines": [np.c_[x[4], y[4]]],
    ...         "workspace": ((0.0, 0.0), 2.0), "model_discs": [[0.0, 0.0, 0.5]],
    ...         "obstacles": [np.array([[-0.5, -0.5], [0.5, -0.5], [0.0, 0.5]])], "goal": (1.5, 0.0)}
    >>> arts = plot_star_world(data, max_cells=5)
    >>> len(arts), arts[0].extra["stride"], len(arts[2].obstacles)
    (4, 2, 2)
    >>> import matplotlib.pyplot as plt; plt.close(arts[0].figure)
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle

    if int(max_cells) < 2:
        raise ParameterError(f"max_cells must be at least 2, got {max_cells}")
    if fig is None:
        fig = plt.figure(figsize=(13.0, 10.5), layout="constrained")
    else:
        fig.clear()
    x, y = np.asarray(data["x"]), np.asarray(data["y"])
    stride = max(1, math.ceil(max(x.shape) / int(max_cells)))
    xs, ys = x[::stride, ::stride], y[::stride, ::stride]
    kappa, lam = float(data["kappa"]), float(data["lambda"])
    arts: list[Artists] = []

    def surface(pos: int, z: NDArray[np.float64], label: str, panel_title: str, cmap: str) -> Artists:
        ax = fig.add_subplot(2, 2, pos, projection="3d")
        ax.view_init(elev=38, azim=-62)  # a 3-D Axes
        zz = np.asarray(z, dtype=float)[::stride, ::stride]
        finite = np.isfinite(zz)
        lo = float(zz[finite].min()) if finite.any() else 0.0
        hi = float(zz[finite].max()) if finite.any() else 1.0
        art = Artists(ax)
        art.surface = ax.plot_surface(xs, ys, np.where(finite, zz, hi), cmap=cmap, vmin=lo, vmax=hi if hi > lo else lo + 1,
                                      linewidth=0, antialiased=False, rstride=1, cstride=1, alpha=0.9)
        art.mappable = art.surface
        art.extra["stride"] = stride
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.set_zlabel(label)
        ax.set_title(panel_title)
        return art

    arts.append(surface(1, data["humps"], "-beta_i", "obstacle functions: one hump per obstacle", "magma"))
    arts.append(surface(2, data["attractive"], "gamma^kappa", f"attractive part gamma^kappa (kappa = {kappa:g})",
                        "viridis"))

    ax = fig.add_subplot(2, 2, 3)
    art = Artists(ax)
    for i, line in enumerate(data["mapped_lines"]):
        (ln,) = ax.plot(line[:, 0], line[:, 1], color="tab:blue" if i % 2 == 0 else "tab:orange", linewidth=0.6)
        art.extra.setdefault("lattice", []).append(ln)
    (c0, r0) = data["workspace"]
    ws = Circle(c0, r0, fill=False, color="0.2", linewidth=1.2)
    ax.add_patch(ws)
    art.obstacles.append(ws)
    for cx, cy, r in np.asarray(data["model_discs"]).reshape(-1, 3):
        disc = Circle((cx, cy), r, facecolor=OCCUPIED_COLOR, edgecolor="tab:red", linewidth=1.2)
        ax.add_patch(disc)
        art.obstacles.append(disc)
    for shape in data["obstacles"]:
        shape = np.asarray(shape)
        if shape.ndim == 2:
            ring = np.vstack([shape, shape[:1]])
            (ln,) = ax.plot(ring[:, 0], ring[:, 1], color="0.55", linestyle="--", linewidth=0.9)
            art.extra.setdefault("outlines", []).append(ln)
    g = np.asarray(data["goal"])
    art.markers["goal"] = ax.scatter([g[0]], [g[1]], marker="*", s=160, color="tab:green", zorder=6, label="goal")
    ax.set_aspect("equal")
    ax.set_xlim(c0[0] - r0 * 1.05, c0[0] + r0 * 1.05)
    ax.set_ylim(c0[1] - r0 * 1.05, c0[1] + r0 * 1.05)
    ax.set_title(f"mapped space: free-space lattice under h_lambda (lambda = {lam:g}); model discs, star outlines dashed",
                 fontsize=9)
    arts.append(art)

    phi = np.asarray(data["phi"], dtype=float)
    art = surface(4, np.where(np.isfinite(phi), phi, 1.0), "phi", "navigation function phi(h_lambda(q))", "viridis")
    if path is not None and len(path.points):
        xv, yv = x[0], y[:, 0]
        c = np.clip(np.searchsorted(xv, path.points[:, 0]), 0, len(xv) - 1)
        r = np.clip(np.searchsorted(yv, path.points[:, 1]), 0, len(yv) - 1)
        pz = np.where(np.isfinite(phi[r, c]), phi[r, c], 1.0) + 0.01
        (line,) = art.ax.plot(path.points[:, 0], path.points[:, 1], pz, color="tab:red", linewidth=2.2, zorder=10,
                              label=_path_label(path))
        art.paths.append(line)
    arts.append(art)
    if title is not None:
        fig.suptitle(title)
    return arts


# ----------------------------------------------------------------------------------------------
# basins
# ----------------------------------------------------------------------------------------------
def plot_basins(
    basins: Any,
    ax: Axes | None = None,
    *,
    grid: Grid | None = None,
    max_legend: int = 6,
    title: str | None = None,
    legend_loc: str = "best",
) -> Artists:
    """Each free cell coloured by where gradient descent from it ends.

    Parameters
    ----------
    basins : Basins
        From :func:`gridfield.following.follower.basins`: ``label`` (0 obstacle, 1 goal, ``k >= 2`` local
        minima) and ``minima`` (the sinks' points; row ``k - 1`` for label ``k``, so that row 0,
        the goal's sink, is not marked as a local minimum; a list of the local minima alone is
        accepted too), ``goal_cell`` or ``goal``.
    grid : Grid, optional
        Needed only when ``basins`` does not carry its grid.
    max_legend : int
        At most this many local-minimum basins get a legend entry (largest first).
    title : str, optional
    legend_loc : str
        Where the legend goes: matplotlib's ``loc`` (``"best"`` avoids the markers, not the obstacles), or
        ``"below"``: under the axes in two columns, covering nothing of the map.

    Returns
    -------
    Artists
        ``image`` (labels; colour range ``(-0.5, max label + 0.5)``), ``markers`` (``minima``, ``goal``),
        ``legend``.

    Examples
    --------
    >>> import numpy as np, types
    >>> from gridfield.core.grid import Grid
    >>> lab = np.array([[0, 1, 1], [2, 2, 1]])
    >>> b = types.SimpleNamespace(label=lab, minima=np.array([[0.5, 1.5]]))
    >>> art = plot_basins(b, grid=Grid((2, 3), 1.0))
    >>> art.image.get_clim(), len(art.legend.get_texts())
    ((-0.5, 2.5), 3)
    >>> import matplotlib.pyplot as plt; plt.close(art.figure)
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    grid = grid if grid is not None else _grid_of(basins)
    lab = np.asarray(getattr(basins, "label", None) if hasattr(basins, "label") else basins.labels)
    if lab.shape != grid.shape:
        raise GridfieldError(f"basin labels have shape {lab.shape}, but the grid has shape {grid.shape}")
    lab = lab.astype(np.int64)
    if lab.size and lab.min() < 0:
        raise GridfieldError(f"basin labels must be >= 0 (0 obstacle, 1 goal, k >= 2 minima), got {lab.min()}")
    n = int(lab.max()) if lab.size else 1
    n = max(n, 1)

    colors = [OCCUPIED_COLOR, GOAL_BASIN_COLOR] + [MINIMUM_COLORS[k % len(MINIMUM_COLORS)] for k in range(n - 1)]
    ax = _new_axes(ax)
    art = Artists(ax)
    art.image = ax.imshow(lab, origin="lower", extent=grid.extent, cmap=ListedColormap(colors), vmin=-0.5,
                          vmax=n + 0.5 if n > 1 else 1.5, interpolation="nearest", zorder=0)
    art.mappable = art.image
    free = lab > 0
    nfree = max(int(free.sum()), 1)
    counts = np.bincount(lab.ravel(), minlength=n + 1)
    minima = _points_or_empty(getattr(basins, "minima", None), "basins.minima")
    goal_cell = getattr(basins, "goal_cell", None)
    # label 1 drains to where the goal cell's descent ends: the goal itself, or a sink off it (the
    # repulsion of nearby obstacles displaces the minimum), and then it is no "goal basin"
    off, beside = None, False
    if len(minima) == n and goal_cell is not None:
        sink = grid.cell_of(float(minima[0][0]), float(minima[0][1]))
        off = minima[0] if sink is not None and tuple(sink) != tuple(goal_cell) else None
        beside = off is not None and max(abs(int(a) - int(b)) for a, b in zip(sink, goal_cell, strict=True)) == 1  # type: ignore[arg-type]
    near = ", the cell beside the goal's" if beside else ""
    first = (f"goal basin ({_share(int(counts[1]), nfree, 0)})" if off is None else
             f"basin of the goal cell's sink ({_share(int(counts[1]), nfree, 0)};\nthe sink is off the goal, "
             f"at ({off[0]:.4g}, {off[1]:.4g}){near})")
    handles = [Patch(facecolor=colors[1], edgecolor="0.3", label=first)]
    order = np.argsort(-counts[2:], kind="stable")[:max_legend] + 2 if n >= 2 else np.empty(0, int)
    for k in order:
        if counts[k]:
            handles.append(Patch(facecolor=colors[k], edgecolor="0.3",
                                 label=f"minimum {k - 1} ({_share(int(counts[k]), nfree)})"))
    hidden = int((counts[2:] > 0).sum()) - (len(handles) - 1)
    if len(minima) == n:  # row k - 1 is the sink of label k: row 0 is the goal's own sink
        minima = minima[1:]
    if len(minima):
        art.markers["minima"] = ax.scatter(minima[:, 0], minima[:, 1], marker="X", s=60, color="red",
                                           edgecolor="white", linewidth=0.7, zorder=5)
        handles.append(art.markers["minima"])
        art.markers["minima"].set_label(f"local minima ({len(minima)})")
    f = getattr(basins, "field", None)
    goal = getattr(basins, "goal", None)
    goal = goal if goal is not None else getattr(f, "goal", None)
    if goal is None and getattr(basins, "goal_cell", None) is not None:
        goal = grid.cell_to_world(np.asarray(basins.goal_cell))[0]
    if goal is not None:
        g = _point_or_none(goal, "goal")
        art.markers["goal"] = ax.scatter([g[0]], [g[1]], marker="*", s=180, color="gold", edgecolor="black",  # type: ignore[index]
                                         zorder=6, label="goal")
        handles.append(art.markers["goal"])
    if hidden > 0:
        handles.append(Patch(facecolor="none", edgecolor="none", label=f"(+{hidden} smaller basins)"))
    where: dict[str, Any] = ({"loc": "upper center", "bbox_to_anchor": (0.5, -0.1), "ncols": 2}
                             if legend_loc == "below" else {"loc": legend_loc})
    art.legend = ax.legend(handles=handles, fontsize=7.5, framealpha=0.85, **where)
    # a ROS map: its known part (a basins result holds no map; its field may)
    frame_axes(ax, _known_bounds(_gridmap_of(f), grid.bounds))
    ax.set_title(title if title is not None else "basins of attraction")
    return art
