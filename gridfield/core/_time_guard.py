"""The time guard of the searches and their progress line (part of :mod:`gridfield.core.limits`).

The searches whose time grows with a map's detail rather than its cells estimate their time from
that detail before they start (:func:`estimate_seconds`, :func:`check_seconds`; a command of several
searches on their sum, :func:`check_stages`, counted on a grid map by :func:`grid_map_work`) and
refuse above :func:`max_seconds`; :func:`progress` shows a long search in progress. The rule and the
figures are described in :mod:`gridfield.core.limits` ("Time of the searches"), which re-exports
every public name here; private to :mod:`gridfield.core`.
"""

from __future__ import annotations

import contextlib
import math
import os
import time
from collections.abc import Iterator, Sequence
from typing import TextIO

from .errors import ParameterError, SizeLimitError

#: Environment variable that sets the time limit of the searches, in seconds (``inf``: none).
SECONDS_ENV_VAR = "GRIDFIELD_MAX_SECONDS"

#: The default time limit of a search, in seconds.
DEFAULT_MAX_SECONDS = 120.0

#: Seconds per unit of each search's work (rough, see "Time of the searches" in gridfield.core.limits),
#: measured on the 2-core development machine under load 3-7 (so on the safe side): the any-angle graph per convex corner
#: (1024^2 cells of 30 % noise: 428673 corners, 108 s; 2048^2 of 5 % noise: 718041 corners, past
#: 150 s), the exact polygons of a grid map per blocked run (one shapely union: superlinear, see
#: :data:`SECONDS_POWER`; 2479 runs 1.2 s, 9055 runs 6.6 s), the vector visibility graph per ordered
#: pair of vertices (0.3-0.8 s for 384-768 vertices), the exact potential per vertex of its geometry
#: (the union and the tree) and per follower step (1.7 ms on seed 000's three obstacles), and per
#: follower step among a grid map's exact polygons (5.5-7.6 ms on 256^2-512^2 checkerboards of 4-cell
#: squares, rising with the size).
SECONDS_PER: dict[str, float] = {
    "convex corner": 2.5e-4,
    "blocked run": 3e-5,
    "vertex pair": 2e-6,
    "obstacle vertex": 2.5e-5,
    "follower step": 2e-3,
    "follower step among grid polygons": 1e-2,
}

#: The power of the unit count of the kinds of work whose time grows faster than their count: the
#: union of a grid map's blocked runs (``SECONDS_PER * runs ** 1.35``, fitted on the checkerboards above).
SECONDS_POWER: dict[str, float] = {"blocked run": 1.35}

#: Estimated seconds above which a search shows its progress (:func:`progress`).
PROGRESS_SECONDS = 5.0

#: Seconds between two updates of the progress line.
PROGRESS_INTERVAL = 1.0

#: Environment variable that switches :func:`progress` on (``1``) or off (``0``) whatever stderr is.
PROGRESS_ENV_VAR = "GRIDFIELD_PROGRESS"


def estimate_seconds(work: dict[str, float]) -> float:
    """The estimated seconds of ``work`` (units by kind: :data:`SECONDS_PER`, :data:`SECONDS_POWER`).

    Parameters
    ----------
    work : dict
        Units of work by kind, e.g. ``{"convex corner": 4e5}``.

    Returns
    -------
    float

    Examples
    --------
    >>> estimate_seconds({"convex corner": 4000, "follower step": 1000})
    3.0
    """
    return float(sum(float(n) ** SECONDS_POWER.get(kind, 1.0) * SECONDS_PER[kind] for kind, n in work.items()))


def max_seconds() -> float:
    """The time limit of a search in force: ``GRIDFIELD_MAX_SECONDS``, else :data:`DEFAULT_MAX_SECONDS`.

    Returns
    -------
    float
        ``inf`` switches the limit off; an empty or malformed value raises
        :class:`~gridfield.core.errors.ParameterError`.

    Examples
    --------
    >>> max_seconds() > 0
    True
    """
    env = os.environ.get(SECONDS_ENV_VAR)
    if env is None:
        return DEFAULT_MAX_SECONDS
    try:
        v = float(env.replace("_", ""))
    except ValueError:
        v = math.nan
    if not v > 0:  # NaN too
        raise ParameterError(f"{SECONDS_ENV_VAR} must be a positive number of seconds (inf: no limit), got {env!r}")
    return v


def check_seconds(work: dict[str, float], what: str) -> float:
    """Refuse a search whose estimated time exceeds :func:`max_seconds`; return the estimate.

    Parameters
    ----------
    work : dict
        Units of work by kind (keys of :data:`SECONDS_PER`), e.g. ``{"convex corner": 4e5}``.
    what : str
        What is being built, for the message.

    Returns
    -------
    float
        The estimated seconds.

    Raises
    ------
    SizeLimitError
        Naming the work, the estimate, the limit and how to raise it.

    Examples
    --------
    >>> check_seconds({"convex corner": 100}, "any-angle graph") < 1
    True
    >>> check_seconds({"convex corner": 10**8}, "any-angle graph of map.png")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.SizeLimitError: any-angle graph of map.png: 100000000 convex corners would take about 25000 s, ...
    """
    estimate = estimate_seconds(work)
    limit = max_seconds()
    if estimate > limit:
        units = ", ".join(f"{n:.0f} {kind}s" for kind, n in work.items() if n)
        raise SizeLimitError(
            f"{what}: {units} would take about {estimate:.0f} s, more than the limit of {limit:g} s; raise it "
            f"with the environment variable {SECONDS_ENV_VAR}=N (inf: no limit), or use a smaller or coarser map"
        )
    _SEARCH[:] = [(what, estimate, time.monotonic())]
    return estimate


def check_stages(stages: Sequence[tuple[str, dict[str, float]]], what: str) -> float:
    """Refuse a command of several searches up front when the sum of their estimates exceeds :func:`max_seconds`.

    Each stage is then still checked on its own by :func:`check_seconds` when it starts.

    Parameters
    ----------
    stages : sequence of (name, work)
        Each stage's name (for the message) and its units of work by kind (:data:`SECONDS_PER`).
    what : str
        The command, for the message.

    Returns
    -------
    float
        The estimated seconds of all stages.

    Raises
    ------
    SizeLimitError
        One line: each stage's estimate, their sum, the limit and how to raise it.

    Examples
    --------
    >>> check_stages([("exact polygons", {"blocked run": 10}), ("follower", {"follower step": 100})], "compare") < 1
    True
    >>> check_stages([("any-angle graph", {"convex corner": 5e5}), ("exact potential", {"follower step": 1e4})],
    ...              "compare of map.png")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.SizeLimitError: compare of map.png: any-angle graph about 125 s + exact potential about 20 s would take about 145 s in all, ...
    """
    parts = [(name, estimate_seconds(work)) for name, work in stages]
    total = sum(t for _, t in parts)
    limit = max_seconds()
    if total > limit:
        shown = " + ".join(f"{name} about {t:.0f} s" if t >= 10 else f"{name} about {t:.2g} s" for name, t in parts)
        raise SizeLimitError(
            f"{what}: {shown if len(parts) > 1 else parts[0][0]} would take about {total:.0f} s"
            f"{' in all' if len(parts) > 1 else ''}, more than the limit of {limit:g} s; raise it with the "
            f"environment variable {SECONDS_ENV_VAR}=N (inf: no limit), or use a smaller or coarser map"
        )
    return total


def grid_map_work(occupied: object) -> dict[str, float]:
    """The units of work of the searches on a grid map's blocked cells, counted without building anything.

    Parameters
    ----------
    occupied : (rows, cols) array_like of bool
        The blocked cells.

    Returns
    -------
    dict
        ``"blocked run"`` (horizontal runs of blocked cells: the exact polygons' boxes), ``"convex
        corner"`` (lattice points with exactly one blocked cell of four around them, the map's frame
        blocked: the any-angle graph's nodes) and ``"obstacle vertex"`` (the corners of the exact
        polygons: lattice points with one or three blocked cells around, two at a diagonal touch).

    Examples
    --------
    >>> import numpy as np
    >>> occ = np.zeros((4, 5), bool); occ[1:3, 1:3] = True
    >>> grid_map_work(occ)
    {'blocked run': 2.0, 'convex corner': 4.0, 'obstacle vertex': 4.0}
    """
    import numpy as np

    occ = np.asarray(occupied, dtype=bool)
    runs = int(np.count_nonzero(occ[:, 0])) + int(np.count_nonzero(occ[:, 1:] & ~occ[:, :-1]))
    padded = np.ones((occ.shape[0] + 2, occ.shape[1] + 2), dtype=np.uint8)
    padded[1:-1, 1:-1] = occ
    around = padded[:-1, :-1] + padded[:-1, 1:] + padded[1:, :-1] + padded[1:, 1:]  # lattice points
    corners = int(np.count_nonzero(around == 1))
    padded[:] = 0  # the polygons' vertices: the blocked cells alone, no frame
    padded[1:-1, 1:-1] = occ
    a, b, c, d = padded[:-1, :-1], padded[:-1, 1:], padded[1:, :-1], padded[1:, 1:]
    around = a + b + c + d
    diagonal = (around == 2) & (a == d)  # two pieces touching at a corner: a vertex of each
    vertices = int(np.count_nonzero((around == 1) | (around == 3))) + 2 * int(np.count_nonzero(diagonal))
    return {"blocked run": float(runs), "convex corner": float(corners), "obstacle vertex": float(vertices)}


# the search last checked by check_seconds: (what, estimate in s, its start on time.monotonic()), for progress()
_SEARCH: list[tuple[str, float, float]] = []


@contextlib.contextmanager
def progress(enabled: bool | None = None, *, stream: TextIO | None = None, interval: float | None = None
             ) -> Iterator[None]:
    """Within the block, show the search in progress on ``stream`` when its estimate exceeds :data:`PROGRESS_SECONDS`.

    A thread rewrites one line, ``what: 12 s elapsed of about 43 s estimated``, every ``interval``
    seconds while a search checked by :func:`check_seconds` (or the next one) runs; the line is
    cleared when the block ends. The library never calls it: the command line does, on a terminal.

    Parameters
    ----------
    enabled : bool, optional
        Default: ``GRIDFIELD_PROGRESS`` (:data:`PROGRESS_ENV_VAR`: ``1`` on, ``0`` off), else when
        ``stream`` is a terminal.
    stream : text file, optional
        Default ``sys.stderr``.
    interval : float, optional
        Seconds between updates (default :data:`PROGRESS_INTERVAL`).

    Yields
    ------
    None

    Examples
    --------
    >>> import io
    >>> out = io.StringIO()
    >>> with progress(True, stream=out, interval=0.01):
    ...     _ = check_seconds({"convex corner": 8e4}, "any-angle graph of map.png")  # about 20 s
    ...     time.sleep(0.1)
    >>> "any-angle graph of map.png: 0 s elapsed of about 20 s estimated" in out.getvalue()
    True
    """
    import sys
    import threading

    out = stream if stream is not None else sys.stderr
    every = PROGRESS_INTERVAL if interval is None else float(interval)
    if enabled is None:
        env = os.environ.get(PROGRESS_ENV_VAR, "").strip().lower()
        enabled = env in ("1", "true", "yes", "on") if env else bool(getattr(out, "isatty", lambda: False)())
    _SEARCH.clear()
    if not enabled:
        yield
        return
    stop = threading.Event()
    lock = threading.Lock()
    shown = [0]

    def erase() -> None:  # with the lock held
        if shown[0]:
            out.write("\r" + " " * shown[0] + "\r")
            out.flush()
            shown[0] = 0

    def tick() -> None:
        while not stop.wait(every):
            with lock:
                if not _SEARCH or _SEARCH[0][1] <= PROGRESS_SECONDS:
                    continue
                what, estimate, t0 = _SEARCH[0]
                line = f"{what}: {time.monotonic() - t0:.0f} s elapsed of about {estimate:.0f} s estimated"
                out.write("\r" + line.ljust(shown[0]))
                out.flush()
                shown[0] = len(line)

    class _Erasing:  # stdout: the progress line is erased (and the search over) before the command prints
        def __init__(self, inner: TextIO) -> None:
            self._inner = inner

        def write(self, text: str) -> int:
            with lock:
                erase()
                _SEARCH.clear()
            return self._inner.write(text)

        def __getattr__(self, name: str) -> object:
            return getattr(self._inner, name)

    real_stdout = sys.stdout
    sys.stdout = _Erasing(real_stdout)
    thread = threading.Thread(target=tick, name="gridfield-progress", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join()
        if sys.stdout.__class__ is _Erasing:
            sys.stdout = real_stdout
        with lock:
            erase()
        _SEARCH.clear()
