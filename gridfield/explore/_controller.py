"""The explorer's controller: :class:`Explorer`, its widgets, mouse and keys, and the public actions.

Each action (a button, a key, a click, or its method called directly) runs one transition of the
model (:mod:`gridfield.explore._model`), then has the view (:mod:`gridfield.explore._view`) redraw
what changed and re-plans (:meth:`Explorer.recompute`). The sliders, the planner's radio buttons
and the buttons are built and kept up to date here.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path as FsPath
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import GridfieldError, ParameterError
from ..core.grid import GridMap
from ..core.path import Path
from ..geometry.world import Robot, World
from ._model import EXPLORER_PLANNERS, SLIDER_PARAMS, _State, available_planners
from ._view import ROBOT_COLOR, ExplorerView

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


class Explorer(ExplorerView):
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
        # the model (state, C-space) and the view (figure, map layer) first, then the controls
        super().__init__(target, params=params, planner=planner, resolution=resolution, start=start, goal=goal,
                         robot=robot, on_message=on_message, figsize=figsize)
        self.movie = False
        self.movie_file = FsPath(movie_file) if movie_file is not None else FsPath("gridfield_movie.gif")
        self.movie_written: list[FsPath] = []
        self.drawing = False
        self.draw_mode = "obstacle"
        self.vertices: list[tuple[float, float]] = []
        self._next_click = "start" if self.start is None else ("goal" if self.goal is None else "start")
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

    # -- widgets ---------------------------------------------------------------------------
    def _slider_range(self, name: str, value: float | None = None) -> tuple[float, float]:
        """A slider's range: centred on ``value`` (the value in use, e.g. the default scaled to the
        map), so it starts in the middle and can go either way: 0 to twice it for the gains (``zeta``,
        ``eta``), a tenth of it to 1.9 times it for the lengths (which must stay > 0); the fixed
        ranges below for a value that is 0, infinite (d_star's right end) or not given."""
        if value is not None and math.isfinite(value) and value > 0:
            lo = 0.0 if name in ("zeta", "eta") else value / 10.0
            return lo, 2.0 * value - lo
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
        # every slider shows the value in use: the given one, or the registry's default scaled to the map
        in_use = self._params_in_use()
        for i, name in enumerate(SLIDER_PARAMS):
            v = float(in_use[name])
            lo, hi = self._slider_range(name, v)
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
        used = self.sliders_in_use()
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
        if name == "model":
            self._update_sliders()
        self.recompute()

    def set_planner(self, name: str | None) -> None:
        """Switch planner (radio button callback), show its sliders only, and recompute."""
        if name is None or name == self.planner:
            return
        self._use_planner(name)
        labels = [t.get_text() for t in self.radio.labels] if self.radio is not None else []
        if self.radio is not None and name in labels and self.radio.value_selected != name:
            self.radio.set_active(labels.index(name))  # calls back into set_planner, which returns early
        self._update_sliders()
        self.recompute()

    # -- undo ------------------------------------------------------------------------------
    def _restore(self, s: _State) -> None:
        self._restore_state(s)
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

    def _set_endpoint(self, which: str, p: tuple[float, float], *, push: bool = True) -> bool:
        why = self._is_free(p)
        if why is not None:
            self._set_message(f"{which} not set: {why.replace('point', which, 1)}")
            self.figure.canvas.draw_idle()
            return False
        self._move_endpoint(which, p, push=push)
        if self.on_message is not None:
            self.on_message(f"{which} set to ({p[0]:.4g}, {p[1]:.4g})")
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
        self._add_obstacle(vertices)
        self._redraw_map()
        self.recompute()

    def set_robot(self, robot: Robot | float | ArrayLike | None, *, at: tuple[float, float] | None = None) -> None:
        """Set the robot: a radius, a convex polygon around its reference point, or None (a point).

        With ``at``, the start moves there (the drawn robot's reference point) when it is free.
        When the C-space is on it is rebuilt for the new robot. Raises :class:`ParameterError`
        for a non-convex polygon.
        """
        r = self._set_robot(robot)
        self._redraw_map()
        if at is not None and self._is_free(at) is None:
            self._move_endpoint("start", at, push=False)
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
        self._turn_cspace_on()
        self._redraw_map()
        self.recompute()
        return True

    def remove_obstacle(self, obstacle_id: int) -> None:
        """Remove the world obstacle ``obstacle_id`` (undoable): its cells are freed, the brushfire is
        updated where they were (:mod:`gridfield.distance.incremental`), the C-space rebuilt if on, and the
        path recomputed.

        Raises :class:`ParameterError` when there is no world or no such obstacle.
        """
        self._remove_obstacle(obstacle_id)
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
            from ..plot import check_animation_file

            try:
                check_animation_file(self.movie_file.with_suffix(".gif"))
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

    def _write_movie(self) -> None:
        from ..plot import ffmpeg_missing, save_plan_animation

        assert self.path is not None
        target = self._plan_target()
        assert target is not None  # a path was planned on it
        gif = self.movie_file.with_suffix(".gif")
        # an MP4 too where ffmpeg runs: a system one, or imageio-ffmpeg's (the [video] extra)
        files = [gif] + ([gif.with_suffix(".mp4")] if ffmpeg_missing() is None else [])
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

    # -- planning --------------------------------------------------------------------------
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
        try:
            path = self._plan()
        except GridfieldError as e:
            self._draw_no_path(f"{self.planner}: {e}")
            return None
        if path is None:
            self._draw_no_path(f"click on the map to set the {'start' if self.start is None else 'goal'}")
            return None
        self._draw_path()
        p = path
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

    def close(self) -> None:
        """Close the figure."""
        import matplotlib.pyplot as plt

        for cid in self.canvas_ids:
            self.figure.canvas.mpl_disconnect(cid)
        plt.close(self.figure)
