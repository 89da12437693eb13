"""A robot on any map: the entry points the commands use (private; import from gridfield.geometry.cspace).

:func:`as_robot` turns what the API accepts into a :class:`~gridfield.geometry.world.Robot`;
:func:`apply_robot` builds the configuration space of a world or a grid for it (through
``_vector`` and ``_grid``); :func:`check_robot_point`, :func:`workspace_clearance` and
:func:`robot_clearance` check start, goal and paths against the workspace the robot moves in.
"""

from __future__ import annotations

import dataclasses
import math
from typing import cast, overload

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import Point

from ...core.errors import GridfieldError, ParameterError
from ...core.grid import Grid, GridMap
from ...core.limits import check_cells
from .._polygons import _as_geometry, _convex_polygon, minkowski_obstacle
from ..rasterize import rasterize, rasterize_geometry
from ..world import Obstacle, Robot, World
from ._grid import _dilate_gridmap, _runs
from ._headings import check_headings
from ._poses import PoseMap, pose_map
from ._vector import cspace_world, inflate_world


def check_robot_polygon(vertices: ArrayLike, name: str = "robot") -> NDArray[np.float64]:
    """Validate a convex robot polygon (vertices around its reference point, the origin); return it
    normalized (counter-clockwise, lowest vertex first).

    Parameters
    ----------
    vertices : (N, 2) array_like
        One vertex (a point), two (a segment) or a convex polygon; repeated vertices are dropped.
    name : str, default "robot"
        The argument's name, for the message.

    Returns
    -------
    ndarray, shape (K, 2)
        Counter-clockwise, lowest vertex first, collinear vertices removed.

    Raises
    ------
    ParameterError
        If the array is not (N, 2) finite numbers, or the polygon is not convex.

    Examples
    --------
    >>> check_robot_polygon([[0, 1], [0, 0], [1, 0]])
    array([[0., 0.],
           [1., 0.],
           [0., 1.]])
    """
    return _convex_polygon(vertices, name)


def as_robot(robot: Robot | float | ArrayLike | None) -> Robot | None:
    """A :class:`~gridfield.geometry.world.Robot` from a Robot, a radius (number) or convex polygon vertices.

    Parameters
    ----------
    robot : Robot, float, (N, 2) array_like or None
        What the API accepts as a robot.

    Returns
    -------
    Robot or None
        ``robot`` itself when it is a Robot; None for None (a point robot).

    Examples
    --------
    >>> as_robot(0.5).radius, as_robot([[0, 0], [1, 0], [0, 1]]).extent, as_robot(None)
    (0.5, 1.0, None)
    """
    if robot is None or isinstance(robot, Robot):
        return robot
    if isinstance(robot, int | float | np.integer | np.floating) and not isinstance(robot, bool):
        return Robot(radius=float(robot))
    return Robot(vertices=check_robot_polygon(robot, "robot"))


def conservative_footprint(robot: Robot, resolution: float) -> NDArray[np.bool_]:
    """The cell offsets a grid obstacle cell reaches in the configuration space, conservatively.

    Returns a ``(2m+1, 2m+1)`` boolean array whose centre is offset ``(0, 0)``: offset ``k`` is
    set iff the closed cell square ``k`` cells away meets ``S ⊕ (−R)``, where ``S`` is the closed
    cell square at the centre and ``R`` the robot. Dilating an occupancy by it marks every cell
    holding a configuration at which the robot touches an occupied cell (and only cells within
    one cell of such a configuration). A disc of radius ``r``: offsets whose squares are at most
    ``r`` apart (``h * hypot(max(|di|-1, 0), max(|dj|-1, 0)) <= r``); a polygon: the
    conservative rasterization of ``S ⊕ (−R)``. A robot of no size gives the single centre cell.

    Parameters
    ----------
    robot : Robot
    resolution : float
        The grid's cell size (> 0), in the robot's units.

    Returns
    -------
    ndarray of bool, shape (2m+1, 2m+1)
        ``m`` is one more than the robot's reach in cells, rounded up (a margin of unset offsets).

    Examples
    --------
    >>> conservative_footprint(Robot(radius=0.4), 1.0).astype(int)[1:-1, 1:-1]
    array([[1, 1, 1],
           [1, 1, 1],
           [1, 1, 1]])
    >>> int(conservative_footprint(Robot(radius=1.2), 1.0).sum())  # 5 x 5 minus the 4 corners
    21
    """
    h = check_positive_resolution(resolution)
    if robot.is_point:
        return np.ones((1, 1), dtype=bool)
    if robot.radius is not None:
        r = robot.radius
        m = math.ceil(r / h) + 1
        check_cells((2 * m + 1, 2 * m + 1), f"the footprint of the robot ({robot.describe()}) at cell size {h:g}")
        gap = np.maximum(np.abs(np.arange(-m, m + 1)) - 1, 0).astype(np.float64)
        d2 = gap[:, None] ** 2 + gap[None, :] ** 2
        inside: NDArray[np.bool_] = d2 * (h * h) <= (r * r) * (1 + 1e-9)
        return inside
    assert robot.vertices is not None
    square = 0.5 * h * np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    reach = minkowski_obstacle(square, robot.vertices)  # S ⊕ (−R)
    m = math.ceil(float(np.max(np.abs(reach))) / h + 0.5) + 1
    check_cells((2 * m + 1, 2 * m + 1), f"the footprint of the robot ({robot.describe()}) at cell size {h:g}")
    grid = Grid((2 * m + 1, 2 * m + 1), h, origin=(-(m + 0.5) * h, -(m + 0.5) * h))
    return rasterize_geometry(_as_geometry(reach), grid)


def centre_footprint(radius: float, resolution: float) -> NDArray[np.bool_]:
    """The cell offsets an occupied cell blocks for a disc robot decided at cell centres (tight).

    Offset ``k = (di, dj)`` is set iff the closed cell square ``k`` cells away is within ``radius``
    of the centre cell's centre: ``h * hypot(max(|di| - 1/2, 0), max(|dj| - 1/2, 0)) <= radius``
    (with a relative margin of ``1e-9`` on the safe side). Dilating an occupancy by it blocks
    exactly the cells at whose centre the disc touches an occupied square; a disc below half a
    cell gives the centre alone (it behaves like a point). The footprint's size is checked by the
    size guard (:func:`gridfield.core.limits.check_cells`) before it is built.

    Parameters
    ----------
    radius : float
        The disc's radius (>= 0), in the grid's units.
    resolution : float
        The grid's cell size (> 0).

    Returns
    -------
    ndarray of bool, shape (2m+1, 2m+1)
        Centred on offset ``(0, 0)``; ``m`` leaves a margin of unset offsets.

    Examples
    --------
    >>> centre_footprint(0.4, 1.0).astype(int)[1:-1, 1:-1]  # below half a cell: the centre alone
    array([[0, 0, 0],
           [0, 1, 0],
           [0, 0, 0]])
    >>> int(centre_footprint(0.5, 1.0).sum()), int(centre_footprint(1.6, 1.0).sum())  # touching counts
    (5, 21)
    """
    h = check_positive_resolution(resolution)
    r = float(radius)
    m = math.ceil(r / h + 0.5) + 1
    check_cells((2 * m + 1, 2 * m + 1), f"the footprint of a disc robot of radius {r:g} at cell size {h:g}")
    gap = np.maximum(np.abs(np.arange(-m, m + 1)) - 0.5, 0.0)
    d2 = gap[:, None] ** 2 + gap[None, :] ** 2
    inside: NDArray[np.bool_] = d2 * (h * h) <= (r * r) * (1 + 1e-9)
    return inside


def check_positive_resolution(resolution: float) -> float:
    h = float(resolution)
    if not (math.isfinite(h) and h > 0):
        raise ParameterError(f"resolution must be a positive number, got {resolution!r}")
    return h


def _wall_strips(world: World, robot: Robot) -> list[Obstacle]:
    """With a wall border: the bands along the bounds where the robot would touch the wall."""
    if world.border != "wall":
        return []
    if robot.radius is not None:
        left = right = bottom = top = robot.radius
    else:
        assert robot.vertices is not None
        v = robot.vertices
        left, right = max(0.0, -float(v[:, 0].min())), max(0.0, float(v[:, 0].max()))
        bottom, top = max(0.0, -float(v[:, 1].min())), max(0.0, float(v[:, 1].max()))
    xmin, ymin, xmax, ymax = world.bounds
    boxes = [(xmin, ymin, min(xmin + left, xmax), ymax) if left > 0 else None,
             (max(xmax - right, xmin), ymin, xmax, ymax) if right > 0 else None,
             (xmin, ymin, xmax, min(ymin + bottom, ymax)) if bottom > 0 else None,
             (xmin, max(ymax - top, ymin), xmax, ymax) if top > 0 else None]
    oid = max((o.id for o in world.obstacles), default=0)
    out = []
    for b in boxes:
        if b is not None:
            oid += 1
            out.append(Obstacle(oid, "polygon", shapely.box(*b)))
    return out


@overload
def apply_robot(target: World | GridMap, robot: Robot | float | ArrayLike | None,
                headings: None = None) -> World | GridMap: ...


@overload
def apply_robot(target: World | GridMap, robot: Robot | float | ArrayLike | None,
                headings: int) -> World | GridMap | PoseMap: ...


def apply_robot(target: World | GridMap, robot: Robot | float | ArrayLike | None,
                headings: int | None = None) -> World | GridMap | PoseMap:
    """The configuration space of ``target`` for a robot that translates (or, with ``headings``, turns):
    what every command plans on.

    - a :class:`World`: exact C-obstacles, a disc's by :func:`inflate_world`, a convex polygon's
      by :func:`cspace_world` (Minkowski sums), plus, with ``border="wall"``, the bands
      along the bounds where the robot would touch the wall; grid planners then rasterize them
      conservatively as usual, exact planners use them directly;
    - a :class:`GridMap` (bitmaps, ROS, Moving AI), a disc: a cell is blocked iff the disc placed
      at its **centre** touches an occupied cell square or the wall (exact distance from the centre
      to the squares; :func:`centre_footprint`), the tightest rule that keeps the planners' moves
      safe: a disc below half a cell blocks nothing new (it behaves like a point), and from half a
      cell on no free cell has an occupied 4-neighbour, so the disc swept along any move between
      8-neighbouring free centres whose side cells are free touches nothing (along a move, the
      distance to each cell square is smallest at an end, except at the corner a diagonal cuts
      between two side cells, which are then free). From half a cell on, a diagonal whose side
      cell is blocked may still be one the disc fits along (the two free cells touch only at a
      corner): :func:`corner_diagonals` checks each such diagonal exactly (distance from the segment
      between the centres to the occupied squares more than ``r``) and the result's
      :attr:`GridMap.diagonals <gridfield.core.grid.GridMap.diagonals>` holds those it fits along (None
      when there is none), so the grid planners' discrete moves (``wavefront``,
      ``wavefront-octile``) are exactly the moves the disc fits along. Such a passage has no width
      for a planner that moves or spreads its field continuously (``potential``, ``fmm``,
      ``harmonic``, ``navfn``, ``visibility``): :func:`gridfield.planners.plan` says so when it is
      the reason a run does not reach. A point between centres (a continuous follower's step)
      keeps at least ``r - h / sqrt(2)`` of clearance. A polygon: the occupancy dilated by
      :func:`conservative_footprint` (no configuration at which the robot touches an occupied cell
      stays free; the wall border grows too). A disc as large as the map's diagonal (with an
      obstacle or a wall) is refused at once, and every footprint is sized by the size guard
      before it is built. Its ``world``, if any, becomes the world's C-space.

    Parameters
    ----------
    target : World or GridMap
    robot : Robot, float or (N, 2) array_like or None
        A radius, a convex polygon around the reference point (the origin of its vertices), or
        None (a point robot: ``target`` is returned unchanged).
    headings : int, optional
        For a robot that turns: the number of heading bins (2 to
        :data:`~gridfield.geometry.cspace.MAX_HEADINGS`); the result is then a :class:`PoseMap`, the
        pose grid ``[heading, row, col]`` (:func:`~gridfield.geometry.cspace.heading_occupancy`; a world
        is rasterized at its resolution first). None or 1: the robot translates at heading 0 (as without
        it).

    Returns
    -------
    World, GridMap or PoseMap
        Of the same type as ``target`` (a :class:`PoseMap` with ``headings`` >= 2); a world's ``robot`` is
        cleared (it has been applied) and a grid's ``meta["robot"]`` describes the robot.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((5, 7), bool); occ[2, 3] = True
    >>> apply_robot(GridMap(Grid((5, 7), 1.0), occ), 0.5).occupied.astype(int)  # touches the square at 0.5
    array([[0, 0, 0, 0, 0, 0, 0],
           [0, 0, 0, 1, 0, 0, 0],
           [0, 0, 1, 1, 1, 0, 0],
           [0, 0, 0, 1, 0, 0, 0],
           [0, 0, 0, 0, 0, 0, 0]])
    >>> apply_robot(GridMap(Grid((5, 7), 1.0), occ), 0.3).occupied.sum()  # below half a cell: as a point
    np.int64(1)
    >>> from gridfield.io import read_world, bundled_map
    >>> c = apply_robot(read_world(bundled_map("seed000.yaml")), 0.3)
    >>> [round(v, 3) for v in c.obstacles[0].geometry.bounds]
    [3.7, 9.7, 12.3, 18.3]
    """
    r = as_robot(robot)
    n = 1 if headings is None else check_headings(headings)
    if n > 1:
        return _turning(target, r, n)
    if isinstance(target, World):
        if r is None or r.is_point:
            return dataclasses.replace(target, robot=None)
        xmin, ymin, xmax, ymax = target.bounds
        diag = math.hypot(xmax - xmin, ymax - ymin)
        inside = shapely.box(xmin, ymin, xmax, ymax)
        if r.extent >= diag and (target.border == "wall" or (r.radius is not None and any(
                ob.geometry.intersects(inside) for ob in target.obstacles))):
            raise GridfieldError(
                f"{target.source or 'the world'}: the robot ({r.describe()}) is larger than the world's diagonal "
                f"({diag:.4g}): wherever it is placed it touches {'the wall' if target.border == 'wall' else 'an obstacle'}"
                ", so nothing is free; use a smaller robot")
        try:
            grown = (inflate_world(target, r.radius) if r.radius is not None
                     else cspace_world(target, cast("NDArray[np.float64]", r.vertices)))
        except shapely.errors.GEOSException as e:
            raise GridfieldError(f"{target.source or 'the world'}: cannot build the configuration space of the robot "
                                 f"({r.describe()}): the geometry library failed ({str(e).splitlines()[0][:120]}); "
                                 "use a robot of a size comparable to the world") from None
        return dataclasses.replace(grown, obstacles=(*grown.obstacles, *_wall_strips(target, r)), robot=None)
    if not isinstance(target, GridMap):
        raise ParameterError(f"apply_robot needs a World or a GridMap, got {type(target).__name__}")
    if r is None or r.is_point:
        return target
    _refuse_larger_than_the_map(target, r)
    if target.grid.border != "wall" and not target.occupied.any():
        out = target  # nothing to grow, whatever the robot's size
    else:
        footprint = (centre_footprint(r.radius, target.grid.resolution) if r.radius is not None
                     else conservative_footprint(r, target.grid.resolution))
        out = _dilate_gridmap(target, _runs(footprint))
    world = apply_robot(target.world, r) if isinstance(target.world, World) else target.world
    meta = dict(target.meta)
    meta["robot"] = r.describe()
    diagonals = (corner_diagonals(target.occupied, out.occupied, r.radius, target.grid.resolution)
                 if r.radius is not None else None)
    return out.with_occupied(out.occupied, world=world, meta=meta, diagonals=diagonals)


def _turning(target: World | GridMap, r: Robot | None, headings: int) -> PoseMap:
    """:func:`apply_robot` for a robot that turns: the pose grid of the (rasterized) workspace."""
    if r is None or r.is_point:
        raise ParameterError("headings need a robot with a shape (--robot): a point robot does not turn")
    if isinstance(target, World):
        if target.resolution is None:
            raise ParameterError(f"{target.source or 'the world'}: a turning robot plans on a grid, and the world "
                                 "has no resolution; give one (--resolution)")
        gm = rasterize(dataclasses.replace(target, robot=None), target.resolution)
    elif isinstance(target, GridMap):
        gm = target
    else:
        raise ParameterError(f"apply_robot needs a World or a GridMap, got {type(target).__name__}")
    if gm.ndim != 2:
        raise ParameterError(f"{gm.source or 'the map'} is a voxel grid: a turning robot plans on a 2-D map "
                             "(its headings make the pose grid 3-D)")
    _refuse_larger_than_the_map(gm, r)
    return pose_map(gm, r, headings)


def _sweep_offsets(radius: float, resolution: float) -> list[tuple[list[int], list[int]]]:
    """For the two diagonals of a 2x2 block (bit 0: from the centre of cell ``(0, 0)`` to that of
    ``(1, 1)``; bit 1: ``(0, 1)`` to ``(1, 0)``), the offsets ``(rows, cols)`` from the block's first
    cell of the cell squares within ``radius`` of the diagonal (the same ``1e-9`` margin as
    :func:`centre_footprint`) but farther than that from both end centres: the squares only the
    middle of the move can touch."""
    h, r = float(resolution), float(radius)
    m = math.ceil(r / h) + 1
    grid_a, grid_b = np.meshgrid(np.arange(-m, m + 2), np.arange(-m, m + 2), indexing="ij")
    a, b = grid_a.ravel(), grid_b.ravel()
    boxes = shapely.box(b, a, b + 1, a + 1)  # (x = col, y = row) in cell units
    limit = (r / h) ** 2 * (1 + 1e-9)
    out = []
    for (y0, x0), (y1, x1) in (((0.5, 0.5), (1.5, 1.5)), ((0.5, 1.5), (1.5, 0.5))):
        near = shapely.distance(shapely.LineString([(x0, y0), (x1, y1)]), boxes) ** 2 <= limit
        ends = [np.maximum(np.abs(b + 0.5 - x) - 0.5, 0.0) ** 2 + np.maximum(np.abs(a + 0.5 - y) - 0.5, 0.0) ** 2
                <= limit for x, y in ((x0, y0), (x1, y1))]
        keep = near & ~ends[0] & ~ends[1]
        out.append((a[keep].tolist(), b[keep].tolist()))
    return out


def corner_diagonals(occupied: NDArray[np.bool_], blocked: NDArray[np.bool_], radius: float,
                     resolution: float) -> NDArray[np.uint8] | None:
    """The diagonal moves a disc robot fits along although a side cell is blocked in its C-space.

    The grid planners keep Moving AI's rule on the configuration space (a diagonal step needs both
    side cells free), which is exact below half a cell (a blocked side cell is then an occupied
    square whose corner the diagonal touches) but, from half a cell on, refuses diagonals the disc
    fits along: two free cells of the C-space touching only at a corner. This finds them: for each
    2x2 block whose diagonal joins two free cells of ``blocked`` with a blocked side cell, the
    exact distance from the segment between the two centres to the occupied squares of
    ``occupied`` must exceed ``radius`` (the squares within ``radius`` of an end are free, the
    ends being free; the wall is farthest at an end, so it needs no check). Vectorized over the
    candidate blocks (one pass per cell square only the middle of a diagonal can touch).

    Parameters
    ----------
    occupied : ndarray of bool, shape (rows, cols)
        The workspace occupancy.
    blocked : ndarray of bool, shape (rows, cols)
        Its configuration space for the disc (:func:`apply_robot`).
    radius, resolution : float
        The disc's radius and the cell size.

    Returns
    -------
    ndarray of uint8, shape (rows - 1, cols - 1), or None
        :attr:`GridMap.diagonals <gridfield.core.grid.GridMap.diagonals>` (bit 0: ``(r, c) <-> (r+1, c+1)``,
        bit 1: ``(r, c+1) <-> (r+1, c)``); None when there is none (always below half a cell).

    Examples
    --------
    >>> occ = np.zeros((2, 4), bool); occ[1, 0] = occ[0, 3] = True
    >>> blocked = np.array([[1, 0, 1, 1], [1, 1, 0, 1]], bool)  # the C-space of a disc of 0.6
    >>> corner_diagonals(occ, blocked, 0.6, 1.0)  # (0, 1) <-> (1, 2): bit 0 of block (0, 1)
    array([[0, 1, 0]], dtype=uint8)
    >>> corner_diagonals(occ, blocked, 0.4, 1.0) is None  # below half a cell: never
    True
    """
    rows, cols = blocked.shape
    if rows < 2 or cols < 2 or not 2 * float(radius) >= float(resolution):
        return None
    free = ~blocked
    b00, b01, b10, b11 = blocked[:-1, :-1], blocked[:-1, 1:], blocked[1:, :-1], blocked[1:, 1:]
    candidates = (free[:-1, :-1] & free[1:, 1:] & (b01 | b10),  # bit 0
                  free[:-1, 1:] & free[1:, :-1] & (b00 | b11))  # bit 1
    if not (candidates[0].any() or candidates[1].any()):
        return None
    sweeps = _sweep_offsets(radius, resolution)
    pad = max((max(map(abs, a + b), default=0) for a, b in sweeps), default=0) + 1
    occ = np.pad(np.asarray(occupied, dtype=bool), pad)  # outside: free (the wall is farthest at an end)
    out = np.zeros((rows - 1, cols - 1), np.uint8)
    for bit, (cand, (da, db)) in enumerate(zip(candidates, sweeps, strict=True)):
        i, j = np.nonzero(cand)
        ok = np.ones(len(i), bool)
        for a, b in zip(da, db, strict=True):
            ok &= ~occ[i + (a + pad), j + (b + pad)]
        out[i[ok], j[ok]] |= np.uint8(1 << bit)
    return out if out.any() else None


def _refuse_larger_than_the_map(target: GridMap, robot: Robot) -> None:
    """A disc at least as large as the map's diagonal touches an occupied cell (or the wall) wherever it is
    placed, as does, with a wall, any robot reaching farther than the diagonal: say so before building
    anything."""
    g = target.grid
    diag = g.resolution * math.hypot(g.rows, g.cols)
    wall = g.border == "wall"
    if (robot.radius is not None and robot.radius >= diag and (wall or bool(target.occupied.any()))) or (
            wall and robot.extent > diag):
        raise GridfieldError(
            f"{target.source or 'the map'}: the robot ({robot.describe()}) is larger than the map's diagonal "
            f"({diag:.4g}): wherever it is placed it touches {'the wall' if wall else 'an occupied cell'}, so no "
            "cell is free; use a smaller robot")


def _grid_distance(gridmap: GridMap, p: NDArray[np.float64], reach: float) -> float:
    """Exact distance from ``p`` to the nearest occupied cell square (or the wall) within ``reach``
    (``inf`` when none is that close)."""
    grid = gridmap.grid
    h = grid.resolution
    x0, y0 = grid.origin
    c0, c1 = math.floor((p[0] - reach - x0) / h) - 1, math.floor((p[0] + reach - x0) / h) + 1
    r0, r1 = math.floor((p[1] - reach - y0) / h) - 1, math.floor((p[1] + reach - y0) / h) + 1
    c0, r0 = max(c0, 0), max(r0, 0)
    c1, r1 = min(c1, grid.cols - 1), min(r1, grid.rows - 1)
    best = math.inf
    if c0 <= c1 and r0 <= r1:
        rows, cols = np.nonzero(gridmap.occupied[r0:r1 + 1, c0:c1 + 1])
        if len(rows):
            cx = x0 + (cols + c0 + 0.5) * h
            cy = y0 + (rows + r0 + 0.5) * h
            dx = np.maximum(np.abs(p[0] - cx) - h / 2, 0.0)
            dy = np.maximum(np.abs(p[1] - cy) - h / 2, 0.0)
            best = float(np.min(np.hypot(dx, dy)))
    if grid.border == "wall":
        xmin, ymin, xmax, ymax = grid.bounds
        best = min(best, max(0.0, min(p[0] - xmin, xmax - p[0], p[1] - ymin, ymax - p[1])))
    return best


def check_robot_point(
    target: World | GridMap,
    robot: Robot | float | ArrayLike | None,
    name: str,
    point: ArrayLike,
    cspace: World | GridMap | None = None,
) -> None:
    """Raise a :class:`GridfieldError` naming the distance when the robot placed at ``point`` collides.

    ``target`` is the workspace (before :func:`apply_robot`). A disc collides when the nearest
    obstacle is at most its radius away; a polygon when its outline placed at ``point`` meets an
    obstacle (a world's exact geometry, or a grid's occupied cell squares; the wall border
    counts). With ``cspace`` (a grid from :func:`apply_robot`), a point whose cell the conservative
    grid configuration space blocks is also refused, with the distance and the cell size.
    A point outside the map is left to the planner's own check.

    Parameters
    ----------
    target : World or GridMap
        The workspace.
    robot : Robot, float, (N, 2) array_like or None
        As for :func:`apply_robot`; None checks nothing.
    name : str
        The point's name (``"start"``, ``"goal"``), for the message.
    point : (x, y)
    cspace : World or GridMap, optional
        The configuration space already built from ``target``.

    Returns
    -------
    None
        Nothing when the robot fits at ``point``.

    Raises
    ------
    GridfieldError
        When the robot placed at ``point`` touches an obstacle (or the grid C-space blocks it).

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> w = read_world(bundled_map("seed000.yaml"))
    >>> check_robot_point(w, 0.5, "start", (1, 10))
    >>> check_robot_point(w, 4, "start", (1, 10))
    Traceback (most recent call last):
    ...
    gridfield.core.errors.GridfieldError: start (1, 10) is 3.61 from obstacle 1, within the robot (disc of radius 4); ...
    """
    r = as_robot(robot)
    p = np.asarray(point, dtype=float).reshape(-1)
    if r is None or p.shape != (2,) or not np.all(np.isfinite(p)):
        return
    where = f"{name} ({p[0]:g}, {p[1]:g})"
    if isinstance(target, World):
        _check_in_world(target, r, where, p)
    elif isinstance(target, GridMap) and target.grid.contains(p)[0]:
        if not target.is_free(p)[0]:  # the point itself is in an occupied cell: no robot size helps
            (cspace if isinstance(cspace, GridMap) else target).check_point(name, p)
        _check_on_grid(target, r, where, p, cspace)


_HINT = "move it or make the robot smaller"


def _check_in_world(target: World, r: Robot, where: str, p: NDArray[np.float64]) -> None:
    """:func:`check_robot_point` on a world's exact geometry."""
    xmin, ymin, xmax, ymax = target.bounds
    if not (xmin <= p[0] <= xmax and ymin <= p[1] <= ymax):
        return
    dists = [(float(ob.distance(p[None, :])[0]), f"obstacle {ob.id}") for ob in target.obstacles]
    if target.border == "wall":
        dists.append((float(min(p[0] - xmin, xmax - p[0], p[1] - ymin, ymax - p[1])), "the wall"))
    if not dists:
        return
    d, what = min(dists)
    if d <= 0.0:  # the point itself is not free: no robot size helps
        raise GridfieldError(f"{where} lies {'on' if what == 'the wall' else 'inside'} {what}")
    if r.radius is not None:
        if d <= r.radius:
            raise GridfieldError(f"{where} is {d:.3g} from {what}, within the robot ({r.describe()}); {_HINT}")
        return
    placed = r.outline(p)
    for ob in target.obstacles:
        hit = (placed.distance(Point(ob.center)) <= ob.radius
               if ob.kind == "circle" and ob.center is not None and ob.radius is not None
               else placed.intersects(ob.geometry))
        if hit:
            raise GridfieldError(f"{where}: the robot ({r.describe()}) placed there overlaps obstacle {ob.id} "
                                 f"(the reference point is {float(ob.distance(p[None, :])[0]):.3g} from it); {_HINT}")
    if target.border == "wall":
        bx0, by0, bx1, by1 = placed.bounds
        if min(bx0 - xmin, xmax - bx1, by0 - ymin, ymax - by1) <= 0:
            raise GridfieldError(f"{where}: the robot ({r.describe()}) placed there touches the wall; {_HINT}")


def _check_on_grid(target: GridMap, r: Robot, where: str, p: NDArray[np.float64],
                   cspace: World | GridMap | None) -> None:
    """:func:`check_robot_point` on a grid's occupied cells (and its grid C-space, when given)."""
    h = target.grid.resolution
    d = _grid_distance(target, p, r.extent + 2 * h)
    if r.radius is not None:
        if d <= r.radius:
            raise GridfieldError(f"{where} is {d:.3g} from the nearest occupied cell, within the robot "
                                 f"({r.describe()}); {_HINT}")
    else:
        placed = r.outline(p)
        hits = rasterize_geometry(placed, target.grid) & target.occupied
        xmin, ymin, xmax, ymax = target.grid.bounds
        bx0, by0, bx1, by1 = placed.bounds
        outside = target.grid.border == "wall" and min(bx0 - xmin, xmax - bx1, by0 - ymin, ymax - by1) <= 0
        if hits.any() or outside:
            raise GridfieldError(f"{where}: the robot ({r.describe()}) placed there overlaps occupied cells "
                                 f"(the reference point is {d:.3g} from the nearest); {_HINT}")
    if isinstance(cspace, GridMap) and not cspace.is_free(p)[0]:
        if r.radius is not None:
            centre = target.grid.cell_to_world(np.asarray([target.grid.cell_of(float(p[0]), float(p[1]))]))[0]
            dc = _grid_distance(target, centre, r.extent + 2 * h)
            raise GridfieldError(f"{where} is {d:.3g} from the nearest occupied cell, enough for the robot "
                                 f"({r.describe()}), but the centre of its cell ({centre[0]:g}, {centre[1]:g}) is "
                                 f"{dc:.3g} from it, and planners move between cell centres; move it to a cell "
                                 "whose centre is farther from the obstacles")
        raise GridfieldError(f"{where} is {d:.3g} from the nearest occupied cell, enough for the robot "
                             f"({r.describe()}), but its cell is blocked in the grid's configuration space, which "
                             f"is conservative by up to one cell ({h:g}); move it a little or use a finer grid")


def workspace_clearance(target: World | GridMap, points: ArrayLike) -> float:
    """Smallest distance from the path ``points`` to the workspace obstacles (before the robot grew them).

    A world: :meth:`World.clearance` (exact, segments included). A grid: the exact distance from
    each vertex to the nearest occupied cell square (the wall border counts). For a disc robot
    of radius ``r`` planned in the configuration space, this is at least ``r``, up to the
    follower's steps between vertices.

    Parameters
    ----------
    target : World or GridMap
        The workspace.
    points : (N, 2) array_like
        The path's vertices, world coordinates.

    Returns
    -------
    float
        The smallest distance (``inf`` with no obstacle and an open border).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((4, 4), bool); occ[0, 0] = True
    >>> round(workspace_clearance(GridMap(Grid((4, 4), 1.0), occ), [[3.0, 1.0], [3.0, 4.0]]), 6)
    2.0
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if isinstance(target, World):
        return float(target.clearance(pts))
    if not isinstance(target, GridMap):
        raise ParameterError(f"workspace_clearance needs a World or a GridMap, got {type(target).__name__}")
    from scipy.spatial import cKDTree

    grid = target.grid
    h = grid.resolution
    best = math.inf
    if grid.border == "wall":
        xmin, ymin, xmax, ymax = grid.bounds
        best = float(np.min(np.maximum(np.minimum.reduce(
            [pts[:, 0] - xmin, xmax - pts[:, 0], pts[:, 1] - ymin, ymax - pts[:, 1]]), 0.0)))
    cells = np.argwhere(target.occupied)
    if len(cells) == 0 or len(pts) == 0:
        return best
    centres = grid.cell_to_world(cells)
    tree = cKDTree(centres)
    d0, _ = tree.query(pts)
    # a square nearer than the nearest centre's square has its centre within d0 + h / sqrt(2)
    cand = tree.query_ball_point(pts, d0 + h * math.sqrt(0.5) + 1e-12)
    lens = np.fromiter((len(c) for c in cand), dtype=np.intp, count=len(cand))
    idx = np.concatenate([np.asarray(c, dtype=np.intp) for c in cand])
    owner = np.repeat(np.arange(len(pts)), lens)
    dx = np.maximum(np.abs(pts[owner, 0] - centres[idx, 0]) - h / 2, 0.0)
    dy = np.maximum(np.abs(pts[owner, 1] - centres[idx, 1]) - h / 2, 0.0)
    return min(best, float(np.min(np.hypot(dx, dy))))


def robot_clearance(target: World | GridMap, robot: Robot | float | ArrayLike, points: ArrayLike) -> float | None:
    """Smallest distance between the robot's body, placed at each path vertex, and the workspace obstacles.

    A world: exact (shapely; circles analytic; the wall counts). A grid: for a disc,
    :func:`workspace_clearance` less the radius; for a polygon on a grid, None (not computed).
    0 means the robot touches an obstacle at some vertex.

    Parameters
    ----------
    target : World or GridMap
        The workspace.
    robot : Robot, float or (N, 2) array_like
        As for :func:`apply_robot`.
    points : (N, 2) array_like
        The path's vertices (positions of the reference point).

    Returns
    -------
    float or None
        The smallest distance; None for a polygon robot on a grid.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}]})
    >>> round(robot_clearance(w, [[0, -0.5], [1, -0.5], [1, 0.5], [0, 0.5]], [[2, 5], [2, 8]]), 6)
    1.0
    """
    r = as_robot(robot)
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if r is None or len(pts) == 0:
        return workspace_clearance(target, pts) if r is None else math.inf
    if r.radius is not None and not isinstance(target, World):
        return max(workspace_clearance(target, pts) - r.radius, 0.0)
    if not isinstance(target, World):
        return None
    if r.radius is not None:
        return max(float(target.distance(pts).min()) - r.radius, 0.0)
    assert r.vertices is not None
    v = r.vertices
    if len(v) >= 3:
        bodies = shapely.polygons(pts[:, None, :] + v[None])
    elif len(v) == 2:
        bodies = shapely.linestrings(pts[:, None, :] + v[None])
    else:
        bodies = shapely.points(pts + v[0])
    best = math.inf
    for ob in target.obstacles:
        if ob.kind == "circle" and ob.center is not None and ob.radius is not None:
            d = np.maximum(shapely.distance(bodies, Point(ob.center)) - ob.radius, 0.0)
        else:
            d = shapely.distance(bodies, ob.geometry)
        best = min(best, float(np.min(d)))
    if target.border == "wall":
        xmin, ymin, xmax, ymax = target.bounds
        b = shapely.bounds(bodies)
        best = min(best, float(np.maximum(np.minimum.reduce(
            [b[:, 0] - xmin, xmax - b[:, 2], b[:, 1] - ymin, ymax - b[:, 3]]), 0.0).min()))
    return best
