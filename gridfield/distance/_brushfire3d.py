"""The brushfire of a voxel grid (3-D :class:`~gridfield.core.grid.GridMap`), behind
:func:`gridfield.distance.brushfire.brushfire` (private: call that function, which checks the arguments
and dispatches here on ``gridmap.ndim == 3``).

Metrics
-------
``connectivity=26`` numbers the wavefront steps by the chessboard distance in voxels
(``max(|dz|, |dy|, |dx|)``), ``connectivity=6`` by the taxicab distance (``|dz| + |dy| + |dx|``); the
default metric follows the connectivity, as 8 and 4 do in 2-D. Euclidean is the exact distance
between voxel centres.

Nearest obstacle
----------------
``nearest_layer``, ``nearest_row`` and ``nearest_col`` are ``int16`` when every axis of the grid has at
most :data:`INT16_AXIS` voxels (always, in practice: a 32766-voxel axis is far beyond memory in 3-D),
else ``int32``: three ``int16`` arrays take 6 bytes a voxel where ``int32`` would take 12, which keeps
a 512^3 Euclidean map with its nearest obstacles within 2.5 GiB (``benchmarks/README.md``, "Voxel
grids"). Cast them (``.astype(np.intp)``) before arithmetic that could overflow 16 bits, such as a
flat index. The Euclidean nearest voxel is, of those at the least distance, the one with the smallest
col, then row, then layer; chessboard and taxicab give any one of the nearest. The wall border's
voxels are the shell just outside the six faces, across a face (layer ``-1``/``layers`` with the
voxel's own row and col, and so on), never an edge of the shell.

Labels and GVD
--------------
Labels are those of ``GridMap.obstacle_id`` when the map has them, else the 26-connected component
numbers of the obstacles exactly as ``scipy.ndimage.label(occupied, structure=np.ones((3, 3, 3)))``
numbers them; :data:`~gridfield.distance.brushfire.BORDER_LABEL` for the wall. The GVD is 2-D's rule
over the 26 neighbours: of each pair of 26-neighbouring free voxels with different labels, the one
farther from its obstacle is marked (on a tie, the one with the smaller label).

Implementation
--------------
The compiled kernel :mod:`gridfield.distance._edt3` (see its docstring): the separable Euclidean
transform (a column pass along z, then per layer the lower envelopes along y and x), a two-pass raster
chamfer for chessboard and taxicab, the label gather, the GVD and the saturation. The column pass
runs in blocks of the ``(y, x)`` plane and the others by ranges of layers, as tasks on the
brushfire's thread pool (``run``); the chamfer is one sequential task.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.grid import GridMap
from ..core.results import DistanceMap

#: The longest axis with ``int16`` nearest-obstacle indices (the wall's index ``n`` must fit too).
INT16_AXIS = 32766
#: Voxels of the ``(y, x)`` plane per task of the Euclidean column pass (about 64 KiB of its float64).
_PLANE_BLOCK = 8192
_BORDER_LABEL = -1  # gridfield.distance.brushfire.BORDER_LABEL (that module imports this one)
_NO_FLAT = np.zeros((1, 1, 1), np.int32)  # the chamfer's nearest voxels, when not wanted

Runner = Callable[[Sequence[Callable[[], object]], int], None]


def _kernel() -> Any:
    """The compiled kernel module (gridfield/distance/_edt3.pyx), imported on first use."""
    from . import _edt3  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _edt3


def _ranges(kernel: Callable[..., object], n: int, parts: int, *args: object) -> list[Callable[[], object]]:
    """Tasks running ``kernel(lo, hi, *args)`` over ``range(n)`` in ``parts`` nearly equal pieces."""
    parts = max(1, min(n, parts))
    bounds = [i * n // parts for i in range(parts + 1)]
    return [partial(kernel, bounds[i], bounds[i + 1], *args) for i in range(parts) if bounds[i] < bounds[i + 1]]


def index_dtype(shape: tuple[int, ...]) -> type[np.signedinteger[Any]]:
    """The dtype of a voxel grid's nearest-obstacle indices: ``int16`` if every axis has at most
    :data:`INT16_AXIS` voxels, else ``int32``.

    Parameters
    ----------
    shape : (layers, rows, cols)

    Returns
    -------
    numpy dtype class

    Examples
    --------
    >>> index_dtype((512, 512, 512)).__name__, index_dtype((2, 40000, 3)).__name__
    ('int16', 'int32')
    """
    return np.int16 if max(shape, default=0) <= INT16_AXIS else np.int32


def brushfire3d(gridmap: GridMap, connectivity: int, metric: str, saturate: float | None, far: float,
                want_steps: bool, want_nearest: bool, want_label: bool, want_gvd: bool, nthreads: int,
                run: Runner) -> DistanceMap:
    """The distance map of a voxel grid (arguments checked by :func:`gridfield.distance.brushfire.brushfire`).

    Parameters
    ----------
    gridmap : GridMap
        A voxel map (``gridmap.ndim == 3``).
    connectivity : {26, 6}
    metric : {"chessboard", "taxicab", "euclidean"}
    saturate : float or None
    far : float
    want_steps, want_nearest, want_label, want_gvd : bool
        What to compute (the GVD needs the labels).
    nthreads : int
        Threads for the tasks (``run`` runs them).
    run : callable
        ``run(tasks, nthreads)``: the brushfire's thread pool.

    Returns
    -------
    DistanceMap
        3-D arrays; ``nearest_layer`` set with the nearest obstacle.

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.distance.brushfire import brushfire
    >>> occ = np.zeros((2, 3, 4), bool); occ[0, 1, 0] = True
    >>> d = brushfire(GridMap(Grid(occ.shape, 1.0), occ), metric="euclidean")
    >>> d.distance[1, 1, 3] == np.sqrt(1 + 9), d.nearest_index[0][1, 1, 3], d.nearest_index[2][1, 1, 3]
    (np.True_, np.int16(0), np.int16(0))
    >>> brushfire(GridMap(Grid(occ.shape, 1.0), occ)).steps[1]
    array([[1, 1, 2, 3],
           [1, 1, 2, 3],
           [1, 1, 2, 3]], dtype=int32)
    """
    k = _kernel()
    shape = gridmap.grid.shape
    occ8 = np.ascontiguousarray(gridmap.occupied, dtype=bool).view(np.uint8)
    wall = gridmap.grid.border == "wall"
    res = float(gridmap.grid.resolution)
    layers = shape[0]
    parts = 1 if nthreads <= 1 else 4 * nthreads
    idx = index_dtype(shape)
    if not wall and not occ8.any():
        return _unreached(gridmap, connectivity, metric, saturate, far, want_steps, want_nearest, want_label,
                          want_gvd, idx)
    need_nearest = want_nearest or want_label
    nl = nr = nc = None
    if need_nearest:
        nl, nr, nc = (np.empty(shape, idx) for _ in range(3))
    dummy = np.zeros((1, 1, 1), idx)
    chess_steps = connectivity == 26
    steps = None
    if metric == "euclidean":
        distance = np.empty(shape, np.float64)
        plane = shape[1] * shape[2]
        vz = nl.reshape(layers, plane) if nl is not None else dummy[0]
        run(_ranges(k.column_pass, plane, max(parts, -(-plane // _PLANE_BLOCK)) if plane else 1,
                    occ8.reshape(layers, plane), wall, distance.reshape(layers, plane), vz, need_nearest), nthreads)
        run(_ranges(k.slice_pass, layers, parts, distance, *(nl, nr, nc) if nl is not None else (dummy,) * 3,
                    need_nearest, wall, res), nthreads)
        if want_steps:
            steps = np.empty(shape, np.int32)
            k.chamfer(occ8, wall, chess_steps, steps, _NO_FLAT, False)
    else:
        key = np.empty(shape, np.int32)
        # the nearest voxel as one flat index into the padded grid while the passes carry it
        padded = (shape[0] + 2) * (shape[1] + 2) * (shape[2] + 2)
        flat = np.empty(shape, np.int32 if padded < 2**31 else np.int64) if need_nearest else _NO_FLAT
        k.chamfer(occ8, wall, metric == "chessboard", key, flat, need_nearest)
        if need_nearest:
            run(_ranges(k.decode, layers, parts, flat, nl, nr, nc), nthreads)
        del flat
        distance = np.empty(shape, np.float64)
        run(_ranges(k.scale_steps, layers, parts, key, res, distance), nthreads)
        if want_steps:
            if chess_steps == (metric == "chessboard"):
                steps = key
            else:
                steps = np.empty(shape, np.int32)
                k.chamfer(occ8, wall, chess_steps, steps, _NO_FLAT, False)
        del key
    label = gvd = None
    if want_label:
        comp = _components(gridmap, occ8)
        label = np.empty(shape, np.int32)
        run(_ranges(k.gather_labels, layers, parts, nl, nr, nc, comp, _BORDER_LABEL, 0, label), nthreads)
        del comp
        if want_gvd:
            gvd = np.empty(shape, bool)
            run(_ranges(k.gvd_layers, layers, parts, label, distance, occ8, gvd.view(np.uint8)), nthreads)
    if not want_nearest:
        nl = nr = nc = None
    if saturate is not None:
        run(_ranges(k.saturate_layers, layers, parts, distance, saturate, far), nthreads)
    return DistanceMap(gridmap, connectivity, metric, steps, distance, nr, nc, label, gvd, saturate, far,
                       nearest_layer=nl)


def _components(gridmap: GridMap, occ8: NDArray[np.uint8]) -> NDArray[np.int32]:
    """The obstacles' labels: ``obstacle_id``, or their 26-connected components (``scipy.ndimage.label``)."""
    if gridmap.obstacle_id is not None:
        return np.ascontiguousarray(gridmap.obstacle_id, dtype=np.int32)
    from scipy import ndimage

    comp = np.empty(occ8.shape, np.int32)
    ndimage.label(occ8.view(bool), structure=np.ones((3, 3, 3), bool), output=comp)
    return comp


def _unreached(gridmap: GridMap, connectivity: int, metric: str, saturate: float | None, far: float,
               want_steps: bool, want_nearest: bool, want_label: bool, want_gvd: bool,
               idx: type[np.signedinteger[Any]]) -> DistanceMap:
    """The map of a voxel grid without any obstacle and with an open border: no voxel is reached."""
    shape = gridmap.grid.shape
    minus = [np.full(shape, -1, idx) for _ in range(3)] if want_nearest else [None] * 3
    return DistanceMap(
        gridmap, connectivity, metric, np.full(shape, -1, np.int32) if want_steps else None,
        np.full(shape, np.inf if saturate is None else far), minus[1], minus[2],
        np.zeros(shape, np.int32) if want_label else None, np.zeros(shape, bool) if want_gvd else None,
        saturate, far, nearest_layer=minus[0],
    )
