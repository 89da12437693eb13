"""Configuration space (Lozano-Perez C-obstacles): obstacles grown by the robot's shape.

Two robot models, each on vector worlds and on grids:

- **disc robot** of radius ``r`` (rotation does not matter): every obstacle grows by ``r``;
  :func:`inflate_world` (shapely buffer) and :func:`inflate_grid` (Euclidean distance threshold);
- **convex polygon robot**, translation only: the C-obstacle of a workspace obstacle ``O`` is the
  Minkowski sum ``O ⊕ (−R)`` where ``R`` is the robot's shape in its own frame and the robot's
  **reference point is the origin (0, 0) of that frame**: the robot at configuration ``q``
  occupies ``q + R``, which meets ``O`` iff ``q ∈ O ⊕ (−R)``. :func:`minkowski_obstacle`
  computes it as the convex hull of all pairwise vertex differences, :func:`star_algorithm` by
  the seed's star algorithm (merging the two polygons' edges in the order of their directions);
  :func:`cspace_world` and :func:`cspace_grid` apply it to whole worlds and grids.

Polygon vertex arrays are ``(N, 2)`` world coordinates ``(x, y)``; convex polygons may be given
in either orientation and with or without a repeated closing vertex. Returned convex polygons are
counter-clockwise, start at the lowest vertex (lowest y, then lowest x), repeat no vertex and
contain no collinear vertices; a degenerate result has 1 (point) or 2 (segment) rows.

Layout of the package (one job per module), on the leaf ``gridfield.geometry._polygons`` (convex polygons as
normalized vertex arrays, :func:`minkowski_obstacle`, :func:`star_algorithm`; below ``world``, which
checks robot polygons with it): ``_vector`` (worlds:
:func:`inflate_world`, :func:`cspace_world`), ``_grid`` (grids: :func:`inflate_grid`,
:func:`cspace_grid` and the footprint dilation), ``_robot`` (a robot on any map:
:func:`as_robot`, :func:`apply_robot`, :func:`centre_footprint` (discs on grids, decided at cell
centres), :func:`conservative_footprint` (polygons on grids), the start/goal and
clearance checks), ``_headings`` and ``_poses`` (a robot that turns: the C-obstacles stacked over heading
bins, :func:`heading_occupancy`, and the pose grid :class:`PoseMap`). Each builds on the ones before it; this ``__init__`` only re-exports their
public names. The submodules are private: import from ``gridfield.geometry.cspace``.
"""

from __future__ import annotations

from .._polygons import minkowski_obstacle, star_algorithm
from ._grid import cspace_grid, inflate_grid
from ._headings import MAX_HEADINGS, check_headings, heading_centres, heading_footprints, heading_occupancy, swept_robot
from ._poses import PoseMap, pose_map, wrap_angle
from ._robot import (
    apply_robot,
    as_robot,
    centre_footprint,
    check_robot_point,
    check_robot_polygon,
    conservative_footprint,
    robot_clearance,
    workspace_clearance,
)

# not in __all__, but importable from here as it was from the single-file module
from ._robot import check_positive_resolution as check_positive_resolution
from ._vector import cspace_world, inflate_world

__all__ = [
    "MAX_HEADINGS",
    "PoseMap",
    "apply_robot",
    "as_robot",
    "centre_footprint",
    "check_headings",
    "check_robot_point",
    "check_robot_polygon",
    "conservative_footprint",
    "cspace_grid",
    "cspace_world",
    "heading_centres",
    "heading_footprints",
    "heading_occupancy",
    "inflate_grid",
    "inflate_world",
    "minkowski_obstacle",
    "pose_map",
    "robot_clearance",
    "star_algorithm",
    "swept_robot",
    "workspace_clearance",
    "wrap_angle",
]

