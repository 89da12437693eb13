"""The navigation escape: leave a local minimum along the grid's navigation function.

``escape="navigation"`` (:func:`gridfield.follow.follow`): at a local minimum of the potential the
follower drives down the octile wavefront from the goal (:func:`gridfield.navigation.wavefront`,
the exact shortest-path cost over 8-connected moves that never cut a corner) from the stall point,
cell centre by cell centre, until it enters a cell whose discrete steepest descent on the potential
ends somewhere else than the stall's does (another basin of :func:`gridfield.follow.basins`); there
the potential descent resumes. Two rules make it complete:

- each escape must start at a lower navigation value than the one before; when it does not (the
  potential led the follower back uphill), the escape drives all the way to the goal;
- the last escape allowed by ``escape_tries`` drives all the way to the goal too.

So when the goal is reachable, the follower reaches it. Every move of the escape is a step between
neighbouring free cell centres, so it never touches an obstacle. On a map with an ``open`` border the
navigation function also runs through a one-cell free ring around the grid (open space, where the
follower may go too).

Examples
--------
>>> import numpy as np
>>> from gridfield.grid import Grid, GridMap
>>> from types import SimpleNamespace
>>> occ = np.zeros((5, 5), bool); occ[1:4, 2] = True
>>> gm = GridMap(Grid((5, 5), 1.0, border="wall"), occ)
>>> f = SimpleNamespace(map=gm, potential=np.zeros((5, 5)), goal=(4.5, 2.5))
>>> esc = NavigationEscape(f)
>>> [tuple(q) for q in esc((0.5, 2.5), final=True)]
[(0.5, 1.5), (1.5, 0.5), (2.5, 0.5), (3.5, 0.5), (3.5, 1.5), (4.5, 2.5)]
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .grid import Grid, GridMap

__all__ = ["NavigationEscape", "navigation_map"]

Point = tuple[float, float]


def navigation_map(gridmap: GridMap) -> GridMap:
    """The map the navigation escape and the reachability check search: ``gridmap`` itself for a
    ``wall`` border, else ``gridmap`` inside a one-cell free ring (open space around the grid).

    Parameters
    ----------
    gridmap : GridMap

    Returns
    -------
    GridMap
        With a ``wall`` border: ``gridmap`` itself; otherwise a map two cells wider and taller, with
        a ``wall`` border and the same resolution, shifted by one cell.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.grid import Grid, GridMap
    >>> m = navigation_map(GridMap(Grid((2, 3), 0.5, (1.0, 1.0)), np.zeros((2, 3), bool)))
    >>> m.grid.shape, m.grid.origin
    ((4, 5), (0.5, 0.5))
    """
    g = gridmap.grid
    if g.border == "wall":
        return gridmap
    res = g.resolution
    ring = Grid((g.rows + 2, g.cols + 2), res, (g.origin[0] - res, g.origin[1] - res), border="wall")
    occ = np.pad(np.asarray(gridmap.occupied, dtype=bool), 1, constant_values=False)
    return GridMap(ring, occ)


class NavigationEscape:
    """The navigation escape of a grid field (see the module docstring).

    Parameters
    ----------
    field : Field-like
        Has ``map`` (GridMap), ``potential`` (array) and ``goal``.

    Call it as ``escape(point, final=...)``: the moves (world points, the first one the stall
    point's own cell centre) to drive from ``point``, or ``[]`` when the goal cannot be reached
    from there. ``final=True`` drives all the way to the goal.

    Examples
    --------
    A column of obstacle cells splits a 5 x 5 map. With a ``wall`` border the goal cannot be
    reached; with an ``open`` border the escape goes round through the free ring below the grid:

    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from gridfield.grid import Grid, GridMap
    >>> occ = np.zeros((5, 5), bool); occ[:, 2] = True
    >>> def escape(border):
    ...     gm = GridMap(Grid((5, 5), 1.0, border=border), occ)
    ...     return NavigationEscape(SimpleNamespace(map=gm, potential=np.zeros((5, 5)), goal=(4.5, 2.5)))
    >>> escape("wall")((0.5, 2.5))
    []
    >>> moves = escape("open")((0.5, 2.5), final=True)
    >>> [float(y) for x, y in moves]
    [1.5, 0.5, -0.5, -0.5, -0.5, 0.5, 1.5, 2.5]
    """

    def __init__(self, field: Any) -> None:
        self.field = field
        self.gridmap: GridMap = field.map
        self.goal = np.asarray(field.goal, dtype=float).reshape(2)
        self._last_value = math.inf

    @cached_property
    def _frame(self) -> tuple[float, float, float]:
        """``(x0, y0, res)`` of :func:`navigation_map`: the wavefront runs in its cell units, so that
        its ties (and so the escape's path in cells) do not depend on the map's resolution."""
        g = navigation_map(self.gridmap).grid
        return float(g.origin[0]), float(g.origin[1]), float(g.resolution)

    def _to_cells(self, point: Point) -> Point:
        x0, y0, res = self._frame
        return ((float(point[0]) - x0) / res, (float(point[1]) - y0) / res)

    @cached_property
    def nav(self) -> Any:
        """The octile wavefront from the goal on :func:`navigation_map`, in cell units (unit cells,
        origin at its lower-left corner); computed on first use."""
        from .navigation import wavefront

        nm = navigation_map(self.gridmap)
        unit = GridMap(Grid(nm.grid.shape, 1.0, border="wall"), nm.occupied)
        return wavefront(unit, self._to_cells(tuple(self.goal)), costs="octile")

    @cached_property
    def sink(self) -> NDArray[np.intp]:
        """Each grid cell's discrete descent sink on the potential (:func:`gridfield.follow.basins`)."""
        from .follow import basins

        return basins(self.field).sink

    def value(self, point: Point) -> float:
        """The navigation value (octile distance to the goal, in cells) at the cell containing ``point``."""
        u, v = self._to_cells(point)
        cell = self.nav.grid.cell_of(u, v)
        return math.inf if cell is None else float(self.nav.value[cell])

    def __call__(self, point: Point, *, final: bool = False) -> list[Point]:
        from .navigation import extract_path

        lead: list[Point] = []
        if self.nav.grid.cell_of(*self._to_cells(point)) is None:
            # out in the open space around an open map: straight back to the ring around the grid
            # (the segment stays outside the grid, so it is free)
            g = self.gridmap.grid
            half = 0.5 * g.resolution
            xmin, ymin, xmax, ymax = g.bounds
            point = (min(max(float(point[0]), xmin - half), xmax + half),
                     min(max(float(point[1]), ymin - half), ymax + half))
            lead = [point]
        v = self.value(point)
        if not math.isfinite(v):
            return []
        path = extract_path(self.nav, self._to_cells(point), method="descent")
        x0, y0, res = self._frame
        chain = path.points[1:] * res + np.array([x0, y0])
        chain[-1] = self.goal  # exactly
        cells = np.asarray(path.extra["cells"])
        drive_all = final or v >= self._last_value
        self._last_value = v
        if not drive_all:
            g = self.gridmap.grid
            shift = 0 if g.border == "wall" else 1  # the ring around an open map
            r, c = cells[:, 0] - shift, cells[:, 1] - shift
            inside = (r >= 0) & (r < g.rows) & (c >= 0) & (c < g.cols)
            rc = np.clip(r, 0, g.rows - 1), np.clip(c, 0, g.cols - 1)
            sink = np.where(inside, self.sink[rc], -1)
            own = sink[0]
            other = np.flatnonzero(inside & (sink != own) & (sink >= 0))
            if len(other):
                chain = chain[: int(other[0]) + 1]
        return lead + [(float(x), float(y)) for x, y in chain]
