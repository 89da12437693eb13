"""The complete potential ``nf1`` on voxel grids (3-D): the default field of the ``potential`` planner.

In 2-D, ``nf1`` (:mod:`gridfield.fields.navfield`) is an eikonal fast march slowed near obstacles by
the clearance band. On a voxel grid the same model is the 26-neighbour wavefront of
:mod:`gridfield.fields.navigation3d` (the bounding-box move rule) with the clearance band's slowness
``1 + band_gain * (1 - D / clearance_band)**2`` for ``D < clearance_band`` (``D`` the Euclidean distance
from the voxel centre to the nearest blocked voxel centre, the wall border's shell included; the same
parameters and defaults as 2-D: 6 cells and 0.5). ``attraction="octile"``, ``clearance_band=0`` or
``band_gain=0`` give the plain wavefront distance.

It is a navigation function by construction: ``U`` is a shortest-path cost from the goal, so every
settled voxel but the goal has an allowed neighbour of lower value (its Dijkstra parent), and the
discrete descent (:func:`gridfield.fields.navigation3d.voxel_descent`) from every settled voxel ends
at the goal. The gradient arrays are upwind differences per axis (towards the lower neighbour, never
across a non-finite value), in world units; blocked and unsettled voxels have ``U = inf`` and zero
gradient. The field lives on the map itself (the voxel wavefront stays inside the grid whatever the
border: see :mod:`gridfield.fields.navigation3d`). ``nf2`` and ``nf-blend`` are 2-D models.

The clearance ``D`` is the Euclidean 3-D brushfire (:func:`gridfield.fields.navigation3d.voxel_clearance`).

Examples
--------
>>> from gridfield.core.grid import Grid, GridMap
>>> gm = GridMap(Grid((4, 4, 4), 1.0, border="wall"), np.zeros((4, 4, 4), bool))
>>> f = nav_field3d(gm, (0.5, 0.5, 0.5))
>>> f.params["model"], f.grad_z.shape, float(f.potential[0, 0, 0])
('nf1', (4, 4, 4), 0.0)
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ..core.results import Field
from .navigation3d import STOP_MARGIN_CELLS, check_voxel_map, voxel_clearance, voxel_wavefront

__all__ = ["band_slowness", "nav_field3d", "upwind_gradient3d"]

#: The follower's progress window for the complete model (off, as in 2-D).
NF_PROGRESS_WINDOW = 0


def upwind_gradient3d(value: NDArray[np.float64], resolution: float) -> tuple[NDArray[np.float64], ...]:
    """The upwind gradient of a distance-like array, per **array** axis: along each axis the one-sided
    difference towards the lower neighbour (0 where none is lower and on non-finite voxels; a non-finite
    neighbour is never used), divided by ``resolution``.

    Parameters
    ----------
    value : ndarray
        Any number of dimensions.
    resolution : float
        The cell size.

    Returns
    -------
    tuple of ndarray
        One array per axis (for a voxel grid: d/dz, d/dy, d/dx).

    Examples
    --------
    >>> g = upwind_gradient3d(np.array([[[0.0, 1.0, 3.0]]]), 1.0)
    >>> g[2].tolist(), g[0].tolist()
    ([[[0.0, 1.0, 2.0]]], [[[0.0, 0.0, 0.0]]])
    """
    v = np.asarray(value, dtype=np.float64)
    pad = np.pad(v, 1, constant_values=np.inf)
    inner = tuple(slice(1, -1) for _ in range(v.ndim))
    bad = ~np.isfinite(v)
    out = []
    for a in range(v.ndim):
        lo = list(inner)
        hi = list(inner)
        lo[a] = slice(0, -2)
        hi[a] = slice(2, None)
        low, high = pad[tuple(lo)], pad[tuple(hi)]
        with np.errstate(invalid="ignore"):
            g = np.where(low <= high, np.where(low < v, v - low, 0.0), np.where(high < v, high - v, 0.0))
        g[bad | ~np.isfinite(g)] = 0.0
        out.append(g / resolution)
    return tuple(out)


def band_slowness(distance: NDArray[np.float64], occupied: NDArray[np.bool_], band: float,
                  gain: float) -> NDArray[np.float64]:
    """The clearance band's slowness ``1 + gain * (1 - D / band)**2`` for ``D < band``, 1 beyond and where
    there is no obstacle, ``inf`` on blocked voxels (:func:`gridfield.fields.navfield.band_cost`'s rule).

    Parameters
    ----------
    distance : ndarray of float
        The clearance ``D`` of each voxel (:func:`gridfield.fields.navigation3d.voxel_clearance`), in
        world units; a non-finite value (``inf``: no obstacle) gets slowness 1.
    occupied : ndarray of bool, same shape as ``distance``
        The blocked voxels.
    band : float
        The width of the band (``clearance_band``, > 0, the units of ``distance``).
    gain : float
        The extra slowness at ``D = 0`` (``band_gain``, >= 0).

    Returns
    -------
    ndarray of float64, same shape as ``distance``
        A new array, the slowness for :func:`gridfield.fields.navigation3d.voxel_wavefront`: between 1
        and ``1 + gain`` on free voxels, ``inf`` on blocked ones.

    Examples
    --------
    >>> band_slowness(np.array([0.0, 1.0, 2.0, 3.0]), np.array([True, False, False, False]), 3.0, 1.0).round(3)
    array([  inf, 1.444, 1.111, 1.   ])
    """
    with np.errstate(invalid="ignore", over="ignore"):
        cost = 1.0 + gain * np.maximum(0.0, 1.0 - distance / band) ** 2
    cost[~np.isfinite(distance)] = 1.0
    cost[occupied] = np.inf
    return cost


def nav_field3d(gridmap: GridMap, goal: ArrayLike, params: Mapping[str, Any] | None = None, *,
                stop_at: ArrayLike | None = None, clearance: NDArray[np.float64] | None = None) -> Field:
    """The :class:`~gridfield.core.results.Field` of the complete model ``nf1`` on a voxel grid.

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    goal : (x, y, z)
        In a free voxel.
    params : mapping, optional
        Read: ``model`` (``nf1``, the default; the others are refused), ``attraction``,
        ``clearance_band``, ``band_gain`` (registry defaults, scaled to the map).
    stop_at : (x, y, z), optional
        The start of a planned query: the wavefront settles the voxels up to its value plus
        :data:`~gridfield.fields.navigation3d.STOP_MARGIN_CELLS` cells (times the largest slowness),
        ``inf`` beyond.
    clearance : ndarray, optional
        The map's clearance (``voxel_clearance``) to reuse.

    Returns
    -------
    Field
        ``potential``, ``grad_x``, ``grad_y``, ``grad_z``; ``params`` resolved, ``progress_window`` 0
        unless given; ``distance`` is None.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((1, 1, 4), 1.0), np.zeros((1, 1, 4), bool))
    >>> nav_field3d(gm, (0.5, 0.5, 0.5)).potential.ravel().tolist()
    [0.0, 1.0, 2.0, 3.0]
    >>> nav_field3d(gm, (0.5, 0.5, 0.5), {"model": "nf2"})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: on a voxel grid the complete model is 'nf1'; model='nf2' is a 2-D model
    """
    from ..core.params import resolve_field, validate

    gm = check_voxel_map(gridmap, "nav_field3d")
    given = dict(validate(params))
    res = gm.grid.resolution
    p = resolve_field({"model": "nf1", **given}, unit=res)
    if p["model"] != "nf1":
        raise ParameterError(f"on a voxel grid the complete model is 'nf1'; model={p['model']!r} is a 2-D model")
    band, gain = float(p["clearance_band"]), float(p["band_gain"])
    occ = np.asarray(gm.occupied, dtype=bool)
    slow = None
    if p["attraction"] != "octile" and band > 0 and gain > 0:
        d = voxel_clearance(gm) if clearance is None else clearance
        slow = band_slowness(d, occ, band, gain)
        slow[occ] = 1.0  # never read (blocked voxels are not entered)
    top = 1.0 + gain if slow is not None else 1.0
    U = voxel_wavefront(gm, goal, slowness=slow, stop_at=stop_at, margin=STOP_MARGIN_CELLS * res * top)
    gz, gy, gx = upwind_gradient3d(U, res)
    g = gm.check_point("goal", goal)
    if "progress_window" not in given:
        p["progress_window"] = NF_PROGRESS_WINDOW
    return Field(gm, U, gx, gy, (float(g[0]), float(g[1]), float(g[2])), p, None, grad_z=gz)  # type: ignore[arg-type]
