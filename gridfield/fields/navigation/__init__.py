"""Navigation functions: potentials whose only minimum is the goal (Choset et al. sec. 4.5-4.6).

Five constructions, the first four returned as a :class:`NavigationField` (the value array and its grid):

- :func:`wavefront` -- the grid navigation function: the exact shortest-path cost to the goal cell
  over 4- or 8-connected moves, with unit costs or octile costs (1 and sqrt 2), optionally raised near
  obstacles (``clearance_weight``). Diagonal moves never cut a corner: a diagonal step is allowed only
  when both orthogonally adjacent cells are free (the Moving AI rule), or when the map's
  :attr:`~gridfield.core.grid.GridMap.diagonals` allow it (a disc robot's configuration space). Computed by Dijkstra with a
  bucket queue in a compiled kernel; :func:`extract_path` follows it down to the goal.
- :func:`fmm` -- the Euclidean geodesic distance by fast marching (scikit-fmm, optional extra
  ``gridfield[fmm]``), followed along its interpolated gradient: near-any-angle paths.
- :func:`harmonic` -- a solution of Laplace's equation (goal 0, obstacles and border 1), solved with a
  sparse preconditioned conjugate-gradient method. Far from the goal the harmonic function underflows;
  the field is continued by nested "shells" in log scale (see :func:`harmonic`).
- :func:`sphere_nav_function` -- the Rimon-Koditschek navigation function of a sphere world (disc
  obstacles inside a disc workspace), with its analytic gradient.
- star worlds -- the same function on a world of star-shaped polygons and discs, through the
  star-to-sphere transformation :func:`star_to_sphere`: :func:`star_world` (a :class:`StarWorld` of
  :class:`StarObstacle`), :func:`nav_function`, :func:`spurious_minima`, :func:`choose_kappa`,
  :func:`folds`, :func:`follow_star_nav`; :func:`star_nav_field` is its :class:`NavigationField`
  and :func:`star_figure_data` the arrays of its figures.

The planners ``wavefront``, ``wavefront-octile``, ``fmm``, ``harmonic``, ``sphere-nav`` and ``star-nav``
of :mod:`gridfield.planners` are :func:`plan_wavefront`, :func:`plan_wavefront_octile`, :func:`plan_fmm`,
:func:`plan_harmonic`, :func:`plan_sphere_nav` and :func:`plan_star_nav`; :func:`gridfield.fields.navtable.navigation_field` gives
the field of any of the first five (``gridfield field``; ``star-nav``'s is :func:`star_nav_field`).

Star worlds. A *star world* is a disc workspace holding disjoint obstacles that are each star-shaped about a
centre ``q_i`` (polygons whose kernel contains ``q_i``, and discs). The star-to-sphere transformation
``h_lambda`` maps it onto a *sphere world* (model discs ``(p_i, r_i)`` in the same workspace), where
the sphere-world navigation function ``phi`` of :func:`gridfield.fields.navigation.sphere_nav_function` is
known; ``phi(h_lambda(q))`` is then a navigation function of the star world (Rimon & Koditschek,
"Exact robot navigation using artificial potential functions", IEEE Trans. Robotics and Automation
8(5), 1992; Choset et al., *Principles of Robot Motion*, sec. 4.6; seed 002, third question).

The planner ``star-nav`` (:func:`~gridfield.fields.navigation.plan_star_nav`) follows ``-grad phi(h_lambda(q))``
like ``sphere-nav``. :func:`~gridfield.fields.navigation.star_nav_field` gives the arrays of
``gridfield field --planner star-nav`` and the seed's figures (:func:`gridfield.plot.plot_star_world`).

Units: every value array is in world units (lengths, or costs measured as lengths), and every point
crosses the public boundary as world coordinates ``(x, y)``; arrays are indexed ``[row, col]`` with
row 0 the lowest y, as everywhere in gridfield. What lies outside the grid is never traversed by
the grid navigation functions, whatever the grid's ``border`` (the harmonic one treats it as a wall
at value 1).

Layout of the package (one construction per module, all of them sharing ``_field``): ``_field``
(:class:`NavigationField`, :func:`extract_path`, the shared checks and the planner adapter),
``_wavefront`` (:func:`wavefront`, :func:`clearance_cost`), ``_fmm``, ``_harmonic``, ``_sphere``
(sphere worlds), and star worlds in three modules: ``_star_obstacle`` (star-shaped obstacles and
their smooth R-function obstacle functions), ``_star_world`` (the star world, its scaled obstacle
functions and the star-to-sphere transformation, built on ``_sphere``'s terms) and ``_star_nav``
(``kappa`` and ``lambda`` checks, the follower, the planner, the field and the figure data); this
``__init__`` re-exports their public names; :func:`gridfield.fields.navtable.navigation_field`, the one
function that knows every grid-field construction (NavFn's too, which builds on this package), is a layer
above, in :mod:`gridfield.fields.navtable`. ``gridfield.star``, which re-exported the star names, is a
deprecated alias for one release. The submodules are private: import from
``gridfield.fields.navigation``. (They carry a leading underscore also because ``wavefront``, ``fmm`` and
``harmonic`` are the names of functions of the package, which a submodule of the same name would
shadow.)
"""

from __future__ import annotations

# Besides __all__, the names of the single-file module that callers use stay importable from here
# (``X as X`` marks a re-export), among them the sphere-world terms the star worlds reuse.
from ._field import COSTS as COSTS
from ._field import KINDS, NavigationField, extract_path, grid_options
from ._field import SQRT2 as SQRT2
from ._field import upwind_gradient as upwind_gradient
from ._fmm import fmm, plan_fmm
from ._harmonic import MIC_OMEGA as MIC_OMEGA
from ._harmonic import SOLVERS as SOLVERS
from ._harmonic import harmonic, plan_harmonic
from ._sphere import KAPPA_LADDER as KAPPA_LADDER
from ._sphere import _rk_phi_grad as _rk_phi_grad
from ._sphere import _rk_terms as _rk_terms
from ._sphere import plan_sphere_nav, sphere_nav_field, sphere_nav_function
from ._star_nav import CLEARANCE_STEP as CLEARANCE_STEP
from ._star_nav import (
    StarNavWarning,
    choose_kappa,
    folds,
    follow_star_nav,
    plan_star_nav,
    spurious_minima,
    star_figure_data,
    star_nav_field,
)
from ._star_obstacle import R_ALPHA as R_ALPHA
from ._star_obstacle import R_EPS as R_EPS
from ._star_obstacle import StarObstacle, find_star_center
from ._star_world import StarWorld, nav_function, star_betas, star_to_sphere, star_world
from ._wavefront import clearance_cost, plan_wavefront, plan_wavefront_octile, wavefront

__all__ = [
    "KINDS",
    "NavigationField",
    "StarNavWarning",
    "StarObstacle",
    "StarWorld",
    "choose_kappa",
    "clearance_cost",
    "extract_path",
    "find_star_center",
    "fmm",
    "folds",
    "follow_star_nav",
    "grid_options",
    "harmonic",
    "nav_function",
    "plan_fmm",
    "plan_harmonic",
    "plan_sphere_nav",
    "plan_star_nav",
    "plan_wavefront",
    "plan_wavefront_octile",
    "sphere_nav_field",
    "sphere_nav_function",
    "spurious_minima",
    "star_betas",
    "star_figure_data",
    "star_nav_field",
    "star_to_sphere",
    "star_world",
    "wavefront",
]
