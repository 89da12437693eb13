"""Exceptions raised by gridfield.

Every error a user can cause (a malformed map, a bad parameter, a start inside an
obstacle) is raised as :class:`GridfieldError` or a subclass, with a message that
names the file, key or value at fault and what was expected. The command line turns
these into one line on stderr and exit code 2.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

__all__ = ["GridfieldError", "MapFormatError", "ParameterError", "check_finite", "check_positive"]


class GridfieldError(ValueError):
    """Base class of every error caused by bad input to gridfield."""


class MapFormatError(GridfieldError):
    """A map or world file is missing, unreadable or malformed."""


class ParameterError(GridfieldError):
    """A parameter value is out of range, not finite, or of the wrong kind."""


def check_positive(name: str, value: float, *, allow_inf: bool = False) -> float:
    """Return ``value`` as a float, or raise :class:`ParameterError` unless it is > 0.

    Examples
    --------
    >>> check_positive("resolution", 0.5)
    0.5
    >>> check_positive("resolution", 0)
    Traceback (most recent call last):
    ...
    gridfield.errors.ParameterError: resolution must be a positive finite number, got 0
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a positive number, got {value!r}") from None
    if math.isnan(v) or v <= 0 or (math.isinf(v) and not allow_inf):
        raise ParameterError(f"{name} must be a positive{'' if allow_inf else ' finite'} number, got {value!r}")
    return v


def check_finite(name: str, values: Iterable[float] | float) -> None:
    """Raise :class:`ParameterError` if any of ``values`` is NaN or infinite.

    Examples
    --------
    >>> check_finite("start", [1.0, 2.0])
    >>> check_finite("start", [1.0, float("nan")])
    Traceback (most recent call last):
    ...
    gridfield.errors.ParameterError: start must be finite numbers, got [1.0, nan]
    """
    vals = [values] if isinstance(values, int | float) else list(values)
    try:
        ok = all(math.isfinite(float(v)) for v in vals)
    except (TypeError, ValueError):
        ok = False
    if not ok:
        shown = values if not isinstance(values, int | float) else vals[0]
        raise ParameterError(f"{name} must be finite numbers, got {list(shown) if not isinstance(shown, int | float) else shown!r}")
