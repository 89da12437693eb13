"""The field behind any navigation-function planner, by name: the one table that knows every grid-field
construction of :mod:`gridfield.fields.navigation`, and Nav2's NavFn (:mod:`gridfield.fields.navfn`), which
builds on that package (so the table sits above both, and neither imports the other back).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, cast

from numpy.typing import ArrayLike

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ..core.params import Navigation, validate
from .navfn import navfn
from .navigation import NavigationField, fmm, grid_options, harmonic, sphere_nav_field, wavefront

__all__ = ["navigation_field"]


def navigation_field(gridmap: GridMap, goal: ArrayLike, planner_name: str,
                     params: Mapping[str, Any] | None = None) -> NavigationField:
    """The field behind a navigation-function planner (for ``gridfield field``).

    Parameters
    ----------
    gridmap : GridMap
    goal : (x, y)
    planner_name : {"wavefront", "wavefront-octile", "fmm", "harmonic", "navfn", "sphere-nav"}
    params : mapping
        Planner parameters (``connectivity``, ``clearance_weight``, ``q_star``, ``kappa``, checked by the
        registry); its other parameters are ignored.
        ``sphere-nav`` needs the map to have been rasterized from a world of circles; without ``kappa``
        it uses the number of obstacles + 1.

    Returns
    -------
    NavigationField
        With ``potential`` (= ``value``), ``grad_x`` and ``grad_y`` arrays of the grid's shape.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> nav = navigation_field(GridMap(Grid((1, 3), 1.0), np.zeros((1, 3), bool)), (0.5, 0.5), "wavefront", {})
    >>> nav.potential, nav.grad_x
    (array([[0., 1., 2.]]), array([[0., 1., 1.]]))
    """
    p = validate(params)
    nav = p.group(Navigation)
    if planner_name == "wavefront":
        return wavefront(gridmap, goal, connectivity=nav.connectivity, costs="unit", **grid_options(p))
    if planner_name == "wavefront-octile":
        return wavefront(gridmap, goal, connectivity=nav.connectivity, costs="octile", **grid_options(p))
    if planner_name == "fmm":
        return fmm(gridmap, goal, **grid_options(p))
    if planner_name == "harmonic":
        return harmonic(gridmap, goal)
    if planner_name == "navfn":  # Nav2's NavFn on the map's (inflated) costmap, from the goal over the whole map
        navfn_names = ("allow_unknown", "goal_tolerance", "robot_radius", "inflation_radius", "cost_scaling_factor",
                       "lut_precision")
        return cast(NavigationField, navfn(gridmap, goal, params={k: v for k, v in p.items() if k in navfn_names}))
    if planner_name == "sphere-nav":
        return sphere_nav_field(gridmap, goal, nav)
    raise ParameterError(
        f"unknown navigation planner {planner_name!r}; expected one of wavefront, wavefront-octile, fmm, harmonic, navfn, sphere-nav"
    )
