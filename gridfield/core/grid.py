"""Grid geometry and occupancy maps.

Conventions (written once, used everywhere in gridfield):

- World frame: x to the right, y up.
- Arrays are indexed ``[row, col] == [iy, ix]`` and **row 0 is the lowest y**.
- Cell ``(iy, ix)`` covers ``x in [x0 + ix*res, x0 + (ix+1)*res)`` and
  ``y in [y0 + iy*res, y0 + (iy+1)*res)``; its centre is ``origin + (ix + 0.5, iy + 0.5) * res``.
- Points cross public boundaries as world coordinates ``(x, y)`` in arrays of shape ``(N, 2)``;
  cells as integer arrays of shape ``(N, 2)`` holding ``(row, col)``.
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
Border = Literal["open", "wall"]


def _check_shape(shape: object) -> tuple[int, int]:
    """``shape`` as two positive Python ints, or :class:`ParameterError`."""
    msg = f"grid shape must be two positive integers (rows, cols), got {shorten(shape)}"
    try:
        dims = tuple(cast("Iterable[object]", shape))
    except TypeError:
        raise ParameterError(msg) from None
    if len(dims) != 2:
        raise ParameterError(msg)
    out = []
    for d in dims:
        if isinstance(d, bool | np.bool_) or not isinstance(d, int | np.integer | float | np.floating):
            raise ParameterError(msg)
        if not (math.isfinite(d) and float(d).is_integer() and d > 0):
            raise ParameterError(msg)
        out.append(int(d))
    return out[0], out[1]


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
    """Geometry of a 2-D grid: shape, cell size, world position of the lower-left corner, border.

    Parameters
    ----------
    shape : (int, int)
        ``(rows, cols)``; rows grow with y.
    resolution : float
        Cell edge length in world units (> 0).
    origin : (float, float)
        World coordinates of the lower-left corner of cell ``(0, 0)``.
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
    """

    shape: tuple[int, int]
    resolution: float
    origin: tuple[float, float] = (0.0, 0.0)
    border: Border = "open"

    def __post_init__(self) -> None:
        object.__setattr__(self, "shape", _check_shape(self.shape))
        object.__setattr__(self, "resolution", check_resolution(self.resolution))
        try:
            n_origin = len(tuple(self.origin))
        except TypeError:
            n_origin = -1
        if n_origin != 2:
            raise ParameterError(f"origin must be two numbers (x, y), got {shorten(self.origin)}")
        check_finite("origin", self.origin)
        object.__setattr__(self, "origin", (float(self.origin[0]), float(self.origin[1])))
        if self.border not in BORDERS:
            raise ParameterError(f"border must be one of {BORDERS}, got {shorten(self.border)}")
        if not (math.isfinite(self.origin[0] + self.shape[1] * self.resolution)
                and math.isfinite(self.origin[1] + self.shape[0] * self.resolution)):
            raise ParameterError(
                f"a {self.shape[0]} x {self.shape[1]} grid of resolution {self.resolution:g} at origin "
                f"({self.origin[0]:g}, {self.origin[1]:g}) reaches beyond the largest floating-point number"
            )
        check_cells(self.shape, "grid")

    # -- derived geometry ---------------------------------------------------------------
    @property
    def rows(self) -> int:
        return self.shape[0]

    @property
    def cols(self) -> int:
        return self.shape[1]

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, ymin, xmax, ymax)`` of the area the grid covers."""
        x0, y0 = self.origin
        return (x0, y0, x0 + self.cols * self.resolution, y0 + self.rows * self.resolution)

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` for ``imshow(..., origin="lower", extent=...)``."""
        xmin, ymin, xmax, ymax = self.bounds
        return (xmin, xmax, ymin, ymax)

    def with_border(self, border: Border) -> Grid:
        """Return the same geometry with another ``border``."""
        return Grid(self.shape, self.resolution, self.origin, border)

    @classmethod
    def covering(
        cls, bounds: tuple[float, float, float, float], resolution: float, *, border: Border = "open"
    ) -> Grid:
        """The grid with cells of size ``resolution`` whose lower-left corner is at ``bounds[:2]``
        and which covers ``bounds`` (the last row/column may stick out when the size is not a
        multiple of ``resolution``).

        Examples
        --------
        >>> Grid.covering((0, 0, 25, 20), 0.5).shape
        (40, 50)
        """
        res = check_resolution(resolution)
        check_finite("bounds", bounds)
        if len(tuple(bounds)) != 4:
            raise ParameterError(f"bounds must be [xmin, ymin, xmax, ymax], got {list(bounds)}")
        xmin, ymin, xmax, ymax = (float(b) for b in bounds)
        if not (xmax > xmin and ymax > ymin):
            raise ParameterError(f"bounds must be [xmin, ymin, xmax, ymax] with max > min, got {list(bounds)}")
        check_cells(((ymax - ymin) / res, (xmax - xmin) / res), f"bounds {list(bounds)} at resolution {res:g}")
        # Tolerate floating noise: 25 / 0.1 = 250.00000000000003 must give 250 columns.
        cols = max(1, math.ceil((xmax - xmin) / res - 1e-9))
        rows = max(1, math.ceil((ymax - ymin) / res - 1e-9))
        return cls((rows, cols), res, (xmin, ymin), border)

    # -- conversions --------------------------------------------------------------------
    def world_to_cell(self, points: ArrayLike) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
        """Cells ``(row, col)`` containing world points, and a mask of the points inside the grid.

        Points outside the grid get the cell index they would have on an unbounded grid
        (possibly negative or past the last row/column; clipped to +-2**62), never a wrapped
        one; use the mask. Non-finite points get ``(-1, -1)`` and ``False``. A point exactly on a
        cell boundary ``origin + i * res`` (as computed in floating point) belongs to cell ``i``.
        """
        p = as_points(points)
        x0, y0 = self.origin
        col = cell_index(p[:, 0], x0, self.resolution)
        row = cell_index(p[:, 1], y0, self.resolution)
        finite = np.isfinite(col) & np.isfinite(row)
        lim = INDEX_LIMIT
        col = np.clip(np.where(finite, col, -1), -lim, lim).astype(np.intp)
        row = np.clip(np.where(finite, row, -1), -lim, lim).astype(np.intp)
        inside = finite & (row >= 0) & (row < self.rows) & (col >= 0) & (col < self.cols)
        return np.stack([row, col], axis=1), inside

    def cell_of(self, x: float, y: float) -> tuple[int, int] | None:
        """The cell ``(row, col)`` holding one world point, or ``None`` when it lies outside the grid
        or is not finite. The same rule as :meth:`world_to_cell`, for a single point at a fraction of
        its cost.

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
        if 0 <= r < self.shape[0] and 0 <= c < self.shape[1]:
            return r, c
        return None

    def cell_to_world(self, cells: ArrayLike) -> NDArray[np.float64]:
        """World coordinates ``(x, y)`` of the centres of cells given as ``(row, col)``."""
        c = np.asarray(cells)
        if c.ndim == 1 and c.shape[0] == 2:
            c = c[None, :]
        if c.ndim != 2 or c.shape[1] != 2:
            raise ParameterError(f"cells must have shape (N, 2) holding (row, col), got shape {np.shape(cells)}")
        x0, y0 = self.origin
        x = x0 + (c[:, 1] + 0.5) * self.resolution
        y = y0 + (c[:, 0] + 0.5) * self.resolution
        return np.stack([x, y], axis=1)

    def contains(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether each world point lies inside the area the grid covers."""
        return self.world_to_cell(points)[1]

    def cell_centers(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """1-D arrays of the x coordinates of the column centres and y of the row centres."""
        x0, y0 = self.origin
        xs = x0 + (np.arange(self.cols) + 0.5) * self.resolution
        ys = y0 + (np.arange(self.rows) + 0.5) * self.resolution
        return np.asarray(xs, dtype=np.float64), np.asarray(ys, dtype=np.float64)


@dataclass(frozen=True, eq=False)
class GridMap:
    """An occupancy grid: a boolean array (``True`` = obstacle) with its :class:`Grid`.

    Parameters
    ----------
    grid : Grid
    occupied : ndarray of bool, shape ``grid.shape``
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
            d = np.asarray(self.diagonals)
            want = (max(self.grid.rows - 1, 0), max(self.grid.cols - 1, 0))
            if d.shape != want:
                raise GridfieldError(f"diagonals has shape {d.shape}, but the grid's 2x2 blocks have shape {want}")
            if d.size and (not np.issubdtype(d.dtype, np.integer) or int(d.min()) < 0 or int(d.max()) > 3):
                raise ParameterError("diagonals must hold the bits 0 and 1 (values 0 to 3) of a uint8 array")
            object.__setattr__(self, "diagonals", np.ascontiguousarray(d, dtype=np.uint8))

    @property
    def shape(self) -> tuple[int, int]:
        return self.grid.shape

    @property
    def occupied_fraction(self) -> float:
        return float(self.occupied.mean())

    def is_free(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether each world point lies in a free cell. Outside the grid: free iff the border is open."""
        cells, inside = self.grid.world_to_cell(points)
        free = np.full(len(cells), self.grid.border == "open")
        r, c = cells[inside].T
        free[inside] = ~self.occupied[r, c]
        p = as_points(points)
        free &= np.isfinite(p).all(axis=1)
        return free

    def check_point(self, name: str, point: ArrayLike) -> NDArray[np.float64]:
        """Validate a start/goal point: finite, inside the map, in a free cell. Returns it as ``(2,)``.

        Raises :class:`GridfieldError` naming the point and what is wrong.
        """
        try:  # fast path: a finite point in a free cell (single queries on small maps are dominated by this)
            p = np.asarray(point, dtype=np.float64).reshape(-1)
            if p.shape == (2,):
                cell = self.grid.cell_of(p[0], p[1])
                if cell is not None and not self.occupied[cell]:
                    return p
        except (TypeError, ValueError):
            pass
        try:
            p = np.asarray(point, dtype=np.float64).reshape(-1)
        except (TypeError, ValueError):
            raise ParameterError(f"{name} must be two numbers X Y, got {shorten(point)}") from None
        if p.shape != (2,):
            raise ParameterError(f"{name} must be two numbers X Y, got {shorten(point)}")
        check_finite(name, p)
        if not self.grid.contains(p)[0]:
            xmin, ymin, xmax, ymax = self.grid.bounds
            raise GridfieldError(
                f"{name} ({p[0]:g}, {p[1]:g}) lies outside the map, which covers "
                f"x in [{xmin:g}, {xmax:g}), y in [{ymin:g}, {ymax:g})"
            )
        if not self.is_free(p)[0]:
            raise GridfieldError(f"{name} ({p[0]:g}, {p[1]:g}) lies inside an obstacle{self._free_hint(p)}")
        return p

    def _free_hint(self, p: NDArray[np.float64]) -> str:
        """Where a point inside an obstacle could go: the nearest free cell, and when that one lies in a
        pocket apart from the map's largest free region (8-connected), the nearest cell of that region
        too (the largest region is labelled only for maps held in memory)."""
        near = self.nearest_free(p)
        if near is None:
            return ""
        text = f"; the nearest free cell's centre is ({near[0]:.6g}, {near[1]:.6g})"
        if not isinstance(self.occupied, np.ndarray):
            return text
        from scipy import ndimage

        labels, n = ndimage.label(~self.occupied, structure=np.ones((3, 3), bool))
        if n < 2:
            return text
        sizes = np.bincount(labels.ravel())
        sizes[0] = 0
        big = int(np.argmax(sizes))
        cell = self.grid.cell_of(near[0], near[1])
        if cell is None or labels[cell] == big:
            return text
        main = self.nearest_free(p, among=labels == big)
        if main is None:  # pragma: no cover - the largest region has cells
            return text
        k = int(sizes[labels[cell]])
        return (f"{text}, in a pocket of {k} free cell{'' if k == 1 else 's'} closed off from the rest; the "
                f"nearest cell of the map's largest free region ({int(sizes[big])} cells) is at "
                f"({main[0]:.6g}, {main[1]:.6g})")

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
        p = np.asarray(point, dtype=np.float64).reshape(2)
        rows, cols = self.shape
        x0, y0 = self.grid.origin
        h = self.grid.resolution
        r0 = min(max(int(np.floor((p[1] - y0) / h)), 0), rows - 1)
        c0 = min(max(int(np.floor((p[0] - x0) / h)), 0), cols - 1)
        for half in (8, 64, 512, max(rows, cols)):
            ra, rb, ca, cb = max(r0 - half, 0), min(r0 + half + 1, rows), max(c0 - half, 0), min(c0 + half + 1, cols)
            win = ~np.asarray(self.occupied[ra:rb, ca:cb], dtype=bool) if among is None else among[ra:rb, ca:cb]
            rr, cc = np.nonzero(win)
            if rr.size == 0:
                continue
            d2 = (rr + ra - r0) ** 2 + (cc + ca - c0) ** 2
            k = int(np.argmin(d2))
            # the nearest cell found lies within the window's inscribed radius, or the window is the map
            if d2[k] <= half * half or (ra == 0 and ca == 0 and rb == rows and cb == cols):
                return np.array([x0 + (cc[k] + ca + 0.5) * h, y0 + (rr[k] + ra + 0.5) * h])
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
