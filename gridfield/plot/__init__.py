"""Figures and animations: occupancy maps, distance maps, potentials, surfaces, basins, comparisons.

Plotting never computes: every function draws the result it is given (a map, a distance map, a
field, basins, paths) and computes nothing from it. A :class:`~gridfield.geometry.world.World` is drawn as
its vector outlines; occupancy only when a :class:`~gridfield.core.grid.GridMap` is given; a potential
only when the caller passes the field it already has (``gridfield.planners.plan_with_field(...)``
hands back the field a ``potential`` path followed).

The package has three layers: the drawing layers (occupancy, outlines, paths, endpoints, legend,
quiver, the potential's colour scale and the :class:`Artists` record; the private module
``gridfield.plot._layers``, whose layers that other parts of gridfield draw with are exported here:
:func:`draw_outlines`, :func:`frame_axes`, :func:`potential_scale`, :func:`stall_points`,
:func:`title_of`), the figures (one function per figure:
:mod:`gridfield.plot.figures` for maps and fields, :mod:`gridfield.plot.results` for comparisons,
convergence and the plan figure written to a file, :mod:`gridfield.plot.voxels` for voxel grids: slices,
a 3-D scene of isosurfaces, the figure ``--plot`` writes for a voxel map) and :mod:`gridfield.plot.animation` (GIF/MP4
writers, with the pieces the demo's and the explorer's movies share: :func:`animation_figure`,
:func:`write_animation`, :func:`check_animation_file`, :func:`ffmpeg_missing`). Every function follows one contract:

- matplotlib is imported inside the function (importing :mod:`gridfield.plot` is cheap);
- ``ax=None`` creates a new figure (constrained layout), otherwise the function draws into ``ax``;
- the function returns an :class:`Artists` record of what it drew and never calls ``plt.show()``;
- images use ``origin="lower"`` and ``extent=grid.extent`` (world coordinates, row 0 at the bottom);
- ``ax.lines`` holds exactly the drawn paths (one :class:`~matplotlib.lines.Line2D` per path): start,
  goal and stall points are scatter collections and segment obstacles a line collection, so that
  tests and callers can count paths.

Animations (:func:`save_plan_animation`, :func:`animate_brushfire`) are written as GIF with pillow,
or as MP4 when ffmpeg is installed.
"""

from __future__ import annotations

from ._layers import (
    OCCUPIED_COLOR,
    Artists,
    draw_outlines,
    frame_axes,
    potential_scale,
    stall_points,
    title_of,
)
from .animation import (
    animate_brushfire,
    animation_figure,
    check_animation_file,
    ffmpeg_missing,
    save_plan_animation,
    write_animation,
)
from .figures import (
    plot_basins,
    plot_brushfire,
    plot_map,
    plot_potential,
    plot_star_world,
    plot_surface,
)
from .results import plot_comparison, plot_convergence, save_plan_figure
from .voxels import plot_voxel_scene, plot_voxel_slices, plot_voxel_surface, save_voxel_figure, voxel_isosurface

__all__ = [
    "OCCUPIED_COLOR",
    "Artists",
    "animate_brushfire",
    "animation_figure",
    "check_animation_file",
    "draw_outlines",
    "ffmpeg_missing",
    "frame_axes",
    "plot_basins",
    "plot_brushfire",
    "plot_comparison",
    "plot_convergence",
    "plot_map",
    "plot_potential",
    "plot_star_world",
    "plot_surface",
    "plot_voxel_scene",
    "plot_voxel_slices",
    "plot_voxel_surface",
    "potential_scale",
    "save_plan_animation",
    "save_plan_figure",
    "save_voxel_figure",
    "stall_points",
    "title_of",
    "voxel_isosurface",
    "write_animation",
]
