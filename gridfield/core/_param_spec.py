"""The parameter registry's entry type: :class:`Spec`, one parameter's kind, default, range and meaning.

A :class:`Spec` checks and converts one value (:meth:`Spec.check`) and says in words what it allows
(:meth:`Spec.allowed`); the registry (:data:`gridfield.core.params.REGISTRY`) holds one per parameter,
built from the tables of :mod:`gridfield.core._param_table`. Part of :mod:`gridfield.core.params`,
which re-exports :class:`Spec`; private to :mod:`gridfield.core`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .errors import ParameterError
from .planner_table import PLANNERS


@dataclass(frozen=True)
class Spec:
    """One parameter: how it is checked, its default, and what it means.

    ``kind`` is ``number``, ``integer``, ``choice``, ``alpha`` (a number or a pair) or ``point``;
    ``minimum``/``strict`` bound numbers (``strict``: ``> minimum``), ``least`` and ``maximum`` narrow
    that range where the values beyond are meaningless or overflow (``inf`` is governed by ``allow_inf``
    alone; each has its own message); ``allow_inf`` admits ``inf``;
    ``allow_none`` admits ``None`` (``scale`` then says what ``None`` resolves to).

    Attributes
    ----------
    name : str
        The parameter's name (a key of :data:`REGISTRY`, a CLI flag ``--name`` when ``flag``).
    group : str
        Its concern (``attraction``, ``repulsion``, ... ``navigation``).
    kind : {"number", "integer", "choice", "alpha", "point"}
    default : object
        The value :func:`resolve` gives when none is given (``None``: scaled, see ``scale``).
    meaning : str
        One phrase, shown by ``--help`` and the docs.
    choices : tuple
        The allowed values of a ``choice``.
    minimum, strict, least, maximum, allow_inf, allow_none
        The range of a number (see above).
    scale : str
        The scaling rule of a ``None`` default, in words.
    planners : tuple of str
        The planners that read it (derived from the ``reads`` of :data:`gridfield.planners.PLANNERS`).
    flag : bool
        Whether it gets its own command-line flag (all take ``--param name=value``).

    Examples
    --------
    >>> from gridfield.core.params import REGISTRY
    >>> spec = REGISTRY["q_star"]
    >>> spec.group, spec.allowed()
    ('repulsion', 'a number > 0 (inf allowed)')
    >>> spec.check(2), spec.check(math.inf)
    (2.0, inf)
    >>> spec.check(0)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: q_star must be a number > 0 (inf allowed), got 0
    """

    name: str
    group: str
    kind: str
    default: Any
    meaning: str
    choices: tuple[Any, ...] = ()
    minimum: float | None = None
    strict: bool = False
    least: float | None = None
    maximum: float | None = None
    allow_inf: bool = False
    allow_none: bool = False
    scale: str = ""
    flag: bool = True

    @property
    def planners(self) -> tuple[str, ...]:
        """The planners that read it: those whose :data:`gridfield.planners.PLANNERS` entry lists it
        in ``reads`` (the planner table is the one place that says what a planner reads)."""
        return tuple(name for name, entry in PLANNERS.items() if self.name in entry.reads)

    def allowed(self) -> str:
        """The allowed values in words (``a number > 0``, ``one of 'a', 'b'``)."""
        if self.kind == "choice":
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.kind == "point":
            return "two numbers (x, y)"
        base = {"number": "a number" if self.allow_inf else "a finite number", "integer": "an integer",
                "alpha": "a finite number or a pair (ax, ay)"}[self.kind]
        if self.minimum is not None:
            base += f" {'>' if self.strict else '>='} {self.minimum:g}"
        if self.allow_inf:
            base += " (inf allowed)"
        return base

    def check(self, value: Any) -> Any:
        """``value`` validated and converted (``float``/``int``/``str``/tuple); raises ParameterError."""
        if value is None:
            if self.allow_none:
                return None
            raise ParameterError(f"{self.name} must be {self.allowed()}, got None")
        if self.kind == "choice":
            for c in self.choices:
                if value == c and type(value) is not bool and (isinstance(c, str) == isinstance(value, str)):
                    return c
            raise ParameterError(f"{self.name} must be {self.allowed()}; got {_short(value)}")
        if self.kind == "point":
            try:
                vals = [float(v) for v in value]
            except (TypeError, ValueError):
                vals = []
            if len(vals) != 2 or not all(math.isfinite(v) for v in vals) or isinstance(value, str):
                raise ParameterError(f"{self.name} must be {self.allowed()}, got {_short(value)}")
            return (vals[0], vals[1])
        if self.kind == "alpha" and isinstance(value, list | tuple):
            if len(value) != 2:
                raise ParameterError(f"{self.name} must be {self.allowed()}, got {_short(value)}")
            a, b = (self._number(v, value) for v in value)
            return a if a == b else (a, b)
        return self._number(value, value)

    def _number(self, v: Any, shown: Any) -> float | int:
        bad = ParameterError(f"{self.name} must be {self.allowed()}, got {_short(shown)}")
        if isinstance(v, bool) or (not isinstance(v, int | float) and not _is_numpy_number(v)):
            raise bad
        f = float(v)
        if math.isnan(f) or (math.isinf(f) and not self.allow_inf):
            raise bad
        if self.minimum is not None and (f < self.minimum or (self.strict and f == self.minimum)):
            raise bad
        if self.least is not None and f < self.least:
            raise ParameterError(f"{self.name} must be at least {self.least:g} ({self.allowed()}), got {_short(shown)}")
        if self.maximum is not None and f > self.maximum and not math.isinf(f):
            raise ParameterError(f"{self.name} must be at most {self.maximum:g} ({self.allowed()}), got {_short(shown)}")
        if self.kind == "integer":
            if not f.is_integer():
                raise bad
            return int(f)
        return f



def _is_numpy_number(v: Any) -> bool:
    import numbers

    return isinstance(v, numbers.Real)


def _short(v: Any, limit: int = 200) -> str:
    text = repr(v)
    return text if len(text) <= limit else text[: limit - 3] + "..."
