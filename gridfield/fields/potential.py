"""Potentials and their gradient arrays: attractive, repulsive (Khatib), saturated, vortex.

Every function here takes arrays (a :class:`~gridfield.core.grid.Grid`, a
:class:`~gridfield.distance.brushfire.DistanceMap`) and returns arrays of the grid's shape, indexed
``[row, col]`` with row 0 at the lowest y (see :mod:`gridfield.core.grid`). Values are evaluated at
**cell centres**; gradients are in world units (``dU/dx``, ``dU/dy``). The force a follower uses is
``-(grad_x, grad_y)``.

The models (names from Choset et al. ch. 4):

attractive (goal ``g``, ``d = |q - g|``)
    ``d_star = inf``: quadratic ``0.5*zeta*d**2`` everywhere.
    ``0 < d_star < inf``: Choset's combined form (seed 002): ``0.5*zeta*d**2`` for ``d <= d_star``,
    ``d_star*zeta*d - 0.5*zeta*d_star**2`` beyond; value and gradient are continuous at ``d_star``
    and the gradient magnitude is capped at ``zeta*d_star``.
    ``d_star = 0``: pure conic ``zeta*d`` (gradient magnitude ``zeta``, 0 at the goal itself). This
    is a separate case, not the limit of the combined form (whose slope ``zeta*d_star`` tends to 0).

repulsive (distance ``D`` to the nearest obstacle, influence ``q_star``)
    ``U = 0.5*eta*(1/D - 1/q_star)**2`` for ``D < q_star``, 0 beyond. The force is
    ``eta*(1/D - 1/q_star)/D**p`` along ``grad D`` with ``p = repulsive_power``. For ``p = 2`` the
    arrays are exactly ``grad U``. For any other ``p`` (seed 000 uses ``p = 3``) the force has no
    relation to ``U``: the potential array **stays the classic potential above** and the gradient
    arrays hold the negative of the ``p``-model force (so that the follower moves along the
    seed's force); ``gradient="finite_difference"`` is refused there because it would silently
    differentiate the ``p = 2`` potential instead.

``D``, the distance behind the repulsion
    ``D`` is the brushfire's distance: the Euclidean distance from the cell centre to the **centre
    of the nearest occupied cell** (for ``metric="chessboard"``/``"taxicab"`` that metric's
    distance, as in seed 002's grid brushfire). The wall border counts as a ring of occupied cells
    just outside the grid. ``grad D`` is the unit vector from that nearest cell centre to the cell
    centre: an exact direction, taken from the single nearest obstacle cell, so nothing is
    smeared across the generalized Voronoi diagram. Against the exact distances of the seed worlds
    (``world.distance``) with the conservative rasterization, it was the most accurate of the
    distances tried, in value and in direction, at every resolution from 0.4 to 0.05; the distance
    to the nearest point of the nearest occupied *square* is a guaranteed lower bound but biased by
    a full cell, because a conservative rasterization marks cells the obstacle only touches (the
    figures: ``benchmarks/README.md``, "Potentials", "The distance behind the repulsion"). On
    conservatively rasterized worlds ``D`` still underestimates the exact distance (the nearest
    occupied cell is the one sticking out most), so the grid repulsion errs on the strong, safe
    side. On bitmaps, where the pixel square itself is the obstacle, ``D``
    overestimates by half a cell along axis-parallel edges.

``repulsion="sum"`` (seed 000)
    One term per obstacle, each with that obstacle's own distance, summed. Obstacles are the
    labels of the occupied cells (world obstacle ids when the map was rasterized from a world,
    else 8-connected components); the wall border is one more obstacle. Each term is computed only
    in the obstacle's bounding box dilated by ``q_star`` (a Euclidean distance transform with
    indices on that window), never in a full-grid pass per obstacle.

saturated distance (seed 004)
    With ``saturate = R``, distances ``D >= R`` become ``far`` (the distance map's ``far``,
    ``inf`` by default) and exert no repulsion. With ``R < q_star`` the repulsion then drops to
    zero at ``D = R``: the seed's behaviour.

vortex (seed 003)
    See :func:`vortex_field`.

complete models (``model="nf1"``, ``"nf2"``, ``"nf-blend"``)
    Numerical navigation functions with one minimum per free component, the goal: see
    :mod:`gridfield.fields.navfield`. :func:`build_field` builds ``"khatib"`` when ``model`` is unset; the
    ``potential`` planner (:func:`gridfield.following.follower.plan_potential`) builds ``"nf1"``.

Obstacle cells hold ``potential = +inf`` and zero gradients in every model. All returned arrays
are float64, computed in float64: the fused kernel (compiled ahead of time, branch-free so that it
vectorizes, IEEE division semantics) streams its outputs at ``np.copyto`` speed
(``benchmarks/README.md``, "Potentials"), so float32 could only gain by halving the bytes, at the
cost of precision where ``U`` spans many orders of magnitude near obstacles. Grids below
2048 x 2048 cells are computed on the calling thread only.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.coords import as_xy
from ..core.errors import ParameterError
from ..core.grid import Grid, GridMap
from ..core.limits import check_grid
from ..core.params import REGISTRY, check
from ..core.results import Field
from ..distance.brushfire import DistanceMap, brushfire
from . import _potential as _kp  # type: ignore[attr-defined]  # a compiled extension, no stubs
from .potential_args import METRIC_CODE, integer_power, saturation
from .vortex import vortex_field, vortex_lattice, vortex_model_field

__all__ = [
    "GRADIENTS",
    "MODELS",
    "REPULSIONS",
    "Field",
    "attractive",
    "build_field",
    "finite_difference_gradient",
    "repulsive",
    "resolve_params",
    "vortex_field",
    "vortex_lattice",
]

#: The options of ``repulsion``, ``gradient`` and ``model`` (the registry's choices).
REPULSIONS: tuple[str, ...] = REGISTRY["repulsion"].choices
GRADIENTS: tuple[str, ...] = REGISTRY["gradient"].choices
MODELS: tuple[str, ...] = REGISTRY["model"].choices
#: The complete models, built by :func:`gridfield.fields.navfield.nav_field` (kept here so that resolving
#: parameters does not import it).
_NF_MODELS = ("nf1", "nf2", "nf-blend")


# ----------------------------------------------------------------------------------------------
# parameters
# ----------------------------------------------------------------------------------------------
def resolve_params(params: Mapping[str, Any] | None = None, *, unit: float = 1.0) -> dict[str, Any]:
    """Validate potential parameters and fill in the defaults, lengths scaled to the map.

    Names and values are checked against the registry (:data:`gridfield.core.params.REGISTRY`); names a
    potential does not read (the follower's ``step``, ``alpha``, ...) pass through validated.
    Defaults (the registry's, of :data:`gridfield.core.params.FIELD_GROUPS`): ``zeta=1``, ``repulsive_power=2``, ``repulsion='nearest'``,
    ``metric='euclidean'``, ``gradient='analytic'``, ``model='khatib'``, ``saturate=None``; and,
    scaled to the map's length ``unit`` (its cell size) by :func:`gridfield.core.params.resolve`:
    ``q_star`` = 4 cells, ``d_star`` = 2 ``q_star``, ``eta`` balanced so that the repulsion at
    ``q_star / 2`` equals the largest attraction. Vortex model ``ka=25``, ``kr=30``, ``ko=5``,
    ``spacing=None`` (the map's resolution), ``sample_radius=None`` (1.05 x each circle's radius).

    Parameters
    ----------
    params : mapping, optional
        Parameter name -> value; given values always win.
    unit : float
        The map's length unit (a grid's cell size) the scaled defaults are expressed in.

    Returns
    -------
    dict
        The potential parameters (of :data:`gridfield.core.params.FIELD_GROUPS`), resolved, plus the other names given.

    Raises
    ------
    ParameterError
        for an unknown name, a negative gain, ``q_star <= 0``, NaN, ``inf`` where it is not
        allowed (only ``d_star`` and ``q_star`` may be infinite), or an unknown option string; the
        message names the parameter, the value and what is valid.

    Examples
    --------
    >>> p = resolve_params({"eta": 2, "step": 0.1})
    >>> p["eta"], p["q_star"], p["d_star"], p["repulsion"], p["step"]
    (2.0, 4.0, 8.0, 'nearest', 0.1)
    >>> resolve_params({}, unit=0.05)["q_star"]
    0.2
    >>> resolve_params({"repulsion": "all"})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: repulsion must be one of 'nearest', 'sum'; got 'all'
    >>> resolve_params({"q_star": 0})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: q_star must be a number > 0 (inf allowed), got 0
    """
    from ..core.params import resolve_field

    given = dict(params or {})
    p = resolve_field(given, unit=unit)
    if p["model"] is None:  # unset: the array API's model (the potential planner resolves it to 'nf1')
        p["model"] = "khatib"
    if p["model"] == "khatib" and p["gradient"] == "finite_difference" and p["repulsive_power"] != 2:
        raise ParameterError(
            f"gradient='finite_difference' differentiates the potential 0.5*eta*(1/D - 1/q_star)**2, whose "
            f"gradient is the repulsive_power=2 force; repulsive_power={p['repulsive_power']:g} has no such "
            "potential: use gradient='analytic' or repulsive_power=2"
        )
    if p["model"] == "vortex":
        if "gradient" in given and p["gradient"] != "finite_difference":
            raise ParameterError(
                "the vortex model is defined by finite differences on its lattice; "
                "use gradient='finite_difference' (or leave gradient unset)"
            )
        p["gradient"] = "finite_difference"
    return p


#: Below this many cells (2048^2) the parallel kernels run on the calling thread only. The kernels
#: are memory-bound (one thread streams at ``np.copyto`` speed), so a second thread gains little,
#: and on a busy machine waiting for the thread pool cost more than the kernel itself (the figures:
#: benchmarks/README.md, "Potentials").
_PARALLEL_MIN_CELLS = 1 << 22


@contextlib.contextmanager
def _threads_for(cells: int) -> Iterator[None]:
    if cells >= _PARALLEL_MIN_CELLS:
        yield
        return
    before = _kp.get_num_threads()
    _kp.set_num_threads(1)
    try:
        yield
    finally:
        _kp.set_num_threads(before)


def _khatib_arrays(
    occ: NDArray[np.bool_] | None, nr: NDArray[Any] | None, nc: NDArray[Any] | None, grid: Grid,
    goal: tuple[float, float], zeta: float, d_star: float,
    metric: str, eta: float, q_star: float, power: float, sat: float, far: float, *, nearest: bool = True,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """U, dU/dx, dU/dy: attractive (``zeta = 0``: none) + nearest-obstacle repulsive (if ``nearest``).

    ``occ is None``: attractive only, no obstacles. Otherwise obstacle cells get ``+inf`` / 0.
    """
    U, GX, GY = np.empty(grid.shape), np.empty(grid.shape), np.empty(grid.shape)
    x0, y0 = grid.origin
    if occ is None:
        with _threads_for(U.size):
            _kp._attractive_kernel(x0, y0, grid.resolution, goal[0], goal[1], zeta, d_star, d_star == 0.0, U, GX, GY)
        return U, GX, GY
    occ = np.ascontiguousarray(occ, dtype=bool)
    assert nr is not None and nc is not None
    nr, nc = _int32(nr), _int32(nc)
    ipow = integer_power(power)
    fused = nearest and 0 <= ipow <= 4
    code = METRIC_CODE[metric]
    with _threads_for(U.size):
        _kp._khatib_kernel(occ, nr, nc, x0, y0, grid.resolution, goal[0], goal[1], zeta, d_star, d_star == 0.0, code,
                       eta if fused else 0.0, q_star, max(ipow, 0), sat, far, U, GX, GY)
    if nearest and not fused:
        _kp._rep_accumulate(occ, nr, nc, 0, 0, grid.resolution, code, eta, q_star, ipow, power, sat, far, U, GX, GY)
    return U, GX, GY


# ----------------------------------------------------------------------------------------------
# array functions
# ----------------------------------------------------------------------------------------------
def attractive(
    grid: Grid, goal: ArrayLike, *, zeta: float = 1.0, d_star: float = math.inf
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Attractive potential and its gradient at the cell centres of ``grid``.

    Parameters
    ----------
    grid : Grid
    goal : (x, y)
        World coordinates of the goal (it may lie anywhere, even off the grid).
    zeta : float
        Attractive gain (>= 0).
    d_star : float
        ``inf``: quadratic ``0.5*zeta*d**2``; ``0 < d_star < inf``: quadratic up to ``d_star``, then
        conic ``d_star*zeta*d - 0.5*zeta*d_star**2`` (continuous value and gradient);
        ``0``: pure conic ``zeta*d`` (gradient 0 at the goal itself).

    Returns
    -------
    U, grad_x, grad_y : ndarray of float64, shape ``grid.shape``

    Examples
    --------
    >>> g = Grid((1, 4), 1.0)
    >>> U, gx, gy = attractive(g, (0.5, 0.5), zeta=2.0, d_star=1.0)
    >>> U.tolist(), gx.tolist(), gy.tolist()
    ([[0.0, 1.0, 3.0, 5.0]], [[0.0, 2.0, 2.0, 2.0]], [[0.0, 0.0, 0.0, 0.0]])
    """
    gx0, gy0 = as_xy(goal, "goal")
    zeta = check("zeta", zeta)
    d_star = check("d_star", d_star)
    return _khatib_arrays(None, None, None, grid, (gx0, gy0), zeta, d_star, "euclidean", 0.0, 1.0, 2.0,
                          math.inf, math.inf)


def _int32(a: NDArray[Any]) -> NDArray[np.int32]:
    return np.ascontiguousarray(a, dtype=np.int32)


def repulsive(
    dmap: DistanceMap,
    *,
    eta: float = 1.0,
    q_star: float = 2.0,
    power: float = 2.0,
    mode: str = "nearest",
    gradient: str = "analytic",
    saturate: float | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Repulsive potential ``0.5*eta*(1/D - 1/q_star)**2`` (0 beyond ``q_star``) and its gradient.

    Parameters
    ----------
    dmap : DistanceMap
        The brushfire of the map; its ``metric`` defines ``D`` (see the module docstring) and its
        nearest-obstacle cells give ``grad D``. Its ``saturate``/``far`` are honoured.
    eta : float
        Repulsive gain (>= 0).
    q_star : float
        Distance of influence (> 0; ``inf`` allowed).
    power : float
        ``p`` of the force ``eta*(1/D - 1/q_star)/D**p`` along ``grad D``; 2 gives exactly
        ``grad U``. For other ``p`` the returned gradient is the negative of that force and ``U``
        is still the classic potential.
    mode : {"nearest", "sum"}
        One term from the nearest obstacle, or one term per obstacle summed (seed 000).
    gradient : {"analytic", "finite_difference"}
        From the nearest-obstacle vectors, or :func:`finite_difference_gradient` of ``U``
        (only for ``power == 2``).
    saturate : float, optional
        Saturation radius: distances ``>= saturate`` become ``dmap.far`` (default: ``dmap.saturate``).

    Returns
    -------
    U, grad_x, grad_y : ndarray of float64
        ``U = +inf`` and zero gradient on obstacle cells.

    Examples
    --------
    A single obstacle cell; the cell two to the right has ``D = 2``:

    >>> occ = np.zeros((1, 4), bool); occ[0, 0] = True
    >>> U, gx, gy = repulsive(brushfire(GridMap(Grid((1, 4), 1.0), occ), metric="euclidean"), q_star=4.0)
    >>> float(U[0, 2]) == 0.5 * (1/2 - 1/4) ** 2, float(gx[0, 2]) == -(1/2 - 1/4) / 2**2
    (True, True)
    >>> float(U[0, 0]), float(gx[0, 0])
    (inf, 0.0)
    """
    eta = check("eta", eta)
    q_star = check("q_star", q_star)
    power = check("repulsive_power", power, argument="power")
    mode = check("repulsion", mode, argument="mode")
    gradient = check("gradient", gradient)
    if gradient == "finite_difference" and power != 2:
        raise ParameterError(f"gradient='finite_difference' needs power=2 (the gradient of U), got power={power:g}")
    if saturate is not None:
        saturate = check("saturate", saturate)
    sat, far = saturation(dmap, saturate)
    grid = dmap.grid
    occ = dmap.map.occupied
    U, GX, GY = _khatib_arrays(occ, dmap.nearest_row, dmap.nearest_col, grid, (0.0, 0.0), 0.0, math.inf,
                               dmap.metric, eta, q_star, power, sat, far, nearest=mode == "nearest")
    if mode == "sum":
        _sum_repulsion(dmap, eta, q_star, power, sat, far, U, GX, GY)
    if gradient == "finite_difference":
        GX, GY = finite_difference_gradient(U, grid)
    return U, GX, GY


def _obstacle_labels(dmap: DistanceMap) -> NDArray[np.int32]:
    """Occupied cells labelled by obstacle (world id or component, >= 1), 0 on free cells.

    Ids are used as they are when they are positive (one pass); occupied cells with id <= 0
    (e.g. cells added by an inflation) make all ids be renumbered 1..K instead.
    """
    occ = dmap.map.occupied
    ids = dmap.map.obstacle_id if dmap.map.obstacle_id is not None else dmap.label
    if ids is None:
        raise ParameterError(
            "the per-obstacle repulsion (mode/repulsion 'sum') needs obstacle labels, but this distance map "
            "was computed without them and its map has no obstacle ids: use brushfire(..., compute_labels=True) "
            "(or gridfield.fields.potential.field_distance_map with repulsion='sum')")
    lab = np.where(occ, ids, 0).astype(np.int32, copy=False)
    if lab.size and (lab[occ] <= 0).any():
        _, inverse = np.unique(ids[occ], return_inverse=True)
        lab[occ] = inverse.reshape(-1).astype(np.int32) + 1
    return lab


def _sum_repulsion(dmap: DistanceMap, eta: float, q_star: float, power: float, sat: float, far: float,
                   U: NDArray[np.float64], GX: NDArray[np.float64], GY: NDArray[np.float64]) -> None:
    """Add one repulsive term per obstacle (and the wall) to U, GX, GY in place."""
    from scipy import ndimage  # here, not at import: it costs about 0.3 s and only this model needs it

    grid = dmap.grid
    rows, cols = grid.shape
    res = grid.resolution
    occ = dmap.map.occupied
    metric = METRIC_CODE[dmap.metric]
    # no term beyond the influence distance, nor beyond the saturation radius (unless far is nearer)
    reach = q_star if far < q_star else min(q_star, sat)
    k = rows + cols if not math.isfinite(reach) else math.ceil(reach / res) + 1
    lab = _obstacle_labels(dmap)
    for i, box in enumerate(ndimage.find_objects(lab), start=1):
        if box is None:
            continue
        r0, r1 = max(box[0].start - k, 0), min(box[0].stop + k, rows)
        c0, c1 = max(box[1].start - k, 0), min(box[1].stop + k, cols)
        win = (slice(r0, r1), slice(c0, c1))
        mine = lab[win] == i
        if metric == 0:
            idx = ndimage.distance_transform_edt(~mine, return_distances=False, return_indices=True)
        else:
            idx = ndimage.distance_transform_cdt(~mine, metric=("chessboard", "taxicab")[metric - 1],
                                                 return_distances=False, return_indices=True)
        _kp._rep_accumulate(np.ascontiguousarray(occ[win]), _int32(idx[0]), _int32(idx[1]), 0, 0, res, metric, eta,
                        q_star, integer_power(power), power, sat, far, U[win], GX[win], GY[win])
    if grid.border == "wall":
        _wall_repulsion(grid, occ, metric, k, eta, q_star, power, sat, far, U, GX, GY)


def _wall_repulsion(grid: Grid, occ: NDArray[np.bool_], metric: int, k: int, eta: float, q_star: float,
                    power: float, sat: float, far: float, U: NDArray[np.float64], GX: NDArray[np.float64],
                    GY: NDArray[np.float64]) -> None:
    """The wall border as one obstacle: the ring of cells just outside the grid, within ``k`` cells."""
    rows, cols = grid.shape
    k = min(k, max(rows, cols))
    # disjoint bands covering every cell within k cells of an edge: bottom, top, left, right
    lo, hi = min(k, rows), max(rows - k, min(k, rows))
    bands = [(0, lo, 0, cols), (hi, rows, 0, cols), (lo, hi, 0, min(k, cols)), (lo, hi, max(cols - k, min(k, cols)), cols)]
    for r0, r1, c0, c1 in bands:
        if r1 <= r0 or c1 <= c0:
            continue
        r, c = np.mgrid[r0:r1, c0:c1].astype(np.int32)
        # nearest ring cell: straight out through the nearest edge (the four candidates' minimum)
        cand_r = np.stack([np.full_like(r, -1), np.full_like(r, rows), r, r])
        cand_c = np.stack([c, c, np.full_like(c, -1), np.full_like(c, cols)])
        which = np.argmin(np.stack([r + 1, rows - r, c + 1, cols - c]), axis=0)[None]
        nr = np.take_along_axis(cand_r, which, 0)[0]
        nc = np.take_along_axis(cand_c, which, 0)[0]
        win = (slice(r0, r1), slice(c0, c1))
        _kp._rep_accumulate(np.ascontiguousarray(occ[win]), _int32(nr - r0), _int32(nc - c0), 0, 0, grid.resolution,
                        metric, eta, q_star, integer_power(power), power, sat, far, U[win], GX[win], GY[win])


def finite_difference_gradient(
    U: NDArray[np.float64], grid: Grid
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(dU/dx, dU/dy)`` by finite differences (:func:`numpy.gradient`), aware of ``inf`` cells.

    Central differences where both neighbours along an axis are finite, one-sided differences
    where only one is (and at the grid edges, as :func:`numpy.gradient` does), 0 where neither is
    and on non-finite cells themselves.

    Parameters
    ----------
    U : ndarray, shape ``grid.shape``
        Values at the cell centres; ``inf`` (obstacles) and NaN cells are skipped.
    grid : Grid
        Gives the spacing.

    Returns
    -------
    grad_x, grad_y : ndarray of float64, shape ``grid.shape``

    Examples
    --------
    >>> U = np.array([[np.inf, 1.0, 2.0, 4.0]])
    >>> gx, gy = finite_difference_gradient(U, Grid((1, 4), 0.5))
    >>> gx.tolist(), gy.tolist()
    ([[0.0, 2.0, 3.0, 4.0]], [[0.0, 0.0, 0.0, 0.0]])
    """
    U = np.asarray(U, dtype=np.float64)
    if U.shape != grid.shape:
        raise ParameterError(f"U has shape {U.shape}, but the grid has shape {grid.shape}")
    finite = np.isfinite(U)
    Uf = np.where(finite, U, 0.0)
    h = grid.resolution
    out = []
    for axis in (1, 0):  # x along columns, y along rows
        n = U.shape[axis]
        if n < 2:
            out.append(np.zeros_like(U))
            continue
        g = np.gradient(Uf, h, axis=axis)
        fwd = np.zeros(U.shape, bool)  # the next cell along the axis exists and is finite
        bwd = np.zeros(U.shape, bool)
        lead = [slice(None)] * 2
        tail = [slice(None)] * 2
        lead[axis], tail[axis] = slice(0, n - 1), slice(1, n)
        fwd[tuple(lead)] = finite[tuple(tail)]
        bwd[tuple(tail)] = finite[tuple(lead)]
        diff = np.zeros_like(U)  # forward differences U[i+1] - U[i]
        diff[tuple(lead)] = (Uf[tuple(tail)] - Uf[tuple(lead)]) / h
        back = np.zeros_like(U)  # backward differences U[i] - U[i-1]
        back[tuple(tail)] = diff[tuple(lead)]
        interior = np.zeros(U.shape, bool)
        interior[tuple(lead)] = True
        interior &= np.roll(interior, 1, axis=axis)  # cells with both neighbours inside the grid
        g = np.where(interior & fwd & bwd, g, np.where(fwd, diff, np.where(bwd, back, 0.0)))
        g[~finite] = 0.0
        out.append(g)
    return out[0], out[1]


# ----------------------------------------------------------------------------------------------
# build_field
# ----------------------------------------------------------------------------------------------
def field_distance_map(gridmap: GridMap, params: Mapping[str, Any] | None = None, *,
                       labels: bool | None = None, steps: bool = False) -> DistanceMap:
    """The brushfire :func:`build_field` computes for ``params`` (its ``metric`` and ``saturate``;
    labels and GVD only where the per-obstacle sum needs them, unless ``labels`` says otherwise;
    the wavefront ``steps``, which no potential reads, only with ``steps=True``).

    Compute it once and pass it as ``dmap=`` to build many fields (other goals, other gains) on
    one map.

    Examples
    --------
    >>> occ = np.zeros((3, 4), bool); occ[0, 0] = True
    >>> d = field_distance_map(GridMap(Grid((3, 4), 1.0), occ), {"metric": "taxicab"})
    >>> float(d.distance[2, 3]), d.steps is None, d.label is None
    (5.0, True, True)
    """
    p = resolve_params(params)
    # Labels (and the GVD built from them) are read only by the per-obstacle sum of a grid without
    # world obstacle ids; skipping them saves a third of the brushfire's time and memory.
    if labels is None:
        labels = p["repulsion"] == "sum" and gridmap.obstacle_id is None
    return brushfire(gridmap, connectivity=4 if p["metric"] == "taxicab" else 8, metric=p["metric"],
                     saturate=p["saturate"], compute_steps=steps, compute_labels=labels, compute_gvd=labels)


def build_field(
    gridmap: GridMap, goal: ArrayLike, params: Mapping[str, Any] | None = None, *, dmap: DistanceMap | None = None
) -> Field:
    """Build the potential field of ``params`` on ``gridmap`` for ``goal``.

    ``model="khatib"`` (default): :func:`attractive` + :func:`repulsive` in one fused pass (for
    ``repulsion="nearest"``; ``"sum"`` adds the per-obstacle terms window by window).
    ``model="vortex"``: :func:`vortex_field` on the lattice of the map's world (its circles, its
    start, its bounds at ``spacing``); the returned field's map is that lattice, not ``gridmap``,
    and ``dmap`` is not used.
    ``model="nf1"``, ``"nf2"``, ``"nf-blend"``: the complete models of :mod:`gridfield.fields.navfield`
    (:func:`gridfield.fields.navfield.nav_field`; ``dmap`` must then be Euclidean). With ``model`` unset
    this function builds ``"khatib"`` (the potential *planner* defaults to ``"nf1"``).
    ``gradient="finite_difference"`` replaces the analytic gradient arrays by
    :func:`finite_difference_gradient` of ``U`` (for comparison; only with ``repulsive_power=2``).

    Parameters
    ----------
    gridmap : GridMap
    goal : (x, y)
        Must lie in a free cell of the map.
    params : mapping, optional
        Parameter names of :data:`gridfield.planners.PARAMETERS`; see :func:`resolve_params`.
        Follower parameters are carried along in ``Field.params`` and otherwise ignored.
    dmap : DistanceMap, optional
        A brushfire of ``gridmap`` to reuse (its metric must agree with ``params["metric"]`` when
        that is given); computed with ``metric`` and ``saturate`` when omitted.

    Returns
    -------
    Field
        The potential and its gradient arrays, the resolved parameters and the distance map.

    Raises
    ------
    ParameterError
        for invalid parameters (see :func:`resolve_params`).
    GridfieldError
        for a goal outside the map or inside an obstacle.

    Examples
    --------
    >>> occ = np.zeros((4, 6), bool); occ[:, 0] = True
    >>> f = build_field(GridMap(Grid((4, 6), 1.0), occ), (5.5, 1.5), {"zeta": 0.5, "eta": 1, "q_star": 3})
    >>> round(float(f.potential[1, 2]), 6), round(float(f.grad_x[1, 2]), 6)
    (2.263889, -1.541667)
    >>> build_field(GridMap(Grid((4, 6), 1.0), occ), (0.5, 1.5))
    Traceback (most recent call last):
    ...
    gridfield.core.errors.GridfieldError: goal (0.5, 1.5) lies inside an obstacle; the nearest free cell's centre is (1.5, 1.5)
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"build_field needs a GridMap, got {type(gridmap).__name__}")
    if gridmap.grid.ndim == 3:  # a voxel grid: gridfield.fields.potential3d
        from .potential3d import build_field3d

        return build_field3d(gridmap, goal, params)
    check_grid(gridmap.grid.shape, "field", f"build_field on {gridmap.source or 'the grid map'}")  # bytes, up front
    from ..core.params import validate

    given = dict(validate(params))
    p = resolve_params(given, unit=gridmap.grid.resolution)
    if p["model"] == "vortex":
        return vortex_model_field(gridmap, goal, p)
    if p["model"] in _NF_MODELS:
        from .navfield import nav_field

        field: Field = nav_field(gridmap, goal, given, dmap=dmap)
        return field
    g = gridmap.check_point("goal", goal)
    goal_xy = (float(g[0]), float(g[1]))
    if dmap is None:
        dmap = field_distance_map(gridmap, p)
    else:
        if not isinstance(dmap, DistanceMap) or dmap.grid.shape != gridmap.grid.shape:
            raise ParameterError("dmap must be a DistanceMap of the same grid as gridmap")
        if "metric" in given and p["metric"] != dmap.metric:
            raise ParameterError(f"params ask for metric {p['metric']!r}, but dmap was computed with {dmap.metric!r}")
        p["metric"] = dmap.metric
    grid = gridmap.grid
    sat, far = saturation(dmap, p["saturate"])
    nearest = p["repulsion"] == "nearest"
    U, GX, GY = _khatib_arrays(gridmap.occupied, dmap.nearest_row, dmap.nearest_col, grid, goal_xy, p["zeta"],
                               p["d_star"], dmap.metric, p["eta"], p["q_star"], p["repulsive_power"], sat, far,
                               nearest=nearest)
    if not nearest:
        _sum_repulsion(dmap, p["eta"], p["q_star"], p["repulsive_power"], sat, far, U, GX, GY)
    if p["gradient"] == "finite_difference":
        GX, GY = finite_difference_gradient(U, grid)
    return Field(gridmap, U, GX, GY, goal_xy, p, dmap)


