"""An interactive explorer: click start and goal, draw obstacles, move sliders, watch the field and path.

:class:`Explorer` is a thin matplotlib layer over the library: every update calls
:func:`gridfield.planners.plan` (and :func:`gridfield.potential.build_field` for the background
of the potential planner), so what the explorer shows is exactly what ``gridfield plan`` computes.

Mouse and widgets
-----------------
- left click on the map: sets the start, the next click the goal, then the start again, ...
- "draw obstacle" button: while on, left clicks add polygon vertices and a right click (or the
  button again) closes the polygon, adds it to the world as an obstacle and re-rasterizes;
- sliders ``zeta``, ``eta``, ``q_star``, ``d_star`` (its right end means ``inf``) and ``step``;
- radio buttons: the planner (``potential``, ``exact-potential``, ``wavefront-octile``, those
  installed).

The explorer never calls ``plt.show()``; ``gridfield explore MAP`` does. It works headless
(Agg), which is how it is tested: send events to ``explorer.figure.canvas`` or call the
methods (:meth:`Explorer.set_start`, :meth:`Explorer.set_param`, :meth:`Explorer.add_polygon`, ...).
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import GridfieldError, ParameterError
from .grid import GridMap
from .path import Path
from .world import Obstacle, World

__all__ = ["EXPLORER_PLANNERS", "SLIDER_PARAMS", "Explorer", "available_planners"]

#: Planners the explorer offers, in order, when their module is installed.
EXPLORER_PLANNERS = ("potential", "exact-potential", "wavefront-octile")
#: Parameters with a slider.
SLIDER_PARAMS = ("zeta", "eta", "q_star", "d_star", "step")


def _module_available(name: str) -> bool:
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):
        return False


def available_planners(*, world: bool = True) -> list[str]:
    """The explorer planners whose modules are installed (exact ones only when a vector world exists).

    Examples
    --------
    >>> set(available_planners()) <= set(EXPLORER_PLANNERS)
    True
    """
    from .planners import PLANNERS

    out = []
    for name in EXPLORER_PLANNERS:
        module, _, kind = PLANNERS[name]
        if kind == "world" and not world:
            continue
        if _module_available(module):
            out.append(name)
    return out


class Explorer:
    """Interactive potential-field explorer on a matplotlib figure.

    Parameters
    ----------
    target : World or GridMap
        The map. A world is rasterized at ``resolution`` (default: its own); drawn polygons are
        added to the world and the grid is re-rasterized. A grid map without a world gets drawn
        polygons burnt into its occupancy.
    params : mapping, optional
        Planner parameters overriding the world file's ``params``.
    planner : str
        One of :data:`EXPLORER_PLANNERS`.
    resolution : float, optional
    start, goal : (x, y), optional
        Default: the world's start and goal.
    figsize : (float, float)

    Attributes
    ----------
    figure, ax : the figure and the map axes
    sliders : dict of name to Slider
    radio : RadioButtons or None
    draw_button : Button
    path : Path or None
        The latest planning result.
    field : Field or None
        The latest potential (potential planner only).
    message : str
        The status line (the latest result or error).
    path_line : Line2D
        The drawn path (the only line of ``ax.lines`` apart from the polygon being drawn).
    n_updates : int
        How many times the field and path were recomputed.

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> ex = Explorer(read_world(bundled_map("seed003_circles.yaml")), planner="potential")
    >>> ex.start, ex.goal
    ((0.0, 4.0), (0.0, -4.0))
    >>> ex.close()
    """

    def __init__(
        self,
        target: World | GridMap,
        *,
        params: Mapping[str, Any] | None = None,
        planner: str = "potential",
        resolution: float | None = None,
        start: ArrayLike | None = None,
        goal: ArrayLike | None = None,
        figsize: tuple[float, float] = (11.0, 7.0),
    ) -> None:
        import matplotlib.pyplot as plt

        from .planners import check_params

        if not isinstance(target, World | GridMap):
            raise ParameterError(f"Explorer needs a World or a GridMap, got {type(target).__name__}")
        if planner not in EXPLORER_PLANNERS:
            raise ParameterError(f"planner must be one of {EXPLORER_PLANNERS}, got {planner!r}")
        self.world: World | None = target if isinstance(target, World) else (
            target.world if isinstance(target.world, World) else None)
        if isinstance(target, GridMap):
            self.resolution = target.grid.resolution
            self.gridmap: GridMap | None = target
        else:
            self.resolution = resolution
            self.gridmap = self._rasterize()
        if self.gridmap is None and planner != "exact-potential":
            raise GridfieldError("the explorer needs gridfield.rasterize to show a vector world on a grid")
        base = dict(self.world.params) if self.world is not None else {}
        base.update(params or {})
        self.params: dict[str, Any] = check_params(base)
        self.planner = planner
        w = self.world
        self.start: tuple[float, float] | None = self._point(start, "start") if start is not None else (
            w.start if w is not None else None)
        self.goal: tuple[float, float] | None = self._point(goal, "goal") if goal is not None else (
            w.goal if w is not None else None)
        if self.world is not None and (start is not None or goal is not None):
            self.world = dataclasses.replace(self.world, start=self.start, goal=self.goal)
            if self.gridmap is not None and isinstance(self.gridmap.world, World):
                self.gridmap = self.gridmap.with_occupied(self.gridmap.occupied, world=self.world)
        self.path: Path | None = None
        self.field: Any = None
        self.message = ""
        self.n_updates = 0
        self.drawing = False
        self.vertices: list[tuple[float, float]] = []
        self._next_click = "start" if self.start is None else ("goal" if self.goal is None else "start")

        self.figure = plt.figure(figsize=figsize)
        self.ax = self.figure.add_axes((0.06, 0.1, 0.6, 0.82))
        self._build_map_layer()
        self._build_widgets()
        self.canvas_ids = [
            self.figure.canvas.mpl_connect("button_press_event", self.on_click),
            self.figure.canvas.mpl_connect("key_press_event", self.on_key),
        ]
        self.recompute()

    # -- construction ----------------------------------------------------------------------
    def _rasterize(self) -> GridMap | None:
        if self.world is None:
            return self.gridmap
        try:
            from .rasterize import as_gridmap
        except ImportError:
            return None
        res = self.resolution if self.resolution is not None else self.world.resolution
        if res is None:
            xmin, ymin, xmax, ymax = self.world.bounds
            res = max(xmax - xmin, ymax - ymin) / 200.0
        return as_gridmap(self.world, res)

    def _point(self, p: ArrayLike, name: str) -> tuple[float, float]:
        a = np.asarray(p, dtype=float).reshape(-1)
        if a.shape != (2,) or not np.all(np.isfinite(a)):
            raise ParameterError(f"{name} must be two finite numbers x, y, got {p!r}")
        return (float(a[0]), float(a[1]))

    def _bounds(self) -> tuple[float, float, float, float]:
        if self.gridmap is not None:
            return self.gridmap.grid.bounds
        assert self.world is not None
        return self.world.bounds

    def _build_map_layer(self) -> None:
        from matplotlib.colors import ListedColormap

        from .plot import OCCUPIED_COLOR, _draw_outlines, _frame

        ax = self.ax
        xmin, ymin, xmax, ymax = self._bounds()
        extent = (xmin, xmax, ymin, ymax)
        shape = self.gridmap.shape if self.gridmap is not None else (2, 2)
        self.field_image = ax.imshow(np.ma.masked_array(np.zeros(shape), mask=True), origin="lower", extent=extent, cmap="viridis",
                                     interpolation="nearest", zorder=0, vmin=0.0, vmax=1.0)
        self.occupancy_image = ax.imshow(np.ma.masked_array(np.zeros(shape), mask=True), origin="lower", extent=extent,
                                         cmap=ListedColormap([OCCUPIED_COLOR]), vmin=0.5, vmax=1.5,
                                         interpolation="nearest", zorder=1)
        self._update_occupancy()
        self.outlines = _draw_outlines(ax, self.world) if self.world is not None else []
        self._outline_fn = _draw_outlines
        (self.path_line,) = ax.plot([], [], color="tab:red", linewidth=2.0, zorder=5, label="path")
        (self.draft_line,) = ax.plot([], [], color="tab:orange", marker="o", linestyle="--", zorder=6)
        empty = np.empty((0, 2))
        self.start_marker = ax.scatter(empty[:, 0], empty[:, 1], marker="o", s=70, color="tab:green",
                                       edgecolor="black", zorder=7, label="start")
        self.goal_marker = ax.scatter(empty[:, 0], empty[:, 1], marker="*", s=180, color="gold", edgecolor="black",
                                      zorder=7, label="goal")
        self.stall_marker = ax.scatter(empty[:, 0], empty[:, 1], marker="X", s=90, color="red", edgecolor="white",
                                       zorder=8, label="stall")
        self._update_endpoints()
        _frame(ax, self._bounds())
        self.status_text = self.figure.text(0.06, 0.02, "", fontsize=9, family="monospace")
        self.ax.set_title("click: start, then goal", fontsize=10)

    def _slider_range(self, name: str) -> tuple[float, float]:
        xmin, ymin, xmax, ymax = self._bounds()
        span = max(xmax - xmin, ymax - ymin)
        res = self.gridmap.grid.resolution if self.gridmap is not None else span / 200.0
        return {
            "zeta": (0.01, 10.0),
            "eta": (0.01, 50.0),
            "q_star": (res, max(span / 3.0, 2 * res)),
            "d_star": (res, max(span, 2 * res)),  # the right end means inf
            "step": (res / 10.0, max(10.0 * res, res / 5.0)),
        }[name]

    def _build_widgets(self) -> None:
        from matplotlib.widgets import Button, RadioButtons, Slider

        fig = self.figure
        self.sliders: dict[str, Any] = {}
        # What the planners use when a parameter is not given (gridfield.potential.DEFAULTS; the
        # follower's step defaults to one cell), so that every slider shows the value in use.
        res = self.gridmap.grid.resolution if self.gridmap is not None else self._slider_range("step")[0] * 10
        defaults = {"zeta": 1.0, "eta": 1.0, "q_star": 2.0, "d_star": math.inf, "step": res}
        for i, name in enumerate(SLIDER_PARAMS):
            lo, hi = self._slider_range(name)
            v = float(self.params.get(name, defaults[name]))
            if name == "d_star" and math.isinf(v):
                v = hi
            lo, hi = min(lo, v), max(hi, v)  # the range always holds the value in use
            sax = fig.add_axes((0.76, 0.56 - 0.055 * i, 0.17, 0.03))
            s = Slider(sax, name, lo, hi, valinit=v)
            s.on_changed(lambda val, n=name: self._on_slider(n, val))
            self.sliders[name] = s
            self._show_slider_value(name)
        choices = available_planners(world=self.world is not None)
        if self.gridmap is None:
            choices = [c for c in choices if c == "exact-potential"]
        if self.planner not in choices:
            choices = [*choices, self.planner] if self.planner in EXPLORER_PLANNERS else choices
        self.radio = None
        if choices:
            rax = fig.add_axes((0.72, 0.68, 0.26, 0.04 + 0.05 * len(choices)))
            rax.set_title("planner", fontsize=9)
            self.radio = RadioButtons(rax, choices, active=choices.index(self.planner))
            self.radio.on_clicked(self.set_planner)
        bax = fig.add_axes((0.72, 0.14, 0.26, 0.06))
        self.draw_button = Button(bax, "draw obstacle")
        self.draw_button.on_clicked(lambda _event: self.toggle_drawing())

    # -- state changes ---------------------------------------------------------------------
    def _slider_value(self, name: str, val: float) -> float:
        if name == "d_star" and val >= self.sliders[name].valmax:
            return math.inf
        return float(val)

    def _show_slider_value(self, name: str) -> None:
        s = self.sliders[name]
        v = self._slider_value(name, s.val)
        s.valtext.set_text("inf" if math.isinf(v) else f"{v:.3g}")

    def _on_slider(self, name: str, val: float) -> None:
        self.params[name] = self._slider_value(name, val)
        self._show_slider_value(name)
        self.recompute()

    def set_param(self, name: str, value: float) -> None:
        """Set a parameter (moving its slider, if it has one) and recompute."""
        from .planners import check_params

        check_params({name: value})
        if name in self.sliders:
            s = self.sliders[name]
            v = s.valmax if (name == "d_star" and math.isinf(float(value))) else float(value)
            if not (s.valmin <= v <= s.valmax):
                raise ParameterError(f"{name} = {value!r} is outside the slider range [{s.valmin:g}, {s.valmax:g}]")
            s.set_val(v)  # triggers _on_slider -> recompute
            self.params[name] = value
            return
        self.params[name] = value
        self.recompute()

    def set_planner(self, name: str | None) -> None:
        """Switch planner (radio button callback) and recompute."""
        if name is None or name == self.planner:
            return
        if name not in EXPLORER_PLANNERS:
            raise ParameterError(f"planner must be one of {EXPLORER_PLANNERS}, got {name!r}")
        self.planner = name
        labels = [t.get_text() for t in self.radio.labels] if self.radio is not None else []
        if self.radio is not None and name in labels and self.radio.value_selected != name:
            self.radio.set_active(labels.index(name))  # calls back into set_planner, which returns early
        self.recompute()

    def _is_free(self, p: tuple[float, float]) -> str | None:
        """None when ``p`` is a valid start/goal, else why not."""
        try:
            if self.gridmap is not None and self.planner != "exact-potential":
                self.gridmap.check_point("point", p)
            elif self.world is not None:
                self.world.check_point("point", p)
        except GridfieldError as e:
            return str(e)
        return None

    def set_start(self, x: float, y: float) -> bool:
        """Set the start (if free) and recompute; returns whether it was accepted."""
        return self._set_endpoint("start", (float(x), float(y)))

    def set_goal(self, x: float, y: float) -> bool:
        """Set the goal (if free) and recompute; returns whether it was accepted."""
        return self._set_endpoint("goal", (float(x), float(y)))

    def _set_endpoint(self, which: str, p: tuple[float, float]) -> bool:
        why = self._is_free(p)
        if why is not None:
            self._set_message(f"{which} not set: {why.replace('point', which, 1)}")
            self.figure.canvas.draw_idle()
            return False
        setattr(self, which, p)
        if self.world is not None:
            # the world carries start and goal too (the vortex model puts a charge at the start)
            self.world = dataclasses.replace(self.world, **{which: p})
            if self.gridmap is not None and isinstance(self.gridmap.world, World):
                self.gridmap = self.gridmap.with_occupied(self.gridmap.occupied, world=self.world)
        self._update_endpoints()
        self.recompute()
        return True

    def toggle_drawing(self) -> None:
        """Start drawing a polygon, or finish the one being drawn (button callback)."""
        if not self.drawing:
            self.drawing = True
            self.vertices = []
            self.draw_button.label.set_text("finish obstacle")
            self._set_message("drawing: left click adds a vertex, right click closes the polygon")
        else:
            self.close_polygon()
        self.figure.canvas.draw_idle()

    def add_vertex(self, x: float, y: float) -> None:
        """Add a vertex to the polygon being drawn."""
        self.vertices.append((float(x), float(y)))
        v = np.asarray(self.vertices)
        self.draft_line.set_data(v[:, 0], v[:, 1])
        self.figure.canvas.draw_idle()

    def close_polygon(self) -> bool:
        """Finish drawing: add the polygon (3 or more vertices) as an obstacle. Returns whether one was added."""
        verts, self.vertices = self.vertices, []
        self.drawing = False
        self.draw_button.label.set_text("draw obstacle")
        self.draft_line.set_data([], [])
        if len(verts) < 3:
            self._set_message("polygon discarded: it needs at least 3 vertices")
            self.figure.canvas.draw_idle()
            return False
        try:
            self.add_polygon(verts)
        except GridfieldError as e:
            self._set_message(f"polygon discarded: {e}")
            self.figure.canvas.draw_idle()
            return False
        return True

    def add_polygon(self, vertices: Sequence[Sequence[float]] | NDArray[np.float64]) -> None:
        """Add a polygon obstacle, re-rasterize and recompute.

        Raises :class:`GridfieldError` for fewer than 3 vertices or a self-intersecting outline.
        """
        import shapely
        from shapely.geometry import Polygon

        v = np.asarray(vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3 or not np.all(np.isfinite(v)):
            raise ParameterError(f"a polygon needs at least 3 finite vertices (x, y), got shape {v.shape}")
        poly = Polygon(v)
        if poly.area <= 0 or not poly.is_valid:
            raise GridfieldError(f"the polygon is not simple ({shapely.is_valid_reason(poly)}); "
                                 "click the vertices in order around it")
        if self.world is not None:
            oid = max((o.id for o in self.world.obstacles), default=0) + 1
            self.world = dataclasses.replace(
                self.world, obstacles=(*self.world.obstacles, Obstacle(oid, "polygon", poly)))
            self.gridmap = self._rasterize()
        elif self.gridmap is not None:
            from .rasterize import rasterize_geometry

            occ = self.gridmap.occupied | rasterize_geometry(poly, self.gridmap.grid)
            self.gridmap = self.gridmap.with_occupied(occ)
        self._update_occupancy()
        for a in self.outlines:
            a.remove()
        from matplotlib.collections import PatchCollection
        from matplotlib.patches import Polygon as MplPolygon

        if self.world is not None:
            self.outlines = self._outline_fn(self.ax, self.world)
        else:
            self.outlines.append(self.ax.add_collection(
                PatchCollection([MplPolygon(v, closed=True)], facecolor="none", edgecolor="tab:blue", linewidth=1.6,
                                zorder=3)))
        self.recompute()

    # -- events ----------------------------------------------------------------------------
    def on_click(self, event: Any) -> None:
        """Mouse handler: start/goal clicks, or polygon vertices while drawing."""
        if event.inaxes is not self.ax or event.xdata is None or event.ydata is None:
            return
        x, y = float(event.xdata), float(event.ydata)
        button = int(getattr(event, "button", 1) or 1)
        if self.drawing:
            if button == 1:
                self.add_vertex(x, y)
            elif button == 3:
                self.close_polygon()
            return
        if button != 1:
            return
        which = self._next_click
        if self._set_endpoint(which, (x, y)):
            self._next_click = "goal" if which == "start" else "start"

    def on_key(self, event: Any) -> None:
        """Keys: ``d`` toggles polygon drawing, ``escape`` abandons the polygon being drawn."""
        if event.key == "d":
            self.toggle_drawing()
        elif event.key == "escape" and self.drawing:
            self.vertices = []
            self.close_polygon()

    # -- drawing ---------------------------------------------------------------------------
    def _set_message(self, text: str) -> None:
        self.message = text
        self.status_text.set_text(text)

    def _update_occupancy(self) -> None:
        if self.gridmap is None:
            return
        occ = self.gridmap.occupied
        self.occupancy_image.set_data(np.ma.masked_array(np.ones(occ.shape), mask=~occ))

    def _update_endpoints(self) -> None:
        empty = np.empty((0, 2))
        self.start_marker.set_offsets(np.atleast_2d(self.start) if self.start is not None else empty)
        self.goal_marker.set_offsets(np.atleast_2d(self.goal) if self.goal is not None else empty)

    def _update_field_image(self) -> None:
        """Background: the log-scaled potential of the potential planner, else nothing."""
        from matplotlib.colors import LogNorm

        self.field = None
        if self.planner != "potential" or self.goal is None or self.gridmap is None:
            self.field_image.set_visible(False)
            return
        try:
            from .potential import build_field
        except ImportError:
            self.field_image.set_visible(False)
            return
        try:
            self.field = build_field(self.gridmap, np.asarray(self.goal), self.params)
        except GridfieldError:
            self.field_image.set_visible(False)
            return
        from .plot import _potential_scale

        fmap = self.field.map  # the vortex model lives on its own lattice
        u = np.asarray(self.field.potential, dtype=float)
        finite = np.isfinite(u) & ~fmap.occupied
        if not finite.any():
            self.field_image.set_visible(False)
            return
        z, lo, hi, _ = _potential_scale(u, finite, None, True)
        self.field_image.set_data(np.ma.masked_array(z, mask=~finite))
        self.field_image.set_extent(fmap.grid.extent)
        self.field_image.set_norm(LogNorm(vmin=lo, vmax=hi))
        self.field_image.set_visible(True)

    def recompute(self) -> Path | None:
        """Rebuild the field (background) and re-plan with the current start, goal, parameters and planner."""
        from .planners import plan

        self.n_updates += 1
        self._update_field_image()
        self.path = None
        if self.start is None or self.goal is None:
            self.path_line.set_data([], [])
            self.stall_marker.set_offsets(np.empty((0, 2)))
            self._set_message(f"click on the map to set the {'start' if self.start is None else 'goal'}")
            self.figure.canvas.draw_idle()
            return None
        # exact-potential on a grid map runs on its exact polygons (gridfield.gridpoly, through plan)
        target: World | GridMap | None = (self.world if self.planner == "exact-potential" and self.world is not None
                                          else self.gridmap)
        try:
            if target is None:
                raise GridfieldError(f"planner {self.planner!r} needs a vector world, and this map is a grid")
            self.path = plan(self.planner, target, self.start, self.goal, self.params, resolution=None)
        except GridfieldError as e:
            self.path_line.set_data([], [])
            self.stall_marker.set_offsets(np.empty((0, 2)))
            self._set_message(f"{self.planner}: {e}")
            self.figure.canvas.draw_idle()
            return None
        from .plot import _stall_points

        pts = self.path.points
        self.path_line.set_data(pts[:, 0], pts[:, 1])
        self.stall_marker.set_offsets(_stall_points(self.path))
        p = self.path
        self._set_message(f"{p.planner}: {p.status}, {p.iterations} steps, length {p.length:.4g}, "
                          f"{p.seconds * 1e3:.0f} ms")
        self.figure.canvas.draw_idle()
        return self.path

    def close(self) -> None:
        """Close the figure."""
        import matplotlib.pyplot as plt

        for cid in self.canvas_ids:
            self.figure.canvas.mpl_disconnect(cid)
        plt.close(self.figure)
