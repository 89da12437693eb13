"""The occupancy rule of images and arrays: which values are obstacles, checked and said in words.

Two rules, chosen by the readers' ``occupancy`` option (:data:`OCCUPANCY_RULES`), never guessed:

- ``"dark"``: grey levels, dark = occupied. A value ``v`` of an image whose white is ``W`` (255 for 8 bits,
  65535 for 16, the integer type's or the TIFF's bit depth; 1 for a 1-bit image) has occupancy
  ``(W - v) / W`` and is an obstacle when that exceeds ``threshold`` (default 0.5); ``negate`` reads
  ``v / W`` instead (light = occupied); a min-is-white TIFF stores 0 as white. The default of the image
  readers (PNG, PGM, BMP, TIFF). Floats and signed integers have no grey convention and are refused.
- ``"nonzero"``: any non-zero value is an obstacle (label rasters, masks); booleans True = obstacle. The
  default of ``.npy`` and plain Zarr arrays, which are arrays in gridfield's row order, not images.

Booleans that are not an image (a ``.npy``, a Zarr array) hold occupancy under either rule: True = obstacle.
The rule applied is recorded in the map's ``meta["occupancy_rule"]`` (``gridfield info`` prints it).
"""

from __future__ import annotations

from pathlib import Path as FsPath
from typing import Any

import numpy as np

from ..core.chunkcache import OccupancyRule
from ..core.errors import MapFormatError, ParameterError, shorten

__all__ = ["OCCUPANCY_RULES", "check_grey_options", "grey_text", "raster_rule"]

#: The values of the readers' ``occupancy`` option: grey levels (dark = occupied), or non-zero = obstacle.
OCCUPANCY_RULES = ("dark", "nonzero")

#: The advice of a refusal: what to give instead.
_GIVE = ("give occupancy='nonzero' (--occupancy nonzero) to read every non-zero value as an obstacle, or save "
         "the map as unsigned integers (0 = black = obstacle) or booleans (True = obstacle)")


def check_grey_options(occupancy: Any, threshold: Any, negate: Any, where: Any = "") -> tuple[str, float, bool]:
    """The ``occupancy``, ``threshold`` and ``negate`` options checked: ``threshold`` a number in [0, 1],
    ``negate`` a boolean, and both left at their defaults unless the rule is ``"dark"``.

    Parameters
    ----------
    occupancy : {"dark", "nonzero"}
    threshold : float in [0, 1]
    negate : bool
    where : str or path, optional
        The file, named first in the messages.

    Returns
    -------
    (str, float, bool)
        The three, checked.

    Examples
    --------
    >>> check_grey_options("dark", 0.65, True)
    ('dark', 0.65, True)
    >>> check_grey_options("nonzero", 0.5, True, "m.tif")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: m.tif: negate applies to grey levels (occupancy='dark'); ...
    """
    prefix = f"{where}: " if where else ""
    if occupancy not in OCCUPANCY_RULES:
        raise ParameterError(f"{prefix}occupancy must be one of {', '.join(map(repr, OCCUPANCY_RULES))}, got "
                             f"{shorten(occupancy)}")
    rule = str(occupancy)
    thr = _check_unit("threshold", threshold, str(where))
    neg = _as_bool01("negate", negate, str(where))
    if rule == "nonzero" and (neg or thr != 0.5):
        given = " and ".join(n for n, on in (("threshold", thr != 0.5), ("negate", neg)) if on)
        raise ParameterError(f"{prefix}{given} {'apply' if ' and ' in given else 'applies'} to grey levels "
                             "(occupancy='dark'); occupancy='nonzero' reads every non-zero value as an obstacle")
    return rule, thr, neg


def grey_text(threshold: float, negate: bool, scale: str = "") -> str:
    """The grey rule in words, e.g. ``"dark = occupied (grey level below 50 % of white)"``.

    Parameters
    ----------
    threshold : float
    negate : bool
    scale : str
        What the values are, appended after a semicolon (e.g. ``"values 0..255, 0 = black"``).

    Returns
    -------
    str

    Examples
    --------
    >>> grey_text(0.5, False, "values 0..65535, 0 = black")
    'dark = occupied (grey level below 50 % of white; values 0..65535, 0 = black)'
    >>> grey_text(0.65, True)
    'light = occupied (negate: grey level above 65 % of white)'
    """
    if negate:
        head = f"light = occupied (negate: grey level above {threshold * 100:g} % of white"
    else:
        head = f"dark = occupied (grey level below {(1.0 - threshold) * 100:g} % of white"
    return head + (f"; {scale})" if scale else ")")


def raster_rule(p: FsPath, dtype: Any, occupancy: str, threshold: float, negate: bool, *,
                image: bool, min_is_white: bool = False, bits: int | None = None) -> OccupancyRule:
    """The rule that turns a raster of ``dtype`` into occupancy (options already checked by
    :func:`check_grey_options`), or MapFormatError naming the file when its values have no grey
    convention under ``"dark"``.

    Parameters
    ----------
    p : pathlib.Path
        The file (for the messages).
    dtype : numpy dtype
    occupancy, threshold, negate
        The checked options.
    image : bool
        An image (a TIFF: booleans are 1-bit grey levels) or an array (booleans are occupancy).
    min_is_white : bool
        The image stores 0 as white (TIFF photometric MINISWHITE).
    bits : int, optional
        The image's bits per sample, when fewer than its integer type holds (a 12-bit TIFF).

    Returns
    -------
    OccupancyRule

    Examples
    --------
    >>> r = raster_rule(FsPath("m.tif"), np.uint16, "dark", 0.5, False, image=True)
    >>> r.white, r.text
    (65535.0, 'dark = occupied (grey level below 50 % of white; values 0..65535, 0 = black)')
    >>> raster_rule(FsPath("m.npy"), np.bool_, "dark", 0.5, False, image=False).text
    'True = obstacle (boolean raster)'
    """
    dt = np.dtype(dtype)
    if dt == np.bool_ and not (image and occupancy == "dark"):
        if occupancy == "dark" and (negate or threshold != 0.5):
            raise ParameterError(f"{p}: a boolean array holds occupancy (True = obstacle), not grey levels: "
                                 "threshold and negate do not apply")
        return OccupancyRule(text="True = obstacle (boolean raster)")
    if occupancy == "nonzero":
        return OccupancyRule(text="non-zero = obstacle")
    if dt.kind == "f":
        raise MapFormatError(f"{p}: a {dt} raster has no grey-level convention (its values may be heights, "
                             f"probabilities or grey levels); {_GIVE}")
    if dt.kind != "b" and dt.kind != "u":
        raise MapFormatError(f"{p}: {dt} values (signed integers) have no grey-level convention; {_GIVE}")
    depth = 1 if dt.kind == "b" else 8 * dt.itemsize
    if bits is not None and 0 < bits < depth:
        depth = bits
    white = float(2**depth - 1)
    scale = "1-bit" if depth == 1 else f"values 0..{2**depth - 1}"
    if min_is_white:
        scale += f", min-is-white: {'1 = black' if depth == 1 else '0 = white'}"
    else:
        scale += ", 0 = black"
    return OccupancyRule(white, threshold, light=negate != min_is_white, text=grey_text(threshold, negate, scale))


def _check_unit(name: str, value: Any, where: str = "") -> float:
    """A number in [0, 1] (bools and NaN rejected)."""
    prefix = f"{where}: " if where else ""
    try:
        if isinstance(value, bool):
            raise TypeError
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{prefix}{name} must be a number in [0, 1], got {shorten(value)}") from None
    if not 0.0 <= v <= 1.0:
        raise ParameterError(f"{prefix}{name} must be a number in [0, 1], got {shorten(value)}")
    return v


def _as_bool01(name: str, value: Any, where: str = "") -> bool:
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, int | np.integer) and value in (0, 1):
        return bool(value)
    prefix = f"{where}: " if where else ""
    raise ParameterError(f"{prefix}{name} must be 0 or 1 (or false/true), got {shorten(value)}")
