"""``gridfield field``: build a potential field on a map and save its arrays and figures."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

from ._common import (
    add_map_arguments,
    add_param_arguments,
    add_robot_arguments,
    collect_params,
    load_target,
    robot_target,
)

#: Planners whose field ``gridfield field`` builds: the potential field and the navigation functions.
FIELD_PLANNERS = ("potential", "wavefront", "wavefront-octile", "fmm", "harmonic", "navfn", "sphere-nav", "star-nav")


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "field", help="build a potential field (U and its gradient) on a map",
        description="Build the attractive/repulsive (or vortex) potential field of a map for a goal; "
                    "print a summary and optionally write its arrays (.npz) and figures. Parameters come from "
                    "the world file's 'params', overridden by the options below (others via --param K=V, "
                    "e.g. --param saturate=0.5 or --param model=vortex).")
    add_map_arguments(p)
    p.add_argument("--planner", default="potential", choices=FIELD_PLANNERS,
                   help="whose field: the potential field (default) or a navigation function")
    p.add_argument("--goal", nargs="+", type=float, metavar="X",
                   help="goal point X Y (X Y Z on a voxel grid; default: the world file's goal)")
    p.add_argument("--npz", metavar="F",
                   help="write occupied, distance, label, gvd, potential, grad_x, grad_y + resolution, origin "
                        "(and a disc robot's diagonals through corners, GridMap.diagonals)")
    p.add_argument("--plot", metavar="F", help="save the potential (contours and force arrows) as a figure (a voxel "
                                               "map: orthogonal slices and a 3-D view of the obstacles)")
    p.add_argument("--surface", metavar="F", help="save the potential as a 3-D surface figure (star-nav: the "
                                                  "star world's four figures: beta humps, attractive part, mapped space, surface; "
                                                  "a voxel map: its x-y slice at the goal)")
    p.add_argument("--basins", metavar="F",
                   help="save the basins of attraction of steepest descent (goal basin and local minima)")
    add_robot_arguments(p)
    add_param_arguments(p)
    from ._chunked import add_chunk_arguments

    add_chunk_arguments(p)
    return p


def _goal(args: argparse.Namespace, target: Any) -> list[float]:
    from ..core.errors import ParameterError

    if args.goal is not None:
        return list(args.goal)
    world = target if hasattr(target, "obstacles") else getattr(target, "world", None)
    goal = getattr(world, "goal", None)
    if goal is None:
        raise ParameterError(f"{args.map} names no goal; pass --goal X Y")
    return list(goal)


def _world_params(target: Any) -> dict[str, Any]:
    from ..geometry.world import World

    world = target if isinstance(target, World) else getattr(target, "world", None)
    return dict(world.params) if isinstance(world, World) else {}


def _save_figure(art: Any, file: str) -> None:
    import matplotlib.pyplot as plt

    from ..core.errors import GridfieldError

    fig = art.figure
    try:
        fig.savefig(file, dpi=110)
    except OSError as e:
        raise GridfieldError(f"{file}: cannot write: {e.strerror or e}") from None
    except ValueError as e:  # an unknown image format
        raise GridfieldError(f"{file}: {e}") from None
    finally:
        plt.close(fig)


def _check_output(file: str | None) -> None:
    from ..core.errors import GridfieldError

    if file is not None and not Path(file).resolve().parent.is_dir():
        raise GridfieldError(f"{file}: the folder {Path(file).parent} does not exist")


def _run_chunked(args: argparse.Namespace) -> int:
    """``--out F.zarr``: the classic (khatib) field chunk by chunk (gridfield.chunked), to a store."""
    from ..core.chunkcache import LazyGridMap
    from ..core.errors import ParameterError
    from ..core.params import validate
    from ..fields.potential import resolve_params
    from ..geometry.rasterize import as_gridmap
    from ..io import redact
    from . import _chunked  # type: ignore[attr-defined]  # a compiled extension, no stubs

    if args.planner != "potential":
        raise ParameterError(f"the chunked computation builds the potential field; not --planner {args.planner}")
    target = load_target(args, lazy=True)
    goal = _goal(args, target)
    params = _world_params(target)
    params.update(collect_params(args))
    if params.get("model") is None:
        params["model"] = "khatib"  # the chunked field is the classic one unless the complete nf1 is asked for
    octile = params["model"] == "nf1" and params.get("attraction") == "octile"
    if params["model"] != "khatib" and not octile:
        raise ParameterError(f"the chunked computation builds the classic field (model khatib) or the complete "
                             f"nf1 with the octile wavefront (--param model=nf1 --param attraction=octile), not "
                             f"model {params['model']!r}{' with its eikonal attraction' if params['model'] == 'nf1' else ''}")
    gridmap = target if isinstance(target, LazyGridMap) else as_gridmap(robot_target(args, target, goal=goal),
                                                                          args.resolution)
    grid = gridmap.grid
    if grid.ndim != 2:
        raise ParameterError(f"{args.map} is a voxel grid: the chunked computation (--chunks, --out) is 2-D; "
                             "leave them out to compute it in memory")
    g = gridmap.check_point("goal", goal)
    cell = grid.cell_of(float(g[0]), float(g[1]))
    assert cell is not None  # check_point: inside the grid
    # the chunked field's goal is the centre of the goal's cell (gridfield.chunked.field)
    gxy = tuple(float(v) for v in grid.cell_to_world([cell])[0])
    given = dict(validate(params))
    if octile:
        return _run_chunked_nf1(args, gridmap, cell, gxy, given)
    p = resolve_params(given, unit=grid.resolution)
    _chunked.check_halo(args, p["saturate"], grid.resolution)
    _, occ = _chunked.lazy_occupancy(args, gridmap)
    with _chunked.scheduler(args) as sched, _chunked.scratch(args) as tmp:  # connect first: an unreachable
        from .. import chunked  # scheduler fails before any work

        d, nr, nc = chunked.distance(occ, metric=p["metric"], resolution=grid.resolution, saturate=p["saturate"],
                                     return_nearest=True, border=grid.border, scratch=tmp)
        f = chunked.field(d, nr, nc, goal_cell=cell, resolution=grid.resolution, origin=grid.origin, params=given,
                          metric=p["metric"])
        arrays = {"occupied": occ, "distance": d, "nearest_row": nr, "nearest_col": nc,
                  "U": f["U"], "dUdx": f["dUdx"], "dUdy": f["dUdy"]}
        t0 = time.perf_counter()
        n = _chunked.write(args, arrays, grid, "field",
                           {"metric": p["metric"], "saturate": p["saturate"], "goal": gxy, "params": p}, sched,
                           gridmap.diagonals)
    s = time.perf_counter() - t0
    print(f"field {grid.rows}x{grid.cols} cells of {grid.resolution:g} in {n} chunks of {args.chunks} (khatib, "
          f"{p['repulsion']} repulsion), goal ({gxy[0]:g}, {gxy[1]:g}, the centre of its cell): wrote {redact(args.out)} "
          f"({', '.join(arrays)}) in {s:.1f} s")
    return 0


def _run_chunked_nf1(args: argparse.Namespace, gridmap: Any, cell: tuple[int, ...], gxy: tuple[float, ...],
                     given: dict[str, Any]) -> int:
    """``--out F.zarr`` with ``model: nf1, attraction: octile``: the complete field by the chunked wavefront
    (gridfield.chunked.nf1_octile_field), bit-identical to the in-memory field; a wall border only."""
    from ..core.errors import ParameterError
    from ..core.params import resolve_field
    from ..fields.navfield import NF_PROGRESS_WINDOW
    from ..io import redact
    from . import _chunked  # type: ignore[attr-defined]  # a compiled extension, no stubs

    grid = gridmap.grid
    if grid.border != "wall":
        raise ParameterError("the chunked nf1 field needs a map whose border is a wall (an open border runs the "
                             "fronts round the grid through a ring the store would not hold)")
    p = resolve_field(given, unit=grid.resolution)
    if "progress_window" not in given:
        p["progress_window"] = NF_PROGRESS_WINDOW  # as the in-memory complete field (navfield.nav_field)
    _, occ = _chunked.lazy_occupancy(args, gridmap)
    try:
        import dask
    except ImportError:  # pragma: no cover - the [dask] extra installs it
        raise ParameterError("--out (the chunked computation) needs dask: pip install 'gridfield[dask]'") from None
    with _chunked.scheduler(args) as sched:
        from .. import chunked

        t0 = time.perf_counter()
        ctx = dask.config.set(scheduler=sched) if isinstance(sched, str) else sched.as_current()
        with ctx:
            f, rounds = chunked.nf1_octile_field(occ, cell, resolution=grid.resolution)
        arrays = {"occupied": occ, "U": f["U"], "dUdx": f["dUdx"], "dUdy": f["dUdy"]}
        n = _chunked.write(args, arrays, grid, "field", {"goal": gxy, "params": p}, sched, gridmap.diagonals)
    s = time.perf_counter() - t0
    print(f"field {grid.rows}x{grid.cols} cells of {grid.resolution:g} in {n} chunks of {args.chunks} (nf1, octile "
          f"wavefront, a complete model: one minimum, the goal; {rounds} rounds), goal ({gxy[0]:g}, {gxy[1]:g}, the "
          f"centre of its cell): wrote {redact(args.out)} ({', '.join(arrays)}) in {s:.1f} s")
    return 0


def run(args: argparse.Namespace) -> int:
    from ._chunked import chunked

    if chunked(args):
        return _run_chunked(args)
    from ..fields.potential import build_field, field_distance_map, resolve_params
    from ..geometry.rasterize import as_gridmap
    from ..planners import check_params
    from ._common import check_figure_file

    for option in ("plot", "surface", "basins"):
        check_figure_file(getattr(args, option), f"--{option}")
    for f in (args.npz, args.plot, args.surface, args.basins):
        _check_output(f)
    target = load_target(args)
    from ._common import check_point_args

    check_point_args(args, target)  # X Y, or X Y Z on a voxel grid
    goal = _goal(args, target)
    params = _world_params(target)
    params.update(collect_params(args))
    gridmap = as_gridmap(robot_target(args, target, goal=goal), args.resolution)
    if args.planner == "star-nav":
        from ..fields.navigation import star_nav_field

        gridmap.check_point("goal", goal)
        t0 = time.perf_counter()
        nav = star_nav_field(gridmap, goal, check_params(params))
        ms = (time.perf_counter() - t0) * 1e3
        model = f"star-nav navigation function, kappa={nav.params['kappa']:g}, lambda={nav.params['lambda']:g}"
        return _report(args, nav.to_field(), model, ms, None, star_figure=nav.aux["figure"])
    if args.planner != "potential":
        from ..fields.navtable import navigation_field

        gridmap.check_point("goal", goal)
        t0 = time.perf_counter()
        field = navigation_field(gridmap, goal, args.planner, check_params(params)).to_field()
        ms = (time.perf_counter() - t0) * 1e3
        return _report(args, field, f"{args.planner} navigation function", ms, None)
    if params.get("model") is None:  # what `plan` follows on this map: the potential planner's default model
        from ..following.follower import PLANNER_MODEL

        params = {**params, "model": PLANNER_MODEL}
    resolved = resolve_params(params)
    dmap, ms_brushfire = None, None  # timed apart only where it is computed apart
    if resolved["model"] == "khatib":  # the vortex model works on its own lattice
        gridmap.check_point("goal", goal)
        t0 = time.perf_counter()
        dmap = field_distance_map(gridmap, resolved, labels=True, steps=True)  # --npz and figures show them all
        ms_brushfire = (time.perf_counter() - t0) * 1e3
    t0 = time.perf_counter()
    field = build_field(gridmap, goal, params, dmap=dmap)
    ms = (time.perf_counter() - t0) * 1e3
    p = field.params
    if p["model"] == "vortex":
        model = "vortex"
    elif p["model"] == "khatib":
        model = f"khatib, {p['repulsion']} repulsion, p={p['repulsive_power']:g}, {p['gradient']} gradient"
    else:
        model = f"{p['model']}, a complete model: one minimum, the goal"
    return _report(args, field, model, ms, ms_brushfire)


def _report(args: argparse.Namespace, field: Any, model: str, ms: float, ms_brushfire: float | None,
            star_figure: dict[str, Any] | None = None) -> int:
    """Print the field's summary and write the files asked for."""
    import textwrap

    import numpy as np

    from ..io import write_npz

    grid = field.grid
    free = ~field.map.occupied & np.isfinite(field.potential)
    u = field.potential[free]
    gmag = (np.hypot(field.grad_x, field.grad_y) if grid.ndim == 2 else np.sqrt(sum(g * g for g in field.gradient)))[free]
    urange = f"U in [{u.min():.4g}, {u.max():.4g}]" if u.size else "no free cell"
    at = ", ".join(f"{v:g}" for v in field.goal)  # x, y (, z on a voxel grid)
    print(f"field {'x'.join(map(str, grid.shape))} cells of {grid.resolution:g} ({model}), goal ({at}): "
          f"{urange} over {int(free.sum())} free cells, max |grad U| {gmag.max() if gmag.size else 0:.4g}, "
          + (f"built in {ms_brushfire + ms:.1f} ms (brushfire {ms_brushfire:.1f} ms, potential {ms:.1f} ms)"
             if ms_brushfire is not None else f"built in {ms:.1f} ms (its distance maps included)"))

    if args.npz:
        d = field.distance
        arrays: dict[str, Any] = {"occupied": field.map.occupied, "potential": field.potential,
                                  "grad_x": field.grad_x, "grad_y": field.grad_y}
        if d is not None:
            arrays.update({k: getattr(d, k) for k in ("steps", "distance", "label", "gvd")
                           if getattr(d, k) is not None})
        write_npz(args.npz, arrays, grid, diagonals=field.map.diagonals)
        print(f"wrote {args.npz}")
    if args.plot or args.surface or args.basins:
        from .. import plot as gplot

        if args.plot:
            from ..plot import title_of

            name = title_of(field.map) or str(args.map)
            title = f"{name}: {getattr(args, 'planner', 'potential')} field ({model}), goal ({at})"
            if grid.ndim == 3:  # a voxel map: slices of the potential and the 3-D scene (gridfield.plot.voxels)
                gplot.save_voxel_figure(args.plot, field, title=title)
            else:
                _save_figure(gplot.plot_potential(field, ax=None, title="\n".join(textwrap.wrap(title, 70))),
                             args.plot)
            print(f"wrote {args.plot}")
        if args.surface and grid.ndim == 3:  # the potential's x-y slice at the goal, as a surface
            _save_figure(gplot.plot_voxel_surface(field, ax=None), args.surface)
            print(f"wrote {args.surface}")
        elif args.surface and star_figure is not None:
            _save_figure(gplot.plot_star_world(star_figure)[0], args.surface)
            print(f"wrote {args.surface}")
        elif args.surface:
            _save_figure(gplot.plot_surface(field, ax=None), args.surface)
            print(f"wrote {args.surface}")
        if args.basins:
            from ..following.follower import basins

            _save_figure(gplot.plot_basins(basins(field), ax=None), args.basins)
            print(f"wrote {args.basins}")
    sys.stdout.flush()
    return 0
