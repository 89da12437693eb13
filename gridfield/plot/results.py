"""Figures of results: a grid planner's path against the exact one, convergence studies, and the
figure of a planned path written to a file.

Like the figures of :mod:`gridfield.plot.figures`, these draw the paths and numbers they are given:
:func:`plot_comparison` and :func:`save_plan_figure` draw the map as :func:`~gridfield.plot.plot_map`
does, :func:`plot_convergence` the error columns of a convergence study.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ..core.path import Path
from ..geometry.world import World
from ._layers import Artists, PathLike, _check_figure_file, _goal_of, _legend, _new_axes, _save
from .figures import plot_map

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = [
    "plot_comparison",
    "plot_convergence",
    "save_plan_figure",
]

# ----------------------------------------------------------------------------------------------
# grid vs exact
# ----------------------------------------------------------------------------------------------
def plot_comparison(
    target: World | GridMap,
    grid_path: Path,
    exact_path: Path,
    ax: Axes | None = None,
    *,
    deviation: float | None = None,
    title: str | None = None,
) -> Artists:
    """A grid planner's path against the exact planner's on the same world.

    The exact path is drawn dashed on top of the grid path; the title reports both lengths and,
    when given, the deviation between them (the figure computes nothing: pass
    :func:`gridfield.compare.max_deviation`, or any metric of :mod:`gridfield.compare`).

    Parameters
    ----------
    target : World or GridMap
        Drawn as by :func:`plot_map`: the grid map the grid planner used shows its cells, a world
        only its outlines.
    grid_path, exact_path : Path
        The grid planner's path (solid) and the exact planner's (dashed).
    ax : Axes, optional
        Draw into this axes; default: a new figure.
    deviation : float, optional
        The paths' deviation, shown in the title (as "max deviation").
    title : str, optional
        Default: both lengths and the deviation.

    Returns
    -------
    Artists
        As :func:`plot_map`; ``paths == [grid line, exact line]``, ``extra['deviation']`` (NaN when
        not given).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.compare import max_deviation
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 4, 4], "obstacles": [{"circle": {"center": [2, 2], "radius": 1}}]})
    >>> a = Path(np.array([[0.5, 0.5], [0.5, 3.5]]), "reached", "potential")
    >>> b = Path(np.array([[0.5, 0.5], [0.7, 3.5]]), "reached", "exact-potential")
    >>> art = plot_comparison(w, a, b, deviation=max_deviation(a, b))
    >>> len(art.paths), art.ax.get_title(), art.image is None
    (2, 'grid 3 vs exact 3.01, max deviation 0.2', True)
    >>> import matplotlib.pyplot as plt; plt.close(art.figure)
    """
    art = plot_map(target, ax, paths=[grid_path, exact_path], legend=True,
                   path_styles=[{"color": "tab:red", "linewidth": 2.4},
                                {"color": "black", "linestyle": "--", "linewidth": 1.6}],
                   start=grid_path.points[0] if len(grid_path.points) else None, title="")
    dev = math.nan if deviation is None else float(deviation)
    art.extra["deviation"] = dev
    lengths = f"grid {grid_path.length:.3g} vs exact {exact_path.length:.3g}"
    art.ax.set_title(title if title is not None else
                     lengths if deviation is None else f"{lengths}, max deviation {dev:.3g}", fontsize=10)
    return art


def plot_convergence(
    resolutions: Sequence[float] | Sequence[Mapping[str, Any]],
    errors: Mapping[str, Sequence[float]] | None = None,
    ax: Axes | None = None,
    *,
    slopes: Sequence[float] = (1.0,),
    xlabel: str = "resolution (cell size)",
    ylabel: str = "error",
    title: str | None = None,
) -> Artists:
    """Errors against resolution on log-log axes, one line per error column.

    Parameters
    ----------
    resolutions : sequence of float, or sequence of dict
        Cell sizes; or rows (dicts with a ``"resolution"`` key and one key per error column), as
        a convergence study returns them, in which case ``errors`` is taken from the rows' other
        numeric keys.
    errors : mapping of name to sequence of float
        Each sequence as long as ``resolutions``. Non-positive or non-finite values are left out
        (they have no logarithm); a column with none left is not drawn.
    slopes : sequence of float
        Reference lines ``error ∝ h**s`` (dotted), anchored at the first column's coarsest point;
        with a single resolution there is no slope: its errors are drawn alone, and the axes say so.

    Returns
    -------
    Artists
        ``paths`` holds one line per drawn error column; ``extra['reference']`` the slope lines.

    Examples
    --------
    >>> art = plot_convergence([0.4, 0.2, 0.1], {"length": [0.3, 0.16, 0.07], "end": [0.0, 0.1, 0.05]})
    >>> len(art.paths), art.ax.get_xscale(), art.ax.get_yscale()
    (2, 'log', 'log')
    >>> rows = [{"resolution": 0.2, "error": 0.1, "planner": "x"}, {"resolution": 0.1, "error": 0.05, "planner": "x"}]
    >>> len(plot_convergence(rows, slopes=()).paths)
    1
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    seq: list[Any] = list(resolutions)
    if errors is None:
        if not seq or not all(isinstance(r, Mapping) for r in seq):
            raise ParameterError("plot_convergence needs resolutions and an errors mapping, or a list of row dicts")
        if not all("resolution" in r for r in seq):
            raise ParameterError("every row passed to plot_convergence needs a 'resolution' key")
        names = [k for k in seq[0] if k != "resolution" and all(
            isinstance(r.get(k), int | float | np.number) and not isinstance(r.get(k), bool) for r in seq)]
        errors = {k: [float(r[k]) for r in seq] for k in names}
        seq = [float(r["resolution"]) for r in seq]
    h = np.asarray(seq, dtype=float)
    if h.ndim != 1 or not np.all(np.isfinite(h) & (h > 0)):
        raise ParameterError(f"resolutions must be positive finite numbers, got {list(seq)!r}")
    ax = _new_axes(ax, figsize=(6.0, 4.6))
    art = Artists(ax)
    order = np.argsort(h)
    markers = "osD^vP*"
    for i, (name, errs) in enumerate(errors.items()):
        e = np.asarray(errs, dtype=float)
        if e.shape != h.shape:
            raise ParameterError(f"error column {name!r} has {e.size} values for {h.size} resolutions")
        ok = np.isfinite(e[order]) & (e[order] > 0)
        if not ok.any():
            continue
        (line,) = ax.plot(h[order][ok], e[order][ok], marker=markers[i % len(markers)], label=name)
        art.paths.append(line)
    art.extra["reference"] = []
    single = False
    if art.paths:
        x0, y0 = art.paths[0].get_xdata()[-1], art.paths[0].get_ydata()[-1]
        hh = np.array([h.min(), h.max()])
        if hh[0] < hh[1]:
            for s in slopes:
                (ref,) = ax.plot(hh, y0 * (hh / x0) ** s, linestyle=":", color="0.4", label=rf"$\propto h^{{{s:g}}}$")
                art.extra["reference"].append(ref)
        else:  # one resolution: its errors, but no slope to draw or compare (the title says so)
            single = True
        from matplotlib.ticker import FuncFormatter, NullFormatter

        ax.set_xscale("log")
        ax.set_yscale("log")
        # plain numbers at the resolutions studied instead of 6x10^-2 style labels
        ax.set_xticks(np.unique(h))
        plain = FuncFormatter(lambda v, _pos: f"{v:g}")
        ax.xaxis.set_major_formatter(plain)
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_major_formatter(plain)
    else:
        ax.text(0.5, 0.5, "no positive errors to plot", transform=ax.transAxes, ha="center", va="center")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if art.paths:  # after the axis labels: a legend below the axes goes under them
        _legend(ax, art)
    ax.grid(True, which="both", alpha=0.3)
    ax.set_title((title if title is not None else "convergence") + (" (one resolution: no slope)" if single else ""))
    return art


# ----------------------------------------------------------------------------------------------
# files: figures (the file checks and the save are _layers' _check_figure_file and _save)
# ----------------------------------------------------------------------------------------------
def save_plan_figure(
    file: PathLike,
    target: World | GridMap,
    path: Path,
    *,
    goal: ArrayLike | None = None,
    dpi: int = 110,
) -> FsPath:
    """Write a figure of the map and a planned path (what ``gridfield plan --plot F`` writes).

    Parameters
    ----------
    file : path
        The format follows the suffix (``.png``, ``.pdf``, ``.svg``, ``.jpg``); the folder must exist.
    target : World or GridMap
        Drawn as by :func:`plot_map` (a grid map's cells; a world's outlines). A voxel map is drawn by
        :func:`~gridfield.plot.voxels.save_voxel_figure` (slices and a 3-D scene).
    path : Path
        Drawn with its start, stall points and hint.
    goal : (x, y), optional
        The goal marked; default: ``path.extra["goal"]`` (recorded by
        :func:`gridfield.planners.plan`), else the world's goal, else the end of a path that
        reached its goal.
    dpi : int
        Resolution of raster formats.

    Returns
    -------
    pathlib.Path
        The file written.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> from gridfield.core.grid import Grid, GridMap
    >>> m = GridMap(Grid((4, 6), 0.5), np.zeros((4, 6), bool))
    >>> p = Path(np.array([[0.2, 0.2], [2.5, 1.7]]), "reached", "demo")
    >>> with tempfile.TemporaryDirectory() as d:
    ...     out = save_plan_figure(os.path.join(d, "plan.png"), m, p, dpi=30)
    ...     out.name, out.stat().st_size > 0
    ('plan.png', True)
    """
    if isinstance(target, GridMap) and target.ndim == 3:  # a voxel map: slices and the 3-D scene
        from .voxels import save_voxel_figure

        return save_voxel_figure(file, target, paths=[path], goal=goal, dpi=dpi)
    p = _check_figure_file(file)
    g = _goal_of(path, target, goal)
    start = path.points[0] if len(path.points) else None
    art = plot_map(target, paths=[path], start=start, goal=g)
    _save(art.figure, p, dpi)
    return p
