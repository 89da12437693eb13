"""The size guard: refuse inputs whose grids would not fit in memory, before allocating anything.

Every grid gridfield builds is checked here first (:func:`check_cells`): a world rasterized at a
fine resolution, an image (from its header, before decoding), an ``.npz`` array (from its header,
before loading), the resolutions of ``compare``, arrays given to the API. Above the limit a
:class:`~gridfield.errors.SizeLimitError` names the size in cells and bytes and how to raise the
limit, in well under a second.

The limit, in cells, is the first of:

1. :func:`override` (the command line's ``--max-cells``),
2. the environment variable ``GRIDFIELD_MAX_CELLS``,
3. :func:`default_max_cells`: a quarter of the machine's physical memory divided by
   :data:`BYTES_PER_CELL` (what a distance map, a potential and its gradients need per cell),
   leaving room for temporaries, decoding and other programs.

Examples
--------
>>> check_cells((100, 200), "grid")
20000
>>> with override(1000):
...     check_cells((100, 200), "world.yaml at resolution 0.1")
Traceback (most recent call last):
...
gridfield.errors.SizeLimitError: world.yaml at resolution 0.1: 100 x 200 = 20000 cells would need about 1.3 MB ...
"""

from __future__ import annotations

import contextlib
import functools
import math
import os
from collections.abc import Iterator, Sequence

from .errors import ParameterError, SizeLimitError

__all__ = ["BYTES_PER_CELL", "ENV_VAR", "check_cells", "default_max_cells", "max_cells", "override", "parse_max_cells"]

#: Bytes per cell of the full pipeline: occupancy, brushfire (steps, distance, nearest obstacle,
#: labels, GVD), potential and its two gradients, plus temporaries.
BYTES_PER_CELL = 64

#: Environment variable that sets the limit in cells.
ENV_VAR = "GRIDFIELD_MAX_CELLS"

_OVERRIDE: list[int] = []


def _physical_memory() -> int | None:
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):  # not POSIX
        return None


@functools.cache
def default_max_cells() -> int:
    """A quarter of the physical memory over :data:`BYTES_PER_CELL` (2**26 cells if the memory is unknown).

    Returns
    -------
    int
        At least a million cells.

    Examples
    --------
    >>> default_max_cells() >= 10**6
    True
    """
    mem = _physical_memory()
    if not mem or mem <= 0:
        return 2**26
    return max(10**6, mem // 4 // BYTES_PER_CELL)


def parse_max_cells(value: object, where: str) -> int:
    """A positive cell count from an option or the environment (``1e9`` and ``1_000_000`` allowed).

    Parameters
    ----------
    value : str or number
    where : str
        The option or variable it came from, for the message.

    Returns
    -------
    int

    Examples
    --------
    >>> parse_max_cells("1e9", "--max-cells"), parse_max_cells("2_000", "GRIDFIELD_MAX_CELLS")
    (1000000000, 2000)
    >>> parse_max_cells("lots", "--max-cells")
    Traceback (most recent call last):
    ...
    gridfield.errors.ParameterError: --max-cells must be a positive number of cells, got 'lots'
    """
    try:
        if isinstance(value, bool):
            raise ValueError
        n = float(str(value).replace("_", "")) if isinstance(value, str) else float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        n = math.nan
    if not (math.isfinite(n) and n >= 1):
        raise ParameterError(f"{where} must be a positive number of cells, got {value!r}")
    return int(n)


def _env_or_default() -> int:
    env = os.environ.get(ENV_VAR)
    return parse_max_cells(env, ENV_VAR) if env else default_max_cells()


def max_cells() -> int:
    """The limit in force, in cells (see the module docstring).

    Returns
    -------
    int
        The innermost :func:`override`, else ``GRIDFIELD_MAX_CELLS``, else :func:`default_max_cells`.

    Examples
    --------
    >>> with override("5e6"):
    ...     max_cells()
    5000000
    """
    return _OVERRIDE[-1] if _OVERRIDE else _env_or_default()


@contextlib.contextmanager
def override(limit: int | float | str | None) -> Iterator[None]:
    """Within the ``with`` block the limit is ``limit`` cells (``None``: no change).

    Parameters
    ----------
    limit : int, float, str or None
        Parsed by :func:`parse_max_cells`.

    Yields
    ------
    None
        The previous limit is restored when the block ends (overrides nest).

    Examples
    --------
    >>> with override(100):
    ...     check_cells((10, 10), "grid")
    100
    """
    if limit is None:
        yield
        return
    _OVERRIDE.append(parse_max_cells(limit, "max_cells"))
    try:
        yield
    finally:
        _OVERRIDE.pop()


def _bytes(n: float) -> str:
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= size:
            return f"{n / size:.2g} {unit}" if n / size < 10 else f"{n / size:.0f} {unit}"
    return f"{n:.0f} B"


def check_cells(shape_or_count: Sequence[float] | float, what: str, *, bytes_per_cell: int = BYTES_PER_CELL) -> int:
    """Raise :class:`SizeLimitError` if a grid of this shape (or cell count) exceeds the limit.

    Parameters
    ----------
    shape_or_count : (rows, cols), any shape, or a number of cells
        Non-integers (e.g. an extent over a resolution) are allowed: the count is what matters.
    what : str
        What is being sized, for the message (e.g. ``"map.png (image header)"``).
    bytes_per_cell : int
        For the message's byte estimate.

    Returns
    -------
    int
        The number of cells (when within the limit).

    Examples
    --------
    >>> check_cells((100, 200), "grid"), check_cells(2.5e3, "an extent over a resolution")
    (20000, 2500)
    >>> with override(1000):
    ...     check_cells((50, 50), "map.png (image header)")
    Traceback (most recent call last):
    ...
    gridfield.errors.SizeLimitError: map.png (image header): 50 x 50 = 2500 cells would need about 160 kB of memory, ...
    """
    if type(shape_or_count) is tuple and len(shape_or_count) == 2 and type(shape_or_count[0]) is int and type(
            shape_or_count[1]) is int:  # the common case (a Grid's shape), kept cheap
        n = shape_or_count[0] * shape_or_count[1]
        if n <= (_OVERRIDE[-1] if _OVERRIDE else _env_or_default()):
            return n
    if isinstance(shape_or_count, int | float):
        count = float(shape_or_count)
        shape_text = ""
    else:
        dims = [float(d) for d in shape_or_count]
        count = math.prod(dims) if dims else 1.0
        shape_text = " x ".join(f"{d:.0f}" if d < 1e15 else f"{d:.3g}" for d in dims) + " = "
    limit = max_cells()
    if not count <= limit:  # NaN too
        if not math.isfinite(count):
            cells, memory = "more cells than a float can count", "unbounded memory"
        else:
            cells = f"{count:.0f} cells" if count < 1e15 else f"{count:.3g} cells"
            memory = f"about {_bytes(count * bytes_per_cell)} of memory"
        raise SizeLimitError(
            f"{what}: {shape_text}{cells} would need {memory}, more "
            f"than the limit of {limit} cells; raise it with --max-cells N or the environment variable "
            f"{ENV_VAR}=N (or use a coarser resolution / a smaller map)"
        )
    return int(count)
