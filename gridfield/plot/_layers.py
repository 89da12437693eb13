"""The drawing layers every figure is made of: occupancy, obstacle outlines, paths, endpoints, legend,
quiver, potential colour scale, and the :class:`Artists` record figures return.

A layer draws what it is given into an axes and returns the artists it added; it computes nothing
but how to show the data (colour ranges, decimation of arrows, the axes frame).
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import GridfieldError, ParameterError
from ..core.grid import Grid, GridMap
from ..core.path import Path
from ..geometry.world import World

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["OCCUPIED_COLOR", "Artists", "draw_outlines", "frame_axes", "potential_scale", "stall_points", "title_of"]

PathLike = str | os.PathLike[str]

#: Colours of the occupancy image: free, occupied.
FREE_COLOR = "white"
OCCUPIED_COLOR = "0.22"
#: Colour of vector obstacle outlines.
OUTLINE_COLOR = "tab:blue"
#: Colours given to successive paths.
PATH_COLORS = ("tab:red", "tab:orange", "tab:purple", "tab:cyan", "tab:brown", "tab:pink", "tab:olive")
#: Colour of the goal's basin and, cycled, of the local minima's basins (no greens: the goal is green).
GOAL_BASIN_COLOR = "#b8e0b0"
MINIMUM_COLORS = ("#4c78a8", "#f58518", "#e45756", "#b279a2", "#9d755d", "#ff9da6", "#72b7b2", "#bab0ac",
                  "#eeca3b", "#9ecae9", "#ffbf79", "#d6a5c9")
#: Animation formats and the matplotlib writer each needs.
ANIMATION_FORMATS = {".gif": "pillow", ".mp4": "ffmpeg"}
#: The label of the figures gridfield creates itself (``ax=None``).
OWN_FIGURE = "gridfield"


@dataclass
class Artists:
    """What a plotting function drew, for callers that restyle or update it and for tests.

    Attributes
    ----------
    ax : Axes
        The axes drawn into (a 3-D axes for :func:`plot_surface`).
    image : AxesImage or None
        The main raster layer (occupancy, distance, basins), drawn with ``origin="lower"``.
    mappable : ScalarMappable or None
        What the colour bar shows (an image or a filled contour set); its ``get_clim()`` is the
        colour range used.
    contours : ContourSet or None
        Iso-lines (brushfire) or filled contours (potential).
    obstacles : list
        Artists of vector obstacle outlines and occupancy overlays.
    paths : list of Line2D
        One line per path, in the order given.
    markers : dict
        Scatter collections by role: ``"start"``, ``"goal"``, ``"stall"``, ``"minima"``, ...
    quiver : Quiver or None
    surface : Poly3DCollection or None
    colorbar : Colorbar or None
    legend : Legend or None
    extra : dict
        Anything else (GVD overlay, label overlay, reference lines).

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> art = Artists(plt.figure().add_subplot())
    >>> art.figure is art.ax.figure, art
    (True, Artists(paths=0, markers=[], obstacles=0, drawn=[]))
    >>> plt.close(art.figure)
    """

    ax: Any
    image: Any = None
    mappable: Any = None
    contours: Any = None
    obstacles: list[Any] = field(default_factory=list)
    paths: list[Any] = field(default_factory=list)
    markers: dict[str, Any] = field(default_factory=dict)
    quiver: Any = None
    surface: Any = None
    colorbar: Any = None
    legend: Any = None
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def figure(self) -> Figure:
        """The figure of :attr:`ax`."""
        fig: Figure = self.ax.figure
        return fig

    def __repr__(self) -> str:
        drawn = [name for name in ("image", "contours", "quiver", "surface", "colorbar", "legend")
                 if getattr(self, name) is not None]
        return (f"Artists(paths={len(self.paths)}, markers={sorted(self.markers)}, obstacles={len(self.obstacles)}, "
                f"drawn={drawn})")


# ----------------------------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------------------------
def _new_axes(ax: Axes | None, *, projection: str | None = None, figsize: tuple[float, float] = (7.0, 5.6)) -> Axes:
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=figsize, layout="constrained")
    fig.set_label(OWN_FIGURE)  # gridfield's own figure: a legend below the map may make it taller
    return fig.add_subplot(projection=projection)


def _grid_of(obj: Any) -> Grid:
    """The :class:`Grid` an array-holding result belongs to (GridMap, DistanceMap, Field, Basins, ...)."""
    seen = 0
    while obj is not None and seen < 4:
        if isinstance(obj, Grid):
            return obj
        if isinstance(obj, GridMap):
            return obj.grid
        g = getattr(obj, "grid", None)
        if isinstance(g, Grid):
            return g
        nxt = None
        for name in ("map", "gridmap", "field"):
            nxt = getattr(obj, name, None)
            if nxt is not None:
                break
        obj, seen = nxt, seen + 1
    raise GridfieldError(f"cannot find the grid of {type(obj).__name__}; pass grid=... explicitly")


def _gridmap_of(obj: Any) -> GridMap | None:
    if isinstance(obj, GridMap):
        return obj
    for name in ("map", "gridmap"):
        m = getattr(obj, name, None)
        if isinstance(m, GridMap):
            return m
    f = getattr(obj, "field", None)
    return _gridmap_of(f) if f is not None and f is not obj else None


def _world_of(target: Any) -> World | None:
    if isinstance(target, World):
        return target
    w = getattr(target, "world", None)
    if isinstance(w, World):
        return w
    m = _gridmap_of(target)
    return m.world if m is not None and isinstance(m.world, World) else None


def _point_or_none(p: ArrayLike | None, name: str) -> NDArray[np.float64] | None:
    if p is None:
        return None
    a = np.asarray(p, dtype=float).reshape(-1)
    if a.shape != (2,) or not np.all(np.isfinite(a)):
        raise ParameterError(f"{name} must be a point (x, y) of finite numbers, got {p!r}")
    return a


def _points_or_empty(p: ArrayLike | None, name: str) -> NDArray[np.float64]:
    if p is None:
        return np.empty((0, 2))
    a = np.asarray(p, dtype=float)
    if a.size == 0:
        return np.empty((0, 2))
    a = a.reshape(-1, 2) if a.ndim == 1 and a.shape[0] == 2 else a
    if a.ndim != 2 or a.shape[1] != 2:
        raise ParameterError(f"{name} must be points of shape (N, 2), got shape {np.shape(p)}")
    return a


def title_of(target: Any) -> str:
    """The map's name for a title: its file name, or for a ROS map (whose YAML is usually ``map.yaml``)
    its folder's name.

    Parameters
    ----------
    target : GridMap, World or object
        Anything with a ``source`` (and ``meta``), or a world's holder.

    Returns
    -------
    str
        The name ('' when the target has no source).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> title_of(SimpleNamespace(source="maps/turtlebot3_world/map.yaml", meta={"format": "ros"}))
    'turtlebot3_world'
    >>> title_of(SimpleNamespace(source="maps/arena/arena.map", meta={"format": "movingai"}))
    'arena.map'

    A grid grown by a robot (``meta["robot"]``, :func:`gridfield.geometry.cspace.apply_robot`) shows its
    configuration space, not the map's own cells, and its title says so:

    >>> title_of(SimpleNamespace(source="m/map.yaml", meta={"format": "ros", "robot": "disc of radius 0.2"}))
    'm, configuration space of the robot (disc of radius 0.2)'
    """
    src = getattr(target, "source", "") or getattr(_world_of(target), "source", "") or ""
    meta = getattr(target, "meta", None) or {}
    robot = meta.get("robot") if isinstance(meta, Mapping) else None
    suffix = f"configuration space of the robot ({robot})" if robot else ""
    if not src:
        return suffix
    path = FsPath(src)
    name = path.parent.name if meta.get("format") == "ros" and path.parent.name else path.name
    return f"{name}, {suffix}" if suffix else name


def _known_bounds(gm: GridMap | None, fallback: tuple[float, ...],
                  margin: int = 8) -> tuple[float, ...]:
    """The bounds a figure shows: a ROS map's known part (its free cells, ``margin`` cells wider: the
    view ``gridfield.demo.crop_to_known`` crops to); the whole map when nothing is free or it is no ROS
    map; ``fallback`` without a grid map (a vector world, a result that holds no map)."""
    if gm is None:
        return fallback
    free = ~np.asarray(gm.occupied, dtype=bool)
    if (gm.meta or {}).get("format") != "ros" or not free.any():
        return gm.grid.bounds
    rows, cols = np.nonzero(free.any(axis=1))[0], np.nonzero(free.any(axis=0))[0]
    r0, r1 = max(rows[0] - margin, 0), min(rows[-1] + margin + 1, gm.grid.rows)
    c0, c1 = max(cols[0] - margin, 0), min(cols[-1] + margin + 1, gm.grid.cols)
    (x0, y0), h = gm.grid.origin, gm.grid.resolution
    return (x0 + c0 * h, y0 + r0 * h, x0 + c1 * h, y0 + r1 * h)


def _share(count: int, total: int, digits: int = 1) -> str:
    """A share of cells for a legend, with ``digits`` decimals: never "100 %" unless all, never
    "0 %" for some.

    Examples
    --------
    >>> _share(5, 5), _share(9999, 10000), _share(1, 10000), _share(123, 1000), _share(1, 3, 0)
    ('100 %', '> 99.9 %', '< 0.1 %', '12.3 %', '33 %')
    """
    pct = 100.0 * count / max(total, 1)
    step = 10.0 ** -digits
    if count >= total:
        return "100 %"
    if pct >= 100.0 - step / 2:
        return f"> {100.0 - step:.{digits}f} %"
    if count > 0 and pct < step / 2:
        return f"< {step:.{digits}f} %"
    return f"{pct:.{digits}f} %"


def _occupancy_layer(ax: Axes, gm: GridMap, *, alpha: float = 1.0, zorder: float = 0.0,
                     free_color: str | None = FREE_COLOR) -> Any:
    """Occupancy as an image: ``free_color`` (or transparent) on free cells, dark grey on obstacles."""
    from matplotlib.colors import ListedColormap

    if free_color is None:
        data: NDArray[Any] = np.ma.masked_array(np.ones(gm.shape), mask=~gm.occupied)
        cmap = ListedColormap([OCCUPIED_COLOR])
        vmin, vmax = 0.5, 1.5
    else:
        data = gm.occupied.astype(np.uint8)
        cmap = ListedColormap([free_color, OCCUPIED_COLOR])
        vmin, vmax = -0.5, 1.5
    return ax.imshow(data, origin="lower", extent=gm.grid.extent, cmap=cmap, vmin=vmin, vmax=vmax,
                     interpolation="nearest", alpha=alpha, zorder=zorder)


def draw_outlines(ax: Axes, world: World, *, color: str = OUTLINE_COLOR, zorder: float = 3.0) -> list[Any]:
    """Outline every vector obstacle of ``world``: polygons, circles (exact), segments, points.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes to draw into.
    world : World
        The vector world whose obstacles are outlined.
    color : str, optional
        Edge colour (default :data:`OUTLINE_COLOR`).
    zorder : float, optional
        Drawing order of the outlines.

    Returns
    -------
    list
        The collections added: one for polygons and circles, one for segments, one for points
        (only those the world has).

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [
    ...     {"circle": {"center": [5, 5], "radius": 1}}, {"segment": [[1, 1], [2, 8]]}]})
    >>> ax = Figure().add_subplot()
    >>> len(draw_outlines(ax, w))
    2
    """
    from matplotlib.collections import LineCollection, PatchCollection
    from matplotlib.patches import Circle
    from matplotlib.patches import Polygon as MplPolygon

    patches: list[Any] = []  # matplotlib Circle and Polygon patches
    segments, points = [], []
    for ob in world.obstacles:
        if ob.kind == "circle" and ob.center is not None and ob.radius is not None:
            patches.append(Circle(ob.center, ob.radius))
        elif ob.kind == "polygon":
            patches.append(MplPolygon(ob.vertices, closed=True))
        elif ob.kind == "segment":
            segments.append(ob.vertices)
        else:
            points.append(ob.vertices.reshape(-1, 2)[0])
    out: list[Any] = []
    if patches:
        out.append(ax.add_collection(PatchCollection(patches, facecolor="none", edgecolor=color, linewidth=1.6,
                                                     zorder=zorder)))
    if segments:
        out.append(ax.add_collection(LineCollection(segments, colors=color, linewidths=2.2, zorder=zorder)))
    if points:
        p = np.asarray(points)
        out.append(ax.scatter(p[:, 0], p[:, 1], s=18, color=color, zorder=zorder))
    return out


def frame_axes(ax: Axes, bounds: tuple[float, ...], points: Sequence[NDArray[np.float64]] = ()) -> None:
    """Equal-aspect world axes showing ``bounds``, widened to show every point of ``points`` (paths
    that left an open-bordered grid).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes to frame.
    bounds : tuple of float
        ``(xmin, ymin, xmax, ymax)`` in world units.
    points : sequence of (n, 2) arrays, optional
        Points that must be visible (non-finite rows are ignored); the view grows past ``bounds`` by a
        2 % margin where one lies outside.

    Returns
    -------
    None

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> ax = Figure().add_subplot()
    >>> frame_axes(ax, (0.0, 0.0, 10.0, 5.0), [np.array([[11.0, 2.0]])])
    >>> [round(float(v), 2) for v in ax.get_xlim()]
    [0.0, 11.2]
    """
    xmin, ymin, xmax, ymax = bounds
    pts = [p for p in points if len(p)]
    if pts:
        allp = np.concatenate(pts)
        allp = allp[np.all(np.isfinite(allp), axis=1)]
        if len(allp):
            pad = 0.02 * max(xmax - xmin, ymax - ymin)
            (px0, py0), (px1, py1) = allp.min(axis=0), allp.max(axis=0)
            xmin = px0 - pad if px0 < xmin else xmin
            ymin = py0 - pad if py0 < ymin else ymin
            xmax = px1 + pad if px1 > xmax else xmax
            ymax = py1 + pad if py1 > ymax else ymax
    ax.set_xlim(xmin, xmax)
    ax.set_ylim(ymin, ymax)
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")


def _path_label(path: Path) -> str:
    """A path's legend entry: planner, status and length (three significant digits, whole units from
    1000 on, never an exponent: ``length 1188``, not ``1.19e+03``).

    Examples
    --------
    >>> from gridfield.core.path import Path
    >>> import numpy as np
    >>> _path_label(Path(np.array([[0.0, 0.0], [1188.3, 0.0]]), "reached", "potential"))
    'potential: reached, length 1188'
    >>> _path_label(Path(np.array([[0.0, 0.0], [4.2426, 0.0]]), "reached", "potential"))
    'potential: reached, length 4.24'
    """
    if path.status == "no_path":  # no path, no length ("length 0" read as a path of length 0)
        return f"{path.planner}: no_path (no path joins start and goal)"
    n = float(path.length)
    length = f"{n:.0f}" if abs(n) >= 1000 else f"{n:.3g}"
    return f"{path.planner}: {path.status}, length {length}"


def stall_points(path: Path | None) -> NDArray[np.float64]:
    """Stall points a follower recorded (``extra['local_minima']``, else ``extra['stall_point']``),
    or its end when it stopped in a local minimum.

    Parameters
    ----------
    path : Path or None
        A planned path (None gives no points).

    Returns
    -------
    ndarray of float, shape (n, 2)
        The points to mark, in world coordinates (empty when the path did not stall).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.path import Path
    >>> p = Path(np.array([[0.0, 0.0], [1.0, 1.0]]), "local_minimum", "potential")
    >>> stall_points(p).tolist()
    [[1.0, 1.0]]
    >>> stall_points(None).shape
    (0, 2)
    """
    if path is None:
        return np.empty((0, 2))
    extra = path.extra if isinstance(path.extra, Mapping) else {}
    pts = np.empty((0, 2))
    for key in ("local_minima", "stall_point"):
        if extra.get(key) is not None:
            pts = _points_or_empty(extra[key], f"path.extra[{key!r}]")
            if len(pts):
                break
    if len(pts) == 0 and path.status == "local_minimum" and len(path.points):
        pts = path.points[-1:].copy()
    return pts


def _draw_paths(ax: Axes, paths: Sequence[Path], art: Artists, *, zorder: float = 5.0,
                styles: Sequence[Mapping[str, Any]] | None = None,
                bounds: tuple[float, ...] | None = None) -> None:
    """Each path, its navigation-escape stretches, its stall points and (the first) hint. The hint is
    a text box below the axes, so it never covers the map; stall points outside ``bounds`` (a follower
    that left an open-bordered map) get their own legend entry and the map's edge is drawn."""
    stalls = []
    for i, p in enumerate(paths):
        if not isinstance(p, Path):
            raise ParameterError(f"paths must be gridfield Path objects, got {type(p).__name__} at position {i}")
        style: dict[str, Any] = {"color": PATH_COLORS[i % len(PATH_COLORS)], "linewidth": 2.0}
        if styles is not None and i < len(styles):
            style.update(styles[i])
        (line,) = ax.plot(p.points[:, 0], p.points[:, 1], label=_path_label(p), zorder=zorder, **style)
        art.paths.append(line)
        segs = p.extra.get("navigation_segments") if isinstance(p.extra, Mapping) else None
        for k, (i0, i1) in enumerate(segs or ()):
            (nav,) = ax.plot(p.points[i0: i1 + 1, 0], p.points[i0: i1 + 1, 1], color="magenta", linewidth=2.6,
                             linestyle=(0, (2, 1)), zorder=zorder + 0.5,
                             label="navigation escape" if k == 0 else None)
            art.extra.setdefault("navigation", []).append(nav)
        s = stall_points(p)
        if len(s):
            stalls.append(s)
        hint = p.extra.get("hint") if isinstance(p.extra, Mapping) else None
        if hint and "hint" not in art.extra:
            import textwrap

            # below the axes (under the x label), outside the map: it covers no stall point or path
            art.extra["hint"] = ax.annotate("\n".join(textwrap.wrap(f"hint: {hint}", 100)), xy=(0.0, 0.0),
                                            xycoords="axes fraction", xytext=(0, -36), textcoords="offset points",
                                            fontsize=7, va="top", ha="left", zorder=zorder + 3, annotation_clip=False,
                                            bbox={"facecolor": "white", "alpha": 0.85, "edgecolor": "0.6"})
            _room_for_the_box(ax)
    if stalls:
        s = np.concatenate(stalls)
        outside = np.zeros(len(s), bool)
        if bounds is not None:
            xmin, ymin, xmax, ymax = bounds
            outside = (s[:, 0] < xmin) | (s[:, 0] > xmax) | (s[:, 1] < ymin) | (s[:, 1] > ymax)
        if (~outside).any():
            art.markers["stall"] = ax.scatter(s[~outside, 0], s[~outside, 1], marker="X", s=90, color="red",
                                              edgecolor="white", linewidth=0.8, zorder=zorder + 2, label="stall point")
        if outside.any():
            from matplotlib.patches import Rectangle

            xmin, ymin, xmax, ymax = bounds  # type: ignore[misc]
            art.extra["map_edge"] = ax.add_patch(Rectangle((xmin, ymin), xmax - xmin, ymax - ymin, fill=False,
                                                           edgecolor="0.2", linestyle="--", linewidth=1.0,
                                                           zorder=zorder + 1, label="edge of the map"))
            art.markers["stall_outside"] = ax.scatter(s[outside, 0], s[outside, 1], marker="X", s=90,
                                                      color="white", edgecolor="red", linewidth=1.2,
                                                      zorder=zorder + 2,
                                                      label="stall point outside the map (the follower left it)")


def _room_for_the_box(ax: Axes) -> None:
    """A constrained layout makes room for the hint's text but not for its box's frame, which the
    figure's lower edge then cut: leave it a margin of 8 points."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    engine = ax.figure.get_layout_engine()
    if isinstance(engine, ConstrainedLayoutEngine) and engine.get()["h_pad"] < 8 / 72:
        engine.set(h_pad=8 / 72)


def _draw_endpoints(ax: Axes, art: Artists, start: NDArray[np.float64] | None, goal: NDArray[np.float64] | None,
                    *, zorder: float = 6.0) -> None:
    if start is not None:
        art.markers["start"] = ax.scatter([start[0]], [start[1]], marker="o", s=70, color="tab:green",
                                          edgecolor="black", zorder=zorder, label="start")
    if goal is not None:
        art.markers["goal"] = ax.scatter([goal[0]], [goal[1]], marker="*", s=180, color="gold",
                                         edgecolor="black", zorder=zorder, label="goal")


def _legend(ax: Axes, art: Artists, *, loc: str = "outside", fontsize: float = 8.0) -> None:
    """The legend of what ``ax`` shows; ``loc="outside"`` (the figures' default) puts it beside the axes,
    covering neither the map nor a path: below the x axis' labels or right of the axes (top-aligned),
    whichever leaves the map larger. That needs a layout that makes room for it: the constrained layout
    of the one-map figures gridfield creates (colour bars aside). In a figure of several panels (where
    the room taken beside one equal-aspect panel shrinks it below its title) or one laid out otherwise
    it falls back to matplotlib's ``"best"`` inside the axes (the corner the lines and markers cross
    least). Any other ``loc`` is matplotlib's."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return
    from matplotlib.figure import Figure
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    where: dict[str, Any] = {"loc": loc}
    beside = False
    fig = ax.get_figure()  # a subfigure (not a Figure) gets "best" too
    if loc == "outside":
        where = {"loc": "best"}
        if (isinstance(fig, Figure) and isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine)
                and [a for a in fig.axes if a.get_label() != "<colorbar>"] == [ax]):
            hint = art.extra.get("hint")  # a path's hint box below the axes: the legend goes under it
            where = _outside(ax, fig, labels, fontsize, hint=None if hint is None else hint.get_text())
            grow, beside = where.pop("grow", 0.0), where.pop("beside", False)
            if grow and fig.get_label() == OWN_FIGURE:  # room for the legend, so that the map keeps its size
                w, h = fig.get_size_inches()
                fig.set_size_inches(w, h + grow / 72.0)
    art.legend = ax.legend(handles, labels, fontsize=fontsize, framealpha=0.85, **where)
    if beside and isinstance(fig, Figure) and fig.get_label() == OWN_FIGURE:
        # one layout pass now, with the legend: the constrained layout's single pass at a save leaves
        # too little room beside the map, and a long label ran past the figure's edge (an 8room_000 path)
        fig.draw_without_rendering()


def _outside(ax: Axes, fig: Figure, labels: Sequence[str], fontsize: float, *, hint: str | None = None
             ) -> dict[str, Any]:
    """Where :func:`_legend` puts a legend beside ``ax``: below (up to three columns, offset past the x
    tick labels and axis label, and past the hint box :func:`_draw_paths` puts there) or right (one
    column, a small gap), the side being chosen on an estimate of the legend's size (points: 0.5 em per
    character, 2.5 em of handle and padding, 1.4 em per row; text lines 1.3 em) against the figure's:
    the one that scales the shown area less. With a hint, always below it (a legend beside the axes
    and a hint box wider than them are not laid out on the first draw). Below, ``"grow"`` is the height
    in points the legend adds (a figure gridfield created grows by it: the map keeps its size and the
    title stays inside); right, ``"beside"`` is True (:func:`_legend` then lays the figure out once)."""
    import matplotlib as mpl
    from matplotlib.font_manager import FontProperties
    from matplotlib.transforms import ScaledTranslation

    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    dw, dh = max(abs(x1 - x0), 1e-300), max(abs(y1 - y0), 1e-300)
    fw, fh = (72.0 * v - 60.0 for v in fig.get_size_inches())  # points, less the axes' labels
    entries = sorted((0.5 * fontsize * len(t) + 2.5 * fontsize for t in labels), reverse=True)
    ncols = next((c for c in (3, 2) if c <= len(labels) and sum(entries[:c]) <= fw), 1)
    rows = -(-len(labels) // ncols)
    size = FontProperties(size=mpl.rcParams["xtick.labelsize"]).get_size_in_points()
    below = float(mpl.rcParams["xtick.major.size"]) + float(mpl.rcParams["xtick.major.pad"]) + 1.3 * size + 4.0
    if ax.get_xlabel():
        below += 1.3 * float(ax.xaxis.label.get_fontsize()) + float(ax.xaxis.labelpad)
    if hint is not None:  # the box's top is 36 points under the axes; 7-point lines, 0.3 em of padding
        below = max(below, 36.0 + 1.3 * 7.0 * (hint.count("\n") + 1) + 2 * 2.1 + 6.0)
    tall = below + 1.4 * fontsize * rows + fontsize
    if hint is not None or min(fw / dw, (fh - tall) / dh) >= min((fw - entries[0] - 6.0) / dw, fh / dh):
        shift = ScaledTranslation(0.0, -below / 72.0, fig.dpi_scale_trans)
        return {"loc": "upper center", "bbox_to_anchor": (0.5, 0.0), "bbox_transform": ax.transAxes + shift,
                "ncols": ncols, "borderaxespad": 0.0, "grow": 1.4 * fontsize * rows + 2.0 * fontsize}
    shift = ScaledTranslation(6.0 / 72.0, 0.0, fig.dpi_scale_trans)
    return {"loc": "upper left", "bbox_to_anchor": (1.0, 1.0), "bbox_transform": ax.transAxes + shift,
            "borderaxespad": 0.0, "beside": True}


def _finite_levels(lo: float, hi: float, n: int) -> NDArray[np.float64]:
    """``n`` levels strictly inside ``(lo, hi)`` (so that contour never warns of empty levels)."""
    if not (np.isfinite(lo) and np.isfinite(hi)) or hi <= lo:
        return np.empty(0)
    return np.linspace(lo, hi, n + 2)[1:-1]


def potential_scale(u: NDArray[np.float64], finite: NDArray[np.bool_], cap: float | None,
                     log: bool) -> tuple[NDArray[np.float64], float, float, str]:
    """Values to colour, their colour range and a label: ``U`` clipped at ``cap``, or for ``log``
    ``U - min U`` clipped into ``[lo, cap - min U]`` (log colour scales need positive values).

    Parameters
    ----------
    u : ndarray of float
        The potential.
    finite : ndarray of bool
        Where ``u`` is finite (free, reached cells); the rest is shown at the top of the range.
    cap : float or None
        Top of the colour range; None: the 95th percentile of the finite values (linear) or their
        maximum (log).
    log : bool
        A log colour scale of ``U - min U``.

    Returns
    -------
    values : ndarray of float
        What to colour, the shape of ``u``.
    lo, hi : float
        The colour range.
    label : str
        The colour bar's label.

    Examples
    --------
    >>> import numpy as np
    >>> u = np.array([[0.0, 1.0], [4.0, np.inf]])
    >>> v, lo, hi, label = potential_scale(u, np.isfinite(u), 2.0, False)
    >>> v.tolist(), lo, hi, label
    ([[0.0, 1.0], [2.0, 2.0]], 0.0, 2.0, 'potential U')
    """
    vals = u[finite]
    umin = float(vals.min())
    if cap is None:
        cap = float(vals.max()) if log else float(np.percentile(vals, 95.0))
    cap = float(cap)
    if not np.isfinite(cap):
        raise ParameterError(f"cap must be a finite potential value, got {cap!r}")
    if not log:
        hi = cap if cap > umin else umin + 1.0
        return np.clip(np.where(finite, u, hi), umin, hi), umin, hi, "potential U"
    hi = cap - umin
    if hi <= 0:
        hi = 1.0
    v = np.where(finite, u - umin, hi)
    pos = v[finite & (v > 0)]
    lo = float(np.percentile(pos, 1.0)) if pos.size else hi * 1e-6
    lo = min(max(lo, hi * 1e-12), hi / 10.0)
    return np.clip(v, lo, hi), lo, hi, "U − min U (log scale)"


def _log_ticks(lo: float, hi: float) -> list[float]:
    """Decades inside ``[lo, hi]``, or a few rounded values when the range spans less than two.

    Examples
    --------
    >>> _log_ticks(0.5, 2000.0)
    [1.0, 10.0, 100.0, 1000.0]
    >>> _log_ticks(2.0, 30.0)
    [2.0, 4.9, 12.0, 30.0]
    """
    decades = [10.0**k for k in range(math.ceil(math.log10(lo)), math.floor(math.log10(hi)) + 1)]
    if len(decades) >= 2:
        return decades
    return [float(f"{v:.2g}") for v in np.geomspace(lo, hi, 4)]


def _decimated_quiver(ax: Axes, grid: Grid, gx: NDArray[np.float64], gy: NDArray[np.float64],
                      free: NDArray[np.bool_], step: int | None, *, color: str = "black", zorder: float = 4) -> Any:
    rows, cols = grid.shape
    if step is None:
        step = max(1, round(max(rows, cols) / 28))
    step = int(step)
    if step < 1:
        raise ParameterError(f"quiver_step must be a positive number of cells, got {step}")
    r = np.arange(step // 2, rows, step)
    c = np.arange(step // 2, cols, step)
    rr, cc = np.meshgrid(r, c, indexing="ij")
    u, v = -gx[rr, cc], -gy[rr, cc]
    mag = np.hypot(u, v)
    ok = free[rr, cc] & np.isfinite(mag) & (mag > 0)
    if not ok.any():
        return None
    xs, ys = grid.cell_centers()
    length = 0.75 * step * grid.resolution
    return ax.quiver(xs[cc[ok]], ys[rr[ok]], u[ok] / mag[ok], v[ok] / mag[ok], angles="xy", scale_units="xy",
                     scale=1.0 / length, width=0.0025, color=color, alpha=0.65, zorder=zorder, pivot="mid")


def _goal_of(path: Path, target: Any, goal: ArrayLike | None) -> NDArray[np.float64] | None:
    """The goal a path was planned to: given, recorded in ``path.extra``, the world's when the path
    starts at the world's start, or the end of a path that reached its goal."""
    if goal is not None:
        return _point_or_none(goal, "goal")
    g = path.extra.get("goal") if isinstance(path.extra, Mapping) else None
    if g is not None:
        return _point_or_none(g, "goal")
    w = _world_of(target)
    if w is not None and w.goal is not None and w.start is not None and len(path.points) and np.allclose(
            path.points[0], w.start):
        return np.asarray(w.goal, dtype=float)
    if path.reached and len(path.points):
        end: NDArray[np.float64] = path.points[-1].copy()
        return end
    return None


# ----------------------------------------------------------------------------------------------
# files: figures (save_plan_figure, save_voxel_figure)
# ----------------------------------------------------------------------------------------------
def _check_figure_file(file: PathLike) -> FsPath:
    p = FsPath(file)
    if p.suffix.lower() not in (".png", ".pdf", ".svg", ".jpg", ".jpeg"):
        raise ParameterError(f"{p}: unknown figure format {p.suffix!r}; use .png, .pdf, .svg or .jpg")
    if p.parent and not p.parent.exists():
        raise GridfieldError(f"{p}: the folder {p.parent} does not exist")
    return p


def _save(fig: Figure, file: FsPath, dpi: int = 110) -> None:
    import matplotlib.pyplot as plt

    try:
        fig.savefig(file, dpi=dpi)
    except OSError as e:
        raise GridfieldError(f"{file}: cannot write: {e.strerror or e}") from None
    finally:
        plt.close(fig)


def _pool(arr: NDArray[Any], k: int | Sequence[int], fill: Any, reduce: Any) -> NDArray[Any]:
    """Blocks of ``k`` voxels per axis (one size, or one per axis) reduced by ``reduce`` (``np.any``: a
    max-pool of booleans, ``np.min``), the array padded with ``fill`` to a multiple of the block."""
    ks = (k,) * 3 if isinstance(k, int) else tuple(int(v) for v in k)
    if all(v == 1 for v in ks):
        return arr
    pad = [(0, -n % v) for n, v in zip(arr.shape, ks, strict=True)]
    a = np.pad(arr, pad, constant_values=fill)
    L, R, C = (n // v for n, v in zip(a.shape, ks, strict=True))
    out: NDArray[Any] = reduce(a.reshape(L, ks[0], R, ks[1], C, ks[2]), axis=(1, 3, 5))
    return out
