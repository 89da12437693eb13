"""Star worlds: the Rimon-Koditschek navigation function through the star-to-sphere transformation.

A *star world* is a disc workspace holding disjoint obstacles that are each star-shaped about a
centre ``q_i`` (polygons whose kernel contains ``q_i``, and discs). The star-to-sphere transformation
``h_lambda`` maps it onto a *sphere world* (model discs ``(p_i, r_i)`` in the same workspace), where
the sphere-world navigation function ``phi`` of :func:`gridfield.navigation.sphere_nav_function` is
known; ``phi(h_lambda(q))`` is then a navigation function of the star world (Rimon & Koditschek,
"Exact robot navigation using artificial potential functions", IEEE Trans. Robotics and Automation
8(5), 1992; Choset et al., *Principles of Robot Motion*, sec. 4.6; seed 002, third question).

The planner ``star-nav`` (:func:`~gridfield.navigation.plan_star_nav`) follows ``-grad phi(h_lambda(q))``
like ``sphere-nav``. :func:`~gridfield.navigation.star_nav_field` gives the arrays of
``gridfield field --planner star-nav`` and the seed's figures (:func:`gridfield.plot.plot_star_world`).

The implementation lives in :mod:`gridfield.navigation`, whose page documents these functions and
classes: its private submodules ``_star_obstacle`` (star-shaped obstacles and their smooth
R-function obstacle functions, with the construction and the proof of the sign), ``_star_world``
(the star world and the star-to-sphere transformation) and ``_star_nav`` (the choice of ``kappa``,
the check of ``lambda``, the follower, the planner, the field and the figure data). This module
re-exports them: ``from gridfield.star import X`` works for every name of its ``__all__``, and
for the other names of the former single-file module that callers use (``folds``,
``star_figure_data``, the constants, ``_choose_kappa``).
"""

from __future__ import annotations

from .navigation._star_nav import CLEARANCE_STEP as CLEARANCE_STEP
from .navigation._star_nav import KAPPA_LADDER as KAPPA_LADDER
from .navigation._star_nav import (
    StarNavWarning,
    follow_star_nav,
    plan_star_nav,
    spurious_minima,
    star_nav_field,
)
from .navigation._star_nav import _choose_kappa as _choose_kappa
from .navigation._star_nav import folds as folds
from .navigation._star_nav import star_figure_data as star_figure_data
from .navigation._star_obstacle import R_ALPHA as R_ALPHA
from .navigation._star_obstacle import R_EPS as R_EPS
from .navigation._star_obstacle import StarObstacle, find_star_center
from .navigation._star_world import StarWorld, nav_function, star_betas, star_to_sphere, star_world

__all__ = [
    "StarNavWarning",
    "StarObstacle",
    "StarWorld",
    "find_star_center",
    "follow_star_nav",
    "nav_function",
    "plan_star_nav",
    "spurious_minima",
    "star_betas",
    "star_nav_field",
    "star_to_sphere",
    "star_world",
]
