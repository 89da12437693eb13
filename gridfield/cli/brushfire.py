"""``gridfield brushfire``: the wavefront distance map of a map (steps, distance, labels, GVD)."""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any

from ._chunked import add_chunk_arguments
from ._common import add_map_arguments, add_robot_arguments, occupancy_options, robot_target

_BITMAPS = (".png", ".pgm", ".bmp", ".npy", ".tif", ".tiff", ".ply", ".xyz")  # --resolution: rasters' pixel size, clouds' voxel


def _positive(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"expected a positive finite number, got {text!r}")
    return v


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "brushfire", help="wavefront distance map: steps, distance, nearest-obstacle labels, GVD",
        description="Compute the brushfire (wavefront) distance map of a map or world: the wavefront number of "
                    "every cell (obstacles 0, their neighbours 1, ...), the distance to the nearest obstacle, the "
                    "label of that obstacle and the generalized Voronoi diagram. A wall border counts as an "
                    "obstacle. Prints a one-line summary; optionally writes the arrays and a figure.")
    add_map_arguments(p)
    p.add_argument("--connectivity", type=int, choices=(4, 8, 6, 26), default=None,
                   help="neighbourhood of the wavefront that numbers the steps (default 8; on a voxel grid 26 or 6, "
                        "default 26)")
    p.add_argument("--metric", choices=("chessboard", "taxicab", "euclidean"), default=None,
                   help="what the distance measures (default: chessboard for 8-connectivity, taxicab for 4)")
    p.add_argument("--saturate", type=_positive, default=None, metavar="R",
                   help="saturation radius in world units: distances at or beyond it become infinite")
    p.add_argument("--npz", metavar="F",
                   help="write occupied, steps, distance, nearest_row, nearest_col, label, gvd "
                        "+ resolution, origin, border (and a disc robot's diagonals through corners, "
                        "GridMap.diagonals) to the .npz file F")
    p.add_argument("--plot", metavar="F",
                   help="save the distance heat map with iso-distance contours and the GVD (PNG, PDF, SVG, ...); "
                        "of a voxel map: orthogonal slices and a 3-D view of the obstacles, in one file")
    add_robot_arguments(p)
    add_chunk_arguments(p)
    return p


def _check_output(file: str | None) -> None:
    from ..core.errors import GridfieldError

    if file is not None and not Path(file).resolve().parent.is_dir():
        raise GridfieldError(f"{file}: the folder {Path(file).parent} does not exist")


def _load(args: argparse.Namespace) -> Any:
    """The map as a GridMap: bitmaps take --resolution as their pixel size, worlds are rasterized."""
    from ..core.chunkcache import LazyGridMap
    from ..core.errors import ParameterError
    from ..geometry.rasterize import as_gridmap
    from ..io import read

    options: dict[str, Any] = occupancy_options(args)
    if args.unknown is not None:
        options["unknown"] = args.unknown
    bitmap = Path(args.map).suffix.lower() in _BITMAPS
    if bitmap and args.resolution is not None:
        options["resolution"] = args.resolution
    try:
        target = read(args.map, **options)
    except TypeError as e:  # an option the format's reader does not take
        raise ParameterError(f"{args.map}: {e}") from None
    if isinstance(target, LazyGridMap):  # the in-memory brushfire reads it whole (within the size guard)
        target = target.to_gridmap()
    return as_gridmap(robot_target(args, target), None if bitmap else args.resolution)


def _save_plot(dmap: Any, file: str) -> None:
    from matplotlib.figure import Figure

    from ..core.errors import GridfieldError
    from ..plot import plot_brushfire

    grid = dmap.grid
    if grid.ndim == 3:  # a voxel map: orthogonal slices and the 3-D scene, one file (gridfield.plot.voxels)
        from ..plot import save_voxel_figure

        save_voxel_figure(file, dmap, title=f"{Path(dmap.map.source).name or 'map'}: {dmap.metric} distance")
        return
    aspect = grid.rows / grid.cols
    fig = Figure(figsize=(7.5, max(2.5, min(12.0, 6.5 * aspect + 1.0))), layout="constrained")
    ax = fig.add_subplot()
    name = Path(dmap.map.source).name if dmap.map.source else "map"
    plot_brushfire(dmap, ax, title=f"{name}: {dmap.metric} distance, GVD in red")
    try:
        fig.savefig(file, dpi=110)
    except OSError as e:
        raise GridfieldError(f"{file}: cannot write: {e.strerror or e}") from None
    except ValueError as e:  # an unknown image format
        raise GridfieldError(f"{file}: {e}") from None


def summary(dmap: Any, ms: float) -> str:
    """One line: shape, metric, largest distance, GVD cells, labels, time."""
    import numpy as np

    from ..distance.brushfire import BORDER_LABEL

    grid = dmap.grid
    occ = dmap.map.occupied
    d = dmap.distance
    finite = np.isfinite(d)
    dmax = f"{float(d[finite].max()):.4g}" if finite.any() else "inf"
    smax = int(dmap.steps.max())
    obstacles = int(np.unique(dmap.label[occ]).size) if occ.any() else 0
    wall = bool((dmap.label == BORDER_LABEL).any())
    labels = f"{obstacles} obstacle label{'s' if obstacles != 1 else ''}" + (" + wall" if wall else "")
    sat = ""
    if dmap.saturate is not None:
        sat = f", {int((d == dmap.far).sum())} cells saturated at {dmap.saturate:g}"
    return (f"brushfire {'x'.join(map(str, grid.shape))} cells of {grid.resolution:g} ({dmap.connectivity}-connected steps, "
            f"{dmap.metric} distance, {grid.border} border): max distance {dmax} ({smax} steps){sat}, "
            f"{int(dmap.gvd.sum())} GVD cells, {labels}, {ms:.1f} ms")


def _run_chunked(args: argparse.Namespace) -> int:
    """``--out F.zarr``: the distance and nearest obstacle chunk by chunk (gridfield.chunked), to a store."""
    from ..core.chunkcache import LazyGridMap
    from ..core.errors import ParameterError
    from ..io import redact
    from . import _chunked  # type: ignore[attr-defined]  # a compiled extension, no stubs
    from ._common import load_target

    if args.connectivity not in (None, 8):
        raise ParameterError("--connectivity numbers the wavefront steps, which the chunked computation does not "
                             "compute (it writes distance, nearest_row, nearest_col); leave it out with --out")
    target = load_target(args, lazy=True)
    gridmap = target if isinstance(target, LazyGridMap) else _load(args)
    if isinstance(target, LazyGridMap) and _robot_given(args):
        raise ParameterError("a robot's configuration space is computed in memory; not with a map read by chunks")
    grid, occ = _chunked.lazy_occupancy(args, gridmap)
    metric = args.metric or "chessboard"
    _chunked.check_halo(args, args.saturate, grid.resolution)
    with _chunked.scheduler(args) as sched, _chunked.scratch(args) as tmp:  # connect first: an unreachable
        from .. import chunked  # scheduler fails before any work

        # the nearest obstacle cells are exact for Euclidean only (chessboard/taxicab ties follow the in-memory
        # raster order): the other metrics write the distance alone
        nearest = metric == "euclidean"
        out = chunked.distance(occ, metric=metric, resolution=grid.resolution, saturate=args.saturate,
                               return_nearest=nearest, border=grid.border, scratch=tmp)
        arrays = {"occupied": occ, "distance": out[0], "nearest_row": out[1], "nearest_col": out[2]} if nearest \
            else {"occupied": occ, "distance": out}
        t0 = time.perf_counter()
        n = _chunked.write(args, arrays, grid, "distance", {"metric": metric, "saturate": args.saturate}, sched,
                           gridmap.diagonals)
    s = time.perf_counter() - t0
    print(f"brushfire {grid.rows}x{grid.cols} cells of {grid.resolution:g} in {n} chunks of {args.chunks} "
          f"({metric} distance, {grid.border} border{'' if args.saturate is None else f', saturated at {args.saturate:g}'}): "
          f"wrote {redact(args.out)} ({', '.join(arrays)}) in {s:.1f} s")
    return 0


def _robot_given(args: argparse.Namespace) -> bool:
    return any(getattr(args, k, None) is not None for k in ("robot", "robot_radius"))


def run(args: argparse.Namespace) -> int:
    from . import _chunked  # type: ignore[attr-defined]  # a compiled extension, no stubs

    if _chunked.chunked(args):
        return _run_chunked(args)
    import numpy as np

    from ..core.grid import Grid, GridMap
    from ..distance.brushfire import brushfire
    from ..io import write_npz
    from ._common import check_figure_file

    check_figure_file(args.plot)
    for f in (args.npz, args.plot):
        _check_output(f)
    gridmap = _load(args)
    options = {"connectivity": args.connectivity, "metric": args.metric, "saturate": args.saturate}
    # The first call in a process loads (or compiles) the kernels: do it on a tiny map, time it apart.
    t0 = time.perf_counter()
    tiny = np.zeros((2,) * gridmap.grid.ndim, bool)
    tiny.flat[0] = True
    brushfire(GridMap(Grid(tiny.shape, 1.0, border=gridmap.grid.border), tiny), **options)
    t1 = time.perf_counter()
    dmap = brushfire(gridmap, **options)
    ms = (time.perf_counter() - t1) * 1e3
    print(summary(dmap, ms) + f" (+ {(t1 - t0) * 1e3:.0f} ms loading the compiled kernels)")
    if args.npz:
        arrays = {"occupied": gridmap.occupied, "steps": dmap.steps, "distance": dmap.distance,
                  "nearest_row": dmap.nearest_row, "nearest_col": dmap.nearest_col, "label": dmap.label,
                  "gvd": dmap.gvd}
        if dmap.nearest_layer is not None:  # a voxel grid
            arrays["nearest_layer"] = dmap.nearest_layer
        write_npz(args.npz, arrays, gridmap.grid, diagonals=gridmap.diagonals)
        print(f"wrote {args.npz}")
    if args.plot:
        _save_plot(dmap, args.plot)
        print(f"wrote {args.plot}")
    return 0
