"""The planner registry's table: each planner's module, function, kind and the parameters it reads.

A leaf (it imports nothing of gridfield), so that both :mod:`gridfield.planners` (the dispatcher,
which re-exports :data:`PLANNERS`) and :mod:`gridfield.core.params` (whose "read by" lists are derived
from the ``reads`` here) can import it. Adding a planner is one entry here and its module.
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["PLANNERS", "Planner"]


class Planner(NamedTuple):
    """One planner of :data:`PLANNERS`.

    Parameters
    ----------
    module : str
        The module defining it (imported only when the planner is used).
    function : str
        ``fn(target, start, goal, params) -> Path`` in that module.
    kind : {"grid", "world"}
        What it plans on: a GridMap or a World.
    reads : tuple of str
        The parameters (names of :data:`gridfield.core.params.REGISTRY`) it reads; their "read by"
        lists in ``--help`` and the docs are derived from these.

    Returns
    -------
    Planner
        A named tuple; ``module, function, kind, reads = entry``.

    Examples
    --------
    >>> p = PLANNERS["wavefront"]
    >>> p.kind, p.reads
    ('grid', ('q_star', 'clearance_weight', 'connectivity'))
    """

    module: str
    function: str
    kind: str
    reads: tuple[str, ...] = ()


# what several planners read (names of gridfield.core.params.REGISTRY)
_FIELD = ("zeta", "d_star", "eta", "q_star", "repulsive_power", "repulsion", "saturate")
_FOLLOWER = ("step_rule", "step", "alpha", "min_speed", "tolerance", "max_iterations", "gradient_threshold",
             "progress_window", "confine_window", "escape", "escape_tries", "escape_radius", "seed")
_PATH = ("step", "tolerance", "max_iterations")  # following a navigation function's gradient
_GRID_NAV = ("q_star", "clearance_weight")  # the clearance cost of a grid navigation function

#: name -> :class:`Planner` (module, function, kind, reads); kind "grid" needs a GridMap, "world" a World.
PLANNERS: dict[str, Planner] = {
    "potential": Planner("gridfield.following.follower", "plan_potential", "grid",
                         (*_FIELD, "metric", "gradient", "model", "ka", "kr", "ko", "spacing", "sample_radius",
                          "attraction", "clearance_gain", "clearance_band", "band_gain", *_FOLLOWER, "sampling")),
    "exact-potential": Planner("gridfield.exact.continuous", "plan_exact_potential", "world",
                               (*_FIELD, "model", *_FOLLOWER)),  # model: only 'khatib' (it refuses 'vortex')
    "visibility": Planner("gridfield.exact.visibility", "plan_visibility", "world"),
    "wavefront": Planner("gridfield.fields.navigation", "plan_wavefront", "grid", (*_GRID_NAV, "connectivity")),
    "wavefront-octile": Planner("gridfield.fields.navigation", "plan_wavefront_octile", "grid", (*_GRID_NAV, "connectivity")),
    "fmm": Planner("gridfield.fields.navigation", "plan_fmm", "grid", (*_GRID_NAV, *_PATH)),
    "harmonic": Planner("gridfield.fields.navigation", "plan_harmonic", "grid"),  # the field has no parameter
    "navfn": Planner("gridfield.fields.navfn", "plan_navfn", "grid",  # Nav2's NavFn on the (inflated) costmap
                     ("allow_unknown", "goal_tolerance", "robot_radius", "inflation_radius", "cost_scaling_factor",
                      "lut_precision")),
    "sphere-nav": Planner("gridfield.fields.navigation", "plan_sphere_nav", "world",
                          (*_PATH, "progress_window", "kappa", "workspace_center", "workspace_radius")),
    "star-nav": Planner("gridfield.fields.navigation", "plan_star_nav", "world",
                        (*_PATH, "progress_window", "kappa", "lambda", "workspace_center", "workspace_radius")),
}
