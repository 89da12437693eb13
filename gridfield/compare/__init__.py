"""Grid planners against exact-geometry planners: metrics, convergence study, batch comparison.

Metrics (pure functions on point arrays ``(N, 2)``; a :class:`~gridfield.core.path.Path` works too):

- :func:`length_ratio` — path length over a reference (the exact planner's, the visibility optimum);
- :func:`hausdorff` — symmetric Hausdorff distance (:func:`scipy.spatial.distance.directed_hausdorff`);
- :func:`discrete_frechet` — discrete Fréchet distance (dynamic programming, one numpy step per
  anti-diagonal); unlike Hausdorff it sees the order of the points, so a path that doubles back
  is far from a straight one even when it covers the same ground;
- :func:`end_error` — distance between the end points (the stall points of two stuck followers);
- :func:`min_clearance`, :func:`collides` — exact clearance of a path against the world;
- :func:`status_agreement` — whether two planners ended the same way;
- :func:`distance_map_errors` — every brushfire metric against the exact obstacle distance at the
  cell centres: max, mean and by distance band.

Both distances between curves are computed on the polylines resampled at ``spacing`` (their
vertices plus points at most ``spacing`` apart), which makes them independent of how densely each
planner records its points and within ``spacing / 2`` of the continuous distances.

:func:`convergence_study` runs a grid planner at a list of resolutions against an exact planner
and reports these metrics per resolution; :func:`observed_order` is the least-squares slope of an
error against the resolution on log-log axes (error ~ C h^order).

The path and the stall point are expected to converge at first order in the cell size: a
conservative rasterization moves every obstacle boundary by up to one cell, and a Euclidean
brushfire's distances are off by up to ``h / sqrt(2)``. Once the cell is well below the follower's
step, the fixed steps both followers take add an error that does not shrink with ``h``, so the
errors stop falling steadily; a stalled follower's Fréchet distance also sees how long it
oscillated before stopping. The orders measured on the bundled seed 000 worlds, and the command
that measures them, are in ``benchmarks/README.md`` ("Grid against exact geometry").

:func:`batch_compare` plans many random start/goal pairs on one world and reports success rates
of the grid and exact potential fields and of the octile wavefront, and their length ratios to
the visibility-graph optimum.

The code is split by job into private submodules (import every name from ``gridfield.compare``):
``_metrics`` (the metrics and :func:`observed_order`), ``_study`` (the convergence study),
``_batch`` (the batch comparison) and ``_common`` (what the last two share: the target, the block
factor on grid maps, the exact optimum).
"""

from __future__ import annotations

from ._batch import batch_compare
from ._common import optimum_solver
from ._metrics import (
    collides,
    discrete_frechet,
    distance_map_errors,
    end_error,
    final_point,
    hausdorff,
    length_ratio,
    max_deviation,
    min_clearance,
    observed_order,
    resample,
    status_agreement,
)
from ._study import ERROR_COLUMNS as _ERROR_COLUMNS
from ._study import STUDY_COLUMNS as _STUDY_COLUMNS
from ._study import convergence_study, no_path_at_resolution, study_errors, study_orders

# (owned by ``_study``; assigned here to document them on this page)
#: Keys of every row of :func:`convergence_study`, in table order.
STUDY_COLUMNS = _STUDY_COLUMNS
#: Error columns whose convergence :func:`observed_order` is reported for.
ERROR_COLUMNS = _ERROR_COLUMNS

__all__ = [
    "ERROR_COLUMNS",
    "STUDY_COLUMNS",
    "batch_compare",
    "collides",
    "convergence_study",
    "discrete_frechet",
    "distance_map_errors",
    "end_error",
    "final_point",
    "hausdorff",
    "length_ratio",
    "max_deviation",
    "min_clearance",
    "no_path_at_resolution",
    "observed_order",
    "optimum_solver",
    "resample",
    "status_agreement",
    "study_errors",
    "study_orders",
]
