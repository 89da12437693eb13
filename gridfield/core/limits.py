"""The size guard: refuse inputs whose grids would not fit in memory, before allocating anything.

Every grid gridfield builds is checked here first (:func:`check_cells`): a world rasterized at a
fine resolution, an image (from its header, before decoding), an ``.npz`` array (from its header,
before loading), the resolutions of ``compare``, arrays given to the API. Above the limit a
:class:`~gridfield.core.errors.SizeLimitError` names the size in cells and bytes and how to raise the
limit, in well under a second.

The limit, in cells, is the first of:

1. :func:`override` (the command line's ``--max-cells``),
2. the environment variable ``GRIDFIELD_MAX_CELLS``,
3. :func:`default_max_cells`: a quarter of the machine's physical memory divided by
   :data:`BYTES_PER_CELL` (what a distance map, a potential and its gradients need per cell),
   leaving room for temporaries, decoding and other programs.

Bytes per job
    Within :func:`job` (the command line enters it for every command: ``plan:potential``,
    ``brushfire``, ``sweep``, ...), every grid checked is also sized in bytes: its cells times the
    job's measured peak bytes per cell (:data:`JOB_BYTES_PER_CELL`, from ``benchmarks/memory.py``)
    times the number of workers. The rule:

    - with the default limit (no ``--max-cells``, no ``GRIDFIELD_MAX_CELLS``), a grid is refused
      when its cells exceed :func:`default_max_cells` **or** its estimate exceeds
      :func:`memory_budget` (:data:`MEMORY_FRACTION` of the memory available now), whichever is
      stricter;
    - a limit set by the user is the user's word: cells only (the estimate is still named in the
      message). Should memory then run out anyway, the command line and the sweep runner turn
      the ``MemoryError`` into one :class:`~gridfield.core.errors.SizeLimitError` line
      (:func:`out_of_memory`) naming what was being built.

Time of the searches
    The searches whose time grows with a map's detail rather than its cells (the any-angle
    visibility graph of a grid map's corners, which only the ``graph`` search builds, the exact polygons of a grid map, the visibility graph of a vector
    world, the exact potential's geometry) estimate their time from that detail before they start
    (:func:`check_seconds`, :data:`SECONDS_PER`) and refuse above ``GRIDFIELD_MAX_SECONDS``
    (default :data:`DEFAULT_MAX_SECONDS`; ``inf`` switches it off). The figures are rough (the
    2-core development machine; ``benchmarks/README.md``, "Time of the searches"): the point is to
    refuse a search of minutes in well under a second, not to predict it. A command of several
    searches is refused up front on their sum (:func:`check_stages`; ``plan`` and ``compare`` count
    a grid map's work with :func:`grid_map_work` before building its polygons). The command line
    shows the search in progress on stderr when its estimate exceeds :data:`PROGRESS_SECONDS`
    (:func:`progress`: on a terminal, or with ``GRIDFIELD_PROGRESS=1``). The time guard and the
    progress line are written in ``core/_time_guard.py``; this module re-exports them.

The API's byte guard
    :func:`check_grid` sizes the grid of ``plan``'s grid planners, ``build_field`` and ``brushfire``
    in bytes as within :func:`job` when no job is in force: half the memory available now by default.

Examples
--------
>>> check_cells((100, 200), "grid")
20000
>>> with override(1000):
...     check_cells((100, 200), "world.yaml at resolution 0.1")
Traceback (most recent call last):
...
gridfield.core.errors.SizeLimitError: world.yaml at resolution 0.1: 100 x 200 = 20000 cells would need about 1.3 MB ...
"""

from __future__ import annotations

import contextlib
import functools
import math
import os
from collections.abc import Iterator, Sequence

from ._time_guard import (
    DEFAULT_MAX_SECONDS,
    PROGRESS_ENV_VAR,
    PROGRESS_INTERVAL,
    PROGRESS_SECONDS,
    SECONDS_ENV_VAR,
    SECONDS_PER,
    SECONDS_POWER,
    check_seconds,
    check_stages,
    estimate_seconds,
    grid_map_work,
    max_seconds,
    progress,
)
from .errors import ParameterError, SizeLimitError

__all__ = [
    "BYTES_PER_CELL",
    "DEFAULT_MAX_SECONDS",
    "ENV_VAR",
    "JOB_BYTES_PER_CELL",
    "MEMORY_FRACTION",
    "PROGRESS_ENV_VAR",
    "PROGRESS_INTERVAL",
    "PROGRESS_SECONDS",
    "SECONDS_ENV_VAR",
    "SECONDS_PER",
    "SECONDS_POWER",
    "available_memory",
    "check_cells",
    "check_grid",
    "check_seconds",
    "check_stages",
    "default_max_cells",
    "estimate_seconds",
    "grid_map_work",
    "job",
    "job_bytes_per_cell",
    "job_planners",
    "max_cells",
    "max_seconds",
    "memory_budget",
    "out_of_memory",
    "override",
    "parse_max_cells",
    "progress",
    "user_limit",
]

#: Bytes per cell of the full pipeline: occupancy, brushfire (steps, distance, nearest obstacle,
#: labels, GVD), potential and its two gradients, plus temporaries.
BYTES_PER_CELL = 64

#: Environment variable that sets the limit in cells.
ENV_VAR = "GRIDFIELD_MAX_CELLS"

#: Peak bytes per cell of each job, measured by ``benchmarks/memory.py`` (peak resident memory of
#: the command at 512^2, 1024^2 and 1448^2 cells (plan:potential: 1024^2 and 2048^2, stop 39), least-squares slope over the cell count), rounded up
#: by about a quarter for what the benchmark map does not exercise. Keys are a command or
#: ``command:planner``; :func:`job_bytes_per_cell` falls back from ``plan:X`` to ``plan`` and from
#: an unknown job to :data:`BYTES_PER_CELL`.
JOB_BYTES_PER_CELL: dict[str, int] = {
    "info": 8,  # measured 5.5: the occupancy and the labelling of its obstacle regions
    "brushfire": 48,  # measured 35
    "field": 96,  # measured 74 (the potential model; a navigation field uses its planner's figure)
    "plan": 176,  # the largest planner but harmonic: unknown planners on a grid
    "plan:potential": 160,  # measured 126 (the classic field with its diagnosis; the default nf1 95)
    "plan:wavefront": 56,  # measured 43
    "plan:wavefront-octile": 24,  # measured 18
    "plan:fmm": 64,  # measured 52
    "plan:harmonic": 400,  # measured 312
    "compare": 192,  # the grid planner at the finest resolution (default potential) and the exact one; measured 154
    "explore": 160,  # not measured (interactive): the potential planner's figure
    "sweep": 176,  # not measured: per worker, the spec's largest planner figure once its planners are known
}

#: Fraction of the memory available now that one job may plan to use (see "Bytes per job").
MEMORY_FRACTION = 0.5

_OVERRIDE: list[int] = []

# the job in force: (name, bytes per cell, workers, budget in bytes or None); see job()
_JOB: list[tuple[str, int, int, int | None]] = []


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
    gridfield.core.errors.ParameterError: --max-cells must be a positive number of cells, got 'lots'
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
    return parse_max_cells(env, ENV_VAR) if env is not None else default_max_cells()  # "" is refused too


def user_limit() -> int | None:
    """The limit the user set (:func:`override`, else ``GRIDFIELD_MAX_CELLS``), or None for the default.

    Returns
    -------
    int or None
        An empty or junk ``GRIDFIELD_MAX_CELLS`` raises :class:`~gridfield.core.errors.ParameterError`,
        the same rule as ``--max-cells`` (:func:`parse_max_cells`).

    Examples
    --------
    >>> with override(10**6):
    ...     user_limit()
    1000000
    """
    if _OVERRIDE:
        return _OVERRIDE[-1]
    env = os.environ.get(ENV_VAR)
    return None if env is None else parse_max_cells(env, ENV_VAR)


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation now (None where it cannot be read).

    psutil's ``virtual_memory().available`` when psutil is installed, else ``MemAvailable`` of
    ``/proc/meminfo`` (Linux), else the free pages of ``os.sysconf``.

    Returns
    -------
    int or None

    Examples
    --------
    >>> m = available_memory()
    >>> m is None or m > 0
    True
    """
    try:
        import psutil  # type: ignore[import-untyped]  # optional

        return int(psutil.virtual_memory().available)
    except Exception:  # not installed, or no answer on this platform
        pass
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_AVPHYS_PAGES"))
    except (AttributeError, ValueError, OSError):
        return None


def memory_budget() -> int | None:
    """:data:`MEMORY_FRACTION` of :func:`available_memory` (None where that is unknown).

    Returns
    -------
    int or None

    Examples
    --------
    >>> b = memory_budget()
    >>> b is None or b > 0
    True
    """
    mem = available_memory()
    return None if not mem or mem <= 0 else int(mem * MEMORY_FRACTION)


def job_bytes_per_cell(name: str) -> int:
    """The peak bytes per cell of job ``name`` (:data:`JOB_BYTES_PER_CELL`, with its fall-backs).

    Parameters
    ----------
    name : str
        A command or ``command:planner`` (``plan:potential``).

    Returns
    -------
    int

    Examples
    --------
    >>> job_bytes_per_cell("plan:potential"), job_bytes_per_cell("plan:visibility") == job_bytes_per_cell("plan")
    (160, True)
    """
    if name in JOB_BYTES_PER_CELL:
        return JOB_BYTES_PER_CELL[name]
    return JOB_BYTES_PER_CELL.get(name.split(":", 1)[0], BYTES_PER_CELL)


@contextlib.contextmanager
def job(name: str, *, workers: int = 1) -> Iterator[None]:
    """Within the block, every grid checked is also sized in bytes for job ``name`` (see the module docstring).

    Parameters
    ----------
    name : str
        A key of :data:`JOB_BYTES_PER_CELL` (or ``command:planner``; see :func:`job_bytes_per_cell`).
    workers : int, default 1
        Processes that will each hold such a grid at once (a sweep's workers).

    Yields
    ------
    None

    Examples
    --------
    >>> import gridfield.core.limits as L
    >>> with job("plan:potential"), L._budget_for_tests(10**6):   # a 1 MB budget: 160 B x 10**4 cells is more
    ...     check_cells((100, 100), "map.png (image header)")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.SizeLimitError: map.png (image header): plan:potential on 100 x 100 = 10000 cells would need about 1.6 MB ...
    """
    budget = memory_budget()
    _JOB.append((name, job_bytes_per_cell(name), max(1, int(workers)), budget))
    _LAST.clear()  # out_of_memory names this job's grids only
    try:
        yield
    finally:
        _JOB.pop()


def job_planners(names: Sequence[str]) -> None:
    """Size the ``sweep`` job in force by the largest figure of the grid planners it runs.

    Until it is called, a sweep is sized by the ``sweep`` figure; the job's end forgets it.

    Parameters
    ----------
    names : sequence of str
        The planners the sweep runs (their ``plan:NAME`` figures of :data:`JOB_BYTES_PER_CELL`).

    Returns
    -------
    None
        Outside a ``sweep`` job, or with no names, nothing changes.

    Examples
    --------
    >>> with job("sweep", workers=2):
    ...     job_planners(["wavefront-octile"])
    ...     _JOB[-1][:3]
    ('sweep', 24, 2)
    """
    if not _JOB or _JOB[-1][0] != "sweep" or not names:
        return
    name, _, workers, budget = _JOB[-1]
    _JOB[-1] = (name, max(job_bytes_per_cell(f"plan:{p}") for p in names), workers, budget)


@contextlib.contextmanager
def _budget_for_tests(budget: int | None) -> Iterator[None]:
    """Within the block the job in force has a memory budget of ``budget`` bytes (tests, doctests)."""
    name, per_cell, workers, old = _JOB.pop()
    _JOB.append((name, per_cell, workers, budget))
    try:
        yield
    finally:
        _JOB[-1] = (name, per_cell, workers, old)


def out_of_memory(error: BaseException, what: str | None = None) -> SizeLimitError:
    """A ``MemoryError`` as one clear :class:`~gridfield.core.errors.SizeLimitError`: what was built, how to go on.

    Parameters
    ----------
    error : MemoryError
        numpy's ``_ArrayMemoryError`` (a subclass) says which array it could not allocate.
    what : str, optional
        What was being built (default: the job in force and its last grid).

    Returns
    -------
    SizeLimitError

    Examples
    --------
    >>> str(out_of_memory(MemoryError("Unable to allocate 8 GiB"), "plan potential on map.png"))
    'plan potential on map.png: out of memory (Unable to allocate 8 GiB); use a coarser resolution, ...'
    """
    if what is None:
        what = _LAST[0] if _LAST else (f"{_JOB[-1][0]}" if _JOB else "gridfield")
    detail = " ".join(str(error).split()) or type(error).__name__
    return SizeLimitError(
        f"{what}: out of memory ({detail}); use a coarser resolution, a smaller map or fewer workers, "
        f"or lower --max-cells / {ENV_VAR} so that such grids are refused before they are built"
    )


_LAST: list[str] = []  # the last grid sized within a job, for out_of_memory's message


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
        For the message's byte estimate (within a :func:`job`, the job's figure times its workers).

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
    gridfield.core.errors.SizeLimitError: map.png (image header): 50 x 50 = 2500 cells would need about 160 kB of memory, ...
    """
    if type(shape_or_count) is tuple and len(shape_or_count) == 2 and type(shape_or_count[0]) is int and type(
            shape_or_count[1]) is int:  # the common case (a Grid's shape), kept cheap
        n = shape_or_count[0] * shape_or_count[1]
        if not _JOB and n <= (_OVERRIDE[-1] if _OVERRIDE else _env_or_default()):
            return n
    if isinstance(shape_or_count, int | float):
        count = float(shape_or_count)
        shape_text = ""
    else:
        dims = [float(d) for d in shape_or_count]
        count = math.prod(dims) if dims else 1.0
        shape_text = " x ".join(f"{d:.0f}" if d < 1e15 else f"{d:.3g}" for d in dims) + " = "
    limit = max_cells()
    if _JOB and count <= limit:
        _check_job_bytes(count, what, shape_text)
    if not count <= limit:  # NaN too
        if not math.isfinite(count):
            cells, memory = "more cells than a float can count", "unbounded memory"
        else:
            cells = f"{count:.0f} cells" if count < 1e15 else f"{count:.3g} cells"
            per_cell = _JOB[-1][1] * _JOB[-1][2] if _JOB else bytes_per_cell  # the job's own figure
            memory = f"about {_bytes(count * per_cell)} of memory"
        raise SizeLimitError(
            f"{what}: {shape_text}{cells} would need {memory}, more "
            f"than the limit of {limit} cells; raise it with --max-cells N or the environment variable "
            f"{ENV_VAR}=N (or use a coarser resolution / a smaller map)"
        )
    return int(count)


def check_grid(shape: Sequence[int], name: str, what: str) -> int:
    """The API's byte guard: size a grid for job ``name`` before anything is allocated for it.

    Within a :func:`job` (the command line) the job in force has sized the grid already and this is
    :func:`check_cells`; outside one (a call of :func:`gridfield.planners.plan`,
    :func:`gridfield.fields.potential.build_field` or :func:`gridfield.distance.brushfire.brushfire`) the grid is
    sized as within ``job(name)``: refused when its cells times ``name``'s figure
    (:data:`JOB_BYTES_PER_CELL`) exceed half the memory available now (:func:`memory_budget`),
    unless a limit in cells was set (:func:`override`, ``GRIDFIELD_MAX_CELLS``).

    Parameters
    ----------
    shape : (rows, cols)
    name : str
        A key of :data:`JOB_BYTES_PER_CELL` (``plan:potential``, ``brushfire``, ``field``).
    what : str
        What is being built, for the message.

    Returns
    -------
    int
        The number of cells.

    Raises
    ------
    SizeLimitError
        One line: the estimate in bytes, the memory available and how to raise the limit.

    Examples
    --------
    >>> check_grid((100, 100), "plan:potential", "plan potential on map.png")
    10000
    """
    if _JOB:
        return check_cells(tuple(shape), what)
    with job(name):
        return check_cells(tuple(shape), what)


def _check_job_bytes(count: float, what: str, shape_text: str) -> None:
    """The byte rule of the job in force (the module docstring's "Bytes per job")."""
    name, per_cell, workers, budget = _JOB[-1]
    need = count * per_cell * workers
    who = f" x {workers} workers" if workers > 1 else ""
    cells = f"{count:.0f} cells" if count < 1e15 else f"{count:.3g} cells"
    _LAST[:] = [f"{what}: {name} on {shape_text}{cells} (about {_bytes(need)}{who})"]
    if user_limit() is not None or budget is None or need <= budget:
        return
    raise SizeLimitError(
        f"{what}: {name} on {shape_text}{cells} would need about {_bytes(need)} of memory "
        f"({per_cell} B per cell{who}), more than the limit of {_bytes(budget)} "
        f"({MEMORY_FRACTION:g} of the {_bytes(budget / MEMORY_FRACTION)} available now); raise it with "
        f"--max-cells N or the environment variable {ENV_VAR}=N (a limit in cells that replaces this "
        f"estimate), or use a coarser resolution / a smaller map{' / fewer workers' if workers > 1 else ''}"
    )
