"""The complete models' slownesses, NF2's skeleton and the maps the fronts run on, for
:mod:`gridfield.fields.navfield` (a private module; import from there).

What the complete models march on, computed without a march: NF2's skeleton of the free space
(:func:`skeleton`, :func:`nf_skeleton`) and its slowness (:func:`nf2_cost`), the slowness of
``nf-blend`` (:func:`blend_cost`) and of ``nf1``'s clearance band (:func:`band_cost`), and the maps
a field lives on with either border (:func:`work_maps`). The march itself (:func:`gridfield.fields.navfield.eikonal`),
the fields' values (:func:`gridfield.fields.navfield.nf_potential`) and the
:class:`~gridfield.fields.potential.Field` (:func:`gridfield.fields.navfield.nav_field`) are
:mod:`gridfield.fields.navfield`'s, whose module text describes every model.

See Also
--------
gridfield.fields.navfield : The march and the fields of the complete models, and the public home of these names.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ..distance.brushfire import DistanceMap, brushfire

#: Medial-axis cells: the nearest obstacle cells of two 8-neighbours lie at least this many cells
#: apart (squared), and the cell is at least ``SKELETON_MIN_CLEARANCE`` cells from its obstacle.
SKELETON_SPREAD2 = 9.0
SKELETON_MIN_CLEARANCE = 1.5
#: NF2's slowness off the skeleton (1 on it): the front runs along the skeleton and reaches the
#: other cells from it, so the descent from a cell climbs onto the skeleton and runs along it to
#: the goal. A finite cost (where Latombe's NF2 propagates along the skeleton only) bridges the gaps
#: of a grid skeleton (one-cell doors, where no two fronts meet by the skeleton's rule) and keeps
#: one minimum by construction (the march's rule), whatever the skeleton's connectivity.
NF2_OFF_SKELETON_COST = 3.0
#: Cells from the skeleton over which NF2's slowness rises from 1 to :data:`NF2_OFF_SKELETON_COST`.
NF2_VALLEY_CELLS = 3.0


def skeleton(dmap: DistanceMap) -> NDArray[np.bool_]:
    """The skeleton of the free space NF2 runs along: the brushfire's GVD (cells where the fronts of
    two obstacles meet) plus the medial axis inside one obstacle's concavities, which the GVD of
    labels does not see (a room whose walls are one obstacle): free cells whose nearest obstacle
    cell and a free 8-neighbour's lie at least 3 cells apart, the one farther from its obstacle
    marked, at least 1.5 cells from an obstacle.

    Parameters
    ----------
    dmap : DistanceMap
        A Euclidean brushfire with ``nearest_row``/``nearest_col`` (and ``gvd`` when computed).

    Returns
    -------
    ndarray of bool, the grid's shape

    Examples
    --------
    A corridor 5 cells wide between two walls of one obstacle: the skeleton is its middle row.

    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((7, 12), bool); occ[0] = occ[-1] = True; occ[:, 0] = True
    >>> sk = skeleton(brushfire(GridMap(Grid((7, 12), 1.0), occ), metric="euclidean"))
    >>> np.flatnonzero(sk[:, 6]).tolist()
    [3]
    """
    occ = np.asarray(dmap.map.occupied, dtype=bool)
    free = ~occ
    d = np.where(free & np.isfinite(dmap.distance), dmap.distance, 0.0) / dmap.grid.resolution
    if dmap.nearest_row is None or dmap.nearest_col is None:
        raise ParameterError("skeleton needs a distance map with its nearest obstacle cells (compute_nearest=True)")
    nr = dmap.nearest_row.astype(np.float64)
    nc = dmap.nearest_col.astype(np.float64)
    sk = np.zeros(occ.shape, bool)
    rows, cols = occ.shape
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        a = (slice(0, rows - dr), slice(max(-dc, 0), cols - max(dc, 0)))
        b = (slice(dr, rows), slice(max(dc, 0), cols - max(-dc, 0)))
        both = free[a] & free[b]
        spread = (nr[a] - nr[b]) ** 2 + (nc[a] - nc[b]) ** 2
        meet = both & (spread >= SKELETON_SPREAD2)
        first = meet & (d[a] >= d[b])
        sk[a] |= first
        sk[b] |= meet & ~first
    sk &= d >= SKELETON_MIN_CLEARANCE
    if dmap.gvd is not None:
        sk |= dmap.gvd & free
    return sk


def nf_skeleton(gridmap: GridMap) -> tuple[DistanceMap, NDArray[np.bool_], NDArray[np.float64]]:
    """What NF2 computes once per map: the Euclidean brushfire (labels and GVD) of ``gridmap``, its
    :func:`skeleton` and the slowness :func:`nf2_cost` (the potential planner keeps them in its
    ``cache``).

    Parameters
    ----------
    gridmap : GridMap

    Returns
    -------
    dmap, skeleton, cost : DistanceMap, ndarray of bool, ndarray of float64

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((7, 12), bool); occ[0] = occ[-1] = True
    >>> d, sk, cost = nf_skeleton(GridMap(Grid((7, 12), 1.0), occ))
    >>> d.gvd is not None, np.flatnonzero(sk[:, 6]).tolist(), cost[:, 6].round(2).tolist()
    (True, [3], [3.0, 2.33, 1.67, 1.0, 1.67, 2.33, 3.0])
    """
    dmap = brushfire(gridmap, metric="euclidean", compute_labels=True, compute_gvd=True)
    sk = skeleton(dmap)
    return dmap, sk, nf2_cost(sk)


def nf2_cost(sk: NDArray[np.bool_]) -> NDArray[np.float64]:
    """NF2's slowness: 1 on the skeleton, rising linearly with the distance to it to
    :data:`NF2_OFF_SKELETON_COST` at :data:`NF2_VALLEY_CELLS` cells and beyond (a valley a follower
    with one-cell steps can run down; a one-cell line of speed 1 would make it zigzag across).

    Parameters
    ----------
    sk : ndarray of bool
        The skeleton (:func:`skeleton`).

    Returns
    -------
    ndarray of float64
        The slowness, in [1, :data:`NF2_OFF_SKELETON_COST`].

    Examples
    --------
    >>> sk = np.zeros((1, 7), bool); sk[0, 0] = True
    >>> nf2_cost(sk).round(3).tolist()
    [[1.0, 1.667, 2.333, 3.0, 3.0, 3.0, 3.0]]
    """
    from scipy import ndimage

    if not sk.any():
        return np.full(sk.shape, NF2_OFF_SKELETON_COST)
    dsk = ndimage.distance_transform_edt(~sk)
    return 1.0 + (NF2_OFF_SKELETON_COST - 1.0) * np.minimum(dsk / NF2_VALLEY_CELLS, 1.0)


def blend_cost(dmap: DistanceMap, q_star: float, gain: float) -> NDArray[np.float64]:
    """The slowness of ``nf-blend``: ``1 + gain * (q_star / D - 1)**2`` for ``D < q_star``, 1 beyond
    (``D`` the brushfire distance; the shape of the Khatib repulsion ``(1/D - 1/q_star)**2``
    scaled by ``q_star**2``).

    Parameters
    ----------
    dmap : DistanceMap
        A Euclidean brushfire of the map.
    q_star : float
        Distance of influence (world units).
    gain : float
        ``clearance_gain`` (>= 0).

    Returns
    -------
    ndarray of float64
        >= 1 on free cells, ``inf`` on obstacle cells.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((1, 5), bool); occ[0, 0] = True
    >>> blend_cost(brushfire(GridMap(Grid((1, 5), 1.0), occ)), 3.0, 1.0).round(3).tolist()
    [[inf, 5.0, 1.25, 1.0, 1.0]]
    """
    d = dmap.distance
    with np.errstate(divide="ignore", invalid="ignore"):
        rep = np.where(d < q_star, (q_star / d - 1.0) ** 2, 0.0)
    cost = 1.0 + gain * rep
    cost[~np.isfinite(d) & ~dmap.map.occupied] = 1.0  # no obstacle at all
    cost[dmap.map.occupied] = np.inf
    return cost


def band_cost(dmap: DistanceMap, band: float, gain: float) -> NDArray[np.float64]:
    """The slowness of ``nf1``'s clearance band: ``1 + gain * (1 - D / band)**2`` for ``D < band``, 1
    beyond (``D`` the brushfire distance).

    Parameters
    ----------
    dmap : DistanceMap
        A Euclidean brushfire of the map.
    band : float
        ``clearance_band`` (world units, > 0).
    gain : float
        ``band_gain`` (>= 0).

    Returns
    -------
    ndarray of float64
        In ``[1, 1 + gain]`` on free cells, ``inf`` on obstacle cells.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((1, 5), bool); occ[0, 0] = True
    >>> band_cost(brushfire(GridMap(Grid((1, 5), 1.0), occ)), 3.0, 1.0).round(3).tolist()
    [[inf, 1.444, 1.111, 1.0, 1.0]]
    """
    d = dmap.distance
    with np.errstate(invalid="ignore", over="ignore"):  # a band so thin that D / band overflows: no band
        cost = 1.0 + gain * np.maximum(0.0, 1.0 - d / band) ** 2
    cost[~np.isfinite(d) & ~dmap.map.occupied] = 1.0  # no obstacle at all
    cost[dmap.map.occupied] = np.inf
    return cost


def work_maps(gridmap: GridMap) -> tuple[GridMap, GridMap]:
    """The maps a complete model's field lives on: ``(fronts, distances)``. With a ``wall`` border
    both are ``gridmap``. With an ``open`` border the fronts run on ``gridmap`` inside a one-cell
    free ring with a wall beyond (:func:`gridfield.following.escapes.navigation_map`'s rule: a path may pass
    round the grid), and the brushfire on the same ring with an open border (no wall to keep off).

    Parameters
    ----------
    gridmap : GridMap

    Returns
    -------
    fronts, distances : GridMap

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> a, b = work_maps(GridMap(Grid((2, 3), 1.0), np.zeros((2, 3), bool)))
    >>> a.grid.shape, a.grid.border, b.grid.border, a.grid.origin
    ((4, 5), 'wall', 'open', (-1.0, -1.0))
    """
    g = gridmap.grid
    if g.border == "wall":
        return gridmap, gridmap
    from ..core.grid import Grid

    res = g.resolution
    occ = np.pad(np.asarray(gridmap.occupied, dtype=bool), 1, constant_values=False)
    shape = (g.rows + 2, g.cols + 2)
    origin = (g.origin[0] - res, g.origin[1] - res)
    return (GridMap(Grid(shape, res, origin, border="wall"), occ),
            GridMap(Grid(shape, res, origin, border="open"), occ))
