"""The taut post-pass of the ``potential`` planner: the descended path pulled straight where the
grid allows, keeping the clearance it promised.

A gradient follower's path is as long as the field's discrete staircase and the clearance band's
detours make it. :func:`taut_path` shortens it by string pulling over its *own* vertices (no other
planner's path): from each kept vertex, the farthest later vertex it sees is kept next (galloping
then bisection over the vertex index, each candidate segment checked), and the pass is repeated
on its output until nothing changes (at most :data:`TAUT_PASSES` times). The result is a
sub-sequence of the descended vertices: it starts at the start and ends at the goal, and every
segment is either one of the descended path's own or one that was checked.

What "sees" means (the check of a segment, exact geometry on the grid; the compiled walk of
``gridfield.fields._eikonal``): every cell whose square the segment crosses (its exact supercover)
is free and its brushfire distance (the field's ``distance``, cell centre to the nearest obstacle
cell centre, the distance :attr:`Path.min_clearance <gridfield.core.path.Path>` reports) is at
least the **promised clearance**

    ``need = min(c, clearance_band)``,

``c`` the smallest brushfire distance of the cells the descended path crosses (its own clearance,
over its segments, not only its vertices). So the pass never brings the path into a cell closer to
an obstacle than the closest one it entered before, or than the band width where the descended path
kept more: on a map whose path passes a one-cell door (``c`` one cell) the taut path may run along
walls and touch convex corners, like the any-angle optimum; where the field's band kept the path
3-4 cells off the walls (``c`` 3-4 cells, most ROS queries) the taut path keeps them too. A segment
that passes exactly through a grid vertex touches the two cells beside it at a point only: they are
not entered, except that two blocked cells meeting at that vertex (a pinch) block it; within 1e-9
of a vertex both side cells count as entered. Outside the field's map is blocked.

Examples
--------
An L-shaped descended path round a free corner is pulled straight; round a blocked cell it keeps
the corner:

>>> from gridfield.core.grid import Grid, GridMap
>>> gm = GridMap(Grid((3, 3), 1.0, border="wall"), np.zeros((3, 3), bool))
>>> pts = np.array([[0.5, 0.5], [0.5, 1.5], [0.5, 2.5], [1.5, 2.5], [2.5, 2.5]])
>>> taut_path(gm, np.ones((3, 3)), pts, 0.0)[0].tolist()
[[0.5, 0.5], [2.5, 2.5]]
>>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
>>> taut_path(GridMap(gm.grid, occ), np.ones((3, 3)), pts, 0.0)[0].tolist()
[[0.5, 0.5], [0.5, 2.5], [2.5, 2.5]]
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.grid import GridMap

__all__ = ["TAUT_MODELS", "TAUT_PASSES", "crossed_clearance", "taut_path"]

#: The models whose planned paths get the taut post-pass (:func:`gridfield.following.follower.plan_potential`):
#: ``nf1``, the default. NF2 keeps the skeleton's clearance on purpose and ``nf-blend`` its repulsion;
#: the classic field's paths are left as the follower made them.
TAUT_MODELS: tuple[str, ...] = ("nf1",)
#: How many times the string pulling runs over its own output at most (it stops when a pass keeps
#: every vertex): the greedy pass is not optimal over its vertices (what a vertex sees is not
#: monotone in the index), and a second pass over the kept ones shortens some more.
TAUT_PASSES = 3


def _kernels() -> Any:
    from ..fields import _eikonal  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _eikonal


def _arrays(gridmap: GridMap, clearance: ArrayLike) -> tuple[NDArray[np.uint8], NDArray[np.float64]]:
    occ = np.ascontiguousarray(np.asarray(gridmap.occupied, dtype=bool)).view(np.uint8)
    clear = np.ascontiguousarray(clearance, dtype=np.float64)
    if clear.shape != occ.shape:
        raise ValueError(f"clearance has shape {clear.shape}, the map {occ.shape}")
    return occ, clear


def _cell_units(gridmap: GridMap, points: ArrayLike) -> NDArray[np.float64]:
    g = gridmap.grid
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    return np.ascontiguousarray((pts - np.asarray(g.origin, dtype=np.float64)) / g.resolution)


def crossed_clearance(gridmap: GridMap, clearance: ArrayLike, points: ArrayLike) -> float:
    """The smallest ``clearance`` of the cells the polyline ``points`` crosses (the module's rule),
    or -1 when it crosses a blocked cell or leaves the map (``inf`` for no points).

    Parameters
    ----------
    gridmap : GridMap
        Its blocked cells and grid (points in its world coordinates).
    clearance : ndarray of float, the map's shape
        Per cell (a brushfire's ``distance``, world units).
    points : array_like of shape (n, 2)

    Returns
    -------
    float

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((3, 3), bool); occ[0, 1] = True
    >>> gm = GridMap(Grid((3, 3), 1.0, border="wall"), occ)
    >>> d = np.array([[1.0, 0.0, 1.0], [1.4, 1.0, 1.4], [2.2, 2.0, 2.2]])
    >>> crossed_clearance(gm, d, [[0.5, 2.5], [2.5, 2.5]]), crossed_clearance(gm, d, [[0.5, 0.5], [2.5, 0.5]])
    (2.0, -1.0)
    >>> crossed_clearance(gm, d, [[0.5, 0.5], [1.5, 1.5]])   # touches the blocked cell's corner only
    1.0
    """
    occ, clear = _arrays(gridmap, clearance)
    return float(_kernels().crossed_clearance(_cell_units(gridmap, points), occ, clear))


def taut_path(gridmap: GridMap, clearance: ArrayLike, points: ArrayLike,
              band: float) -> tuple[NDArray[np.float64], float]:
    """The descended path ``points`` pulled taut (string pulling over its own vertices), never into a
    cell of ``clearance`` below ``min(c, band)``, ``c`` the path's own :func:`crossed_clearance`.

    Parameters
    ----------
    gridmap : GridMap
        The map the path was followed on (a field's ``map``).
    clearance : ndarray of float, the map's shape
        The brushfire distance per cell (a field's ``distance.distance``), world units.
    points : array_like of shape (n, 2)
        The descended path, start first, goal last.
    band : float
        The clearance band (world units; 0: the pass only keeps the path in free cells).

    Returns
    -------
    points : ndarray of shape (k, 2)
        A sub-sequence of ``points`` with the same first and last point. When the descended path
        itself crosses a blocked cell by the module's rule (``c`` < 0) it is returned unchanged.
    need : float
        The promised clearance the pass kept (``nan`` when it did not run).

    Examples
    --------
    A staircase descent across an empty 6 x 6 grid becomes its straight segment:

    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((6, 6), 1.0, border="wall"), np.zeros((6, 6), bool))
    >>> stairs = np.array([[0.5 + (k + 1) // 2, 0.5 + k // 2] for k in range(11)])
    >>> p, need = taut_path(gm, np.full((6, 6), 9.0), stairs, 6.0)
    >>> p.tolist(), need
    ([[0.5, 0.5], [5.5, 5.5]], 6.0)
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if len(pts) < 3:
        return pts.copy(), math.nan
    occ, clear = _arrays(gridmap, clearance)
    cells = _cell_units(gridmap, pts)
    k = _kernels()
    own = float(k.crossed_clearance(cells, occ, clear))
    if own < 0:
        return pts.copy(), math.nan
    need = min(own, float(band)) if band > 0 else 0.0
    keep = np.arange(len(pts))
    for _ in range(TAUT_PASSES):
        sub = k.taut(np.ascontiguousarray(cells[keep]), occ, clear, need)
        if len(sub) == len(keep):
            break
        keep = keep[sub]
    return pts[keep], need
