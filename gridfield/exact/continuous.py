"""The continuous (exact-geometry) potential-field planner on vector worlds.

:func:`plan_exact_potential` follows the same attractive / repulsive models, parameters, step
rules, stop rules and escapes as the grid planner ``potential`` -- through the same core,
:func:`gridfield.following.follower.descend` -- with the field sampled differently: the force at a point is
computed from the exact distance and closest point to each obstacle instead of being read from
gradient arrays.

Force (``p`` the point, ``g`` the goal; names of :data:`gridfield.planners.PARAMETERS`)
    attractive: ``-grad`` of gridfield.fields.potential's attractive potential (``zeta``, ``d_star``);
    repulsive: for an obstacle at distance ``D < q_star`` with closest point ``c``,
    ``eta * (1/D - 1/q_star) / D**repulsive_power`` along ``(p - c) / D``; ``repulsion="sum"``
    adds one term per obstacle (seed 000), ``"nearest"`` takes only the nearest obstacle.
    A wall border is one more obstacle: the boundary of the world's bounds. ``saturate=R`` drops
    the repulsion of obstacles at ``D >= R`` (seed 004). Distances are Euclidean and gradients
    analytic: the grid options ``metric`` and ``gradient`` have no meaning here and are ignored.

Closest points
    circles analytically (``Obstacle.center``/``radius``), polygons, segments and points with
    :func:`shapely.shortest_line`; with more than a few obstacles only those within ``q_star``
    (an STRtree query) are measured.

Potential (for the ``potential_increase`` escape)
    the attractive potential plus ``0.5 * eta * (1/D - 1/q_star)**2`` per obstacle within
    ``q_star`` -- the classic potential, which is what gridfield.fields.potential stores for every
    ``repulsive_power``.

Blocking
    a move ``p -> q`` is blocked when the closed segment touches an obstacle (shapely
    ``intersects``; circles analytically) or, with a wall border, reaches the world's boundary.
    With an open border the world extends beyond its bounds as free space.

Seed 000 (``maps/seed000.yaml``: start (1, 10), goal (22, 12), zeta = eta = 1, q_star = 2,
repulsive_power 3, sum over obstacles, step 0.1) reaches the goal after exactly 247 steps; the
path is the 248 visited points plus the goal (appended, like the seed's ``P = [P Xf]``), length
24.7621 (24.7 for the 247 steps). With the segment (17.5, 10)-(17.5, 8)
(``maps/seed000_segment.yaml``) it oscillates between (16.874, 9.058) and (16.970, 9.028) and
stops as a local minimum after 213 steps; the stall point, the one of the two with the smaller
force, is (16.970, 9.028), the point the seed reports. The continuous equilibrium is
(16.9512, 9.0518).

Examples
--------
>>> from gridfield.io import read_world, bundled_map
>>> w = read_world(bundled_map("seed000.yaml"))
>>> p = plan_exact_potential(w, w.start, w.goal, w.params)
>>> p.status, p.iterations, round(p.length, 4)
('reached', 247, 24.7621)
"""

from __future__ import annotations

import math
import time
import weakref
from collections.abc import Callable, Mapping
from dataclasses import replace
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike

from ..core.errors import GridfieldError, ParameterError
from ..core.params import Escape, Follower, group, validate
from ..core.path import Path
from ..fields.potential import resolve_params
from ..fields.sampling import attraction_force
from ..following.descent import descend, rules
from ..following.follower import resolve_follow_params
from ..geometry.world import World

__all__ = ["ExactField", "default_step", "plan_exact_potential"]

#: Above this many non-circle obstacles the force queries an STRtree for those within q_star.
_TREE_MIN = 8


class ExactField:
    """Forces, potential and blocking of the Khatib model on a vector world, from exact geometry.

    Parameters
    ----------
    world : World
    goal : (2,) array_like
    params : mapping, optional
        Potential parameters (:func:`gridfield.fields.potential.resolve_params`); ``model`` must be
        ``"khatib"``. Follower parameters are ignored here.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}]})
    >>> f = ExactField(w, (9, 5), {"zeta": 0.0, "eta": 1.0, "q_star": 2.0, "repulsive_power": 2})
    >>> [round(v, 6) for v in f.force((7.0, 5.0))]   # D = 1: eta*(1 - 1/2)/1**2 along +x
    [0.5, 0.0]
    >>> f.blocked((3.0, 3.0), (7.0, 7.0)), f.blocked((3.0, 3.0), (3.0, 7.0))
    (True, False)
    """

    def __init__(self, world: World, goal: ArrayLike, params: Mapping[str, Any] | None = None) -> None:
        if not isinstance(world, World):
            raise ParameterError(f"the exact planner needs a World, got {type(world).__name__}")
        p = resolve_params(params, unit=default_step(world))
        if p["model"] != "khatib":
            raise ParameterError(f"the exact planner implements model 'khatib' only, got model {p['model']!r}; "
                                 "the vortex model is a grid field: use planner 'potential'")
        self.world = world
        self.params = p
        g = np.asarray(goal, dtype=float).reshape(-1)
        self.goal = (float(g[0]), float(g[1]))
        self.zeta, self.d_star = p["zeta"], p["d_star"]
        self.eta, self.q_star, self.power = p["eta"], p["q_star"], float(p["repulsive_power"])
        self.sum = p["repulsion"] == "sum"
        self.saturate = p["saturate"]
        circles = [ob for ob in world.obstacles if ob.kind == "circle"]
        self._circles = [(float(ob.center[0]), float(ob.center[1]), float(ob.radius)) for ob in circles]  # type: ignore[index,arg-type]
        self._geoms, tree, self._union = _geometry(world)
        self._tree = tree if len(self._geoms) > _TREE_MIN else None
        self._wall = world.border == "wall"
        self._attr = attraction_force(self.goal, p)

    def __repr__(self) -> str:
        return (f"ExactField(obstacles={len(self.world.obstacles)}, goal=({self.goal[0]:.6g}, {self.goal[1]:.6g}), "
                f"repulsion={self.params['repulsion']!r}, q_star={self.q_star:.6g})")

    # -- distances ------------------------------------------------------------------------
    def closest(self, p: tuple[float, float]) -> list[tuple[float, float, float]]:
        """``(D, cx, cy)``: distance and closest point of each obstacle that can repel at ``p``.

        All obstacles (and the wall) when there are few, else those an STRtree finds within
        ``q_star`` (or the nearest, for ``repulsion="nearest"``).
        """
        x, y = p
        out: list[tuple[float, float, float]] = []
        for cx, cy, r in self._circles:
            dx, dy = x - cx, y - cy
            rho = math.sqrt(dx * dx + dy * dy)
            if rho > 0:
                out.append((rho - r, cx + r * dx / rho, cy + r * dy / rho))
            else:
                out.append((-r, cx + r, cy))
        if len(self._geoms):
            pt = shapely.points(p)
            geoms = self._geoms
            if self._tree is not None:
                if math.isfinite(self.q_star) and self.sum:
                    idx = self._tree.query(pt, predicate="dwithin", distance=self.q_star)
                else:
                    idx = self._tree.query_nearest(pt)
                geoms = geoms[idx]
            if len(geoms):
                c = shapely.get_coordinates(shapely.shortest_line(geoms, pt))[0::2].tolist()
                for cx, cy in c:
                    out.append((math.hypot(x - cx, y - cy), cx, cy))
        if self._wall:
            xmin, ymin, xmax, ymax = self.world.bounds
            out.append(min(((x - xmin, xmin, y), (xmax - x, xmax, y), (y - ymin, x, ymin), (ymax - y, x, ymax))))
        return out

    def _active(self, p: tuple[float, float]) -> list[tuple[float, float, float]]:
        near = self.closest(p)
        if not near:
            return near
        if not self.sum:
            near = [min(near, key=lambda t: t[0])]
        lim = self.q_star if self.saturate is None else min(self.q_star, self.saturate)
        return [t for t in near if t[0] < lim]

    # -- the field ------------------------------------------------------------------------
    def attraction(self, p: tuple[float, float]) -> tuple[float, float]:
        """The attractive force at ``p``."""
        return self._attr(p)

    def force(self, p: tuple[float, float]) -> tuple[float, float]:
        """The force ``F = F_attr + F_rep`` at ``p``. Raises GridfieldError inside an obstacle."""
        fx, fy = self._attr(p)
        x, y = p
        eta, iq, power = self.eta, 1.0 / self.q_star, self.power
        for d, cx, cy in self._active(p):
            if d <= 0.0:
                raise GridfieldError(f"the point ({x:g}, {y:g}) lies inside or on an obstacle")
            mag = eta * (1.0 / d - iq) / d**power
            fx += mag * (x - cx) / d
            fy += mag * (y - cy) / d
        return fx, fy

    def potential(self, p: tuple[float, float]) -> float:
        """The potential at ``p`` (attractive + classic repulsive ``0.5*eta*(1/D - 1/q_star)**2``)."""
        gx, gy = self.goal
        dist = math.hypot(p[0] - gx, p[1] - gy)
        u: float
        if self.d_star == 0.0:
            u = self.zeta * dist
        elif dist <= self.d_star:
            u = 0.5 * self.zeta * dist * dist
        else:
            u = self.d_star * self.zeta * dist - 0.5 * self.zeta * self.d_star**2
        iq = 1.0 / self.q_star
        for d, _, _ in self._active(p):
            if d <= 0.0:
                return math.inf
            u += 0.5 * self.eta * (1.0 / d - iq) ** 2
        return u

    def blocked(self, p: tuple[float, float], q: tuple[float, float]) -> bool:
        """Whether the closed segment ``p -> q`` touches an obstacle or (wall border) the world's boundary."""
        if self._wall:
            xmin, ymin, xmax, ymax = self.world.bounds
            for x, y in (p, q):
                if not (xmin < x < xmax and ymin < y < ymax):
                    return True
        ax, ay = p
        bx, by = q
        vx, vy = bx - ax, by - ay
        vv = vx * vx + vy * vy
        for cx, cy, r in self._circles:
            t = 0.0 if vv == 0 else min(1.0, max(0.0, ((cx - ax) * vx + (cy - ay) * vy) / vv))
            if math.hypot(ax + t * vx - cx, ay + t * vy - cy) <= r:
                return True
        if self._union is not None:
            seg = shapely.linestrings([p, q]) if vv > 0 else shapely.points(p)
            if shapely.intersects(self._union, seg):
                return True
        return False


#: Per world: its non-circle geometries, their STRtree and their prepared union (None when there are none).
#: Built once per world (a grid map's world has thousands of pieces; the union takes seconds).
_GEOMETRY: weakref.WeakKeyDictionary[World, tuple[Any, Any, Any]] = weakref.WeakKeyDictionary()


def _geometry(world: World) -> tuple[Any, Any, Any]:
    if world not in _GEOMETRY:
        geoms = np.array([ob.geometry for ob in world.obstacles if ob.kind != "circle"], dtype=object)
        tree = shapely.STRtree(geoms) if len(geoms) else None
        union = shapely.union_all(geoms) if len(geoms) else None
        if union is not None:
            shapely.prepare(union)
        _GEOMETRY[world] = (geoms, tree, union)
    return _GEOMETRY[world]


def _check_point(world: World, name: str, point: ArrayLike) -> np.ndarray:
    """``world.check_point``, with a fast path for a point clear of the cached union (no circles)."""
    p = np.asarray(point, dtype=float).reshape(-1)
    if p.shape == (2,) and np.all(np.isfinite(p)) and not any(ob.kind == "circle" for ob in world.obstacles):
        xmin, ymin, xmax, ymax = world.bounds
        union = _geometry(world)[2]
        if xmin <= p[0] <= xmax and ymin <= p[1] <= ymax and (
                union is None or not shapely.intersects(union, shapely.points(p))):
            return p
    return world.check_point(name, point)


def _clearance(world: World, pts: np.ndarray) -> float:
    """``world.clearance(pts)``; without circles and with many obstacles, through the cached STRtree."""
    geoms, tree, union = _geometry(world)
    if len(geoms) <= _TREE_MIN or len(pts) < 2 or any(ob.kind == "circle" for ob in world.obstacles):
        return world.clearance(pts)
    line = shapely.linestrings(pts)
    if shapely.intersects(union, line):
        best = 0.0
    else:
        _, dist = tree.query_nearest(line, return_distance=True)
        best = float(dist.min()) if len(dist) else math.inf
    if world.border == "wall":
        xmin, ymin, xmax, ymax = world.bounds
        dw = np.minimum.reduce([pts[:, 0] - xmin, xmax - pts[:, 0], pts[:, 1] - ymin, ymax - pts[:, 1]])
        best = min(best, float(np.maximum(dw, 0.0).min()))
    return best


def default_step(world: World) -> float:
    """The length unit the exact planner scales its registry defaults by: the world's ``resolution``
    when it gives one, else a hundredth of the shorter side of its bounds.

    Parameters
    ----------
    world : World
        The vector world.

    Returns
    -------
    float

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> default_step(world_from_dict({"bounds": [0, 0, 20, 10], "border": "wall", "obstacles": []}))
    0.1
    >>> default_step(world_from_dict({"bounds": [0, 0, 20, 10], "border": "wall", "resolution": 0.25, "obstacles": []}))
    0.25
    """
    if world.resolution is not None:
        return float(world.resolution)
    xmin, ymin, xmax, ymax = world.bounds
    return min(xmax - xmin, ymax - ymin) / 100.0


def plan_exact_potential(world: World, start: ArrayLike, goal: ArrayLike, params: Mapping[str, Any] | None, *,
                         cache: dict[Any, Any] | None = None) -> Path:
    """The ``exact-potential`` planner: :func:`gridfield.following.follower.descend` on exact forces.

    Parameters
    ----------
    world : World
    start, goal : (2,) array_like
        Free points of the world (a point inside an obstacle raises :class:`GridfieldError`).
    params : mapping
        Potential parameters (:func:`gridfield.fields.potential.resolve_params`) and follower parameters
        (:func:`gridfield.following.follower.resolve_follow_params`; ``step`` defaults to the world's resolution, else
        1/100 of its smaller side; ``sampling`` is ignored).

    Returns
    -------
    Path
        ``planner="exact-potential"``; ``min_clearance`` is the exact distance of the path
        polyline to the obstacles; ``seconds`` the time of the descent; ``extra["build_seconds"]``
        the time of setting up the geometry (union, STRtree).

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> w = read_world(bundled_map("seed000_segment.yaml"))
    >>> p = plan_exact_potential(w, w.start, w.goal, w.params)
    >>> p.status, p.extra["stop_reason"], [round(v, 3) for v in p.extra["stall_point"]]
    ('local_minimum', 'oscillation', [16.97, 9.028])
    >>> plan_exact_potential(w, (8.0, 14.0), w.goal, w.params)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.GridfieldError: start (8, 14) lies inside obstacle 1 (polygon)
    """
    params = validate(params)  # a raw mapping from a direct call is checked too
    if not isinstance(world, World):
        raise ParameterError(f"the exact planner needs a World, got {type(world).__name__}")
    s = _check_point(world, "start", start)
    g = _check_point(world, "goal", goal)
    params = dict(params or {})
    from ..core.limits import check_seconds
    from ..core.params import MAX_ITERATIONS

    steps = params.get("max_iterations")
    check_seconds({"obstacle vertex": sum(len(ob.vertices) for ob in world.obstacles),  # the union and tree
                   "follower step": MAX_ITERATIONS if steps is None else steps}, f"exact potential of {world.source or 'the world'}")
    t0 = time.perf_counter()
    field = ExactField(world, g, params)
    build = time.perf_counter() - t0
    fp = resolve_follow_params(params, unit=default_step(world))
    potential: Callable[[tuple[float, float]], float] | None = None
    attraction = None
    if fp["escape"] == "potential_increase":
        potential, attraction = field.potential, field.attraction
    path = descend(
        field.force, s, g, blocked=field.blocked, potential=potential, attraction=attraction,
        rng=np.random.default_rng(fp["seed"]), planner="exact-potential",
        spec=rules(group(Follower, fp), group(Escape, fp)),
    )
    extra = dict(path.extra)
    extra["build_seconds"] = build
    merged = dict(field.params)
    merged.update(fp)
    merged.pop("sampling", None)
    return replace(path, params=merged, min_clearance=_clearance(world, path.points), extra=extra)
