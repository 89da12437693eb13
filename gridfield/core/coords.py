"""Points and cell indices: the parsers of point arguments and the world -> cell index rule.

Private: :mod:`gridfield.core.grid` owns these rules (its :class:`~gridfield.core.grid.Grid` methods use them);
the stages that parse a point argument or index one point import them from here.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import ParameterError, shorten

__all__ = ["INDEX_LIMIT", "as_points", "as_xy", "cell_index", "scalar_index"]


def as_points(points: ArrayLike, name: str = "points", ndim: int = 2) -> NDArray[np.float64]:
    """World points as a float array of shape ``(N, ndim)`` (a single point ``(ndim,)`` becomes one row).

    Examples
    --------
    >>> as_points([1, 2]).shape, as_points([[1, 2, 3]], ndim=3).shape
    ((1, 2), (1, 3))
    """
    p = np.asarray(points, dtype=np.float64)
    if p.ndim == 1 and p.shape[0] == ndim:
        p = p[None, :]
    if p.ndim != 2 or p.shape[1] != ndim:
        raise ParameterError(f"{name} must have shape (N, {ndim}) or ({ndim},), got shape {np.shape(points)}")
    return p


def as_xy(point: object, name: str) -> tuple[float, float]:
    """A point given as an argument (start, goal, ...) as two finite floats ``(x, y)``.

    The one point parser of the public functions: a string, anything but two numbers, NaN or
    ``inf`` is a :class:`ParameterError` naming the argument.

    Examples
    --------
    >>> as_xy([1, 2.5], "start"), as_xy(np.array([[3.0, 4.0]]), "goal")
    ((1.0, 2.5), (3.0, 4.0))
    >>> as_xy((1.0, float("nan")), "goal")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: goal must be two finite numbers (x, y), got (1.0, nan)
    """
    try:
        raw = np.asarray(point)
        ok = raw.dtype.kind in "iuf" and raw.size == 2
        a = raw.astype(np.float64, copy=False).reshape(2) if ok else None
    except (TypeError, ValueError):
        a = None
    if a is None or not (math.isfinite(a[0]) and math.isfinite(a[1])):
        raise ParameterError(f"{name} must be two finite numbers (x, y), got {shorten(point)}")
    return float(a[0]), float(a[1])


#: World -> cell indices are clipped to +-this before the cast to int, so that points far outside
#: (say 1e300) stay outside and never overflow or wrap.
INDEX_LIMIT = float(2**62)


def cell_index(coord: NDArray[np.float64], origin: float, res: float) -> NDArray[np.float64]:
    """``floor((coord - origin) / res)``, corrected so that it agrees exactly with the cell
    boundaries ``origin + i * res`` as computed in floating point (half-open intervals)."""
    with np.errstate(over="ignore", invalid="ignore"):
        i = np.floor((coord - origin) / res)
        i = i + (coord >= origin + (i + 1) * res)
        i = i - (coord < origin + i * res)
    return i


def scalar_index(v: float, origin: float, res: float) -> int:
    """:func:`cell_index` for one finite Python float (the same boundary rule, the same IEEE double
    arithmetic), without numpy's per-call overhead: single-point queries are dominated by it."""
    i = math.floor((v - origin) / res)
    if v >= origin + (i + 1) * res:
        i += 1
    if v < origin + i * res:
        i -= 1
    return i
