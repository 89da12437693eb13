"""Why a potential-field run did not reach its goal, and what would help: :func:`diagnose`.

Every run of the ``potential`` planner that does not reach the goal carries ``extra["hint"]``
(one line, also printed by ``gridfield plan`` and drawn on its figure) and ``extra["diagnosis"]``:

- ``reachable``: whether the goal can be reached from the start at all, by the octile wavefront
  from the goal (:mod:`gridfield.following.escapes`; 8-connected moves that never cut a corner, and around an
  open border). An unreachable goal ends the run as ``no_path`` before any step.
- ``basin_share``: the share of the free cells whose discrete steepest descent on the potential
  ends where the stall's does (:func:`gridfield.following.follower.basins`): how much of the map leads into the
  same trap.
- ``trap``: the point that names the trap, the same whatever the start: the discrete sink of the
  stall's cell (the cell where steepest descent on the potential ends), or, when that sink is the
  goal's own (the minimum is displaced off the goal), the stall point.
- ``passage``: the narrowest point of the shortest path from the trap to the goal (its clearance,
  the brushfire distance there, and where it is). When the repulsion's reach ``q_star`` is wider than
  that clearance, the passage is closed by repulsion from both sides.
- ``tried`` and ``suggest``: a smaller ``q_star`` is proposed only after it was tried and reached:
  the field is rebuilt on the same map with it (the brushfire reused; ``d_star`` and ``eta`` follow
  it where they were the scaled defaults, as ``--q-star`` does on the command line) and followed
  from the same start. ``tried`` lists each value tried and its status; ``suggest`` holds the first
  value that reached, and the hint says "try --q-star X" only then. When none reached, the hint
  says so and describes the passage.
- the hint also names the escape that always works when the goal is reachable
  (``--escape navigation`` follows the octile wavefront out of every minimum) and, for a follower
  pressed onto a wall (``stop_reason`` ``blocked``) or out of steps, what happened there.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..core.results import Field
from .escapes import NavigationEscape

if TYPE_CHECKING:
    from ..core.grid import GridMap
    from ..core.path import Path

__all__ = ["corner_passage", "diagnose", "robot_no_path", "unreachable_hint"]

#: The planners that take the diagonals a disc robot fits along though a side cell is blocked
#: (:attr:`gridfield.core.grid.GridMap.diagonals`): their moves are discrete steps between cell centres.
CORNER_PLANNERS = ("wavefront", "wavefront-octile")


def _fmt(v: float) -> str:
    return f"{v:.3g}"


def unreachable_hint(start: Any, goal: Any) -> str:
    """The hint of a ``no_path`` run.

    Parameters
    ----------
    start, goal : (x, y)
        The run's end points, world coordinates.

    Returns
    -------
    str
        One line naming both points (shortest round-trip formatting).

    Examples
    --------
    >>> unreachable_hint((1.0, 2.0), (3.0, 4.0))
    'the goal (3, 4) cannot be reached from the start (1, 2): no free path joins them on this map'
    """
    return (f"the goal ({_fmt(goal[0])}, {_fmt(goal[1])}) cannot be reached from the start "
            f"({_fmt(start[0])}, {_fmt(start[1])}): no free path joins them on this map")


def corner_passage(gridmap: GridMap, start: Any, goal: Any) -> str | None:
    """Why a planner that moves continuously cannot join ``start`` and ``goal`` where the grid planners can:
    only along a diagonal through a corner the robot passes (:attr:`~gridfield.core.grid.GridMap.diagonals`).

    A disc robot of at least half a cell may fit along the diagonal between two free cells of its
    configuration space that touch only at a corner (both side cells blocked). The discrete
    planners (:data:`CORNER_PLANNERS`) step along it; for a planner that moves continuously (a
    potential-field follower, fast marching, any-angle paths, NavFn, the exact planners on the
    map's polygons) the C-space there is a single point: the passage has zero width. This returns
    the hint saying so when the octile wavefront joins the two points with those diagonals and not
    without them, else None.

    Parameters
    ----------
    gridmap : GridMap
        A configuration space (:func:`gridfield.geometry.cspace.apply_robot`).
    start, goal : (x, y)
        Free points of it.

    Returns
    -------
    str or None

    Examples
    --------
    >>> from gridfield.geometry.cspace import apply_robot
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((2, 4), bool); occ[1, 0] = occ[0, 3] = True
    >>> print(corner_passage(apply_robot(GridMap(Grid((2, 4), 1.0), occ), 0.6), (1.5, 0.5), (2.5, 1.5)))
    the robot passes between the start (1.5, 0.5) and the goal (2.5, 1.5) only along the diagonal
    through the corner (2, 1) of two blocked cells of its configuration space: it fits along it, but
    such a passage has no width for a planner that moves or spreads its field continuously; wavefront
    and wavefront-octile take it
    """
    if gridmap.diagonals is None:
        return None
    from ..fields.navigation import extract_path, wavefront

    grid = gridmap.grid
    cell = grid.cell_of(float(start[0]), float(start[1]))
    if cell is None:
        return None
    nav = wavefront(gridmap, goal, costs="octile", stop_at=start)
    if not math.isfinite(float(nav.value[cell])):
        return None
    plain = wavefront(gridmap.with_occupied(gridmap.occupied, diagonals=None), goal, costs="octile", stop_at=start)
    if math.isfinite(float(plain.value[cell])):
        return None
    cells = np.asarray(extract_path(nav, start, method="descent").extra["cells"], dtype=np.int64).reshape(-1, 2)
    a, b = cells[:-1], cells[1:]
    occ = gridmap.occupied
    # the diagonal steps with a blocked side cell: the corner they pass is the larger row and column line
    through = (a[:, 0] != b[:, 0]) & (a[:, 1] != b[:, 1]) & (occ[b[:, 0], a[:, 1]] | occ[a[:, 0], b[:, 1]])
    corners = list(zip((grid.origin[0] + np.maximum(a[through, 1], b[through, 1]) * grid.resolution).tolist(),
                       (grid.origin[1] + np.maximum(a[through, 0], b[through, 0]) * grid.resolution).tolist(),
                       strict=True))
    where = ", ".join(f"({x:.4g}, {y:.4g})" for x, y in corners[:3]) + (", ..." if len(corners) > 3 else "")
    one = len(corners) == 1
    which = "the diagonal through the corner" if one else "diagonals through the corners"
    return (f"the robot passes between the start ({_fmt(start[0])}, {_fmt(start[1])}) and the goal "
            f"({_fmt(goal[0])}, {_fmt(goal[1])}) only along {which} {where} of two blocked cells of its "
            f"configuration space: it fits along {'it' if one else 'them'}, but such a passage has no width "
            "for a planner that moves or spreads its field continuously; "
            f"{' and '.join(CORNER_PLANNERS)} take {'it' if one else 'them'}")


def with_corner_passage(path: Path, gridmap: GridMap, start: Any, goal: Any) -> Path:
    """``path`` with :func:`corner_passage`'s hint when it did not reach and the corner passage is why
    (``extra["hint"]``, ``extra["diagnosis"]["corner_passage"]``); else ``path`` unchanged.

    Parameters
    ----------
    path : Path
        A run of a planner that is not one of :data:`CORNER_PLANNERS` on ``gridmap``.
    gridmap : GridMap
    start, goal : (x, y)

    Returns
    -------
    Path
    """
    import dataclasses

    if path.status == "reached" or gridmap.diagonals is None or path.planner in CORNER_PLANNERS:
        return path
    hint = corner_passage(gridmap, start, goal)
    if hint is None:
        return path
    diagnosis = {**path.extra.get("diagnosis", {}), "reachable": True, "corner_passage": True}
    return dataclasses.replace(path, extra={**path.extra, "hint": hint, "diagnosis": diagnosis})


def robot_no_path(path: Path, point: Path, robot: str, start: Any, goal: Any) -> Path:
    """A ``no_path`` run in a robot's configuration space, its hint saying when the robot closes the passage.

    ``point`` is the same search (planner, parameters, start, goal) on the map without the robot's
    shape. When it does not end ``no_path`` either, the goal is cut off by the robot's size or shape,
    not by the map: the hint says so and how the point's run ended (``a point reaches it`` only when
    it did); ``extra["diagnosis"]`` gets ``robot_closes_passage`` (True) and ``point_status``.
    Otherwise (or when ``path`` is not ``no_path``) ``path`` is returned unchanged.

    Parameters
    ----------
    path : Path
        The run in the configuration space.
    point : Path
        The same run for a point robot.
    robot : str
        The robot, as its ``describe()`` says (``"disc of radius 0.4"``).
    start, goal : (x, y)
        The run's end points, world coordinates.

    Returns
    -------
    Path
        ``path``, with a new ``extra["hint"]`` and ``extra["diagnosis"]`` when the robot closes the passage.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.path import Path
    >>> blocked = Path(np.array([[1.0, 2.0]]), "no_path", "wavefront")
    >>> point = Path(np.array([[1.0, 2.0], [3.0, 2.0]]), "reached", "wavefront")
    >>> print(robot_no_path(blocked, point, "disc of radius 0.4", (1, 2), (3, 2)).hint)
    the robot (disc of radius 0.4) closes the passage: the goal (3, 2) cannot be reached by it from the start
    (1, 2), but a point reaches it (wavefront on the map without the robot's shape, length 2)
    """
    import dataclasses

    if path.status != "no_path" or point.status == "no_path" or path.extra.get("diagnosis", {}).get("corner_passage"):
        return path  # (a corner passage: the robot does pass, along a diagonal, and the hint says where)
    if point.status == "reached":
        verdict = f"a point reaches it ({point.planner} on the map without the robot's shape, length {point.length:.4g})"
    else:
        verdict = (f"a free path joins them for a point ({point.planner} on the map without the robot's shape "
                   f"ends {point.status}, not no_path)")
    # the end points as the plan line prints them (4 digits: 1.825 stays 1.825)
    hint = (f"the robot ({robot}) closes the passage: the goal ({goal[0]:.4g}, {goal[1]:.4g}) cannot be reached "
            f"by it from the start ({start[0]:.4g}, {start[1]:.4g}), but {verdict}")
    if robot.startswith("polygon"):  # a shape that may fit turned: the pose planners (issue 45)
        hint += "; if the robot can turn, plan in (x, y, theta): --headings N (apply_robot(..., headings=N))"
    diagnosis = {**path.extra.get("diagnosis", {}), "reachable": False, "robot_closes_passage": True,
                 "point_status": point.status}
    return dataclasses.replace(path, extra={**path.extra, "hint": hint, "diagnosis": diagnosis})


def diagnose(path: Any, field: Field, escape: NavigationEscape | None = None, *,
             follow: Callable[..., Any] | None = None) -> dict[str, Any]:
    """The diagnosis of a potential-field run that did not reach its goal (see the module docstring).

    Parameters
    ----------
    path : Path
        A ``potential`` run whose status is not ``reached``.
    field : Field
        The field it followed (``map``, ``potential``, ``goal``, ``distance``, ``params``).
    escape : NavigationEscape, optional
        Reused for its wavefront and basins when the caller has one.
    follow : callable, optional
        ``follow(field, start, params=...) -> Path``, the follower a proposed ``q_star`` is re-run with
        (:func:`gridfield.following.follower.follow`, which passes itself: diagnose sits below the follower). Without
        it no ``q_star`` is proposed, only the passage is named.

    Returns
    -------
    dict
        ``hint`` (one line), ``reachable``, ``basin_share``, ``stall`` (where the run stopped),
        ``trap`` (the point the trap is described by) and, when known, ``passage`` (``clearance``,
        ``at``), ``tried`` (``[q_star, status]`` of each re-run) and ``suggest`` (parameter -> a
        value that was tried and reached).

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.fields.potential import build_field
    >>> from gridfield.following.follower import follow
    >>> occ = np.zeros((9, 15), bool); occ[1:8, 7] = True     # a wall between start and goal
    >>> f = build_field(GridMap(Grid((9, 15), 1.0, border="wall"), occ), (13.5, 4.5))
    >>> p = follow(f, (1.5, 4.5))
    >>> p.status
    'local_minimum'
    >>> d = diagnose(p, f)
    >>> d["reachable"], d["hint"].endswith("--escape navigation reaches it")
    (True, True)
    """
    esc = escape if escape is not None else NavigationEscape(field)
    gm = field.map
    grid = gm.grid
    stall = path.extra.get("stall_point") or path.end.tolist()
    stall = (float(stall[0]), float(stall[1]))
    out: dict[str, Any] = {"stall": list(stall)}
    value = esc.value(stall)
    reachable = math.isfinite(value)
    out["reachable"] = reachable
    cell = grid.cell_of(*stall)
    free = ~np.asarray(gm.occupied, dtype=bool)
    goal_basin = False
    trap = stall
    if cell is not None and free[cell]:
        sink = esc.sink
        out["basin_share"] = float(np.count_nonzero(sink == sink[cell]) / max(int(np.count_nonzero(free)), 1))
        gcell = grid.cell_of(float(field.goal[0]), float(field.goal[1]))
        goal_basin = gcell is not None and bool(sink[gcell] == sink[cell])
        if not goal_basin:  # the trap's own point: its sink cell, the same from every start draining there
            rc = np.unravel_index(int(sink[cell]), grid.shape)
            trap = tuple(grid.cell_to_world(np.array([[rc[0], rc[1]]]))[0].tolist())
    else:
        out["basin_share"] = math.nan
    out["trap"] = list(trap)
    reason = path.extra.get("stop_reason", "")
    where = f"({_fmt(stall[0])}, {_fmt(stall[1])})"
    if path.status == "max_iterations":
        lead = f"the step budget ran out at {where}; raise --max-iterations"
    elif reason == "blocked":
        lead = (f"the force presses the follower onto the obstacle at {where} (no free step within 75 degrees "
                "of it)")
    elif goal_basin:
        gap = math.hypot(stall[0] - float(field.goal[0]), stall[1] - float(field.goal[1]))
        lead = (f"local minimum at {where}, {_fmt(gap)} from the goal: repulsion from obstacles near the goal "
                "moves the potential's minimum off it")
    else:
        share = out["basin_share"]
        basin = f"its basin is {share:.0%} of the free space" if math.isfinite(share) else ""
        lead = (f"local minimum of the potential around ({_fmt(trap[0])}, {_fmt(trap[1])})"
                f"{' (' + basin + ')' if basin else ''}")
    tips: list[str] = []
    q_star = float(field.params.get("q_star", math.nan)) if getattr(field, "params", None) else math.nan
    if reachable:
        passage = _narrowest(field, trap)
        if passage is not None:
            clearance, at = passage
            out["passage"] = {"clearance": clearance, "at": at}
            res = grid.resolution
            if math.isfinite(q_star) and q_star > clearance >= res:
                narrow = (f"q_star {_fmt(q_star)} is wider than the half-width {_fmt(clearance)} of the passage "
                          f"at ({_fmt(at[0])}, {_fmt(at[1])})")
                tried = _try_q_star(path, field, clearance, follow) if follow is not None else []
                out["tried"] = tried
                good = [q for q, status in tried if status == "reached"]
                if good:
                    out["suggest"] = {"q_star": good[0]}
                    tips.append(f"{narrow}; try --q-star {_fmt(good[0])}: re-run with it, it reaches the goal from this start")
                elif tried:
                    values = ", ".join(_fmt(q) for q, _ in tried)
                    tips.append(f"{narrow}, but a smaller one does not reach either (--q-star {values} tried)")
                else:
                    tips.append(narrow)
        tips.append("the goal is reachable: --escape navigation reaches it")
    else:
        tips.append("the goal cannot be reached from here: no free path leads there")
    out["hint"] = lead + "; " + "; ".join(tips)
    return out


#: The ``q_star`` values a failed run is re-run with, as fractions of the passage's half-width (largest
#: first: the least change that reaches); each is rounded to the 3 digits the hint prints.
Q_STAR_TRIES = (0.9, 0.5)


def _try_q_star(path: Any, field: Field, clearance: float, follow: Callable[..., Any]) -> list[list[Any]]:
    """Re-run ``path``'s query with each ``q_star`` of :data:`Q_STAR_TRIES` until one reaches.

    The field is rebuilt on the same map with the same brushfire (``field.distance``) and the same
    parameters, except ``q_star`` and, where they were the scaled defaults of the old ``q_star``
    (:func:`gridfield.core.params.resolve`), ``d_star`` and ``eta``, which are scaled again: what
    ``gridfield plan ... --q-star X`` runs. Returns ``[[q_star, status], ...]`` in the order tried.
    """
    from ..core.params import D_STAR_PER_Q_STAR, balanced_eta
    from ..fields.potential import build_field

    start = path.points[0]
    unit = field.map.grid.resolution
    base = {**field.params, **path.params}
    q_old = float(base["q_star"])
    d_old = float(base["d_star"])
    derived_d = d_old == D_STAR_PER_Q_STAR * q_old
    derived_eta = math.isclose(float(base["eta"]), balanced_eta(float(base["zeta"]), d_old, q_old,
                                                                 float(base["repulsive_power"]), unit), rel_tol=1e-12)
    tried: list[list[Any]] = []
    for fraction in Q_STAR_TRIES:
        q = float(_fmt(fraction * clearance))
        if not 0 < q < q_old or any(q == t[0] for t in tried):
            continue
        params = {**base, "q_star": q}
        if derived_d:
            params.pop("d_star")
        if derived_eta:
            params.pop("eta")
        params = {k: v for k, v in params.items() if v is not None}
        rerun = follow(build_field(field.map, field.goal, params, dmap=field.distance), start, params=params)
        tried.append([q, rerun.status])
        if rerun.status == "reached":
            break
    return tried


def _narrowest(field: Field, stall: tuple[float, float]) -> tuple[float, list[float]] | None:
    """``(clearance, point)`` of the passage every path from ``stall`` to the goal must squeeze through:
    the bottleneck clearance ``b``, the largest ``t`` such that the free cells with brushfire distance
    ``>= t`` still join the stall's cell to the goal's (4-connected; around an open border the
    outside counts as wide open), found by bisection over the distance values. ``point`` is a cell of
    clearance ``b`` in that region, the one closest to the way from the stall to the goal."""
    from scipy import ndimage

    dmap = getattr(field, "distance", None)
    if dmap is None:
        return None
    gm = field.map
    grid = gm.grid
    a = grid.cell_of(*stall)
    g = grid.cell_of(float(field.goal[0]), float(field.goal[1]))
    if a is None or g is None:
        return None
    free = ~np.asarray(gm.occupied, dtype=bool)
    dist = np.where(free, np.asarray(dmap.distance, dtype=float), -np.inf)
    if grid.border != "wall":  # the open space around the map
        dist = np.pad(dist, 1, constant_values=np.inf)
        a, g = (a[0] + 1, a[1] + 1), (g[0] + 1, g[1] + 1)
    # the stall's own surroundings (within q_star) are the trap, not a passage: always open
    q_star = float(field.params.get("q_star", 0.0)) if getattr(field, "params", None) else 0.0
    reach = min(q_star, 3.0 * max(grid.rows, grid.cols) * grid.resolution) if math.isfinite(q_star) else 0.0
    rr, cc = np.indices(dist.shape)
    near = np.hypot(rr - a[0], cc - a[1]) * grid.resolution <= reach
    near[g] = False  # a goal close to obstacles is a real narrowing (its repulsion displaces the minimum)
    dist = np.where(near & (dist >= 0), np.inf, dist)
    vals = np.unique(dist[np.isfinite(dist) & (dist >= 0)])
    vals = vals[vals <= dist[g]]
    if not len(vals):
        return None

    def joined(t: float) -> NDArray[np.int32] | None:
        lab = ndimage.label(dist >= t)[0]
        return lab if lab[a] != 0 and lab[a] == lab[g] else None

    lo, hi = 0, len(vals) - 1
    if joined(float(vals[lo])) is None:
        return None
    while lo < hi:  # the largest index whose threshold still joins them
        mid = (lo + hi + 1) // 2
        if joined(float(vals[mid])) is not None:
            lo = mid
        else:
            hi = mid - 1
    b = float(vals[lo])
    # where: the narrowest cell of the shortest path through the cells of clearance >= b
    from ..core.grid import Grid, GridMap
    from ..fields.navigation import extract_path, wavefront

    wide = GridMap(Grid(dist.shape, 1.0, border="wall"), ~(dist >= b))
    nav = wavefront(wide, (g[1] + 0.5, g[0] + 0.5), costs="octile", stop_at=(a[1] + 0.5, a[0] + 0.5))
    cells = np.asarray(extract_path(nav, (a[1] + 0.5, a[0] + 0.5), method="descent").extra.get("cells", []))
    if not len(cells):
        return None
    k = int(np.argmin(dist[cells[:, 0], cells[:, 1]]))
    if dist[cells[k, 0], cells[k, 1]] != b:  # (never: the path must pass the bottleneck)
        return None
    off = 0 if grid.border == "wall" else 1
    return b, grid.cell_to_world(np.array([[cells[k, 0] - off, cells[k, 1] - off]]))[0].tolist()
