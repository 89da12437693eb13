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
``gridfield.following._taut``): every cell whose square the segment crosses (its exact supercover)
is free, and its brushfire distance ``D`` (the field's ``distance``: cell centre to the nearest
obstacle cell centre, the distance :attr:`Path.min_clearance <gridfield.core.path.Path>` reports)
is at least the cell's **promised clearance**

    ``need(cell) = min(clearance_band, the smallest D of the descended path's vertex cells within
    clearance_band of the cell)``,

and ``clearance_band`` for a cell farther than that from every vertex. That is the clearance the
descended path promised: the band keeps it up to ``clearance_band`` off the walls where that is
cheap, and the taut path never comes closer to an obstacle, anywhere, than the descended path came
nearby (or than the band, where the descended path kept more). Where the descended path itself
passes a one-cell door or runs along a wall (``D`` one cell), the taut path may run along the walls
there and touch convex corners, like the any-angle optimum; where the band kept the descended path
3-4 cells off the walls (most ROS queries; the middle of a corridor narrower than two bands) the
taut path keeps them too. ``clearance_band`` 0 (the plain distance, or ``band_gain`` 0): every free
cell may be crossed. A segment that passes exactly through a grid vertex touches the two cells
beside it at a point only: they are not entered, except that two blocked cells meeting at that
vertex (a pinch) block it; within 1e-9 of a vertex both side cells count as entered. Outside the
field's map is blocked.

Examples
--------
An L-shaped descended path round a free corner is pulled straight; round a blocked cell it keeps
the corner:

>>> from gridfield.core.grid import Grid, GridMap
>>> gm = GridMap(Grid((3, 3), 1.0, border="wall"), np.zeros((3, 3), bool))
>>> pts = np.array([[0.5, 0.5], [0.5, 1.5], [0.5, 2.5], [1.5, 2.5], [2.5, 2.5]])
>>> taut_path(gm, np.ones((3, 3)), pts, 0.0).tolist()
[[0.5, 0.5], [2.5, 2.5]]
>>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
>>> taut_path(GridMap(gm.grid, occ), np.ones((3, 3)), pts, 0.0).tolist()
[[0.5, 0.5], [0.5, 2.5], [2.5, 2.5]]
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.grid import GridMap

__all__ = ["TAUT_MODELS", "TAUT_PASSES", "crossed_clearance", "taut_path"]

#: The models whose planned paths get the taut post-pass (:func:`gridfield.following.follower.plan_potential`):
#: ``nf1``, the default, with its eikonal attraction (``attraction="octile"`` keeps the descended path,
#: as ``gridfield plan`` on a stored field, which follows it alone, does). NF2 keeps the skeleton's clearance on purpose and ``nf-blend`` its repulsion;
#: the classic field's paths are left as the follower made them.
TAUT_MODELS: tuple[str, ...] = ("nf1",)
#: How many times the string pulling runs over its own output at most (it stops when a pass keeps
#: every vertex): the greedy pass is not optimal over its vertices (what a vertex sees is not
#: monotone in the index), and a second pass over the kept ones shortens some more.
TAUT_PASSES = 3


def _kernels() -> Any:
    from . import _taut  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _taut


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


def taut_path(gridmap: GridMap, clearance: ArrayLike, points: ArrayLike, band: float) -> NDArray[np.float64]:
    """The descended path ``points`` pulled taut (string pulling over its own vertices), never into a
    cell below its promised clearance (the module's rule).

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
    ndarray of shape (k, 2)
        A sub-sequence of ``points`` with the same first and last point (each segment one of the
        descended path's own or a checked one).

    Examples
    --------
    A staircase descent across an empty 6 x 6 grid becomes its straight segment:

    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((6, 6), 1.0, border="wall"), np.zeros((6, 6), bool))
    >>> stairs = np.array([[0.5 + (k + 1) // 2, 0.5 + k // 2] for k in range(11)])
    >>> taut_path(gm, np.full((6, 6), 9.0), stairs, 6.0).tolist()
    [[0.5, 0.5], [5.5, 5.5]]

    Down the middle of a corridor (rows 1-5, ``D`` 3 on the middle row) to a goal beside its wall
    (``D`` 1): the band keeps the middle row's clearance until within a band of the goal, the plain
    distance (``band`` 0) cuts straight across:

    >>> occ = np.zeros((7, 20), bool); occ[[0, 6]] = True
    >>> d = np.minimum(np.arange(7), 6 - np.arange(7))[:, None] * np.ones((1, 20))
    >>> pts = [[x + 0.5, 3.5] for x in range(20)] + [[19.5, 2.5], [19.5, 1.5]]
    >>> corridor = GridMap(Grid((7, 20), 1.0, border="wall"), occ)
    >>> taut_path(corridor, d, pts, 6.0).tolist(), taut_path(corridor, d, pts, 0.0).tolist()
    ([[0.5, 3.5], [19.5, 3.5], [19.5, 1.5]], [[0.5, 3.5], [19.5, 1.5]])
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if len(pts) < 3:
        return pts.copy()
    occ, clear = _arrays(gridmap, clearance)
    cells = _cell_units(gridmap, pts)
    res = gridmap.grid.resolution
    band = max(float(band), 0.0)
    keep = _kernels().taut(cells, occ, clear, band, band / res, TAUT_PASSES)
    return pts[keep]
