"""The demo's parts: one function per part of :data:`gridfield.demo.DEMO_PARTS` (``_PARTS``), each
planning through the run's bookkeeping and saving its figures, the helpers they share
(:func:`crop_to_known`, :func:`classic_vs_complete_figure`, the grid-map figure) and the warm-up.

Part of :mod:`gridfield.demo` (which re-exports every public name here); private to it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path as FsPath
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.grid import Grid, GridMap
from ..core.path import Path
from ._run import _Run

#: The grid maps run with gridfield's defaults, which scale with the map's cell size
#: (gridfield.core.params: q_star 4 cells, d_star 2 q_star, balanced eta, step 1 cell).
TURTLEBOT3_START, TURTLEBOT3_GOAL = (-2.0, -0.5), (2.0, 0.5)


def _figure(nrows: int, ncols: int, size: tuple[float, float], **kw: Any) -> tuple[Any, Any]:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(nrows, ncols, figsize=size, layout="constrained", squeeze=False, **kw)
    return fig, axes


def crop_to_known(gridmap: GridMap, *, margin: int = 8) -> GridMap:
    """The part of a map around its free cells (ROS maps are mostly unknown space), ``margin`` cells wider.

    Examples
    --------
    >>> occ = np.ones((10, 10), bool); occ[4:6, 3:7] = False
    >>> crop_to_known(GridMap(Grid((10, 10), 0.5), occ), margin=1).grid.bounds
    (1.0, 1.5, 4.0, 3.5)
    """
    free = ~gridmap.occupied
    if not free.any():
        return gridmap
    rows, cols = np.nonzero(free.any(axis=1))[0], np.nonzero(free.any(axis=0))[0]
    r0, r1 = max(rows[0] - margin, 0), min(rows[-1] + margin + 1, gridmap.shape[0])
    c0, c1 = max(cols[0] - margin, 0), min(cols[-1] + margin + 1, gridmap.shape[1])
    g = gridmap.grid
    origin = (g.origin[0] + c0 * g.resolution, g.origin[1] + r0 * g.resolution)
    grid = Grid((r1 - r0, c1 - c0), g.resolution, origin, g.border)
    ids = gridmap.obstacle_id[r0:r1, c0:c1] if gridmap.obstacle_id is not None else None
    return GridMap(grid, np.ascontiguousarray(gridmap.occupied[r0:r1, c0:c1]), ids, gridmap.world, gridmap.source,
                   {**gridmap.meta, "cropped_from": g.shape})


BUNDLED = (
    ("seed000.yaml", "seed 000 world"),
    ("seed000_segment.yaml", "seed 000 + segment"),
    ("seed003_circles.yaml", "seed 003 circles"),
    ("turtlebot3_world/map.yaml", "TurtleBot3 world (ROS)"),
    ("nav2_depot/depot.yaml", "nav2 depot (ROS)"),
    ("arena/arena.map", "arena (Moving AI)"),
)


def _part_maps(run: _Run) -> None:
    from ..geometry.rasterize import as_gridmap
    from ..io import bundled_map, read
    from ..plot import plot_map

    fig, axes = _figure(2, 3, (15.0, 9.0))
    for ax, (name, title) in zip(axes.ravel(), BUNDLED, strict=True):
        target = read(bundled_map(name))
        if isinstance(target, GridMap) and target.meta.get("format") == "ros":
            target = crop_to_known(target)
        vector = not isinstance(target, GridMap)
        if vector and target.resolution is not None:
            target = as_gridmap(target)  # the world's own cells, drawn with its outlines
        plot_map(target, ax, legend=False, title="")
        if isinstance(target, GridMap):
            g = target.grid
            shape = f"rasterized {g.rows}x{g.cols} at {g.resolution:g}" if vector else f"{g.rows}x{g.cols} at {g.resolution:g}"
        else:
            shape = "vector world"
        ax.set_title(f"{title}\n{FsPath(name).name}: {shape}", fontsize=10)
    run.save(fig, "maps.png")


def _part_seed000(run: _Run) -> None:
    from ..compare import max_deviation
    from ..following.follower import basins
    from ..geometry.rasterize import as_gridmap
    from ..io import bundled_map, read_world
    from ..plot import plot_basins, plot_comparison, plot_potential, plot_surface, save_plan_animation

    res = 0.1 if run.quick else 0.05
    worlds = {key: read_world(bundled_map(f"{key}.yaml")) for key in ("seed000", "seed000_segment")}
    maps: dict[str, GridMap] = {}
    fields: dict[str, Any] = {}
    grid_paths: dict[str, Path] = {}
    exact_paths: dict[str, Path] = {}
    for key, w in worlds.items():
        maps[key] = as_gridmap(w, res)
        grid_paths[key], fields[key] = run.plan_with_field("seed000", key, maps[key], "potential", w.start, w.goal,  # type: ignore[arg-type]
                                                           note=f"grid h={res:g}")
        exact_paths[key] = run.plan("seed000", key, w, "exact-potential", w.start, w.goal, note="exact geometry")  # type: ignore[arg-type]
    fig, axes = _figure(1, 2, (14.0, 5.6))
    for ax, key in zip(axes.ravel(), worlds, strict=True):
        plot_comparison(maps[key], grid_paths[key], exact_paths[key], ax,
                        deviation=max_deviation(grid_paths[key], exact_paths[key]))
        ax.set_title(f"{key}: grid (h={res:g}) vs exact\n{ax.get_title()}", fontsize=10)
    run.save(fig, "seed000_paths.png")

    seg = worlds["seed000_segment"]
    field_seg = fields["seed000_segment"]  # the fields the paths followed: drawn, not built again
    art = plot_potential(field_seg, path=grid_paths["seed000_segment"],
                         title="seed 000 + segment: potential, -grad U, stall point")
    run.save(art.figure, "seed000_segment_potential.png")
    art = plot_surface(fields["seed000"], path=grid_paths["seed000"], max_cells=60 if run.quick else 150,
                       title="seed 000: potential surface (capped) and the follower's path")
    run.save(art.figure, "seed000_surface.png")
    art = plot_basins(basins(field_seg), title="seed 000 + segment: where steepest descent ends",
                      legend_loc="below")  # inside, "best" covers the triangle (it avoids markers only)
    run.save(art.figure, "seed000_segment_basins.png")
    gif = run.out / "seed000_segment_follower.gif"
    save_plan_animation(gif, maps["seed000_segment"], grid_paths["seed000_segment"], field=field_seg, goal=seg.goal,
                        max_frames=30 if run.quick else 80, fps=15, dpi=60 if run.quick else 72)
    run.add_file(gif)


#: Names of the convergence-study error columns in the figure.
_ERROR_NAMES = {"hausdorff": "Hausdorff", "frechet": "Fréchet", "end_error": "end / stall point",
                "length_error": "|length ratio − 1|"}


def _part_convergence(run: _Run) -> None:
    from ..compare import convergence_study, study_errors, study_orders
    from ..io import bundled_map, read_world
    from ..plot import plot_convergence

    hs = [0.4, 0.2, 0.1] if run.quick else [0.4, 0.2, 0.1, 0.05]
    fig, axes = _figure(1, 2, (12.0, 4.8))
    for ax, key in zip(axes.ravel(), ("seed000", "seed000_segment"), strict=True):
        w = read_world(bundled_map(f"{key}.yaml"))
        rows = convergence_study(w, w.start, w.goal, hs)  # type: ignore[arg-type]
        errors = {_ERROR_NAMES[k]: v for k, v in study_errors(rows).items()}
        plot_convergence([r["resolution"] for r in rows], errors, ax, title=f"{key}: grid potential vs exact")
        orders = {k: v for k, v in study_orders(rows).items() if not math.isnan(v)}
        line = ", ".join(f"{_ERROR_NAMES[k]} {v:.2f}" for k, v in orders.items())
        run.result.notes.append(f"{key}: observed orders (error ~ h^p) at h = {', '.join(map(str, hs))}: {line}")
        run.log(run.result.notes[-1])
    run.save(fig, "convergence.png")


def _part_seed003(run: _Run) -> None:
    from ..geometry.rasterize import as_gridmap
    from ..io import bundled_map, read_world
    from ..plot import plot_potential

    w = read_world(bundled_map("seed003_circles.yaml"))
    gm = as_gridmap(w)
    fig, axes = _figure(1, 2, (13.0, 5.6))
    for ax, ko in zip(axes.ravel(), (5.0, 10.0), strict=True):
        params = {"ko": ko}
        path, field_ = run.plan_with_field("seed003", f"seed003 Ko={ko:g}", gm, "potential", w.start, w.goal,  # type: ignore[arg-type]
                                           params, note="vortex field, spacing 0.4")
        plot_potential(field_, ax, path=path, quiver_step=1, title=f"vortex field, Ko = {ko:g}: {path.status}")
    run.save(fig, "seed003_vortex.png")


def _part_seed002(run: _Run) -> None:
    from ..fields.navigation import star_figure_data, star_world
    from ..io import bundled_map, read_world
    from ..plot import plot_star_world

    w = read_world(bundled_map("star_two.yaml"))
    path = run.plan("seed002", "star_two", w, "star-nav", w.start, w.goal, note="star world, seed 002's kappa, lambda")  # type: ignore[arg-type]
    sw = star_world(w, w.goal)  # type: ignore[arg-type]
    xmin, ymin, xmax, ymax = w.bounds
    n = 61 if run.quick else 121
    x, y = np.meshgrid(np.linspace(xmin, xmax, n), np.linspace(ymin, ymax, n))
    data = star_figure_data(sw, kappa=path.extra["kappa"], lam=path.extra["lambda"], x=x, y=y,
                            lines=15 if run.quick else 21)
    arts = plot_star_world(data, path=path, max_cells=30 if run.quick else 60, title=f"seed 002: star-world navigation function (star_two.yaml): "
                                                  f"{path.status}, length {path.length:.2f}")
    run.save(arts[0].figure, "seed002_star_world.png")


def _grid_map_part(run: _Run, part: str, gm: GridMap, start: Sequence[float], goal: Sequence[float],
                   params: Mapping[str, Any], title: str, *, note: str = "") -> tuple[Path, Any]:
    """The 2 x 2 figure of a grid map; returns the potential run and the field it followed."""
    from ..distance.brushfire import brushfire
    from ..following.follower import basins
    from ..plot import plot_basins, plot_brushfire, plot_map, plot_potential

    fig, axes = _figure(2, 2, (13.0, 11.0))
    dmap = brushfire(gm, metric="euclidean")
    plot_brushfire(dmap, axes[0, 0], title="brushfire: distance to the nearest obstacle, GVD in red")
    shown = "default parameters" if not params else "params " + ", ".join(f"{k}={v}" for k, v in params.items())
    pot, field_ = run.plan_with_field(part, part, gm, "potential", start, goal, params,
                                      note="; ".join(x for x in (note, shown) if x))
    plot_potential(field_, axes[0, 1], path=pot,
                   title=f"potential, model {field_.params.get('model')} ({shown}): {pot.status}")
    plot_basins(basins(_whole_field(gm, goal, field_)), axes[1, 0], title="basins of attraction")
    paths = [pot]
    if not pot.reached:
        paths.append(run.plan(part, part, gm, "potential", start, goal, {**params, "escape": "navigation"},
                              note="escape navigation (the hint's advice)"))
    paths.append(run.plan(part, part, gm, "wavefront-octile", start, goal, note=note))
    plot_map(gm, axes[1, 1], paths=paths, start=start, goal=goal, title="paths")
    fig.suptitle(title)
    run.save(fig, f"{part}.png")
    return pot, field_


def _whole_field(gm: GridMap, goal: Sequence[float], field_: Any) -> Any:
    """The field whose basins a figure shows: a complete model's planned query settles its fronts only
    up to the start's value (``inf`` beyond, a rim that basins would count as minima), so the same
    parameters are built over the whole map (:func:`gridfield.fields.potential.build_field`, the brushfire
    reused); any other field as it is."""
    from ..fields.navfield import NF_MODELS
    from ..fields.potential import build_field

    if field_.params.get("model") not in NF_MODELS:
        return field_
    return build_field(gm, goal, field_.params, dmap=field_.distance)


def _part_turtlebot3(run: _Run) -> None:
    from ..io import bundled_map, read_ros_map

    gm = crop_to_known(read_ros_map(bundled_map("turtlebot3_world/map.yaml")))
    _grid_map_part(run, "turtlebot3", gm, TURTLEBOT3_START, TURTLEBOT3_GOAL, {},
                   "TurtleBot3 world (ROS map_server map, 0.05 m cells, cropped to the known area)")


def _part_arena(run: _Run) -> None:
    from ..io import bundled_map, read_movingai_map, read_scen

    gm = read_movingai_map(bundled_map("arena/arena.map"))
    scen = read_scen(bundled_map("arena/arena.map.scen"), map_height=gm.shape[0])
    i = int(np.argmax(scen.optimal))
    start, goal = scen.start_xy[i].tolist(), scen.goal_xy[i].tolist()
    note = f"scenario {i}, optimal {scen.optimal[i]:g}"
    complete, complete_field = _grid_map_part(
        run, "arena", gm, start, goal, {},
        f"Moving AI 'arena' (49x49), scenario {i}: optimal octile length {scen.optimal[i]:g}", note=note)
    classic, classic_field = run.plan_with_field("arena", "arena", gm, "potential", start, goal, CLASSIC_PARAMS,
                                                 note=f"{note}; classic field")
    fig = classic_vs_complete_figure(classic, classic_field, complete, complete_field,
                                     f"Moving AI 'arena', scenario {i}: the classic field stalls, the complete "
                                     "field reaches (same map, start and goal)")
    run.save(fig, "arena_classic_vs_complete.png")
    line = "arena, scenario {}: {}".format(i, "; ".join(_run_words(p) for p in (classic, complete)))
    run.result.notes.append(line)
    run.log(line)


#: The classic field of the stall-versus-complete comparison (the planner's default is the complete nf1).
CLASSIC_PARAMS: dict[str, Any] = {"model": "khatib"}


def _model_name(path: Path) -> str:
    model = str(path.params.get("model") or "")
    kind = "complete field" if model not in ("khatib", "vortex") else "classic field"
    return f"{kind} (model: {model})" if model else kind


def _run_words(path: Path) -> str:
    """'classic field (model: khatib): local_minimum at (x, y), length 80' and the like."""
    where = ""
    if path.status == "local_minimum":
        from ..plot import stall_points

        s = stall_points(path)
        where = f" at ({s[-1, 0]:.3g}, {s[-1, 1]:.3g})" if len(s) else ""
    return f"{_model_name(path)}: {path.status}{where}, length {path.length:.4g}"


def classic_vs_complete_figure(classic: Path, classic_field: Any, complete: Path, complete_field: Any,
                               title: str) -> Any:
    """One figure, two panels: the classic field's run (its stall point and hint) and the complete field's.

    Parameters
    ----------
    classic, complete : Path
        The two ``potential`` runs on one map from one start to one goal.
    classic_field, complete_field : Field
        The fields they followed (``plan_with_field``).
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
        Left: the classic run over its potential; right: the complete one. Each panel's title names
        the model, the status and the length.

    Examples
    --------
    >>> import numpy as np, matplotlib.pyplot as plt
    >>> from gridfield.planners import plan_with_field
    >>> occ = np.zeros((12, 16), bool); occ[2:10, 8] = True
    >>> gm = GridMap(Grid((12, 16), 1.0, border="wall"), occ)
    >>> runs = [plan_with_field("potential", gm, (2.5, 6.5), (13.5, 6.5), p) for p in (CLASSIC_PARAMS, {})]
    >>> fig = classic_vs_complete_figure(*runs[0], *runs[1], "a wall")
    >>> [ax.get_title().rsplit(":", 1)[0] for ax in fig.axes if ax.get_label() != "<colorbar>"]
    ['classic field (model: khatib)', 'complete field (model: nf1)']
    >>> plt.close(fig)
    """
    from ..plot import plot_potential

    fig, axes = _figure(1, 2, (14.0, 7.0))
    fig.get_layout_engine().set(rect=(0.0, 0.08, 1.0, 0.92))  # room below the axes for the hint's box
    for ax, path, field_ in zip(axes.ravel(), (classic, complete), (classic_field, complete_field), strict=True):
        plot_potential(field_, ax, path=path, title=f"{_model_name(path)}: {path.status}, length {path.length:.4g}")
    fig.suptitle(title)
    return fig


#: The moving-obstacle part: potential parameters (nearest-obstacle repulsion, so the field can be
#: updated in a window), the walker (a square of this side, walking up and down at x = its column)
#: and how far the robot and the walker move per frame.
MOVING_PARAMS: dict[str, Any] = {"zeta": 1.0, "eta": 1.0, "q_star": 2.0, "repulsive_power": 2, "repulsion": "nearest",
                 "step": 0.1, "tolerance": 0.1, "max_iterations": 5000}
MOVING_WALKER: dict[str, Any] = {"side": 1.6, "x": 19.4, "y": (3.0, 17.0), "speed": 0.55}
MOVING_ROBOT_SPEED = 0.5


def _walk(points: NDArray[np.float64], distance: float) -> NDArray[np.float64]:
    """The point ``distance`` along the polyline ``points`` (its end if shorter)."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    point: NDArray[np.float64]
    if len(points) < 2 or distance >= cum[-1]:
        point = points[-1].copy()
        return point
    i = int(np.searchsorted(cum, distance, side="right")) - 1
    t = (distance - cum[i]) / seg[i] if seg[i] > 0 else 0.0
    point = points[i] + t * (points[i + 1] - points[i])
    return point


def _part_moving(run: _Run) -> None:
    from matplotlib.colors import ListedColormap, LogNorm
    from matplotlib.patches import Rectangle

    from ..distance.brushfire import brushfire
    from ..distance.incremental import IncrementalBrushfire
    from ..fields.incremental import update_field
    from ..fields.potential import build_field
    from ..following.follower import follow
    from ..geometry.rasterize import as_gridmap
    from ..io import bundled_map, read_world
    from ..plot import OCCUPIED_COLOR, animation_figure, draw_outlines, potential_scale, write_animation

    w = read_world(bundled_map("seed000.yaml"))
    res = 0.2 if run.quick else 0.1
    static = as_gridmap(w, res)
    grid = static.grid
    ib = IncrementalBrushfire(static, compute_labels=False)
    goal = np.asarray(w.goal, float)
    field = build_field(ib.gridmap, goal, MOVING_PARAMS, dmap=ib.distance_map)
    side, wx, speed = (float(MOVING_WALKER[k]) for k in ("side", "x", "speed"))
    y_lo, y_hi = (float(v) for v in MOVING_WALKER["y"])
    pace = 2.0 if run.quick else 1.0  # quick: half the frames, twice the distance per frame
    speed *= pace
    robot_speed = MOVING_ROBOT_SPEED * pace
    n_side = max(1, round(side / res))

    def walker_cells(y: float) -> np.ndarray:
        r0 = int(np.floor((y - grid.origin[1]) / res)) - n_side // 2
        c0 = int(np.floor((wx - grid.origin[0]) / res)) - n_side // 2
        rr, cc = np.mgrid[max(0, r0):min(grid.rows, r0 + n_side), max(0, c0):min(grid.cols, c0 + n_side)]
        m = np.zeros(grid.shape, bool)
        m[rr, cc] = True
        return m & ~static.occupied

    robot = np.asarray(w.start, float)
    y, direction = y_lo, 1.0
    block = walker_cells(y)
    field = update_field(field, ib, ib.update(occupied=block))
    frames: list[dict[str, Any]] = []
    inc_ms: list[float] = []
    trail = [robot.copy()]
    max_frames = 30 if run.quick else 90
    status = "max_iterations"  # out of frames before the robot arrived
    for _ in range(max_frames):
        path = follow(field, robot, params=MOVING_PARAMS)
        frames.append({"u": field.potential.copy(), "walker": y, "path": path.points.copy(),
                       "robot": robot.copy(), "trail": np.array(trail), "status": path.status})
        if np.linalg.norm(robot - goal) <= MOVING_PARAMS["tolerance"] + 1e-9:
            status = "reached"
            break
        robot = _walk(path.points, robot_speed)
        trail.append(robot.copy())
        # the walker moves on, unless it would step onto the robot (then it waits)
        y_new = y + direction * speed
        if not y_lo <= y_new <= y_hi:
            direction = -direction
            y_new = y + direction * speed
        new_block = walker_cells(y_new)
        cell = grid.cell_of(float(robot[0]), float(robot[1]))
        if cell is not None and new_block[cell]:
            continue
        t0 = time.perf_counter()
        window = ib.update(occupied=new_block & ~block, freed=block & ~new_block)
        field = update_field(field, ib, window)
        inc_ms.append((time.perf_counter() - t0) * 1e3)
        y, block = y_new, new_block
    t0 = time.perf_counter()
    brushfire(ib.gridmap, metric="euclidean", compute_steps=False, compute_labels=False)
    build_field(ib.gridmap, goal, MOVING_PARAMS)
    full_ms = (time.perf_counter() - t0) * 1e3
    length = float(np.linalg.norm(np.diff(np.array(trail), axis=0), axis=1).sum())
    med = float(np.median(inc_ms)) if inc_ms else 0.0
    run.result.rows.append({
        "part": "moving", "map": "seed000 + walker", "planner": "potential (replanned)",
        "model": str(field.params.get("model") or ""), "status": status,
        "length": round(length, 3), "steps": len(frames), "ms": round(med, 2),
        "note": f"per frame: incremental distance + field {med:.2f} ms (median) vs full brushfire + field "
                f"{full_ms:.1f} ms; robot {robot_speed:g} m/frame",
    })

    # the animation: potential (log colours, fixed range), map, walker, planned path, trail, robot
    fig, ax = animation_figure((6.4, 5.2), 60 if run.quick else 72)
    finite0 = np.isfinite(frames[0]["u"])
    _, lo, hi, _ = potential_scale(frames[0]["u"], finite0, None, True)
    umin = float(frames[0]["u"][finite0].min())

    def shade(u: np.ndarray) -> np.ma.MaskedArray:
        fin = np.isfinite(u)
        return np.ma.masked_array(np.clip(np.where(fin, u - umin, hi), lo, hi), mask=~fin)

    image = ax.imshow(shade(frames[0]["u"]), origin="lower", extent=grid.extent, cmap="viridis",
                      norm=LogNorm(vmin=lo, vmax=hi), interpolation="nearest", zorder=0)
    ax.imshow(np.ma.masked_array(np.ones(grid.shape), mask=~static.occupied), origin="lower", extent=grid.extent,
              cmap=ListedColormap([OCCUPIED_COLOR]),
              vmin=0.5, vmax=1.5, interpolation="nearest", zorder=1)
    draw_outlines(ax, w)
    walker = Rectangle((wx - side / 2, y_lo - side / 2), side, side, facecolor="magenta", edgecolor="black", zorder=4)
    ax.add_patch(walker)
    # colours that the first frame holds in quantity: the GIF's palette is taken from it
    (planned,) = ax.plot([], [], color="black", linestyle="--", linewidth=1.4, zorder=5)
    (walked,) = ax.plot([], [], color="white", linewidth=2.4, zorder=6)
    bot = ax.scatter([robot[0]], [robot[1]], s=70, color="white", edgecolor="black", zorder=8)
    ax.scatter([goal[0]], [goal[1]], marker="*", s=180, color="gold", edgecolor="black", zorder=8)
    ax.set_xlim(grid.extent[0], grid.extent[1])
    ax.set_ylim(grid.extent[2], grid.extent[3])
    ax.set_aspect("equal")
    title = ax.set_title(" ", fontsize=9)

    def update(i: int) -> None:
        f = frames[i]
        image.set_data(shade(f["u"]))
        walker.set_xy((wx - side / 2, f["walker"] - side / 2))
        planned.set_data(f["path"][:, 0], f["path"][:, 1])
        walked.set_data(f["trail"][:, 0], f["trail"][:, 1])
        bot.set_offsets(f["robot"][None, :])
        title.set_text(f"frame {i}: replanned path {f['status']}; map + field updated in {med:.2f} ms "
                       f"(full: {full_ms:.0f} ms)")

    gif = run.out / "moving_obstacle.gif"
    write_animation(fig, update, len(frames), (image, walker, planned, walked, bot, title), gif, 6)
    run.add_file(gif)


def _warm_up(run: _Run) -> None:
    """Load the compiled kernels and warm the caches on a tiny map, so that the timings in the table
    are the planners' and not the first call's."""
    from ..distance.brushfire import brushfire
    from ..fields.potential import build_field
    from ..following.follower import basins, plan_potential
    from ..planners import plan

    t0 = time.perf_counter()
    occ = np.zeros((12, 12), bool)
    occ[5:7, 5:7] = True
    occ[2:10, 8] = True
    gm = GridMap(Grid((12, 12), 1.0), occ)
    s, g = np.array([1.5, 1.5]), np.array([10.5, 10.5])
    for extra in ({}, {"repulsion": "sum", "repulsive_power": 3}, {"escape": "navigation"},
                  {"escape": "random_walk"}):
        plan_potential(gm, s, g, {"q_star": 2.0, "step": 0.5, "tolerance": 0.5, **extra})
    for name in ("wavefront-octile", "wavefront", "harmonic"):
        plan(name, gm, s, g)
    brushfire(gm, metric="euclidean")
    basins(build_field(gm, g))
    run.log(f"warm-up: {time.perf_counter() - t0:.1f} s loading the kernels and warming the caches on a 12 x 12 map "
            "(not part of any time in the table)")


#: part -> the function that runs it
_PARTS: dict[str, Callable[[_Run], None]] = {
    "maps": _part_maps,
    "seed000": _part_seed000,
    "convergence": _part_convergence,
    "seed003": _part_seed003,
    "seed002": _part_seed002,
    "turtlebot3": _part_turtlebot3,
    "arena": _part_arena,
    "moving": _part_moving,
}
