"""Animations: a follower moving along its path (:func:`save_plan_animation`) and the brushfire
wavefront growing (:func:`animate_brushfire`), written as GIF with pillow or MP4 with ffmpeg.

The frames are drawn on a figure of their own Agg canvas (no window, whatever the backend); the
background potential of :func:`save_plan_animation` is the field the caller passes.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import GridfieldError, ParameterError
from ..core.grid import GridMap
from ..core.path import Path
from ..core.results import GradientField
from ..geometry.world import World
from ._layers import (
    ANIMATION_FORMATS,
    Artists,
    PathLike,
    _draw_endpoints,
    _goal_of,
    _grid_of,
    _point_or_none,
    frame_axes,
    stall_points,
)
from .figures import plot_map, plot_potential

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["animate_brushfire", "animation_figure", "check_animation_file", "ffmpeg_missing", "save_plan_animation",
           "write_animation"]


def check_animation_file(file: PathLike) -> FsPath:
    """Validate an animation file name: ``.gif``, or ``.mp4`` when ffmpeg runs (system, or the ``[video]`` extra).

    Parameters
    ----------
    file : str or os.PathLike
        The file to write.

    Returns
    -------
    pathlib.Path
        The file, checked: a known suffix, an existing folder, and for MP4 an ffmpeg that runs.

    Raises
    ------
    ParameterError
        An unknown suffix.
    GridfieldError
        A missing folder, or MP4 without ffmpeg.

    Examples
    --------
    >>> check_animation_file("run.gif").suffix
    '.gif'
    >>> check_animation_file("run.avi")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: run.avi: unknown animation format '.avi'; use .gif (or .mp4: ffmpeg, or the gridfield[video] extra)
    """
    p = FsPath(file)
    suffix = p.suffix.lower()
    if suffix not in ANIMATION_FORMATS:
        raise ParameterError(f"{p}: unknown animation format {suffix!r}; use .gif (or .mp4: ffmpeg, or the "
                             "gridfield[video] extra)")
    if p.parent and not p.parent.exists():
        raise GridfieldError(f"{p}: the folder {p.parent} does not exist")
    if suffix == ".mp4" and (missing := ffmpeg_missing()) is not None:
        raise GridfieldError(f"{p}: {missing}")
    return p


def ffmpeg_missing() -> str | None:
    """None when matplotlib's ffmpeg writer can run: a system ffmpeg, else the binary that
    imageio-ffmpeg ships (the ``[video]`` extra), which is then made matplotlib's
    ``animation.ffmpeg_path``; otherwise what to install.

    Returns
    -------
    str or None
        None when MP4 can be written, else one sentence saying what is missing and what to install.

    Examples
    --------
    >>> msg = ffmpeg_missing()
    >>> msg is None or "ffmpeg" in msg
    True
    """
    import matplotlib
    from matplotlib import animation

    if animation.writers.is_available("ffmpeg"):
        return None
    try:
        import imageio_ffmpeg
    except ImportError:
        return ("writing MP4 needs ffmpeg, which was not found on the PATH: pip install 'gridfield[video]' "
                "(imageio-ffmpeg ships one), install ffmpeg, or write a .gif instead")
    try:
        exe = imageio_ffmpeg.get_ffmpeg_exe()
    except RuntimeError as e:  # installed without its binary (no wheel for this platform)
        return f"writing MP4 needs ffmpeg: imageio-ffmpeg has none here ({e}); install ffmpeg or write a .gif"
    matplotlib.rcParams["animation.ffmpeg_path"] = exe
    return None if animation.writers.is_available("ffmpeg") else f"writing MP4: the ffmpeg at {exe} does not run"


def animation_figure(figsize: tuple[float, float], dpi: int) -> tuple[Figure, Axes]:
    """A figure on its own Agg canvas (no pyplot, no window, whatever the backend).

    Parameters
    ----------
    figsize : tuple of float
        Width and height in inches.
    dpi : int
        Dots per inch.

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure (constrained layout).
    ax : matplotlib.axes.Axes
        Its one axes.

    Examples
    --------
    >>> fig, ax = animation_figure((4.0, 3.0), 50)
    >>> fig.canvas.get_width_height()
    (200, 150)
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    return fig, fig.add_subplot()


def _frame_indices(n: int, max_frames: int) -> NDArray[np.intp]:
    if max_frames < 1:
        raise ParameterError(f"max_frames must be at least 1, got {max_frames}")
    if n <= max_frames:
        return np.arange(n)
    return np.unique(np.linspace(0, n - 1, max_frames).round().astype(np.intp))


def write_animation(fig: Figure, update: Callable[[int], None], n_frames: int, animated: Sequence[Any],
                     file: FsPath, fps: int) -> None:
    """Render ``n_frames`` frames and write them.

    GIF: the static part of the figure is drawn once and each frame redraws only the ``animated``
    artists over it (blitting), then pillow writes the frames with one shared palette. MP4: matplotlib's
    ffmpeg writer (a full redraw per frame).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A figure on an Agg canvas (:func:`animation_figure`).
    update : callable
        ``update(k)`` sets the ``animated`` artists to frame ``k``.
    n_frames : int
        How many frames.
    animated : sequence of matplotlib artists
        The artists that change between frames.
    file : pathlib.Path
        A file checked by :func:`check_animation_file`.
    fps : int
        Frames per second (at least 1).

    Returns
    -------
    None

    Examples
    --------
    >>> import tempfile, pathlib
    >>> fig, ax = animation_figure((2.0, 2.0), 40)
    >>> (dot,) = ax.plot([0.0], [0.0], "o"); _ = ax.set_xlim(-1, 4); _ = ax.set_ylim(-1, 4)
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "dot.gif"
    >>> write_animation(fig, lambda k: dot.set_data([k], [k]), 4, [dot], out, fps=5)
    >>> from PIL import Image
    >>> with Image.open(out) as im:
    ...     im.n_frames
    4
    """
    if fps < 1:
        raise ParameterError(f"fps must be at least 1, got {fps}")
    if file.suffix.lower() == ".mp4":
        from matplotlib import animation

        anim = animation.FuncAnimation(fig, update, frames=n_frames, blit=False, repeat=False)
        try:
            anim.save(str(file), writer=animation.FFMpegWriter(fps=fps))
        except OSError as e:
            raise GridfieldError(f"{file}: cannot write: {e.strerror or e}") from None
        return
    from PIL import Image

    canvas = fig.canvas
    for a in animated:
        a.set_animated(True)
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)  # type: ignore[attr-defined]  # matplotlib stubs: a 3-D Axes / Agg canvas / Polygon patch at runtime
    frames = []
    palette = None
    for k in range(n_frames):
        update(k)
        canvas.restore_region(background)  # type: ignore[attr-defined]  # matplotlib stubs: a 3-D Axes / Agg canvas / Polygon patch at runtime
        for a in animated:
            fig.draw_artist(a)
        rgb = Image.fromarray(np.asarray(canvas.buffer_rgba())[..., :3])  # type: ignore[attr-defined]  # matplotlib stubs: a 3-D Axes / Agg canvas / Polygon patch at runtime
        if palette is None:
            palette = rgb.quantize(colors=255, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
        frames.append(rgb.quantize(palette=palette, dither=Image.Dither.NONE))
    try:
        frames[0].save(file, format="GIF", save_all=True, append_images=frames[1:], duration=max(1, round(1000 / fps)),
                       loop=0, disposal=1)
    except OSError as e:
        raise GridfieldError(f"{file}: cannot write: {e.strerror or e}") from None


def save_plan_animation(
    file: PathLike,
    target: World | GridMap,
    path: Path,
    *,
    field: GradientField | None = None,
    goal: ArrayLike | None = None,
    fps: int = 20,
    max_frames: int = 120,
    dpi: int = 80,
    robot_shape: Any = None,
) -> FsPath:
    """Animate a follower moving along ``path``: over the potential ``field`` when the caller
    passes it, otherwise over the map.

    Parameters
    ----------
    file : path
        ``.gif`` (pillow) or ``.mp4`` (needs ffmpeg; :class:`GridfieldError` otherwise).
    target : World or GridMap
        The map drawn when no field is given (as by :func:`plot_map`).
    path : Path
        The path animated, one frame per point (sampled down to ``max_frames``).
    field : Field, optional
        Background potential: the field the path followed, as the caller has it
        (``gridfield.planners.plan_with_field(...)`` hands it back); nothing is rebuilt here.
    goal : (x, y), optional
        The goal the path was planned to (see :func:`gridfield.plot.save_plan_figure`).
    fps, max_frames : int
        Long paths are sampled down to ``max_frames`` evenly spaced frames (first and last kept).
    dpi : int
        Resolution of the frames.
    robot_shape : Robot, optional
        Its outline is drawn at each frame, its reference point on the path.

    Returns
    -------
    pathlib.Path
        The file written.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> from gridfield.core.grid import Grid, GridMap
    >>> m = GridMap(Grid((4, 6), 0.5), np.zeros((4, 6), bool))
    >>> p = Path(np.array([[0.2, 0.2], [1.0, 1.0], [2.5, 1.7]]), "reached", "demo")
    >>> with tempfile.TemporaryDirectory() as d:
    ...     out = save_plan_animation(os.path.join(d, "run.gif"), m, p, dpi=20)
    ...     out.suffix, out.stat().st_size > 0
    ('.gif', True)
    """
    p = check_animation_file(file)
    if len(path.points) == 0:
        raise GridfieldError("the path has no points to animate")
    g = _goal_of(path, target, goal)
    fig, ax = animation_figure((6.4, 5.0), int(dpi))
    art: Artists
    if field is not None:
        art = plot_potential(field, ax, quiver=True, colorbar=False, title="")
        if g is None:
            g = _point_or_none(getattr(field, "goal", None), "goal")
    else:
        art = plot_map(target, ax, start=path.points[0], goal=g, legend=False, title="")
    _draw_endpoints(ax, art, None if "start" in art.markers else path.points[0],
                    None if (g is None or "goal" in art.markers) else g)
    pts = path.points
    idx = _frame_indices(len(pts), int(max_frames))
    (trail,) = ax.plot([], [], color="tab:red", linewidth=2.0, zorder=7)
    robot = ax.scatter([pts[0, 0]], [pts[0, 1]], s=80, color="tab:red", edgecolor="white", zorder=9)
    stall = stall_points(path)
    stall_marker = ax.scatter(stall[:, 0], stall[:, 1], marker="X", s=110, color="red", edgecolor="white",
                              zorder=10)
    title = ax.set_title(" ")
    animated = [trail, robot, stall_marker, title]
    body = None
    if robot_shape is not None:
        from matplotlib.patches import Polygon as MplPolygon

        shape = robot_shape.outline((0.0, 0.0))
        outline = np.asarray(shape.exterior.coords if hasattr(shape, "exterior") else shape.coords, dtype=float)
        body = ax.add_patch(MplPolygon(outline + pts[0], closed=True, facecolor="tab:red", alpha=0.35,
                                       edgecolor="black", zorder=8))
        animated.append(body)

    def update(k: int) -> None:
        i = int(idx[k])
        trail.set_data(pts[: i + 1, 0], pts[: i + 1, 1])
        robot.set_offsets(pts[i : i + 1])
        if body is not None:
            body.set_xy(outline + pts[i])  # type: ignore[attr-defined]  # matplotlib stubs: a 3-D Axes / Agg canvas / Polygon patch at runtime
        last = k == len(idx) - 1
        title.set_text(f"{path.planner}: step {i}/{len(pts) - 1}" + (f" — {path.status}" if last else ""))
        stall_marker.set_visible(last)

    write_animation(fig, update, len(idx), animated, p, int(fps))
    return p


def animate_brushfire(
    dmap: Any,
    file: PathLike,
    *,
    fps: int = 10,
    max_frames: int = 60,
    dpi: int = 80,
) -> FsPath:
    """Animate the brushfire wavefront growing out of the obstacles, one frame per wave (sampled
    down to ``max_frames``): cells with ``steps <= k`` are coloured by their step number.

    Parameters
    ----------
    dmap : DistanceMap
        From :func:`gridfield.distance.brushfire.brushfire` with its wavefront ``steps``.
    file : path
        ``.gif``, or ``.mp4`` with ffmpeg.
    fps, max_frames, dpi : int
        Frame rate, most frames, resolution of the frames.

    Returns
    -------
    pathlib.Path
        The file written.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.distance.brushfire import brushfire
    >>> occ = np.zeros((6, 6), bool); occ[0, 0] = True
    >>> with tempfile.TemporaryDirectory() as d:
    ...     out = animate_brushfire(brushfire(GridMap(Grid((6, 6), 1.0), occ)), os.path.join(d, "bf.gif"), dpi=20)
    ...     out.suffix
    '.gif'
    """
    p = check_animation_file(file)
    grid = _grid_of(dmap)
    if dmap.steps is None:
        raise GridfieldError("the distance map has no wavefront steps (computed with compute_steps=False)")
    steps = np.asarray(dmap.steps)
    top = int(steps.max()) if steps.size else 0
    if top <= 0:
        raise GridfieldError("the distance map has no wavefront to animate (no obstacle, or no free cell)")
    waves = np.unique(np.linspace(0, top, min(top + 1, int(max_frames))).round().astype(int))
    fig, ax = animation_figure((6.4, 5.0), int(dpi))
    img = ax.imshow(np.ma.masked_array(np.zeros(grid.shape), mask=True), origin="lower", extent=grid.extent,
                    cmap="viridis", vmin=0, vmax=top, interpolation="nearest")
    fig.colorbar(img, ax=ax, shrink=0.85, label="wavefront step")
    frame_axes(ax, grid.bounds)
    title = ax.set_title(" ")

    def update(k: int) -> None:
        w = int(waves[k])
        img.set_data(np.ma.masked_array(steps, mask=(steps > w) | (steps < 0)))
        title.set_text(f"brushfire: wave {w}/{top}")

    write_animation(fig, update, len(waves), (img, title), p, int(fps))
    return p

