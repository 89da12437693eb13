"""Figures of a turning robot: the C-obstacles stacked over the heading, the path as the robot's
footprints, and an animation of the robot moving and turning along it.

Drawn from what they are given: a :class:`~gridfield.geometry.cspace.PoseMap` (its occupancy over
``[heading, row, col]``, its workspace and robot) and a :class:`~gridfield.core.path.Path` with
``poses``. The C-obstacle surface is the boundary of the blocked poses turned into triangles by
:func:`skimage.measure.marching_cubes` (a drawing step: it computes nothing the planners use), in
axes x, y (world units) and the heading in degrees, the textbook's figure of a rotating robot's
configuration space (Latombe 1991, fig. 3; Choset et al. 2005, fig. 3.14).
"""

from __future__ import annotations

import math
from os import PathLike
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import NDArray

from ..core.errors import ParameterError
from ..core.grid import Grid, GridMap
from ..core.path import Path
from ._layers import OCCUPIED_COLOR, Artists, _known_bounds, _new_axes, _occupancy_layer, _pool, frame_axes
from .animation import animation_figure, check_animation_file, write_animation

if TYPE_CHECKING:
    from matplotlib.axes import Axes


class PoseMap(Protocol):
    """What these figures read of a :class:`gridfield.geometry.cspace.PoseMap` (plotting imports no
    algorithm, so not the class itself)."""

    occupied: NDArray[np.bool_]
    workspace: GridMap
    robot: Any
    headings: int

    @property
    def grid(self) -> Grid: ...

__all__ = ["plot_footprints", "plot_pose_space", "save_pose_animation", "save_pose_figure"]

#: At most this many voxels along an axis go to marching cubes (larger pose grids are max-pooled
#: first, so that thin C-obstacles survive): a 400 x 400 x 72 grid draws in about a second.
MAX_SURFACE_CELLS = 96


def _outline(pm: PoseMap, pose: NDArray[np.float64]) -> NDArray[np.float64]:
    """The robot's outline at a pose, as a closed ``(M + 1, 2)`` polygon (a disc: 48 points)."""
    r = pm.robot
    if r.radius is not None:
        t = np.linspace(0, 2 * math.pi, 49)
        return np.column_stack([pose[0] + r.radius * np.cos(t), pose[1] + r.radius * np.sin(t)])
    assert r.vertices is not None
    c, s = math.cos(pose[2]), math.sin(pose[2])
    v = r.vertices
    out = np.column_stack([pose[0] + c * v[:, 0] - s * v[:, 1], pose[1] + s * v[:, 0] + c * v[:, 1]])
    return np.vstack([out, out[:1]])


def _poses_of(path: Path | None) -> NDArray[np.float64] | None:
    if path is None:
        return None
    if path.poses is None:
        raise ParameterError("the path has no poses (it was not planned for a turning robot)")
    return path.poses


def plot_pose_space(pm: PoseMap, path: Path | None = None, *, ax: Axes | None = None,
                    max_cells: int = MAX_SURFACE_CELLS) -> Artists:
    """The C-obstacles of a turning robot as a surface over ``(x, y, heading)``, and the path's poses.

    Parameters
    ----------
    pm : PoseMap
    path : Path, optional
        A path with ``poses``, drawn as a 3-D line (headings unwrapped along it, in degrees).
    ax : 3-D Axes, optional
        Draw into these axes (``projection="3d"``); default a new figure.
    max_cells : int
        Pose grids larger than this along an axis are max-pooled before the surface is made.

    Returns
    -------
    Artists

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.geometry.cspace import pose_map
    >>> from gridfield.geometry.world import Robot
    >>> occ = np.zeros((12, 12), bool); occ[6, :4] = occ[6, 8:] = True
    >>> pm = pose_map(GridMap(Grid((12, 12), 0.25), occ), Robot(vertices=[[-0.6, -0.15], [0.6, -0.15], [0.6, 0.15], [-0.6, 0.15]]), 16)
    >>> art = plot_pose_space(pm)
    >>> art.ax.get_zlabel()
    'heading (degrees)'
    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # type: ignore[import-untyped]
    from skimage.measure import marching_cubes

    ax = _new_axes(ax, projection="3d", figsize=(7.0, 6.0))
    art = Artists(ax)
    h = pm.grid.resolution
    # a ROS map's known part only (the figures of 2-D maps crop the same way), as whole cells
    xmin, ymin, xmax, ymax = _known_bounds(pm.workspace, pm.grid.bounds)
    c0, c1 = (round((v - pm.grid.origin[0]) / h) for v in (xmin, xmax))
    r0, r1 = (round((v - pm.grid.origin[1]) / h) for v in (ymin, ymax))
    occ = pm.occupied[:, r0:r1, c0:c1]
    n, rows, cols = occ.shape
    step = [max(1, math.ceil(s / max_cells)) for s in (n, rows, cols)]
    occ = _pool(occ, step, False, np.any)  # a blocked pose anywhere in a block blocks the block
    # the heading axis wraps round: repeat the first slice after the last so the surface closes at 360
    vol = np.concatenate([occ, occ[:1]], axis=0).astype(np.float32)
    vol = np.pad(vol, ((0, 0), (1, 1), (1, 1)))
    dz = 360.0 / n * step[0]
    if vol.any() and not vol[:, 1:-1, 1:-1].all():
        verts, faces, _, _ = marching_cubes(vol, level=0.5, spacing=(dz, h * step[1], h * step[2]))
        # (heading, y, x) -> (x, y, heading), cell centres shifted into world coordinates
        x = verts[:, 2] + xmin + (0.5 * step[2] - 1 * step[2]) * h
        y = verts[:, 1] + ymin + (0.5 * step[1] - 1 * step[1]) * h
        z = verts[:, 0] - 180.0 / n
        tri = np.stack([x, y, z], axis=1)[faces]
        coll = Poly3DCollection(tri, facecolor=OCCUPIED_COLOR, edgecolor="none", alpha=0.35)
        ax.add_collection3d(coll)  # type: ignore[attr-defined]  # a 3-D Axes at runtime
        art.surface = coll
    poses = _poses_of(path)
    if poses is not None and len(poses):
        deg = np.degrees(np.unwrap(poses[:, 2])) % 360.0
        (line,) = ax.plot(poses[:, 0], poses[:, 1], deg, color="tab:red", lw=2, label=path.planner if path else "")
        art.paths.append(line)
    ax.set_xlim(xmin, xmax)
    ax.set_ylim(ymin, ymax)
    ax.set_zlim(0, 360)  # type: ignore[attr-defined]
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("heading (degrees)")  # type: ignore[attr-defined]
    ax.set_title(f"C-obstacles of the robot over {n} headings")
    return art


def plot_footprints(pm: PoseMap, path: Path, *, ax: Axes | None = None, every: int | None = None) -> Artists:
    """The workspace with the robot's outline drawn at poses along the path.

    Parameters
    ----------
    pm : PoseMap
    path : Path
        With ``poses``.
    ax : Axes, optional
    every : int, optional
        Draw the outline at every ``every``-th pose (default: about 24 outlines), and always at the ends.

    Returns
    -------
    Artists
        ``art.paths`` holds the path's line; the outlines are one line collection.

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.geometry.cspace import pose_map
    >>> from gridfield.geometry.world import Robot
    >>> pm = pose_map(GridMap(Grid((8, 8), 0.5), np.zeros((8, 8), bool)), Robot(vertices=[[-0.5, -0.2], [0.5, -0.2], [0.5, 0.2], [-0.5, 0.2]]), 8)
    >>> p = Path(np.array([[1.0, 1.0], [3.0, 3.0]]), "reached", "demo", poses=np.array([[1.0, 1.0, 0.0], [3.0, 3.0, 1.5]]))
    >>> len(plot_footprints(pm, p).paths)
    1
    """
    from matplotlib.collections import LineCollection

    poses = _poses_of(path)
    assert poses is not None
    ax = _new_axes(ax)
    art = Artists(ax)
    art.image = _occupancy_layer(ax, pm.workspace)
    k = every if every is not None else max(1, len(poses) // 24)
    idx = sorted({*range(0, len(poses), max(1, int(k))), len(poses) - 1}) if len(poses) else []
    outlines = [_outline(pm, poses[i]) for i in idx]  # one per drawn pose (a few dozen), not per cell
    coll = LineCollection(outlines, colors="tab:blue", linewidths=0.9, alpha=0.7, zorder=4)
    ax.add_collection(coll)
    art.extra["footprints"] = coll
    (line,) = ax.plot(poses[:, 0], poses[:, 1], color="tab:red", lw=1.6, zorder=5, label=path.planner)
    art.paths.append(line)
    if len(poses):
        art.markers["start"] = ax.scatter([poses[0, 0]], [poses[0, 1]], marker="o", color="tab:green", zorder=6,
                                          label="start")
        art.markers["goal"] = ax.scatter([poses[-1, 0]], [poses[-1, 1]], marker="*", s=120, color="tab:red", zorder=6,
                                         label="goal")
    frame_axes(ax, _known_bounds(pm.workspace, pm.grid.bounds))
    ax.set_aspect("equal")
    ax.set_title(f"{path.planner}: {path.status}, length {path.length:.3g}, {pm.headings} headings")
    return art


def save_pose_figure(file: str | PathLike[str], pm: PoseMap, path: Path, *, dpi: int = 110) -> None:
    """The plan figure of a turning robot, written to ``file``: its footprints along the path beside the
    C-obstacles over the headings with the path's poses.

    Parameters
    ----------
    file : str or os.PathLike
        A figure file (``.png``, ``.pdf``, ``.svg``, ...).
    pm : PoseMap
    path : Path
        With ``poses``.
    dpi : int

    Returns
    -------
    None

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.geometry.cspace import pose_map
    >>> from gridfield.geometry.world import Robot
    >>> pm = pose_map(GridMap(Grid((8, 8), 0.5), np.zeros((8, 8), bool)), Robot(vertices=[[-0.5, -0.2], [0.5, -0.2], [0.5, 0.2], [-0.5, 0.2]]), 8)
    >>> p = Path(np.array([[1.0, 1.0], [3.0, 3.0]]), "reached", "demo", poses=np.array([[1.0, 1.0, 0.0], [3.0, 3.0, 1.5]]))
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "plan.png"
    >>> save_pose_figure(out, pm, p)
    >>> out.stat().st_size > 0
    True
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.0, 6.0), layout="constrained")
    FigureCanvasAgg(fig)
    plot_footprints(pm, path, ax=fig.add_subplot(1, 2, 1))
    plot_pose_space(pm, path, ax=fig.add_subplot(1, 2, 2, projection="3d"))
    fig.savefig(file, dpi=dpi)


def save_pose_animation(pm: PoseMap, path: Path, file: str | PathLike[str], *, fps: int = 12, dpi: int = 90,
                        max_frames: int = 150) -> None:
    """An animation of the robot moving and turning along a path (GIF, or MP4 with ffmpeg).

    Parameters
    ----------
    pm : PoseMap
    path : Path
        With ``poses``.
    file : str or os.PathLike
        ``.gif`` or ``.mp4``.
    fps, dpi : int
    max_frames : int
        The poses are subsampled to at most this many frames.

    Returns
    -------
    None

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.geometry.cspace import pose_map
    >>> from gridfield.geometry.world import Robot
    >>> pm = pose_map(GridMap(Grid((8, 8), 0.5), np.zeros((8, 8), bool)), Robot(radius=0.3), 4)
    >>> p = Path(np.array([[1.0, 1.0], [3.0, 3.0]]), "reached", "demo", poses=np.array([[1.0, 1.0, 0.0], [3.0, 3.0, 1.5]]))
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "turn.gif"
    >>> save_pose_animation(pm, p, out, max_frames=2)
    >>> out.stat().st_size > 0
    True
    """
    out = check_animation_file(file)
    poses = _poses_of(path)
    assert poses is not None
    if len(poses) == 0:
        raise ParameterError("the path has no poses to animate")
    fig, ax = animation_figure((6.0, 6.0 * pm.grid.rows / max(pm.grid.cols, 1) + 0.4), dpi)
    _occupancy_layer(ax, pm.workspace)
    ax.plot(poses[:, 0], poses[:, 1], color="tab:red", lw=1.0, alpha=0.6)
    frame_axes(ax, pm.grid.bounds)
    ax.set_aspect("equal")
    frames = np.unique(np.linspace(0, len(poses) - 1, min(max_frames, len(poses))).round().astype(int))
    first = _outline(pm, poses[frames[0]])
    (robot,) = ax.plot(first[:, 0], first[:, 1], color="tab:blue", lw=1.8, animated=True)
    title = ax.set_title("")

    def update(i: int) -> None:
        p = poses[frames[i]]
        o = _outline(pm, p)
        robot.set_data(o[:, 0], o[:, 1])
        title.set_text(f"pose {frames[i] + 1}/{len(poses)}: ({p[0]:.2f}, {p[1]:.2f}, {math.degrees(p[2]):.0f} deg)")

    write_animation(fig, update, len(frames), [robot, title], out, fps)
