"""The pose grid of a turning robot: :class:`PoseMap` (private; import from :mod:`gridfield.geometry.cspace`).

A :class:`PoseMap` is the 3-D configuration space ``[heading, row, col]`` of a robot that turns, over a
2-D workspace map: its occupancy (:func:`heading_occupancy`, one slice per heading bin, each covering
its whole bin), the workspace, the robot and the turning cost. It hands the 3-D planners a voxel
:class:`~gridfield.core.grid.GridMap` (:meth:`PoseMap.voxels`) with the heading as axis 0, periodic, and
the per-axis spacing of the moves (:meth:`PoseMap.spacing`), and converts poses ``(x, y, theta)`` to
cells and back.

Turning cost: a turn by ``a`` radians costs ``turn_radius * a`` in world units, the arc that the
robot's farthest point (from the reference point) travels; a move of ``(dk, dr, dc)`` cells costs the
Euclidean length of ``(turn_radius * dk * 2 pi / N, dr * h, dc * h)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core.errors import GridfieldError, ParameterError, shorten
from ...core.grid import Grid, GridMap
from ..world import Robot
from ._headings import heading_centres, heading_occupancy, turn_radius

__all__ = ["PoseMap", "pose_map", "wrap_angle"]


def wrap_angle(theta: ArrayLike) -> NDArray[np.float64]:
    """Angles wrapped into ``[-pi, pi)``.

    Parameters
    ----------
    theta : array_like
        Angles in radians.

    Returns
    -------
    ndarray of float64

    Examples
    --------
    >>> wrap_angle([0.0, 3.5, -4.0]).round(4).tolist()
    [0.0, -2.7832, 2.2832]
    """
    t = np.asarray(theta, dtype=np.float64)
    out: NDArray[np.float64] = (t + math.pi) % (2.0 * math.pi) - math.pi
    return out


@dataclass(frozen=True, eq=False)
class PoseMap:
    """The configuration space of a turning robot: a pose grid ``[heading, row, col]`` over a 2-D map.

    Attributes
    ----------
    workspace : GridMap
        The 2-D map the robot moves in (before the robot grew its obstacles).
    occupied : ndarray of bool, shape (headings, rows, cols)
        Slice ``k``: the cell centres from which the robot, turned anywhere in heading bin ``k``,
        touches an occupied cell square or the wall (:func:`~gridfield.geometry.cspace.heading_occupancy`).
    robot : Robot
    headings : int
        Bins of the heading circle; bin ``k`` is centred on ``2 pi k / headings``.
    meta : dict
        What built it (``meta["robot"]``, ``meta["headings"]``).

    Examples
    --------
    A wall with a 1.5 m door and a 1.6 m x 0.4 m cart: the door is closed to the cart sideways, open
    lengthwise.

    >>> occ = np.zeros((8, 8), bool); occ[4, :2] = True; occ[4, 5:] = True
    >>> cart = Robot(vertices=[[-0.8, -0.2], [0.8, -0.2], [0.8, 0.2], [-0.8, 0.2]])
    >>> pm = pose_map(GridMap(Grid((8, 8), 0.5), occ), cart, 8)
    >>> pm.shape, pm.cell_of_pose((1.75, 2.25, math.pi / 2)), round(pm.turn_cost, 4)
    ((8, 8, 8), (2, 4, 3), 0.6477)
    >>> bool(pm.occupied[0, 4, 3]), bool(pm.occupied[2, 4, 3])
    (True, False)
    """

    workspace: GridMap
    occupied: NDArray[np.bool_]
    robot: Robot
    headings: int
    meta: dict[str, Any] = field(default_factory=dict)
    #: Work on this occupancy that the planners share (its clearance, ...), filled on first use.
    cache: dict[str, Any] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        want = (self.headings, *self.workspace.shape)
        if self.occupied.shape != want:
            raise GridfieldError(f"PoseMap.occupied has shape {self.occupied.shape}, expected {want}")

    def __repr__(self) -> str:
        return (f"PoseMap(headings={self.headings}, shape={self.workspace.shape}, robot={self.robot.describe()!r}, "
                f"free={1 - float(self.occupied.mean()):.1%})")

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(headings, rows, cols)``."""
        n, r, c = self.occupied.shape
        return n, r, c

    @property
    def grid(self) -> Grid:
        """The workspace's 2-D grid."""
        return self.workspace.grid

    @property
    def bin_width(self) -> float:
        """Radians per heading bin."""
        return 2.0 * math.pi / self.headings

    @property
    def turn_radius(self) -> float:
        """The robot's farthest point from its reference point."""
        return turn_radius(self.robot)

    @property
    def turn_cost(self) -> float:
        """World length charged for a turn by one heading bin: ``turn_radius * bin_width``."""
        return self.turn_radius * self.bin_width

    def spacing(self) -> tuple[float, float, float]:
        """The cost of one step along each axis ``(heading, row, col)``, in cells of the workspace."""
        return self.turn_cost / self.grid.resolution, 1.0, 1.0

    def voxels(self) -> GridMap:
        """The occupancy as a voxel :class:`GridMap` for the 3-D kernels: axis 0 is the heading (its
        geometry along z is a placeholder: use :meth:`cell_of_pose` and :meth:`pose_of_cell`)."""
        g = self.grid
        return GridMap(Grid(self.shape, g.resolution, origin=(g.origin[0], g.origin[1], 0.0), border=g.border),
                       self.occupied, source=self.workspace.source,
                       meta={**self.meta, "periodic_axes": (0,), "spacing": self.spacing()})

    def voxel_point(self, cell: tuple[int, int, int]) -> NDArray[np.float64]:
        """A pose cell ``(heading bin, row, col)`` as a point of :meth:`voxels` (its centre, the bin on the
        placeholder z axis), the form the 3-D kernels take."""
        g = self.grid
        k, r, c = cell
        return np.array([g.origin[0] + (c + 0.5) * g.resolution, g.origin[1] + (r + 0.5) * g.resolution,
                         (k + 0.5) * g.resolution])

    def heading_bin(self, theta: float) -> int:
        """The bin holding a heading (radians, any turn)."""
        return int(math.floor(float(theta) / self.bin_width + 0.5)) % self.headings

    def cell_of_pose(self, pose: ArrayLike) -> tuple[int, int, int] | None:
        """``(heading bin, row, col)`` of a pose ``(x, y, theta)``, or None outside the map."""
        p = np.asarray(pose, dtype=np.float64).reshape(3)
        cell = self.grid.cell_of(p[0], p[1])
        if cell is None or not math.isfinite(p[2]):
            return None
        return self.heading_bin(p[2]), int(cell[0]), int(cell[1])

    def pose_of_cell(self, cells: ArrayLike) -> NDArray[np.float64]:
        """Poses ``(x, y, theta)`` (theta in ``[-pi, pi)``) of cells ``(heading bin, row, col)``, shape (N, 3)."""
        c = np.asarray(cells).reshape(-1, 3)
        xy = self.grid.cell_to_world(c[:, 1:])
        return np.column_stack([xy, wrap_angle(heading_centres(self.headings)[c[:, 0] % self.headings])])

    def around(self, x: float, y: float) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
        """The rows and columns of the four cell centres around a position (the dual cell holding it;
        clamped to the grid within half a cell of its edge)."""
        g = self.grid
        u = (float(x) - g.origin[0]) / g.resolution - 0.5
        v = (float(y) - g.origin[1]) / g.resolution - 0.5
        # a position on a centre's row or column needs only that one (floor == ceil; centres computed in
        # floating point count as on it)
        u = round(u) if abs(u - round(u)) < 1e-9 else u
        v = round(v) if abs(v - round(v)) < 1e-9 else v
        cols = np.clip([math.floor(u), math.ceil(u)], 0, g.cols - 1)
        rows = np.clip([math.floor(v), math.ceil(v)], 0, g.rows - 1)
        return rows, cols

    def fitting_bins(self, x: float, y: float) -> NDArray[np.intp]:
        """The heading bins in which the robot fits at the four cell centres around ``(x, y)``: there a pose
        is safe, and so is the motion from it to those centres within its bin."""
        rows, cols = self.around(x, y)
        blocked = self.occupied[:, rows[:, None], cols[None, :]].reshape(self.headings, -1).any(axis=1)
        return np.flatnonzero(~blocked)

    def check_pose(self, name: str, pose: ArrayLike, *, heading_given: bool = True) -> NDArray[np.float64]:
        """Validate a start or goal pose: inside the map, and the robot clear of the obstacles there and at
        the four cell centres around it (the planners leave a pose for one of them).

        Returns the pose as ``(3,)``; without ``heading_given`` (a goal ``X Y``) the heading is not checked,
        only that the robot fits there at some heading.

        Raises
        ------
        GridfieldError
            Naming the pose and what the robot touches.
        """
        p = np.asarray(pose, dtype=np.float64).reshape(-1)
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise ParameterError(f"{name} must be three finite numbers X Y THETA, got {shorten(pose)}")
        self.workspace.check_point(name, p[:2])  # outside the map, or inside an occupied cell
        k, r, c = self.cell_of_pose(p)  # type: ignore[misc]  # inside: checked above
        where = f"{name} ({p[0]:g}, {p[1]:g}, {p[2]:g})"
        fit = self.fitting_bins(p[0], p[1])
        if heading_given:
            if k not in fit:
                hint = (f"; headings that fit there: {_bins_text(self, fit)}" if fit.size else
                        "; no heading fits there")
                if self.occupied[k, r, c]:
                    raise GridfieldError(f"{where}: the robot ({self.robot.describe()}) turned to {p[2]:g} rad "
                                         f"(heading bin {k} of {self.headings}) touches {self._what(p)}{hint}")
                raise GridfieldError(f"{where}: the robot ({self.robot.describe()}) fits at the centre of its cell, "
                                     f"but not at every cell centre around the pose (planners move between them; "
                                     f"the nearest obstacle is {self._what(p)}){hint}; move it a little or use a "
                                     "finer grid")
        elif fit.size == 0:
            raise GridfieldError(f"{name} ({p[0]:g}, {p[1]:g}): the robot ({self.robot.describe()}) touches "
                                 f"{self._what(p)} there at every heading")
        return p

    def _what(self, p: NDArray[np.float64]) -> str:
        """The obstacle (nearest occupied cell, or the wall) the robot at this pose reaches."""
        gm = self.workspace
        h = gm.grid.resolution
        rr, cc = np.nonzero(gm.occupied)
        if rr.size == 0:
            return "the wall"
        x = gm.grid.origin[0] + (cc + 0.5) * h
        y = gm.grid.origin[1] + (rr + 0.5) * h
        d = np.hypot(x - p[0], y - p[1])
        i = int(np.argmin(d))
        txt = f"the occupied cell at ({x[i]:g}, {y[i]:g}), {max(float(d[i]) - h / 2, 0.0):.3g} from the reference point"
        if gm.grid.border == "wall":
            xmin, ymin, xmax, ymax = gm.grid.bounds
            dw = min(p[0] - xmin, xmax - p[0], p[1] - ymin, ymax - p[1])
            if dw < float(d[i]) - h / 2:
                txt = f"the wall, {dw:.3g} from the reference point"
        return txt


def _bins_text(pm: PoseMap, bins: NDArray[np.intp]) -> str:
    deg = np.degrees(wrap_angle(heading_centres(pm.headings)[bins]))
    shown = ", ".join(f"{d:.0f}" for d in deg[:8])
    return f"{shown}{', ...' if len(deg) > 8 else ''} degrees"


def pose_map(gridmap: GridMap, robot: Robot, headings: int) -> PoseMap:
    """The :class:`PoseMap` of a 2-D map for a turning robot.

    Parameters
    ----------
    gridmap : GridMap
        The 2-D workspace.
    robot : Robot
        A convex polygon (or a disc: every slice is then the same).
    headings : int
        Bins of the heading circle, 2 to :data:`~gridfield.geometry.cspace.MAX_HEADINGS`.

    Returns
    -------
    PoseMap

    Examples
    --------
    >>> cart = Robot(vertices=[[-0.8, -0.2], [0.8, -0.2], [0.8, 0.2], [-0.8, 0.2]])
    >>> pose_map(GridMap(Grid((10, 10), 0.5), np.zeros((10, 10), bool)), cart, 16)
    PoseMap(headings=16, shape=(10, 10), robot='polygon -0.8,-0.2 0.8,-0.2 0.8,0.2 -0.8,0.2', free=100.0%)
    """
    occ = heading_occupancy(gridmap, robot, headings)
    return PoseMap(gridmap, occ, robot, int(headings), meta={**gridmap.meta, "robot": robot.describe(),
                                                             "headings": int(headings)})
