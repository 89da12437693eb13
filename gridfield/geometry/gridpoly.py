"""Exact obstacles of a grid map: the blocked cells as polygons, and conservative coarsening.

:func:`grid_world` turns a :class:`~gridfield.core.grid.GridMap` into a :class:`~gridfield.geometry.world.World`
whose obstacles are the connected pieces of the union of the blocked cell squares (holes included,
in world coordinates; collinear vertices removed), so that the exact planners (``visibility``,
``exact-potential``) and the exact metrics of :mod:`gridfield.compare` run on bitmap, ROS and
Moving AI maps. :func:`gridfield.planners.plan` does this automatically (once per map) when an
exact planner gets a grid map.

Corner rule
    Two blocked cells that touch only at a corner **block passage through that corner** (the
    Moving AI no-corner-cutting rule): no path squeezes through the zero-width gap. In the union the
    two squares stay separate polygons (or one ring touching itself at the point), and the exact
    planners treat such a point as a pinch point (:data:`gridfield.exact.visibility.PINCH_RULES`
    ``"block"``; the follower of ``exact-potential`` never touches an obstacle at all). A path may
    still *touch* a convex corner (one blocked cell) and run along cell edges.

Border
    The world keeps the grid's bounds and border: ``wall`` (Moving AI maps) closes the map, ``open``
    leaves the plane outside the grid free.

:func:`block_downsample` coarsens a grid by an integer factor, a coarse cell being blocked when any
of its fine cells is (a conservative grid: its free space lies inside the fine one's).

Examples
--------
>>> import numpy as np
>>> from gridfield.core.grid import Grid, GridMap
>>> occ = np.zeros((4, 4), bool); occ[1, 1] = occ[2, 2] = True   # two cells touching at (2, 2)
>>> w = grid_world(GridMap(Grid((4, 4), 0.5), occ))
>>> [ob.geometry.bounds for ob in w.obstacles]
[(0.5, 0.5, 1.0, 1.0), (1.0, 1.0, 1.5, 1.5)]
>>> block_downsample(GridMap(Grid((4, 4), 0.5), occ), 2).occupied.astype(int).tolist()
[[1, 0], [0, 1]]
"""

from __future__ import annotations

import weakref
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon

from ..core.errors import ParameterError
from ..core.grid import Grid, GridMap
from ..core.limits import check_cells
from .world import Obstacle, World

__all__ = ["block_downsample", "blocked_runs", "grid_world", "source_grid", "subdivide"]

_WORLDS: weakref.WeakKeyDictionary[GridMap, World] = weakref.WeakKeyDictionary()
_SOURCES: weakref.WeakKeyDictionary[World, weakref.ref[GridMap]] = weakref.WeakKeyDictionary()


def blocked_runs(occupied: NDArray[np.bool_]) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp]]:
    """Maximal runs of blocked cells along each row: ``(row, first_col, end_col)`` (end exclusive).

    Parameters
    ----------
    occupied : ndarray of bool, shape (rows, cols)
        The blocked cells (row 0 first).

    Returns
    -------
    row, first_col, end_col : ndarray of int
        One entry per run, ordered by row, then column; the run covers ``first_col <= col < end_col``.

    Examples
    --------
    >>> r, c0, c1 = blocked_runs(np.array([[1, 1, 0, 1], [0, 0, 0, 0]], bool))
    >>> r.tolist(), c0.tolist(), c1.tolist()
    ([0, 0], [0, 3], [2, 4])
    """
    occ = np.asarray(occupied, dtype=bool)
    p = np.zeros((occ.shape[0], occ.shape[1] + 2), dtype=np.int8)
    p[:, 1:-1] = occ
    d = np.diff(p, axis=1)
    rows, c0 = np.nonzero(d == 1)
    _, c1 = np.nonzero(d == -1)
    return rows, c0, c1


def _polygons(gm: GridMap) -> list[Polygon]:
    rows, c0, c1 = blocked_runs(gm.occupied)
    if rows.size == 0:
        return []
    from ..core.limits import check_seconds

    check_seconds({"blocked run": rows.size}, f"exact polygons of {gm.source or 'the grid map'}")  # before the union
    (x0, y0), h = gm.grid.origin, gm.grid.resolution
    boxes = shapely.box(x0 + c0 * h, y0 + rows * h, x0 + c1 * h, y0 + (rows + 1) * h)
    union = shapely.simplify(shapely.union_all(boxes), 0.0)  # exact for axis-aligned boxes; drops collinear vertices
    parts = [g for g in shapely.get_parts(shapely.normalize(union)) if isinstance(g, Polygon) and not g.is_empty]
    # a stable order: by lower-left corner (row, then column)
    parts.sort(key=lambda g: (g.bounds[1], g.bounds[0]))
    return parts


def grid_world(gridmap: GridMap) -> World:
    """The grid's blocked cells as an exact polygon :class:`World` (cached per map object).

    Obstacle ``k`` (1-based) is the ``k``-th connected piece of the union of the blocked cell
    squares, in order of their lowest row, then column; two cells touching only at a corner are
    separate pieces (module docstring: they block passage through that corner). The world has the
    grid's bounds, border and resolution, the map's ``source``, and no start or goal.

    Parameters
    ----------
    gridmap : GridMap

    Returns
    -------
    World

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((3, 3), bool); occ[0, :] = True; occ[1:, 1] = True      # a T, 5 cells
    >>> w = grid_world(GridMap(Grid((3, 3), 1.0, border="wall"), occ))
    >>> len(w.obstacles), w.obstacles[0].geometry.area, len(w.obstacles[0].vertices), w.border
    (1, 5.0, 8, 'wall')
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"grid_world needs a GridMap, got {type(gridmap).__name__}")
    world = _WORLDS.get(gridmap)
    if world is None:
        obstacles = tuple(Obstacle(k + 1, "polygon", g) for k, g in enumerate(_polygons(gridmap)))
        xmin, ymin, xmax, ymax = gridmap.grid.bounds  # a 2-D map's
        world = World(bounds=(xmin, ymin, xmax, ymax), obstacles=obstacles, border=gridmap.grid.border,
                      resolution=gridmap.grid.resolution, source=gridmap.source)
        _WORLDS[gridmap] = world
        _SOURCES[world] = weakref.ref(gridmap)
    return world


def source_grid(world: Any) -> GridMap | None:
    """The grid map a world was made from by :func:`grid_world`, or ``None``.

    Parameters
    ----------
    world : World or any object
        A world (anything else gives ``None``).

    Returns
    -------
    GridMap or None
        The map, while it is alive, if ``world`` came from :func:`grid_world`.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> gm = GridMap(Grid((2, 2), 1.0), np.eye(2, dtype=bool))
    >>> source_grid(grid_world(gm)) is gm, source_grid("not a world")
    (True, None)
    """
    try:
        ref = _SOURCES.get(world)
    except TypeError:  # not weak-referenceable
        return None
    return ref() if ref is not None else None


def subdivide(gridmap: GridMap, parts: int) -> GridMap:
    """Refine a grid by an integer ``parts``: every cell becomes ``parts x parts`` cells of its state.

    The free space is exactly the same (the blocked cells cover the same squares), so a finer grid of a
    grid map is no approximation of it: :func:`gridfield.compare.convergence_study` refines a grid map
    this way below its own resolution (and coarsens it with :func:`block_downsample` above it).

    Parameters
    ----------
    gridmap : GridMap
        The map.
    parts : int
        Cells per cell along each axis (>= 1; 1 returns ``gridmap`` itself).

    Returns
    -------
    GridMap
        The fine map (resolution ``1/parts`` of the map's, same origin and border).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.array([[True, False]])
    >>> f = subdivide(GridMap(Grid((1, 2), 1.0), occ), 2)
    >>> f.shape, f.grid.resolution, f.occupied.astype(int).tolist()
    ((2, 4), 0.5, [[1, 1, 0, 0], [1, 1, 0, 0]])
    """
    k = _positive_integer(parts, "subdivision")
    if k == 1:
        return gridmap
    rows, cols = gridmap.shape
    check_cells((rows * k, cols * k), f"a x1/{k} grid of {gridmap.source or 'the map'}")
    occ = np.repeat(np.repeat(np.asarray(gridmap.occupied, dtype=bool), k, axis=0), k, axis=1)
    grid = Grid((rows * k, cols * k), gridmap.grid.resolution / k, gridmap.grid.origin, gridmap.grid.border)
    src = f"{gridmap.source} (x1/{k} cells)" if gridmap.source else ""
    return GridMap(grid, occ, source=src, meta=dict(gridmap.meta))


def _positive_integer(value: Any, what: str) -> int:
    """``value`` as an int, or a ParameterError naming ``what`` unless it is an integer >= 1 (not a bool)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ParameterError(f"{what} must be a positive integer, got {value!r}")
    return int(value)


def block_downsample(gridmap: GridMap, factor: int) -> GridMap:
    """Coarsen a grid by an integer ``factor``: a coarse cell is blocked if any fine cell in it is.

    The coarse grid has the same origin and cells ``factor`` times larger; when the shape is not a
    multiple of ``factor`` the last coarse row/column sticks out, the part outside the map counting
    as blocked for a wall border and as free for an open one. The result is conservative: every
    free coarse cell is free in the fine map.

    Parameters
    ----------
    gridmap : GridMap
        The fine map.
    factor : int
        Cells per coarse cell along each axis (>= 1; 1 returns ``gridmap`` itself).

    Returns
    -------
    GridMap
        The coarse map (resolution ``factor`` times the fine one, same origin and border).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((5, 5), bool); occ[0, 0] = True
    >>> c = block_downsample(GridMap(Grid((5, 5), 1.0, border="wall"), occ), 2)
    >>> c.shape, c.grid.resolution, c.occupied.astype(int).tolist()
    ((3, 3), 2.0, [[1, 0, 1], [0, 0, 1], [1, 1, 1]])
    """
    k = _positive_integer(factor, "downsampling factor")
    if k == 1:
        return gridmap
    rows, cols = gridmap.shape
    R, C = -(-rows // k), -(-cols // k)
    pad = np.full((R * k, C * k), gridmap.grid.border == "wall", dtype=bool)
    pad[:rows, :cols] = gridmap.occupied
    occ = np.asarray(pad.reshape(R, k, C, k).any(axis=(1, 3)), dtype=bool)
    grid = Grid((R, C), gridmap.grid.resolution * k, gridmap.grid.origin, gridmap.grid.border)
    src = f"{gridmap.source} (x{k} blocks)" if gridmap.source else ""
    return GridMap(grid, occ, source=src, meta=dict(gridmap.meta))
