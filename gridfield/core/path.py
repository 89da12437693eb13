"""The result every planner returns: :class:`Path`, and the schema of its ``extra`` details.

``status`` is one of :data:`STATUSES` and is never ``"reached"`` unless the last point is
within the planner's tolerance of the goal. ``Path.extra`` holds planner-specific details under
the keys of :class:`PathExtra` (and :class:`NavigationAux` those of a navigation field's ``aux``):
one place that lists every key a module writes, with its type and meaning, so that readers
(figures, the diagnosis, the comparison, the CLI) and writers agree. A key outside the schema is
refused when the path is made.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, TypedDict

import numpy as np
from numpy.typing import NDArray

__all__ = ["STATUSES", "NavigationAux", "Path", "PathExtra", "path_length"]

STATUSES = ("reached", "local_minimum", "collision", "max_iterations", "no_path")

Point = list[float]  # [x, y] in world units (JSON-friendly)


#: Every key a planner, the dispatcher or the CLI writes into :attr:`Path.extra` (all optional):
#: the follower (:mod:`gridfield.follow`, also behind ``exact-potential``), the ``potential``
#: planner, the navigation planners, the exact planners (visibility, any-angle, sphere and star
#: worlds), :func:`gridfield.planners.plan` and ``gridfield plan``. (The functional form, because
#: one key, ``"lambda"``, is a Python keyword.)
PathExtra = TypedDict(
    "PathExtra",
    {
        # -- the query (gridfield.planners.plan) --
        "start": tuple[float, float],  # the start planned from
        "goal": tuple[float, float],  # the goal planned to (figures mark it)
        "field_seconds": float,  # time building the fields (of Path.seconds)
        "follow_seconds": float,  # the planner's own time after the fields (of Path.seconds)
        # -- the follower (follow.descend, follow.follow_many) --
        "stop_reason": str,  # why it stopped: goal, oscillation, no_progress, confined, small_gradient, blocked, max_iterations, unreachable
        "stall_point": Point,  # where it stalled (local_minimum)
        "local_minima": list[Point],  # every stall point, escapes included
        "oscillation": list[Point],  # the two alternating points of an oscillation stop
        "blocked_at": Point,  # the rejected full step of a blocked follower
        "slid_steps": int,  # steps shortened or turned because the full step was blocked
        "goal_appended": bool,  # whether the goal was appended as the last point
        "left_map": bool,  # the path left an open-bordered grid
        "outside_fraction": float,  # the fraction of its points outside the grid
        "sampling": str,  # how the field was sampled between cells (nearest, bilinear)
        "alpha_xy": list[float] | None,  # the per-axis step scales of the scaled step rule
        "escapes_tried": int,  # escapes attempted from local minima
        "escapes_succeeded": int,  # those that reached the goal or another minimum
        "escapes": list[dict[str, Any]],  # one record per escape: from, at_iteration, kind, outcome, points
        "navigation_segments": list[tuple[int, int]],  # point index ranges moved by the navigation escape
        # -- the potential planner (follow.plan_potential, exact.plan_exact_potential) --
        "build_seconds": float,  # time building the field
        "hint": str,  # one line: why the run failed and what to try (gridfield.following.diagnose)
        "diagnosis": dict[str, Any],  # the diagnosis behind the hint (gridfield.following.diagnose.diagnose)
        "median_clearance": float,  # median brushfire distance at the path's points (complete models; Path.min_clearance: the smallest)
        "finish": dict[str, Any],  # complete models: the follower's stall finished by the field's discrete descent (follow.descend_cells): stop_reason, from, cells, dropped (points after the last one on a valued cell)
        # -- navigation functions (gridfield.fields.navigation) --
        "value": float,  # the navigation function's value at the start cell
        "grid_length": float,  # length of the path through cell centres
        "cells": Any,  # (N, 2) int array: the cells of a discrete descent
        "reason": str,  # why there is no path
        "finished_by": str,  # "wavefront": the follower stopped on a flat spot and the octile wavefront finished
        # -- sphere and star worlds (navigation.plan_sphere_nav, star.plan_star_nav) --
        "kappa": float,  # the kappa that was used
        "lambda": float,  # the lambda that was used (star-nav)
        "tried": list[float],  # the kappas tried (sphere-nav)
        "kappa_tried": list[float],  # the kappas tried (star-nav)
        "workspace_center": Point,  # the workspace disc's centre
        "workspace_radius": float,  # its radius
        "followed": str,  # which function the star-nav path followed
        "folds": int,  # folds of the star-to-sphere map met on the path
        "star_centers": dict[int, Point],  # obstacle id -> star centre
        # -- exact shortest paths (visibility, anyangle) --
        "nodes": int,  # nodes of the visibility graph
        "edges": int,  # its edges
        "polygons": int,  # polygons of the navigation mesh (anyangle's Polyanya search)
        "pinch": str,  # how corner-touching obstacles are treated
        "graph_seconds": float,  # time building the graph
        "optimal_length": float,  # the shortest path's length
        # -- gridfield plan --scenario --
        "optimal": float,  # the scenario's published optimal length
    },
    total=False,
)

PathExtra.__doc__ = """The schema of :attr:`Path.extra`: every key, all optional (a ``TypedDict``; each key's type and
meaning are commented in the source).

Attributes
----------
start, goal, field_seconds, follow_seconds
    The query and its time split, recorded by :func:`gridfield.planners.plan`.
stop_reason, stall_point, local_minima, oscillation, blocked_at, slid_steps, goal_appended, left_map, \
outside_fraction, sampling, alpha_xy, escapes_tried, escapes_succeeded, escapes, navigation_segments
    How the follower (:func:`gridfield.following.follower.follow`, :func:`gridfield.following.follower.follow_many`) ended.
build_seconds, hint, diagnosis, median_clearance, finish
    The potential planners: field build time, the one-line hint and its diagnosis; the median
    clearance along the path (the complete models of :mod:`gridfield.fields.navfield`); for a complete
    model whose follower stalled, the stall it finished from by the field's discrete descent
    (:func:`gridfield.following.follower.descend_cells`: the follower's ``stop_reason``, the point, the cells).
value, grid_length, cells, reason, finished_by
    Navigation functions: value at the start, grid length, the descent's cells, why no path, and
    ``"wavefront"`` when the follower stopped on a flat spot short of the goal and the octile
    wavefront's descent from there finished the path.
kappa, lambda, tried, kappa_tried, workspace_center, workspace_radius, followed, folds, star_centers
    Sphere and star worlds.
nodes, edges, polygons, pinch, graph_seconds, optimal_length
    Exact shortest paths (visibility graph, any-angle; ``polygons``: the navigation mesh of the
    any-angle Polyanya search).
optimal
    ``gridfield plan --scenario``: the scenario's published optimal length.

Examples
--------
>>> import numpy as np
>>> p = Path(np.zeros((1, 2)), "local_minimum", "demo", extra=PathExtra(stall_point=[0.0, 0.0]))
>>> p.extra["stall_point"], "lambda" in PathExtra.__optional_keys__
([0.0, 0.0], True)
>>> Path(np.zeros((1, 2)), "reached", "demo", extra={"stall": [0.0, 0.0]})
Traceback (most recent call last):
...
ValueError: Path.extra keys ['stall'] are not in gridfield.core.path.PathExtra; add them there
"""

#: The keys :class:`Path` accepts in ``extra``.
EXTRA_KEYS = frozenset(PathExtra.__optional_keys__)


class NavigationAux(TypedDict, total=False):
    """The keys of a navigation field's ``aux`` (:class:`gridfield.fields.navigation.NavigationField`), all
    optional; each key's type and meaning are commented in the source.

    Attributes
    ----------
    cost
        The cell cost of a weighted wavefront or fmm (``clearance_weight``).
    harmonic, shell, shells, iterations, seconds
        The harmonic function: ``u`` of shell 0, each cell's shell, how many, solver iterations, time.
    grad_x, grad_y, figure
        Star worlds: the analytic gradient and the arrays of seed 002's figures.

    Examples
    --------
    >>> sorted(NavigationAux.__optional_keys__)[:3]
    ['cost', 'figure', 'grad_x']
    """

    cost: Any  # (rows, cols) float array: the cell cost of a weighted wavefront or fmm (clearance_weight)
    harmonic: Any  # (rows, cols) float array: the harmonic potential u of shell 0
    shell: Any  # (rows, cols) int array: each cell's shell (-1 obstacles)
    shells: int  # how many shells the harmonic function needed
    iterations: int  # solver iterations of the harmonic function
    seconds: float  # the harmonic solve's time
    grad_x: Any  # (rows, cols) float array: the analytic gradient (star worlds)
    grad_y: Any  # (rows, cols) float array
    figure: dict[str, Any]  # the arrays of seed 002's figures (star.star_figure_data)


def path_length(points: NDArray[np.float64]) -> float:
    """Sum of the Euclidean lengths of the segments of a polyline ``(N, 2)`` (or ``(N, 3)``).

    Parameters
    ----------
    points : ndarray, shape (N, 2) or (N, 3)
        The polyline's vertices in world coordinates.

    Returns
    -------
    float
        Its length (0 for fewer than two points).

    Examples
    --------
    >>> path_length(np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]]))
    6.0
    >>> path_length(np.array([[0.0, 0.0, 0.0], [2.0, 3.0, 6.0]]))
    7.0
    """
    p = np.asarray(points, dtype=float)
    if len(p) < 2:
        return 0.0
    d = np.diff(p, axis=0)
    if d.shape[1] == 2:
        return float(np.hypot(*d.T).sum())
    return float(np.sqrt((d * d).sum(axis=1)).sum())


@dataclass(frozen=True, eq=False)
class Path:
    """A planned path and how the planner ended.

    Attributes
    ----------
    points : ndarray, shape (N, 2)
        World coordinates from the start to where the planner stopped; ``(N, 3)`` holding ``(x, y, z)``
        on a voxel grid.
    status : str
        One of :data:`STATUSES`.
    planner : str
        The planner's name (as in ``gridfield plan --planner``).
    iterations : int
        Steps taken (follower iterations, or expanded path cells).
    params : mapping
        The parameters the planner ran with.
    seconds : float
        Wall time of the query: through :func:`gridfield.planners.plan`, everything after loading
        (building the fields and following; ``extra["field_seconds"]`` and
        ``extra["follow_seconds"]`` split it); from a planner called directly, its own time.
    min_clearance : float
        Smallest distance to an obstacle along the path, as the planner measures it
        (NaN when the planner does not measure it).
    extra : PathExtra
        Planner-specific details (e.g. escape attempts, stall points); the keys of
        :class:`PathExtra` only.
    poses : ndarray, shape (N, 3), or None
        For a robot that turns: the poses ``(x, y, theta)`` (radians, in ``[-pi, pi)``) along the path,
        one per point (``points`` is then their ``(x, y)``); None otherwise.

    Examples
    --------
    >>> p = Path(np.array([[0.0, 0.0], [1.0, 0.0]]), "reached", "demo")
    >>> p.length, p.end.tolist()
    (1.0, [1.0, 0.0])
    >>> sorted(p.to_json())
    ['end', 'field_seconds', 'follow_seconds', 'hint', 'iterations', 'length', 'min_clearance', 'params', 'path', 'planner', 'seconds', 'status']
    >>> p
    Path(planner='demo', status='reached', points=2, length=1, end=(1, 0), iterations=0)
    """

    points: NDArray[np.float64]
    status: str
    planner: str
    iterations: int = 0
    params: Mapping[str, Any] = field(default_factory=dict)
    seconds: float = 0.0
    min_clearance: float = math.nan
    # PathExtra for readers (a misspelt key is a type error); writers may pass any mapping, whose
    # keys __post_init__ checks against the schema
    extra: PathExtra | Mapping[str, Any] = field(default_factory=dict)
    poses: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"status must be one of {STATUSES}, got {self.status!r}")
        unknown = sorted(set(self.extra) - EXTRA_KEYS)
        if unknown:
            raise ValueError(f"Path.extra keys {unknown} are not in gridfield.core.path.PathExtra; add them there")
        pts = np.asarray(self.points, dtype=float)
        if not (pts.ndim == 2 and pts.shape[1] == 3):
            pts = pts.reshape(-1, 2)
        object.__setattr__(self, "points", pts)
        if self.poses is not None:
            poses = np.asarray(self.poses, dtype=float).reshape(-1, 3)
            if len(poses) != len(pts):
                raise ValueError(f"Path.poses has {len(poses)} rows, but the path has {len(pts)} points")
            object.__setattr__(self, "poses", poses)

    @property
    def length(self) -> float:
        return path_length(self.points)

    @property
    def end(self) -> NDArray[np.float64]:
        return self.points[-1] if len(self.points) else np.full(self.points.shape[1], math.nan)

    @property
    def reached(self) -> bool:
        return self.status == "reached"

    @property
    def hint(self) -> str | None:
        """Why a run did not reach its goal and what does, in one line; ``None`` for a run without one.

        The ``potential`` planner gives every run that does not reach the goal a hint
        (:func:`gridfield.following.diagnose.diagnose`, the same text as ``extra["hint"]``, ``gridfield plan``'s
        ``hint:`` line and ``--json``'s ``hint``): where it stopped, the trap (described the same from
        every start that drains into it: its basin, the narrowest passage on the way to the goal), a
        ``--q-star`` only after a re-run with it reached the goal, and ``--escape navigation``, which
        reaches every reachable goal. Navigation functions that cannot reach say why (``extra["reason"]``).

        Examples
        --------
        >>> from gridfield.core.grid import Grid, GridMap
        >>> from gridfield.planners import plan
        >>> occ = np.zeros((10, 10), bool); occ[4:6, 0:7] = True
        >>> classic = {"model": "khatib"}   # the classic field (the default nf1 model does not stall)
        >>> p = plan("potential", GridMap(Grid((10, 10), 1.0), occ), (2.5, 1.5), (2.5, 8.5), classic)
        >>> p.status, p.hint.endswith("--escape navigation reaches it")
        ('local_minimum', True)
        >>> plan("potential", GridMap(Grid((10, 10), 1.0), occ), (2.5, 1.5), (7.5, 8.5), classic).hint is None
        True
        """
        hint = self.extra.get("hint") or self.extra.get("reason")
        return str(hint) if hint else None

    def to_json(self) -> dict[str, Any]:
        """The JSON object of ``gridfield plan --json`` (the public contract in README.md).

        Numbers are JSON numbers, never strings: a value that is not finite is ``null``, and when one
        is infinite the key ``infinite`` lists where (``{"params.d_star": 1}``: +inf; -1 for -inf);
        NaN is ``null`` alone (no value).

        Examples
        --------
        >>> p = Path(np.zeros((1, 2)), "reached", "demo", params={"d_star": math.inf, "eta": 1.0})
        >>> j = p.to_json()
        >>> j["params"], j["infinite"]
        ({'d_star': None, 'eta': 1.0}, {'params.d_star': 1})
        """
        infinite: dict[str, int] = {}

        def clean(v: Any, where: str) -> Any:
            if isinstance(v, float | np.floating):
                v = float(v)
                if math.isinf(v):
                    infinite[where] = 1 if v > 0 else -1
                return v if math.isfinite(v) else None
            if isinstance(v, np.integer):
                return int(v)
            if isinstance(v, Mapping):
                return {str(k): clean(x, f"{where}.{k}" if where else str(k)) for k, x in v.items()}
            if isinstance(v, list | tuple | np.ndarray):
                return [clean(x, f"{where}[{i}]") for i, x in enumerate(v.tolist() if isinstance(v, np.ndarray) else v)]
            return v

        out = {
            "planner": self.planner,
            "status": self.status,
            "path": clean(self.points, "path"),
            "end": clean(self.end, "end"),
            "length": clean(self.length, "length"),
            "iterations": int(self.iterations),
            "min_clearance": clean(self.min_clearance, "min_clearance"),
            "params": clean(dict(self.params), "params"),
            "seconds": clean(self.seconds, "seconds"),
            "field_seconds": clean(self.extra.get("field_seconds", 0.0), "field_seconds"),
            "follow_seconds": clean(self.extra.get("follow_seconds", self.seconds), "follow_seconds"),
            "hint": self.hint,
            **({"optimal": clean(self.extra["optimal"], "optimal")} if "optimal" in self.extra else {}),
            **({"median_clearance": clean(self.extra["median_clearance"], "median_clearance")}
               if "median_clearance" in self.extra else {}),
        }
        if self.poses is not None:
            out["poses"] = clean(self.poses, "poses")
        if infinite:
            out["infinite"] = infinite
        return out

    def __repr__(self) -> str:
        end = ", ".join(f"{v:.6g}" for v in self.end)
        return (f"Path(planner={self.planner!r}, status={self.status!r}, points={len(self.points)}, "
                f"length={self.length:.6g}, end=({end}), iterations={self.iterations})")
