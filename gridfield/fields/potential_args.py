"""How a field's parameters reach the compiled potential kernels: the metric's code, the repulsive
power as an integer when it is one, and the saturation of the distances.

Private: shared by :mod:`gridfield.fields.potential` (the in-memory field), :mod:`gridfield.distance.incremental`
(its window updates) and :mod:`gridfield.chunked` (the field chunk by chunk), so that all three pass
the kernels the same arguments.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..core.results import DistanceMap

__all__ = ["METRIC_CODE", "integer_power", "saturation"]

#: The brushfire metric's code in the compiled potential kernels.
METRIC_CODE = {"euclidean": 0, "chessboard": 1, "taxicab": 2}


def integer_power(power: float) -> int:
    """``power`` as a small non-negative int, or -1 when it is fractional (or huge).

    Examples
    --------
    >>> integer_power(2.0), integer_power(1.5), integer_power(100.0)
    (2, -1, -1)
    """
    return int(power) if float(power).is_integer() and 0 <= power <= 64 else -1


def saturation(dmap: DistanceMap, saturate: float | None) -> tuple[float, float]:
    """``(saturation distance, far value)`` of a distance map: ``saturate`` when given, else the
    map's own (``inf`` when neither), and the value its unreached cells hold."""
    sat = saturate if saturate is not None else dmap.saturate
    return (math.inf if sat is None else float(sat)), float(dmap.far)
