"""Configuration spaces of occupancy grids (private; import from gridfield.geometry.cspace).

:func:`inflate_grid` grows the occupied cells of a :class:`~gridfield.core.grid.GridMap` by a disc
robot's radius (Euclidean feature transform, exact in integer cell units); :func:`cspace_grid`
dilates them by the rasterized reflected robot. The dilation by a footprint (``_runs``,
``_dilate``, ``_dilate_gridmap``) is shared with :func:`gridfield.geometry.cspace.apply_robot`.
"""

from __future__ import annotations

import itertools
import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

from ...core.errors import ParameterError
from ...core.grid import Grid, GridMap
from ...core.limits import check_cells
from .._polygons import _as_geometry, _check_radius, _clean_convex, _convex_polygon
from ..rasterize import rasterize_geometry


def inflate_grid(gridmap: GridMap, radius: float) -> GridMap:
    """C-space of a disc robot on a grid: occupied where the distance to an occupied cell <= radius.

    Distances are Euclidean and measured **between cell centres** (the feature transform of
    ``scipy.ndimage.distance_transform_edt`` on the free cells gives each cell's nearest obstacle
    cell; the comparison is exact in integer cell units, with a relative tolerance of ``1e-9`` on
    ``radius / resolution``); a radius below one cell therefore changes nothing. With ``border="wall"`` the wall (a ring of
    occupied cells just outside the grid, as in :mod:`gridfield.brushfire`) grows too. Each new
    cell takes the ``obstacle_id`` of its nearest obstacle cell (0 when that is the wall).

    Parameters
    ----------
    gridmap : GridMap
    radius : float
        Robot radius in world units (>= 0, finite).

    Returns
    -------
    GridMap
        Same grid, border and world; the grown occupancy and ``obstacle_id``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((5, 5), bool); occ[2, 2] = True
    >>> inflate_grid(GridMap(Grid((5, 5), 0.5), occ), 1.0).occupied.astype(int)
    array([[0, 0, 1, 0, 0],
           [0, 1, 1, 1, 0],
           [1, 1, 1, 1, 1],
           [0, 1, 1, 1, 0],
           [0, 0, 1, 0, 0]])
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"inflate_grid needs a GridMap, got {type(gridmap).__name__}")
    r = _check_radius(radius)
    grid = gridmap.grid
    res = grid.resolution
    wall = grid.border == "wall"
    occ = np.pad(gridmap.occupied, 1, constant_values=True) if wall else gridmap.occupied
    if r < res or not occ.any():
        return gridmap.with_occupied(gridmap.occupied.copy(),
                                     obstacle_id=None if gridmap.obstacle_id is None else gridmap.obstacle_id.copy())
    # The feature transform (index of the nearest obstacle cell) alone is faster in scipy than
    # the distances; the squared distance in cells follows from it exactly, in integers.
    idx = ndimage.distance_transform_edt(~occ, return_distances=False, return_indices=True)
    nrows, ncols = occ.shape
    dr = idx[0] - np.arange(nrows, dtype=idx.dtype)[:, None]
    dc = idx[1] - np.arange(ncols, dtype=idx.dtype)[None, :]
    limit = (r / res) ** 2 * (1 + 2e-9) + 1e-9
    inflated = (dr.astype(np.int64) ** 2 + dc.astype(np.int64) ** 2) <= limit
    del dr, dc
    ids = None
    if gridmap.obstacle_id is not None:
        src = np.pad(gridmap.obstacle_id, 1) if wall else gridmap.obstacle_id
        ids = np.where(inflated, src[idx[0], idx[1]], 0).astype(np.int32)
    if wall:
        inflated = inflated[1:-1, 1:-1]
        ids = None if ids is None else ids[1:-1, 1:-1]
    return gridmap.with_occupied(inflated, obstacle_id=ids)


def _footprint(robot: NDArray[np.float64], resolution: float) -> NDArray[np.bool_]:
    """Conservative rasterization of ``−R`` on a ``(2m+1)^2`` grid whose centre cell is centred on
    the reference point: cell ``(m + i, m + j)`` is the offset of ``i`` rows and ``j`` columns."""
    neg = -robot
    m = math.ceil(float(np.max(np.abs(neg))) / resolution + 0.5) + 1
    grid = Grid((2 * m + 1, 2 * m + 1), resolution, origin=(-(m + 0.5) * resolution, -(m + 0.5) * resolution))
    return rasterize_geometry(_as_geometry(_clean_convex(neg)), grid)


def _runs(footprint: NDArray[np.bool_]) -> list[tuple[int, int, int]]:
    """Horizontal runs ``(row offset, first col offset, last col offset)`` of a centred footprint."""
    m = footprint.shape[0] // 2
    padded = np.pad(footprint, ((0, 0), (1, 1))).astype(np.int8)
    d = np.diff(padded, axis=1)
    starts, ends = np.nonzero(d == 1), np.nonzero(d == -1)
    return [(int(r) - m, int(a) - m, int(b) - 1 - m) for r, a, b in zip(starts[0], starts[1], ends[1], strict=True)]


def _dilate(arr: NDArray[Any], runs: list[tuple[int, int, int]], pad_value: int) -> NDArray[Any]:
    """``out[y, x] = max over runs (dr, a, b) and s in [a, b] of arr[y - dr, x - s]``, with
    ``pad_value`` outside ``arr`` (a Minkowski-sum dilation by the footprint), via one 1-D
    running maximum per run (cost independent of the run's length)."""
    rows, cols = arr.shape
    p = max(max(abs(dr), abs(a), abs(b)) for dr, a, b in runs) + 1
    check_cells((rows + 2 * p, cols + 2 * p), "the padded grid of a footprint dilation")
    padded = np.pad(arr, p, constant_values=pad_value)
    out = np.zeros_like(arr)
    # one running maximum per distinct run (a, b), used for every row offset that has it, then dropped:
    # memory stays at two padded grids whatever the footprint (max is order-independent: same result)
    for (a, b), group in itertools.groupby(sorted(runs, key=lambda t: (t[1], t[2], t[0])), key=lambda t: (t[1], t[2])):
        length = b - a + 1
        f = ndimage.maximum_filter1d(padded, length, axis=1, mode="constant", cval=pad_value)
        c0 = p - b + length // 2
        for dr, _, _ in group:
            r0 = p - dr
            np.maximum(out, f[r0:r0 + rows, c0:c0 + cols], out=out)
        del f
    return out


def cspace_grid(gridmap: GridMap, robot_vertices: ArrayLike) -> GridMap:
    """C-space of a convex polygon robot that translates, on a grid.

    The occupancy is dilated by the **footprint**: the reflected robot ``−R`` rasterized
    conservatively (closed cells) at the grid's resolution on cells centred on the reference
    point (the origin of ``robot_vertices``). A cell ``q`` is occupied iff ``q = c + k`` for an
    occupied cell ``c`` and a footprint offset ``k``. The result contains every cell whose centre
    lies in the exact C-space of the rasterized obstacles and is within one cell of the exact
    C-space. With ``border="wall"`` the wall grows too. Each cell's ``obstacle_id`` is the
    lowest id among the obstacle cells that reach it (0 if only the wall or id-less cells do).

    Parameters
    ----------
    gridmap : GridMap
    robot_vertices : (M, 2) array_like
        Convex robot polygon in the robot's frame (origin = reference point), world units.

    Returns
    -------
    GridMap
        Same grid, border and world; the dilated occupancy and ``obstacle_id``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((4, 5), bool); occ[1, 2] = True
    >>> m = cspace_grid(GridMap(Grid((4, 5), 1.0), occ), [[0, 0], [1.6, 0], [1.6, 0.4], [0, 0.4]])
    >>> m.occupied.astype(int)  # the robot extends right of its reference point: C-obstacle to the left
    array([[0, 0, 0, 0, 0],
           [1, 1, 1, 0, 0],
           [0, 0, 0, 0, 0],
           [0, 0, 0, 0, 0]])
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"cspace_grid needs a GridMap, got {type(gridmap).__name__}")
    robot = _convex_polygon(robot_vertices, "robot_vertices")
    return _dilate_gridmap(gridmap, _runs(_footprint(robot, gridmap.grid.resolution)))


def _dilate_gridmap(gridmap: GridMap, runs: list[tuple[int, int, int]]) -> GridMap:
    """Dilate the occupancy (and the obstacle ids, the lowest id winning) by a footprint's runs;
    the wall border (``border="wall"``) grows too."""
    wall = gridmap.grid.border == "wall"
    ids = gridmap.obstacle_id
    if ids is None:
        occ = _dilate(gridmap.occupied.view(np.uint8), runs, pad_value=int(wall)).astype(bool)
        return gridmap.with_occupied(occ, obstacle_id=None)
    # priority: free 0, occupied without id 1, id k -> big - k (the maximum is the lowest id)
    big = int(max(int(ids.max(initial=0)), 0)) + 2
    dtype = np.uint8 if big <= np.iinfo(np.uint8).max else np.uint16 if big <= np.iinfo(np.uint16).max else np.int64
    prio = np.where(gridmap.occupied, np.where(ids > 0, big - ids, 1), 0).astype(dtype)
    out = _dilate(prio, runs, pad_value=1 if wall else 0)
    new_ids = np.where(out >= 2, big - out, 0).astype(np.int32)
    return gridmap.with_occupied(out > 0, obstacle_id=new_ids)
