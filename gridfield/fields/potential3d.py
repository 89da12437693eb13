"""The classic attractive/repulsive (Khatib) field on voxel grids (3-D).

The same model as :mod:`gridfield.fields.potential` (``model="khatib"``), per voxel centre ``q``:
attractive ``0.5 zeta d**2`` within ``d_star`` of the goal and ``d_star zeta d - 0.5 zeta d_star**2``
beyond (``d_star = 0``: the pure cone ``zeta d``), plus the repulsion ``0.5 eta (1/D - 1/q_star)**2``
for ``D < q_star``, whose gradient is ``-eta (1/D - 1/q_star) / D**p`` along ``grad D`` (``p =
repulsive_power``; 2 is the gradient of the potential). ``D`` is the Euclidean distance from the voxel
centre to the centre of the nearest blocked voxel (a wall border's shell included) and ``grad D`` the
unit vector from that centre, exact per voxel. Blocked voxels have ``U = inf`` and zero gradient.
``saturate = R`` drops the repulsion where ``D >= R``. The 2-D options ``repulsion="sum"``, the
chessboard/taxicab metrics and ``gradient="finite_difference"`` are refused on voxels.

The field can trap its follower in a local minimum (it is the classic field); the ``potential``
planner reports it as in 2-D.

Examples
--------
>>> from gridfield.core.grid import Grid, GridMap
>>> gm = GridMap(Grid((1, 1, 4), 1.0), np.zeros((1, 1, 4), bool))
>>> f = build_field3d(gm, (0.5, 0.5, 0.5), {"zeta": 2.0, "d_star": 1.0})
>>> f.potential.ravel().tolist(), f.grad_x.ravel().tolist()
([0.0, 1.0, 3.0, 5.0], [0.0, 2.0, 2.0, 2.0])
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ..core.limits import check_grid
from ..core.results import Field
from .navigation3d import check_voxel_map, voxel_clearance

__all__ = ["build_field3d"]


def build_field3d(gridmap: GridMap, goal: ArrayLike, params: Mapping[str, Any] | None = None) -> Field:
    """The potential field of ``params`` on a voxel grid: ``model="khatib"`` (the default here, as for
    :func:`gridfield.fields.potential.build_field`) or the complete ``nf1``
    (:func:`gridfield.fields.navfield3d.nav_field3d`).

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    goal : (x, y, z)
        In a free voxel.
    params : mapping, optional
        Read: ``zeta``, ``d_star``, ``eta``, ``q_star``, ``repulsive_power``, ``saturate``, ``model``
        (defaults of the registry, scaled to the map as in 2-D).

    Returns
    -------
    Field
        ``potential``, ``grad_x``, ``grad_y``, ``grad_z`` in world units; ``params`` resolved.

    Raises
    ------
    ParameterError
        A 2-D-only option, or not a voxel grid.
    GridfieldError
        A goal outside the grid or in a blocked voxel.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((1, 1, 4), bool); occ[0, 0, 3] = True
    >>> f = build_field3d(GridMap(Grid((1, 1, 4), 1.0), occ), (0.5, 0.5, 0.5), {"eta": 1.0, "q_star": 3.0})
    >>> f.potential.ravel().round(4).tolist()   # 0.5 d**2 + 0.5 (1/D - 1/3)**2 within D < 3
    [0.0, 0.5139, 2.2222, inf]
    """
    from ..core.params import resolve_field, validate

    gm = check_voxel_map(gridmap, "build_field")
    check_grid(gm.grid.shape, "field", f"build_field on {gm.source or 'the voxel grid'}")
    given = dict(validate(params))
    p = resolve_field(given, unit=gm.grid.resolution)
    if p["model"] is None:
        p["model"] = "khatib"
    if p["model"] in ("nf1", "nf2", "nf-blend"):
        from .navfield3d import nav_field3d

        return nav_field3d(gm, goal, given)
    if p["model"] != "khatib":
        raise ParameterError(f"on a voxel grid the field models are 'khatib' and 'nf1'; model={p['model']!r} is 2-D")
    for name, ok in (("repulsion", "nearest"), ("metric", "euclidean"), ("gradient", "analytic")):
        if p[name] != ok:
            raise ParameterError(f"{name}={p[name]!r} is a 2-D option; a voxel grid's Khatib field uses {name}={ok!r}")
    g = gm.check_point("goal", goal)
    grid = gm.grid
    res = grid.resolution
    xs, ys, zs = grid.cell_centers()
    Z, Y, X = np.meshgrid(zs, ys, xs, indexing="ij")
    vec = (X - g[0], Y - g[1], Z - g[2])
    d = np.sqrt(vec[0] ** 2 + vec[1] ** 2 + vec[2] ** 2)
    zeta, d_star = float(p["zeta"]), float(p["d_star"])
    if d_star == 0.0:  # the pure cone
        U = zeta * d
        with np.errstate(invalid="ignore", divide="ignore"):
            scale = np.where(d > 0, zeta / d, 0.0)
    elif math.isinf(d_star):
        U = 0.5 * zeta * d * d
        scale = np.full(d.shape, zeta)
    else:
        near = d <= d_star
        U = np.where(near, 0.5 * zeta * d * d, d_star * zeta * d - 0.5 * zeta * d_star * d_star)
        with np.errstate(invalid="ignore", divide="ignore"):
            scale = np.where(near, zeta, np.where(d > 0, d_star * zeta / d, 0.0))
    G = [v * scale for v in vec]
    D, idx = voxel_clearance(gm, nearest=True)
    eta, q_star, power = float(p["eta"]), float(p["q_star"]), float(p["repulsive_power"])
    sat = math.inf if p["saturate"] is None else float(p["saturate"])
    occ = np.asarray(gm.occupied, dtype=bool)
    rep = (q_star > D) & (sat > D) & ~occ & (D > 0)
    if rep.any():
        Dr = D[rep]
        nearest = [grid.origin[a] + (idx[2 - a][rep] + 0.5) * res for a in range(3)]  # x, y, z of the obstacle
        here = (X[rep], Y[rep], Z[rep])
        inv = 1.0 / Dr - (0.0 if math.isinf(q_star) else 1.0 / q_star)
        U[rep] += 0.5 * eta * inv * inv
        mag = eta * inv / Dr ** power  # the force's size along grad D
        for a in range(3):
            G[a][rep] -= mag * (here[a] - nearest[a]) / Dr
    U[occ] = np.inf
    for a in range(3):
        G[a][occ] = 0.0
    return Field(gm, U, G[0], G[1], (float(g[0]), float(g[1]), float(g[2])), p, None,  # type: ignore[arg-type]
                 grad_z=G[2])
