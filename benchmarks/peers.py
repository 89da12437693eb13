"""Benchmark: the peers a user would otherwise pick, on the same maps, as ratios to gridfield.

Run ``python benchmarks/peers.py`` (options: ``--repeat`` (default 3), ``--scale F`` to shrink the
example maps (``--scale 0.25`` for a smoke run), ``--json``). The peers are in gridfield's
``[bench]`` extra (``roboticstoolbox-python``, ``python-motion-planning``); a peer that is not
installed is reported as missing, not as a failure.

Each peer runs on its own example-sized map, and gridfield's equivalent on the same map in the
same process; ``ratio`` is peer time / gridfield time (medians; > 1: gridfield is faster):

``RTB DistanceTransformPlanner``
    Robotics Toolbox for Python's ``DistanceTransformPlanner`` (metric ``"euclidean"``: 8
    neighbours, diagonal cost sqrt 2) on its book example, the ``house`` floor plan shipped with
    ``rtb-data`` (397 x 596 cells), from ``br3`` to ``kitchen``: ``plan()`` (the distance
    transform from the goal) + ``query(start)`` (the path). gridfield: ``plan("wavefront", ...)``,
    the wavefront navigation function from the goal and its descent path; the
    ``wavefront-octile`` variant (the same octile costs as RTB's euclidean) is shown too.
``pmp A*``
    python-motion-planning 2.1's ``AStar`` on a ``Grid`` laid out like the package's README
    example: 51 x 31 cells, a wall round the border and four wall segments, obstacles inflated by
    3 cells, from (5, 5) to (45, 25). gridfield: ``plan("wavefront-octile", ...)`` on the same
    cells (obstacles and inflation occupied), the same 8-neighbour octile metric; both return the
    shortest octile path (lengths are compared). For scale (not a target: not pmp's example map)
    the same pair also runs on RTB's house floor plan.
``pmp APF``
    python-motion-planning's ``APF`` is a *path-tracking controller* for a robot model, not a
    planner: each control step it finds a look-ahead point on a given path, computes an
    attractive force towards it and a repulsive force from its ESDF (3 x 3 window,
    ``numpy.gradient``), and turns the sum into an acceleration. There is no APF planner to time
    against ``plan``, so it is compared per step and per force: (1) a whole APF control step
    (``get_action``: force + look-ahead + velocity/acceleration) against one step of gridfield's
    follower (``follow``'s time per iteration: force, step rule, exact cell-walk collision check,
    stop rules); (2) its attractive + repulsive force (its two force methods, which take one point
    per call) at every free cell centre against gridfield's force at the same points
    (``sample_force``: bilinear interpolation of the precomputed gradient arrays, all points in one
    call), per point; (3) for context, not a target, the same force against gridfield's one-point
    sampler (``grid_sampler``) called once per point, where Python's call overhead (measured beside
    it: a compiled function that returns its arguments) is most of gridfield's time. pmp is timed
    at every free cell centre of the README-like map without the inflation (the controller avoids obstacles itself), with a CircularRobot of radius 0.5, its default gains and
    a repulsive range of 3 (pmp's default, 2 x the radius = 1, never acts on 1 m cells: every free
    cell centre is at least 1 from an obstacle centre); its ESDF is built once beforehand, as
    gridfield's field is. gridfield uses the same gains and range, ``d_star = 1`` (the APF pulls
    towards a look-ahead point about 1 m ahead, so its attraction is about 1 at most).
``cell-by-cell``
    The classic potential-field script's way (as in PythonRobotics' potential_field_planning):
    a plain Python double loop over the cells of a 600 x 500 grid, each summing the attractive
    term and the repulsive term of the nearest of 4 obstacle points (written here from the
    formula, not copied), once in the scripts' style (a function call per term, ``np.hypot`` on
    scalars: the peer of the 100x target) and once as tight as plain Python gets (``math.hypot``,
    inlined: context, not a target; it is this benchmark's own rewrite, not a script a user
    would find and pick, and it shows how much of the gap is the interpreter alone). gridfield:
    ``build_field`` on the same grid with those 4 cells occupied (brushfire + fused potential
    **and** gradients, which the loop does not compute). The potentials are checked to agree
    (``max |dU|``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from end_to_end import Timing, timed


@dataclass
class Row:
    """One peer against its gridfield equivalent."""

    peer: str
    what: str
    map: str
    gridfield: str
    peer_time: Timing | None = None
    gf_time: Timing | None = None
    note: str = ""
    status: str = "ok"  # ok | missing | failed
    unit: str = "ms"
    context: bool = False  #: shown for scale or as a breakdown, not a target (the name says why)

    @property
    def ratio(self) -> float:
        if self.peer_time is None or self.gf_time is None:
            return math.nan
        return self.peer_time.median / self.gf_time.median

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["ratio"] = self.ratio
        return d


@dataclass
class _Context:
    repeat: int
    scale: float
    rows: list[Row] = field(default_factory=list)


def _gridmap(occupied: np.ndarray, resolution: float = 1.0, source: str = "") -> Any:
    from gridfield.core.grid import Grid, GridMap

    return GridMap(Grid(occupied.shape, resolution), np.ascontiguousarray(occupied, bool), source=source)


def _gf_plan(name: str, gm: Any, start: Sequence[float], goal: Sequence[float],
             params: dict[str, Any] | None = None) -> Any:
    from gridfield.planners import plan

    return plan(name, gm, start, goal, params or {})


def _missing(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}".splitlines()[0]


# ----------------------------------------------------------------------------------------------
# Robotics Toolbox: DistanceTransformPlanner
# ----------------------------------------------------------------------------------------------
def _house(scale: float) -> tuple[np.ndarray, tuple[int, int], tuple[int, int]]:
    """RTB's house floor plan (row 0 = y 0, as gridfield), start br3 and goal kitchen as (x, y) cells."""
    from roboticstoolbox import rtb_load_matfile

    house = rtb_load_matfile("data/house.mat")
    occ = np.asarray(house["floorplan"]) > 0
    start, goal = (int(v) for v in house["places"]["br3"]), (int(v) for v in house["places"]["kitchen"])
    start, goal = tuple(start), tuple(goal)
    k = max(1, round(1 / scale)) if scale < 1 else 1
    if k > 1:  # shrink (smoke runs): a cell is occupied if all its k x k source cells are, so no door closes
        h, w = (occ.shape[0] // k) * k, (occ.shape[1] // k) * k
        occ = occ[:h, :w].reshape(h // k, k, w // k, k).all(axis=(1, 3))
        start, goal = (start[0] // k, start[1] // k), (goal[0] // k, goal[1] // k)
    return occ, start, goal  # type: ignore[return-value]


def bench_rtb(ctx: _Context) -> None:
    """RTB DistanceTransformPlanner vs gridfield's wavefront planners on the house floor plan."""
    base = Row("RTB DistanceTransformPlanner (euclidean): plan + query", "wavefront from the goal + path",
               "house floor plan", 'plan("wavefront")')
    try:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            from roboticstoolbox import DistanceTransformPlanner
        occ, start, goal = _house(ctx.scale)
    except Exception as e:  # ImportError, or its data package missing
        base.status, base.note = "missing", _missing(e)
        ctx.rows.append(base)
        return
    base.map = f"house floor plan {occ.shape[0]}x{occ.shape[1]}"

    def rtb() -> np.ndarray:
        dx = DistanceTransformPlanner(occ.astype(np.uint8), goal=goal, metric="euclidean")
        dx.plan()
        return dx.query(start=start)

    # RTB is slow (seconds): no warm-up run, it has nothing to compile
    t_rtb, rtb_path = timed(rtb, ctx.repeat, warmup=0, budget=40.0)
    rtb_len = float(np.sum(np.hypot(*np.diff(np.asarray(rtb_path, float), axis=0).T)))
    gm = _gridmap(occ, 1.0, "house")
    s, g = (start[0] + 0.5, start[1] + 0.5), (goal[0] + 0.5, goal[1] + 0.5)
    for name in ("wavefront", "wavefront-octile"):
        row = Row(base.peer, base.what, base.map, f'plan("{name}")', peer_time=t_rtb)
        try:
            t_gf, path = timed(lambda name=name: _gf_plan(name, gm, s, g), max(ctx.repeat, 5))
            row.gf_time = t_gf
            row.note = (f"path length: RTB {rtb_len:.1f}, gridfield {path.length:.1f} ({path.status}, "
                        f"{len(path.points)} points)")
        except Exception as e:
            row.status, row.note = "missing" if "not available" in str(e) else "failed", _missing(e)
        ctx.rows.append(row)


# ----------------------------------------------------------------------------------------------
# python-motion-planning: A* and APF
# ----------------------------------------------------------------------------------------------
PMP_START, PMP_GOAL = (5, 5), (45, 25)


def _pmp_grid() -> Any:
    """A 51 x 31 pmp Grid laid out like the package's README example (indexed ``[x, y]``)."""
    from python_motion_planning.common import TYPES, Grid

    grid = Grid(bounds=[[0, 51], [0, 31]])
    grid.fill_boundary_with_obstacles()
    t = grid.type_map
    t[10:21, 15] = TYPES.OBSTACLE
    t[20, :15] = TYPES.OBSTACLE
    t[30, 15:] = TYPES.OBSTACLE
    t[40, :16] = TYPES.OBSTACLE
    grid.inflate_obstacles(radius=3)
    return grid


def _pmp_occupancy(grid: Any) -> np.ndarray:
    """gridfield occupancy ``[row=y, col=x]`` of a pmp grid: obstacles and inflation are occupied."""
    from python_motion_planning.common import TYPES

    data = np.asarray(grid.type_map.data)
    return ((data == TYPES.OBSTACLE) | (data == TYPES.INFLATION)).T


def bench_pmp_astar(ctx: _Context) -> Any:
    """pmp A* vs gridfield wavefront-octile; returns the A* path (cells) for the APF benchmark."""
    row = Row("python-motion-planning AStar", "shortest 8-neighbour octile path", "pmp README-like 51x31",
              'plan("wavefront-octile")')
    try:
        from python_motion_planning.path_planner.graph_search.a_star import AStar

        grid = _pmp_grid()
    except Exception as e:
        row.status, row.note = "missing", _missing(e)
        ctx.rows.append(row)
        return None

    def astar() -> Any:
        return AStar(map_=grid, start=PMP_START, goal=PMP_GOAL).plan()

    t_pmp, (path, info) = timed(astar, max(ctx.repeat, 5))  # warm-up compiles pmp's numba helpers
    row.peer_time = t_pmp
    gm = _gridmap(_pmp_occupancy(grid), 1.0, "pmp example")
    s, g = (PMP_START[0] + 0.5, PMP_START[1] + 0.5), (PMP_GOAL[0] + 0.5, PMP_GOAL[1] + 0.5)
    try:
        t_gf, gpath = timed(lambda: _gf_plan("wavefront-octile", gm, s, g), max(ctx.repeat, 5) * 4)
        row.gf_time = t_gf
        row.note = f"path length: A* {info['length']:.3f}, gridfield {gpath.length:.3f} ({gpath.status})"
    except Exception as e:
        row.status, row.note = "missing" if "not available" in str(e) else "failed", _missing(e)
    ctx.rows.append(row)
    return path


def bench_pmp_astar_house(ctx: _Context) -> None:
    """Context: pmp A* on RTB's house floor plan (a real-sized map) vs gridfield wavefront-octile."""
    row = Row("python-motion-planning AStar (context: a bigger map)", "shortest 8-neighbour octile path",
              "house floor plan", 'plan("wavefront-octile")', context=True)
    try:
        from python_motion_planning.common import TYPES, Grid
        from python_motion_planning.path_planner.graph_search.a_star import AStar

        occ, start, goal = _house(ctx.scale)
    except Exception as e:
        row.status, row.note = "missing", _missing(e)
        ctx.rows.append(row)
        return
    row.map = f"house floor plan {occ.shape[0]}x{occ.shape[1]}"
    type_map = np.where(occ.T, TYPES.OBSTACLE, TYPES.FREE).astype(np.int8)  # pmp indexes [x, y]
    grid = Grid(bounds=[[0, occ.shape[1]], [0, occ.shape[0]]], type_map=type_map)
    t_pmp, (_, info) = timed(lambda: AStar(map_=grid, start=start, goal=goal).plan(), ctx.repeat, warmup=0,
                             budget=30.0)
    row.peer_time = t_pmp
    gm = _gridmap(occ, 1.0, "house")
    s, g = (start[0] + 0.5, start[1] + 0.5), (goal[0] + 0.5, goal[1] + 0.5)
    try:
        t_gf, gpath = timed(lambda: _gf_plan("wavefront-octile", gm, s, g), max(ctx.repeat, 5))
        row.gf_time = t_gf
        row.note = (f"path length: A* {info['length']:.3f}, gridfield {gpath.length:.3f} ({gpath.status}); "
                    f"A* expanded {len(info['expand'])} cells")
    except Exception as e:
        row.status, row.note = "missing" if "not available" in str(e) else "failed", _missing(e)
    ctx.rows.append(row)


#: APF's repulsive influence range for the benchmark: pmp's default (2 x the robot radius = 1 cell)
#: never acts on a grid of 1 m cells (every free cell centre is at least 1 from an obstacle
#: centre), so its repulsive force would always be the cheap early exit.
APF_RANGE = 3.0


def _per_point(t: Timing, n: int) -> Timing:
    """A timing of a loop over ``n`` points as microseconds per point."""
    k = 1e6 / n
    return Timing(t.median * k, t.min * k, t.max * k, t.n)


def bench_pmp_apf(ctx: _Context, astar_path: Any) -> None:
    """pmp APF's force and control step vs gridfield's force sample and follower step."""
    where = "pmp README-like 51x31, no inflation"
    rows = [
        Row("python-motion-planning APF: get_action (one control step)", "one step", where,
            "one follower step (follow(): seconds / iterations)", unit="us"),
        Row("python-motion-planning APF: attractive + repulsive force at each free cell centre", "force at points",
            where, "force at the same points (sample_force(field, points), bilinear), per point", unit="us"),
        Row("python-motion-planning APF: attractive + repulsive force at a point (context: one Python call per "
            "point on both sides)", "force at a point", where,
            "force at a point (grid_sampler(field)(p), bilinear)", unit="us", context=True),
    ]
    try:
        from gymnasium import spaces
        from python_motion_planning.common import TYPES
        from python_motion_planning.common.env.robot.circular_robot import CircularRobot
        from python_motion_planning.controller.path_tracker.apf import APF

        grid = _pmp_grid()
        if astar_path is None:
            from python_motion_planning.path_planner.graph_search.a_star import AStar

            astar_path, _ = AStar(map_=grid, start=PMP_START, goal=PMP_GOAL).plan()
        # the controller avoids obstacles itself: give it the walls without the planner's inflation
        data = grid.type_map.data
        data[data == TYPES.INFLATION] = TYPES.FREE
        grid.update_esdf()  # built once, outside the timed loops (gridfield's field likewise)
    except Exception as e:
        for r in rows:
            r.status, r.note = "missing", _missing(e)
        ctx.rows += rows
        return
    from gridfield.fields.potential import build_field
    from gridfield.following.follower import follow, grid_sampler, sample_force

    occ = _pmp_occupancy(grid)
    world_path = [grid.map_to_world(p) for p in astar_path]
    robot = CircularRobot(dim=2, radius=0.5)
    apf = APF(spaces.Box(-np.inf, np.inf, shape=(6,)), spaces.Box(-1.0, 1.0, shape=(3,)), 0.1, path=world_path,
              robot_model=robot, obstacle_grid=grid, max_lin_speed=1.0, rep_range=APF_RANGE)
    # every free cell centre (pmp cell (i, j) and gridfield cell (row j, col i) share the centre (i + .5, j + .5))
    rr, cc = np.nonzero(~occ)
    pts = np.stack([cc + 0.5, rr + 0.5], axis=1)
    n = len(pts)
    active = float(np.mean(grid.esdf[cc, rr] * grid.resolution < APF_RANGE))
    target = np.asarray(world_path[-1], float)
    obs = [np.array([x, y, 0.0, 0.0, 0.0, 0.0]) for x, y in pts]

    def pmp_forces() -> None:
        for p in pts:
            apf._calculate_attractive_force(p, target)
            apf._calculate_repulsive_force(p)

    def pmp_steps() -> None:
        for o in obs:
            apf.get_action(o)

    gm = _gridmap(occ, 1.0, "pmp example")
    goal = (PMP_GOAL[0] + 0.5, PMP_GOAL[1] + 0.5)
    # the APF's gains and range; it pulls towards a look-ahead point about 1 m ahead (|F_att| <= ~1):
    # d_star = 1 caps gridfield's attraction at the same magnitude
    params = {"q_star": APF_RANGE, "zeta": 1.0, "eta": 1.0, "d_star": 1.0}
    fld = build_field(gm, goal, params)
    force = grid_sampler(fld)
    tuples = [(float(x), float(y)) for x, y in pts]

    def gf_forces() -> None:
        for p in tuples:
            force(p)

    def gf_forces_batch() -> None:
        sample_force(fld, pts)

    # the floor of any per-point call: a compiled (C) function of two floats
    echo = math.copysign

    def call_floor() -> None:
        for p in tuples:
            echo(p[0], p[1])

    reps = max(ctx.repeat, 3)
    t_force = _per_point(timed(pmp_forces, reps)[0], n)
    t_step = _per_point(timed(pmp_steps, reps)[0], n)
    t_gf_force = _per_point(timed(gf_forces, reps * 3)[0], n)
    t_gf_batch = _per_point(timed(gf_forces_batch, reps * 20)[0], n)
    t_floor = _per_point(timed(call_floor, reps * 3)[0], n)

    # gridfield's follower: time per step from Path.seconds / iterations (the follower's own clock)
    start = (PMP_START[0] + 0.5, PMP_START[1] + 0.5)
    per_step: list[float] = []
    last: list[Any] = []

    def gf_follow() -> None:
        p = follow(fld, start, params={**params, "step": 0.25, "max_iterations": 5000})
        per_step.append(p.seconds / max(p.iterations, 1) * 1e6)
        last[:] = [p]

    timed(gf_follow, reps * 3)
    per_step = per_step[1:]  # drop the warm-up
    t_gf_step = Timing(float(np.median(per_step)), min(per_step), max(per_step), len(per_step))
    p = last[0]
    at = f"at all {n} free cell centres, {active:.0%} of them within the repulsive range {APF_RANGE:g}"
    follower = f"follower from (5.5, 5.5), step 0.25: {p.status} after {p.iterations} steps"
    if p.status == "collision":
        follower += " (with the APF's gains the repulsion one cell from a wall is weaker than the attraction)"
    rows[0].peer_time, rows[0].gf_time = t_step, t_gf_step
    rows[0].note = f"pmp {at} (look-ahead on the A* path, velocity and acceleration); gridfield {follower}"
    rows[1].peer_time, rows[1].gf_time = t_force, t_gf_batch
    rows[1].note = (f"both {at}; pmp's force methods take one point per call, gridfield's sample_force all "
                    "of them in one call")
    rows[2].peer_time, rows[2].gf_time = t_force, t_gf_force
    rows[2].note = (f"both {at}; of gridfield's time per call, {t_floor.median:.2f} us is the floor of calling "
                    "any compiled function with two floats from a Python loop (measured: math.copysign)")
    ctx.rows += rows


# ----------------------------------------------------------------------------------------------
# The classic cell-by-cell potential (PythonRobotics-style), written here from the formula
# ----------------------------------------------------------------------------------------------
#: The 4 obstacle points of the classic script's example, shifted into a 60 m x 50 m world.
CELL_OBSTACLES = ((25.0, 35.0), (15.0, 25.0), (30.0, 36.0), (35.0, 35.0))
CELL_GOAL = (40.0, 40.0)


def _attraction(x: float, y: float, gx: float, gy: float, zeta: float) -> float:
    """Attractive potential of one cell, numpy scalar maths (as the classic script)."""
    return 0.5 * zeta * np.hypot(x - gx, y - gy) ** 2


def _repulsion(x: float, y: float, ox: Sequence[float], oy: Sequence[float], eta: float, q_star: float) -> float:
    """Repulsive potential of one cell from the nearest obstacle point, found by a loop over them."""
    nearest, dmin = -1, math.inf
    for i in range(len(ox)):
        d = np.hypot(x - ox[i], y - oy[i])
        if d < dmin:
            nearest, dmin = i, d
    d = np.hypot(x - ox[nearest], y - oy[nearest])
    if d <= 1e-9:
        return math.inf
    if d >= q_star:
        return 0.0
    return 0.5 * eta * (1.0 / d - 1.0 / q_star) ** 2


def cell_by_cell_potential(width: int, height: int, res: float, goal: tuple[float, float],
                           obstacles: Sequence[tuple[float, float]], zeta: float, eta: float,
                           q_star: float, *, style: str = "script") -> list[list[float]]:
    """The potential at every cell centre by a plain Python double loop (the reference, slow on purpose).

    ``U = 0.5*zeta*d_goal**2 + 0.5*eta*(1/d - 1/q_star)**2`` with ``d`` the distance to the nearest
    obstacle point (repulsion only where ``d < q_star``; ``inf`` at an obstacle point), one cell at
    a time into an x-major list of lists.

    ``style="script"``: the way the classic potential-field scripts write it, one function call per
    term per cell, distances by ``np.hypot`` on scalars, the nearest obstacle found by index and
    its distance recomputed. ``style="tight"``: the same loop tuned as far as plain Python goes
    (``math.hypot``, inlined terms): the fastest a cell-by-cell Python loop can be.
    """
    gx, gy = goal
    ox, oy = [o[0] for o in obstacles], [o[1] for o in obstacles]
    pmap = [[0.0] * height for _ in range(width)]
    for ix in range(width):
        x = (ix + 0.5) * res
        column = pmap[ix]
        for iy in range(height):
            y = (iy + 0.5) * res
            if style == "script":
                column[iy] = float(_attraction(x, y, gx, gy, zeta) + _repulsion(x, y, ox, oy, eta, q_star))
                continue
            u = 0.5 * zeta * ((x - gx) ** 2 + (y - gy) ** 2)
            d = math.inf
            for o in obstacles:
                d = min(d, math.hypot(x - o[0], y - o[1]))
            if d <= 1e-9:
                u = math.inf
            elif d < q_star:
                u += 0.5 * eta * (1.0 / d - 1.0 / q_star) ** 2
            column[iy] = u
    return pmap


def bench_cell_by_cell(ctx: _Context) -> None:
    """The cell-by-cell Python potential (script style and tight) vs gridfield's build_field on the same grid."""
    from gridfield.fields.potential import build_field

    scale = min(ctx.scale, 1.0)
    width, height = max(8, round(600 * scale)), max(8, round(500 * scale))
    res = 0.1 / scale
    obstacles = [((math.floor(x / res) + 0.5) * res, (math.floor(y / res) + 0.5) * res) for x, y in CELL_OBSTACLES]
    goal = ((math.floor(CELL_GOAL[0] / res) + 0.5) * res, (math.floor(CELL_GOAL[1] / res) + 0.5) * res)
    zeta, eta, q_star = 1.0, 100.0, 5.0
    occ = np.zeros((height, width), bool)
    for x, y in obstacles:
        occ[int(y / res), int(x / res)] = True
    gm = _gridmap(occ, res, "cell-by-cell")
    params = {"zeta": zeta, "d_star": math.inf, "eta": eta, "q_star": q_star}
    t_gf, fld = timed(lambda: build_field(gm, goal, params), max(ctx.repeat, 5) * 2)
    free = ~occ
    for style, label in (("script", "as the classic script writes it: np.hypot on scalars, a call per term"),
                         ("tight", "context: the same loop tuned as far as plain Python goes, math.hypot, inlined")):
        t_ref, pmap = timed(lambda style=style: cell_by_cell_potential(width, height, res, goal, obstacles, zeta,
                                                                       eta, q_star, style=style),
                            ctx.repeat, warmup=0, budget=30.0)
        ref = np.asarray(pmap).T  # x-major -> [row, col]
        err = float(np.max(np.abs(ref[free] - fld.potential[free]) / np.maximum(1.0, np.abs(ref[free]))))
        ctx.rows.append(Row(f"cell-by-cell Python potential ({label})", "potential on every cell",
                            f"{width}x{height}, 4 obstacle points", "build_field (brushfire + potential + gradients)",
                            peer_time=t_ref, gf_time=t_gf, context=style == "tight",
                            note=f"max relative |dU| between the two potentials: {err:.1e}"))


# ----------------------------------------------------------------------------------------------
def measure(repeat: int = 3, scale: float = 1.0) -> list[Row]:
    """Run every peer benchmark; a failing one becomes a ``failed`` row, never an exception."""
    ctx = _Context(repeat, scale)
    astar: dict[str, Any] = {}
    steps: list[tuple[str, Callable[[], Any]]] = [
        ("rtb", lambda: bench_rtb(ctx)),
        ("pmp A*", lambda: astar.setdefault("path", bench_pmp_astar(ctx))),
        ("pmp A* (house)", lambda: bench_pmp_astar_house(ctx)),
        ("pmp APF", lambda: bench_pmp_apf(ctx, astar.get("path"))),
        ("cell-by-cell", lambda: bench_cell_by_cell(ctx)),
    ]
    for name, fn in steps:
        t0 = time.perf_counter()
        try:
            fn()
        except Exception as e:  # report, keep going
            ctx.rows.append(Row(name, "", "", "", status="failed", note=_missing(e)))
        print(f"  peers: {name} done in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return ctx.rows


def _fmt(t: Timing | None, unit: str) -> str:
    if t is None:
        return "-"
    k = 1e3 if unit == "ms" else 1.0
    return f"{t.median * k:,.4g} ({t.min * k:,.4g}-{t.max * k:,.4g}) n={t.n}"


def table(rows: Sequence[Row]) -> str:
    """A markdown table of the rows; ratio = peer median / gridfield median."""
    out = ["| peer | map | peer time | gridfield equivalent | gridfield time | ratio (peer / gridfield) | ≥ 100x | notes |",
           "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        u = r.unit
        peer = f"{_fmt(r.peer_time, u)} {u}" if r.peer_time else "-"
        if r.status != "ok" or r.gf_time is None:
            out.append(f"| {r.peer} | {r.map} | {peer} | {r.gridfield} | {r.status} | - | - | {r.note} |")
            continue
        verdict = "(context)" if r.context else ("yes" if r.ratio >= 100 else "NO")
        out.append(f"| {r.peer} | {r.map} | {peer} | {r.gridfield} | {_fmt(r.gf_time, u)} {u} "
                   f"| **{r.ratio:,.0f}x** | {verdict} | {r.note} |")
    return "\n".join(out)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per measurement (median reported)")
    ap.add_argument("--scale", type=float, default=1.0, help="shrink the example maps (smoke runs: 0.25)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    rows = measure(args.repeat, args.scale)
    print(json.dumps([r.as_dict() for r in rows], indent=1, default=str) if args.json else table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
