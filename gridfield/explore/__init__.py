"""An interactive explorer: the seed 004 workflow on a matplotlib figure, in a window, a browser or Jupyter.

:class:`Explorer` is a thin matplotlib layer over the library: every update calls
:func:`gridfield.planners.plan` on the map, or on its configuration space
(:func:`gridfield.geometry.cspace.apply_robot`) once a robot is drawn and the C-space computed, so what the
explorer shows is exactly what ``gridfield plan`` computes. The potential planner's background is
the field that plan followed (``plan_with_field(...)``): one build per update.

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
:class:`gridfield.distance.incremental.IncrementalBrushfire` of the planning map, updated by the cells that
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

Layout of the package (one job per module; the submodules are private: import from
``gridfield.explore``): ``_model`` is the explorer without a figure (:class:`_model.ExplorerModel`:
the state, the undo stack, the transitions that rasterize a drawn obstacle, rebuild the C-space and
keep the incremental brushfire, planning: ``_plan``; :data:`EXPLORER_PLANNERS`,
:data:`SLIDER_PARAMS`, :data:`PLANNER_SLIDERS`, :func:`available_planners`); ``_view`` is the
figure over it (:class:`_view.ExplorerView`: the axes, the map layer, the colour bar, the 3-D
surface, the status line; it draws what the model holds and computes nothing); ``_controller`` is
:class:`Explorer` itself (the widgets, the mouse and keys, :data:`BUTTONS`, the public actions: a
model transition, then a redraw and a re-plan, and the movie).
"""

from __future__ import annotations

# Besides __all__, the public names of the single-file module stay importable from here (``X as X``
# marks a re-export): the colours CSPACE_COLOR and ROBOT_COLOR.
from ._controller import BUTTONS as _BUTTONS
from ._controller import Explorer
from ._model import EXPLORER_PLANNERS as _EXPLORER_PLANNERS
from ._model import PLANNER_SLIDERS as _PLANNER_SLIDERS
from ._model import SLIDER_PARAMS as _SLIDER_PARAMS
from ._model import available_planners
from ._view import CSPACE_COLOR as CSPACE_COLOR
from ._view import ROBOT_COLOR as ROBOT_COLOR

# The constants are owned by ``_model`` (planners, sliders) and ``_controller`` (buttons); assigned here to
# document them on this page.
#: Planners the explorer offers, in order, when their module is installed.
EXPLORER_PLANNERS = _EXPLORER_PLANNERS
#: Parameters with a slider.
SLIDER_PARAMS = _SLIDER_PARAMS
#: The sliders each planner reads (the others are hidden while it is selected).
PLANNER_SLIDERS = _PLANNER_SLIDERS
#: Buttons: name -> (label, key). Each calls the method of the same name.
BUTTONS = _BUTTONS

__all__ = ["BUTTONS", "EXPLORER_PLANNERS", "PLANNER_SLIDERS", "SLIDER_PARAMS", "Explorer", "available_planners"]
