"""Exceptions raised by gridfield.

Every error a user can cause (a malformed map, a bad parameter, a start inside an
obstacle) is raised as :class:`GridfieldError` or a subclass, with a message that
names the file, key or value at fault and what was expected. The command line turns
these into one line on stderr and exit code 2.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

__all__ = [
    "MESSAGE_LIMIT",
    "ArgumentTypeError",
    "GridfieldError",
    "MapFormatError",
    "ParameterError",
    "SizeLimitError",
    "cap_message",
    "check_finite",
    "check_positive",
    "shorten",
]

#: Longest error message kept whole; longer ones keep their start and end around a marker.
MESSAGE_LIMIT = 600

#: Longest repr of a value shown inside a message (see :func:`shorten`).
VALUE_LIMIT = 200


def shorten(value: object, limit: int = VALUE_LIMIT) -> str:
    """``repr(value)``, cut to about ``limit`` characters for an error message.

    Containers are cut before their repr is built, so that a huge (or alias-expanded) value
    costs no more than its first items.

    Parameters
    ----------
    value : object
        Any value; a container of more than 20 items is shown by its first 20 and its length.
    limit : int, default VALUE_LIMIT
        Longest text returned, about (a cut text ends with its full length in characters).

    Returns
    -------
    str
        The repr, whole or cut; ``<TypeName>`` when the value's ``__repr__`` raises.

    Examples
    --------
    >>> shorten([1.0, 2.0])
    '[1.0, 2.0]'
    >>> s = shorten(list(range(10**6)))
    >>> len(s) < 260, s.endswith("(1000000 items)")
    (True, True)
    """
    try:
        if isinstance(value, list | tuple | dict | set | frozenset) and len(value) > 20:
            items = iter(value.items() if isinstance(value, dict) else value)
            head = [next(items) for _ in range(20)]
            return shorten(head, limit)[:limit] + f"... ({len(value)} items)"
        text = repr(value)
    except Exception:  # a broken __repr__ must not hide the real error
        return f"<{type(value).__name__}>"
    if len(text) > limit:
        text = text[: limit - 40] + f"... ({len(text)} characters)"
    return text


def cap_message(message: str, limit: int = MESSAGE_LIMIT) -> str:
    """``message`` whole when it has at most ``limit`` characters, else its start and end around a
    marker that says how many characters were cut (what every gridfield error and the CLI's error
    line do).

    Parameters
    ----------
    message : str
        The message.
    limit : int, optional
        The longest message kept whole (default :data:`MESSAGE_LIMIT`).

    Returns
    -------
    str
        At most about ``limit`` characters.

    Examples
    --------
    >>> cap_message("short")
    'short'
    >>> cap_message("x" * 300 + "END", limit=100)
    'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx ...[243 characters cut]... xxxxxxxxxxxxxxxxxEND'
    """
    if len(message) <= limit:
        return message
    tail = limit // 5
    head = limit - tail - 40
    return f"{message[:head]} ...[{len(message) - head - tail} characters cut]... {message[-tail:]}"


class GridfieldError(ValueError):
    """Base class of every error caused by bad input to gridfield.

    A message longer than :data:`MESSAGE_LIMIT` characters is shortened (its start and end are
    kept), so that no error can flood a terminal or a log.

    Examples
    --------
    >>> len(str(GridfieldError("x" * 10**6))) <= MESSAGE_LIMIT
    True
    """

    def __init__(self, *args: object) -> None:
        if len(args) == 1 and isinstance(args[0], str):
            args = (cap_message(args[0]),)
        super().__init__(*args)


class MapFormatError(GridfieldError):
    """A map or world file is missing, unreadable or malformed."""


class ParameterError(GridfieldError):
    """A parameter value is out of range, not finite, or of the wrong kind."""


class ArgumentTypeError(ParameterError, TypeError):
    """An argument of a gridfield function has the wrong type (also a :class:`TypeError`)."""


class SizeLimitError(GridfieldError):
    """An input would need more cells (memory) than the configured limit (see :mod:`gridfield.core.limits`)."""


def check_positive(name: str, value: float, *, allow_inf: bool = False) -> float:
    """Return ``value`` as a float, or raise :class:`ParameterError` unless it is > 0.

    Parameters
    ----------
    name : str
        The parameter's name, used in the error message.
    value : float
        The value to check (anything ``float()`` accepts).
    allow_inf : bool, default False
        Accept ``inf`` (for limits that may be switched off).

    Returns
    -------
    float
        ``float(value)``.

    Raises
    ------
    ParameterError
        If the value is not a number, NaN, zero or negative (or infinite without ``allow_inf``).

    Examples
    --------
    >>> check_positive("resolution", 0.5)
    0.5
    >>> check_positive("resolution", 0)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: resolution must be a positive finite number, got 0
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a positive number, got {shorten(value)}") from None
    if math.isnan(v) or v <= 0 or (math.isinf(v) and not allow_inf):
        raise ParameterError(f"{name} must be a positive{'' if allow_inf else ' finite'} number, got {shorten(value)}")
    return v


def check_finite(name: str, values: Iterable[float] | float) -> None:
    """Raise :class:`ParameterError` if any of ``values`` is NaN or infinite.

    Parameters
    ----------
    name : str
        The argument's name, used in the error message.
    values : float or iterable of float
        One number or several (a point, a list of bounds).

    Returns
    -------
    None
        The check only raises; nothing is returned when every value is finite.

    Raises
    ------
    ParameterError
        If a value is NaN, infinite or not a number.

    Examples
    --------
    >>> check_finite("start", [1.0, 2.0])
    >>> check_finite("start", [1.0, float("nan")])
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: start must be finite numbers, got [1.0, nan]
    """
    vals = [values] if isinstance(values, int | float) else list(values)
    try:
        ok = all(math.isfinite(float(v)) for v in vals)
    except (TypeError, ValueError):
        ok = False
    if not ok:
        shown = values if not isinstance(values, int | float) else vals[0]
        raise ParameterError(f"{name} must be finite numbers, got {shorten(list(shown) if not isinstance(shown, int | float) else shown)}")
