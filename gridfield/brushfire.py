"""Brushfire (wavefront) distance maps: steps, distances, nearest obstacle, labels, GVD.

Numbering: obstacle cells have ``steps == 0``, their neighbours 1, and so on (the textbook
brushfire of Choset et al. sec. 4.3 numbers obstacles 1 and their neighbours 2; subtract 1).
With ``connectivity=8`` the wavefront measures chessboard distance, with 4 taxicab distance.

A wall border counts as an obstacle ring just outside the grid: its cells are rows ``-1`` and
``rows``, columns ``-1`` and ``cols``, and its label is :data:`BORDER_LABEL`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from .errors import ParameterError
from .grid import Grid, GridMap

__all__ = ["BORDER_LABEL", "METRICS", "DistanceMap", "brushfire"]

METRICS = ("chessboard", "taxicab", "euclidean")
#: Label of the wall border (outside the grid) in :attr:`DistanceMap.label`.
BORDER_LABEL = -1


@dataclass(frozen=True, eq=False)
class DistanceMap:
    """Result of :func:`brushfire`. Every array has the grid's shape.

    Attributes
    ----------
    map : GridMap
        The occupancy map the distances were computed on.
    connectivity : int
    metric : str
    steps : ndarray of int32
        Wavefront number (0 on obstacles). ``-1`` where no obstacle exists at all.
    distance : ndarray of float64
        Distance to the nearest obstacle cell in world units, by ``metric`` (``inf`` where none).
        With ``saturate``, distances ``>= saturate`` are replaced by ``far``.
    nearest_row, nearest_col : ndarray of int32
        Cell index of the nearest obstacle cell (may be -1 or ``rows``/``cols`` for the wall border;
        -1 on both where there is no obstacle).
    label : ndarray of int32
        Label of the nearest obstacle: the world obstacle id when the grid was rasterized from a
        world, else the 8-connected component number (1-based); :data:`BORDER_LABEL` for the wall
        border; 0 where there is no obstacle. Obstacle cells carry their own label.
    gvd : ndarray of bool
        Free cells where the wavefronts of two different labels meet (one cell thick).
    """

    map: GridMap
    connectivity: int
    metric: str
    steps: NDArray[np.int32]
    distance: NDArray[np.float64]
    nearest_row: NDArray[np.int32]
    nearest_col: NDArray[np.int32]
    label: NDArray[np.int32]
    gvd: NDArray[np.bool_]
    saturate: float | None = None
    far: float = np.inf

    @property
    def grid(self) -> Grid:
        return self.map.grid

    def nearest_point(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """World coordinates ``(x, y)`` of the centre of each cell's nearest obstacle cell."""
        g = self.grid
        x = g.origin[0] + (self.nearest_col + 0.5) * g.resolution
        y = g.origin[1] + (self.nearest_row + 0.5) * g.resolution
        none = self.nearest_row == -1
        none &= self.nearest_col == -1
        return np.where(none, np.nan, x), np.where(none, np.nan, y)


def _components(occ: NDArray[np.bool_]) -> NDArray[np.int32]:
    lab, _ = ndimage.label(occ, structure=np.ones((3, 3), dtype=bool))
    return lab.astype(np.int32)


def brushfire(
    gridmap: GridMap,
    *,
    connectivity: int = 8,
    metric: str | None = None,
    saturate: float | None = None,
    far: float = np.inf,
) -> DistanceMap:
    """Wavefront distance map of an occupancy grid.

    Parameters
    ----------
    gridmap : GridMap
    connectivity : {8, 4}
        Neighbourhood of the wavefront that numbers ``steps``.
    metric : {"chessboard", "taxicab", "euclidean"}, optional
        What ``distance`` measures; default: chessboard for 8-connectivity, taxicab for 4.
    saturate : float, optional
        Saturation radius (seed 004): distances at or beyond it become ``far``.
    far : float
        Value of saturated distances (default ``inf``).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((3, 5), bool); occ[1, 0] = True
    >>> d = brushfire(GridMap(Grid((3, 5), 1.0), occ))
    >>> d.steps
    array([[1, 1, 2, 3, 4],
           [0, 1, 2, 3, 4],
           [1, 1, 2, 3, 4]], dtype=int32)
    """
    if connectivity not in (4, 8):
        raise ParameterError(f"connectivity must be 4 or 8, got {connectivity!r}")
    if metric is None:
        metric = "chessboard" if connectivity == 8 else "taxicab"
    if metric not in METRICS:
        raise ParameterError(f"metric must be one of {METRICS}, got {metric!r}")
    if saturate is not None and not (np.isfinite(saturate) and saturate > 0):
        raise ParameterError(f"saturate must be a positive finite distance, got {saturate!r}")
    grid = gridmap.grid
    occ = gridmap.occupied
    wall = grid.border == "wall"
    pad = 1 if wall else 0
    if wall:
        occ = np.pad(occ, 1, constant_values=True)
    rows, cols = occ.shape

    if not occ.any():
        shape = grid.shape
        minus = np.full(shape, -1, np.int32)
        return DistanceMap(gridmap, connectivity, metric, minus, np.full(shape, np.inf), minus, minus.copy(),
                           np.zeros(shape, np.int32), np.zeros(shape, bool), saturate, far)

    step_metric = "chessboard" if connectivity == 8 else "taxicab"
    steps, idx = ndimage.distance_transform_cdt(~occ, metric=step_metric, return_indices=True)
    if metric == "euclidean":
        edt, idx = ndimage.distance_transform_edt(~occ, return_indices=True)
        distance = edt * grid.resolution
    elif metric == step_metric:
        distance = steps * grid.resolution
    else:
        other, idx = ndimage.distance_transform_cdt(~occ, metric=metric, return_indices=True)
        distance = other * grid.resolution
    nr, nc = idx[0], idx[1]

    if gridmap.obstacle_id is not None:
        lab = np.pad(gridmap.obstacle_id, pad) if wall else gridmap.obstacle_id.copy()
    else:
        lab = _components(np.pad(gridmap.occupied, pad) if wall else gridmap.occupied)
    if wall:
        ring = np.ones((rows, cols), bool)
        ring[1:-1, 1:-1] = False
        lab = lab.copy()
        lab[ring] = BORDER_LABEL
    label = lab[nr, nc]

    sl = (slice(pad, rows - pad), slice(pad, cols - pad))
    steps, distance, label = steps[sl].astype(np.int32), distance[sl].astype(np.float64), label[sl]
    nr, nc = (nr[sl] - pad).astype(np.int32), (nc[sl] - pad).astype(np.int32)
    gvd = _gvd(label, distance, gridmap.occupied)
    if saturate is not None:
        distance = np.where(distance >= saturate, far, distance)
    return DistanceMap(gridmap, connectivity, metric, steps, distance, nr, nc, label.astype(np.int32), gvd,
                       saturate, far)


def _gvd(label: NDArray[np.int32], distance: NDArray[np.float64], occupied: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Free cells next to a free cell of another label; of each such pair the farther cell (ties: the first)."""
    gvd = np.zeros(label.shape, bool)
    free = ~occupied
    # forward half of the 8-neighbourhood: (dr, dc)
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        a = (slice(0, label.shape[0] - dr), slice(max(0, -dc), label.shape[1] - max(0, dc)))
        b = (slice(dr, None), slice(max(0, dc), label.shape[1] + min(0, dc) or None))
        meet = (label[a] != label[b]) & free[a] & free[b]
        a_mark = meet & (distance[a] >= distance[b])
        gvd[a] |= a_mark
        gvd[b] |= meet & ~a_mark
    return gvd
