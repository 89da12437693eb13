"""The field at points: the force and potential of a grid Field, segment blocking, the attraction.

:func:`grid_sampler` samples ``F = -grad U`` from a :class:`~gridfield.fields.potential.Field`'s
gradient arrays: ``bilinear`` interpolation between the four surrounding cell centres that are
*free* (obstacle cells' weights are dropped and the rest renormalized, so obstacle cells'
zero gradients never blend in), clamped to the grid (no extrapolation); or ``nearest`` (the
cell containing the point, the vortex field's follower). :func:`grid_blocked` walks the cells a segment crosses
exactly. **Open border**: what lies outside the grid is free space; the follower may leave
the grid, and the field there is the field at the nearest point of the grid (clamping).
**Wall border**: leaving the grid is blocked, like entering an obstacle.

The kernels are compiled (:mod:`gridfield.fields._samplers`); :func:`grid_sampler`,
:func:`grid_potential_sampler` and :func:`grid_blocked` return callables for one point at a time
(what :func:`gridfield.following.descent.descend` asks for), :func:`sample_force` samples many points at once.

Examples
--------
>>> from types import SimpleNamespace
>>> gm = GridMap(Grid((1, 2), 1.0), np.zeros((1, 2), bool))
>>> f = SimpleNamespace(map=gm, grad_x=np.array([[1.0, 3.0]]), grad_y=np.zeros((1, 2)))
>>> grid_sampler(f)((1.0, 0.5)), sample_force(f, [[0.5, 0.5], [1.5, 0.5]]).tolist()
((-2.0, -0.0), [[-1.0, -0.0], [-3.0, -0.0]])
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.chunkcache import is_lazy
from ..core.coords import as_points, as_xy
from ..core.errors import ParameterError
from ..core.grid import Grid, GridMap
from ..core.params import REGISTRY, Attraction, Model, Vortex, check, known
from ..core.results import GradientField
from ._samplers import ForceSampler, SegmentTest, ValueSampler, _cell_values, _force_many, _segment_blocked
from .sampler_args import gradient_arrays, grid_args

__all__ = [
    "SAMPLINGS",
    "GradientField",
    "attraction_force",
    "clearance_at",
    "distance_at",
    "grid_blocked",
    "grid_potential_sampler",
    "grid_sampler",
    "sample_force",
]

#: How the gradient arrays are sampled at a point (the registry's choices for ``sampling``).
SAMPLINGS: tuple[str, ...] = REGISTRY["sampling"].choices
Point = tuple[float, float]


def _lazy_force(field: GradientField, sampling: str) -> Callable[[Point], tuple[float, float]]:
    from ..core import chunkcache as cc

    g = field.map.grid
    mk: Callable[..., Any] = cc.nearest2 if sampling == "nearest" else cc.bilinear2
    f = mk(field.grad_x, field.grad_y, field.map.occupied, g.origin[0], g.origin[1], g.resolution)

    def force(p: Point) -> tuple[float, float]:
        vx, vy = f(p[0], p[1])
        return -vx, -vy

    return force


def grid_sampler(field: GradientField, *, sampling: str = "bilinear") -> Callable[[Point], tuple[float, float]]:
    """``force(p) -> (fx, fy)``: the force ``-grad U`` of a Field at world points, from its arrays.

    ``bilinear`` interpolates among the free corner cells only (renormalized weights) and clamps to
    the grid; ``nearest`` takes the cell containing the point (clamped); obstacle cells give 0.

    Parameters
    ----------
    field : Field
        From :func:`gridfield.fields.potential.build_field` (anything with ``map``, ``grad_x``, ``grad_y``).
    sampling : {"bilinear", "nearest"}

    Returns
    -------
    callable
        ``force((x, y)) -> (fx, fy)``, one compiled call per point (the arrays are bound once).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> gm = GridMap(Grid((2, 3), 1.0), np.array([[False, False, True], [False, False, False]]))
    >>> gx = np.array([[1.0, 3.0, 0.0], [1.0, 3.0, 5.0]])
    >>> f = grid_sampler(SimpleNamespace(map=gm, grad_x=gx, grad_y=np.zeros((2, 3))))
    >>> f((1.0, 1.0))   # halfway between the centres 0.5 and 1.5: -(1 + 3) / 2
    (-2.0, -0.0)
    >>> f((2.0, 0.5))   # the obstacle cell (row 0, col 2) is left out
    (-3.0, -0.0)
    """
    check("sampling", sampling)
    if is_lazy(field):  # a field read from a Zarr store: sampled through its chunk cache
        return _lazy_force(field, sampling)
    gx, gy = gradient_arrays(field)
    occ, x0, y0, res = grid_args(field.map)
    nearest = sampling == "nearest"
    force: Callable[[Point], tuple[float, float]] = ForceSampler(gx, gy, occ, x0, y0, res, nearest)
    return force


def sample_force(field: GradientField, points: ArrayLike, *, sampling: str = "bilinear") -> NDArray[np.float64]:
    """The force ``-grad U`` of a Field at many world points at once, sampled like :func:`grid_sampler`.

    One compiled pass over the points: use it rather than a Python loop over ``grid_sampler`` calls
    when the points are known together (a quiver plot, a batch of robot positions, a trajectory).

    Parameters
    ----------
    field : Field
        From :func:`gridfield.fields.potential.build_field` (anything with ``map``, ``grad_x``, ``grad_y``).
    points : array_like, shape (N, 2) or (2,)
        World points ``(x, y)``; they must be finite. Points outside the grid are clamped to it.
    sampling : {"bilinear", "nearest"}

    Returns
    -------
    ndarray, shape (N, 2)
        ``(fx, fy)`` per point; 0 in obstacle cells.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> gm = GridMap(Grid((2, 3), 1.0), np.array([[False, False, True], [False, False, False]]))
    >>> gx = np.array([[1.0, 3.0, 0.0], [1.0, 3.0, 5.0]])
    >>> sample_force(SimpleNamespace(map=gm, grad_x=gx, grad_y=np.zeros((2, 3))), [[1.0, 1.0], [2.0, 0.5]])
    array([[-2., -0.],
           [-3., -0.]])
    """
    check("sampling", sampling)
    pts = as_points(points)
    if not np.isfinite(pts).all():
        k = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise ParameterError(f"points must be finite; point {k} is {pts[k].tolist()}")
    if is_lazy(field):
        f = _lazy_force(field, sampling)
        return np.array([f((x, y)) for x, y in pts.tolist()], dtype=np.float64).reshape(-1, 2)
    gx, gy = gradient_arrays(field)
    occ, x0, y0, res = grid_args(field.map)
    xs, ys = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
    fx, fy = np.empty(len(pts)), np.empty(len(pts))
    if len(pts):
        _force_many(gx, gy, occ, x0, y0, res, sampling == "nearest", xs, ys, fx, fy)
    return np.stack([fx, fy], axis=1)


def grid_potential_sampler(field: GradientField, *, sampling: str = "bilinear") -> Callable[[Point], float]:
    """``potential(p) -> U``: a Field's potential at world points, sampled like :func:`grid_sampler`.

    Only free corner cells enter the bilinear interpolation (obstacle cells hold ``+inf``); the
    potential-increase escape of :func:`gridfield.following.descent.descend` reads it.

    Parameters
    ----------
    field : Field
        Anything with ``map`` and ``potential``.
    sampling : {"bilinear", "nearest"}

    Returns
    -------
    callable
        ``potential((x, y)) -> U``.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> gm = GridMap(Grid((1, 3), 1.0), np.array([[False, False, True]]))
    >>> u = grid_potential_sampler(SimpleNamespace(map=gm, potential=np.array([[1.0, 3.0, np.inf]])))
    >>> u((1.0, 0.5)), u((2.0, 0.5))   # halfway between 1 and 3; next to the obstacle: its cell left out
    (2.0, 3.0)
    """
    check("sampling", sampling)
    if is_lazy(field):
        from ..core import chunkcache as cc

        g = field.map.grid
        mk: Callable[..., Any] = cc.nearest2 if sampling == "nearest" else cc.bilinear2
        fu = mk(field.potential, field.potential, field.map.occupied, g.origin[0], g.origin[1], g.resolution)
        return lambda p: fu(p[0], p[1])[0]
    u = np.ascontiguousarray(field.potential, dtype=np.float64)
    occ, x0, y0, res = grid_args(field.map)
    potential: Callable[[Point], float] = ValueSampler(u, occ, x0, y0, res, sampling == "nearest")
    return potential


def grid_blocked(gridmap: GridMap) -> Callable[[Point, Point], bool]:
    """``blocked(p, q)``: whether the segment ``p -> q`` crosses an occupied cell or leaves a walled map.

    The cells are walked exactly (a segment through a cell corner checks both side cells). Outside
    an open-border grid is free.

    Parameters
    ----------
    gridmap : GridMap

    Returns
    -------
    callable
        ``blocked((x, y), (x2, y2)) -> bool``.

    Examples
    --------
    >>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
    >>> b = grid_blocked(GridMap(Grid((3, 3), 1.0), occ))
    >>> b((0.5, 0.5), (2.5, 0.5)), b((0.5, 0.5), (2.5, 2.5)), b((0.5, 1.5), (-1.0, 1.5))
    (False, True, False)
    >>> bw = grid_blocked(GridMap(Grid((3, 3), 1.0, border="wall"), occ))
    >>> bw((0.5, 1.5), (-1.0, 1.5))
    True
    """
    if is_lazy(gridmap):
        from ..core.chunkcache import segment_blocked

        g = gridmap.grid
        return segment_blocked(cast("Any", gridmap.occupied), g.origin[0], g.origin[1], g.resolution, g.border == "wall",
                               _segment_blocked)
    occ, x0, y0, res = grid_args(gridmap)
    wall = gridmap.grid.border == "wall"
    blocked: Callable[[Point, Point], bool] = SegmentTest(occ, x0, y0, res, wall)
    return blocked


def attraction_force(goal: ArrayLike, params: Mapping[str, Any]) -> Callable[[Point], tuple[float, float]]:
    """``attraction(p) -> (fx, fy)``: the attractive force of the potential models at a point.

    ``model="khatib"``: ``-grad`` of :mod:`gridfield.fields.potential`'s quadratic / combined / conic
    attractive potential (``zeta``, ``d_star``); ``model="vortex"``: ``-ka * (p - goal)``.

    Parameters
    ----------
    goal : (x, y)
    params : mapping
        Resolved parameters: ``model``, and ``zeta``, ``d_star`` (khatib) or ``ka`` (vortex).

    Returns
    -------
    callable
        ``attraction((x, y)) -> (fx, fy)``.

    Examples
    --------
    >>> f = attraction_force((0.0, 0.0), {"zeta": 2.0, "d_star": 1.0})
    >>> f((0.5, 0.0)), f((4.0, 0.0))
    ((-1.0, -0.0), (-2.0, -0.0))
    """
    gx, gy = as_xy(goal, "goal")
    p = known(params)
    if p.group(Model).model == "vortex":
        ka = float(p.group(Vortex).ka)

        def vortex_attr(p: Point) -> tuple[float, float]:
            return -ka * (p[0] - gx), -ka * (p[1] - gy)

        return vortex_attr
    a = p.group(Attraction)
    zeta = float(a.zeta)
    # an unresolved d_star (None: 2 q_star, scaled to a map this point function does not know): no conic part
    d_star = math.inf if a.d_star is None else float(a.d_star)

    def attr(p: Point) -> tuple[float, float]:
        dx, dy = p[0] - gx, p[1] - gy
        d = math.sqrt(dx * dx + dy * dy)
        if d == 0.0:
            return 0.0, 0.0
        if d_star == 0.0:  # pure conic (potential.py's separate case)
            return -zeta * dx / d, -zeta * dy / d
        if d <= d_star:
            return -zeta * dx, -zeta * dy
        return -d_star * zeta * dx / d, -d_star * zeta * dy / d

    return attr


def distance_at(field: GradientField, points: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Brushfire (Euclidean) distance of the cells containing the points (clamped to the grid), and
    whether each point lies inside the grid.

    Parameters
    ----------
    field : GradientField
        A field; its ``distance`` (the brushfire it was built on) is read, else the Euclidean
        brushfire of its map is computed; a stored (lazy) field reads its stored distances chunk by
        chunk (NaN where none was stored).
    points : ndarray of float, shape (n, 2)
        World coordinates.

    Returns
    -------
    distance : ndarray of float, shape (n,)
        The distance of each point's cell (the nearest cell of the grid for a point outside it).
    inside : ndarray of bool, shape (n,)
        Whether each point lies inside the grid.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((1, 4), bool); occ[0, 0] = True
    >>> f = SimpleNamespace(map=GridMap(Grid((1, 4), 1.0), occ), distance=None)
    >>> d, inside = distance_at(f, np.array([[3.5, 0.5], [9.0, 0.5]]))
    >>> d.tolist(), inside.tolist()
    ([3.0, 3.0], [True, False])
    """
    dmap = getattr(field, "distance", None)
    if is_lazy(field):  # a stored field: its stored distances, read chunk by chunk (NaN when none was stored)
        from ..core.chunkcache import cell_values

        return cell_values(None if dmap is None else dmap.distance, field.map.grid, points)
    if dmap is None:
        from ..distance.brushfire import brushfire

        dmap = brushfire(field.map, metric="euclidean")
    dist = np.ascontiguousarray(dmap.distance, dtype=np.float64)
    grid: Grid = field.map.grid
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    out = np.empty(len(pts))
    inside = np.empty(len(pts), np.bool_)
    _cell_values(dist, grid.origin[0], grid.origin[1], grid.resolution, pts[:, 0].copy(), pts[:, 1].copy(), out,
                 inside)
    return out, inside


def clearance_at(field: GradientField, points: NDArray[np.float64]) -> float:
    """Smallest brushfire distance at the cells of the path's points (:func:`distance_at`); NaN for
    no points.

    Parameters
    ----------
    field : GradientField
        The field the path followed.
    points : ndarray of float, shape (n, 2)
        The path's points.

    Returns
    -------
    float

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((1, 4), bool); occ[0, 0] = True
    >>> f = SimpleNamespace(map=GridMap(Grid((1, 4), 1.0), occ), distance=None)
    >>> clearance_at(f, np.array([[1.5, 0.5], [3.5, 0.5]]))
    1.0
    """
    return float(np.min(distance_at(field, points)[0])) if len(points) else math.nan

