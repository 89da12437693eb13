"""The grid navigation function (wavefront) and its clearance cost.

The wavefront is the exact shortest-path cost to the goal cell over 4- or 8-connected moves with unit
or octile costs, optionally raised near obstacles by :func:`clearance_cost`. It is the only navigation
function that is exact on the grid itself (no discretization of a continuous equation), which is why
the navigation escape, the incremental updates and the Moving AI checks all build on it. The cell loop
(Dijkstra with a bucket queue) is a compiled kernel (``gridfield/fields/_navigation.pyx``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core.errors import GridfieldError, ParameterError
from ...core.grid import GridMap
from ...core.params import Navigation, validate
from ...core.path import Path
from ._field import (
    COSTS,
    SQRT2,
    NavigationField,
    _check_connectivity,
    _check_weight,
    _goal_cell,
    _kernel_navigation,
    _plan_grid,
    grid_options,
)


def clearance_cost(gridmap: GridMap, clearance_weight: float, q_star: float | None = None) -> NDArray[np.float64]:
    """Cell cost of the clearance-aware navigation functions:
    ``1 + clearance_weight * max(0, 1 - D / q_star)``, with ``D`` the Euclidean brushfire distance
    from the cell centre to the nearest obstacle cell centre (world units).

    A cell next to an obstacle (``D = resolution``) costs almost ``1 + clearance_weight``; the extra cost
    falls linearly to 0 at ``D = q_star`` (default: 5 cells), like the inflation layer of a ROS
    costmap used by navfn. A step between cells costs its length times the mean of the two cell costs.
    Obstacle cells get ``inf``.

    Parameters
    ----------
    gridmap : GridMap
    clearance_weight : float
        Extra cost next to an obstacle (finite, >= 0; 0 gives cost 1 on every free cell).
    q_star : float, optional
        Distance of influence (world units, > 0); default 5 cells.

    Returns
    -------
    ndarray of float64, shape ``gridmap.shape``
        The cell costs: >= 1 on free cells, ``inf`` on obstacle cells.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((1, 5), bool); occ[0, 0] = True
    >>> clearance_cost(GridMap(Grid((1, 5), 1.0), occ), 2.0, q_star=4.0)
    array([[inf, 2.5, 2. , 1.5, 1. ]])
    """
    from ...distance.brushfire import brushfire

    w = _check_weight(clearance_weight)
    res = gridmap.grid.resolution
    q = 5.0 * res if q_star is None else float(q_star)
    if not (math.isfinite(q) and q > 0):
        raise ParameterError(f"q_star must be a positive finite distance, got {q_star!r}")
    d = brushfire(gridmap, metric="euclidean").distance
    with np.errstate(invalid="ignore"):
        cost = 1.0 + w * np.clip(1.0 - d / q, 0.0, None)
    cost[~np.isfinite(d)] = 1.0  # no obstacle anywhere
    cost[gridmap.occupied] = np.inf
    return cost


# ----------------------------------------------------------------------------------------------
# Wavefront (grid navigation function)
# ----------------------------------------------------------------------------------------------
def wavefront(
    gridmap: GridMap,
    goal: ArrayLike,
    *,
    connectivity: int = 8,
    costs: Literal["unit", "octile"] = "unit",
    clearance_weight: float = 0.0,
    q_star: float | None = None,
    stop_at: ArrayLike | None = None,
) -> NavigationField:
    """The grid navigation function: shortest-path cost from every cell to the goal cell.

    Parameters
    ----------
    gridmap : GridMap
    goal : (x, y)
        Goal point (world coordinates); it must lie in a free cell of the grid.
    connectivity : {8, 4}
        Moves to the 8 or 4 neighbours. Diagonal moves never cut a corner: a diagonal step is allowed
        only when both orthogonally adjacent cells are free (the Moving AI rule), or when the map's
        :attr:`~gridfield.core.grid.GridMap.diagonals` allow it (a disc robot's configuration space: the
        diagonals the robot fits along though a side cell is blocked).
    costs : {"unit", "octile"}
        ``"unit"``: every move costs one cell (Choset's wavefront, chessboard/taxicab steps);
        ``"octile"``: orthogonal moves cost 1, diagonal ones sqrt 2 (the Moving AI benchmark metric).
        Values are multiplied by the resolution (world units).
    clearance_weight : float
        0 (default) for plain costs; otherwise each step's cost is multiplied by the mean
        :func:`clearance_cost` of its two cells, so that paths keep away from obstacles.
    q_star : float, optional
        Distance of influence of the clearance cost (default 5 cells).
    stop_at : (x, y), optional
        End the search once the cell containing this point is settled (a point-to-point query). Values
        up to that cell's value are exact; larger ones are upper bounds or ``inf``.

    Returns
    -------
    NavigationField
        ``kind="wavefront"``; ``value`` is ``inf`` on obstacles and unreachable cells.

    Notes
    -----
    Dijkstra's algorithm with a bucket queue (Dial): buckets hold cells by ``floor(cost)`` in cells,
    and since every step costs at least one cell, a bucket's cells are final when it is reached and
    need no ordering. With octile costs only three buckets are ever live. The values are exact sums of
    step costs (floating point).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
    >>> m = GridMap(Grid((3, 3), 1.0), occ)
    >>> wavefront(m, (0.5, 0.5), costs="octile").value  # no diagonal step past the blocked centre
    array([[ 0.,  1.,  2.],
           [ 1., inf,  3.],
           [ 2.,  3.,  4.]])
    >>> wavefront(GridMap(Grid((2, 3), 1.0), np.zeros((2, 3), bool)), (0.5, 0.5), costs="octile").value.round(4)
    array([[0.    , 1.    , 2.    ],
           [1.    , 1.4142, 2.4142]])
    >>> wavefront(m, (0.5, 0.5), connectivity=4).value
    array([[ 0.,  1.,  2.],
           [ 1., inf,  3.],
           [ 2.,  3.,  4.]])
    """
    conn = _check_connectivity(connectivity)
    if costs not in COSTS:
        raise ParameterError(f"costs must be one of {COSTS}, got {costs!r}")
    w = _check_weight(clearance_weight)
    g, (gr, gc) = _goal_cell(gridmap, goal)
    sr = sc = -1
    if stop_at is not None:
        cells, inside = gridmap.grid.world_to_cell(stop_at)
        if not inside[0]:
            raise GridfieldError(f"stop_at {np.asarray(stop_at).tolist()} lies outside the map")
        sr, sc = (int(v) for v in cells[0])
    k = _kernel_navigation()
    free = ~gridmap.occupied
    diag = SQRT2 if costs == "octile" else 1.0
    aux: dict[str, Any] = {}
    if w > 0:
        cost = clearance_cost(gridmap, w, q_star)
        dist = k.wavefront_weighted(free, np.where(free, cost, 1.0), gr, gc, conn, diag, sr, sc,
                                    gridmap.grid.resolution, gridmap.diagonals)
        aux["cost"] = cost
    else:
        dist = k.wavefront_uniform(free, gr, gc, conn, diag, sr, sc, gridmap.grid.resolution, gridmap.diagonals)
    params = {"connectivity": conn, "costs": costs, "clearance_weight": w, "q_star": q_star}
    return NavigationField(gridmap, dist, g, (gr, gc), "wavefront", params, aux)


def plan_wavefront(gridmap: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64],
                   params: Mapping[str, Any], *, cache: dict[Any, Any] | None = None) -> Path:
    """Planner ``wavefront``: unit-cost wavefront (``connectivity`` 8 or 4, optional
    ``clearance_weight``/``q_star``) and the descent of :func:`extract_path`.

    ``Path.seconds`` is the path extraction; the wavefront's own time is ``extra["field_seconds"]``.

    Parameters
    ----------
    gridmap : GridMap
    start, goal : ndarray, shape (2,)
        World points in free cells (checked by :func:`gridfield.planners.plan`).
    params : mapping
        Validated planner parameters (:mod:`gridfield.core.params`); read here: ``connectivity``,
        ``clearance_weight``, ``q_star``.

    Returns
    -------
    Path
        From :func:`extract_path`: ``points`` from ``start`` to ``goal``, ``status``, ``params`` (the
        given ones and the field's), ``extra`` with ``value``, ``grid_length`` and ``field_seconds``.

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> m = GridMap(Grid((2, 3), 1.0), np.zeros((2, 3), bool))
    >>> plan_wavefront(m, np.array([0.5, 0.5]), np.array([2.5, 1.5]), {"connectivity": 4}).iterations
    3
    """
    params = validate(params)  # a raw mapping from a direct call is checked too
    t0 = time.perf_counter()
    nav = wavefront(gridmap, goal, connectivity=params.group(Navigation).connectivity, costs="unit", **grid_options(params))
    return _plan_grid(nav, start, params, "wavefront", time.perf_counter() - t0)


def plan_wavefront_octile(gridmap: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64],
                          params: Mapping[str, Any], *, cache: dict[Any, Any] | None = None) -> Path:
    """Planner ``wavefront-octile``: octile-cost wavefront (Moving AI metric) and its descent: a shortest
    8-connected path without corner cutting.

    Parameters
    ----------
    gridmap : GridMap
    start, goal : ndarray, shape (2,)
        World points in free cells (checked by :func:`gridfield.planners.plan`).
    params : mapping
        Validated planner parameters (:mod:`gridfield.core.params`); read here: ``connectivity``,
        ``clearance_weight``, ``q_star``.

    Returns
    -------
    Path
        From :func:`extract_path`: ``points`` from ``start`` to ``goal``, ``status``, ``params`` (the
        given ones and the field's), ``extra`` with ``value``, ``grid_length`` and ``field_seconds``.

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> m = GridMap(Grid((2, 3), 1.0), np.zeros((2, 3), bool))
    >>> round(plan_wavefront_octile(m, np.array([0.5, 0.5]), np.array([2.5, 1.5]), {}).length, 4)
    2.4142
    """
    if gridmap.grid.ndim == 3:  # a voxel grid: the 26-neighbour wavefront (gridfield.fields.navigation3d)
        from ..navigation3d import plan_voxel_wavefront

        return plan_voxel_wavefront(gridmap, start, goal, params, cache=cache)
    params = validate(params)  # a raw mapping from a direct call is checked too
    t0 = time.perf_counter()
    nav = wavefront(gridmap, goal, connectivity=params.group(Navigation).connectivity, costs="octile", **grid_options(params))
    return _plan_grid(nav, start, params, "wavefront-octile", time.perf_counter() - t0)
