"""The result every planner returns: :class:`Path`.

``status`` is one of :data:`STATUSES` and is never ``"reached"`` unless the last point is
within the planner's tolerance of the goal.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["STATUSES", "Path", "path_length"]

STATUSES = ("reached", "local_minimum", "collision", "max_iterations", "no_path")


def path_length(points: NDArray[np.float64]) -> float:
    """Sum of the Euclidean lengths of the segments of a polyline ``(N, 2)``.

    Examples
    --------
    >>> path_length(np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]]))
    6.0
    """
    p = np.asarray(points, dtype=float)
    if len(p) < 2:
        return 0.0
    return float(np.hypot(*np.diff(p, axis=0).T).sum())


@dataclass(frozen=True, eq=False)
class Path:
    """A planned path and how the planner ended.

    Attributes
    ----------
    points : ndarray, shape (N, 2)
        World coordinates from the start to where the planner stopped.
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
    extra : mapping
        Planner-specific details (e.g. escape attempts, stall points).

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
    extra: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"status must be one of {STATUSES}, got {self.status!r}")
        pts = np.asarray(self.points, dtype=float).reshape(-1, 2)
        object.__setattr__(self, "points", pts)

    @property
    def length(self) -> float:
        return path_length(self.points)

    @property
    def end(self) -> NDArray[np.float64]:
        return self.points[-1] if len(self.points) else np.array([math.nan, math.nan])

    @property
    def reached(self) -> bool:
        return self.status == "reached"

    def to_json(self) -> dict[str, Any]:
        """The JSON object of ``gridfield plan --json`` (the public contract in README.md)."""

        def clean(v: Any) -> Any:
            if isinstance(v, float | np.floating):
                v = float(v)
                return v if math.isfinite(v) else (None if math.isnan(v) else ("inf" if v > 0 else "-inf"))
            if isinstance(v, np.integer):
                return int(v)
            if isinstance(v, Mapping):
                return {str(k): clean(x) for k, x in v.items()}
            if isinstance(v, list | tuple | np.ndarray):
                return [clean(x) for x in (v.tolist() if isinstance(v, np.ndarray) else v)]
            return v

        return {
            "planner": self.planner,
            "status": self.status,
            "path": clean(self.points),
            "end": clean(self.end),
            "length": clean(self.length),
            "iterations": int(self.iterations),
            "min_clearance": clean(self.min_clearance),
            "params": clean(dict(self.params)),
            "seconds": clean(self.seconds),
            "field_seconds": clean(self.extra.get("field_seconds", 0.0)),
            "follow_seconds": clean(self.extra.get("follow_seconds", self.seconds)),
            "hint": self.extra.get("hint"),
            **({"optimal": clean(self.extra["optimal"])} if "optimal" in self.extra else {}),
        }

    def __repr__(self) -> str:
        x, y = self.end
        return (f"Path(planner={self.planner!r}, status={self.status!r}, points={len(self.points)}, "
                f"length={self.length:.6g}, end=({x:.6g}, {y:.6g}), iterations={self.iterations})")
