"""The grid navigation function on voxel grids (3-D): the 26-neighbour wavefront and its descent.

:func:`voxel_wavefront` is Dijkstra from the goal voxel over the 26-neighbourhood with move costs 1,
sqrt 2 and sqrt 3 cells (times the resolution), where **a move needs every voxel of its bounding box
free**: both ends, the two side voxels of a 2-axis diagonal, all eight voxels of the 2x2x2 block of a
3-axis diagonal (the rule of the Moving AI 3-D benchmarks, Brewer & Sturtevant, "Benchmarks for
pathfinding in 3D voxel space", SoCS 2018). Those are exactly the voxels whose closed cube the segment
between the two centres touches, so a chain of allowed moves is a polyline that touches no blocked
voxel (:func:`segment_clear`, the exact test of any segment). The compiled kernel
(``gridfield/fields/_navigation3.pyx``) uses a circular bucket queue (Dial) while the move costs allow
it and an indexed binary heap otherwise.

Options for a planner in (x, y, theta) (issue 45): per-axis ``spacing`` (a move costs
``sqrt(sum (spacing_a d_a)^2)``), a ``periodic`` axis 0 (the heading wraps round), a per-voxel
``slowness`` (a move costs its length times the mean slowness of its two ends: a clearance band), and
``stop_at`` with a ``margin`` (a point-to-point query settles only what its descent reads).

The voxel wavefront stays inside the grid whatever its ``border`` (as the 2-D grid navigation
functions do): with ``"open"`` nothing is gained by leaving a voxel grid's box, and ``"wall"`` is the
same search. The wall border is an obstacle shell for the clearance (:func:`voxel_clearance`).

The planner ``wavefront-octile`` on a voxel grid is :func:`plan_voxel_wavefront` (a dispatch of
:func:`gridfield.fields.navigation.plan_wavefront_octile`).

Examples
--------
>>> import numpy as np
>>> from gridfield.core.grid import Grid, GridMap
>>> occ = np.zeros((2, 2, 2), bool); occ[0, 0, 1] = True
>>> gm = GridMap(Grid((2, 2, 2), 1.0), occ)
>>> v = voxel_wavefront(gm, (0.5, 0.5, 0.5))
>>> float(v[1, 1, 1]) == 1 + 2 ** 0.5   # the 3-axis diagonal is refused: (0, 0, 1) is blocked
True
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import GridfieldError, ParameterError
from ..core.grid import GridMap
from ..core.limits import check_cells
from ..core.path import Path

__all__ = ["STOP_MARGIN_CELLS", "cached_clearance", "cell_units", "check_voxel_map", "clearance_slowness", "free_mask",
           "path_clear", "path_clearance", "plan_voxel_wavefront", "segment_clear", "shortcut_path", "voxel_clearance",
           "voxel_descent", "voxel_wavefront"]


def _kernel() -> Any:
    """The compiled kernel module (gridfield/fields/_navigation3.pyx), imported on first use."""
    from . import _navigation3  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _navigation3


def _path_kernel() -> Any:
    """The compiled kernel of the voxel paths (gridfield/fields/_voxelpath.pyx), imported on first use."""
    from . import _voxelpath  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _voxelpath


def check_voxel_map(gridmap: object, what: str) -> GridMap:
    """``gridmap`` itself when it is a voxel grid, else a :class:`ParameterError` naming ``what`` needs one.

    Parameters
    ----------
    gridmap : object
        The map to check: a :class:`~gridfield.core.grid.GridMap` of a 3-D grid passes.
    what : str
        The name of the caller (a function or a planner), put in the error message.

    Returns
    -------
    GridMap
        ``gridmap`` itself (the same object, unchanged).

    Raises
    ------
    ParameterError
        ``gridmap`` is not a ``GridMap``, or its grid is not 3-D.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> check_voxel_map(GridMap(Grid((2, 2), 1.0), np.zeros((2, 2), bool)), "f")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: f works on voxel grids (3-D); this map is 2-D (shape (2, 2))
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"{what} needs a GridMap, got {type(gridmap).__name__}")
    if gridmap.grid.ndim != 3:
        raise ParameterError(f"{what} works on voxel grids (3-D); this map is {gridmap.grid.ndim}-D "
                             f"(shape {gridmap.grid.shape})")
    return gridmap


def free_mask(gridmap: GridMap) -> NDArray[np.uint8]:
    """The free voxels as a C-contiguous uint8 mask (what the kernels read).

    Parameters
    ----------
    gridmap : GridMap
        The map (not checked to be 3-D; the kernels use it on voxel grids).

    Returns
    -------
    ndarray of uint8, shape ``gridmap.shape``
        1 on free voxels, 0 on blocked ones (a new array; ``gridmap.occupied`` is not modified).

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((1, 1, 3), bool); occ[0, 0, 1] = True
    >>> m = free_mask(GridMap(Grid((1, 1, 3), 1.0), occ))
    >>> m.dtype, m.shape, m.ravel().tolist()
    (dtype('uint8'), (1, 1, 3), [1, 0, 1])
    """
    return np.ascontiguousarray(~np.asarray(gridmap.occupied, dtype=bool)).view(np.uint8)


def _cell(gridmap: GridMap, name: str, point: ArrayLike) -> tuple[int, int, int]:
    """The voxel ``(layer, row, col)`` of a free world point ``(x, y, z)`` (check_point's errors)."""
    p = gridmap.check_point(name, point)
    cell = gridmap.grid.cell_of(*p)
    assert cell is not None and len(cell) == 3  # check_point: inside the grid
    return int(cell[0]), int(cell[1]), int(cell[2])


def cell_units(gridmap: GridMap, points: ArrayLike) -> NDArray[np.float64]:
    """World points ``(N, 3)`` as cell units in array order ``(q_z, q_y, q_x)`` (what the kernels read).

    A cell unit is ``(coordinate - origin) / resolution``, not rounded: voxel ``(layer, row, col)``
    spans ``[layer, layer + 1) x [row, row + 1) x [col, col + 1)``, its centre is at ``+ 0.5`` on each axis.

    Parameters
    ----------
    gridmap : GridMap
        The map whose grid (``origin``, ``resolution``) gives the units.
    points : array_like, shape (N, 3) or (3,)
        World points ``(x, y, z)``; anything that reshapes to ``(-1, 3)``. Not checked to lie inside the grid.

    Returns
    -------
    ndarray of float64, shape (N, 3)
        C-contiguous; column 0 is z, 1 is y, 2 is x (array order), in cells.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> cell_units(GridMap(Grid((1, 1, 1), 0.5, origin=(1, 0, 0)), np.zeros((1, 1, 1), bool)), [1.25, 0.0, 0.5]).tolist()
    [[1.0, 0.0, 0.5]]
    """
    g = gridmap.grid
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    return np.ascontiguousarray(((p - np.asarray(g.origin)) / g.resolution)[:, ::-1])


def voxel_clearance(gridmap: GridMap, *, nearest: bool = False) -> Any:
    """Euclidean distance from each voxel centre to the nearest blocked voxel centre, in world units.

    The Euclidean brushfire of the voxel grid (:func:`gridfield.distance.brushfire.brushfire`, the one
    place the 3-D fields get their clearance from); the wall border is an obstacle shell just outside the
    grid on all six faces; with an open border and no blocked voxel, ``inf`` everywhere.

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    nearest : bool
        Also return the index of the nearest blocked voxel per axis (a wall's shell voxels are ``-1``
        or the axis' size; ``-1`` on all three where there is no obstacle).

    Returns
    -------
    ndarray of float64, or (ndarray, (ndarray, ndarray, ndarray))
        The distances (0 on blocked voxels), and with ``nearest`` the ``(layer, row, col)`` arrays.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((1, 1, 4), bool); occ[0, 0, 0] = True
    >>> voxel_clearance(GridMap(Grid((1, 1, 4), 0.5), occ)).ravel().tolist()
    [0.0, 0.5, 1.0, 1.5]
    >>> voxel_clearance(GridMap(Grid((1, 1, 3), 1.0, border="wall"), np.zeros((1, 1, 3), bool))).ravel().tolist()
    [1.0, 1.0, 1.0]
    """
    from ..distance.brushfire import brushfire

    gm = check_voxel_map(gridmap, "voxel_clearance")
    dm = brushfire(gm, metric="euclidean", compute_steps=False, compute_nearest=nearest, compute_labels=False,
                   compute_gvd=False)
    if nearest:
        return dm.distance, tuple(np.asarray(i, dtype=np.int32) for i in dm.nearest_index)
    return dm.distance


def _spacing(gridmap: GridMap, spacing: Sequence[float] | None) -> tuple[float, float, float]:
    res = gridmap.grid.resolution
    if spacing is None:
        return res, res, res
    try:
        s = tuple(float(v) for v in spacing)
    except (TypeError, ValueError):
        s = ()
    if len(s) != 3 or not all(math.isfinite(v) and v > 0 for v in s):
        raise ParameterError(f"spacing must be three positive finite numbers (per array axis: layer, row, col), "
                             f"got {spacing!r}")
    return s[0], s[1], s[2]


def voxel_wavefront(gridmap: GridMap, goal: ArrayLike, *, spacing: Sequence[float] | None = None,
                    periodic: bool = False, slowness: ArrayLike | None = None, stop_at: ArrayLike | None = None,
                    margin: float = 0.0) -> NDArray[np.float64]:
    """Shortest-path cost from every voxel to the goal voxel (26 neighbours, the bounding-box rule).

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    goal : (x, y, z)
        In a free voxel.
    spacing : (float, float, float), optional
        The length of a step along each **array** axis (layer, row, col) in world units; default the
        resolution on each. A move ``(d0, d1, d2)`` costs ``sqrt(sum (spacing_a d_a)^2)``.
    periodic : bool
        Axis 0 (layers) wraps round: layer ``-1`` is the last one (a heading axis).
    slowness : ndarray, optional
        Per-voxel slowness (``gridmap.shape``, finite and > 0 on free voxels): a move costs its length
        times the mean slowness of its two ends.
    stop_at : (x, y, z), optional
        A start: the search settles the voxels up to its value plus ``margin`` and stops; the others
        are ``inf``.
    margin : float
        See ``stop_at`` (world units, >= 0).

    Returns
    -------
    ndarray of float64, shape ``gridmap.shape``
        0 at the goal voxel, ``inf`` on blocked, unreached and (with ``stop_at``) unsettled voxels.

    Raises
    ------
    ParameterError
        Not a voxel grid, a bad option.
    GridfieldError
        A goal or ``stop_at`` outside the grid or in a blocked voxel.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((1, 2, 2), 1.0), np.zeros((1, 2, 2), bool))
    >>> voxel_wavefront(gm, (0.5, 0.5, 0.5)).round(4).tolist()
    [[[0.0, 1.0], [1.0, 1.4142]]]
    >>> voxel_wavefront(gm, (0.5, 0.5, 0.5), spacing=(1, 2, 1)).round(4).tolist()
    [[[0.0, 1.0], [2.0, 2.2361]]]
    """
    gm = check_voxel_map(gridmap, "voxel_wavefront")
    check_cells(gm.grid.shape, "voxel wavefront")
    s = _spacing(gm, spacing)
    g = _cell(gm, "goal", goal)
    t = (-1, -1, -1) if stop_at is None else _cell(gm, "stop_at", stop_at)
    m = float(margin)
    if not (math.isfinite(m) and m >= 0):
        raise ParameterError(f"margin must be a finite number >= 0, got {margin!r}")
    free = free_mask(gm)
    if slowness is None:
        slow = np.zeros((0, 0, 0))
    else:
        slow = np.ascontiguousarray(slowness, dtype=np.float64)
        if slow.shape != gm.grid.shape:
            raise ParameterError(f"slowness has shape {slow.shape}, but the grid has shape {gm.grid.shape}")
        on = slow[free.view(bool)]
        if on.size and not (np.isfinite(on).all() and on.min() > 0):
            raise ParameterError("slowness must be finite and > 0 on every free voxel")
    return np.asarray(_kernel().wavefront3(free, *g, *s, bool(periodic), slow, *t, m))


def voxel_descent(gridmap: GridMap, values: NDArray[np.float64], start: ArrayLike, *,
                  periodic: bool = False, parent: bool = False, spacing: Sequence[float] | None = None,
                  slowness: ArrayLike | None = None) -> tuple[NDArray[np.int64], bool]:
    """The discrete steepest descent of a voxel wavefront from ``start``: repeatedly to the allowed
    neighbour (the bounding-box rule) with the lowest value; with ``parent``, to the lower allowed
    neighbour minimizing value + move cost (a shortest-path parent: the chain costs the start's value).

    Every settled voxel but the goal has a lower allowed neighbour (its Dijkstra parent), so from a
    voxel with a finite value the descent ends at the goal (value 0).

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    values : ndarray
        From :func:`voxel_wavefront` on ``gridmap``.
    start : (x, y, z)
        In a free voxel.
    periodic : bool
        As the wavefront was computed.
    parent : bool
        Step to shortest-path parents (``spacing`` and ``slowness`` as the wavefront was computed).
    spacing, slowness : optional
        See :func:`voxel_wavefront` (read with ``parent``).

    Returns
    -------
    cells : ndarray of int64, shape (n, 3)
        ``(layer, row, col)`` from the start voxel to where it ended.
    reached : bool
        Whether it ended at a voxel of value 0.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((3, 3, 3), 1.0), np.zeros((3, 3, 3), bool))
    >>> v = voxel_wavefront(gm, (0.5, 0.5, 0.5))
    >>> cells, reached = voxel_descent(gm, v, (2.5, 2.5, 2.5))
    >>> cells.tolist(), reached
    ([[2, 2, 2], [1, 1, 1], [0, 0, 0]], True)
    """
    gm = check_voxel_map(gridmap, "voxel_descent")
    v = np.asarray(values, dtype=np.float64)
    if v.shape != gm.grid.shape:
        raise ParameterError(f"values has shape {v.shape}, but the grid has shape {gm.grid.shape}")
    k, r, c = _cell(gm, "start", start)
    slow = np.zeros((0, 0, 0)) if slowness is None else np.ascontiguousarray(slowness, dtype=np.float64)
    if slow.size and slow.shape != gm.grid.shape:
        raise ParameterError(f"slowness has shape {slow.shape}, but the grid has shape {gm.grid.shape}")
    cells, reached = _kernel().descend3(v, free_mask(gm), k, r, c, bool(periodic), bool(parent), *_spacing(gm, spacing),
                                        slow)
    return np.asarray(cells), bool(reached)


def segment_clear(gridmap: GridMap, a: ArrayLike, b: ArrayLike) -> bool:
    """Whether the segment from world point ``a`` to ``b`` touches only free voxels of the grid: the
    closed cube of every blocked voxel (and every voxel outside the grid) is tested, so grazing a face,
    an edge or a corner counts as touching.

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    a, b : array_like, shape (3,)
        The segment's ends, world points ``(x, y, z)`` (finite; they may lie outside the grid, which
        makes the segment not clear, as does a point on the grid's boundary).

    Returns
    -------
    bool
        True when the closed segment touches no blocked voxel and stays strictly inside the grid.

    Raises
    ------
    ParameterError
        Not a voxel grid, or a non-finite point.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((1, 2, 2), bool); occ[0, 0, 1] = True
    >>> gm = GridMap(Grid((1, 2, 2), 1.0), occ)
    >>> segment_clear(gm, (0.5, 0.5, 0.5), (0.5, 1.5, 0.5)), segment_clear(gm, (0.5, 0.5, 0.5), (1.5, 1.5, 0.5))
    (True, False)
    """
    gm = check_voxel_map(gridmap, "segment_clear")
    q = cell_units(gm, np.vstack([np.asarray(a, dtype=float).reshape(3), np.asarray(b, dtype=float).reshape(3)]))
    if not np.isfinite(q).all():
        raise ParameterError("segment_clear needs finite points")
    return bool(_path_kernel().segment_clear(free_mask(gm), *q[0], *q[1]))


def path_clear(gridmap: GridMap, points: ArrayLike) -> int:
    """Index of the first segment of a polyline ``(n, 3)`` (world points) that touches a blocked voxel
    or leaves the grid (:func:`segment_clear`), or -1 when none does.

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    points : array_like, shape (n, 3)
        The polyline's vertices, world points ``(x, y, z)`` in order.

    Returns
    -------
    int
        ``i`` when the segment from ``points[i]`` to ``points[i + 1]`` is the first one not clear; -1
        when every segment is clear (always for fewer than two points).

    Raises
    ------
    ParameterError
        Not a voxel grid.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((1, 1, 3), 1.0), np.zeros((1, 1, 3), bool))
    >>> path_clear(gm, [(0.5, 0.5, 0.5), (2.5, 0.5, 0.5), (3.5, 0.5, 0.5)])   # the second segment leaves the grid
    1
    >>> path_clear(gm, [(0.5, 0.5, 0.5), (2.5, 0.5, 0.5)])
    -1
    """
    gm = check_voxel_map(gridmap, "path_clear")
    return int(_path_kernel().path_clear(free_mask(gm), cell_units(gm, points)))


def shortcut_path(gridmap: GridMap, points: ArrayLike) -> NDArray[np.float64]:
    """String pulling over a polyline's own vertices: from each kept vertex the farthest later vertex
    joined to it by a clear segment (:func:`segment_clear`), extended one vertex at a time. The
    polyline's own segments must be clear; the result's are, and it is never longer.

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    points : array_like, shape (n, 3)
        The polyline's vertices, world points ``(x, y, z)``; every segment ``points[i] -> points[i + 1]``
        clear (:func:`path_clear` returns -1). They are not tested: a consecutive pair is always kept
        joined.

    Returns
    -------
    ndarray of float64, shape (m, 3)
        The kept vertices (``m <= n``), a subsequence of ``points`` in order with the first and the last
        included (a new array).

    Raises
    ------
    ParameterError
        Not a voxel grid.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((1, 1, 4), 1.0), np.zeros((1, 1, 4), bool))
    >>> shortcut_path(gm, [(0.5, 0.5, 0.5), (1.5, 0.5, 0.5), (2.5, 0.5, 0.5), (3.5, 0.5, 0.5)]).tolist()
    [[0.5, 0.5, 0.5], [3.5, 0.5, 0.5]]
    """
    gm = check_voxel_map(gridmap, "shortcut_path")
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    keep = _path_kernel().shortcut(free_mask(gm), cell_units(gm, p))
    return p[np.asarray(keep)]


#: A point-to-point query's search settles this many cells beyond the start's value (the follower of
#: a 3-D complete field reads the voxels round its way).
STOP_MARGIN_CELLS = 4.0


def clearance_slowness(distance: NDArray[np.float64], occupied: NDArray[np.bool_], weight: float,
                       q_star: float) -> NDArray[np.float64]:
    """The clearance cost of the 2-D wavefront on voxels: ``1 + weight * max(0, 1 - D / q_star)``
    (1 where there is no obstacle, ``inf`` on blocked voxels).

    Parameters
    ----------
    distance : ndarray of float
        The clearance ``D`` of each voxel (:func:`voxel_clearance`), in world units; a non-finite value
        (``inf``: no obstacle) gets cost 1.
    occupied : ndarray of bool, same shape as ``distance``
        The blocked voxels.
    weight : float
        The planner's ``clearance_weight`` (>= 0): the extra cost at ``D = 0``.
    q_star : float
        The range of the cost (> 0, the units of ``distance``): 1 from ``D >= q_star`` on.

    Returns
    -------
    ndarray of float64, same shape as ``distance``
        A new array, the slowness for :func:`voxel_wavefront`: between 1 and ``1 + weight`` on free
        voxels, ``inf`` on blocked ones.

    Examples
    --------
    >>> clearance_slowness(np.array([0.0, 1.0, 2.0, np.inf]), np.array([True, False, False, False]), 2.0, 4.0)
    array([inf, 2.5, 2. , 1. ])
    """
    with np.errstate(invalid="ignore"):
        cost = 1.0 + weight * np.clip(1.0 - distance / q_star, 0.0, None)
    cost[~np.isfinite(distance)] = 1.0
    cost[occupied] = np.inf
    return cost


def plan_voxel_wavefront(gridmap: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64],
                         params: Mapping[str, Any], *, cache: dict[Any, Any] | None = None,
                         planner: str = "wavefront-octile") -> Path:
    """Planner ``wavefront-octile`` on a voxel grid: the 26-neighbour wavefront from the goal (stopped
    once the start is settled) and its discrete descent, a shortest path of voxel moves under the
    bounding-box rule.

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid.
    start, goal : ndarray, shape (3,)
        World points ``(x, y, z)`` in free voxels.
    params : mapping
        Planner parameters; read: ``clearance_weight`` and ``q_star`` (the clearance cost as a
        slowness, :func:`clearance_slowness`), ``connectivity`` (8, the default, means the 26
        neighbours here; 4 is refused).
    cache : dict, optional
        Keeps the clearance of a map between queries.
    planner : str
        The name put in :attr:`Path.planner`.

    Returns
    -------
    Path
        ``points`` ``(n, 3)``: the start, the centres of the voxels of the descent after the start's
        own (the start voxel's centre included), the goal; ``extra`` with ``value`` (at the start
        voxel), ``grid_length`` (of the voxel chain), ``cells``, ``field_seconds``. ``no_path`` when
        the goal cannot be reached.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((2, 2, 2), 1.0), np.zeros((2, 2, 2), bool))
    >>> p = plan_voxel_wavefront(gm, np.array([0.5, 0.5, 0.5]), np.array([1.5, 1.5, 1.5]), {})
    >>> p.status, round(p.length, 4), p.points.shape
    ('reached', 1.7321, (2, 3))
    """
    from ..core.params import Navigation, Repulsion, validate

    gm = check_voxel_map(gridmap, f"planner {planner!r}")
    p = validate(params)
    nav = p.group(Navigation)
    if nav.connectivity != 8:
        raise ParameterError(f"connectivity {nav.connectivity} is a 2-D option; the voxel wavefront moves to the 26 "
                             "neighbours (leave connectivity unset or 8)")
    w = float(nav.clearance_weight)
    res = gm.grid.resolution
    q_star = p.group(Repulsion).q_star
    q = 5.0 * res if q_star is None else float(q_star)
    s = gm.check_point("start", start)
    g = gm.check_point("goal", goal)
    t0 = time.perf_counter()
    slow = None
    dist = cached_clearance(gm, cache) if w > 0 else None
    if dist is not None:
        slow = clearance_slowness(dist, np.asarray(gm.occupied, dtype=bool), w, q)
    values = voxel_wavefront(gm, g, slowness=slow, stop_at=s)
    field_seconds = time.perf_counter() - t0
    t1 = time.perf_counter()
    k, r, c = _cell(gm, "start", s)
    v0 = float(values[k, r, c])
    ran = {**dict(p), "connectivity": 8, "costs": "octile", "clearance_weight": w, "q_star": q_star}
    if not math.isfinite(v0):
        return Path(s[None, :], "no_path", planner, 0, ran, time.perf_counter() - t1,
                    extra={"value": math.inf, "grid_length": math.inf, "field_seconds": field_seconds,
                           "build_seconds": field_seconds, "reason": "the goal is unreachable from the start"})
    cells, reached = _kernel().descend3(values, free_mask(gm), k, r, c, False, True, res, res, res,
                                        np.zeros((0, 0, 0)) if slow is None else slow)
    cells = np.asarray(cells)
    if not reached:  # pragma: no cover - a settled voxel always has a lower allowed neighbour
        raise GridfieldError("the voxel descent stopped short of the goal (a bug in the wavefront)")
    centres = gm.grid.cell_to_world(cells)
    points = np.vstack([s[None, :], centres[:-1], g[None, :]])
    keep = np.ones(len(points), bool)
    keep[1:] = np.any(np.diff(points, axis=0) != 0, axis=1)
    points = points[keep]
    grid_length = float(np.sqrt((np.diff(centres, axis=0) ** 2).sum(axis=1)).sum())
    min_clearance = float(dist[tuple(cells.T)].min()) if dist is not None else path_clearance(gm, cells, cache)
    extra = {"value": v0, "grid_length": grid_length, "cells": cells, "field_seconds": field_seconds,
             "build_seconds": field_seconds}
    return Path(points, "reached", planner, len(cells) - 1, ran, time.perf_counter() - t1, min_clearance, extra)


#: :func:`path_clearance` looks this many voxels round the path's bounding box first.
_CLEARANCE_WINDOW = 8


def path_clearance(gridmap: GridMap, cells: NDArray[np.int64], cache: dict[Any, Any] | None = None) -> float:
    """The smallest :func:`voxel_clearance` over the voxels ``cells`` ``(n, 3)``, from a distance transform of
    the path's bounding box grown by 8 voxels (exact when the answer is within 8 voxels; the whole
    map's otherwise).

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid (the wall border's shell counts as obstacles, as in :func:`voxel_clearance`).
    cells : ndarray of int, shape (n, 3)
        Voxel indices ``(layer, row, col)`` inside the grid, ``n >= 1`` (a path's voxels).
    cache : dict, optional
        A planner's per-map dict, for the whole map's clearance when the window is not enough
        (:func:`cached_clearance`).

    Returns
    -------
    float
        The smallest distance from one of the voxel centres to the nearest blocked voxel centre, in world
        units (0 when a voxel is blocked; ``inf`` on an open-border map with no blocked voxel).

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((1, 1, 40), bool); occ[0, 0, 0] = True
    >>> gm = GridMap(Grid((1, 1, 40), 1.0), occ)
    >>> path_clearance(gm, np.array([[0, 0, 3], [0, 0, 4]])), path_clearance(gm, np.array([[0, 0, 30]]))
    (3.0, 30.0)
    """
    from scipy import ndimage

    c = np.asarray(cells, dtype=np.int64).reshape(-1, 3)
    shape = gridmap.grid.shape
    lo = np.maximum(c.min(axis=0) - _CLEARANCE_WINDOW, 0)
    hi = np.minimum(c.max(axis=0) + _CLEARANCE_WINDOW + 1, shape)
    box = np.asarray(gridmap.occupied[tuple(slice(a, b) for a, b in zip(lo, hi, strict=True))], dtype=bool)
    if gridmap.grid.border == "wall":  # the shell, on the faces the box shares with the grid
        pads = [(int(a == 0), int(b == n)) for a, b, n in zip(lo, hi, shape, strict=True)]
        box = np.pad(box, pads, constant_values=True)
        lo = lo - np.array([p[0] for p in pads])
    if box.any():
        d = ndimage.distance_transform_edt(~box)[tuple((c - lo).T)].min()
        if d <= _CLEARANCE_WINDOW:
            return float(d * gridmap.grid.resolution)
    return float(cached_clearance(gridmap, cache)[tuple(c.T)].min())


def cached_clearance(gm: GridMap, cache: dict[Any, Any] | None) -> NDArray[np.float64]:
    """:func:`voxel_clearance` of ``gm``, kept in ``cache`` (a planner's per-map dict) when one is given.

    Parameters
    ----------
    gm : GridMap
        A voxel grid.
    cache : dict or None
        Where the clearance is kept, under the key ``("voxel_clearance", gm)``; None computes it each call.

    Returns
    -------
    ndarray of float64, shape ``gm.shape``
        The clearance in world units (:func:`voxel_clearance`); from a cache, the very array stored
        there (not a copy: do not modify it).

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((1, 1, 3), 1.0, border="wall"), np.zeros((1, 1, 3), bool))
    >>> cache = {}
    >>> d = cached_clearance(gm, cache)
    >>> d.ravel().tolist(), cached_clearance(gm, cache) is d, list(cache) == [("voxel_clearance", gm)]
    ([1.0, 1.0, 1.0], True, True)
    """
    key = ("voxel_clearance", gm)
    if cache is not None and key in cache:
        return cache[key]  # type: ignore[no-any-return]
    d = voxel_clearance(gm)
    if cache is not None:
        cache[key] = d
    return d  # type: ignore[no-any-return]
