"""The incremental Euclidean brushfire of a voxel grid (private): :class:`IncrementalVoxels` is the
implementation behind ``gridfield.distance.incremental.IncrementalBrushfire3D``, the subclass of
:class:`~gridfield.distance.incremental.IncrementalBrushfire` that ``IncrementalBrushfire(gridmap)``
makes for a map with ``ndim == 3`` (this module does not import that one: the sibling modules import
no cycle).

The same windows as the 2-D class (see :mod:`gridfield.distance.incremental`), as boxes of layers,
rows and columns, transformed exactly by the compiled kernel :mod:`gridfield.distance._incremental3`:

insertion
    The transform of the new voxels alone on a box around them, merged voxel by voxel into the
    current map (a voxel takes a new one if it beats its nearest obstacle by the rule below). The box
    grows until no voxel on a face of it is within ``sqrt(3)`` voxels of being reached: every voxel
    the change reaches is joined to the new voxels by a 26-connected chain of voxels that are.
removal
    The voxels whose nearest obstacle was removed (orphans) get the transform of all remaining
    obstacles on a box around them, grown until each orphan's obstacle is strictly nearer than any
    voxel outside the box.

The nearest obstacle is the one with the smallest squared distance, then the smallest column, then
row, then layer (the tie rule of the full 3-D transform); a wall border is the shell of voxels just
outside the six faces (layer ``-1``/``layers``, row ``-1``/``rows`` or column ``-1``/``cols``, the
other two coordinates the voxel's own). Distances are ``sqrt(d2) * resolution`` with ``d2`` the
integer squared distance in voxels, so they are the very floats of a full recompute.

Labels: with obstacle ids (``GridMap.obstacle_id``) a voxel's label is the id of its nearest
obstacle, updated in the changed boxes only. Without ids they are the 26-connected components of
the obstacles, numbered in raster order of their first voxel (``scipy.ndimage.label`` with a full
3 x 3 x 3 structure), and recomputed over the whole grid, lazily, on the first read of
:attr:`~IncrementalBrushfire3D.distance_map` after a change (a full-grid pass: only asked for with
``compute_labels=True``; the default on a voxel grid is labels only when the map has ids). The GVD
is 2-D only.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ..core.limits import check_grid
from .brushfire import BORDER_LABEL, DistanceMap

__all__ = ["ID_MAX", "IncrementalVoxels", "Window3"]

#: The largest obstacle id (as :data:`gridfield.distance.incremental.ID_MAX`: 32-bit ids, 0 = none).
ID_MAX = 2**31 - 1

#: A box of a voxel grid: ``(z0, z1, r0, r1, c0, c1)``, layers ``z0:z1``, rows ``r0:r1``, columns ``c0:c1``.
Window3 = tuple[int, int, int, int, int, int]

_Cells = tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]


def _kernel() -> Any:
    """The compiled kernel module (gridfield/distance/_incremental3.pyx), imported on first use."""
    from . import _incremental3  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _incremental3


def _union(a: Window3 | None, b: Window3 | None) -> Window3 | None:
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), max(a[3], b[3]), min(a[4], b[4]), max(a[5], b[5]))


def _as_window(box: NDArray[np.int64]) -> Window3:
    return (int(box[0]), int(box[1]), int(box[2]), int(box[3]), int(box[4]), int(box[5]))


def _empty_box(shape: tuple[int, ...]) -> NDArray[np.int64]:
    return np.array([shape[0], -1, shape[1], -1, shape[2], -1], np.int64)


class IncrementalVoxels:
    """The Euclidean brushfire of a voxel grid whose occupancy changes, updated where it changes.

    The methods of ``IncrementalBrushfire3D``, made by :class:`~gridfield.distance.incremental.IncrementalBrushfire` for a map with
    ``gridmap.ndim == 3`` (the same arguments and methods; cells are ``(layer, row, col)`` and
    windows ``(z0, z1, r0, r1, c0, c1)``). After every :meth:`update` the distance and the nearest
    obstacle voxel equal those of a full Euclidean transform of the new occupancy: the same floats,
    the same voxel (ties: the smallest squared distance, then column, row, layer).

    Parameters
    ----------
    gridmap : GridMap
        The initial voxel map (copied).
    metric : {"euclidean"}
        Only the Euclidean metric.
    compute_labels : bool, optional
        Keep the labels. Default: only when the map has obstacle ids (then they are updated in the
        changed boxes); ``True`` without ids: 26-connected components, relabelled over the whole
        grid on the first read after a change (see the module docstring).
    compute_gvd : bool, optional
        Must be False or None: the GVD is 2-D only.
    threads : int, optional
        Unused on a voxel grid (the initial transform runs on the calling thread).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.distance.incremental import IncrementalBrushfire
    >>> occ = np.zeros((1, 1, 7), bool); occ[0, 0, 0] = True
    >>> ib = IncrementalBrushfire(GridMap(Grid((1, 1, 7), 1.0), occ))
    >>> type(ib).__name__, ib.distance_map.distance[0, 0]
    ('IncrementalBrushfire3D', array([0., 1., 2., 3., 4., 5., 6.]))
    >>> ib.update(occupied=[[0, 0, 6]])
    (0, 1, 0, 1, 4, 7)
    >>> ib.update(freed=[[0, 0, 0]])
    (0, 1, 0, 1, 0, 4)
    >>> ib.distance_map.distance[0, 0], ib.distance_map.nearest_index[2][0, 0]
    (array([6., 5., 4., 3., 2., 1., 0.]), array([6, 6, 6, 6, 6, 6, 6], dtype=int32))
    """

    #: The box changed by the last :meth:`update` (``None``: nothing changed).
    last_window: Window3 | None
    #: Voxels whose nearest obstacle the last :meth:`update` changed.
    last_changed: int

    def __init__(self, gridmap: GridMap, *, metric: str = "euclidean", compute_labels: bool | None = None,
                 compute_gvd: bool | None = None, threads: int | None = None) -> None:
        if not isinstance(gridmap, GridMap) or gridmap.ndim != 3:
            raise ParameterError(f"IncrementalBrushfire3D needs a voxel GridMap (ndim 3), got {gridmap!r:.200}")
        if metric != "euclidean":
            raise ParameterError(f"IncrementalBrushfire supports metric='euclidean' only, got {metric!r}")
        if compute_labels is None:
            compute_labels = gridmap.obstacle_id is not None
        if not isinstance(compute_labels, bool | np.bool_):
            raise ParameterError(f"compute_labels must be True or False, got {compute_labels!r}")
        if compute_gvd is not None and not isinstance(compute_gvd, bool | np.bool_):
            raise ParameterError(f"compute_gvd must be True or False, got {compute_gvd!r}")
        if compute_gvd:
            raise ParameterError("compute_gvd=True: the GVD is 2-D only (a voxel grid has none); pass "
                                 "compute_gvd=False")
        shape = gridmap.grid.shape
        check_grid(shape, "brushfire", f"incremental brushfire of {gridmap.source or 'the voxel map'}")
        k = _kernel()
        self._grid = gridmap.grid
        self._source = gridmap.source
        self._world = gridmap.world
        self._meta = dict(gridmap.meta)
        self._occ = np.array(gridmap.occupied, dtype=bool, order="C")
        self._occ8 = self._occ.view(np.uint8)
        self._ids = None if gridmap.obstacle_id is None else np.array(gridmap.obstacle_id, np.int32, order="C")
        self._max_id = 0 if self._ids is None else int(self._ids.max(initial=0))
        self._res = float(self._grid.resolution)
        self._wall = self._grid.border == "wall"
        self._nl = np.empty(shape, np.int32)
        self._nr = np.empty(shape, np.int32)
        self._nc = np.empty(shape, np.int32)
        d2 = np.empty(shape, np.int64)
        w = self._wall
        k.window_edt3(self._occ8, 0, shape[0], 0, shape[1], 0, shape[2], w, w, w, w, w, w, self._nl, self._nr,
                      self._nc, d2)
        self._dist = np.empty(shape, np.float64)
        k.distance3(0, shape[0], d2, self._res, self._dist)
        del d2
        self._want_label = bool(compute_labels)
        self._want_gvd = False
        self._label: NDArray[np.int32] | None = np.zeros(shape, np.int32) if self._want_label else None
        self._gvd: NDArray[np.bool_] | None = None  # 2-D only
        self._mark = np.zeros(shape, np.uint8)
        self._labels_dirty = self._want_label and self._ids is None
        if self._want_label and self._ids is not None:
            self._local_labels3(k, [(0, shape[0], 0, shape[1], 0, shape[2])], self._ids)
        self._gridmap: GridMap | None = gridmap
        self._dmap: DistanceMap | None = None
        self.last_window = None
        self.last_changed = 0

    def __repr__(self) -> str:
        layers, rows, cols = self._grid.shape
        return (f"IncrementalBrushfire(shape=({layers}, {rows}, {cols}), resolution={self._res:.6g}, "
                f"occupied={int(np.count_nonzero(self._occ))}, last_changed={self.last_changed})")

    @property
    def gridmap(self) -> GridMap:
        """The current map (sharing this object's occupancy and id arrays)."""
        if self._gridmap is None:
            self._gridmap = GridMap(self._grid, self._occ, self._ids, None, self._source, dict(self._meta))
        return self._gridmap

    @property
    def distance_map(self) -> DistanceMap:
        """The current distance map (``nearest_layer`` set; ``steps`` and ``gvd`` None; labels as asked for)."""
        if self._labels_dirty:
            self._relabel3()
        if self._dmap is None:
            self._dmap = DistanceMap(self.gridmap, 26, "euclidean", None, self._dist, self._nr, self._nc,
                                     self._label, None, None, math.inf, nearest_layer=self._nl)
        return self._dmap

    # -- input ------------------------------------------------------------------------
    def _cells3(self, cells: ArrayLike | None, name: str) -> _Cells:
        """Unique voxels (sorted in raster order) and, for each, its position in the input."""
        shape = self._grid.shape
        empty = np.zeros(0, np.int64)
        if cells is None:
            return empty, empty, empty, empty
        a = np.asarray(cells)
        if a.dtype == bool:
            if a.shape != shape:
                raise ParameterError(f"{name}: a boolean mask must have the grid's shape {shape}, got {a.shape}")
            z, r, c = (v.astype(np.int64) for v in np.nonzero(a))
            return z, r, c, np.arange(len(z), dtype=np.int64)
        if a.size == 0:
            return empty, empty, empty, empty
        if a.ndim == 1 and a.shape[0] == 3:
            a = a[None, :]
        if a.ndim != 2 or a.shape[1] != 3 or not np.issubdtype(a.dtype, np.integer):
            raise ParameterError(f"{name} must be integer voxels (layer, row, col) of shape (N, 3) or a boolean mask "
                                 f"of shape {shape}, got an array of shape {a.shape} and dtype {a.dtype}")
        a = a.astype(np.int64)
        bad = ((a < 0) | (a >= np.array(shape, np.int64))).any(axis=1)
        if bad.any():
            i = int(np.argmax(bad))
            raise ParameterError(f"{name}: voxel ({int(a[i, 0])}, {int(a[i, 1])}, {int(a[i, 2])}) lies outside the "
                                 f"grid of shape {shape}")
        flat, first = np.unique(np.ravel_multi_index((a[:, 0], a[:, 1], a[:, 2]), shape), return_index=True)
        z, r, c = np.unravel_index(flat, shape)
        return z.astype(np.int64), r.astype(np.int64), c.astype(np.int64), first.astype(np.int64)

    def _given_ids3(self, ids: int | ArrayLike, occupied: ArrayLike | None, pos: NDArray[np.int64]) -> NDArray[Any]:
        if self._ids is None:
            raise ParameterError("ids are only for maps with world obstacle ids (GridMap.obstacle_id)")
        new_ids = np.asarray(ids)
        n_given = 0 if occupied is None else (int(np.count_nonzero(occupied)) if np.asarray(occupied).dtype == bool
                                              else len(np.asarray(occupied).reshape(-1, 3)))
        if not np.issubdtype(new_ids.dtype, np.integer) or new_ids.ndim > 1 or (
                new_ids.ndim == 1 and len(new_ids) != n_given):
            raise ParameterError(f"ids must be one integer or one per occupied voxel ({n_given}), got {ids!r}")
        if new_ids.size and not (new_ids.min() >= 1 and new_ids.max() <= ID_MAX):
            flat = new_ids.ravel()
            bad = flat[np.flatnonzero((flat < 1) | (flat > ID_MAX))[0]]
            raise ParameterError(f"ids must be obstacle ids in 1..{ID_MAX} (0 is 'no obstacle'; ids are stored "
                                 f"as 32-bit integers), got {int(bad)}")
        return new_ids[pos] if new_ids.ndim == 1 else new_ids

    # -- update -----------------------------------------------------------------------
    def update(self, occupied: ArrayLike | None = None, freed: ArrayLike | None = None, *,
               ids: int | ArrayLike | None = None) -> Window3 | None:
        """Make voxels occupied and/or free, and update the distance map.

        Parameters
        ----------
        occupied, freed : array_like, optional
            Voxels ``(layer, row, col)`` as an integer array of shape ``(N, 3)``, or a boolean mask of
            the grid's shape. Voxels already occupied (free) are ignored; one in both is an error.
        ids : int or array_like, optional
            Only for maps with obstacle ids: the id of the newly occupied voxels (one for all, or one
            per voxel of ``occupied`` in its order), each in ``1..ID_MAX``; default: one new id.

        Returns
        -------
        tuple or None
            The box ``(z0, z1, r0, r1, c0, c1)`` holding every voxel whose occupancy, distance or
            nearest obstacle changed, or None if nothing changed.

        Raises
        ------
        ParameterError
            For voxels outside the grid, malformed voxels or masks, a voxel both occupied and
            freed, or ``ids`` on a map without obstacle ids.

        Examples
        --------
        >>> import numpy as np
        >>> from gridfield.core.grid import Grid, GridMap
        >>> from gridfield.distance.incremental import IncrementalBrushfire
        >>> ib = IncrementalBrushfire(GridMap(Grid((3, 3, 3), 1.0), np.zeros((3, 3, 3), bool)))
        >>> ib.update(occupied=[[1, 1, 1]])
        (0, 3, 0, 3, 0, 3)
        >>> float(ib.distance_map.distance[0, 0, 0]) == 3 ** 0.5
        True
        """
        oz, orr, oc, pos = self._cells3(occupied, "occupied")
        fz, frr, fc, _ = self._cells3(freed, "freed")
        shape = self._grid.shape
        if len(oz) and len(fz):
            both = np.intersect1d(np.ravel_multi_index((oz, orr, oc), shape), np.ravel_multi_index((fz, frr, fc), shape))
            if len(both):
                z, r, c = (int(v) for v in np.unravel_index(int(both[0]), shape))
                raise ParameterError(f"voxel ({z}, {r}, {c}) is both occupied and freed")
        new_ids = None if ids is None else self._given_ids3(ids, occupied, pos)
        keep = ~self._occ[oz, orr, oc]
        if new_ids is None and self._ids is not None and keep.any() and self._max_id >= ID_MAX:
            raise ParameterError(f"no default obstacle id left: the largest, {ID_MAX}, is in use; give ids= "
                                 f"(an id in 1..{ID_MAX})")
        oz, orr, oc = oz[keep], orr[keep], oc[keep]
        if new_ids is not None and new_ids.ndim == 1:
            new_ids = new_ids[keep]
        keep = self._occ[fz, frr, fc]
        fz, frr, fc = fz[keep], frr[keep], fc[keep]
        self.last_window = None
        self.last_changed = 0
        if not len(oz) and not len(fz):
            return None
        k = _kernel()
        boxes: list[Window3] = []
        if len(fz):
            box = self._raise3(k, fz, frr, fc)
            if box is not None:
                boxes.append(box)
            if self._ids is not None:
                self._ids[fz, frr, fc] = 0
        if len(oz):
            if self._ids is not None:
                given = np.asarray(self._max_id + 1 if new_ids is None else new_ids, np.int32)
                self._ids[oz, orr, oc] = given
                self._max_id = max(self._max_id, int(given.max(initial=0)))
            box = self._lower3(k, oz, orr, oc)
            if box is not None:
                boxes.append(box)
        window = None
        for b in boxes:
            window = _union(window, b)
        self._gridmap = None
        self._dmap = None
        if self._want_label:
            if self._ids is not None:
                self._local_labels3(k, boxes, self._ids)
            else:
                self._labels_dirty = True
        self.last_window = window
        return window

    # -- windows ----------------------------------------------------------------------
    def _pad3(self, box: Window3, m: list[int]) -> Window3:
        s = self._grid.shape
        return (max(0, box[0] - m[0]), min(s[0], box[1] + m[1]), max(0, box[2] - m[2]), min(s[1], box[3] + m[3]),
                max(0, box[4] - m[4]), min(s[2], box[5] + m[5]))

    def _edt3(self, k: Any, sites: NDArray[np.uint8], w: Window3, walls: bool
              ) -> tuple[NDArray[np.int32], NDArray[np.int32], NDArray[np.int32], NDArray[np.int64]]:
        s = self._grid.shape
        shape = (w[1] - w[0], w[3] - w[2], w[5] - w[4])
        wl, wr, wc = (np.empty(shape, np.int32) for _ in range(3))
        wd2 = np.empty(shape, np.int64)
        x = walls and self._wall
        k.window_edt3(sites, *w, x and w[0] == 0, x and w[1] == s[0], x and w[2] == 0, x and w[3] == s[1],
                      x and w[4] == 0, x and w[5] == s[2], wl, wr, wc, wd2)
        return wl, wr, wc, wd2

    def _reach_window3(self, k: Any, box: Window3, margin: int) -> tuple[Window3, Any]:
        """The box around ``box`` that holds every voxel the marked voxels may reach, with the
        transform of the marked voxels on it."""
        s = self._grid.shape
        m = [margin] * 6
        flags = np.zeros(6, np.uint8)
        while True:
            w = self._pad3(box, m)
            res = self._edt3(k, self._mark, w, False)
            if w == (0, s[0], 0, s[1], 0, s[2]):
                return w, res
            k.ring_reached3(*w, *s, res[3], self._nl, self._nr, self._nc, flags)
            if not flags.any():
                return w, res
            for i in range(6):
                if flags[i]:
                    m[i] = 2 * m[i] + 2

    @staticmethod
    def _box3(z: NDArray[np.int64], r: NDArray[np.int64], c: NDArray[np.int64]) -> Window3:
        return int(z.min()), int(z.max()) + 1, int(r.min()), int(r.max()) + 1, int(c.min()), int(c.max()) + 1

    def _lower3(self, k: Any, z: NDArray[np.int64], r: NDArray[np.int64], c: NDArray[np.int64]) -> Window3 | None:
        """Insertion (the lower wave): the new voxels' window transform merged in."""
        s = self._grid.shape
        k.set_cells3(z, r, c, self._occ8, 1)
        k.set_cells3(z, r, c, self._mark, 1)
        try:
            box = self._box3(z, r, c)
            far2 = k.max_distance2_3(*self._pad3(box, [1] * 6), self._nl, self._nr, self._nc)
            margin = sum(s) if far2 >= k.NONE_D2 else 2 * math.isqrt(int(far2)) + 4
            w, (wl, wr, wc, wd2) = self._reach_window3(k, box, margin)
            out = _empty_box(s)
            n = k.lower_merge3(*w, wl, wr, wc, wd2, self._nl, self._nr, self._nc, self._dist, self._res, out)
            self.last_changed += int(n)
        finally:
            k.set_cells3(z, r, c, self._mark, 0)
        return _as_window(out) if n else None

    def _raise3(self, k: Any, z: NDArray[np.int64], r: NDArray[np.int64], c: NDArray[np.int64]) -> Window3 | None:
        """Removal (the raise wave): the orphans get the window transform of the remaining obstacles."""
        s = self._grid.shape
        k.set_cells3(z, r, c, self._occ8, 0)
        k.set_cells3(z, r, c, self._mark, 1)
        try:
            w, _ = self._reach_window3(k, self._box3(z, r, c), 8)
            ob = _empty_box(s)
            n, _ = k.orphan_box3(*w, *s, self._nl, self._nr, self._nc, self._mark, ob)
            if not n:
                return None
            self.last_changed += int(n)
            obox = _as_window(ob)
            margin = 2  # usually too small: the check then says how far the window must reach
            while True:
                w2 = self._pad3(obox, [margin] * 6)
                wl, wr, wc, wd2 = self._edt3(k, self._occ8, w2, True)
                worst = k.raise_check3(*obox, *w2, *s, self._nl, self._nr, self._nc, self._mark, wd2)
                if worst == -1:
                    break
                margin = 2 * margin + 2 if worst == -2 else max(2 * margin, int(worst) + 1)
            k.raise_apply3(*obox, w2[0], w2[2], w2[4], *s, self._nl, self._nr, self._nc, self._mark, wl, wr, wc, wd2,
                           self._dist, self._res)
        finally:
            k.set_cells3(z, r, c, self._mark, 0)
        return obox

    # -- labels -----------------------------------------------------------------------
    def _local_labels3(self, k: Any, boxes: list[Window3], ids: NDArray[np.int32]) -> None:
        assert self._label is not None
        for b in boxes:
            k.labels_window3(*b, self._nl, self._nr, self._nc, ids, BORDER_LABEL, self._label)

    def _relabel3(self) -> None:
        """Labels from the 26-connected components (numbered as ``scipy.ndimage.label``), whole grid."""
        from scipy import ndimage

        s = self._grid.shape
        comp = np.empty(s, np.int32)
        ndimage.label(self._occ, structure=np.ones((3, 3, 3), bool), output=comp)
        self._local_labels3(_kernel(), [(0, s[0], 0, s[1], 0, s[2])], comp)
        self._labels_dirty = False
