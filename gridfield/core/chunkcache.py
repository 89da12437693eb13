"""Reading chunked (Zarr) arrays a few tiles at a time: an LRU chunk cache, lazy arrays and lazy maps.

A field stored in a Zarr store (:mod:`gridfield.io`'s ``.zarr`` reader) may be larger than memory. Its
arrays are wrapped in :class:`LazyArray`: indexing one decodes only the chunks the index touches, through
a shared :class:`ChunkCache` (an LRU of decoded chunk tiles with a byte budget), so a follower that
samples the field along a path reads only the chunks the path crosses (and the neighbours its
bilinear stencil reaches). :class:`LazyGridMap` is a :class:`~gridfield.core.grid.GridMap` whose occupancy is
a :class:`LazyArray`; the samplers of :mod:`gridfield.fields.sampling` recognise it (:func:`is_lazy`) and use
the scalar samplers here, which repeat the compiled kernels' arithmetic exactly (the same IEEE double
operations in the same order), so a path on a lazy field is the path on the same field in memory.

A leaf above ``grid``: it imports only ``errors`` and ``grid`` (and numpy), never zarr (any object with
``shape``, ``dtype``, ``chunks`` and slice indexing can be wrapped).
"""

from __future__ import annotations

import functools
import math
import threading
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .coords import as_points, scalar_index
from .errors import GridfieldError, ParameterError
from .grid import Grid, GridMap

__all__ = ["DEFAULT_BUDGET", "NONZERO", "ChunkCache", "LazyArray", "LazyGridMap", "OccupancyRule", "Raster", "is_lazy",
           "lazy_grid"]

#: The default byte budget of a :class:`ChunkCache` (256 MiB of decoded tiles).
DEFAULT_BUDGET = 256 * 2**20

Point = tuple[float, float]


class ChunkCache:
    """An LRU cache of decoded chunk tiles of 2-D arrays, bounded by a byte budget.

    Parameters
    ----------
    budget : int
        Bytes of decoded tiles kept; the least recently used tiles are dropped beyond it (the tile
        just read is always kept, even when it alone exceeds the budget).

    Attributes
    ----------
    reads : int
        Tiles decoded from their arrays so far (cache misses).
    hits : int
        Tile requests answered from the cache.
    read_keys : set
        ``(name, chunk_row, chunk_col)`` of every tile decoded (for tests and reports).

    Examples
    --------
    >>> cache = ChunkCache(budget=1000)
    >>> a = LazyArray(np.arange(100.0).reshape(10, 10), chunks=(5, 5), cache=cache, name="a")
    >>> float(a[7, 2]), float(a[6, 1]), cache.reads, cache.hits
    (72.0, 61.0, 1, 1)
    """

    def __init__(self, budget: int = DEFAULT_BUDGET) -> None:
        if not (isinstance(budget, int | np.integer) and budget > 0):
            raise ParameterError(f"the chunk cache's budget must be a positive number of bytes, got {budget!r}")
        self.budget = int(budget)
        self.nbytes = 0
        self.reads = 0
        self.hits = 0
        self.read_keys: set[tuple[str, int, int]] = set()
        self._tiles: OrderedDict[tuple[int, int, int], NDArray[Any]] = OrderedDict()
        self._lock = threading.Lock()

    def tile(self, array: LazyArray, ci: int, cj: int) -> NDArray[Any]:
        """The decoded chunk ``(ci, cj)`` (chunk row, chunk column) of ``array``."""
        key = (id(array), ci, cj)
        with self._lock:
            t = self._tiles.get(key)
            if t is not None:
                self._tiles.move_to_end(key)
                self.hits += 1
                return t
        t = array._decode(ci, cj)
        with self._lock:
            self.reads += 1
            self.read_keys.add((array.name, ci, cj))
            self._tiles[key] = t
            self.nbytes += t.nbytes
            while self.nbytes > self.budget and len(self._tiles) > 1:
                _, old = self._tiles.popitem(last=False)
                self.nbytes -= old.nbytes
        return t

    def clear(self) -> None:
        """Drop every tile (the counters stay)."""
        with self._lock:
            self._tiles.clear()
            self.nbytes = 0


class LazyArray:
    """A read-only 2-D array read chunk by chunk through a :class:`ChunkCache`.

    Integer and slice indexing (``a[i, j]``, ``a[r0:r1, c0:c1]``) and :meth:`take` (values at many
    cells) decode only the chunks they touch. ``np.asarray(a)`` reads it whole (what a figure
    needs); ``~a`` of a boolean array is its lazy negation, and ``np.count_nonzero`` of either uses the
    count stored with the array when there is one (else it counts chunk by chunk, bypassing the cache).

    Parameters
    ----------
    source : array-like
        A zarr array (or anything with ``shape``, ``dtype`` and slice indexing).
    chunks : (int, int), optional
        Tile shape; default ``source.chunks``.
    cache : ChunkCache, optional
        Shared tile cache (a new one with :data:`DEFAULT_BUDGET` when omitted).
    name : str
        For the cache's ``read_keys``.
    nonzero : int, optional
        The number of non-zero elements, when known (the store keeps it for ``occupied``).

    Examples
    --------
    >>> a = LazyArray(np.eye(4, dtype=bool), chunks=(2, 2), name="occ", nonzero=4)
    >>> a.shape, bool(a[1, 1]), np.count_nonzero(~a), a[0:3, 1:3].tolist()
    ((4, 4), True, 12, [[False, False], [True, False], [False, True]])
    """

    def __init__(self, source: Any, *, chunks: tuple[int, int] | None = None, cache: ChunkCache | None = None,
                 name: str = "", nonzero: int | None = None, _invert: bool = False) -> None:
        shape = tuple(int(n) for n in source.shape)
        if len(shape) != 2:
            raise GridfieldError(f"a lazy array {name!r} must be 2-D, got shape {shape}")
        ch = chunks if chunks is not None else getattr(source, "chunks", None)
        if ch is None or len(ch) != 2:
            ch = shape
        self._source = source
        self.shape: tuple[int, int] = (shape[0], shape[1])
        self.chunks: tuple[int, int] = (max(1, int(ch[0])), max(1, int(ch[1])))
        self.dtype = np.dtype(source.dtype)
        self.cache = cache if cache is not None else ChunkCache()
        self.name = name
        self._nonzero = nonzero
        self._invert = _invert
        if _invert and self.dtype != np.bool_:
            raise GridfieldError(f"~ of a lazy array applies to booleans, not {self.dtype}")

    ndim = 2

    @property
    def size(self) -> int:
        return self.shape[0] * self.shape[1]

    def __len__(self) -> int:
        return self.shape[0]

    def __repr__(self) -> str:
        return f"LazyArray({self.name!r}, shape={self.shape}, dtype={self.dtype}, chunks={self.chunks})"

    # -- tiles ------------------------------------------------------------------------------
    def _decode(self, ci: int, cj: int) -> NDArray[Any]:
        r, c = self.chunks
        t = np.ascontiguousarray(self._source[ci * r:(ci + 1) * r, cj * c:(cj + 1) * c])
        t.setflags(write=False)
        return t

    def tile(self, ci: int, cj: int) -> NDArray[Any]:
        """The decoded chunk ``(ci, cj)``, as stored (before a negation)."""
        return self.cache.tile(self._base(), ci, cj)

    def _base(self) -> LazyArray:
        return self._negated if self._invert else self  # the tiles are cached under the stored array

    # -- indexing ---------------------------------------------------------------------------
    def __getitem__(self, key: Any) -> Any:
        if not isinstance(key, tuple):
            key = (key, slice(None))
        if len(key) != 2:
            raise IndexError(f"a lazy array takes two indices, got {len(key)}")
        if all(isinstance(k, int | np.integer) for k in key):
            i, j = (int(k) + (n if int(k) < 0 else 0) for k, n in zip(key, self.shape, strict=True))
            if not (0 <= i < self.shape[0] and 0 <= j < self.shape[1]):
                raise IndexError(f"index {key} is out of bounds for shape {self.shape}")
            r, c = self.chunks
            v = self.tile(i // r, j // c)[i % r, j % c]
            return ~v if self._invert else v
        if all(isinstance(k, slice | int | np.integer) for k in key):
            sl = [k if isinstance(k, slice) else slice(int(k), int(k) + 1) for k in key]
            (r0, r1, rs), (c0, c1, cs) = (s.indices(n) for s, n in zip(sl, self.shape, strict=True))
            if rs != 1 or cs != 1:
                raise IndexError("a lazy array takes slices with step 1 only")
            out = self.window(r0, max(r0, r1), c0, max(c0, c1))
            if isinstance(key[0], int | np.integer):
                out = out[0]
            elif isinstance(key[1], int | np.integer):
                out = out[:, 0]
            return out
        raise IndexError("a lazy array takes integers and slices; use take(rows, cols) for many cells")

    def window(self, r0: int, r1: int, c0: int, c1: int) -> NDArray[Any]:
        """``a[r0:r1, c0:c1]`` as a numpy array, assembled from the tiles it touches."""
        out = np.empty((r1 - r0, c1 - c0), self.dtype)
        R, C = self.chunks
        for ci in range(r0 // R, (r1 - 1) // R + 1 if r1 > r0 else r0 // R):
            for cj in range(c0 // C, (c1 - 1) // C + 1 if c1 > c0 else c0 // C):
                t = self.tile(ci, cj)
                a0, a1 = max(r0, ci * R), min(r1, (ci + 1) * R)
                b0, b1 = max(c0, cj * C), min(c1, (cj + 1) * C)
                out[a0 - r0:a1 - r0, b0 - c0:b1 - c0] = t[a0 - ci * R:a1 - ci * R, b0 - cj * C:b1 - cj * C]
        return ~out if self._invert else out

    def take(self, rows: Any, cols: Any) -> NDArray[Any]:
        """The values at the cells ``(rows[k], cols[k])`` (in bounds), decoding each chunk touched once."""
        rr = np.asarray(rows, dtype=np.int64).ravel()
        cc = np.asarray(cols, dtype=np.int64).ravel()
        if rr.size and (rr.min() < 0 or cc.min() < 0 or rr.max() >= self.shape[0] or cc.max() >= self.shape[1]):
            raise IndexError(f"cells out of bounds for shape {self.shape}")
        out = np.empty(rr.size, self.dtype)
        R, C = self.chunks
        key = (rr // R) * ((self.shape[1] + C - 1) // C) + cc // C
        order = np.argsort(key, kind="stable")
        ks = key[order]
        starts = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]]) if ks.size else np.array([], np.int64)
        ends = np.r_[starts[1:], ks.size]
        for s, e in zip(starts, ends, strict=True):
            idx = order[s:e]
            ci, cj = int(rr[idx[0]] // R), int(cc[idx[0]] // C)
            out[idx] = self.tile(ci, cj)[rr[idx] - ci * R, cc[idx] - cj * C]
        return ~out if self._invert else out

    # -- numpy protocol ---------------------------------------------------------------------
    def __array__(self, dtype: Any = None, copy: Any = None) -> NDArray[Any]:
        a = np.asarray(self._source[...])
        if self._invert:
            a = ~a
        return a if dtype is None else a.astype(dtype)

    def __invert__(self) -> LazyArray:
        if self._invert:
            return self._negated
        neg = LazyArray(self._source, chunks=self.chunks, cache=self.cache, name=self.name,
                        nonzero=None if self._nonzero is None else self.size - self._nonzero, _invert=True)
        neg._negated = self
        return neg

    def count_nonzero(self) -> int:
        """Non-zero elements: the stored count, else counted chunk by chunk (no tile stays cached)."""
        if self._nonzero is None:
            R, C = self.chunks
            n = 0
            for r0 in range(0, self.shape[0], R):
                for c0 in range(0, self.shape[1], C):
                    n += int(np.count_nonzero(np.asarray(self._source[r0:r0 + R, c0:c0 + C])))
            self._nonzero = self.size - n if self._invert else n
        return self._nonzero

    def __array_function__(self, func: Any, types: Any, args: Any, kwargs: Any) -> Any:
        if func is np.count_nonzero and len(args) == 1 and not kwargs:
            return self.count_nonzero()
        if func is np.shape:
            return self.shape
        return func(*(np.asarray(a) if isinstance(a, LazyArray) else a for a in args), **kwargs)

    _negated: LazyArray


def is_lazy(a: Any) -> bool:
    """Whether ``a`` is a :class:`LazyArray` (or a :class:`LazyGridMap`, or a field on one)."""
    if isinstance(a, LazyArray | LazyGridMap):
        return True
    m = getattr(a, "map", None)
    return isinstance(m, LazyGridMap)


@dataclass(frozen=True, eq=False)
class LazyGridMap(GridMap):
    """A :class:`~gridfield.core.grid.GridMap` whose ``occupied`` is a :class:`LazyArray` (a map read from a
    Zarr store, a BigTIFF or a ``.npy`` memory map): nothing is read whole.

    What a follower asks of a map works chunk by chunk (:meth:`is_free`, :meth:`check_point`, the
    samplers of :mod:`gridfield.fields.sampling`); whole-map algorithms (the in-memory brushfire, the
    planners) want ``np.asarray(m.occupied)``, i.e. :meth:`to_gridmap`.

    Examples
    --------
    >>> occ = LazyArray(np.eye(3, dtype=bool), chunks=(2, 2), name="occupied")
    >>> m = LazyGridMap(Grid((3, 3), 1.0), occ)
    >>> m.is_free([[0.5, 0.5], [1.5, 0.5]]).tolist(), m.to_gridmap().occupied_fraction
    ([False, True], 0.3333333333333333)
    """

    occupied: Any = None  # a LazyArray
    meta: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.grid, Grid):
            raise GridfieldError(f"grid must be a gridfield Grid, got {type(self.grid).__name__}")
        if not isinstance(self.occupied, LazyArray):
            raise GridfieldError(f"a LazyGridMap's occupancy must be a LazyArray, got {type(self.occupied).__name__}")
        if self.occupied.shape != self.grid.shape:
            raise GridfieldError(f"occupancy array has shape {self.occupied.shape}, but the grid has shape "
                                 f"{self.grid.shape}")
        if self.occupied.dtype != np.bool_:
            raise GridfieldError(f"occupied must hold booleans, got dtype {self.occupied.dtype}")

    def __repr__(self) -> str:
        g = self.grid
        src = f", source={self.source!r}" if self.source else ""
        return (f"LazyGridMap(shape={g.shape}, resolution={g.resolution:g}, origin={g.origin}, border={g.border!r}, "
                f"chunks={self.occupied.chunks}{src})")

    @property
    def occupied_fraction(self) -> float:
        occupied: LazyArray = self.occupied
        return occupied.count_nonzero() / max(occupied.size, 1)

    def is_free(self, points: Any) -> NDArray[np.bool_]:
        """Whether each world point lies in a free cell (outside the grid: free iff the border is open)."""
        cells, inside = self.grid.world_to_cell(points)
        free = np.full(len(cells), self.grid.border == "open")
        if inside.any():
            free[inside] = ~self.occupied.take(cells[inside, 0], cells[inside, 1])
        free &= np.isfinite(as_points(points)).all(axis=1)
        return free

    def to_gridmap(self) -> GridMap:
        """The same map in memory (reads the occupancy whole, within the size guard)."""
        from .limits import check_cells

        check_cells(self.grid.shape, f"{self.source or 'a map read by chunks'} (read whole into memory; "
                                     "--out F.zarr computes chunk by chunk)")
        return GridMap(self.grid, np.asarray(self.occupied), source=self.source, meta=dict(self.meta),
                       diagonals=self.diagonals)

    def with_occupied(self, occupied: Any, **changes: object) -> GridMap:
        return self.to_gridmap().with_occupied(occupied, **changes)


# ---------------------------------------------------------------------------------------------
# scalar samplers: the compiled kernels' arithmetic (gridfield/fields/_samplers.pyx), on tiles
# ---------------------------------------------------------------------------------------------
class _Corners:
    """Reads values of up to three lazy arrays at a cell, remembering the last tiles used."""

    def __init__(self, *arrays: LazyArray) -> None:
        self.arrays = arrays
        self.R, self.C = arrays[0].chunks
        self.key: tuple[int, int] = (-1, -1)
        self.tiles: tuple[NDArray[Any], ...] = ()
        self.inv = tuple(a._invert for a in arrays)

    def at(self, j: int, i: int) -> tuple[Any, ...]:
        ci, cj = j // self.R, i // self.C
        if (ci, cj) != self.key:
            self.tiles = tuple(a.tile(ci, cj) for a in self.arrays)
            self.key = (ci, cj)
        jj, ii = j - ci * self.R, i - cj * self.C
        return tuple((not t[jj, ii]) if inv else t[jj, ii] for t, inv in zip(self.tiles, self.inv, strict=True))


def _same_chunks(*arrays: LazyArray) -> None:
    ch = {a.chunks for a in arrays}
    if len(ch) != 1:
        raise GridfieldError(f"the arrays of a lazy field must share one chunk shape, got {sorted(ch)}")


def bilinear2(a: LazyArray, b: LazyArray, occ: LazyArray, x0: float, y0: float,
              res: float) -> Callable[[float, float], tuple[float, float]]:
    """``f(x, y) -> (a, b)``: bilinear interpolation among the free corner cells (renormalized), clamped
    to the grid; the nearest free corner when every weighted corner is occupied; else 0. The rule and
    the arithmetic of the compiled samplers (``fields._samplers.ValueSampler``)."""
    _same_chunks(a, b, occ)
    rows, cols = occ.shape
    rd = _Corners(a, b, occ)

    def f(x: float, y: float) -> tuple[float, float]:
        u = (x - x0) / res - 0.5
        v = (y - y0) / res - 0.5
        if not (u >= 0.0):
            u = 0.0
        if u > cols - 1.0:
            u = cols - 1.0
        if not (v >= 0.0):
            v = 0.0
        if v > rows - 1.0:
            v = rows - 1.0
        i0, j0 = int(u), int(v)
        i1, j1 = min(i0 + 1, cols - 1), min(j0 + 1, rows - 1)
        fu, fv = u - i0, v - j0
        corners = ((j0, i0, (1.0 - fu) * (1.0 - fv)), (j0, i1, fu * (1.0 - fv)),
                   (j1, i0, (1.0 - fu) * fv), (j1, i1, fu * fv))
        sa = sb = sw = 0.0
        vals = []
        for jj, ii, w in corners:
            va, vb, o = rd.at(jj, ii)
            vals.append((jj, ii, va, vb, o))
            if w > 0.0 and not o:
                sa += w * float(va)
                sb += w * float(vb)
                sw += w
        if sw > 0.0:
            return sa / sw, sb / sw
        best, ra, rb = 4.0, 0.0, 0.0
        for jj, ii, va, vb, o in vals:
            if not o:
                dd = (ii - u) * (ii - u) + (jj - v) * (jj - v)
                if dd < best:
                    best, ra, rb = dd, float(va), float(vb)
        return ra, rb

    return f


def nearest2(a: LazyArray, b: LazyArray, occ: LazyArray, x0: float, y0: float,
             res: float) -> Callable[[float, float], tuple[float, float]]:
    """``f(x, y) -> (a, b)`` at the cell containing the point (clamped); 0 in obstacle cells or for a
    point that is not finite (the compiled ``fields._samplers.ValueSampler``)."""
    _same_chunks(a, b, occ)
    rows, cols = occ.shape
    rd = _Corners(a, b, occ)

    def f(x: float, y: float) -> tuple[float, float]:
        if not (math.isfinite(x) and math.isfinite(y)):
            return 0.0, 0.0
        i = min(max(scalar_index(x, x0, res), 0), cols - 1)
        j = min(max(scalar_index(y, y0, res), 0), rows - 1)
        va, vb, o = rd.at(j, i)
        return (0.0, 0.0) if o else (float(va), float(vb))

    return f


def segment_blocked(occ: LazyArray, x0: float, y0: float, res: float, wall: bool,
                    kernel: Callable[..., bool]) -> Callable[[Point, Point], bool]:
    """``blocked(p, q)`` on a lazy occupancy: the compiled segment walk ``kernel`` run on the window of
    cells around the segment (one cell of margin), with the window's origin.

    The window's origin ``x0 + c0 * res`` is rounded once, so a segment that touches a cell boundary
    to within a rounding error may be judged differently than on the whole array (exactly the same
    when ``res`` and ``origin`` are multiples of a power of two, e.g. 0.5 or 1.0 at origin 0).
    """
    rows, cols = occ.shape

    def blocked(p: Point, q: Point) -> bool:
        xa, ya, xb, yb = float(p[0]), float(p[1]), float(q[0]), float(q[1])
        if not (math.isfinite(xa) and math.isfinite(ya) and math.isfinite(xb) and math.isfinite(yb)):
            return bool(kernel(np.zeros((1, 1), np.bool_), x0, y0, res, wall, xa, ya, xb, yb))
        ia, ib = scalar_index(xa, x0, res), scalar_index(xb, x0, res)
        ja, jb = scalar_index(ya, y0, res), scalar_index(yb, y0, res)
        c0 = min(max(min(ia, ib) - 1, 0), cols - 1)
        c1 = min(max(max(ia, ib) + 2, c0 + 1), cols)
        r0 = min(max(min(ja, jb) - 1, 0), rows - 1)
        r1 = min(max(max(ja, jb) + 2, r0 + 1), rows)
        w = np.ascontiguousarray(occ.window(r0, r1, c0, c1))
        # the window's outside: the grid's border where the window reaches it, else the cells beyond are
        # never visited (the segment lies inside the window with a margin of one cell)
        return bool(kernel(w, x0 + c0 * res, y0 + r0 * res, res, wall, xa, ya, xb, yb))

    return blocked


def cell_values(a: LazyArray | None, grid: Grid,
                points: NDArray[np.float64]) -> tuple[NDArray[Any], NDArray[np.bool_]]:
    """``a`` at the cells containing the points (clamped to the grid), and whether each is inside (the
    compiled ``_cell_values``); NaN everywhere when ``a`` is None (a stored field without distances)."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    cells, inside = grid.world_to_cell(pts)
    if a is None:
        return np.full(len(pts), np.nan), inside
    r = np.clip(cells[:, 0], 0, grid.rows - 1)
    c = np.clip(cells[:, 1], 0, grid.cols - 1)
    return a.take(r, c).astype(np.float64), inside


# ---------------------------------------------------------------------------------------------
# big rasters as occupancy: what the BigTIFF, .npy and Zarr-array readers wrap
# ---------------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=16)
def _grey_cut(white: float, light: bool, threshold: float, levels: int) -> int:
    """How many of the levels ``0 .. levels - 1`` are occupied under the grey rule (:class:`OccupancyRule`):
    the darkest ones (``light``: the lightest ones), since the occupancy is monotonic in the level."""
    v = np.arange(levels, dtype=np.float64)
    occupancy = v / white if light else (white - v) / white
    return int(np.count_nonzero(occupancy > threshold))


@dataclass(frozen=True)
class OccupancyRule:
    """How a raster's values become occupancy (``True`` = obstacle), applied to each slice read.

    With ``white`` None: booleans as they are, numbers non-zero = obstacle (labels, masks). Otherwise the
    grey rule of the image readers: a value ``v`` in ``0 .. white`` has occupancy ``(white - v) / white``
    (dark = occupied), or ``v / white`` when ``light`` (``negate``, or a min-is-white image), and is an
    obstacle when that exceeds ``threshold``. Integers of up to 16 bits are compared with the level
    where that changes, found once with the same arithmetic (no float copy of the slice). ``text`` says the rule in words (the readers' ``meta``).

    Parameters
    ----------
    white : float, optional
        The white level (255 for 8 bits, 65535 for 16, 1 for a 1-bit image); None: non-zero = obstacle.
    threshold : float
        Occupancy above which a value is an obstacle (the grey rule only).
    light : bool
        Occupancy ``v / white`` instead of ``(white - v) / white``.
    text : str
        The rule in words.

    Examples
    --------
    >>> grey = OccupancyRule(255.0, text="dark = occupied")
    >>> grey(np.array([0, 127, 128, 255], np.uint8)).tolist()
    [True, True, False, False]
    >>> OccupancyRule()(np.array([0, 3, -1])).tolist()
    [False, True, True]
    """

    white: float | None = None
    threshold: float = 0.5
    light: bool = False
    text: str = "non-zero = obstacle"

    def __call__(self, a: NDArray[Any]) -> NDArray[np.bool_]:
        if self.white is None:
            return a if a.dtype == np.bool_ else a != 0
        if a.dtype == np.bool_ or (a.dtype.kind == "u" and a.dtype.itemsize <= 2):
            levels = 2 if a.dtype == np.bool_ else 1 << (8 * a.dtype.itemsize)
            n = _grey_cut(float(self.white), self.light, float(self.threshold), levels)
            out: NDArray[np.bool_] = a >= levels - n if self.light else a < n  # one comparison, no float copy
            return out
        v = a.astype(np.float64)
        occupancy = v / self.white if self.light else (self.white - v) / self.white
        occupied: NDArray[np.bool_] = occupancy > self.threshold
        return occupied


#: :class:`Raster`'s rule when none is given: booleans as they are, numbers non-zero = obstacle.
NONZERO = OccupancyRule()


class Raster:
    """A 2-D array seen as occupancy (``True`` = obstacle, by ``rule``: default :data:`NONZERO`, booleans
    as they are and numbers non-zero), read by slices; with ``flip`` its first row is the top of the map
    (an image), so gridfield's row ``r`` is the source's row ``rows - 1 - r``.

    Examples
    --------
    >>> r = Raster(np.array([[0, 7], [0, 0]]), flip=True, chunks=(1, 2))
    >>> r[0:2, 0:2].tolist(), r.chunks
    ([[False, False], [False, True]], (1, 2))
    >>> img = np.array([[0, 255], [255, 200]], np.uint8)   # an image: black top-left
    >>> Raster(img, flip=True, rule=OccupancyRule(255.0))[...].tolist()
    [[False, False], [True, False]]
    """

    def __init__(self, source: Any, *, flip: bool = False, chunks: tuple[int, int] | None = None,
                 rule: OccupancyRule = NONZERO) -> None:
        self._source = source
        self.shape = (int(source.shape[0]), int(source.shape[1]))
        self.dtype = np.dtype(np.bool_)
        self.flip = flip
        self.rule = rule
        ch = chunks if chunks is not None else getattr(source, "chunks", None) or self.shape
        self.chunks = (max(1, min(int(ch[0]), self.shape[0])), max(1, min(int(ch[1]), self.shape[1])))

    def __getitem__(self, key: Any) -> NDArray[np.bool_]:
        if key is Ellipsis:
            key = (slice(None), slice(None))
        rs, cs = key
        r0, r1, _ = rs.indices(self.shape[0])
        if self.flip:
            n = self.shape[0]
            a = np.asarray(self._source[n - r1:n - r0, cs])[::-1]
        else:
            a = np.asarray(self._source[r0:r1, cs])
        return self.rule(a)


def lazy_grid(shape: tuple[int, int], resolution: float, origin: tuple[float, float] = (0.0, 0.0),
              border: str = "open") -> Grid:
    """A :class:`~gridfield.core.grid.Grid` for a map read by chunks: the in-memory size guard
    (:func:`gridfield.core.limits.check_cells`) does not apply, since nothing is allocated whole.

    Examples
    --------
    >>> from gridfield.core.limits import override
    >>> with override(100):
    ...     lazy_grid((1000, 1000), 1.0).shape
    (1000, 1000)
    """
    from .limits import override

    with override(max(int(shape[0]) * int(shape[1]), 1)):
        return Grid(shape, resolution, origin, border)  # type: ignore[arg-type]
