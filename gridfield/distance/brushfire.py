"""Brushfire (wavefront) distance maps: steps, distances, nearest obstacle, labels, GVD.

Numbering
---------
Obstacle cells have ``steps == 0``, their neighbours 1, and so on. The textbook brushfire of
Choset et al. (sec. 4.3; seed 002) numbers obstacles 1 and their neighbours 2: subtract 1 from the
textbook's numbers to get ours, so that ``steps`` *is* the distance in cells. With
``connectivity=8`` the wavefront measures chessboard distance (``max(|dr|, |dc|)``), with 4 taxicab
distance (``|dr| + |dc|``).

Border
------
A wall border counts as an obstacle ring just outside the grid: its cells are rows ``-1`` and
``rows``, columns ``-1`` and ``cols``, and its label is :data:`BORDER_LABEL`. An open border is free
space that is not part of the map: the wavefront simply stops at the edge.

Implementation
--------------
Compiled kernels (Cython, built at install): :mod:`gridfield.distance._chamfer`, :mod:`gridfield.distance._edt`
and :mod:`gridfield.distance._brushfire` (the memory pool, components, labels, GVD). Chessboard and taxicab: the
two-pass raster transform with a 3x3 mask, carrying the nearest obstacle cell along with the
distance (on large grids in strips, each on a window with a margin, verified; see :class:`_Chamfer`).
Euclidean: the separable exact transform (per column, then the lower envelope per row; Meijster et
al. 2000) with the nearest obstacle cell. All are exact. Connected obstacle components: union-find
in strips. The kernels release the GIL and run on a small thread pool (``threads``). They are
compiled ahead of time, at install: nothing is compiled at run time, so the first call in a process
costs what the later ones do (``benchmarks/README.md``, "Brushfire", "First call in a fresh process").
The grid-sized result arrays reuse the memory of earlier results that were freed (up to 512 MiB is
kept; their ``flags.owndata`` is False), which spares repeated calls the page faults of fresh memory.
"""

from __future__ import annotations

import itertools
import math
import os
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import partial
from types import ModuleType
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from ..core.errors import ArgumentTypeError, ParameterError, shorten
from ..core.grid import GridMap
from ..core.limits import check_grid
from ..core.results import DistanceMap

__all__ = ["BORDER_LABEL", "METRICS", "DistanceMap", "brushfire"]

METRICS = ("chessboard", "taxicab", "euclidean")
#: Label of the wall border (outside the grid) in :attr:`DistanceMap.label`.
BORDER_LABEL = -1




def _kernel_brushfire() -> Any:
    """The compiled kernel module (gridfield/distance/_brushfire.pyx: memory pool, components, labels, GVD,
    saturation), imported on first use."""
    from . import _brushfire  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _brushfire


def _kernel_chamfer() -> Any:
    """The compiled kernel module (gridfield/distance/_chamfer.pyx: chessboard and taxicab), imported on first use."""
    from . import _chamfer  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _chamfer


def _kernel_edt() -> Any:
    """The compiled kernel module (gridfield/distance/_edt.pyx: the Euclidean transform), imported on first use."""
    from . import _edt  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _edt


#: Grids with fewer cells run on one thread unless ``threads`` says otherwise: below about 1M cells
#: handing work to a second thread costs about as much as it saves, more when the machine is busy
#: (``benchmarks/README.md``, "Brushfire", "How").
PARALLEL_MIN_CELLS = 1 << 20

_NO_COMP = np.zeros((1, 1), np.int32)  # placeholders for arrays that are not needed
_NO_MAP = np.zeros(1, np.int32)
_NO_DIST = np.zeros((1, 1), np.float64)
_NO_GVD = np.zeros((1, 1), bool)
#: Chamfer passes over grids of at least 2 * STRIP_ROWS rows run as strips of about STRIP_ROWS rows,
#: each computed on a window reaching MARGIN rows beyond it (see :class:`_Chamfer`).
STRIP_ROWS = 1024
MARGIN = 64
_POOL: ThreadPoolExecutor | None = None
_POOL_LOCK = threading.Lock()


def _available_threads() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


def _thread_count(threads: int | None, cells: int) -> int:
    available = _available_threads()
    if threads is None:
        return available if cells >= PARALLEL_MIN_CELLS else 1
    if isinstance(threads, bool) or not isinstance(threads, int | np.integer) or threads < 1:
        raise ParameterError(f"threads must be a positive integer or None (all {available} cores for grids of "
                             f"{PARALLEL_MIN_CELLS} cells or more), got {threads!r}")
    return min(int(threads), available)


def _pool() -> ThreadPoolExecutor:
    global _POOL
    with _POOL_LOCK:
        if _POOL is None:
            _POOL = ThreadPoolExecutor(max_workers=_available_threads(), thread_name_prefix="gridfield-brushfire")
        return _POOL


def _run(tasks: Sequence[Callable[[], object]], nthreads: int, first: Callable[[], object] | None = None) -> None:
    """Run ``tasks`` (compiled kernels that release the GIL) on ``nthreads`` threads, this one included;
    this thread runs ``first`` before it joins the others on ``tasks``.

    Each thread takes the next task as soon as it is free, so a thread that the OS does not schedule
    (another job on the core) holds up at most the task it has in hand; with a static split of the
    work (an OpenMP ``prange``) the whole pass would wait for it.
    """
    if nthreads <= 1 or len(tasks) + (first is not None) <= 1:
        if first is not None:
            first()
        for task in tasks:
            task()
        return
    queue = iter(tasks)
    lock = threading.Lock()

    def worker() -> None:
        while True:
            with lock:
                task = next(queue, None)
            if task is None:
                return
            task()

    helpers = [_pool().submit(worker) for _ in range(min(nthreads - 1, len(tasks)))]
    try:
        if first is not None:
            first()
        worker()
    finally:
        for h in helpers:
            h.result()


class _Strips:
    """Labelling the 8-connected obstacle components in horizontal strips (tasks for any thread), then
    joining them across the strip boundaries (:meth:`merge`, in the calling thread)."""

    def __init__(self, k: ModuleType, occ8: NDArray[np.uint8], comp: NDArray[np.int32], n: int) -> None:
        rows, cols = occ8.shape
        self.k, self.occ8, self.comp = k, occ8, comp
        self.firsts = np.array([i * rows // n for i in range(n)], np.int64)  # n <= rows: none empty
        self.ends = np.append(self.firsts[1:], rows)
        caps = [k.strip_cap(int(e - f), cols) for f, e in zip(self.firsts, self.ends, strict=True)]
        self.bases = np.concatenate([[0], np.cumsum(caps[:-1])]).astype(np.int64)
        self.parent = np.empty(int(sum(caps)) + 1, np.int32)
        self.lasts = np.zeros(n, np.int64)

    def _label(self, i: int) -> None:
        self.lasts[i] = self.k.label_strip(self.firsts[i], self.ends[i], self.occ8, self.comp, self.parent,
                                           self.bases[i])

    def tasks(self) -> list[Callable[[], object]]:
        return [partial(self._label, i) for i in range(len(self.firsts))]

    def merge(self) -> NDArray[np.int32]:
        """The final label of each provisional one (unused ones undefined), and :data:`BORDER_LABEL` as
        the last element."""
        comp_map = np.empty(len(self.parent) + 1, np.int32)  # untouched pages are never faulted in
        self.k.merge_strips(self.occ8, self.comp, self.parent, self.firsts, self.bases, self.lasts, comp_map)
        comp_map[-1] = BORDER_LABEL
        return comp_map


class _Chamfer:
    """The two-pass chessboard/taxicab transform over the whole grid (one sequential task), or over
    horizontal strips (independent tasks) on large grids.

    A strip is computed on a window reaching :data:`MARGIN` rows beyond it on both sides. A cell whose
    distance in the window is at most ``MARGIN`` has its exact distance and nearest obstacle: every
    obstacle outside the window is farther than ``MARGIN`` from it. If some cell of a strip is
    farther than that (large open areas), :meth:`finish` redoes the whole grid in one pass. The strip
    layout depends on the grid's size only, so the nearest obstacles chosen among equally near ones
    do not depend on the number of threads.
    """

    def __init__(self, k: ModuleType, occ8: NDArray[np.uint8], wall: bool, conn8: bool, steps: NDArray[np.int32],
                 distance: NDArray[np.float64], res: float, write_distance: bool,
                 nearest: tuple[NDArray[np.int32], NDArray[np.int32]] | None, nthreads: int) -> None:
        self.k, self.occ8, self.wall, self.conn8, self.steps = k, occ8, wall, conn8, steps
        self.distance, self.res, self.write_distance, self.nearest = distance, res, write_distance, nearest
        rows, cols = occ8.shape
        self.idx_dtype = np.int32 if (rows + 2) * (cols + 2) < 2**31 else np.int64
        n = rows // STRIP_ROWS if rows >= 2 * STRIP_ROWS else 1
        if nearest is None and nthreads <= 1:  # the values do not depend on the layout
            n = 1
        self.bounds = [i * rows // n for i in range(n + 1)]
        self.window_rows = min(rows, max(b - a for a, b in itertools.pairwise(self.bounds)) + 2 * MARGIN)
        self.buffers: dict[int, dict[str, NDArray[Any]]] = {}
        self.failed = False

    def tasks(self) -> list[Callable[[], object]]:
        if len(self.bounds) == 2:
            return [self._whole]
        return [partial(self._strip, i) for i in range(len(self.bounds) - 1)]

    def _whole(self) -> None:
        k, w = self.k, self.wall
        dist = self.distance if self.write_distance else _NO_DIST
        if self.nearest is None:
            k.chamfer_steps(self.occ8, w, w, w, self.conn8, self.steps, dist, self.res, self.write_distance)
            return
        nr, nc = self.nearest
        nidx = nc if self.idx_dtype == np.int32 else np.empty(nc.shape, self.idx_dtype)
        k.chamfer_nearest(self.occ8, w, w, w, 0, self.conn8, self.steps, nidx, dist, self.res, self.write_distance)
        k.decode_rows(0, nc.shape[0], nidx, nr, nc)

    def _strip(self, i: int) -> None:
        if self.failed:  # another strip failed: the whole grid is redone anyway
            return
        k, rows = self.k, self.occ8.shape[0]
        a, b = self.bounds[i], self.bounds[i + 1]
        lo, hi = max(0, a - MARGIN), min(rows, b + MARGIN)
        window = self.occ8[lo:hi]
        ws = self._scratch("ws", window.shape, np.int32)
        top, bottom = self.wall and lo == 0, self.wall and hi == rows
        if self.nearest is None:
            wi, nr, nc = _NO_COMP, _NO_COMP, _NO_COMP
            k.chamfer_steps(window, top, bottom, self.wall, self.conn8, ws, _NO_DIST, self.res, False)
        else:
            (nr, nc), wi = self.nearest, self._scratch("wi", window.shape, self.idx_dtype)
            k.chamfer_nearest(window, top, bottom, self.wall, lo, self.conn8, ws, wi, _NO_DIST, self.res, False)
        ok = k.finish_window(a, b, lo, MARGIN, lo > 0 or hi < rows, ws, wi, self.nearest is not None,
                             self.steps, nr, nc, self.distance if self.write_distance else _NO_DIST, self.res,
                             self.write_distance)
        if not ok:
            self.failed = True

    def _scratch(self, name: str, shape: tuple[int, ...], dtype: type) -> NDArray[Any]:
        """A window buffer of this thread, reused by its next strip (no new pages to fault in)."""
        mine = self.buffers.setdefault(threading.get_ident(), {})
        buf = mine.get(name)
        if buf is None or buf.shape[0] < shape[0] or buf.dtype != dtype:
            buf = mine[name] = np.empty((max(shape[0], self.window_rows), shape[1]), dtype)
        return buf[: shape[0]]

    def finish(self) -> None:
        """Drop the window buffers; redo the whole grid in one pass if a strip could not be verified."""
        self.buffers.clear()
        if self.failed:
            self._whole()


def _chunks(kernel: Callable[..., object], n: int, nthreads: int, *args: object,
            min_size: int = 1) -> list[Callable[[], object]]:
    """Tasks running ``kernel(lo, hi, *args)`` over ``range(n)`` in chunks (8 per thread)."""
    k = 1 if nthreads <= 1 else max(1, min(n // max(1, min_size), 8 * nthreads))
    bounds = [i * n // k for i in range(k + 1)]
    return [partial(kernel, bounds[i], bounds[i + 1], *args) for i in range(k) if bounds[i] < bounds[i + 1]]


def _check_flag(name: str, value: object) -> bool:
    if not isinstance(value, bool | np.bool_):
        raise ParameterError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def brushfire(
    gridmap: GridMap,
    *,
    connectivity: int | None = None,
    metric: str | None = None,
    saturate: float | None = None,
    far: float = np.inf,
    compute_steps: bool = True,
    compute_nearest: bool = True,
    compute_labels: bool | None = None,
    compute_gvd: bool | None = None,
    threads: int | None = None,
) -> DistanceMap:
    """Wavefront distance map of an occupancy grid.

    Parameters
    ----------
    gridmap : GridMap
        Occupancy (``True`` = obstacle) and geometry; ``gridmap.grid.border`` says whether what lies
        outside the grid is a wall (an obstacle for the wavefront) or open space.
    connectivity : {8, 4} or {26, 6}, optional
        Neighbourhood of the wavefront that numbers ``steps``: 8 gives chessboard distances in cells
        (the classic brushfire), 4 taxicab; default 8. On a voxel grid (``gridmap.ndim == 3``) 26
        (chessboard, the default) or 6 (taxicab); see :mod:`gridfield.distance._brushfire3d` for what
        differs there (the nearest obstacle's ``int16`` indices, its tie rule).
    metric : {"chessboard", "taxicab", "euclidean"}, optional
        What ``distance`` (and the nearest obstacle) measures; default: chessboard for
        8-connectivity, taxicab for 4. Euclidean is the exact distance between cell centres.
    saturate : float, optional
        Saturation radius in world units (seed 004): distances at or beyond it become ``far``.
        ``steps``, the nearest obstacle and the GVD are not saturated.
    far : float
        Value of saturated distances (default ``inf``).
    compute_steps : bool
        Compute ``steps`` (default True; else it is None). With the Euclidean metric the steps are
        a separate chessboard/taxicab pass: leaving them out (as :func:`gridfield.fields.potential.build_field`
        does, which reads only the distance and the nearest obstacle) saves about a third of that call's time.
    compute_nearest : bool
        Compute ``nearest_row`` / ``nearest_col`` (default True; else they are None).
    compute_labels : bool, optional
        Compute ``label`` (default: True). Labels need a connected-component pass unless the map
        carries ``obstacle_id``.
    compute_gvd : bool, optional
        Compute ``gvd`` (default: ``compute_labels``); needs the labels.
    threads : int, optional
        Threads to use (default: all cores for grids of at least :data:`PARALLEL_MIN_CELLS` cells,
        else 1; more than the cores available are not used). The work is cut into independent
        tasks that the threads take as they become free: the chessboard/taxicab passes in strips of
        :data:`STRIP_ROWS` rows (grids of twice that many rows or more), the component labelling in
        strips, the Euclidean transform, the labels and the GVD in chunks of rows or columns. The
        result does not depend on the number of threads.

    Returns
    -------
    DistanceMap
        Always the same type; fields not computed are None.

    Raises
    ------
    ParameterError
        For an unknown connectivity, metric or flag, a non-positive saturation radius, or
        ``compute_gvd=True`` with ``compute_labels=False``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((3, 5), bool); occ[1, 0] = True
    >>> d = brushfire(GridMap(Grid((3, 5), 1.0), occ))
    >>> d.steps
    array([[1, 1, 2, 3, 4],
           [0, 1, 2, 3, 4],
           [1, 1, 2, 3, 4]], dtype=int32)
    >>> brushfire(GridMap(Grid((3, 5), 1.0), occ), connectivity=4).steps
    array([[1, 2, 3, 4, 5],
           [0, 1, 2, 3, 4],
           [1, 2, 3, 4, 5]], dtype=int32)

    A wall border is an obstacle for the wavefront, labelled :data:`BORDER_LABEL`:

    >>> w = brushfire(GridMap(Grid((3, 5), 1.0, border="wall"), occ))
    >>> w.steps
    array([[1, 1, 1, 1, 1],
           [0, 1, 2, 2, 1],
           [1, 1, 1, 1, 1]], dtype=int32)
    >>> int(w.label[1, 3]), int(w.label[1, 1])
    (-1, 1)

    Labels tell the obstacles apart; the GVD lies where their wavefronts meet:

    >>> two = np.zeros((1, 6), bool); two[0, [0, 5]] = True
    >>> d = brushfire(GridMap(Grid((1, 6), 1.0), two), metric="euclidean")
    >>> d.label, d.gvd
    (array([[1, 1, 1, 2, 2, 2]], dtype=int32), array([[False, False,  True, False, False, False]]))

    Saturation (seed 004) clips the distance, not the steps:

    >>> brushfire(GridMap(Grid((1, 5), 0.5), occ[1:2]), saturate=1.0).distance
    array([[0. , 0.5, inf, inf, inf]])
    """
    req = _validate(gridmap, connectivity, metric, saturate, far, compute_steps, compute_nearest, compute_labels,
                    compute_gvd, threads)
    if gridmap.ndim == 3:  # voxel grids: gridfield/distance/_brushfire3d.py
        from ._brushfire3d import brushfire3d

        return brushfire3d(gridmap, req.connectivity, req.metric, req.saturate, req.far, req.want_steps,
                           req.want_nearest, req.want_label, req.want_gvd, req.nthreads, _run)
    if not req.wall and not req.occ.any():  # no obstacle at all: nothing is reached
        return _unreached(req)
    job = _Job(req)
    job.run_independent()
    job.run_rows()
    job.saturate()
    return job.assemble()


@dataclass
class _Request:
    """The checked arguments of one :func:`brushfire` call."""

    gridmap: GridMap
    connectivity: int
    metric: str
    saturate: float | None
    far: float
    want_steps: bool
    want_nearest: bool
    want_label: bool
    want_gvd: bool
    wall: bool
    occ: NDArray[np.bool_]
    nthreads: int


def _as_float(value: Any) -> float:
    """``value`` as a float; NaN for what is not a number (booleans and strings included)."""
    try:
        return float(value) if not isinstance(value, bool | str) else math.nan
    except (TypeError, ValueError):
        return math.nan


def _validate(gridmap: GridMap, connectivity: int | None, metric: str | None, saturate: float | None, far: float,
              compute_steps: bool, compute_nearest: bool, compute_labels: bool | None, compute_gvd: bool | None,
              threads: int | None) -> _Request:
    """Phase 1 of :func:`brushfire`: check every argument (one clear error for the first bad one)."""
    if not isinstance(gridmap, GridMap):
        hint = " (wrap an occupancy array: GridMap(Grid(occupied.shape, resolution), occupied))" if isinstance(
            gridmap, np.ndarray) else ""
        raise ArgumentTypeError(f"gridmap must be a GridMap, got {type(gridmap).__name__}{hint}")
    check_grid(gridmap.grid.shape, "brushfire", f"brushfire of {gridmap.source or 'the grid map'}")  # bytes, up front
    voxels = gridmap.grid.ndim == 3
    if connectivity is None:
        connectivity = 26 if voxels else 8
    if isinstance(connectivity, bool) or connectivity not in ((26, 6) if voxels else (8, 4)):
        hint = ""
        if connectivity in (4, 8, 6, 26) and not isinstance(connectivity, bool):
            hint = " (4 and 8 are for 2-D maps)" if voxels else " (26 and 6 are for voxel grids)"
        raise ParameterError(f"connectivity must be 6 or 26 on a voxel grid, got {connectivity!r}{hint}" if voxels
                             else f"connectivity must be 4 or 8, got {connectivity!r}{hint}")
    if metric is None:
        metric = "chessboard" if connectivity in (8, 26) else "taxicab"
    if metric not in METRICS:
        raise ParameterError(f"metric must be one of {METRICS}, got {metric!r}")
    if saturate is not None:
        try:
            saturate = float(saturate)
        except (TypeError, ValueError):
            raise ParameterError(f"saturate must be a positive finite distance, got {saturate!r}") from None
        if not (np.isfinite(saturate) and saturate > 0):
            raise ParameterError(f"saturate must be a positive finite distance, got {saturate!r}")
    given_far = far
    far = _as_float(far)
    if math.isnan(far):
        raise ParameterError(f"far must be a number (inf allowed), got {shorten(given_far)}")
    want_steps = _check_flag("compute_steps", compute_steps)
    want_nearest = _check_flag("compute_nearest", compute_nearest)
    want_label = True if compute_labels is None else _check_flag("compute_labels", compute_labels)
    want_gvd = want_label if compute_gvd is None else _check_flag("compute_gvd", compute_gvd)
    if want_gvd and not want_label:
        raise ParameterError("compute_gvd=True needs the labels; pass compute_labels=True or compute_gvd=False")
    occ = np.ascontiguousarray(gridmap.occupied, dtype=bool)
    return _Request(gridmap, connectivity, metric, saturate, far, want_steps, want_nearest, want_label, want_gvd,
                    gridmap.grid.border == "wall", occ, _thread_count(threads, occ.size))


def _unreached(req: _Request) -> DistanceMap:
    """The map of a grid without any obstacle and with an open border: no cell is reached."""
    shape = req.gridmap.grid.shape
    minus = np.full(shape, -1, np.int32)
    return DistanceMap(
        req.gridmap, req.connectivity, req.metric, minus if req.want_steps else None,
        np.full(shape, np.inf if req.saturate is None else req.far),
        minus.copy() if req.want_nearest else None, minus.copy() if req.want_nearest else None,
        np.zeros(shape, np.int32) if req.want_label else None, np.zeros(shape, bool) if req.want_gvd else None,
        req.saturate, req.far,
    )


class _Job:
    """One :func:`brushfire` call after validation: set up (:meth:`__init__`), run the kernels
    (:meth:`run_independent`, :meth:`run_rows`, :meth:`saturate`), assemble (:meth:`assemble`)."""

    def __init__(self, req: _Request) -> None:
        """Phase 2: the output arrays and the label lookup table."""
        self.req = req
        self.k = _kernel_brushfire()
        # the grid-sized arrays reuse the memory of dropped results (see the kernels' `empty`)
        self.empty: Callable[[tuple[int, ...], Any], NDArray[Any]] = getattr(self.k, "empty", np.empty)
        shape = req.gridmap.grid.shape
        self.shape = shape
        self.occ8 = req.occ.view(np.uint8)
        self.res = float(req.gridmap.grid.resolution)
        self.step8 = req.connectivity == 8
        # the Euclidean metric and a metric other than the connectivity's compute the steps in a pass of
        # their own; otherwise the steps are the distance in cells, computed anyway
        self.separate_steps = req.metric == "euclidean" or req.metric != ("chessboard" if self.step8 else "taxicab")
        self.steps = self.empty(shape, np.int32) if req.want_steps or not self.separate_steps else None
        self.distance = self.empty(shape, np.float64)
        self.nearest_row: NDArray[np.int32] | None = None
        self.nearest_col: NDArray[np.int32] | None = None
        self.label: NDArray[np.int32] | None = None
        self.gvd: NDArray[np.bool_] | None = None
        self.vr: NDArray[np.int32] | None = None
        self.key: NDArray[np.int32] | NDArray[np.float64] | None = None  # what orders the cells for the GVD
        # labels are gathered from `flat`: the label grid raveled, plus one element for the wall
        self.flat, self.comp_map, self.use_map = _NO_MAP, _NO_MAP, False
        if req.want_label:
            rows, cols = shape
            self.label = self.empty(shape, np.int32)
            self.flat = self.empty((rows * cols + 1,), np.int32)
            if req.gridmap.obstacle_id is not None:
                self.flat[:-1] = req.gridmap.obstacle_id.ravel()
                self.flat[-1] = BORDER_LABEL

    def run_independent(self) -> None:
        """Phase 3: independent tasks for all threads: the chamfer passes (in strips on large grids), the
        component labelling (in strips) and the column pass of the Euclidean transform (in blocks)."""
        req, k, occ8, shape, nthreads = self.req, self.k, self.occ8, self.shape, self.req.nthreads
        tasks: list[Callable[[], object]] = []
        chamfers: list[_Chamfer] = []
        strips = None
        if req.want_label and req.gridmap.obstacle_id is None:
            strips = _Strips(k, occ8, self.flat[:-1].reshape(shape), 1 if nthreads <= 1 else min(shape[0], 8 * nthreads))
            tasks += strips.tasks()
        if self.separate_steps and req.want_steps:  # the steps by the connectivity's metric, the distance by another
            chamfers.append(_Chamfer(_kernel_chamfer(), occ8, req.wall, self.step8,
                                     cast("NDArray[np.int32]", self.steps), self.distance, self.res, False, None,
                                     nthreads))
        if req.metric == "euclidean":
            self.key = self.distance
            self.vr = self.empty(shape, np.int32)  # column pass result, becomes nearest_row
            tasks += _chunks(_kernel_edt().column_block, shape[1], nthreads, occ8, req.wall, self.vr, min_size=64)
        else:
            self.key = self.empty(shape, np.int32) if self.separate_steps else cast("NDArray[np.int32]", self.steps)
            nearest = None
            if req.want_nearest or req.want_label:  # labels are looked up at the nearest obstacle
                self.nearest_row, self.nearest_col = self.empty(shape, np.int32), self.empty(shape, np.int32)
                nearest = (self.nearest_row, self.nearest_col)
            chamfers.append(_Chamfer(_kernel_chamfer(), occ8, req.wall, req.metric == "chessboard",
                                     cast("NDArray[np.int32]", self.key), self.distance, self.res, True, nearest,
                                     nthreads))
        for chamfer in chamfers:
            tasks = chamfer.tasks() + tasks
        _run(tasks, nthreads)
        del tasks
        for chamfer in chamfers:
            chamfer.finish()
        del chamfers
        if strips is not None:
            self.comp_map, self.use_map = strips.merge(), True
            self.flat[-1] = len(self.comp_map) - 1

    def run_rows(self) -> None:
        """Phase 4, per row: the Euclidean envelope (with labels) and the GVD; or labels and GVD together."""
        req, k, shape, nthreads = self.req, self.k, self.shape, self.req.nthreads
        rows = shape[0]
        if req.metric == "euclidean":
            vr = self.vr
            if req.want_nearest:
                self.nearest_row, self.nearest_col = vr, self.empty(shape, np.int32)
            _run(_chunks(_kernel_edt().edt_rows, rows, nthreads, vr, req.wall, self.res, self.distance, vr,
                         _NO_COMP if self.nearest_col is None else self.nearest_col, req.want_nearest, self.flat,
                         self.comp_map, self.use_map, req.want_label, _NO_COMP if self.label is None else self.label),
                 nthreads)
            self.vr = vr = None
            if req.want_gvd:
                self.gvd = self.empty(shape, bool)
                _run(_chunks(k.gvd_rows, rows, nthreads, self.label, self.key, self.occ8, self.gvd), nthreads)
        elif req.want_label:
            gvd = self.empty(shape, bool) if req.want_gvd else _NO_GVD
            _run(_chunks(k.label_gvd_rows, rows, nthreads, self.nearest_row, self.nearest_col, self.flat,
                         self.comp_map, self.use_map, self.label, req.want_gvd, self.key, self.occ8, gvd), nthreads)
            self.gvd = gvd if req.want_gvd else None
        self.flat = self.comp_map = _NO_MAP
        self.key = None
        if not req.want_nearest:
            self.nearest_row = self.nearest_col = None

    def saturate(self) -> None:
        """Phase 5: distances at or beyond the saturation radius become ``far``."""
        req = self.req
        if req.saturate is not None:
            _run(_chunks(self.k.saturate_rows, self.shape[0], req.nthreads, self.distance, req.saturate, req.far),
                 req.nthreads)

    def assemble(self) -> DistanceMap:
        """Phase 6: the result."""
        req = self.req
        return DistanceMap(req.gridmap, req.connectivity, req.metric, self.steps if req.want_steps else None,
                           self.distance, self.nearest_row, self.nearest_col, self.label, self.gvd, req.saturate,
                           req.far)
