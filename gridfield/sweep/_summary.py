"""The summary of a sweep's rows: success rate and length ratios per map, planner and parameters."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np


def summarize(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Success rate and length ratios (to the optimal where known) per map, planner and params.

    Parameters
    ----------
    rows : sequence of mapping
        Rows of a sweep (:func:`run_sweep`; values may be strings, as read back from the file).

    Returns
    -------
    list of dict
        Per (map, planner, params): ``runs``, ``success_rate``, ``length_ratio`` (mean of length /
        ``optimal`` over the reached runs where it is known), ``length_ratio_any_angle`` (the same
        with ``optimal_any_angle``; NaN where none is known) and ``ms_median``.

    Examples
    --------
    >>> rows = [{"map": "m", "planner": "p", "params": "{}", "status": "reached", "length": "11", "optimal": "10",
    ...          "optimal_any_angle": "8.8", "ms": "1"},
    ...         {"map": "m", "planner": "p", "params": "{}", "status": "local_minimum", "length": "3",
    ...          "optimal": "nan", "ms": "3"}]
    >>> s = summarize(rows)[0]
    >>> s["runs"], s["success_rate"], s["length_ratio"], s["length_ratio_any_angle"], s["ms_median"]
    (2, 0.5, 1.1, 1.25, 2.0)
    """
    groups: dict[tuple[str, str, str], list[Mapping[str, Any]]] = {}
    for r in rows:
        groups.setdefault((r["map"], r["planner"], r["params"]), []).append(r)
    out = []
    for (m, p, par), rs in groups.items():
        reached = [r for r in rs if r["status"] == "reached"]
        ratios = _ratios(reached, "optimal")
        any_ratios = _ratios(reached, "optimal_any_angle")
        out.append({
            "map": m, "planner": p, "params": par, "runs": len(rs),
            "success_rate": len(reached) / len(rs),
            "length_ratio": float(np.mean(ratios)) if ratios else math.nan,
            "length_ratio_any_angle": float(np.mean(any_ratios)) if any_ratios else math.nan,
            "ms_median": float(np.median([float(r["ms"]) for r in rs])),
        })
    return out


def _ratios(rows: Sequence[Mapping[str, Any]], column: str) -> list[float]:
    """``length / column`` of the rows where that reference is known (finite, positive)."""
    out = []
    for r in rows:
        ref = float(r.get(column) or "nan")
        if math.isfinite(ref) and ref > 0:
            out.append(float(r["length"]) / ref)
    return out
