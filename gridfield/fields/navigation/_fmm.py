"""The fast-marching navigation function (scikit-fmm, optional extra ``gridfield[fmm]``).

Fast marching approximates the Euclidean geodesic distance, so following its interpolated gradient gives
near-any-angle paths, where the wavefront's paths are 8-connected cell chains. scikit-fmm is imported
only when a field is built: gridfield works without it.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core.errors import GridfieldError, ParameterError
from ...core.grid import GridMap
from ...core.params import validate
from ...core.path import Path
from ._field import NavigationField, _check_weight, _goal_cell, _plan_grid, grid_options
from ._wavefront import clearance_cost


# ----------------------------------------------------------------------------------------------
# Fast marching
# ----------------------------------------------------------------------------------------------
def fmm(
    gridmap: GridMap,
    goal: ArrayLike,
    *,
    clearance_weight: float = 0.0,
    q_star: float | None = None,
    order: int = 2,
) -> NavigationField:
    """Euclidean geodesic distance to the goal cell by the fast marching method (scikit-fmm).

    The front starts at the goal cell's centre (value 0) and cannot enter obstacle cells; cells it
    never reaches get ``inf``. With ``clearance_weight > 0`` the front moves at speed
    ``1 / clearance_cost`` (the value is then a travel cost, as for :func:`wavefront`).

    Requires the optional dependency scikit-fmm (``pip install gridfield[fmm]``).

    Parameters
    ----------
    gridmap : GridMap
    goal : (x, y)
        Goal point (world coordinates), in a free cell.
    clearance_weight : float
        0 (default) for the geodesic distance; otherwise the travel cost with speed
        ``1 / clearance_cost`` (see :func:`clearance_cost`).
    q_star : float, optional
        Distance of influence of the clearance cost (default 5 cells).
    order : {2, 1}
        Order of scikit-fmm's finite differences.

    Returns
    -------
    NavigationField
        ``kind="fmm"``; ``value`` is ``inf`` on obstacles and on cells the front never reaches;
        ``aux["cost"]`` holds the cell costs when ``clearance_weight > 0``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> nav = fmm(GridMap(Grid((1, 4), 0.5), np.zeros((1, 4), bool)), (0.25, 0.25))
    >>> nav.value
    array([[0. , 0.5, 1. , 1.5]])
    """
    try:
        import skfmm
    except ImportError:
        raise GridfieldError(
            "the fmm navigation function needs scikit-fmm: pip install gridfield[fmm] (or pip install scikit-fmm)"
        ) from None
    if order not in (1, 2):
        raise ParameterError(f"order must be 1 or 2, got {order!r}")
    w = _check_weight(clearance_weight)
    g, (gr, gc) = _goal_cell(gridmap, goal)
    res = gridmap.grid.resolution
    phi = np.ones(gridmap.shape)
    phi[gr, gc] = 0.0
    masked = np.ma.MaskedArray(phi, gridmap.occupied.copy())
    aux: dict[str, Any] = {}
    if w > 0:
        cost = clearance_cost(gridmap, w, q_star)
        speed = np.where(gridmap.occupied, 1.0, 1.0 / np.where(np.isfinite(cost), cost, 1.0))
        t = skfmm.travel_time(masked, speed, dx=res, order=order)
        aux["cost"] = cost
    else:
        t = skfmm.distance(masked, dx=res, order=order)
    value = np.ma.filled(np.ma.asarray(t, dtype=np.float64), np.inf)
    value[gridmap.occupied] = np.inf
    value[gr, gc] = 0.0
    params = {"clearance_weight": w, "q_star": q_star, "order": order}
    return NavigationField(gridmap, value, g, (gr, gc), "fmm", params, aux)


def plan_fmm(gridmap: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64],
             params: Mapping[str, Any], *, cache: dict[Any, Any] | None = None) -> Path:
    """Planner ``fmm``: fast-marching geodesic distance followed along its gradient (``step``, at most
    one cell, default half a cell; ``tolerance``; ``max_iterations``; optional ``clearance_weight``/``q_star``).

    Parameters
    ----------
    gridmap : GridMap
    start, goal : ndarray, shape (2,)
        World points in free cells (checked by :func:`gridfield.planners.plan`).
    params : mapping
        Validated planner parameters (:mod:`gridfield.core.params`); read here: ``clearance_weight``,
        ``q_star``, ``step``, ``tolerance``, ``max_iterations``.

    Returns
    -------
    Path
        From :func:`extract_path`: ``points`` from ``start`` to ``goal``, ``status``, ``params`` (the
        given ones and the field's), ``extra`` with ``value``, ``grid_length`` and ``field_seconds``.

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> m = GridMap(Grid((10, 10), 1.0), np.zeros((10, 10), bool))
    >>> p = plan_fmm(m, np.array([0.5, 0.5]), np.array([9.5, 6.5]), {})
    >>> p.status, round(p.length, 1)
    ('reached', 10.8)
    """
    params = validate(params)  # a raw mapping from a direct call is checked too
    t0 = time.perf_counter()
    nav = fmm(gridmap, goal, **grid_options(params))
    if params.get("step") is not None:  # a world's step for the potential follower may exceed a cell
        params = {**params, "step": min(float(params["step"]), gridmap.grid.resolution)}
    return _plan_grid(nav, start, params, "fmm", time.perf_counter() - t0)
