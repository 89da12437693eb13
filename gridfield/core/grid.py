"""Grid geometry and occupancy maps.

Conventions (written once, used everywhere in gridfield):

- World frame: x to the right, y up.
- Arrays are indexed ``[row, col] == [iy, ix]`` and **row 0 is the lowest y**.
- Cell ``(iy, ix)`` covers ``x in [x0 + ix*res, x0 + (ix+1)*res)`` and
  ``y in [y0 + iy*res, y0 + (iy+1)*res)``; its centre is ``origin + (ix + 0.5, iy + 0.5) * res``.
- Points cross public boundaries as world coordinates ``(x, y)`` in arrays of shape ``(N, 2)``;
  cells as integer arrays of shape ``(N, 2)`` holding ``(row, col)``.

Voxel grids (3-D) follow the same rules on one more axis: arrays are indexed ``[z, y, x] ==
[layer, row, col]``, index 0 is the lowest coordinate on every axis, cell centres are at ``origin +
(index + 0.5) * resolution``, points are ``(x, y, z)`` in arrays of shape ``(N, 3)`` and cells
``(layer, row, col)`` in ``(N, 3)``: the point's coordinates in reverse order of the array's axes.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any, Literal, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .coords import INDEX_LIMIT, as_points, cell_index, scalar_index
from .errors import ArgumentTypeError, GridfieldError, ParameterError, check_finite, check_positive, shorten
from .limits import check_cells

__all__ = ["BORDERS", "RESOLUTION_RANGE", "Grid", "GridMap", "check_resolution"]

#: The cell sizes a grid may have. Outside it the pipeline's arithmetic leaves the normal floats: a
#: subnormal size (1e-320) has an infinite reciprocal (OverflowError / ZeroDivisionError in ``plan``),
#: the potential's balanced gain divides by a length to the power 2 and more (ZeroDivisionError at 1e-200
#: and 1e150), fmm finds no path at 1e-160. Within it, a length's 4th power and its reciprocal's are
#: normal floats. The one rule for every grid (``Grid``, ``Grid.covering``: bitmaps, ROS and ``.npz``
#: files, rasterized worlds).
RESOLUTION_RANGE = (1e-75, 1e75)

BORDERS = ("open", "wall")
_DEFAULT_ORIGIN = (0.0, 0.0)  # Grid's default; a voxel grid given it (by identity) starts at (0, 0, 0)
Border = Literal["open", "wall"]


#: The dimensions a grid may have: a map (rows, cols) or a voxel grid (layers, rows, cols).
NDIMS = (2, 3)
_AXES = "xyz"


def _check_shape(shape: object) -> tuple[int, ...]:
    """``shape`` as two or three positive Python ints, or :class:`ParameterError`."""
    msg = (f"grid shape must be two positive integers (rows, cols) or three (layers, rows, cols), "
           f"got {shorten(shape)}")
    try:
        dims = tuple(cast("Iterable[object]", shape))
    except TypeError:
        raise ParameterError(msg) from None
    if len(dims) not in NDIMS:
        raise ParameterError(msg)
    out = []
    for d in dims:
        if isinstance(d, bool | np.bool_) or not isinstance(d, int | np.integer | float | np.floating):
            raise ParameterError(msg)
        if not (math.isfinite(d) and float(d).is_integer() and d > 0):
            raise ParameterError(msg)
        out.append(int(d))
    return tuple(out)


def check_resolution(value: object, name: str = "resolution") -> float:
    """A grid's cell size as a float: positive, finite and within :data:`RESOLUTION_RANGE`.

    Parameters
    ----------
    value : float
        The cell size (anything ``float()`` accepts).
    name : str
        For the message.

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        Not a number, not positive and finite, or outside :data:`RESOLUTION_RANGE`.

    Examples
    --------
    >>> check_resolution(0.05)
    0.05
    >>> check_resolution(1e-320)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: resolution must be between 1e-75 and 1e+75 (so that lengths in cells, their powers and reciprocals stay normal floats), got 1e-320
    """
    v = check_positive(name, value)  # type: ignore[arg-type]
    lo, hi = RESOLUTION_RANGE
    if not lo <= v <= hi:
        raise ParameterError(f"{name} must be between {lo:g} and {hi:g} (so that lengths in cells, their powers and "
                             f"reciprocals stay normal floats), got {shorten(value)}")
    return v


@dataclass(frozen=True)
class Grid:
    """Geometry of a 2-D grid or a 3-D voxel grid: shape, cell size, world position of the lowest
    corner, border.

    Parameters
    ----------
    shape : (int, int) or (int, int, int)
        ``(rows, cols)``; rows grow with y. A voxel grid: ``(layers, rows, cols)``, layers grow with z.
    resolution : float
        Cell edge length in world units (> 0), the same on every axis.
    origin : (float, float) or (float, float, float)
        World coordinates ``(x, y)`` (a voxel grid: ``(x, y, z)``) of the lowest corner of cell ``(0, 0)``
        (default: zeros).
    border : {"open", "wall"}
        What lies outside the grid: free space or an obstacle.

    Examples
    --------
    >>> g = Grid((2, 3), 0.5, origin=(1.0, 2.0))
    >>> g.cell_to_world([[0, 0], [1, 2]])
    array([[1.25, 2.25],
           [2.25, 2.75]])
    >>> cells, inside = g.world_to_cell([[1.3, 2.9], [9.0, 9.0]])
    >>> cells.tolist(), inside.tolist()
    ([[1, 0], [14, 16]], [True, False])

    A voxel grid: points ``(x, y, z)``, cells ``(layer, row, col)``.

    >>> v = Grid((4, 2, 3), 1.0, origin=(0.0, 0.0, 10.0))
    >>> v.ndim, v.bounds
    (3, (0.0, 0.0, 10.0, 3.0, 2.0, 14.0))
    >>> v.cell_to_world([[3, 1, 2]]).tolist(), v.cell_of(2.5, 1.5, 13.5)
    ([[2.5, 1.5, 13.5]], (3, 1, 2))
    """

    shape: tuple[int, ...]
    resolution: float
    origin: tuple[float, ...] = _DEFAULT_ORIGIN
    border: Border = "open"

    def __post_init__(self) -> None:
        shape = _check_shape(self.shape)
        object.__setattr__(self, "shape", shape)
        nd = len(shape)
        object.__setattr__(self, "resolution", check_resolution(self.resolution))
        origin: object = self.origin
        if nd == 3 and origin is _DEFAULT_ORIGIN:
            origin = (0.0, 0.0, 0.0)
        try:
            n_origin = len(tuple(cast("Iterable[object]", origin)))
        except TypeError:
            n_origin = -1
        if n_origin != nd:
            names = ", ".join(_AXES[:nd])
            raise ParameterError(f"origin must be {'two' if nd == 2 else 'three'} numbers ({names}) for a "
                                 f"{nd}-D grid, got {shorten(origin)}")
        check_finite("origin", cast("Iterable[float]", origin))
        object.__setattr__(self, "origin", tuple(float(o) for o in cast("Iterable[float]", origin)))
        if self.border not in BORDERS:
            raise ParameterError(f"border must be one of {BORDERS}, got {shorten(self.border)}")
        sizes = shape[::-1]  # along x, y (, z)
        if not all(math.isfinite(o + n * self.resolution) for o, n in zip(self.origin, sizes, strict=True)):
            raise ParameterError(
                f"a {' x '.join(map(str, shape))} grid of resolution {self.resolution:g} at origin "
                f"({', '.join(f'{o:g}' for o in self.origin)}) reaches beyond the largest floating-point number"
            )
        check_cells(shape, "grid")

    # -- derived geometry ---------------------------------------------------------------
    @property
    def ndim(self) -> int:
        """2 for a map, 3 for a voxel grid."""
        return len(self.shape)

    @property
    def rows(self) -> int:
        """Cells along y."""
        return self.shape[-2]

    @property
    def cols(self) -> int:
        """Cells along x."""
        return self.shape[-1]

    @property
    def layers(self) -> int:
        """Cells along z (1 for a 2-D grid)."""
        return self.shape[0] if len(self.shape) == 3 else 1

    @property
    def bounds(self) -> tuple[float, ...]:
        """``(xmin, ymin, xmax, ymax)`` of the area the grid covers; a voxel grid's
        ``(xmin, ymin, zmin, xmax, ymax, zmax)``."""
        lo = self.origin
        hi = tuple(o + n * self.resolution for o, n in zip(lo, self.shape[::-1], strict=True))
        return (*lo, *hi)

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` for ``imshow(..., origin="lower", extent=...)`` (of the x-y
        plane, for a voxel grid)."""
        x0, y0 = self.origin[0], self.origin[1]
        return (x0, x0 + self.cols * self.resolution, y0, y0 + self.rows * self.resolution)

    def with_border(self, border: Border) -> Grid:
        """Return the same geometry with another ``border``."""
        return Grid(self.shape, self.resolution, self.origin, border)

    @classmethod
    def covering(
        cls, bounds: tuple[float, ...], resolution: float, *, border: Border = "open"
    ) -> Grid:
        """The grid with cells of size ``resolution`` whose lowest corner is at the bounds' minimum
        and which covers ``bounds`` (the last row/column may stick out when the size is not a
        multiple of ``resolution``).

        ``bounds`` is ``[xmin, ymin, xmax, ymax]`` for a map, ``[xmin, ymin, zmin, xmax, ymax, zmax]``
        for a voxel grid.

        Examples
        --------
        >>> Grid.covering((0, 0, 25, 20), 0.5).shape
        (40, 50)
        >>> Grid.covering((0, 0, 0, 3, 2, 1), 0.5).shape
        (2, 4, 6)
        """
        res = check_resolution(resolution)
        check_finite("bounds", bounds)
        b = [float(v) for v in bounds]
        if len(b) not in (4, 6):
            raise ParameterError(f"bounds must be [xmin, ymin, xmax, ymax] (or [xmin, ymin, zmin, xmax, ymax, zmax] "
                                 f"for a voxel grid), got {list(bounds)}")
        nd = len(b) // 2
        lo, hi = b[:nd], b[nd:]
        if not all(h > v for v, h in zip(lo, hi, strict=True)):
            raise ParameterError(f"bounds must be [{', '.join(f'{a}min' for a in _AXES[:nd])}, "
                                 f"{', '.join(f'{a}max' for a in _AXES[:nd])}] with max > min, got {list(bounds)}")
        check_cells([(h - v) / res for v, h in zip(lo[::-1], hi[::-1], strict=True)],
                    f"bounds {list(bounds)} at resolution {res:g}")
        # Tolerate floating noise: 25 / 0.1 = 250.00000000000003 must give 250 columns.
        sizes = [max(1, math.ceil((h - v) / res - 1e-9)) for v, h in zip(lo, hi, strict=True)]
        return cls(tuple(sizes[::-1]), res, tuple(lo), border)

    # -- conversions --------------------------------------------------------------------
    def world_to_cell(self, points: ArrayLike) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
        """Cells ``(row, col)`` containing world points, and a mask of the points inside the grid.

        Points outside the grid get the cell index they would have on an unbounded grid
        (possibly negative or past the last row/column; clipped to +-2**62), never a wrapped
        one; use the mask. Non-finite points get ``(-1, -1)`` and ``False``. A point exactly on a
        cell boundary ``origin + i * res`` (as computed in floating point) belongs to cell ``i``.
        """
        nd = len(self.shape)
        p = as_points(points, ndim=nd)
        idx = [cell_index(p[:, a], self.origin[a], self.resolution) for a in range(nd)]  # along x, y (, z)
        finite = np.logical_and.reduce([np.isfinite(i) for i in idx])
        lim = INDEX_LIMIT
        out = [np.clip(np.where(finite, i, -1), -lim, lim).astype(np.intp) for i in idx]
        inside = finite.copy()
        for i, n in zip(out, self.shape[::-1], strict=True):
            inside &= (i >= 0) & (i < n)
        return np.stack(out[::-1], axis=1), inside

    def cell_of(self, x: float, y: float, z: float | None = None) -> tuple[int, ...] | None:
        """The cell ``(row, col)`` holding one world point, or ``None`` when it lies outside the grid
        or is not finite. The same rule as :meth:`world_to_cell`, for a single point at a fraction of
        its cost. A voxel grid takes ``z`` too and gives ``(layer, row, col)``.

        Examples
        --------
        >>> g = Grid((2, 3), 0.5, origin=(1.0, 2.0))
        >>> g.cell_of(1.3, 2.9), g.cell_of(9.0, 9.0), g.cell_of(1.0, float("nan"))
        ((1, 0), None, None)
        """
        x, y = float(x), float(y)
        if not (math.isfinite(x) and math.isfinite(y)):
            return None
        r = scalar_index(y, self.origin[1], self.resolution)
        c = scalar_index(x, self.origin[0], self.resolution)
        if len(self.shape) == 3:
            if z is None:
                raise ParameterError("a voxel grid's point needs three coordinates (x, y, z)")
            zf = float(z)
            if not math.isfinite(zf):
                return None
            k = scalar_index(zf, self.origin[2], self.resolution)
            if 0 <= k < self.shape[0] and 0 <= r < self.shape[1] and 0 <= c < self.shape[2]:
                return k, r, c
            return None
        if 0 <= r < self.shape[0] and 0 <= c < self.shape[1]:
            return r, c
        return None

    def cell_to_world(self, cells: ArrayLike) -> NDArray[np.float64]:
        """World coordinates ``(x, y)`` of the centres of cells given as ``(row, col)`` (a voxel grid:
        ``(x, y, z)`` of cells ``(layer, row, col)``)."""
        nd = len(self.shape)
        c = np.asarray(cells)
        if c.ndim == 1 and c.shape[0] == nd:
            c = c[None, :]
        if c.ndim != 2 or c.shape[1] != nd:
            what = "(row, col)" if nd == 2 else "(layer, row, col)"
            raise ParameterError(f"cells must have shape (N, {nd}) holding {what}, got shape {np.shape(cells)}")
        return np.stack([self.origin[a] + (c[:, nd - 1 - a] + 0.5) * self.resolution for a in range(nd)], axis=1)

    def contains(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether each world point lies inside the area the grid covers."""
        return self.world_to_cell(points)[1]

    def cell_centers(self) -> tuple[NDArray[np.float64], ...]:
        """1-D arrays of the x coordinates of the column centres and y of the row centres (and, for a
        voxel grid, z of the layer centres)."""
        return tuple(np.asarray(o + (np.arange(n) + 0.5) * self.resolution, dtype=np.float64)
                     for o, n in zip(self.origin, self.shape[::-1], strict=True))


@dataclass(frozen=True, eq=False)
class GridMap:
    """An occupancy grid: a boolean array (``True`` = obstacle) with its :class:`Grid`.

    Parameters
    ----------
    grid : Grid
    occupied : ndarray of bool, shape ``grid.shape``
        2-D ``[row, col]``, or 3-D ``[layer, row, col]`` for a voxel grid.
    obstacle_id : ndarray of int32, optional
        For grids rasterized from a vector world: the (1-based) id of the world obstacle that
        occupies each cell, 0 for free cells.
    world : gridfield.geometry.World, optional
        The vector world this grid was rasterized from.
    source : str
        Where the map came from (a file name), for messages and figures.
    meta : dict
        What the reader or the configuration space recorded (``meta["robot"]``: the robot applied).
    diagonals : ndarray of uint8, shape ``(rows - 1, cols - 1)``, optional
        Diagonal moves allowed **although a side cell is blocked**, set by
        :func:`gridfield.geometry.cspace.apply_robot` for a disc robot of at least half a cell that fits along
        them (a corner-only passage of the configuration space). Entry ``[r, c]`` is about the 2x2
        block of cells ``(r, c)`` to ``(r + 1, c + 1)``: bit 0 allows the move
        ``(r, c) <-> (r + 1, c + 1)``, bit 1 the move ``(r, c + 1) <-> (r + 1, c)``. None (the
        default, and every map nobody built it for): the Moving AI rule alone, a diagonal needs both
        side cells free. The grid planners' discrete moves read it (:mod:`gridfield.fields.navigation`'s
        wavefronts and descent: ``wavefront``, ``wavefront-octile``); what serves a continuous
        mover keeps the Moving AI rule (:mod:`gridfield.following.basins`, :mod:`gridfield.following.escapes`, the
        chunked wavefront, the eikonal march, the followers). It belongs to this occupancy: :meth:`with_occupied` keeps it only for the same
        array, and a map built from another occupancy (a crop, a downsampling, a bitmap or ROS file) has none.
        gridfield's own files keep it beside the occupancy (``diagonals=`` of :func:`~gridfield.io.write_npz`
        and :func:`~gridfield.io.write_store`, and :func:`~gridfield.io.save_field`; read back by
        :func:`~gridfield.io.read_npz`, :func:`~gridfield.io.read_store`, :func:`~gridfield.io.load_field`).

    Examples
    --------
    >>> import numpy as np
    >>> m = GridMap(Grid((2, 2), 1.0), np.array([[True, False], [False, False]]))
    >>> m.occupied_fraction
    0.25
    >>> m.is_free([[1.5, 0.5], [0.5, 0.5]]).tolist()
    [True, False]
    """

    grid: Grid
    occupied: NDArray[np.bool_]
    obstacle_id: NDArray[np.int32] | None = None
    world: Any = None  # a gridfield.geometry.World (the layer above: not imported here, not even for types)
    source: str = ""
    meta: dict[str, Any] = field(default_factory=dict)
    diagonals: NDArray[np.uint8] | None = None

    def __repr__(self) -> str:
        g = self.grid
        occ = float(np.count_nonzero(self.occupied)) / max(g.rows * g.cols, 1)
        src = f", source={self.source!r}" if self.source else ""
        return (f"GridMap(shape={g.shape}, resolution={g.resolution:g}, origin={g.origin}, border={g.border!r}, "
                f"occupied={occ:.1%}{src})")

    def __post_init__(self) -> None:
        if not isinstance(self.grid, Grid):
            raise ArgumentTypeError(f"grid must be a gridfield Grid, got {type(self.grid).__name__}")
        occ = self.occupied
        if not isinstance(occ, np.ndarray):
            try:
                occ = np.asarray(occ)
            except (TypeError, ValueError) as e:
                raise ArgumentTypeError(f"occupied must be an array of booleans, got {type(self.occupied).__name__} "
                                        f"({e})") from None
        if occ.dtype != np.bool_:
            if not np.issubdtype(occ.dtype, np.integer):
                raise ArgumentTypeError(
                    f"occupied must hold booleans (or the integers 0 and 1), got an array of dtype {occ.dtype}"
                )
            if occ.size and not bool(((occ == 0) | (occ == 1)).all()):
                bad = occ[(occ != 0) & (occ != 1)].flat[0]
                raise ParameterError(f"occupied must hold booleans (or the integers 0 and 1), found the value {bad}")
        if occ.shape != self.grid.shape:
            raise GridfieldError(f"occupancy array has shape {occ.shape}, but the grid has shape {self.grid.shape}")
        object.__setattr__(self, "occupied", occ.astype(bool, copy=False))
        if self.obstacle_id is not None:
            ids = np.asarray(self.obstacle_id)
            if ids.shape != self.grid.shape:
                raise GridfieldError(f"obstacle_id has shape {ids.shape}, but the grid has shape {self.grid.shape}")
            object.__setattr__(self, "obstacle_id", ids.astype(np.int32, copy=False))
        if self.diagonals is not None:
            if self.grid.ndim != 2:
                raise ParameterError("diagonals belong to 2-D maps (a disc robot's corner passages); a voxel grid has none")
            d = np.asarray(self.diagonals)
            want = (max(self.grid.rows - 1, 0), max(self.grid.cols - 1, 0))
            if d.shape != want:
                raise GridfieldError(f"diagonals has shape {d.shape}, but the grid's 2x2 blocks have shape {want}")
            if d.size and (not np.issubdtype(d.dtype, np.integer) or int(d.min()) < 0 or int(d.max()) > 3):
                raise ParameterError("diagonals must hold the bits 0 and 1 (values 0 to 3) of a uint8 array")
            object.__setattr__(self, "diagonals", np.ascontiguousarray(d, dtype=np.uint8))

    @property
    def shape(self) -> tuple[int, ...]:
        return self.grid.shape

    @property
    def ndim(self) -> int:
        """2 for a map, 3 for a voxel grid."""
        return self.grid.ndim

    @property
    def occupied_fraction(self) -> float:
        return float(self.occupied.mean())

    def is_free(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether each world point lies in a free cell. Outside the grid: free iff the border is open."""
        cells, inside = self.grid.world_to_cell(points)
        free = np.full(len(cells), self.grid.border == "open")
        free[inside] = ~self.occupied[tuple(cells[inside].T)]
        p = as_points(points, ndim=self.grid.ndim)
        free &= np.isfinite(p).all(axis=1)
        return free

    def check_point(self, name: str, point: ArrayLike) -> NDArray[np.float64]:
        """Validate a start/goal point: finite, inside the map, in a free cell. Returns it as ``(2,)``
        (a voxel grid's as ``(3,)``).

        Raises :class:`GridfieldError` naming the point and what is wrong.
        """
        nd = self.grid.ndim
        try:  # fast path: a finite point in a free cell (single queries on small maps are dominated by this)
            p = np.asarray(point, dtype=np.float64).reshape(-1)
            if p.shape == (nd,):
                cell = self.grid.cell_of(*p)
                if cell is not None and not self.occupied[cell]:
                    return p
        except (TypeError, ValueError):
            pass
        want = "two numbers X Y" if nd == 2 else "three numbers X Y Z"
        try:
            p = np.asarray(point, dtype=np.float64).reshape(-1)
        except (TypeError, ValueError):
            raise ParameterError(f"{name} must be {want}, got {shorten(point)}") from None
        if p.shape != (nd,):
            raise ParameterError(f"{name} must be {want}, got {shorten(point)}")
        check_finite(name, p)
        where = f"({', '.join(f'{v:g}' for v in p)})"
        if not self.grid.contains(p)[0]:
            b = self.grid.bounds
            spans = ", ".join(f"{a} in [{b[i]:g}, {b[i + nd]:g})" for i, a in enumerate("xyz"[:nd]))
            raise GridfieldError(f"{name} {where} lies outside the map, which covers {spans}")
        if not self.is_free(p)[0]:
            raise GridfieldError(f"{name} {where} lies inside an obstacle{self._free_hint(p)}")
        return p

    def _free_hint(self, p: NDArray[np.float64]) -> str:
        """Where a point inside an obstacle could go: the nearest free cell, and when that one lies in a
        pocket apart from the map's largest free region (8-connected), the nearest cell of that region
        too (the largest region is labelled only for maps held in memory)."""
        near = self.nearest_free(p)
        if near is None:
            return ""
        text = f"; the nearest free cell's centre is ({', '.join(f'{v:.6g}' for v in near)})"
        if not isinstance(self.occupied, np.ndarray):
            return text
        from scipy import ndimage

        labels, n = ndimage.label(~self.occupied, structure=np.ones((3,) * self.occupied.ndim, bool))
        if n < 2:
            return text
        sizes = np.bincount(labels.ravel())
        sizes[0] = 0
        big = int(np.argmax(sizes))
        cell = self.grid.cell_of(*near)
        if cell is None or labels[cell] == big:
            return text
        main = self.nearest_free(p, among=labels == big)
        if main is None:  # pragma: no cover - the largest region has cells
            return text
        k = int(sizes[labels[cell]])
        return (f"{text}, in a pocket of {k} free cell{'' if k == 1 else 's'} closed off from the rest; the "
                f"nearest cell of the map's largest free region ({int(sizes[big])} cells) is at "
                f"({', '.join(f'{v:.6g}' for v in main)})")

    def nearest_free(self, point: ArrayLike, among: NDArray[np.bool_] | None = None) -> NDArray[np.float64] | None:
        """The centre of the free cell nearest to a point (Euclidean, between cell centres; ties to the
        lowest row, then column), or ``None`` when the map has no free cell.

        Searched in windows of growing size around the point (8, 64, 512 cells, then the whole map),
        so that the answer costs what the distance to it needs. Used by :meth:`check_point` to say
        where a start or goal inside an obstacle could go instead.

        Parameters
        ----------
        point : (x, y)
            A point inside the map.
        among : ndarray of bool, optional
            The cells to choose from (of the map's shape); default every free cell.

        Returns
        -------
        ndarray of shape (2,) or None

        Examples
        --------
        >>> occ = np.zeros((3, 4), bool); occ[:, :2] = True
        >>> GridMap(Grid((3, 4), 1.0), occ).nearest_free((0.5, 1.5)).tolist()
        [2.5, 1.5]
        """
        nd = self.grid.ndim
        p = np.asarray(point, dtype=np.float64).reshape(nd)
        shape = self.shape
        h = self.grid.resolution
        # the point's cell in array order ([layer,] row, col), clamped to the grid
        centre = [min(max(int(np.floor((p[a] - self.grid.origin[a]) / h)), 0), shape[nd - 1 - a] - 1)
                  for a in range(nd)][::-1]
        for half in (8, 64, 512, max(shape)):
            lo = [max(c - half, 0) for c in centre]
            hi = [min(c + half + 1, n) for c, n in zip(centre, shape, strict=True)]
            sl = tuple(slice(a, b) for a, b in zip(lo, hi, strict=True))
            win = ~np.asarray(self.occupied[sl], dtype=bool) if among is None else among[sl]
            idx = np.nonzero(win)
            if idx[0].size == 0:
                continue
            d2: NDArray[np.intp] = np.sum([(i + a - c) ** 2 for i, a, c in zip(idx, lo, centre, strict=True)], axis=0)
            k = int(np.argmin(d2))
            # the nearest cell found lies within the window's inscribed radius, or the window is the map
            whole = all(a == 0 for a in lo) and all(b == n for b, n in zip(hi, shape, strict=True))
            if d2[k] <= half * half or whole:
                cell = [int(i[k]) + a for i, a in zip(idx, lo, strict=True)]
                return np.array([self.grid.origin[a] + (cell[nd - 1 - a] + 0.5) * h for a in range(nd)])
        return None

    def with_occupied(self, occupied: NDArray[np.bool_], **changes: object) -> GridMap:
        """A copy with another occupancy array (same grid), e.g. after inflation.

        :attr:`diagonals` belongs to the occupancy: it is kept only when ``occupied`` is this map's
        own array (the same object), and dropped otherwise unless ``diagonals=`` is given.
        """
        kw = {"grid": self.grid, "occupied": occupied, "obstacle_id": self.obstacle_id,
              "world": self.world, "source": self.source, "meta": dict(self.meta),
              "diagonals": self.diagonals if occupied is self.occupied else None}
        kw.update(changes)
        return GridMap(**kw)  # type: ignore[arg-type]
