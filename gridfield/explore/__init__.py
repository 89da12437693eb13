"""An interactive explorer: the seed 004 workflow on a matplotlib figure, in a window, a browser or Jupyter.

:class:`Explorer` is a thin matplotlib layer over the library: every update calls
:func:`gridfield.planners.plan` on the map, or on its configuration space
(:func:`gridfield.cspace.apply_robot`) once a robot is drawn and the C-space computed, so what the
explorer shows is exactly what ``gridfield plan`` computes. The potential planner's background is
the field that plan followed (``plan(..., return_field=True)``): one build per update.

Seed 004's workflow: draw obstacles, draw a convex robot, compute the configuration space (the
C-obstacles are drawn in yellow beside the workspace obstacles), set the start and the goal,
calculate the path, record a movie, show the 3-D potential.

Mouse, buttons and keys
-----------------------
- left click on the map: sets the start, the next click the goal, then the start again, ...
  ("set start" / "set goal", keys ``1`` / ``2``, choose which the next click sets);
- "draw obstacle" (``d``): left clicks add polygon vertices, a right click (or the button again)
  closes the polygon, adds it as an obstacle and re-plans; ``escape`` abandons it (only the new
  polygon is rasterized, and the distance map is updated where it changed, see below);
- "draw robot" (``b``): the same for the robot's convex outline; the first vertex is its
  reference point (the black dot, the point planned for), which becomes the start;
- "C-space" (``x``): plan in the robot's configuration space from now on;
- "calculate path" (``enter``), "movie" (``m``: the next path is written as a GIF, and MP4 where
  ffmpeg exists, to :attr:`Explorer.movie_file`), "3-D" (``3``: the potential surface with the
  path, instead of the map), "undo" (``u``), "clear" (``n``: back to the map as loaded);
  :meth:`Explorer.remove_obstacle` removes any world obstacle (undoable);
- sliders for the current planner's own parameters (``zeta``, ``eta``, ``q_star``, ``d_star``,
  whose right end means ``inf``, and ``step``; none for the wavefront), radio buttons for the
  planner, and a colour bar of the potential.

Maps that change
----------------
The brushfire the potential planner and its background use is an
:class:`gridfield.incremental.IncrementalBrushfire` of the planning map, updated by the cells that
changed since its last use (a drawn or removed obstacle, undo, clear), so drawing an obstacle
runs no full brushfire; cells another obstacle also covers stay occupied with that obstacle's id.
In C-space mode the configuration space is still rebuilt in full (Minkowski sum and
rasterization) after every change, and only its brushfire is updated incrementally. A change of
more than :attr:`Explorer.INCREMENTAL_MAX_FRACTION` of the cells (e.g. turning the C-space on),
the chessboard/taxicab metrics, ``saturate``, the vortex model and the per-obstacle sum on a map
without obstacle ids use the full brushfire.

The explorer never calls ``plt.show()``; ``gridfield explore MAP`` does (``--web`` serves it
through matplotlib's WebAgg backend to a browser; in Jupyter use ``%matplotlib widget``). It works
headless (Agg), which is how it is tested: every button and key has a method
(:meth:`Explorer.set_start`, :meth:`Explorer.add_polygon`, :meth:`Explorer.set_robot`,
:meth:`Explorer.compute_cspace`, :meth:`Explorer.toggle_movie`, :meth:`Explorer.toggle_3d`,
:meth:`Explorer.undo`, :meth:`Explorer.clear`, ...).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path as FsPath
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import GridfieldError, ParameterError
from ..grid import GridMap
from ..path import Path
from ..world import Obstacle, Robot, World

__all__ = ["BUTTONS", "EXPLORER_PLANNERS", "PLANNER_SLIDERS", "SLIDER_PARAMS", "Explorer", "available_planners"]

#: Planners the explorer offers, in order, when their module is installed.
EXPLORER_PLANNERS = ("potential", "exact-potential", "wavefront-octile")
#: Parameters with a slider.
SLIDER_PARAMS = ("zeta", "eta", "q_star", "d_star", "step")
#: The sliders each planner reads (the others are hidden while it is selected).
PLANNER_SLIDERS: dict[str, tuple[str, ...]] = {
    "potential": SLIDER_PARAMS,
    "exact-potential": SLIDER_PARAMS,
    "wavefront-octile": (),
}
#: Buttons: name -> (label, key). Each calls the method of the same name.
BUTTONS: dict[str, tuple[str, str]] = {
    "toggle_drawing": ("draw obstacle", "d"),
    "toggle_robot_drawing": ("draw robot", "b"),
    "compute_cspace": ("C-space", "x"),
    "calculate_path": ("calculate path", "enter"),
    "arm_start": ("set start", "1"),
    "arm_goal": ("set goal", "2"),
    "toggle_movie": ("movie: off", "m"),
    "toggle_3d": ("3-D: off", "3"),
    "undo": ("undo", "u"),
    "clear": ("clear", "n"),
}

#: Colours: C-obstacles (seed 004 draws them yellow) and the robot.
CSPACE_COLOR = "#f2d64b"
ROBOT_COLOR = "#444444"


def available_planners(*, world: bool = True) -> list[str]:
    """The planners the explorer offers: all of :data:`EXPLORER_PLANNERS`, the exact-geometry ones
    only when a vector world exists.

    Parameters
    ----------
    world : bool
        Whether the map has a vector world (without one, the exact planners run on the grid's
        cells as polygons, which the explorer does not offer).

    Returns
    -------
    list of str
        Planner names, in the order of :data:`EXPLORER_PLANNERS`.

    Examples
    --------
    >>> available_planners()
    ['potential', 'exact-potential', 'wavefront-octile']
    >>> available_planners(world=False)
    ['potential', 'wavefront-octile']
    """
    from ..planners import PLANNERS

    return [name for name in EXPLORER_PLANNERS if world or PLANNERS[name][2] != "world"]


@dataclasses.dataclass(frozen=True)
class _State:
    """What undo restores: the workspace, the robot, the C-space and the endpoints."""

    world: World | None
    gridmap: GridMap | None
    robot: Robot | None
    cspace_on: bool
    cworld: World | None
    cgridmap: GridMap | None
    start: tuple[float, float] | None
    goal: tuple[float, float] | None


class Explorer:
    """Interactive potential-field explorer on a matplotlib figure (seed 004's workflow).

    Parameters
    ----------
    target : World or GridMap
        The map (the workspace). A world is rasterized at ``resolution`` (default: its own); drawn
        polygons are added to the world and burnt into the grid (only the polygon is rasterized).
        A grid map without a world gets drawn polygons burnt into its occupancy.
    params : mapping, optional
        Planner parameters overriding the world file's ``params``.
    planner : str
        One of :data:`EXPLORER_PLANNERS`.
    resolution : float, optional
    start, goal : (x, y), optional
        Default: the world's start and goal.
    robot : Robot, float or (N, 2) array_like, optional
        A robot to plan for from the start (its C-space is computed at once); default: the
        world file's ``robot``, else none (a point) until one is drawn.
    movie_file : path, optional
        Where the "movie" toggle writes (``.gif``; an ``.mp4`` of the same name too when ffmpeg
        is on the PATH). Default ``gridfield_movie.gif`` in the current folder.
    on_message : callable, optional
        Called with every status message (``gridfield explore --web`` prints them).
    figsize : (float, float)

    Attributes
    ----------
    figure, ax : the figure and the map axes
    ax3d : the 3-D axes (shown instead of ``ax`` by :meth:`toggle_3d`)
    colorbar : the colour bar of the potential
    sliders : dict of name to Slider
    radio : RadioButtons or None
    buttons : dict of method name to Button (see :data:`BUTTONS`)
    world, gridmap : the workspace (World or None, GridMap or None)
    robot : Robot or None
    cspace_on : bool
        Whether planning happens in the robot's configuration space.
    cworld, cgridmap : what the planners get: the C-space when on, else the workspace
    path : Path or None
        The latest planning result.
    field : Field or None
        The latest potential (potential planner only).
    message : str
        The status line (the latest result or error).
    path_line : Line2D
        The drawn path.
    movie_written : list of pathlib.Path
        The files the latest movie went to.
    n_updates : int
        How many times the field and path were recomputed.

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> ex = Explorer(read_world(bundled_map("seed003_circles.yaml")), planner="potential")
    >>> ex.start, ex.goal
    ((0.0, 4.0), (0.0, -4.0))
    >>> ex.close()
    >>> ex = Explorer(read_world(bundled_map("seed000.yaml")), resolution=0.25)
    >>> ex.set_robot(0.3); ex.compute_cspace()
    True
    >>> ex.path.status, bool(ex.cgridmap.occupied.sum() > ex.gridmap.occupied.sum())
    ('reached', True)
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
        robot: Robot | float | ArrayLike | None = None,
        movie_file: str | FsPath | None = None,
        on_message: Callable[[str], Any] | None = None,
        figsize: tuple[float, float] = (12.0, 7.5),
    ) -> None:
        import matplotlib.pyplot as plt

        from ..planners import check_params

        if not isinstance(target, World | GridMap):
            raise ParameterError(f"Explorer needs a World or a GridMap, got {type(target).__name__}")
        if planner not in EXPLORER_PLANNERS:
            raise ParameterError(f"planner must be one of {EXPLORER_PLANNERS}, got {planner!r}")
        self.on_message = on_message
        self.world: World | None = target if isinstance(target, World) else (
            target.world if isinstance(target.world, World) else None)
        self.resolution: float | None
        if isinstance(target, GridMap):
            self.resolution = target.grid.resolution
            self.gridmap: GridMap | None = target
        else:
            self.resolution = resolution
            self.gridmap = self._rasterize()
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
        from ..cspace import as_robot

        self.robot: Robot | None = as_robot(robot) if robot is not None else (w.robot if w is not None else None)
        self.cspace_on = self.robot is not None
        self.cworld, self.cgridmap = self.world, self.gridmap
        self._rebuild_cspace()
        self.movie = False
        self.movie_file = FsPath(movie_file) if movie_file is not None else FsPath("gridfield_movie.gif")
        self.movie_written: list[FsPath] = []
        self.show_3d = False
        self.history: list[_State] = []
        self._initial = self._state()
        self.path: Path | None = None
        self.field: Any = None
        self.message = ""
        self.n_updates = 0
        self.drawing = False
        self.draw_mode = "obstacle"
        self.vertices: list[tuple[float, float]] = []
        self._next_click = "start" if self.start is None else ("goal" if self.goal is None else "start")

        self.figure = plt.figure(figsize=figsize)
        self.ax = self.figure.add_axes((0.05, 0.09, 0.56, 0.84))
        self.ax3d = self.figure.add_axes((0.05, 0.09, 0.56, 0.84), projection="3d")
        self.ax3d.set_visible(False)
        self.cax = self.figure.add_axes((0.625, 0.09, 0.012, 0.84))
        self._build_map_layer()
        self._build_widgets()
        self.canvas_ids = [
            self.figure.canvas.mpl_connect("button_press_event", self.on_click),
            self.figure.canvas.mpl_connect("key_press_event", self.on_key),
        ]
        self.recompute()

    def __repr__(self) -> str:
        status = self.path.status if self.path is not None else None
        return (f"Explorer(planner={self.planner!r}, start={self.start}, goal={self.goal}, path={status!r}, "
                f"cspace={self.cspace_on}, updates={self.n_updates})")

    # -- construction ----------------------------------------------------------------------
    def _rasterize(self, world: World | None = None) -> GridMap | None:
        from ..rasterize import as_gridmap

        world = self.world if world is None else world
        if world is None:
            return self.gridmap
        res = self.resolution if self.resolution is not None else world.resolution
        if res is None:
            xmin, ymin, xmax, ymax = world.bounds
            res = max(xmax - xmin, ymax - ymin) / 200.0
        return as_gridmap(world, res)

    def _point(self, p: ArrayLike, name: str) -> tuple[float, float]:
        a = np.asarray(p, dtype=float).reshape(-1)
        if a.shape != (2,) or not np.all(np.isfinite(a)):
            raise ParameterError(f"{name} must be two finite numbers x, y, got {p!r}")
        return (float(a[0]), float(a[1]))

    def _workspace(self) -> World | GridMap:
        """The workspace the robot moves in: the vector world, else the grid map."""
        ws = self.world if self.world is not None else self.gridmap
        assert ws is not None  # the constructor takes a World or a GridMap
        return ws

    def _bounds(self) -> tuple[float, float, float, float]:
        if self.gridmap is not None:
            return self.gridmap.grid.bounds
        assert self.world is not None
        return self.world.bounds

    def _build_map_layer(self) -> None:
        from matplotlib.colors import ListedColormap

        from ..plot.layers import OCCUPIED_COLOR, _frame

        ax = self.ax
        xmin, ymin, xmax, ymax = self._bounds()
        extent = (xmin, xmax, ymin, ymax)
        shape = self.gridmap.shape if self.gridmap is not None else (2, 2)
        empty = np.ma.masked_array(np.zeros(shape), mask=True)
        self.field_image = ax.imshow(empty, origin="lower", extent=extent, cmap="viridis",
                                     interpolation="nearest", zorder=0, vmin=0.0, vmax=1.0)
        self.cspace_image = ax.imshow(empty.copy(), origin="lower", extent=extent,
                                      cmap=ListedColormap([CSPACE_COLOR]), vmin=0.5, vmax=1.5,
                                      interpolation="nearest", zorder=0.9, alpha=0.85)
        self.occupancy_image = ax.imshow(empty.copy(), origin="lower", extent=extent,
                                         cmap=ListedColormap([OCCUPIED_COLOR]), vmin=0.5, vmax=1.5,
                                         interpolation="nearest", zorder=1)
        self.outlines: list[Any] = []
        self.cspace_outlines: list[Any] = []
        self._drawn_outlines: list[Any] = []  # polygons burnt into a grid without a world
        (self.path_line,) = ax.plot([], [], color="tab:red", linewidth=2.0, zorder=5, label="path")
        (self.draft_line,) = ax.plot([], [], color="tab:orange", marker="o", linestyle="--", zorder=6)
        from matplotlib.patches import Polygon as MplPolygon

        self.robot_patch = ax.add_patch(MplPolygon(np.zeros((3, 2)), closed=True, facecolor="white", alpha=0.8,
                                                   edgecolor=ROBOT_COLOR, linewidth=1.5, zorder=6.5, visible=False))
        none = np.empty((0, 2))
        self.reference_marker = ax.scatter(none[:, 0], none[:, 1], s=22, color="black", zorder=7.5, label="robot")
        self.start_marker = ax.scatter(none[:, 0], none[:, 1], marker="o", s=70, color="tab:green",
                                       edgecolor="black", zorder=7, label="start")
        self.goal_marker = ax.scatter(none[:, 0], none[:, 1], marker="*", s=180, color="gold", edgecolor="black",
                                      zorder=7, label="goal")
        self.stall_marker = ax.scatter(none[:, 0], none[:, 1], marker="X", s=90, color="red", edgecolor="white",
                                       zorder=8, label="stall")
        self._redraw_map()
        _frame(ax, self._bounds())
        self.colorbar = self.figure.colorbar(self.field_image, cax=self.cax)
        self.colorbar.set_label("U − min U (log scale)", fontsize=8)
        self.cax.tick_params(labelsize=7)
        self.status_text = self.figure.text(0.05, 0.02, "", fontsize=9, family="monospace")
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
            sax = fig.add_axes((0.74, 0.69 - 0.045 * i, 0.2, 0.025))
            s = Slider(sax, name, lo, hi, valinit=v)
            s.on_changed(functools.partial(self._on_slider, name))
            self.sliders[name] = s
            self._show_slider_value(name)
        choices = available_planners(world=self.world is not None)
        if self.gridmap is None:
            choices = [c for c in choices if c == "exact-potential"]
        if self.planner not in choices:
            choices = [*choices, self.planner] if self.planner in EXPLORER_PLANNERS else choices
        self.radio = None
        if choices:
            rax = fig.add_axes((0.7, 0.76, 0.28, 0.03 + 0.045 * len(choices)))
            rax.set_title("planner", fontsize=9)
            self.radio = RadioButtons(rax, choices, active=choices.index(self.planner))
            self.radio.on_clicked(self.set_planner)
        self.buttons: dict[str, Any] = {}
        for k, (method, (label, key)) in enumerate(BUTTONS.items()):
            row, col = divmod(k, 2)
            bax = fig.add_axes((0.69 + 0.148 * col, 0.4 - 0.068 * row, 0.14, 0.055))
            b = Button(bax, f"{label} [{key}]")
            b.label.set_fontsize(8)
            b.on_clicked(functools.partial(self._on_button, method))
            self.buttons[method] = b
        self.draw_button = self.buttons["toggle_drawing"]
        self._update_sliders()

    def _on_button(self, method: str, _event: Any = None) -> None:
        """A button's callback: the method of the same name (see :data:`BUTTONS`)."""
        getattr(self, method)()

    # -- parameters and planner ------------------------------------------------------------
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

    def _update_sliders(self) -> None:
        """Show (and let react) only the sliders the current planner reads."""
        used = PLANNER_SLIDERS.get(self.planner, SLIDER_PARAMS)
        for name, s in self.sliders.items():
            on = name in used
            s.ax.set_visible(on)
            s.set_active(on)

    def set_param(self, name: str, value: float) -> None:
        """Set a parameter (moving its slider, if it has one) and recompute."""
        from ..planners import check_params

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
        """Switch planner (radio button callback), show its sliders only, and recompute."""
        if name is None or name == self.planner:
            return
        if name not in EXPLORER_PLANNERS:
            raise ParameterError(f"planner must be one of {EXPLORER_PLANNERS}, got {name!r}")
        self.planner = name
        labels = [t.get_text() for t in self.radio.labels] if self.radio is not None else []
        if self.radio is not None and name in labels and self.radio.value_selected != name:
            self.radio.set_active(labels.index(name))  # calls back into set_planner, which returns early
        self._update_sliders()
        self.recompute()

    # -- undo ------------------------------------------------------------------------------
    def _state(self) -> _State:
        return _State(self.world, self.gridmap, self.robot, self.cspace_on, self.cworld, self.cgridmap,
                      self.start, self.goal)

    def _push(self) -> None:
        self.history.append(self._state())

    def _restore(self, s: _State) -> None:
        self.world, self.gridmap, self.robot, self.cspace_on = s.world, s.gridmap, s.robot, s.cspace_on
        self.cworld, self.cgridmap, self.start, self.goal = s.cworld, s.cgridmap, s.start, s.goal
        self.drawing = False
        self.vertices = []
        self.draft_line.set_data([], [])
        self._redraw_map()
        self.recompute()

    def undo(self) -> bool:
        """Undo the latest obstacle, robot, C-space, endpoint or clear; returns whether there was one."""
        if not self.history:
            self._set_message("nothing to undo")
            self.figure.canvas.draw_idle()
            return False
        self._restore(self.history.pop())
        return True

    def clear(self) -> None:
        """Back to the map as loaded: no drawn obstacles, the initial robot and endpoints (undoable)."""
        self._push()
        self._restore(self._initial)

    # -- endpoints -------------------------------------------------------------------------
    def _is_free(self, p: tuple[float, float]) -> str | None:
        """None when ``p`` is a valid start/goal, else why not."""
        try:
            if self.cspace_on and self.robot is not None:
                from ..cspace import check_robot_point

                check_robot_point(self._workspace(), self.robot, "point", p)
            if self.cgridmap is not None and self.planner != "exact-potential":
                self.cgridmap.check_point("point", p)
            elif self.cworld is not None:
                self.cworld.check_point("point", p)
        except GridfieldError as e:
            return str(e)
        return None

    def set_start(self, x: float, y: float) -> bool:
        """Set the start (if free) and recompute; returns whether it was accepted."""
        return self._set_endpoint("start", (float(x), float(y)))

    def set_goal(self, x: float, y: float) -> bool:
        """Set the goal (if free) and recompute; returns whether it was accepted."""
        return self._set_endpoint("goal", (float(x), float(y)))

    def arm_start(self) -> None:
        """The next click on the map sets the start ("set start" button)."""
        self._next_click = "start"
        self._set_message("click on the map to set the start")
        self.figure.canvas.draw_idle()

    def arm_goal(self) -> None:
        """The next click on the map sets the goal ("set goal" button)."""
        self._next_click = "goal"
        self._set_message("click on the map to set the goal")
        self.figure.canvas.draw_idle()

    def _sync_endpoints(self) -> None:
        """The worlds carry start and goal too (the vortex model puts a charge at the start)."""
        if self.world is not None:
            self.world = dataclasses.replace(self.world, start=self.start, goal=self.goal)
            if self.gridmap is not None and isinstance(self.gridmap.world, World):
                self.gridmap = self.gridmap.with_occupied(self.gridmap.occupied, world=self.world)
        if not (self.cspace_on and self.robot is not None):
            self.cworld, self.cgridmap = self.world, self.gridmap
        elif self.cworld is not None:
            self.cworld = dataclasses.replace(self.cworld, start=self.start, goal=self.goal)
            if self.cgridmap is not None and isinstance(self.cgridmap.world, World):
                self.cgridmap = self.cgridmap.with_occupied(self.cgridmap.occupied, world=self.cworld)

    def _set_endpoint(self, which: str, p: tuple[float, float], *, push: bool = True) -> bool:
        why = self._is_free(p)
        if why is not None:
            self._set_message(f"{which} not set: {why.replace('point', which, 1)}")
            self.figure.canvas.draw_idle()
            return False
        if push:
            self._push()
        setattr(self, which, p)
        if self.on_message is not None:
            self.on_message(f"{which} set to ({p[0]:.4g}, {p[1]:.4g})")
        self._sync_endpoints()
        self._update_endpoints()
        self.recompute()
        return True

    # -- drawing obstacles and the robot ---------------------------------------------------
    def toggle_drawing(self) -> None:
        """Start drawing an obstacle polygon, or finish the one being drawn (button callback)."""
        self._toggle_draw("obstacle")

    def toggle_robot_drawing(self) -> None:
        """Start drawing the robot's convex outline, or finish it (button callback)."""
        self._toggle_draw("robot")

    def _toggle_draw(self, mode: str) -> None:
        if not self.drawing:
            self.drawing = True
            self.draw_mode = mode
            self.vertices = []
            self.buttons["toggle_drawing" if mode == "obstacle" else "toggle_robot_drawing"].label.set_text(
                f"finish {mode}")
            self.draft_line.set_color("tab:orange" if mode == "obstacle" else ROBOT_COLOR)
            first = " (the first vertex is the reference point)" if mode == "robot" else ""
            self._set_message(f"drawing the {mode}: left click adds a vertex{first}, right click closes it")
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
        """Finish drawing: add the obstacle, or set the robot (3 or more vertices). Returns whether it was."""
        verts, self.vertices = self.vertices, []
        mode = self.draw_mode
        self.drawing = False
        for m, (label, key) in BUTTONS.items():
            if m in ("toggle_drawing", "toggle_robot_drawing"):
                self.buttons[m].label.set_text(f"{label} [{key}]")
        self.draft_line.set_data([], [])
        if len(verts) < 3:
            self._set_message(f"{mode} discarded: it needs at least 3 vertices")
            self.figure.canvas.draw_idle()
            return False
        try:
            if mode == "robot":
                ref = np.asarray(verts[0])
                self.set_robot(np.asarray(verts) - ref, at=(float(ref[0]), float(ref[1])))
            else:
                self.add_polygon(verts)
        except GridfieldError as e:
            self._set_message(f"{mode} discarded: {e}")
            self.figure.canvas.draw_idle()
            return False
        return True

    def add_polygon(self, vertices: Sequence[Sequence[float]] | NDArray[np.float64]) -> None:
        """Add a polygon obstacle, burn its cells into the map (rebuild the C-space when on) and recompute.

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
        self._push()
        if self.world is not None:
            oid = max((o.id for o in self.world.obstacles), default=0) + 1
            ob = Obstacle(oid, "polygon", poly)
            self.world = dataclasses.replace(self.world, obstacles=(*self.world.obstacles, ob))
            if self.gridmap is not None:
                self.gridmap = self._burn_obstacle(ob)  # only the new polygon is rasterized
        elif self.gridmap is not None:
            self.gridmap = self._burn_obstacle(Obstacle(0, "polygon", poly), drawn=v)
        self._rebuild_cspace()
        self._redraw_map()
        self.recompute()

    def set_robot(self, robot: Robot | float | ArrayLike | None, *, at: tuple[float, float] | None = None) -> None:
        """Set the robot: a radius, a convex polygon around its reference point, or None (a point).

        With ``at``, the start moves there (the drawn robot's reference point) when it is free.
        When the C-space is on it is rebuilt for the new robot. Raises :class:`ParameterError`
        for a non-convex polygon.
        """
        from ..cspace import as_robot

        r = as_robot(robot)
        self._push()
        self.robot = r
        if r is None:
            self.cspace_on = False
        self._rebuild_cspace()
        self._redraw_map()
        if at is not None and self._is_free(at) is None:
            self.start = at
            self._sync_endpoints()
            self._update_endpoints()
        self.recompute()
        if r is not None and not self.cspace_on and self.path is not None:
            self._set_message(f"robot: {r.describe()}; press 'C-space' to plan for it. " + self.message)
            self.figure.canvas.draw_idle()

    def compute_cspace(self) -> bool:
        """Plan in the robot's configuration space from now on (seed 004's "Compute Q").

        Returns False (with a message) when there is no robot yet.
        """
        if self.robot is None:
            self._set_message("draw a robot first ('draw robot'), or pass --robot-radius / --robot")
            self.figure.canvas.draw_idle()
            return False
        self._push()
        self.cspace_on = True
        self._rebuild_cspace()
        self._redraw_map()
        self.recompute()
        return True

    def _rebuild_cspace(self) -> None:
        if not (self.cspace_on and self.robot is not None):
            self.cworld, self.cgridmap = self.world, self.gridmap
            return
        from ..cspace import apply_robot

        if self.world is not None:
            cworld = apply_robot(self.world, self.robot)
            assert isinstance(cworld, World)  # a World's C-space is a World
            self.cworld = cworld
            self.cgridmap = self._rasterize(self.cworld) if self.gridmap is not None else None
        else:
            self.cworld = None
            self.cgridmap = apply_robot(self.gridmap, self.robot) if self.gridmap is not None else None  # type: ignore[assignment]

    # -- toggles ---------------------------------------------------------------------------
    def _set_toggle_label(self, method: str, on: bool) -> None:
        label, key = BUTTONS[method]
        self.buttons[method].label.set_text(f"{label.split(':')[0]}: {'on' if on else 'off'} [{key}]")

    def toggle_movie(self, file: str | FsPath | None = None) -> bool:
        """Arm (or disarm) the movie: the next calculated path is written to :attr:`movie_file`
        (GIF; also MP4 when ffmpeg exists). Returns whether it is armed."""
        if file is not None:
            self.movie_file = FsPath(file)
        self.movie = not self.movie
        if self.movie:
            from ..plot.animation import _check_animation_file

            try:
                _check_animation_file(self.movie_file.with_suffix(".gif"))
            except GridfieldError as e:
                self.movie = False
                self._set_message(f"movie: {e}")
        self._set_toggle_label("toggle_movie", self.movie)
        if self.movie:
            self._set_message(f"movie on: the next path goes to {self.movie_file.with_suffix('.gif')}")
        self.figure.canvas.draw_idle()
        return self.movie

    def toggle_3d(self) -> bool:
        """Show the potential as a 3-D surface with the path (instead of the map), or the map again."""
        self.show_3d = not self.show_3d
        self.ax.set_visible(not self.show_3d)
        self.ax3d.set_visible(self.show_3d)
        self.cax.set_visible(self.field is not None and not self.show_3d)
        self._set_toggle_label("toggle_3d", self.show_3d)
        self._update_3d()
        self.figure.canvas.draw_idle()
        return self.show_3d

    def _update_3d(self) -> None:
        if not self.show_3d:
            return
        from ..plot import plot_surface

        self.ax3d.cla()
        self.surface = None
        if self.field is None:
            self.ax3d.text2D(0.5, 0.5, "the 3-D view shows the potential planner's field", ha="center",  # type: ignore[attr-defined]  # a 3-D Axes
                             transform=self.ax3d.transAxes)
            return
        try:
            self.surface = plot_surface(self.field, self.ax3d, path=self.path, title="potential surface")
        except GridfieldError as e:
            self.ax3d.text2D(0.5, 0.5, str(e), ha="center", transform=self.ax3d.transAxes)  # type: ignore[attr-defined]  # a 3-D Axes

    def _write_movie(self) -> None:
        from matplotlib import animation

        from ..plot import save_plan_animation

        assert self.path is not None
        target = self.cworld if self.planner == "exact-potential" else self.cgridmap
        assert target is not None  # a path was planned on it
        gif = self.movie_file.with_suffix(".gif")
        files = [gif] + ([gif.with_suffix(".mp4")] if animation.writers.is_available("ffmpeg") else [])
        written = []
        for f in files:
            save_plan_animation(f, target, self.path, field=self.field, goal=self.goal, robot_shape=self.robot)
            written.append(f)
        self.movie_written = written
        self.movie = False
        self._set_toggle_label("toggle_movie", False)

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
        """Keys: see :data:`BUTTONS`; ``escape`` abandons the polygon being drawn."""
        if event.key == "escape" and self.drawing:
            self.vertices = []
            self.close_polygon()
            return
        for method, (_, key) in BUTTONS.items():
            if event.key == key:
                getattr(self, method)()
                return

    # -- drawing ---------------------------------------------------------------------------
    def _set_message(self, text: str) -> None:
        self.message = text
        self.status_text.set_text(text if len(text) <= 150 else text[:147] + "...")
        if self.on_message is not None:
            self.on_message(text)

    def _redraw_map(self) -> None:
        """Occupancy, C-space, obstacle outlines and the robot, from the current state."""
        from ..plot.layers import _draw_outlines

        if self.gridmap is not None:
            occ = self.gridmap.occupied
            self.occupancy_image.set_data(np.ma.masked_array(np.ones(occ.shape), mask=~occ))
            grown = self.cgridmap.occupied & ~occ if (self.cspace_on and self.cgridmap is not None) else None
            self.cspace_image.set_data(np.ma.masked_array(np.ones(occ.shape), mask=~grown if grown is not None
                                                          else np.ones(occ.shape, bool)))
        for a in (*self.outlines, *self.cspace_outlines):
            a.remove()
        self.outlines, self.cspace_outlines = [], []
        if self.world is not None:
            self.outlines = _draw_outlines(self.ax, self.world)
        elif self.gridmap is not None and self.gridmap.meta.get("drawn"):
            from matplotlib.collections import PatchCollection
            from matplotlib.patches import Polygon as MplPolygon

            self.outlines = [self.ax.add_collection(PatchCollection(
                [MplPolygon(v, closed=True) for v in self.gridmap.meta["drawn"]], facecolor="none",
                edgecolor="tab:blue", linewidth=1.6, zorder=3))]
        if self.cspace_on and self.cworld is not None and self.cworld is not self.world:
            self.cspace_outlines = self._draw_cspace_outlines(self.cworld)
        self._update_endpoints()

    def _draw_cspace_outlines(self, world: World) -> list[Any]:
        import shapely
        from matplotlib.collections import LineCollection

        rings = []
        for ob in world.obstacles:
            for part in shapely.get_parts(ob.geometry):
                if hasattr(part, "exterior"):
                    rings.append(np.asarray(part.exterior.coords))
                    rings += [np.asarray(r.coords) for r in part.interiors]
                else:
                    rings.append(np.asarray(part.coords).reshape(-1, 2))
        if not rings:
            return []
        return [self.ax.add_collection(LineCollection(rings, colors="#b8860b", linewidths=1.2, linestyles="--",
                                                      zorder=2.5))]

    def _update_endpoints(self) -> None:
        empty = np.empty((0, 2))
        self.start_marker.set_offsets(np.atleast_2d(self.start) if self.start is not None else empty)
        self.goal_marker.set_offsets(np.atleast_2d(self.goal) if self.goal is not None else empty)
        if self.robot is not None and self.start is not None and not self.robot.is_point:
            shape = self.robot.outline(self.start)
            xy = np.asarray(shape.exterior.coords if hasattr(shape, "exterior") else shape.coords, dtype=float)
            self.robot_patch.set_xy(xy)  # type: ignore[attr-defined]  # matplotlib stubs: a Polygon patch at runtime
            self.robot_patch.set_visible(True)
            self.reference_marker.set_offsets(np.atleast_2d(self.start))
        else:
            self.robot_patch.set_visible(False)
            self.reference_marker.set_offsets(empty)

    def _background_field(self) -> Any:
        """The potential planner's field on the planning map, built here only when no plan built it
        (no start yet, a failed plan, a goal found unreachable at once); else None."""
        gm = self.cgridmap
        if self.planner != "potential" or self.goal is None or gm is None:
            return None
        from ..potential import build_field

        try:
            return build_field(gm, np.asarray(self.goal), self.params, dmap=self._incremental_dmap())
        except GridfieldError:
            return None

    def _update_field_image(self) -> None:
        """Background and colour bar: the log-scaled :attr:`field` (the potential planner's), else nothing."""
        from matplotlib.colors import LogNorm

        from ..plot.layers import _potential_scale

        if self.field is None:
            self._hide_field()
            return
        fmap = self.field.map  # the vortex model lives on its own lattice
        u = np.asarray(self.field.potential, dtype=float)
        finite = np.isfinite(u) & ~fmap.occupied
        if not finite.any():
            self._hide_field()
            return
        z, lo, hi, _ = _potential_scale(u, finite, None, True)
        self.field_image.set_data(np.ma.masked_array(z, mask=~finite))
        self.field_image.set_extent(fmap.grid.extent)
        self.field_image.set_norm(LogNorm(vmin=lo, vmax=hi))
        self.field_image.set_visible(True)
        self.colorbar.update_normal(self.field_image)
        self.cax.set_visible(not self.show_3d)  # the 3-D view has its own height axis

    def _hide_field(self) -> None:
        self.field_image.set_visible(False)
        self.cax.set_visible(False)

    def calculate_path(self) -> Path | None:
        """Re-plan now ("calculate path" button); the same as :meth:`recompute`."""
        return self.recompute()

    def recompute(self) -> Path | None:
        """Re-plan with the current start, goal, parameters, planner and configuration space, and
        show the potential the plan followed as the background (built once per update: the
        planner hands it back); write the movie when it is armed.

        Returns
        -------
        Path or None
            The new :attr:`path`; None when the start or goal is missing or the plan failed
            (:attr:`message` says why).
        """
        from ..planners import plan

        self.n_updates += 1
        self.path = None
        self.field = None
        if self.start is None or self.goal is None:
            self.field = self._background_field()
            self._update_field_image()
            self.path_line.set_data([], [])
            self.stall_marker.set_offsets(np.empty((0, 2)))
            self._set_message(f"click on the map to set the {'start' if self.start is None else 'goal'}")
            self._update_3d()
            self.figure.canvas.draw_idle()
            return None
        # exact-potential on a grid map runs on its exact polygons (gridfield.gridpoly, through plan)
        target: World | GridMap | None = (self.cworld if self.planner == "exact-potential" and self.cworld is not None
                                          else self.cgridmap)
        try:
            if target is None:
                raise GridfieldError(f"planner {self.planner!r} needs a vector world, and this map is a grid")
            if self.cspace_on and self.robot is not None:
                from ..cspace import check_robot_point

                for name in ("start", "goal"):
                    check_robot_point(self._workspace(), self.robot, name, getattr(self, name))
            dmap = self._incremental_dmap() if target is self.cgridmap else None
            self.path, field = plan(self.planner, target, self.start, self.goal, self.params, resolution=None,
                                    cache=self._plan_cache(target, dmap), return_field=True)
            self.field = field if self.planner == "potential" else None
        except GridfieldError as e:
            self.field = self._background_field()
            self._update_field_image()
            self.path_line.set_data([], [])
            self.stall_marker.set_offsets(np.empty((0, 2)))
            self._set_message(f"{self.planner}: {e}")
            self._update_3d()
            self.figure.canvas.draw_idle()
            return None
        if self.field is None:  # a goal found unreachable at once: no field was built
            self.field = self._background_field()
        self._update_field_image()
        from ..plot.layers import _stall_points

        pts = self.path.points
        self.path_line.set_data(pts[:, 0], pts[:, 1])
        self.stall_marker.set_offsets(_stall_points(self.path))
        p = self.path
        robot = f", robot {self.robot.describe()}" if (self.cspace_on and self.robot is not None) else ""
        text = (f"{p.planner}: {p.status}, {p.iterations} steps, length {p.length:.4g}, "
                f"{p.seconds * 1e3:.0f} ms{robot}")
        if self.movie:
            try:
                self._write_movie()
                text += "; movie: " + ", ".join(str(f) for f in self.movie_written)
            except GridfieldError as e:
                text += f"; movie not written: {e}"
        self._set_message(text)
        self._update_3d()
        self.figure.canvas.draw_idle()
        return self.path

    # -- incremental updates (gridfield.incremental) ---------------------------------------
    # A drawn obstacle is rasterized alone and burnt into the map; a removed one frees its cells
    # (those another obstacle also covers stay occupied with that obstacle's id). The brushfire of
    # the map the planners get (``cgridmap``) is an IncrementalBrushfire, brought up to date with
    # whatever changed since its last use (a drawn or removed obstacle, undo, clear, the C-space)
    # by the cells that differ; the field background and the potential planner reuse its distance
    # map instead of running a full brushfire.
    _incremental: Any = None
    _incremental_for: GridMap | None = None
    #: An update that changes more than this fraction of the cells rebuilds the brushfire instead.
    INCREMENTAL_MAX_FRACTION = 0.125

    def _burn_obstacle(self, ob: Obstacle, *, drawn: NDArray[np.float64] | None = None) -> GridMap:
        """The workspace map with ``ob``'s cells occupied, rasterized as :func:`gridfield.rasterize.rasterize`
        does (cells already occupied keep their lower id); ``drawn``: the outline to keep in the meta
        of a map without a world."""
        from ..rasterize import _obstacle_mask, _tolerance

        gm = self.gridmap
        assert gm is not None
        new = np.zeros(gm.shape, bool)
        hit = _obstacle_mask(gm.grid, ob, _tolerance(gm.grid))
        if hit is not None:
            (r0, r1, c0, c1), mask = hit
            sl = (slice(r0, r1 + 1), slice(c0, c1 + 1))
            new[sl] = mask & ~gm.occupied[sl]
        ids = None
        if gm.obstacle_id is not None:
            ids = gm.obstacle_id.copy()
            ids[new] = ob.id if ob.id > 0 else int(ids.max(initial=0)) + 1
        meta = dict(gm.meta)
        if drawn is not None:
            meta["drawn"] = [*meta.get("drawn", []), drawn]
        world = self.world if isinstance(gm.world, World) else gm.world
        return GridMap(gm.grid, gm.occupied | new, ids, world, gm.source, meta)

    def _unburn_obstacle(self, ob: Obstacle) -> GridMap:
        """The workspace map without ``ob`` (already removed from ``self.world``): its cells are freed,
        or given to the lowest-id remaining obstacle that covers them (only those are rasterized)."""
        from ..rasterize import _obstacle_mask, _tolerance

        gm = self.gridmap
        assert gm is not None and gm.obstacle_id is not None and self.world is not None
        mine = gm.occupied & (gm.obstacle_id == ob.id)
        occ, ids = gm.occupied & ~mine, np.where(mine, 0, gm.obstacle_id).astype(np.int32)
        if mine.any():
            rows, cols = np.nonzero(mine)
            box = (rows.min(), rows.max(), cols.min(), cols.max())
            eps = _tolerance(gm.grid)
            for other in sorted(self.world.obstacles, key=lambda o: o.id):  # ascending: the lowest id wins
                hit = _obstacle_mask(gm.grid, other, eps)
                if hit is None:
                    continue
                (r0, r1, c0, c1), mask = hit
                if r0 > box[1] or r1 < box[0] or c0 > box[3] or c1 < box[2]:
                    continue
                sl = (slice(r0, r1 + 1), slice(c0, c1 + 1))
                take = mask & mine[sl] & ~occ[sl]
                ids[sl][take] = other.id
                occ[sl] |= take
        return GridMap(gm.grid, occ, ids, self.world, gm.source, dict(gm.meta))

    def remove_obstacle(self, obstacle_id: int) -> None:
        """Remove the world obstacle ``obstacle_id`` (undoable): its cells are freed, the brushfire is
        updated where they were (:mod:`gridfield.incremental`), the C-space rebuilt if on, and the
        path recomputed.

        Raises :class:`ParameterError` when there is no world or no such obstacle.
        """
        if self.world is None or self.gridmap is None or self.gridmap.obstacle_id is None:
            raise ParameterError("only obstacles of a vector world can be removed")
        gone = [o for o in self.world.obstacles if o.id == obstacle_id]
        if not gone:
            raise ParameterError(f"the world has no obstacle {obstacle_id!r}")
        self._push()
        self.world = dataclasses.replace(self.world, obstacles=tuple(o for o in self.world.obstacles
                                                                     if o.id != obstacle_id))
        self.gridmap = self._unburn_obstacle(gone[0])
        self._rebuild_cspace()
        self._redraw_map()
        self.recompute()

    def remove_last_obstacle(self) -> bool:
        """Remove the obstacle with the largest id (the one drawn last); returns whether there was one."""
        if self.world is None or not self.world.obstacles:
            self._set_message("no obstacle to remove")
            self.figure.canvas.draw_idle()
            return False
        self.remove_obstacle(max(o.id for o in self.world.obstacles))
        return True

    def _incremental_sync(self, target: GridMap) -> Any:
        """The IncrementalBrushfire of ``target``: the one kept, updated by the cells where its map and
        ``target`` differ (occupancy or id), or a new one (the first time, another grid, or a change
        of more than :attr:`INCREMENTAL_MAX_FRACTION` of the cells)."""
        from ..incremental import IncrementalBrushfire

        ib = self._incremental
        if ib is not None and self._incremental_for is target:
            return ib
        cur = ib.gridmap if ib is not None else None
        if (cur is None or cur.grid != target.grid or
                (cur.obstacle_id is None) != (target.obstacle_id is None)):
            ib = None
        else:
            freed = cur.occupied & ~target.occupied
            added = target.occupied & ~cur.occupied
            if cur.obstacle_id is not None and target.obstacle_id is not None:
                moved = cur.occupied & target.occupied & (cur.obstacle_id != target.obstacle_id)
            else:
                moved = np.zeros(target.shape, bool)
            n = int(np.count_nonzero(freed)) + int(np.count_nonzero(added)) + int(np.count_nonzero(moved))
            if n > self.INCREMENTAL_MAX_FRACTION * target.occupied.size:
                ib = None
            else:
                out, into = freed | moved, added | moved
                if out.any():
                    ib.update(freed=out)
                if into.any():
                    ids = target.obstacle_id[into] if target.obstacle_id is not None else None
                    ib.update(occupied=into, ids=ids)
        if ib is None:
            ib = IncrementalBrushfire(target, compute_labels=False)
        self._incremental, self._incremental_for = ib, target
        return ib

    def _incremental_dmap(self) -> Any:
        """The incremental distance map of the planning map, when the potential field would compute
        this very one (Khatib model, Euclidean, no saturation; the per-obstacle sum only with world
        obstacle ids, as it then needs no labels); else None (the full brushfire runs)."""
        gm = self.cgridmap
        if self.planner != "potential" or gm is None or self.goal is None:
            return None
        from ..potential import resolve_params

        try:
            p = resolve_params(self.params, unit=gm.grid.resolution)
        except GridfieldError:
            return None
        if p["model"] != "khatib" or p["metric"] != "euclidean" or p["saturate"] is not None or (
                p["repulsion"] != "nearest" and gm.obstacle_id is None):
            return None
        return self._incremental_sync(gm).distance_map

    def _plan_cache(self, target: Any, dmap: Any) -> dict[Any, Any] | None:
        """A :func:`gridfield.planners.plan` cache holding ``dmap``, the brushfire of ``target``
        (:func:`gridfield.follow.plan_potential`'s key: map, metric, saturation)."""
        if dmap is None or target is not self.cgridmap:
            return None
        return {("gridmap", target, None): target, ("brushfire", target, "euclidean", None): dmap}

    def close(self) -> None:
        """Close the figure."""
        import matplotlib.pyplot as plt

        for cid in self.canvas_ids:
            self.figure.canvas.mpl_disconnect(cid)
        plt.close(self.figure)
