"""Navigation functions on the pose grid of a turning robot (:class:`~gridfield.geometry.cspace.PoseMap`).

The field is the 3-D wavefront of :mod:`gridfield.fields.navigation3d` on the pose grid ``[heading,
row, col]``: 26 neighbouring poses, the heading axis periodic, a move needing every pose of its
bounding box free (which makes every move safe for the robot, :mod:`gridfield.geometry.cspace`), a step
costing the Euclidean length of ``(turn_cost * dk, h * dr, h * dc)`` (``turn_cost``: the arc the
robot's farthest point travels in one heading bin). With the ``potential`` model's clearance band
(the 2-D ``nf1`` rule, the same parameters ``clearance_band`` and ``band_gain``) the front slows down
near the C-obstacles of each heading slice (``D``: the distance in x, y to the nearest blocked pose of
the same heading), so that the path keeps off them where that is cheap; the ``wavefront-octile`` model
is the plain shortest way. Either way the field has one minimum on each free component, the goal (or
the goal position at any heading): every settled pose but the goal has a lower neighbour it may move
to, its Dijkstra parent.

A goal given without a heading accepts any: the field is built from the goal pose whose heading is the
nearest to reach from the start (found by a first wavefront from the start that stops once a goal pose
is settled: the best one is settled by then).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import GridfieldError
from ..core.grid import GridMap
from ..distance.brushfire import brushfire
from ..geometry.cspace import PoseMap
from .navigation3d import voxel_wavefront

__all__ = ["PoseField", "pose_clearance", "pose_field"]

#: The clearance band's defaults when the parameters leave them unset (cells; the 2-D nf1 registry's).
DEFAULT_BAND_CELLS = 6.0
DEFAULT_BAND_GAIN = 0.5


@dataclass(frozen=True, eq=False)
class PoseField:
    """A navigation function over the poses of a turning robot.

    Attributes
    ----------
    poses : PoseMap
    potential : ndarray of float64, shape (headings, rows, cols)
        Cost to the goal (world units); ``inf`` on blocked and unreached (or, for a planned query,
        unsettled) poses.
    goal : (x, y, theta)
        The goal pose the field descends to (its heading chosen when the goal had none).
    params : dict
        ``model`` (``"potential"`` or ``"wavefront-octile"``), ``clearance_band``, ``band_gain``.

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.geometry.cspace import pose_map
    >>> from gridfield.geometry.world import Robot
    >>> pm = pose_map(GridMap(Grid((6, 6), 0.5), np.zeros((6, 6), bool)), Robot(radius=0.2), 4)
    >>> f = pose_field(pm, (1.25, 1.25, 0.0))
    >>> f.potential.shape, float(f.potential[0, 2, 2]), f.goal
    ((4, 6, 6), 0.0, (1.25, 1.25, 0.0))
    """

    poses: PoseMap
    potential: NDArray[np.float64]
    goal: tuple[float, float, float]
    params: dict[str, Any] = field(default_factory=dict)

    def __repr__(self) -> str:
        g = ", ".join(f"{v:.4g}" for v in self.goal)
        return f"PoseField(shape={self.potential.shape}, goal=({g}), model={self.params.get('model')!r})"


def pose_clearance(pm: PoseMap) -> NDArray[np.float64]:
    """Per pose, the distance (world units, in x and y) to the nearest blocked pose of the same heading
    slice: ``inf`` in a slice with none, 0 on blocked poses.

    Parameters
    ----------
    pm : PoseMap

    Returns
    -------
    ndarray of float64, shape (headings, rows, cols)
        Read-only; computed once per pose map (kept in ``pm.cache``).

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.geometry.cspace import pose_map
    >>> from gridfield.geometry.world import Robot
    >>> occ = np.zeros((1, 6), bool); occ[0, 0] = True
    >>> pm = pose_map(GridMap(Grid((1, 6), 1.0), occ), Robot(radius=0.2), 2)
    >>> pose_clearance(pm)[0].tolist()
    [[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]]
    """
    kept = pm.cache.get("clearance")
    if kept is not None:
        return kept  # type: ignore[no-any-return]
    occ = pm.occupied
    out = np.full(occ.shape, np.inf)
    g = pm.grid
    for k in np.flatnonzero(occ.reshape(occ.shape[0], -1).any(axis=1)):  # per heading slice, each vectorized
        dm = brushfire(GridMap(g, occ[k]), metric="euclidean", compute_steps=False, compute_nearest=False,
                       compute_labels=False, compute_gvd=False)
        out[k] = dm.distance
    out.flags.writeable = False
    pm.cache["clearance"] = out
    return out


def _band_slowness(pm: PoseMap, band: float, gain: float) -> NDArray[np.float64] | None:
    if band <= 0 or gain <= 0:
        return None
    d = pose_clearance(pm)
    with np.errstate(invalid="ignore", over="ignore"):
        cost = 1.0 + gain * np.maximum(0.0, 1.0 - d / band) ** 2
    cost[~np.isfinite(d)] = 1.0
    cost[pm.occupied] = np.inf
    return cost


def pose_field(pm: PoseMap, goal: ArrayLike, params: Mapping[str, Any] | None = None, *,
               start: ArrayLike | None = None, margin: float | None = None) -> PoseField:
    """The navigation function to a goal pose (or a goal position at any heading).

    Parameters
    ----------
    pm : PoseMap
    goal : (x, y, theta) or (x, y)
        Checked by :meth:`PoseMap.check_pose`: the robot must fit there (at some heading, without theta).
    params : mapping, optional
        ``model``: ``"potential"`` (default: with the clearance band) or ``"wavefront-octile"``;
        ``clearance_band`` (world units; default 6 cells) and ``band_gain`` (default 0.5).
    start : (x, y, theta), optional
        A planned query's start: the march settles the poses up to its value plus ``margin`` and
        stops (default margin: 4 cells' length); required for a goal without heading.
    margin : float, optional

    Returns
    -------
    PoseField

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.geometry.cspace import pose_map
    >>> from gridfield.geometry.world import Robot
    >>> cart = Robot(vertices=[[-0.5, -0.2], [0.5, -0.2], [0.5, 0.2], [-0.5, 0.2]])
    >>> pm = pose_map(GridMap(Grid((8, 8), 0.5), np.zeros((8, 8), bool)), cart, 8)
    >>> f = pose_field(pm, (2.25, 2.25, 0.0), {"model": "wavefront-octile"})
    >>> round(float(f.potential[2, 4, 4]), 4), round(pm.turn_cost * 2, 4)   # a quarter turn in place
    (0.8459, 0.8459)
    """
    p = dict(params or {})
    model = p.get("model") or "potential"
    h = pm.grid.resolution
    band = p.get("clearance_band")
    band = DEFAULT_BAND_CELLS * h if band is None else float(band)
    gain = p.get("band_gain")
    gain = DEFAULT_BAND_GAIN if gain is None else float(gain)
    slow = _band_slowness(pm, band, gain) if model == "potential" else None
    vox = pm.voxels()
    spacing = (pm.turn_cost, h, h)
    g = np.asarray(goal, dtype=np.float64).reshape(-1)
    s_cell = None
    if start is not None:
        s = pm.check_pose("start", start)
        s_cell = pm.cell_of_pose(s)
    if g.size == 2:
        pm.check_pose("goal", (*g, 0.0), heading_given=False)
        if s_cell is None:
            raise GridfieldError("a goal without heading needs the start, to choose the goal's heading")
        _, r, c = pm.cell_of_pose((*g, 0.0))  # type: ignore[misc]  # inside: checked above
        free = pm.fitting_bins(g[0], g[1])
        # from the start: stopped once one goal pose is settled, every nearer one is settled too
        probe = voxel_wavefront(vox, pm.voxel_point(s_cell), spacing=spacing, periodic=True, slowness=slow,
                                stop_at=pm.voxel_point((int(free[0]), r, c)))
        k = int(free[np.argmin(probe[free, r, c])])
        gpose = (float(g[0]), float(g[1]), float(pm.pose_of_cell([[k, r, c]])[0, 2]))
        gcell = (k, r, c)
    else:
        gp = pm.check_pose("goal", g)
        gcell = pm.cell_of_pose(gp)  # type: ignore[assignment]
        gpose = (float(gp[0]), float(gp[1]), float(gp[2]))
    m = 4.0 * h if margin is None else float(margin)
    values = voxel_wavefront(vox, pm.voxel_point(gcell), spacing=spacing, periodic=True, slowness=slow,
                             stop_at=None if s_cell is None else pm.voxel_point(s_cell), margin=m)
    return PoseField(pm, values, gpose, {"model": model, "clearance_band": band, "band_gain": gain,
                                         "turn_cost": pm.turn_cost, "goal_cell": gcell})
