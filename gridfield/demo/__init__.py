"""The demo behind ``gridfield demo``: every bundled map and world through the whole pipeline.

:func:`run_demo` loads the bundled maps and worlds, runs the planners on them and writes the
figures (PNG), one animation (GIF) and a summary table (``summary.md``, ``summary.csv``) to a
folder. The parts:

``maps``
    a picture of each bundled occupancy grid (vector worlds rasterized, outlines drawn);
``seed000``
    seed 000's polygon world and its segment variant: the grid follower and the exact planner
    side by side (the segment variant stalls in the local minimum the seed reports, marked),
    the potential, its 3-D surface, the basins of attraction and the follower animated;
``convergence``
    the grid potential against the exact one on both seed 000 worlds at cell sizes 0.4 to 0.05:
    path deviation and stall-point error on log-log axes, with the observed orders;
``seed003``
    seed 003's two circles with the vortex field, ``Ko = 5`` (reaches) and ``Ko = 10`` (does not);
``seed002``
    seed 002's star-world navigation function (``star-nav``, kappa 3, lambda 1): the obstacle
    functions' humps, the attractive part, the mapped space and the surface with the path;
``turtlebot3``, ``arena``
    a ROS map and a Moving AI map: brushfire, potential, basins (of the same field over the whole
    map) and a wavefront path next to the potential path (the default complete field, ``nf1`` with its
    clearance band). On the arena the classic Khatib
    field (``model: khatib``) stalls in a local minimum by the goal: ``arena_classic_vs_complete.png``
    shows that run (stall point and hint) next to the complete field's run that reaches, and the
    summary has a row and a note for each.
``moving``
    seed 000 with an obstacle walking across the robot's way: every frame the obstacle moves, the
    distance map and the potential are updated where they changed (:mod:`gridfield.distance.incremental`),
    and the robot replans from where it stands (``moving_obstacle.gif``).

Every part runs: a part that fails raises (nothing is silently left out).

The package: ``_run`` (:class:`DemoResult` and the run's bookkeeping), ``_parts`` (the parts and the
figures they share), ``_summary`` (``summary.md`` and ``summary.csv``); this module runs them.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from pathlib import Path as FsPath
from typing import Any

from ..core.errors import GridfieldError
from ._parts import _PARTS, _warm_up
from ._parts import BUNDLED as BUNDLED
from ._parts import CLASSIC_PARAMS as CLASSIC_PARAMS
from ._parts import MOVING_PARAMS as MOVING_PARAMS
from ._parts import MOVING_ROBOT_SPEED as MOVING_ROBOT_SPEED
from ._parts import MOVING_WALKER as MOVING_WALKER
from ._parts import TURTLEBOT3_GOAL as TURTLEBOT3_GOAL
from ._parts import TURTLEBOT3_START as TURTLEBOT3_START
from ._parts import classic_vs_complete_figure as classic_vs_complete_figure
from ._parts import crop_to_known as crop_to_known
from ._run import DemoResult as DemoResult
from ._run import _Run
from ._summary import LISTED_COLUMNS as LISTED_COLUMNS
from ._summary import MAX_CELL as MAX_CELL
from ._summary import SUMMARY_COLUMNS as SUMMARY_COLUMNS
from ._summary import TEXT_WIDTH as TEXT_WIDTH
from ._summary import _write_summary
from ._summary import format_table as format_table
from ._summary import wrap_item as wrap_item

__all__ = ["DEMO_PARTS", "SUMMARY_COLUMNS", "DemoResult", "classic_vs_complete_figure", "demo", "run_demo"]

#: The demo's parts, in the order they run.
DEMO_PARTS = ("maps", "seed000", "convergence", "seed003", "seed002", "turtlebot3", "arena", "moving")


def demo(out_dir: str | FsPath = "gridfield-demo", *, quick: bool = False, parts: Sequence[str] | None = None,
         log: Callable[[str], None] | None = None) -> DemoResult:
    """Run the demo and return everything it did (see :func:`run_demo` for the rows only).

    Parameters
    ----------
    out_dir : path
        Created if missing; existing files of the same names are overwritten.
    quick : bool
        Coarser grids, fewer animation frames, lower resolution images (for tests).
    parts : sequence of str, optional
        A subset of :data:`DEMO_PARTS` (default: all).
    log : callable, optional
        Receives one line per step (e.g. ``print``); default: silent.

    Returns
    -------
    DemoResult
        The rows, files, skipped steps and notes.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     result = demo(d, quick=True, parts=[])   # the summary alone: no part
    ...     [f.name for f in result.files], result.rows
    (['summary.md', 'summary.csv'], [])
    """
    import matplotlib

    if parts is None:
        parts = DEMO_PARTS
    unknown = [p for p in parts if p not in DEMO_PARTS]
    if unknown:
        raise GridfieldError(f"unknown demo part {unknown[0]!r}; expected some of {', '.join(DEMO_PARTS)}")
    out = FsPath(out_dir)
    if out.exists() and not out.is_dir():
        raise GridfieldError(f"{out}: exists and is not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise GridfieldError(f"{out}: cannot create the output folder: {e.strerror or e}") from None
    run = _Run(out, quick, log or (lambda _line: None))
    t_all = time.perf_counter()
    _warm_up(run)
    with matplotlib.rc_context({"figure.max_open_warning": 0}):
        for name in parts:
            fn = _PARTS[name]
            t0 = time.perf_counter()
            n_files = len(run.result.files)
            fn(run)
            written = ", ".join(f.name for f in run.result.files[n_files:])
            run.log(f"{name}: {time.perf_counter() - t0:.1f} s  {written}")
    run.result.seconds = time.perf_counter() - t_all
    _write_summary(run.result)
    return run.result


def run_demo(out_dir: str | FsPath = "gridfield-demo", *, quick: bool = False, parts: Sequence[str] | None = None,
             log: Callable[[str], None] | None = None) -> list[dict[str, Any]]:
    """Run every part of the demo, write its files to ``out_dir`` and return the summary rows.

    Each row holds :data:`SUMMARY_COLUMNS`: ``part``, ``map``, ``planner``, ``model`` (the field's
    ``model`` parameter where the planner has one: ``khatib``, ``vortex``, ``nf1``, ...; else empty), ``status``, ``length``,
    ``steps`` (iterations), ``ms`` (wall time of the planner call) and a ``note``. The files are the
    figures (``maps.png``, ``seed000_paths.png``, ``seed000_segment_potential.png``,
    ``seed000_surface.png``, ``seed000_segment_basins.png``, ``convergence.png``, ``seed003_vortex.png``,
    ``seed002_star_world.png``,
    ``turtlebot3.png``, ``arena.png``, ``arena_classic_vs_complete.png``), the animation ``seed000_segment_follower.gif`` and
    ``summary.md`` / ``summary.csv``. ``parts`` and ``log`` are as in :func:`demo`, which also returns
    the files written and the steps skipped.

    Parameters
    ----------
    out_dir : path
        Created if missing.
    quick : bool
        Coarser grids and fewer frames.
    parts : sequence of str, optional
        A subset of :data:`DEMO_PARTS` (default: all).
    log : callable, optional
        Receives one line per step.

    Returns
    -------
    list of dict
        The summary rows.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     run_demo(d, quick=True, parts=[])
    []
    """
    return demo(out_dir, quick=quick, parts=parts, log=log).rows
