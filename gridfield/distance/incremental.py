"""Maps that change: the brushfire distance map and the potential field updated where the map changed.

:class:`IncrementalBrushfire` holds the Euclidean :class:`~gridfield.distance.brushfire.DistanceMap` of an
occupancy grid and updates it when cells become occupied or free
(:meth:`IncrementalBrushfire.update`); afterwards its distance, nearest obstacle, labels and GVD are
*equal* to those of a full :func:`~gridfield.distance.brushfire.brushfire` of the new occupancy: the same
floats, the same nearest obstacle cell (ties included), the same labels and GVD.
:func:`gridfield.fields.incremental.update_field` then recomputes a potential field in the changed window
only, and :func:`gridfield.fields.incremental.update_navigation` a wavefront navigation function (the
fields layer, above this one).

How it works
------------
The full Euclidean transform picks, for every cell, the obstacle cell with the smallest squared
distance, then the smallest column, then the smallest row. A change never needs more than a
window of the grid:

insertion (cells become occupied: the *lower* wave of Kalra et al. / Lau et al.)
    The transform of the new cells alone, on a window around them, merged cell by cell into the
    current map (a cell takes a new cell if it beats its current nearest obstacle by that rule).
    The window grows until no cell on its border is within ``sqrt(2)`` cells of being reached:
    every cell the change reaches is joined to the new cells by an 8-connected chain of cells that
    are (the lattice cells along the straight segment), so none lies outside.
removal (cells become free: the *raise* wave)
    The cells whose nearest obstacle was removed (*orphans*) are found the same way, and get the
    transform of all remaining obstacles on a window around them, grown until each orphan's
    obstacle is strictly nearer than anything outside the window. Every other cell keeps its
    nearest obstacle: it is still there and still the first by the rule.

So the work is proportional to the window, which is the region the change reaches (plus a margin
of about its own size), not to the grid. Unlike the propagating wavefronts of Lau et al. (whose
``DynamicEDT`` may leave a cell with a slightly wrong nearest obstacle, because a discrete Voronoi
region need not be connected), the windows are transformed exactly, so nothing can be missed.

Labels and GVD: with world obstacle ids (``GridMap.obstacle_id``) a cell's label is the id of its
nearest obstacle, so labels and the GVD (a rule on 8-neighbours) are updated in the changed
windows only. Without ids the labels are the 8-connected components numbered in raster order of
their first cell (as :func:`~gridfield.distance.brushfire.brushfire` numbers them). A change that provably
keeps every number (new cells that all join one existing component; removed cells whose
neighbours stay connected around them, or else through the component's cells in a window around
the change, checked by a flood fill; first cells that keep their order) is applied in place, at a
cost proportional to the change, and labels and GVD follow in the windows. Any other change (a
new component, a merge, a split, a component that vanishes or moves past another in raster order,
a connection only outside that window) may renumber every component after it: then labels and GVD are recomputed over the whole grid,
lazily, the first time :attr:`IncrementalBrushfire.distance_map` is read after the update (compiled
passes, about as long as the labelling part of a full brushfire: ``benchmarks/README.md``,
"Incremental brushfire").

Only the Euclidean metric is offered: its nearest obstacle is defined by a rule a window can
reproduce exactly; the chessboard/taxicab transforms choose among equally near obstacles by the
order of their raster passes. ``steps`` (the wavefront numbers) are not kept (``None``).

Voxel grids (``gridmap.ndim == 3``, issue 44): ``IncrementalBrushfire(gridmap)`` makes an
:class:`IncrementalBrushfire3D`, the same windows as boxes (:mod:`gridfield.distance._incremental3d`):
cells ``(layer, row, col)``, windows ``(z0, z1, r0, r1, c0, c1)``, labels from obstacle ids (26-connected
components, recomputed when read, only on request), no GVD.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ._incremental3d import IncrementalVoxels
from .brushfire import BORDER_LABEL, DistanceMap, brushfire

__all__ = ["ID_MAX", "IncrementalBrushfire", "IncrementalBrushfire3D", "Window"]

#: The largest obstacle id (ids are stored as 32-bit integers; 0 means "no obstacle").
ID_MAX = 2**31 - 1

#: A window of the grid: ``(r0, r1, c0, c1)``, rows ``r0:r1`` and columns ``c0:c1``.
Window = tuple[int, int, int, int]

def _kernel_brushfire() -> Any:
    """The compiled kernel module (gridfield/distance/_brushfire.pyx), imported on first use."""
    from . import _brushfire  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _brushfire


def _kernel_incremental() -> Any:
    """The compiled kernel module (gridfield/distance/_incremental.pyx), imported on first use."""
    from . import _incremental  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _incremental


def _union(a: Window | None, b: Window | None) -> Window | None:
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), max(a[3], b[3]))


class IncrementalBrushfire:
    """The Euclidean brushfire of a map whose occupancy changes, updated where it changes.

    Parameters
    ----------
    gridmap : GridMap
        The initial map (copied: later changes go through :meth:`update`).
    metric : {"euclidean"}
        Only the Euclidean metric is supported (see the module docstring).
    compute_labels : bool
        Keep the labels (default True).
    compute_gvd : bool, optional
        Keep the GVD (default: ``compute_labels``); needs the labels.
    threads : int, optional
        Threads of the initial full :func:`~gridfield.distance.brushfire.brushfire`; updates run on the
        calling thread.

    Attributes
    ----------
    gridmap : GridMap
        The current map (its ``world`` is dropped after the first change: it no longer matches).
    distance_map : DistanceMap
        The current distance map. Its arrays are this object's own and change in place on every
        :meth:`update`; copy them to keep a snapshot.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((1, 7), bool); occ[0, 0] = True
    >>> ib = IncrementalBrushfire(GridMap(Grid((1, 7), 1.0), occ))
    >>> ib.distance_map.distance
    array([[0., 1., 2., 3., 4., 5., 6.]])
    >>> ib.update(occupied=[[0, 6]])
    (0, 1, 4, 7)
    >>> ib.distance_map.distance, ib.distance_map.label
    (array([[0., 1., 2., 3., 2., 1., 0.]]), array([[1, 1, 1, 1, 2, 2, 2]], dtype=int32))
    >>> ib.update(freed=[[0, 0]])
    (0, 1, 0, 4)
    >>> ib.distance_map.distance
    array([[6., 5., 4., 3., 2., 1., 0.]])
    """

    def __new__(cls, gridmap: GridMap | None = None, *args: Any, **kwargs: Any) -> IncrementalBrushfire:
        if cls is IncrementalBrushfire and isinstance(gridmap, GridMap) and gridmap.ndim == 3:  # a voxel grid
            return super().__new__(IncrementalBrushfire3D)
        return super().__new__(cls)

    def __init__(self, gridmap: GridMap, *, metric: str = "euclidean", compute_labels: bool = True,
                 compute_gvd: bool | None = None, threads: int | None = None) -> None:
        if not isinstance(gridmap, GridMap):
            raise ParameterError(f"IncrementalBrushfire needs a GridMap, got {type(gridmap).__name__}")
        if metric != "euclidean":
            raise ParameterError(f"IncrementalBrushfire supports metric='euclidean' only, got {metric!r}")
        if not isinstance(compute_labels, bool | np.bool_):
            raise ParameterError(f"compute_labels must be True or False, got {compute_labels!r}")
        want_gvd = bool(compute_labels) if compute_gvd is None else compute_gvd
        if not isinstance(want_gvd, bool | np.bool_):
            raise ParameterError(f"compute_gvd must be True or False, got {compute_gvd!r}")
        if want_gvd and not compute_labels:
            raise ParameterError("compute_gvd=True needs the labels; pass compute_labels=True or compute_gvd=False")
        d = brushfire(gridmap, metric="euclidean", compute_steps=False, compute_labels=bool(compute_labels),
                      compute_gvd=bool(want_gvd), threads=threads)
        self._grid = gridmap.grid
        self._source = gridmap.source
        self._world = gridmap.world
        self._meta = dict(gridmap.meta)
        shape = self._grid.shape
        self._occ = np.array(gridmap.occupied, dtype=bool, order="C")
        self._occ8 = self._occ.view(np.uint8)
        self._ids = None if gridmap.obstacle_id is None else np.array(gridmap.obstacle_id, np.int32, order="C")
        self._max_id = 0 if self._ids is None else int(self._ids.max(initial=0))  # the default id of new cells - 1
        assert d.nearest_row is not None and d.nearest_col is not None
        self._nr = np.ascontiguousarray(d.nearest_row, np.int32)
        self._nc = np.ascontiguousarray(d.nearest_col, np.int32)
        if self._nr is self._nc:  # never shared, but make sure
            self._nc = self._nc.copy()
        self._dist = np.ascontiguousarray(d.distance, np.float64)  # the brushfire's own: no copy
        self._label = d.label
        self._gvd = d.gvd
        self._want_label = bool(compute_labels)
        self._want_gvd = bool(want_gvd)
        self._mark = np.zeros(shape, np.uint8)
        self._comp: NDArray[np.int32] | None = None  # component numbers (maps without ids), see _components
        self._first: NDArray[np.int64] | None = None
        self._labels_dirty = False
        self._gridmap: GridMap | None = gridmap
        self._dmap: DistanceMap | None = None
        self._res = float(self._grid.resolution)
        self._wall = self._grid.border == "wall"
        #: The window changed by the last :meth:`update` (``None``: nothing changed).
        self.last_window: Window | None = None
        #: Cells whose nearest obstacle the last :meth:`update` changed (a cell changed by both its
        #: removals and its insertions counts twice).
        self.last_changed = 0

    def __repr__(self) -> str:
        rows, cols = self._grid.shape
        return (f"IncrementalBrushfire(shape=({rows}, {cols}), resolution={self._res:.6g}, "
                f"occupied={int(np.count_nonzero(self._occ))}, last_changed={self.last_changed})")

    # -- state ------------------------------------------------------------------------
    @property
    def gridmap(self) -> GridMap:
        """The current map (sharing this object's occupancy and id arrays)."""
        if self._gridmap is None:
            self._gridmap = GridMap(self._grid, self._occ, self._ids, None, self._source, dict(self._meta))
        return self._gridmap

    @property
    def distance_map(self) -> DistanceMap:
        """The current distance map: equal to ``brushfire(self.gridmap, metric="euclidean",
        compute_steps=False)`` (labels and GVD as asked for; relabelled here when an update renumbered
        the components)."""
        if self._labels_dirty:
            self._relabel()
        if self._dmap is None:
            self._dmap = DistanceMap(self.gridmap, 8, "euclidean", None, self._dist, self._nr, self._nc,
                                     self._label, self._gvd, None, math.inf)
        return self._dmap

    # -- input ------------------------------------------------------------------------
    def _cells(self, cells: ArrayLike | None, name: str
               ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
        """Unique cells (sorted in raster order) and, for each, its position in the input."""
        shape = self._grid.shape
        empty = np.zeros(0, np.int64)
        if cells is None:
            return empty, empty, empty
        a = np.asarray(cells)
        if a.dtype == bool:
            if a.shape != shape:
                raise ParameterError(f"{name}: a boolean mask must have the grid's shape {shape}, got {a.shape}")
            r, c = np.nonzero(a)
            return r.astype(np.int64), c.astype(np.int64), np.arange(len(r), dtype=np.int64)
        if a.size == 0:
            return empty, empty, empty
        if a.ndim == 1 and a.shape[0] == 2:
            a = a[None, :]
        if a.ndim != 2 or a.shape[1] != 2 or not np.issubdtype(a.dtype, np.integer):
            raise ParameterError(f"{name} must be integer cells (row, col) of shape (N, 2) or a boolean mask of "
                                 f"shape {shape}, got an array of shape {a.shape} and dtype {a.dtype}")
        bad = (a[:, 0] < 0) | (a[:, 0] >= shape[0]) | (a[:, 1] < 0) | (a[:, 1] >= shape[1])
        if bad.any():
            k = int(np.argmax(bad))
            raise ParameterError(f"{name}: cell ({int(a[k, 0])}, {int(a[k, 1])}) lies outside the grid of shape {shape}")
        flat, first = np.unique(a[:, 0].astype(np.int64) * shape[1] + a[:, 1].astype(np.int64), return_index=True)
        return flat // shape[1], flat % shape[1], first.astype(np.int64)

    # -- update -----------------------------------------------------------------------
    def update(self, occupied: ArrayLike | None = None, freed: ArrayLike | None = None, *,
               ids: int | ArrayLike | None = None) -> Window | None:
        """Make cells occupied and/or free, and update the distance map.

        Parameters
        ----------
        occupied, freed : array_like, optional
            Cells ``(row, col)`` as an integer array of shape ``(N, 2)``, or a boolean mask of the
            grid's shape. Cells already occupied (free) are ignored; a cell in both is an error.
        ids : int or array_like, optional
            Only for maps with world obstacle ids: the id of the newly occupied cells (one for all,
            or one per cell of ``occupied`` in its order), each in ``1..ID_MAX``; default: one new id,
            the largest used so far plus one (an error once that would pass ``ID_MAX``).

        Returns
        -------
        tuple or None
            The window ``(r0, r1, c0, c1)`` holding every cell whose occupancy, distance or nearest
            obstacle changed (rows ``r0:r1``, columns ``c0:c1``), or None if nothing changed.

        Raises
        ------
        ParameterError
            For cells outside the grid, malformed cells or masks, a cell both occupied and freed,
            or ``ids`` on a map without obstacle ids.
        """
        orr, occ_c, pos = self._cells(occupied, "occupied")
        frr, frc, _ = self._cells(freed, "freed")
        shape = self._grid.shape
        if len(orr) and len(frr):
            both = np.intersect1d(orr * shape[1] + occ_c, frr * shape[1] + frc)
            if len(both):
                r, c = divmod(int(both[0]), shape[1])
                raise ParameterError(f"cell ({r}, {c}) is both occupied and freed")
        new_ids = None if ids is None else self._given_ids(ids, occupied, pos)
        keep = ~self._occ[orr, occ_c]
        if new_ids is None and self._ids is not None and keep.any() and self._max_id >= ID_MAX:
            raise ParameterError(f"no default obstacle id left: the largest, {ID_MAX}, is in use; give ids= "
                                 f"(an id in 1..{ID_MAX})")
        orr, occ_c = orr[keep], occ_c[keep]
        if new_ids is not None and new_ids.ndim == 1:
            new_ids = new_ids[keep]
        keep = self._occ[frr, frc]
        frr, frc = frr[keep], frc[keep]
        self.last_window = None
        self.last_changed = 0
        if not len(orr) and not len(frr):
            return None
        window = self._apply(_kernel_incremental(), orr, occ_c, frr, frc, new_ids)
        self.last_window = window
        return window

    def _given_ids(self, ids: int | ArrayLike, occupied: ArrayLike | None, pos: Any) -> NDArray[Any]:
        """:meth:`update`'s ``ids`` checked, one per occupied cell in the order of the cells (or one for all)."""
        if self._ids is None:
            raise ParameterError("ids are only for maps with world obstacle ids (GridMap.obstacle_id)")
        new_ids = np.asarray(ids)
        n_given = 0 if occupied is None else (int(np.count_nonzero(occupied)) if np.asarray(occupied).dtype == bool
                                              else len(np.asarray(occupied).reshape(-1, 2)))
        if not np.issubdtype(new_ids.dtype, np.integer) or new_ids.ndim > 1 or (
                new_ids.ndim == 1 and len(new_ids) != n_given):
            raise ParameterError(f"ids must be one integer or one per occupied cell ({n_given}), got {ids!r}")
        if new_ids.size and not (new_ids.min() >= 1 and new_ids.max() <= ID_MAX):
            bad = new_ids.ravel()[np.flatnonzero((new_ids.ravel() < 1) | (new_ids.ravel() > ID_MAX))[0]]
            raise ParameterError(f"ids must be obstacle ids in 1..{ID_MAX} (0 is 'no obstacle'; ids are stored "
                                 f"as 32-bit integers), got {int(bad)}")
        return new_ids[pos] if new_ids.ndim == 1 else new_ids

    def _apply(self, k: ModuleType, orr: NDArray[np.int64], occ_c: NDArray[np.int64], frr: NDArray[np.int64],
               frc: NDArray[np.int64], new_ids: NDArray[Any] | None) -> Window | None:
        """Free ``(frr, frc)``, occupy ``(orr, occ_c)`` (cells that change), update distances and labels;
        the window of every change."""
        boxes: list[Window] = []
        # component numbers (maps without ids): kept in place while the change provably renumbers nothing
        in_place = self._want_label and self._ids is None and not self._labels_dirty
        if len(frr):
            box = self._raise(k, frr, frc)
            if box is not None:
                boxes.append(box)
            if self._ids is not None:
                self._ids[frr, frc] = 0
            if in_place:
                in_place = self._components_removed(k, frr, frc)
        if len(orr):
            if self._ids is not None:
                given = np.asarray(self._max_id + 1 if new_ids is None else new_ids, np.int32)
                self._ids[orr, occ_c] = given
                self._max_id = max(self._max_id, int(given.max(initial=0)))
            box = self._lower(k, orr, occ_c)
            if box is not None:
                boxes.append(box)
            if in_place:
                in_place = self._components_added(k, orr, occ_c)
        window = None
        for b in boxes:
            window = _union(window, b)
        self._gridmap = None
        self._dmap = None
        if self._want_label:
            if self._ids is not None:
                self._local_labels(k, boxes, self._ids)
            elif in_place:
                assert self._comp is not None
                self._local_labels(k, boxes, self._comp)
            else:
                self._labels_dirty = True
        return window

    def _pad(self, box: Window, m: Sequence[int]) -> Window:
        rows, cols = self._grid.shape
        return (max(0, box[0] - m[0]), min(rows, box[1] + m[1]), max(0, box[2] - m[2]), min(cols, box[3] + m[3]))

    def _edt(self, k: ModuleType, sites: NDArray[np.uint8], w: Window, walls: bool
             ) -> tuple[NDArray[np.int32], NDArray[np.int32], NDArray[np.int64]]:
        rows, cols = self._grid.shape
        r0, r1, c0, c1 = w
        h, n = r1 - r0, c1 - c0
        wall = walls and self._wall
        vr = np.empty((h, n), np.int64)
        g, rowv, s, t = (np.empty(n + 2, np.int64) for _ in range(4))
        val, arg = np.empty(n, np.int64), np.empty(n, np.int64)
        wnr, wnc, wd2 = np.empty((h, n), np.int32), np.empty((h, n), np.int32), np.empty((h, n), np.int64)
        k.window_edt(sites, r0, r1, c0, c1, wall and r0 == 0, wall and r1 == rows, wall and c0 == 0,
                     wall and c1 == cols, np.int64(rows + cols + 4), vr, g, rowv, s, t, val, arg, wnr, wnc, wd2)
        return wnr, wnc, wd2

    def _reach_window(self, k: ModuleType, box: Window, margin: int) -> tuple[Window, Any]:
        """The window around ``box`` that holds every cell the marked cells may reach, with the
        transform of the marked cells on it."""
        rows, cols = self._grid.shape
        m = [margin] * 4
        flags = np.zeros(4, np.bool_)
        while True:
            w = self._pad(box, m)
            res = self._edt(k, self._mark, w, False)
            if w == (0, rows, 0, cols):
                return w, res
            k.ring_reached(*w, rows, cols, res[2], self._nr, self._nc, flags)
            if not flags.any():
                return w, res
            for i in range(4):
                if flags[i]:
                    m[i] = 2 * m[i] + 2

    @staticmethod
    def _box(r: NDArray[np.int64], c: NDArray[np.int64]) -> Window:
        return int(r.min()), int(r.max()) + 1, int(c.min()), int(c.max()) + 1

    def _lower(self, k: ModuleType, r: NDArray[np.int64], c: NDArray[np.int64]) -> Window | None:
        k.set_cells(r, c, self._occ8, 1)
        k.set_cells(r, c, self._mark, 1)
        try:
            box = self._box(r, c)
            far2 = k.max_distance2(*self._pad(box, (1, 1, 1, 1)), self._nr, self._nc)
            rows, cols = self._grid.shape
            margin = rows + cols if far2 >= k.NONE_D2 else 2 * math.isqrt(int(far2)) + 4
            w, (wnr, wnc, wd2) = self._reach_window(k, box, margin)
            out = np.array([rows, -1, cols, -1], np.int64)
            n = k.lower_merge(*w, wnr, wnc, wd2, self._nr, self._nc, self._dist, self._res, out)
            self.last_changed += int(n)
        finally:
            k.set_cells(r, c, self._mark, 0)
        return (int(out[0]), int(out[1]), int(out[2]), int(out[3])) if n else None

    def _raise(self, k: ModuleType, r: NDArray[np.int64], c: NDArray[np.int64]) -> Window | None:
        rows, cols = self._grid.shape
        k.set_cells(r, c, self._occ8, 0)
        k.set_cells(r, c, self._mark, 1)
        try:
            box = self._box(r, c)
            w, _ = self._reach_window(k, box, 8)
            ob = np.array([rows, -1, cols, -1], np.int64)
            n, _ = k.orphan_box(*w, rows, cols, self._nr, self._nc, self._mark, ob)
            if not n:
                return None
            self.last_changed += int(n)
            obox = (int(ob[0]), int(ob[1]), int(ob[2]), int(ob[3]))
            margin = 2  # usually too small: the check then says how far the window must reach
            while True:
                w2 = self._pad(obox, [margin] * 4)
                wnr, wnc, wd2 = self._edt(k, self._occ8, w2, True)
                worst = k.raise_check(*obox, *w2, rows, cols, self._nr, self._nc, self._mark, wd2)
                if worst == -1:
                    break
                # -2: some orphan found no obstacle in the window at all: widen it and look again
                margin = 2 * margin + 2 if worst == -2 else max(2 * margin, int(worst) + 1)
            k.raise_apply(*obox, w2[0], w2[2], rows, cols, self._nr, self._nc, self._mark, wnr, wnc, wd2,
                          self._dist, self._res)
        finally:
            k.set_cells(r, c, self._mark, 0)
        return obox

    # -- labels and GVD ---------------------------------------------------------------
    def _components(self, k: ModuleType) -> tuple[NDArray[np.int32], NDArray[np.int64]]:
        """The component number of every obstacle cell and each component's first cell (raster index;
        ``first[0] = -1`` and ``first[K + 1] = rows * cols`` as sentinels), computed when missing."""
        if self._comp is None or self._first is None:
            kb = _kernel_brushfire()
            rows, cols = self._grid.shape
            comp = np.empty((rows, cols), np.int32)
            count = kb.label_components(self._occ8, comp)
            first = np.full(count + 2, -1, np.int64)
            k.first_cells(comp, first)
            first[count + 1] = rows * cols
            self._comp, self._first = comp, first
        return self._comp, self._first

    def _components_removed(self, k: ModuleType, r: NDArray[np.int64], c: NDArray[np.int64]) -> bool:
        """Take the freed cells out of their components in place; False if that may renumber them."""
        if self._comp is None:  # the numbers of the map before this change (already freed in occ)
            k.set_cells(r, c, self._occ8, 1)
            self._components(k)
            k.set_cells(r, c, self._occ8, 0)
        comp, first = self._components(k)
        k.set_cells(r, c, self._mark, 1)
        try:
            ok = bool(k.remove_in_place(r, c, self._occ8, self._mark, comp, first, 32))
            if not ok:  # stuck cells (a removed bridge, say): a flood fill in a window around them
                box = self._box(r, c)
                side = max(box[1] - box[0], box[3] - box[2])
                ok = bool(k.remove_rest_in_place(r, c, self._mark, comp, first,
                                                 *self._pad(box, [2 * side + 32] * 4)))
        finally:
            k.set_cells(r, c, self._mark, 0)
        if not ok:
            self._comp = self._first = None
        return ok

    def _components_added(self, k: ModuleType, r: NDArray[np.int64], c: NDArray[np.int64]) -> bool:
        """Join the new obstacle cells to their components in place; False if that may renumber them."""
        if self._comp is None:
            k.set_cells(r, c, self._occ8, 0)
            self._components(k)
            k.set_cells(r, c, self._occ8, 1)
        comp, first = self._components(k)
        k.set_cells(r, c, self._mark, 1)
        try:
            ok = bool(k.insert_in_place(r, c, self._mark, comp, first, np.empty(len(r), np.int64),
                                        np.empty(len(r), np.int64)))
        finally:
            k.set_cells(r, c, self._mark, 0)
        if not ok:
            self._comp = self._first = None
        return ok

    def _local_labels(self, k: ModuleType, boxes: list[Window], ids: NDArray[np.int32]) -> None:
        assert self._label is not None
        for b in boxes:
            k.labels_window(*b, self._nr, self._nc, ids, BORDER_LABEL, self._label)
        if self._want_gvd:
            assert self._gvd is not None
            for b in boxes:
                k.gvd_window(*self._pad(b, (1, 1, 1, 1)), self._label, self._dist, self._occ8, self._gvd)

    def _relabel(self) -> None:
        k = _kernel_incremental()
        rows, cols = self._grid.shape
        self._comp = self._first = None
        comp, _ = self._components(k)
        assert self._label is not None
        k.gather_rows(0, rows, self._nr, self._nc, comp, BORDER_LABEL, self._label)
        if self._want_gvd:
            assert self._gvd is not None
            k.gvd_window(0, rows, 0, cols, self._label, self._dist, self._occ8, self._gvd)
        self._labels_dirty = False


class IncrementalBrushfire3D(IncrementalVoxels, IncrementalBrushfire):  # type: ignore[misc]  # 3-D boxes for windows
    """:class:`IncrementalBrushfire` on a voxel grid (``gridmap.ndim == 3``), which makes it: the methods
    of :class:`gridfield.distance._incremental3d.IncrementalVoxels` (cells ``(layer, row, col)``,
    windows ``(z0, z1, r0, r1, c0, c1)``; labels from obstacle ids, no GVD).

    Parameters
    ----------
    gridmap : GridMap
        A voxel grid; the other arguments as :class:`IncrementalBrushfire`'s.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy import ndimage
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((4, 5, 6), bool); occ[1, 2, 3] = True
    >>> ib = IncrementalBrushfire(GridMap(Grid((4, 5, 6), 1.0), occ))
    >>> type(ib).__name__
    'IncrementalBrushfire3D'
    >>> box = ib.update(occupied=[[3, 0, 0]])
    >>> occ[3, 0, 0] = True
    >>> bool((ib.distance_map.distance == ndimage.distance_transform_edt(~occ)).all())
    True
    """
