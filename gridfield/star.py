"""Deprecated: star worlds live in :mod:`gridfield.navigation`.

``from gridfield.star import X`` still works for one release, with a :class:`DeprecationWarning`,
for every name the former module exported (``star_world``, ``StarWorld``, ``nav_function``,
``plan_star_nav``, ``star_figure_data``, ``folds``, the constants, ...): import them from
:mod:`gridfield.navigation`, whose API page documents them. ``_choose_kappa`` is now
:func:`gridfield.navigation.choose_kappa`.
"""

from __future__ import annotations

from typing import Any

__all__: list[str] = []

_MOVED = frozenset({
    "CLEARANCE_STEP", "KAPPA_LADDER", "R_ALPHA", "R_EPS", "StarNavWarning", "StarObstacle", "StarWorld",
    "find_star_center", "folds", "follow_star_nav", "nav_function", "plan_star_nav", "spurious_minima",
    "star_betas", "star_figure_data", "star_nav_field", "star_to_sphere", "star_world",
})


def __getattr__(name: str) -> Any:
    """``gridfield.star.X``: deprecated alias of ``gridfield.navigation.X``."""
    new = "choose_kappa" if name == "_choose_kappa" else name
    if name in _MOVED or name == "_choose_kappa":
        import importlib
        import warnings

        warnings.warn(f"gridfield.star.{name} is deprecated: import gridfield.navigation.{new}",
                      DeprecationWarning, stacklevel=2)
        return getattr(importlib.import_module("gridfield.navigation"), new)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
