"""The one parameter registry: every planner parameter's type, default, scaling rule, range and meaning.

Each concern is a frozen dataclass (:class:`Attraction`, :class:`Repulsion`, :class:`Model`,
:class:`NavFunction`, :class:`Vortex`, :class:`Follower`, :class:`Escape`, :class:`Navigation`, :class:`NavFn`) whose fields carry a
:class:`Spec` in their metadata. :data:`REGISTRY` (name -> :class:`Spec`) is built from them, and
everything else is generated from it: :func:`validate` (the check behind
:func:`gridfield.planners.plan`), :func:`resolve` (defaults filled in, lengths scaled to the map),
the command line's flags and their help (:func:`help_text`), the sweep-spec check and the docs.

Adding a parameter is one field in one dataclass (the tables, ``core/_param_table.py``; the
:class:`Spec` type is in ``core/_param_spec.py``), and reading it in the module that uses it.

Length defaults scale with the map
    A length whose default is ``None`` is resolved by :func:`resolve` from the map's length unit
    ``unit`` (a grid map's cell size; an exact planner's world resolution), so a map at resolution
    1 and the same map at 0.05 give the same path in cells:

    - ``q_star`` = 4 cells; ``d_star`` = 2 ``q_star`` (conic attraction beyond it);
    - ``step`` = 1 cell; ``tolerance`` = ``step`` (normalized rule) or 1 cell (scaled rule);
    - ``escape_radius`` = 6 cells;
    - ``clearance_band`` = 6 cells (nf1's band along the obstacles, where its front is slowed);
    - ``eta`` is balanced: the repulsive force at distance ``q_star / 2`` from an obstacle equals
      the largest attractive force ``zeta * min(d_star, 2 q_star)``, so that near a wall the
      repulsion wins (at one cell from a wall, with the defaults, it is 12 times the attraction).

    Values given by a world file's ``params`` or by the user always win.

Examples
--------
>>> p = validate({"q_star": 0.5, "escape": "random_walk"})
>>> p["q_star"], p["escape"]
(0.5, 'random_walk')
>>> validate({"step": "abc"})
Traceback (most recent call last):
...
gridfield.core.errors.ParameterError: step must be a finite number > 0, got 'abc'
>>> r = resolve({}, unit=0.05)
>>> r["q_star"], r["d_star"], r["step"], r["tolerance"], r["escape_radius"]
(0.2, 0.4, 0.05, 0.05, 0.30000000000000004)
"""

from __future__ import annotations

import dataclasses
import difflib
import functools
import math
from collections.abc import Iterator, Mapping
from typing import Any

from ._param_spec import Spec, _short
from ._param_table import (
    CLEARANCE_BAND_CELLS,
    D_STAR_PER_Q_STAR,
    ESCAPE_RADIUS_CELLS,
    MAX_ITERATIONS,
    Q_STAR_CELLS,
    STEP_CELLS,
    Attraction,
    Escape,
    Follower,
    Model,
    NavFn,
    NavFunction,
    Navigation,
    Repulsion,
    Vortex,
)
from .errors import ParameterError

__all__ = [
    "FIELD_GROUPS",
    "GROUPS",
    "REGISTRY",
    "Attraction",
    "Escape",
    "Follower",
    "Model",
    "NavFn",
    "NavFunction",
    "Navigation",
    "Params",
    "Repulsion",
    "Spec",
    "Vortex",
    "check",
    "group",
    "help_text",
    "known",
    "names",
    "parse",
    "resolve",
    "resolve_field",
    "validate",
]


@functools.lru_cache(maxsize=256)
def _argument_spec(name: str, argument: str | None, limits: tuple[tuple[str, Any], ...]) -> Spec:
    """The Spec that checks a function argument (see :func:`check`); built once per signature."""
    lim = dict(limits)
    base = REGISTRY.get(name)
    if base is None:
        kind = lim.pop("kind", "number")
        return Spec(name=argument or name, group="", kind=kind, default=None, meaning="", **lim)
    return dataclasses.replace(base, name=argument or name, allow_none=False, **lim)


def check(name: str, value: Any, *, argument: str | None = None, **limits: Any) -> Any:
    """A function argument checked by the registry's rules: the one argument checker.

    The functions that take a parameter as an argument (:func:`gridfield.following.descent.descend`, the
    arrays of :mod:`gridfield.fields.potential`, the samplers, ...) check it with the :class:`Spec` of
    the registry entry ``name``, so a value means the same everywhere and every message has the
    registry's wording (parameter, value, what is allowed). ``None`` is refused: a function
    argument holds a value, not "resolve the default".

    Parameters
    ----------
    name : str
        The registry entry (:data:`REGISTRY`); or, for an argument that is no planner parameter
        (``unit``, ``revisit_tolerance``), any name, with ``kind`` and the bounds in ``limits``.
    value : object
        The argument's value.
    argument : str, optional
        The argument's own name when it differs from the entry's (``mode`` for ``repulsion``);
        the message names it.
    **limits
        :class:`Spec` fields that override the entry's (``minimum``, ``strict``, ``allow_inf``,
        ``kind``, ``choices``).

    Returns
    -------
    object
        The value converted (``float``, ``int``, the option string, a pair as a tuple).

    Raises
    ------
    ParameterError
        naming the argument, the value and what is allowed.

    Examples
    --------
    >>> check("step", 0.5), check("max_iterations", 10.0), check("repulsion", "sum", argument="mode")
    (0.5, 10, 'sum')
    >>> check("unit", 0, minimum=0.0, strict=True)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: unit must be a finite number > 0, got 0
    >>> check("repulsion", "all", argument="mode")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: mode must be one of 'nearest', 'sum'; got 'all'
    """
    return _argument_spec(name, argument, tuple(sorted(limits.items()))).check(value)


#: The concerns, in the order help and docs list them.
GROUPS: tuple[type, ...] = (Attraction, Repulsion, Model, NavFunction, Vortex, Follower, Escape, Navigation, NavFn)


def _build() -> dict[str, Spec]:
    out: dict[str, Spec] = {}
    for cls in GROUPS:
        for f in dataclasses.fields(cls):
            meta = dict(f.metadata["spec"])
            name = meta.pop("name_override", f.name)  # ``lambda`` is a Python keyword: field ``lam``
            out[name] = Spec(name=name, **meta)
    return out


#: name -> Spec, every parameter a planner may read.
REGISTRY: dict[str, Spec] = _build()

#: The concerns of a potential field: what :func:`gridfield.fields.potential.build_field` reads and keeps, resolved,
#: in ``Field.params`` (:func:`gridfield.fields.potential.resolve_params`, :func:`gridfield.fields.vortex.vortex_field`).
FIELD_GROUPS: tuple[type, ...] = (Attraction, Repulsion, Model, Vortex)


def names(*groups: type) -> tuple[str, ...]:
    """The registry names of the parameters of these concerns, in their order.

    Parameters
    ----------
    *groups : type
        Concerns of :data:`GROUPS` (``Attraction``, ...).

    Returns
    -------
    tuple of str
        Their parameters' names (``lambda`` for ``Navigation.lam``).

    Examples
    --------
    >>> names(Attraction, Model)
    ('zeta', 'd_star', 'model')
    """
    return tuple(f.metadata["spec"].get("name_override", f.name) for cls in groups for f in dataclasses.fields(cls))

_KIND_TYPES = {"number": "float", "integer": "int", "alpha": "float or (float, float)", "point": "(float, float)"}


def _rst_text(text: str) -> str:
    """``text`` with the characters reStructuredText would read as markup escaped."""
    return text.replace("\\", "\\\\").replace("*", "\\*").replace("|", "\\|").replace("`", "\\`")


def _parameters_section(cls: type) -> str:
    """The numpydoc Parameters section of one concern, written from the registry (never out of date)."""
    lines = ["Parameters", "----------"]
    for f in dataclasses.fields(cls):
        name = f.metadata["spec"].get("name_override", f.name)
        s = REGISTRY[name]
        kind = "{" + ", ".join(repr(c) for c in s.choices) + "}" if s.kind == "choice" else _KIND_TYPES[s.kind]
        default = "None" if s.default is None else repr(s.default)
        lines.append(f"{f.name} : {kind}{' or None' if s.allow_none else ''}, default {default}")
        alias = f" (the parameter ``{name}``)" if name != f.name else ""
        scaled = f" None: {s.scale}." if s.default is None and s.scale else ""
        lines.append(f"    {_rst_text(s.meaning[0].upper() + s.meaning[1:])}{alias}.{_rst_text(scaled)} "
                     f"Read by: {', '.join(s.planners)}.")
    return "\n".join(lines)


def _document_groups() -> None:
    """Put each concern's Parameters section before its Examples (docstrings may be stripped by -OO)."""
    for cls in GROUPS:
        doc = cls.__doc__
        if doc is None:
            continue
        head, sep, examples = doc.partition("\n    Examples\n")
        section = _parameters_section(cls).replace("\n", "\n    ")
        cls.__doc__ = f"{head.rstrip()}\n\n    {section}\n{sep}{examples}"


_document_groups()


class Params(Mapping[str, Any]):
    """A validated, read-only mapping of parameter values (only the names given, or resolved).

    Built by :func:`validate`, which checks the values; the constructor does not.

    Parameters
    ----------
    values : mapping
        Parameter name -> checked value.

    Examples
    --------
    >>> p = validate({"eta": 2})
    >>> p["eta"], dict(p)
    (2.0, {'eta': 2.0})
    >>> p
    Params(eta=2.0)
    """

    __slots__ = ("_d",)

    def __init__(self, values: Mapping[str, Any]) -> None:
        self._d = dict(values)

    def __getitem__(self, key: str) -> Any:
        return self._d[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._d)

    def __len__(self) -> int:
        return len(self._d)

    def __repr__(self) -> str:
        return "Params(" + ", ".join(f"{k}={v!r}" for k, v in self._d.items()) + ")"

    def group(self, cls: type) -> Any:
        """The values of one concern as its frozen dataclass (defaults for names not given)."""
        return group(cls, self._d)


def group(cls: type, values: Mapping[str, Any]) -> Any:
    """The values of one concern (a dataclass of :data:`GROUPS`) taken from a parameter mapping.

    The typed view of already checked values (:func:`resolve`'s, a :class:`Params`): the names of
    ``cls`` found in ``values`` fill its fields, the others keep the registry's defaults.

    Parameters
    ----------
    cls : type
        A concern (``Follower``, ``Escape``, ...).
    values : mapping
        Parameter name -> value (other names are ignored).

    Returns
    -------
    object
        An instance of ``cls``.

    Examples
    --------
    >>> f = group(Follower, resolve({"step": 0.5}, unit=1.0))
    >>> f.step, f.tolerance, f.max_iterations
    (0.5, 0.5, 10000)
    """
    fields = {f.metadata["spec"].get("name_override", f.name): f.name for f in dataclasses.fields(cls)}
    return cls(**{fields[k]: v for k, v in values.items() if k in fields})


def _unknown(name: str) -> ParameterError:
    close = difflib.get_close_matches(name, REGISTRY, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return ParameterError(f"unknown parameter {_short(name, 60)}; {hint}known parameters: "
                          f"{', '.join(sorted(REGISTRY))}")


def validate(params: Mapping[str, Any] | None) -> Params:
    """Check names and values of ``params`` against :data:`REGISTRY`; return them converted.

    Parameters
    ----------
    params : mapping or None
        Parameter name -> value (numbers as numbers, options as strings).

    Returns
    -------
    Params
        The same names, values converted (``float``, ``int``, option strings, tuples).

    Raises
    ------
    ParameterError
        An unknown name (with a "did you mean"), or a value of the wrong type or out of range; the
        message names the parameter, the value and what is allowed.

    Examples
    --------
    >>> validate({"max_iterations": 10.0})["max_iterations"]
    10
    >>> validate({"max_iterations": "10"})
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: max_iterations must be an integer >= 0, got '10'
    """
    if params is None:
        return Params({})
    if isinstance(params, Params):
        return params
    if not isinstance(params, Mapping):
        raise ParameterError(f"params must be a mapping of parameter names to values, got {type(params).__name__}")
    out: dict[str, Any] = {}
    for k, v in params.items():
        if not isinstance(k, str) or k not in REGISTRY:
            raise _unknown(str(k))
        out[k] = REGISTRY[k].check(v)
    return Params(out)


def known(record: Mapping[str, Any] | None) -> Params:
    """The registry's names of a parameter record, checked by :func:`validate`; its other keys left out.

    For the record a result keeps (``Field.params``, a follower's merged parameters), which may also
    name its construction (a navigation field's ``navigation``, ``costs``): read it as typed groups,
    ``known(field.params).group(Vortex)``, with the registry's defaults for the names it lacks.

    Parameters
    ----------
    record : mapping or None

    Returns
    -------
    Params

    Examples
    --------
    >>> known({"ka": 10, "navigation": "wavefront"}).group(Vortex).ka
    10.0
    """
    return validate({k: v for k, v in (record or {}).items() if k in REGISTRY})


def parse(name: str, text: str) -> Any:
    """A command-line string as the value parameter ``name`` takes (then checked).

    Parameters
    ----------
    name : str
        A name of :data:`REGISTRY`.
    text : str
        The value as typed: a number, an option, ``none`` (where allowed), ``ax,ay`` for ``alpha``,
        ``x,y`` for a point.

    Returns
    -------
    object
        The checked value (``float``, ``int``, ``str``, tuple or None).

    Raises
    ------
    ParameterError
        For an unknown name or a value the parameter does not allow.

    Examples
    --------
    >>> parse("q_star", "0.5"), parse("escape", "navigation"), parse("max_iterations", "20")
    (0.5, 'navigation', 20)
    >>> parse("kappa", "abc")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: kappa must be a finite number > 0, got 'abc'
    """
    if name not in REGISTRY:
        raise _unknown(name)
    spec = REGISTRY[name]
    t = text.strip()
    if t.lower() in ("none", "null") and spec.allow_none:
        return None
    value: Any = t
    if spec.kind in ("number", "integer", "alpha") or (spec.kind == "choice" and all(isinstance(c, int)
                                                                                     for c in spec.choices)):
        try:
            value = float(t)
            if value.is_integer() and spec.kind != "number":
                value = int(value)
        except ValueError:
            if spec.kind == "alpha" and "," in t:
                try:
                    value = [float(s) for s in t.split(",")]
                except ValueError:
                    value = t
    elif spec.kind == "point":
        try:
            value = [float(s) for s in t.split(",")]
        except ValueError:
            value = t
    return spec.check(value)


def resolve(params: Mapping[str, Any] | None, *, unit: float) -> dict[str, Any]:
    """Every parameter with its default, lengths scaled to the map's length ``unit``.

    Parameters
    ----------
    params : mapping or None
        Given values (validated here); they always win over defaults.
    unit : float
        The map's length unit: a grid map's cell size, or an exact planner's world resolution.

    Returns
    -------
    dict
        Every name of :data:`REGISTRY`; ``q_star``, ``d_star``, ``eta``, ``step``, ``tolerance`` and
        ``escape_radius`` resolved by the rules of the module docstring (the others keep ``None``
        where ``None`` is their meaning).

    Examples
    --------
    >>> r = resolve({"q_star": 2.0, "d_star": math.inf, "eta": 1.0}, unit=0.05)   # given: unchanged
    >>> r["q_star"], r["d_star"], r["eta"], r["step"]
    (2.0, inf, 1.0, 0.05)
    >>> r = resolve({}, unit=1.0)
    >>> r["eta"]   # zeta * d_star * q_star * (q_star / 2)**2 = 1 * 8 * 4 * 4
    128.0
    """
    if not (isinstance(unit, int | float) and math.isfinite(unit) and unit > 0):
        raise ParameterError(f"the map's length unit must be a finite number > 0, got {unit!r}")
    given = validate(params)
    p: dict[str, Any] = {name: spec.default for name, spec in REGISTRY.items()}
    p.update(given)
    if p["q_star"] is None:
        p["q_star"] = Q_STAR_CELLS * unit
    if p["d_star"] is None:
        p["d_star"] = D_STAR_PER_Q_STAR * p["q_star"] if math.isfinite(p["q_star"]) else math.inf
    if p["eta"] is None:
        p["eta"] = balanced_eta(p["zeta"], p["d_star"], p["q_star"], p["repulsive_power"], unit)
    if p["step"] is None:
        p["step"] = STEP_CELLS * unit
    if p["tolerance"] is None:
        p["tolerance"] = p["step"] if p["step_rule"] == "normalized" else unit
    if p["clearance_band"] is None:
        p["clearance_band"] = CLEARANCE_BAND_CELLS * unit
    if p["escape_radius"] is None:
        p["escape_radius"] = ESCAPE_RADIUS_CELLS * unit
    if p["max_iterations"] is None:
        p["max_iterations"] = MAX_ITERATIONS
    return p


def resolve_field(params: Mapping[str, Any] | None, *, unit: float) -> dict[str, Any]:
    """The parameters a potential field is built with: those of :data:`FIELD_GROUPS` resolved, the
    other names given kept, and a complete model's own (``attraction``, ``clearance_gain``).

    The one resolution behind :func:`gridfield.fields.potential.resolve_params` and the complete models of
    :mod:`gridfield.fields.navfield` (which cannot import ``potential``: it dispatches to them). ``model``
    unset stays ``None`` for the caller to choose.

    Parameters
    ----------
    params : mapping, optional
        Parameter names and values (checked by :func:`validate`).
    unit : float
        The map's length unit (cell size) the length defaults scale with.

    Returns
    -------
    dict
        The field parameters in :data:`FIELD_GROUPS` order, then the other names given.

    Examples
    --------
    >>> p = resolve_field({"model": "nf1", "step": 0.1}, unit=0.5)
    >>> p["q_star"], p["attraction"], p["step"]
    (2.0, 'eikonal', 0.1)
    """
    given = dict(validate(params))
    full = resolve(given, unit=unit)
    field_names = names(*FIELD_GROUPS)
    p = {k: full[k] for k in field_names}
    p.update(given)
    p.update({k: full[k] for k in field_names})
    if p["model"] in ("nf1", "nf2", "nf-blend"):  # the complete models' own parameters (NavFunction)
        p.update({k: full[k] for k in names(NavFunction)})
    return p


def balanced_eta(zeta: float, d_star: float, q_star: float, power: float, unit: float) -> float:
    """The repulsive gain whose force at ``q_star / 2`` equals the attraction ``zeta * min(d_star, 2 q_star)``.

    ``q_star = inf``: balanced at 2 units from the obstacle against ``zeta * min(d_star, 8 units)``.

    Examples
    --------
    >>> balanced_eta(1.0, 8.0, 4.0, 2.0, 1.0)   # eta * (1/2 - 1/4) / 2**2 = 8
    128.0
    """
    z = zeta if zeta > 0 else 1.0
    if math.isfinite(q_star):
        db, inv_q, cap = q_star / 2.0, 1.0 / q_star, 2.0 * q_star
    else:
        db, inv_q, cap = 2.0 * unit, 0.0, 8.0 * unit
    attraction = z * min(d_star, cap)
    try:
        eta = float(attraction / ((1.0 / db - inv_q) / db**power))
    except (ZeroDivisionError, OverflowError):
        eta = math.nan
    # q_star so small or large that (q_star/2)**p leaves the floats (no attraction: eta 0 balances it)
    if not (math.isfinite(eta) and (eta > 0 or (eta == 0 and attraction == 0))):
        raise ParameterError(f"q_star = {q_star:g} with repulsive_power {power:g}: the balanced eta (the repulsion "
                             f"at q_star/2 equal to the attraction) is not a finite positive number; give eta, or a "
                             f"q_star nearer the map's scale")
    return eta


def help_text(name: str) -> str:
    """One line for ``--help``: meaning, default (or scaling rule), allowed values, planners.

    Parameters
    ----------
    name : str
        A name of :data:`REGISTRY`.

    Returns
    -------
    str
        The line, with ``%`` doubled for argparse.

    Examples
    --------
    >>> help_text("q_star")
    'obstacle distance of influence of the repulsion; default: 4 cells; a number > 0 (inf allowed); ...'
    """
    s = REGISTRY[name]
    default = s.scale if (s.default is None and s.scale) else ("none" if s.default is None else repr(s.default))
    most = (f", at least {s.least:g}" if s.least is not None else "") + (
        f", at most {s.maximum:g}" if s.maximum is not None else "")
    text = f"{s.meaning}; default: {default}; {s.allowed()}{most}; read by: {', '.join(s.planners)}"
    return text.replace("%", "%%")
