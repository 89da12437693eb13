"""The demo's bookkeeping: :class:`DemoResult` (what a run did) and ``_Run``, which the parts plan
through (each plan a summary row) and save their figures with.

Part of :mod:`gridfield.demo` (which re-exports :class:`DemoResult`); private to it.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import Any

from numpy.typing import ArrayLike

from ..core.path import Path


@dataclass
class DemoResult:
    """What :func:`demo` did: summary rows, files written, parts or steps skipped, notes (observed
    convergence orders).

    Attributes
    ----------
    out_dir : pathlib.Path
        The folder written to.
    rows : list of dict
        The summary rows (:data:`SUMMARY_COLUMNS`).
    files : list of pathlib.Path
        Every file written, in order.
    skipped : list of str
        Steps skipped, one line each (none: every part runs or raises).
    notes : list of str
        Observations (the convergence orders).
    seconds : float
        Wall time of the whole demo.

    Examples
    --------
    >>> DemoResult(FsPath("out"), rows=[{"part": "maps"}], seconds=1.5)
    DemoResult(out_dir='out', rows=1, files=0, skipped=0, seconds=1.5)
    """

    out_dir: FsPath
    rows: list[dict[str, Any]] = field(default_factory=list)
    files: list[FsPath] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    seconds: float = 0.0

    def __repr__(self) -> str:
        return (f"DemoResult(out_dir={str(self.out_dir)!r}, rows={len(self.rows)}, files={len(self.files)}, "
                f"skipped={len(self.skipped)}, seconds={self.seconds:.3g})")


class _Run:
    """Bookkeeping shared by the parts."""

    def __init__(self, out: FsPath, quick: bool, log: Callable[[str], None]) -> None:
        self.out = out
        self.quick = quick
        self.log = log
        self.result = DemoResult(out)

    # -- results ---------------------------------------------------------------------------
    def plan(self, part: str, name: str, target: Any, planner: str, start: ArrayLike, goal: ArrayLike,
             params: Mapping[str, Any] | None = None, *, note: str = "") -> Path:
        return self.plan_with_field(part, name, target, planner, start, goal, params, note=note)[0]

    def plan_with_field(self, part: str, name: str, target: Any, planner: str, start: ArrayLike, goal: ArrayLike,
                        params: Mapping[str, Any] | None = None, *, note: str = "") -> tuple[Path, Any]:
        """Plan, record the row, and return the path with the field it followed (None but for the
        ``potential`` planner): the part draws that field instead of building it again."""
        from ..planners import plan_with_field

        t0 = time.perf_counter()
        path, field_ = plan_with_field(planner, target, start, goal, params)
        ms = (time.perf_counter() - t0) * 1e3
        self.row(part, name, path, ms, note)
        return path, field_

    def row(self, part: str, name: str, path: Path, ms: float, note: str = "") -> None:
        stall = _stall_note(path)
        # the field's model, for the planners that follow one (star-nav carries the world file's params too)
        model = path.params.get("model") if path.planner in _FIELD_PLANNERS else None
        self.result.rows.append({
            "part": part, "map": name, "planner": path.planner, "model": model or "", "status": path.status,
            "length": round(path.length, 3), "steps": int(path.iterations), "ms": round(ms, 1),
            "note": "; ".join(s for s in (note, stall) if s),
        })

    def save(self, fig: Any, name: str) -> FsPath:
        import matplotlib.pyplot as plt

        p = self.out / name
        try:
            fig.savefig(p, dpi=80 if self.quick else 100)
        finally:
            plt.close(fig)
        self.result.files.append(p)
        return p

    def add_file(self, p: FsPath) -> None:
        self.result.files.append(FsPath(p))


#: Planners whose ``model`` parameter chooses the field they follow (the summary's ``model`` column).
_FIELD_PLANNERS = ("potential", "exact-potential")


def _stall_note(path: Path) -> str:
    if path.status != "local_minimum":
        return ""
    from ..plot import stall_points

    s = stall_points(path)
    note = f"stalls at ({s[-1, 0]:.2f}, {s[-1, 1]:.2f})" if len(s) else ""
    hint = path.extra.get("hint")
    return f"{note}; hint: {hint}" if hint else note
