"""The configuration space of a robot that turns: C-obstacles stacked over the heading (private; import
from :mod:`gridfield.geometry.cspace`).

A pose is ``(x, y, theta)``: the robot's reference point (the origin of its vertices) at ``(x, y)``
and the robot turned by ``theta`` (radians, counter-clockwise from the x axis, the ROS convention)
about it. The heading circle is cut into ``N`` bins of width ``2 pi / N``; bin ``k`` is centred on
``theta_k = 2 pi k / N`` and covers ``[theta_k - pi / N, theta_k + pi / N]``. Slice ``k`` of the C-space
marks the cells whose centre, as a position of the reference point, lets the robot touch an occupied
cell square (or the wall border) **at some heading of the bin**: the robot swept through the whole
bin. So a pose grid ``[k, row, col]`` (heading, y, x) is free only where the robot is clear at every
heading of its bin (Lozano-Perez's slices of C-obstacles over the rotation; Latombe, *Robot Motion
Planning*, 1991, ch. 3 and 7, whose slices are exact at one heading each; here each slice covers its
bin so that moves between neighbouring bins are safe too).

Why the moves of the pose grid are safe: a move between neighbouring poses (in x, y and heading,
the heading wrapping round) is safe when every pose of its bounding box is free (the voxel rule of
the 3-D wavefront). At any instant of such a move the heading lies in one of the two bins and the
reference point in the square between the box's cell centres; a robot that meets a cell square of
the lattice from a point of that square meets it from one of the square's corners (the lattice's
squares tile the plane: a point at offset ``t < 1`` cell along an axis from one corner lies in the
obstacle square's span from that corner or the next one), and every corner is a free pose for every
heading of both bins.

Each bin's swept robot is built once (shapely, not per cell): the robot turned to sub-angles of the
bin, each grown by the farthest any of its points moves before the next sub-angle takes over (at most
1/64 of a cell), so that the union contains the true swept region; then rasterized conservatively as a
footprint of cell offsets; the occupancy is dilated by each bin's footprint (one running maximum per
run of offsets, vectorized over the grid).
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import NDArray

from ...core.errors import ParameterError, shorten
from ...core.grid import Grid, GridMap
from ...core.limits import check_cells
from ..rasterize import rasterize_geometry
from ..world import Robot
from ._grid import _dilate, _runs

__all__ = [
    "MAX_HEADINGS",
    "check_headings",
    "heading_centres",
    "heading_footprints",
    "heading_occupancy",
    "swept_robot",
    "turn_radius",
]

#: The most heading bins a C-space may have (a bin of 0.5 degrees; Nav2's Smac planners use 72).
MAX_HEADINGS = 720
#: The swept robot's sub-angles are chosen so that every point of the robot turned between two of them
#: lies within this fraction of a cell of the robot turned to one of them (the margin added to stay on
#: the safe side), unless that would need more than :data:`MAX_TURNS` sub-angles on the circle.
SAGITTA_CELLS = 1.0 / 64.0
MAX_TURNS = 4096
#: Segments per quarter circle of the buffers; their radius is divided by cos(pi / (4 QUAD_SEGS)) so that
#: the polygon contains the round buffer it approximates.
QUAD_SEGS = 4
_INSCRIBED = math.cos(math.pi / (4 * QUAD_SEGS))


def check_headings(headings: object) -> int:
    """The number of heading bins as an int in ``[1, MAX_HEADINGS]``, or :class:`ParameterError`.

    Parameters
    ----------
    headings : int
        The number asked for (``--headings``).

    Returns
    -------
    int

    Examples
    --------
    >>> check_headings(72)
    72
    >>> check_headings(0)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: headings must be a whole number from 1 to 720 (bins of the heading circle), got 0
    """
    if isinstance(headings, int | np.integer) and not isinstance(headings, bool) and 1 <= int(headings) <= MAX_HEADINGS:
        return int(headings)
    raise ParameterError(f"headings must be a whole number from 1 to {MAX_HEADINGS} (bins of the heading circle), "
                         f"got {shorten(headings)}")


def heading_centres(headings: int) -> NDArray[np.float64]:
    """The bins' centre headings ``2 pi k / N`` (radians) for ``k`` from 0 to ``N - 1``.

    Parameters
    ----------
    headings : int
        The number of bins ``N``.

    Returns
    -------
    ndarray of float64, shape (N,)

    Examples
    --------
    >>> heading_centres(4).round(4).tolist()
    [0.0, 1.5708, 3.1416, 4.7124]
    """
    n = check_headings(headings)
    out: NDArray[np.float64] = np.arange(n, dtype=np.float64) * (2.0 * math.pi / n)
    return out


def turn_radius(robot: Robot) -> float:
    """The distance from the reference point to the robot's farthest point: a turn by ``a`` radians
    moves that point along an arc of ``turn_radius * a`` (the turning cost of the pose planners)."""
    if robot.radius is not None:
        return float(robot.radius)
    assert robot.vertices is not None
    return float(np.hypot(robot.vertices[:, 0], robot.vertices[:, 1]).max())


def _rotated(vertices: NDArray[np.float64], theta: float) -> NDArray[np.float64]:
    c, s = math.cos(theta), math.sin(theta)
    rot: NDArray[np.float64] = vertices @ np.array([[c, s], [-s, c]])
    return rot


def swept_robot(robot: Robot, lo: float, hi: float, resolution: float) -> shapely.Geometry:
    """A polygon containing every point the robot covers while it turns from heading ``lo`` to ``hi``.

    Parameters
    ----------
    robot : Robot
        A convex polygon or a disc (a disc's sweep is the disc).
    lo, hi : float
        Headings in radians, ``lo <= hi``.
    resolution : float
        The grid's cell size: the margin over the true swept region is at most
        :data:`SAGITTA_CELLS` of it.

    Returns
    -------
    shapely geometry

    Examples
    --------
    A 2 x 0.2 bar turned by a quarter turn about its middle sweeps (nearly) a disc sector pair:

    >>> bar = Robot(vertices=[[-1, -0.1], [1, -0.1], [1, 0.1], [-1, 0.1]])
    >>> g = swept_robot(bar, 0.0, math.pi / 2, 0.05)
    >>> bool(g.contains(shapely.Point(0.6, 0.6))), bool(g.contains(shapely.Point(0.6, -0.6)))
    (True, False)
    """
    if robot.radius is not None:  # a disc: its sweep is itself (the polygon of the buffer circumscribes it)
        rad = float(robot.radius)
        return shapely.Point(0.0, 0.0).buffer(rad / _INSCRIBED, quad_segs=QUAD_SEGS) if rad > 0 else shapely.Point(0, 0)
    assert robot.vertices is not None
    v = np.asarray(robot.vertices, dtype=np.float64)
    r = turn_radius(robot)
    span = hi - lo
    if span <= 0 or r == 0:
        return shapely.Polygon(v)
    # sub-angles d apart: a point of the robot turned anywhere between two of them lies within the
    # chord 2 r sin(d / 4) of the robot turned to the nearer one
    margin = SAGITTA_CELLS * resolution
    d = 4.0 * math.asin(min(1.0, margin / (2.0 * r)))
    d = max(d, 2.0 * math.pi / MAX_TURNS)
    steps = max(1, math.ceil(span / d))
    grow = 2.0 * r * math.sin(span / steps / 4.0)
    turned = [shapely.Polygon(_rotated(v, a)) for a in lo + (span / steps) * np.arange(steps + 1)]
    # the buffer's polygon is inscribed in the true one: grow its radius so that it contains it
    return shapely.union_all(shapely.buffer(turned, grow / _INSCRIBED * (1 + 1e-9), quad_segs=QUAD_SEGS))


def heading_footprints(robot: Robot, resolution: float, headings: int) -> NDArray[np.bool_]:
    """Per heading bin, the cell offsets whose square the robot touches from a cell centre while it turns
    through the bin.

    Parameters
    ----------
    robot : Robot
    resolution : float
        The cell size.
    headings : int
        The number of bins ``N``.

    Returns
    -------
    ndarray of bool, shape (N, 2m+1, 2m+1)
        ``[k, m + i, m + j]`` is set iff the robot, its reference point at the centre of a cell and its
        heading anywhere in bin ``k``, meets the closed square of the cell ``i`` rows and ``j`` columns
        away.

    Examples
    --------
    A 1.6 x 0.4 robot centred on its reference point, on 0.5 cells: along x at heading 0, along y a
    quarter turn later.

    >>> cart = Robot(vertices=[[-0.8, -0.2], [0.8, -0.2], [0.8, 0.2], [-0.8, 0.2]])
    >>> f = heading_footprints(cart, 0.5, 4)
    >>> f.shape, f[0].sum(axis=1).tolist(), f[1].sum(axis=0).tolist()
    ((4, 9, 9), [0, 0, 0, 5, 5, 5, 0, 0, 0], [0, 0, 0, 5, 5, 5, 0, 0, 0])
    """
    n = check_headings(headings)
    h = float(resolution)
    reach = turn_radius(robot)
    m = math.ceil(reach / h + 0.5) + 1
    check_cells((n, 2 * m + 1, 2 * m + 1), f"the heading footprints of the robot ({robot.describe()}) at cell size {h:g}")
    grid = Grid((2 * m + 1, 2 * m + 1), h, origin=(-(m + 0.5) * h, -(m + 0.5) * h))
    half = math.pi / n
    out = np.zeros((n, 2 * m + 1, 2 * m + 1), dtype=bool)
    for k, c in enumerate(heading_centres(n)):  # one shapely sweep per bin, not per cell
        out[k] = rasterize_geometry(swept_robot(robot, c - half, c + half, h), grid) if n > 1 else \
            rasterize_geometry(swept_robot(robot, 0.0, 2 * math.pi, h), grid)
    return out


def heading_occupancy(gridmap: GridMap, robot: Robot, headings: int) -> NDArray[np.bool_]:
    """The occupancy of the pose grid ``[heading, row, col]`` of a 2-D map for a turning robot.

    Parameters
    ----------
    gridmap : GridMap
        A 2-D map; with ``border="wall"`` the wall blocks too.
    robot : Robot
    headings : int
        Bins of the heading circle (1: the robot turned through every heading, a conservative
        translating C-space).

    Returns
    -------
    ndarray of bool, shape (headings, rows, cols)

    Examples
    --------
    >>> occ = np.zeros((7, 9), bool); occ[3, 4] = True
    >>> cart = Robot(vertices=[[-0.8, -0.2], [0.8, -0.2], [0.8, 0.2], [-0.8, 0.2]])
    >>> c = heading_occupancy(GridMap(Grid((7, 9), 0.5), occ), cart, 4)
    >>> c[0].astype(int)[3].tolist(), c[1].astype(int)[:, 4].tolist()
    ([0, 0, 1, 1, 1, 1, 1, 0, 0], [0, 1, 1, 1, 1, 1, 0])
    """
    if not isinstance(gridmap, GridMap) or gridmap.ndim != 2:
        raise ParameterError("a turning robot's configuration space is built on a 2-D map")
    n = check_headings(headings)
    check_cells((n, *gridmap.shape), "the configuration space over the headings")
    feet = heading_footprints(robot, gridmap.grid.resolution, n)
    wall = int(gridmap.grid.border == "wall")
    occ8 = np.ascontiguousarray(gridmap.occupied, dtype=np.uint8)
    out = np.empty((n, *gridmap.shape), dtype=bool)
    if not occ8.any() and not wall:
        out[:] = False
        return out
    for k in range(n):  # per heading, vectorized over the grid
        # slice k at q is the max of occ[q + o] over the offsets o: _dilate adds the reflected ones
        out[k] = _dilate(occ8, _runs(feet[k][::-1, ::-1]), pad_value=wall).astype(bool)
    return out
