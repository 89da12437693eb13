"""World -> occupancy grid: conservative rasterization of vector obstacles.

A cell is occupied iff its **closed** square ``[x0 + ix*res, x0 + (ix+1)*res] x [y0 + iy*res,
y0 + (iy+1)*res]`` intersects the (closed) obstacle. Consequences:

- a zero-width segment blocks every cell it touches, including cells it only touches along an
  edge or at a corner;
- a point (or any shape) lying exactly on a cell edge occupies both cells sharing that edge, and a
  point on a cell corner occupies all four cells sharing it;
- a shape smaller than a cell occupies the cell(s) it touches.

Comparisons carry a tolerance of ``1e-9 * resolution`` (plus a few ulps of the coordinates) in the
conservative direction, so that a shape that touches a cell in exact arithmetic is never lost to
floating-point rounding. A cell can therefore also be marked when its distance to the obstacle is
below that tolerance.

Method (vectorized per obstacle over the cells of its bounding-box window; the only Python loop
is over obstacles):

- circles analytically: each row of cells meets the disc in one run of columns, found from the
  distance between the row's closed y-interval and the centre;
- polygons, segments and points: an exact supercover of every edge (per edge and column, the
  edge's y-range over the column's closed x-interval gives the rows it touches), plus, for
  polygons, a scanline even-odd fill of the cells whose centres lie inside (holes and multi-part
  geometries included). A closed square that touches no edge is entirely inside or entirely
  outside, so the two parts together are exact.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry.base import BaseGeometry

from ..core.errors import ParameterError, check_positive, shorten
from ..core.grid import Grid, GridMap
from .world import Obstacle, World

__all__ = ["as_gridmap", "rasterize", "rasterize_geometry", "rasterize_obstacle"]

#: Relative tolerance (in cells) of the conservative comparisons.
_REL_TOL = 1e-9


def _tolerance(grid: Grid, extra: float = 0.0) -> float:
    xmin, ymin, xmax, ymax = grid.bounds
    scale = max(abs(xmin), abs(ymin), abs(xmax), abs(ymax), abs(extra))
    return _REL_TOL * grid.resolution + 8.0 * float(np.spacing(scale))


def _edges(n0: int, n1: int, origin: float, res: float) -> NDArray[np.float64]:
    """World coordinates of the cell boundaries ``n0 .. n1 + 1`` (the same arithmetic as Grid)."""
    return origin + np.arange(n0, n1 + 2, dtype=np.float64) * res


def _index_range(lo: float, hi: float, n: int, origin: float, res: float, eps: float) -> tuple[int, int]:
    """First and last index of the cells (0..n-1) whose closed interval meets ``[lo - eps, hi + eps]``."""
    first = math.floor((lo - eps - origin) / res) - 1
    last = math.floor((hi + eps - origin) / res) + 1
    first, last = max(first, 0), min(last, n - 1)
    if first > last:
        return first, last
    e = _edges(first, last, origin, res)
    i0 = first + max(int(np.searchsorted(e, lo - eps, "left")) - 1, 0)
    i1 = first + int(np.searchsorted(e, hi + eps, "right")) - 1
    return max(i0, 0), min(i1, last)


def _expand(starts: NDArray[np.intp], counts: NDArray[np.intp]) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """For runs ``starts[k] .. starts[k] + counts[k] - 1``: (run index, value) of every element."""
    counts = np.maximum(counts, 0)
    run = np.repeat(np.arange(len(counts)), counts)
    offset = np.arange(run.size) - np.repeat(np.cumsum(counts) - counts, counts)
    return run, starts[run] + offset


def _y_on_edges(seg: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.float64]:
    """y of the (non-vertical) edges ``seg`` at ``x``, exact at the edges' end points."""
    ax, ay, bx, by = seg.T
    dx = bx - ax
    safe = np.where(dx == 0, 1.0, dx)
    y = ay + ((x - ax) * (by - ay)) / safe
    y = np.where(x == bx, by, y)
    exact: NDArray[np.float64] = np.where(x == ax, ay, y)
    return exact


def _edge_cells(
    seg: NDArray[np.float64], xe: NDArray[np.float64], ye: NDArray[np.float64], eps: float
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """(rows, cols) of the cells whose closed squares the closed segments ``seg`` (E, 4) touch.

    ``xe`` and ``ye`` are the cell boundaries of a window of ``len(ye) - 1`` rows and
    ``len(xe) - 1`` columns; the indices returned are relative to the window.
    """
    ncols, nrows = len(xe) - 1, len(ye) - 1
    ax, bx = seg[:, 0], seg[:, 2]
    xlo, xhi = np.minimum(ax, bx), np.maximum(ax, bx)
    i0 = np.maximum(np.searchsorted(xe, xlo - eps, "left") - 1, 0)
    i1 = np.minimum(np.searchsorted(xe, xhi + eps, "right") - 1, ncols - 1)
    e, col = _expand(i0, i1 - i0 + 1)
    s = seg[e]
    lo, hi = xlo[e], xhi[e]
    xl = np.clip(xe[col], lo, hi)
    xr = np.clip(xe[col + 1], lo, hi)
    yl, yr = _y_on_edges(s, xl), _y_on_edges(s, xr)
    vertical = s[:, 0] == s[:, 2]
    ylo = np.where(vertical, np.minimum(s[:, 1], s[:, 3]), np.minimum(yl, yr))
    yhi = np.where(vertical, np.maximum(s[:, 1], s[:, 3]), np.maximum(yl, yr))
    j0 = np.maximum(np.searchsorted(ye, ylo - eps, "left") - 1, 0)
    j1 = np.minimum(np.searchsorted(ye, yhi + eps, "right") - 1, nrows - 1)
    k, row = _expand(j0, j1 - j0 + 1)
    return row, col[k]


def _fill_centres(
    seg: NDArray[np.float64], xc: NDArray[np.float64], yc: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """Even-odd test of the cell centres ``(xc[col], yc[row])`` against the closed rings made of ``seg``.

    Vertical scanlines through the column centres; an edge counts for the columns with
    ``min(ax, bx) <= xc < max(ax, bx)`` (the half-open rule counts a shared vertex once). Centres
    exactly on an edge may come out either way; the caller adds the edge cells anyway.
    """
    nrows, ncols = len(yc), len(xc)
    ax, _, bx, _ = seg.T
    xlo, xhi = np.minimum(ax, bx), np.maximum(ax, bx)
    k0 = np.searchsorted(xc, xlo, "left")
    k1 = np.searchsorted(xc, xhi, "left")
    e, col = _expand(k0, k1 - k0)
    ycross = _y_on_edges(seg[e], xc[col])
    row = np.searchsorted(yc, ycross, "right")  # rows whose centre lies above the crossing
    keep = row < nrows
    flat = row[keep] * ncols + col[keep]
    toggles = np.zeros(nrows * ncols, np.uint8)
    if flat.size:
        flat.sort()
        uniq, counts = np.unique(flat, return_counts=True)
        toggles[uniq[counts % 2 == 1]] = 1
    parity = np.cumsum(toggles.reshape(nrows, ncols), axis=0, dtype=np.uint8)
    return (parity & 1).astype(bool)


def _segments_of(geom: BaseGeometry) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(boundary edges, fill edges) of a shapely geometry as ``(E, 4)`` arrays ``ax, ay, bx, by``.

    Points become zero-length edges. Fill edges are the rings of the polygonal parts.
    """
    boundary: list[NDArray[np.float64]] = []
    fill: list[NDArray[np.float64]] = []
    for part in shapely.get_parts(shapely.get_parts(geom)):  # flatten collections one more level
        gtype = part.geom_type
        if gtype in ("Polygon",):
            rings = [part.exterior, *part.interiors]
            for ring in rings:
                c = np.asarray(ring.coords, dtype=np.float64)
                if len(c) >= 2:
                    s = np.hstack([c[:-1], c[1:]])
                    boundary.append(s)
                    fill.append(s)
        elif gtype in ("LineString", "LinearRing"):
            c = np.asarray(part.coords, dtype=np.float64)
            if len(c) == 1:
                c = np.vstack([c, c])
            if len(c) >= 2:
                boundary.append(np.hstack([c[:-1], c[1:]]))
        elif gtype == "Point":
            if not part.is_empty:
                c = np.asarray(part.coords, dtype=np.float64)
                boundary.append(np.hstack([c, c]))
        elif gtype.startswith("Multi") or gtype == "GeometryCollection":
            b, f = _segments_of(part)
            boundary.append(b)
            fill.append(f)
        else:  # pragma: no cover - shapely has no other types
            raise ParameterError(f"cannot rasterize a {gtype}")
    empty = np.empty((0, 4))
    return (np.vstack(boundary) if boundary else empty, np.vstack(fill) if fill else empty)


def _window(grid: Grid, bounds: tuple[float, float, float, float], eps: float) -> tuple[int, int, int, int] | None:
    """Rows ``r0..r1`` and columns ``c0..c1`` of the cells whose closed squares meet ``bounds``."""
    xmin, ymin, xmax, ymax = bounds
    if not all(math.isfinite(v) for v in bounds):
        return None
    rows, cols = grid.shape
    c0, c1 = _index_range(xmin, xmax, cols, grid.origin[0], grid.resolution, eps)
    r0, r1 = _index_range(ymin, ymax, rows, grid.origin[1], grid.resolution, eps)
    if c0 > c1 or r0 > r1:
        return None
    return r0, r1, c0, c1


def _circle_mask(grid: Grid, win: tuple[int, int, int, int], center: tuple[float, float], radius: float,
                 eps: float) -> NDArray[np.bool_]:
    r0, r1, c0, c1 = win
    res = grid.resolution
    xe = _edges(c0, c1, grid.origin[0], res)
    ye = _edges(r0, r1, grid.origin[1], res)
    cx, cy = center
    # distance in y between each row's closed interval and the centre
    dy = np.maximum(np.maximum(ye[:-1] - cy, cy - ye[1:]), 0.0)
    half = np.sqrt(np.maximum(radius * radius - dy * dy, 0.0))
    hit_row = dy <= radius + eps
    lo, hi = cx - half - eps, cx + half + eps
    # columns whose closed x-interval meets [lo, hi]: xe[c+1] >= lo and xe[c] <= hi
    first = np.searchsorted(xe, lo, "left") - 1
    last = np.searchsorted(xe, hi, "right") - 1
    cols = np.arange(c1 - c0 + 1)
    return hit_row[:, None] & (cols[None, :] >= first[:, None]) & (cols[None, :] <= last[:, None])


def _geometry_mask(grid: Grid, win: tuple[int, int, int, int], geom: BaseGeometry, eps: float) -> NDArray[np.bool_]:
    r0, r1, c0, c1 = win
    res = grid.resolution
    xe = _edges(c0, c1, grid.origin[0], res)
    ye = _edges(r0, r1, grid.origin[1], res)
    boundary, fill = _segments_of(geom)
    if len(fill):
        xc = np.asarray(grid.origin[0] + (np.arange(c0, c1 + 1) + 0.5) * res, dtype=np.float64)
        yc = np.asarray(grid.origin[1] + (np.arange(r0, r1 + 1) + 0.5) * res, dtype=np.float64)
        mask = _fill_centres(fill, xc, yc)
    else:
        mask = np.zeros((r1 - r0 + 1, c1 - c0 + 1), bool)
    if len(boundary):
        rr, cc = _edge_cells(boundary, xe, ye, eps)
        mask[rr, cc] = True
    return mask


def _obstacle_mask(grid: Grid, ob: Obstacle, eps: float) -> tuple[tuple[int, int, int, int], NDArray[np.bool_]] | None:
    if ob.kind == "circle" and ob.center is not None and ob.radius is not None:
        win = _window(grid, ob.bounds(), eps)
        return None if win is None else (win, _circle_mask(grid, win, ob.center, float(ob.radius), eps))
    win = _window(grid, tuple(ob.geometry.bounds), eps)
    return None if win is None else (win, _geometry_mask(grid, win, ob.geometry, eps))


def rasterize_obstacle(grid: Grid, obstacle: Obstacle) -> tuple[tuple[int, int, int, int], NDArray[np.bool_]] | None:
    """The cells one obstacle covers, rasterized as :func:`rasterize` does (conservatively, with its
    tolerance): the window of rows and columns its bounds meet and the mask over that window.

    Parameters
    ----------
    grid : Grid
        The grid.
    obstacle : Obstacle
        One obstacle of a world.

    Returns
    -------
    ((r0, r1, c0, c1), mask) or None
        The window's first and last row and column (inclusive) and the bool mask of its cells the
        obstacle covers; None when the obstacle lies off the grid.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 4, 4], "obstacles": [{"polygon": [[1, 1], [2, 1], [2, 2], [1, 2]]}]})
    >>> win, mask = rasterize_obstacle(Grid((4, 4), 1.0), w.obstacles[0])
    >>> win, mask.astype(int).tolist()  # the closed square touches the cells around it
    ((0, 2, 0, 2), [[1, 1, 1], [1, 1, 1], [1, 1, 1]])
    """
    return _obstacle_mask(grid, obstacle, _tolerance(grid))


def rasterize_geometry(geometry: BaseGeometry, grid: Grid) -> NDArray[np.bool_]:
    """Conservative rasterization of one shapely geometry onto ``grid``.

    A cell is ``True`` iff its closed square intersects the closed geometry (see the module
    docstring). Works for points, line strings, polygons (with holes) and their collections.

    Parameters
    ----------
    geometry : shapely geometry
    grid : Grid

    Returns
    -------
    ndarray of bool, shape ``grid.shape``

    Examples
    --------
    >>> from shapely.geometry import Point
    >>> rasterize_geometry(Point(1.0, 1.0), Grid((3, 3), 1.0)).astype(int)
    array([[1, 1, 0],
           [1, 1, 0],
           [0, 0, 0]])
    """
    if not isinstance(geometry, BaseGeometry):
        raise ParameterError(f"geometry must be a shapely geometry, got {type(geometry).__name__}")
    out = np.zeros(grid.shape, bool)
    if geometry.is_empty:
        return out
    eps = _tolerance(grid)
    win = _window(grid, tuple(geometry.bounds), eps)
    if win is not None:
        r0, r1, c0, c1 = win
        out[r0:r1 + 1, c0:c1 + 1] = _geometry_mask(grid, win, geometry, eps)
    return out


def rasterize(
    world: World, resolution: float, *, bounds: tuple[float, ...] | None = None
) -> GridMap:
    """Conservative occupancy grid of a vector world.

    The grid is ``Grid.covering(bounds or world.bounds, resolution, border=world.border)``. A
    cell is occupied iff its closed square intersects an obstacle: segments block every cell they
    touch (also along an edge or at a corner), a point on a cell edge occupies both cells sharing
    it (four at a corner), shapes smaller than a cell occupy the cells they touch. Circles are
    rasterized from their exact centre and radius, not from their polygonal outline.

    Parameters
    ----------
    world : World
    resolution : float
        Cell size in world units (> 0).
    bounds : (xmin, ymin, xmax, ymax), optional
        Area to cover instead of ``world.bounds``; obstacles outside it are clipped.

    Returns
    -------
    GridMap
        ``occupied`` (bool), ``obstacle_id`` (int32: the 1-based id of the world obstacle in the
        cell, 0 for free cells; where obstacles overlap, the **lowest** id), ``world`` and
        ``source`` set from the world.

    Raises
    ------
    ParameterError
        if ``resolution`` is not a positive finite number or ``bounds`` are malformed.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 4, 3], "obstacles": [
    ...     {"segment": [[1.5, 0.5], [3.5, 0.5]]}, {"circle": {"center": [0.5, 2.5], "radius": 0.3}},
    ...     {"polygon": [[2, 1], [4, 1], [4, 3]]}]})
    >>> m = rasterize(w, 1.0)
    >>> m.obstacle_id  # row 0 is the lowest y; closed squares: the triangle touches (1, 1) and (2, 2)
    array([[0, 1, 1, 1],
           [0, 3, 3, 3],
           [2, 0, 3, 3]], dtype=int32)
    """
    if not isinstance(world, World):
        raise ParameterError(f"rasterize needs a World, got {type(world).__name__}")
    res = check_positive("resolution", resolution)
    area = world.bounds if bounds is None else bounds
    try:
        area = tuple(float(v) for v in area)  # type: ignore[assignment]
    except (TypeError, ValueError):
        raise ParameterError(f"bounds must be [xmin, ymin, xmax, ymax], got {shorten(bounds)}") from None
    if len(area) != 4:
        raise ParameterError(f"bounds must be [xmin, ymin, xmax, ymax], got {shorten(bounds)}")
    grid = Grid.covering(area, res, border=world.border)
    occupied = np.zeros(grid.shape, bool)
    ids = np.zeros(grid.shape, np.int32)
    eps = _tolerance(grid)
    for ob in sorted(world.obstacles, key=lambda o: o.id):  # ascending: the lowest id wins overlaps
        hit = _obstacle_mask(grid, ob, eps)
        if hit is None:
            continue
        (r0, r1, c0, c1), mask = hit
        sl = (slice(r0, r1 + 1), slice(c0, c1 + 1))
        sub_ids = ids[sl]
        sub_ids[mask & ~occupied[sl]] = ob.id
        occupied[sl] |= mask
    return GridMap(grid, occupied, obstacle_id=ids, world=world, source=world.source)


def as_gridmap(obj: World | GridMap, resolution: float | None = None) -> GridMap:
    """Return ``obj`` as an occupancy grid: a GridMap passes through, a World is rasterized.

    Parameters
    ----------
    obj : World or GridMap
    resolution : float, optional
        Cell size for a World (default: the world's own ``resolution`` key). For a GridMap it may
        only repeat the map's resolution: resampling is not supported.

    Returns
    -------
    GridMap
        ``obj`` itself for a GridMap; for a World its conservative rasterization (a cell is
        occupied when any part of an obstacle touches it), with the world's bounds and border.

    Raises
    ------
    ParameterError
        when a World has no resolution from either source, when a GridMap's resolution differs
        from ``resolution``, or for any other type.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 2, 2], "resolution": 0.5,
    ...                      "obstacles": [{"polygon": [[0, 0], [1, 0], [0, 1]]}]})
    >>> as_gridmap(w).shape
    (4, 4)
    >>> m = as_gridmap(w, 1.0)
    >>> as_gridmap(m) is m
    True
    """
    if isinstance(obj, GridMap):
        if resolution is not None:
            res = check_positive("resolution", resolution)
            if not math.isclose(res, obj.grid.resolution, rel_tol=1e-9, abs_tol=0.0):
                name = f" {obj.source}" if obj.source else ""
                raise ParameterError(
                    f"the map{name} is a grid with resolution {obj.grid.resolution:g}; "
                    f"resolution {res:g} was requested, but resampling a grid is not supported "
                    "(omit --resolution for grid maps)"
                )
        return obj
    if isinstance(obj, World):
        if resolution is None:
            resolution = obj.resolution
        if resolution is None:
            name = f" {obj.source}" if obj.source else ""
            raise ParameterError(
                f"the world{name} has no 'resolution' key and no resolution was given; "
                "pass --resolution (the cell size in world units) to rasterize it"
            )
        return rasterize(obj, resolution)
    raise ParameterError(f"expected a World or a GridMap, got {type(obj).__name__}")
