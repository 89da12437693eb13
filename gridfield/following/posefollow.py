"""Planning for a turning robot: descending a :class:`~gridfield.fields.posefield.PoseField` to the goal.

:func:`plan_poses` builds the field of the query (:func:`~gridfield.fields.posefield.pose_field`,
truncated at the start) and descends it: from the start pose, repeatedly to the neighbouring pose (in
x, y and heading, the heading wrapping round) of lowest value that the bounding-box rule allows
(:func:`~gridfield.fields.navigation3d.voxel_descent`), which ends at the goal on every reachable query
(each settled pose but the goal has a lower neighbour). Then the descended poses are pulled taut: a
vertex is dropped when the straight motion between its neighbours (``x``, ``y`` and the unwrapped
heading varying linearly) stays clear, judged on the **dual** pose grid (a position between four cell
centres is safe at a heading of a bin when the robot fits at all four centres for that bin, the rule
that makes the grid's own moves safe, :mod:`gridfield.geometry.cspace`); with the ``potential`` model
a shortcut also keeps at least the clearance that the descended path kept (the clearance band's
promise), measured as the distance in x, y to the nearest blocked pose of the same heading.

Between consecutive poses of the result the robot moves in a straight line in ``(x, y)`` while its
heading turns linearly along the unwrapped path; every such motion is collision-free for the robot
(``tests/test_turning.py`` checks it with shapely, placing the robot polygon along it).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.grid import Grid, GridMap
from ..core.path import Path
from ..fields.navigation3d import shortcut_path, voxel_descent
from ..fields.posefield import PoseField, pose_clearance, pose_field
from ..geometry.cspace import PoseMap, wrap_angle

__all__ = ["dual_free", "plan_poses"]


def dual_free(pm: PoseMap, floor: float = 0.0) -> NDArray[np.bool_]:
    """The poses of the dual grid a motion may pass: ``[k, r, c]`` (between the centres of rows ``r``,
    ``r + 1`` and columns ``c``, ``c + 1`` at heading bin ``k``) is free when the robot fits at all four
    centres in bin ``k`` (and, with ``floor`` > 0, each keeps at least that clearance).

    Parameters
    ----------
    pm : PoseMap
    floor : float
        The least clearance (world units, :func:`~gridfield.fields.posefield.pose_clearance`) each of the
        four centres must keep; 0: only free.

    Returns
    -------
    ndarray of bool, shape (headings, rows - 1, cols - 1)

    Examples
    --------
    >>> from gridfield.geometry.cspace import pose_map
    >>> from gridfield.geometry.world import Robot
    >>> occ = np.zeros((3, 3), bool); occ[0, 0] = True
    >>> dual_free(pose_map(GridMap(Grid((3, 3), 1.0), occ), Robot(radius=0.2), 2))[0].astype(int).tolist()
    [[0, 1], [1, 1]]
    """
    ok = ~pm.occupied
    if floor > 0:
        ok = ok & (pose_clearance(pm) >= floor * (1 - 1e-9))
    out: NDArray[np.bool_] = ok[:, :-1, :-1] & ok[:, 1:, :-1] & ok[:, :-1, 1:] & ok[:, 1:, 1:]
    return out


def _box_floor(clear: NDArray[np.float64], cells: NDArray[np.int64], n: int) -> float:
    """The least clearance over the bounding boxes of the path's moves (their 8 corner poses)."""
    if len(cells) < 2:
        return float(clear[tuple(cells.T)].min()) if len(cells) else 0.0
    a, b = cells[:-1], cells[1:]
    vals = []
    for pick in range(8):  # the 8 corners of each move's box (a fixed count, not a loop over cells)
        corner = np.where([(pick >> 2) & 1, (pick >> 1) & 1, pick & 1], b, a)
        corner[:, 0] %= n
        vals.append(clear[tuple(corner.T)])
    return float(np.min(vals))


def _taut(pm: PoseMap, cells: NDArray[np.int64], floor: float) -> NDArray[np.float64]:
    """String pulling of the descended pose cells on the dual grid; returns the kept poses as
    ``(x, y, unwrapped heading)``."""
    n = pm.headings
    h = pm.grid.resolution
    k = cells[:, 0].astype(np.float64)
    # unwrap the heading bins along the path (a step of the descent changes the bin by at most 1)
    dk = np.diff(k)
    dk = (dk + n / 2) % n - n / 2
    ku = np.concatenate([[k[0]], k[0] + np.cumsum(dk)]) if len(k) > 1 else k
    lo = math.floor(ku.min())
    copies = math.ceil((ku.max() - lo + 1) / n) + 1
    dual = dual_free(pm, floor)
    # the dual mask over the unwrapped heading range: tiled copies, starting at bin ``lo``
    tiled = np.roll(np.tile(dual, (copies, 1, 1)), -(lo % n), axis=0)
    g = pm.grid
    vox = GridMap(Grid(tiled.shape, h, origin=(g.origin[0] + 0.5 * h, g.origin[1] + 0.5 * h, 0.0)), ~tiled)
    # points of the dual voxel map: x, y as in the workspace, z = (bin - lo + 0.5) * h
    pts = np.column_stack([g.origin[0] + (cells[:, 2] + 0.5) * h, g.origin[1] + (cells[:, 1] + 0.5) * h,
                           (ku - lo + 0.5) * h])
    kept = shortcut_path(vox, pts)
    theta = (kept[:, 2] / h - 0.5 + lo) * pm.bin_width
    return np.column_stack([kept[:, 0], kept[:, 1], theta])


def plan_poses(pm: PoseMap, start: ArrayLike, goal: ArrayLike, params: Mapping[str, Any] | None = None, *,
               planner: str = "potential", taut: bool = True) -> tuple[Path, PoseField]:
    """Plan for a turning robot on its pose grid: the field of the query, its descent, pulled taut.

    Parameters
    ----------
    pm : PoseMap
    start : (x, y, theta)
    goal : (x, y, theta) or (x, y)
        Without theta, any heading will do.
    params : mapping, optional
        ``clearance_band``, ``band_gain`` (the ``potential`` model).
    planner : {"potential", "wavefront-octile"}
        With or without the clearance band.
    taut : bool
        Pull the descended poses taut (default True).

    Returns
    -------
    path : Path
        ``poses`` ``(n, 3)`` (theta in ``[-pi, pi)``), ``points`` their ``(x, y)``; status
        ``reached`` or ``no_path``.
    field : PoseField

    Examples
    --------
    A 1.6 m x 0.5 m cart through a 1.0 m door in a wall: only lengthwise, so it turns to pass.

    >>> from gridfield.geometry.cspace import pose_map
    >>> from gridfield.geometry.world import Robot
    >>> occ = np.zeros((40, 40), bool); occ[20, :17] = occ[20, 22:] = True   # 0.25 m cells
    >>> cart = Robot(vertices=[[-0.8, -0.25], [0.8, -0.25], [0.8, 0.25], [-0.8, 0.25]])
    >>> pm = pose_map(GridMap(Grid((40, 40), 0.25), occ), cart, 36)
    >>> path, _ = plan_poses(pm, (5.0, 2.5, 0.0), (5.0, 7.5, 0.0))
    >>> path.status, bool(np.abs(np.abs(path.poses[:, 2]) - np.pi / 2).min() < 0.2)
    ('reached', True)
    """
    t0 = time.perf_counter()
    model = "potential" if planner == "potential" else "wavefront-octile"
    p = {**dict(params or {}), "model": model}
    f = pose_field(pm, goal, p, start=start)
    s = pm.check_pose("start", start)
    sc = pm.cell_of_pose(s)
    assert sc is not None  # check_pose: inside
    vox = pm.voxels()
    field_s = time.perf_counter() - t0
    if not math.isfinite(float(f.potential[sc])):
        path = Path(np.asarray([s[:2]]), "no_path", planner, 0, p, time.perf_counter() - t0,
                    poses=np.asarray([s]), extra={"field_seconds": field_s})
        return path, f
    cells, reached = voxel_descent(vox, f.potential, pm.voxel_point(sc), periodic=True)
    if taut and len(cells) > 2:
        floor = _box_floor(pose_clearance(pm), cells, pm.headings) if model == "potential" else 0.0
        poses = _taut(pm, cells, floor)
    else:
        poses = pm.pose_of_cell(cells)
        poses[:, 2] = np.unwrap(poses[:, 2])
    # the exact ends: from the given start pose to its cell's centre, and from the goal cell's centre to
    # the goal (its heading as given, or the bin's centre): each within the dual cell and the bin whose
    # four centres check_pose found free, so these motions are safe too
    ends = [np.array([[s[0], s[1], poses[0, 2] + wrap_angle(s[2] - poses[0, 2])]]), poses]
    if reached:
        gx, gy, gt = f.goal
        ends.append(np.array([[gx, gy, poses[-1, 2] + wrap_angle(gt - poses[-1, 2])]]))
    poses = np.vstack(ends)
    same = np.r_[False, (np.abs(np.diff(poses, axis=0)) < 1e-12).all(axis=1)]
    poses = poses[~same]
    out = np.column_stack([poses[:, :2], wrap_angle(poses[:, 2])])
    secs = time.perf_counter() - t0
    path = Path(out[:, :2], "reached" if reached else "no_path", planner, int(len(cells)), p, secs,
                poses=out, extra={"field_seconds": field_s, "follow_seconds": secs - field_s})
    return path, f
