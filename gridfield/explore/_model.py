"""The explorer's model: its state, the undo stack and the actions that compute; no matplotlib.

:class:`ExplorerModel` is the explorer without a figure. It holds the workspace (the vector world
and its grid map), the robot, the configuration space the planners get, the endpoints, the
parameters and the planner, the latest path and potential, and the undo stack. Its transitions
(``_add_obstacle``, ``_remove_obstacle``, ``_set_robot``, ``_turn_cspace_on``, ``_move_endpoint``,
``_use_planner``, ``_restore_state``) change that state and rebuild what depends on it (the
rasterized obstacle, the C-space); ``_plan`` re-plans. They neither draw nor plan on their own:
:class:`gridfield.explore.Explorer` calls one, then redraws the figure and re-plans.

The brushfire the potential planner uses is an :class:`gridfield.distance.incremental.IncrementalBrushfire`
of the planning map kept here, updated by the cells that changed since its last use (see the
package's docstring, "Maps that change").
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import GridfieldError, ParameterError
from ..core.grid import GridMap
from ..core.path import Path
from ..geometry.world import Obstacle, Robot, World

#: Planners the explorer offers, in order, when their module is installed.
EXPLORER_PLANNERS = ("potential", "exact-potential", "wavefront-octile", "navfn")
#: Parameters with a slider.
SLIDER_PARAMS = ("zeta", "eta", "q_star", "d_star", "step")
#: The sliders each planner reads (the others are hidden while it is selected).
PLANNER_SLIDERS: dict[str, tuple[str, ...]] = {
    "potential": SLIDER_PARAMS,
    "exact-potential": SLIDER_PARAMS,
    "wavefront-octile": (),
    "navfn": (),  # Nav2's NavFn: its costmap parameters have no slider (--param, the map's costmap)
}
#: The sliders of the potential planner each field model reads (:meth:`ExplorerModel.sliders_in_use`): the
#: classic field all of them; nf-blend the repulsion's reach and the step; the other complete models and
#: the vortex model only the step (the classic gains would move nothing).
MODEL_SLIDERS: dict[str, tuple[str, ...]] = {"khatib": SLIDER_PARAMS, "nf-blend": ("q_star", "step")}


def available_planners(*, world: bool = True) -> list[str]:
    """The planners the explorer offers: all of :data:`EXPLORER_PLANNERS`, the exact-geometry ones
    only when a vector world exists.

    Parameters
    ----------
    world : bool
        Whether the map has a vector world (without one, the exact planners run on the grid's
        cells as polygons, which the explorer does not offer).

    Returns
    -------
    list of str
        Planner names, in the order of :data:`EXPLORER_PLANNERS`.

    Examples
    --------
    >>> available_planners()
    ['potential', 'exact-potential', 'wavefront-octile', 'navfn']
    >>> available_planners(world=False)
    ['potential', 'wavefront-octile', 'navfn']
    """
    from ..planners import PLANNERS

    return [name for name in EXPLORER_PLANNERS if world or PLANNERS[name][2] != "world"]


@dataclasses.dataclass(frozen=True)
class _State:
    """What undo restores: the workspace, the robot, the C-space and the endpoints."""

    world: World | None
    gridmap: GridMap | None
    robot: Robot | None
    cspace_on: bool
    cworld: World | None
    cgridmap: GridMap | None
    start: tuple[float, float] | None
    goal: tuple[float, float] | None


class ExplorerModel:
    """The explorer's state and the computations on it, without a figure (the base of
    :class:`gridfield.explore.Explorer`, which documents the attributes).

    Parameters
    ----------
    target : World or GridMap
        The map (the workspace). A world is rasterized at ``resolution`` (default: its own).
    params : mapping, optional
        Planner parameters overriding the world file's ``params``.
    planner : str
        One of :data:`EXPLORER_PLANNERS`.
    resolution : float, optional
    start, goal : (x, y), optional
        Default: the world's start and goal.
    robot : Robot, float or (N, 2) array_like, optional
        A robot to plan for (its C-space is computed at once); default: the world file's
        ``robot``, else none (a point).

    Examples
    --------
    >>> from gridfield.io import read_world, bundled_map
    >>> m = ExplorerModel(read_world(bundled_map("seed000.yaml")), resolution=0.5)
    >>> m._add_obstacle([(14, 2), (17, 2), (17, 5), (14, 5)])  # no figure: nothing is drawn or planned
    >>> m._plan().status, len(m.world.obstacles), m.n_updates
    ('reached', 4, 1)
    >>> m._restore_state(m.history.pop()); len(m.world.obstacles)
    3
    """

    def __init__(
        self,
        target: World | GridMap,
        *,
        params: Mapping[str, Any] | None = None,
        planner: str = "potential",
        resolution: float | None = None,
        start: ArrayLike | None = None,
        goal: ArrayLike | None = None,
        robot: Robot | float | ArrayLike | None = None,
    ) -> None:
        from ..planners import check_params

        if not isinstance(target, World | GridMap):
            raise ParameterError(f"Explorer needs a World or a GridMap, got {type(target).__name__}")
        if planner not in EXPLORER_PLANNERS:
            raise ParameterError(f"planner must be one of {EXPLORER_PLANNERS}, got {planner!r}")
        self.world: World | None = target if isinstance(target, World) else (
            target.world if isinstance(target.world, World) else None)
        self.resolution: float | None
        if isinstance(target, GridMap):
            self.resolution = target.grid.resolution
            self.gridmap: GridMap | None = target
        else:
            self.resolution = resolution
            self.gridmap = self._rasterize()
        base = dict(self.world.params) if self.world is not None else {}
        base.update(params or {})
        self.params: dict[str, Any] = check_params(base)
        self.planner = planner
        w = self.world
        self.start: tuple[float, float] | None = self._point(start, "start") if start is not None else (
            w.start if w is not None else None)
        self.goal: tuple[float, float] | None = self._point(goal, "goal") if goal is not None else (
            w.goal if w is not None else None)
        if self.world is not None and (start is not None or goal is not None):
            self.world = dataclasses.replace(self.world, start=self.start, goal=self.goal)
            if self.gridmap is not None and isinstance(self.gridmap.world, World):
                self.gridmap = self.gridmap.with_occupied(self.gridmap.occupied, world=self.world)
        from ..geometry.cspace import as_robot

        self.robot: Robot | None = as_robot(robot) if robot is not None else (w.robot if w is not None else None)
        self.cspace_on = self.robot is not None
        self.cworld, self.cgridmap = self.world, self.gridmap
        self._rebuild_cspace()
        self.history: list[_State] = []
        self._initial = self._state()
        self.path: Path | None = None
        self.field: Any = None
        self.n_updates = 0

    # -- construction ----------------------------------------------------------------------
    def _rasterize(self, world: World | None = None) -> GridMap | None:
        from ..geometry.rasterize import as_gridmap

        world = self.world if world is None else world
        if world is None:
            return self.gridmap
        res = self.resolution if self.resolution is not None else world.resolution
        if res is None:
            xmin, ymin, xmax, ymax = world.bounds
            res = max(xmax - xmin, ymax - ymin) / 200.0
        return as_gridmap(world, res)

    def _point(self, p: ArrayLike, name: str) -> tuple[float, float]:
        a = np.asarray(p, dtype=float).reshape(-1)
        if a.shape != (2,) or not np.all(np.isfinite(a)):
            raise ParameterError(f"{name} must be two finite numbers x, y, got {p!r}")
        return (float(a[0]), float(a[1]))

    def _workspace(self) -> World | GridMap:
        """The workspace the robot moves in: the vector world, else the grid map."""
        ws = self.world if self.world is not None else self.gridmap
        assert ws is not None  # the constructor takes a World or a GridMap
        return ws

    def _bounds(self) -> tuple[float, ...]:
        if self.gridmap is not None:
            return self.gridmap.grid.bounds
        assert self.world is not None
        return self.world.bounds

    # -- planner ---------------------------------------------------------------------------
    def _use_planner(self, name: str) -> None:
        """Plan with ``name`` from now on; raises :class:`ParameterError` for a planner not offered."""
        if name not in EXPLORER_PLANNERS:
            raise ParameterError(f"planner must be one of {EXPLORER_PLANNERS}, got {name!r}")
        self.planner = name

    # -- undo ------------------------------------------------------------------------------
    def _state(self) -> _State:
        return _State(self.world, self.gridmap, self.robot, self.cspace_on, self.cworld, self.cgridmap,
                      self.start, self.goal)

    def _push(self) -> None:
        self.history.append(self._state())

    def _restore_state(self, s: _State) -> None:
        self.world, self.gridmap, self.robot, self.cspace_on = s.world, s.gridmap, s.robot, s.cspace_on
        self.cworld, self.cgridmap, self.start, self.goal = s.cworld, s.cgridmap, s.start, s.goal

    # -- endpoints -------------------------------------------------------------------------
    def _is_free(self, p: tuple[float, float]) -> str | None:
        """None when ``p`` is a valid start/goal, else why not."""
        try:
            if self.cspace_on and self.robot is not None:
                from ..geometry.cspace import check_robot_point

                check_robot_point(self._workspace(), self.robot, "point", p)
            if self.cgridmap is not None and self.planner != "exact-potential":
                self.cgridmap.check_point("point", p)
            elif self.cworld is not None:
                self.cworld.check_point("point", p)
        except GridfieldError as e:
            return str(e)
        return None

    def _sync_endpoints(self) -> None:
        """The worlds carry start and goal too (the vortex model puts a charge at the start)."""
        if self.world is not None:
            self.world = dataclasses.replace(self.world, start=self.start, goal=self.goal)
            if self.gridmap is not None and isinstance(self.gridmap.world, World):
                self.gridmap = self.gridmap.with_occupied(self.gridmap.occupied, world=self.world)
        if not (self.cspace_on and self.robot is not None):
            self.cworld, self.cgridmap = self.world, self.gridmap
        elif self.cworld is not None:
            self.cworld = dataclasses.replace(self.cworld, start=self.start, goal=self.goal)
            if self.cgridmap is not None and isinstance(self.cgridmap.world, World):
                self.cgridmap = self.cgridmap.with_occupied(self.cgridmap.occupied, world=self.cworld)

    def _move_endpoint(self, which: str, p: tuple[float, float], *, push: bool = True) -> None:
        """Set the start or the goal (``which``) to ``p``, undoable with ``push``; the worlds follow."""
        if push:
            self._push()
        setattr(self, which, p)
        self._sync_endpoints()

    # -- obstacles, robot and C-space ------------------------------------------------------
    def _add_obstacle(self, vertices: Sequence[Sequence[float]] | NDArray[np.float64]) -> None:
        """Add a polygon obstacle (undoable) and burn its cells into the map; the C-space is rebuilt when on.

        Raises :class:`GridfieldError` for fewer than 3 vertices or a self-intersecting outline.
        """
        import shapely
        from shapely.geometry import Polygon

        v = np.asarray(vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3 or not np.all(np.isfinite(v)):
            raise ParameterError(f"a polygon needs at least 3 finite vertices (x, y), got shape {v.shape}")
        poly = Polygon(v)
        if poly.area <= 0 or not poly.is_valid:
            raise GridfieldError(f"the polygon is not simple ({shapely.is_valid_reason(poly)}); "
                                 "click the vertices in order around it")
        self._push()
        if self.world is not None:
            oid = max((o.id for o in self.world.obstacles), default=0) + 1
            ob = Obstacle(oid, "polygon", poly)
            self.world = dataclasses.replace(self.world, obstacles=(*self.world.obstacles, ob))
            if self.gridmap is not None:
                self.gridmap = self._burn_obstacle(ob)  # only the new polygon is rasterized
        elif self.gridmap is not None:
            self.gridmap = self._burn_obstacle(Obstacle(0, "polygon", poly), drawn=v)
        self._rebuild_cspace()

    def _remove_obstacle(self, obstacle_id: int) -> None:
        """Remove the world obstacle ``obstacle_id`` (undoable) and free its cells; the C-space is
        rebuilt when on.

        Raises :class:`ParameterError` when there is no world or no such obstacle.
        """
        if self.world is None or self.gridmap is None or self.gridmap.obstacle_id is None:
            raise ParameterError("only obstacles of a vector world can be removed")
        gone = [o for o in self.world.obstacles if o.id == obstacle_id]
        if not gone:
            raise ParameterError(f"the world has no obstacle {obstacle_id!r}")
        self._push()
        self.world = dataclasses.replace(self.world, obstacles=tuple(o for o in self.world.obstacles
                                                                     if o.id != obstacle_id))
        self.gridmap = self._unburn_obstacle(gone[0])
        self._rebuild_cspace()

    def _set_robot(self, robot: Robot | float | ArrayLike | None) -> Robot | None:
        """Set the robot (undoable; None: a point, which turns the C-space off) and rebuild the
        C-space when on; returns it. Raises :class:`ParameterError` for a non-convex polygon."""
        from ..geometry.cspace import as_robot

        r = as_robot(robot)
        self._push()
        self.robot = r
        if r is None:
            self.cspace_on = False
        self._rebuild_cspace()
        return r

    def _turn_cspace_on(self) -> None:
        """Plan in the robot's configuration space from now on (undoable); there is a robot."""
        self._push()
        self.cspace_on = True
        self._rebuild_cspace()

    def _rebuild_cspace(self) -> None:
        if not (self.cspace_on and self.robot is not None):
            self.cworld, self.cgridmap = self.world, self.gridmap
            return
        from ..geometry.cspace import apply_robot

        if self.world is not None:
            cworld = apply_robot(self.world, self.robot)
            assert isinstance(cworld, World)  # a World's C-space is a World
            self.cworld = cworld
            self.cgridmap = self._rasterize(self.cworld) if self.gridmap is not None else None
        else:
            self.cworld = None
            self.cgridmap = apply_robot(self.gridmap, self.robot) if self.gridmap is not None else None  # type: ignore[assignment]

    # -- planning --------------------------------------------------------------------------
    def _background_field(self) -> Any:
        """The potential planner's field on the planning map, built here only when no plan built it
        (no start yet, a failed plan, a goal found unreachable at once); else None."""
        gm = self.cgridmap
        if self.planner != "potential" or self.goal is None or gm is None:
            return None
        from ..fields.potential import build_field

        try:
            return build_field(gm, np.asarray(self.goal), self.params, dmap=self._incremental_dmap())
        except GridfieldError:
            return None

    def sliders_in_use(self) -> tuple[str, ...]:
        """The sliders the current planner and field model read (the others are hidden): the
        potential planner's default complete model (``nf1``) reads only the step, so the classic
        field's gains are not offered where they would change nothing."""
        names = PLANNER_SLIDERS.get(self.planner, SLIDER_PARAMS)
        if self.planner == "potential":
            from ..following.follower import PLANNER_MODEL

            model = self.params.get("model") or PLANNER_MODEL
            names = tuple(n for n in names if n in MODEL_SLIDERS.get(model, ("step",)))
        return names

    def _plan_target(self) -> World | GridMap | None:
        """What the current planner plans on (and a movie of its run draws): the C-space world for
        ``exact-potential`` when there is one, else the C-space grid map (exact-potential on a grid
        map runs on its exact polygons, :mod:`gridfield.geometry.gridpoly`, through ``plan``)."""
        return self.cworld if self.planner == "exact-potential" and self.cworld is not None else self.cgridmap

    def _params_in_use(self) -> dict[str, Any]:
        """Every parameter's value in the next plan: the given ones, and the registry's defaults scaled
        to the map the current planner plans on (:func:`gridfield.core.params.resolve`, with the unit the
        planner resolves with: a grid map's cell, an exact world's step)."""
        from ..core.params import resolve

        target = self._plan_target()
        if isinstance(target, GridMap):
            unit = target.grid.resolution
        elif isinstance(target, World):
            from ..exact.continuous import default_step

            unit = default_step(target)
        else:
            unit = 1.0
        return resolve(self.params, unit=unit)

    def _plan(self) -> Path | None:
        """Re-plan with the current start, goal, parameters, planner and configuration space: set
        :attr:`path`, and :attr:`field` to the potential the plan followed (the potential planner's;
        built alone by :meth:`_background_field` when no plan built one).

        Returns
        -------
        Path or None
            The new :attr:`path`; None when the start or goal is missing.

        Raises
        ------
        GridfieldError
            When the plan failed (:attr:`path` is None, :attr:`field` the background field).
        """
        from ..planners import plan_with_field

        self.n_updates += 1
        self.path = None
        self.field = None
        if self.start is None or self.goal is None:
            self.field = self._background_field()
            return None
        target = self._plan_target()
        try:
            if target is None:
                raise GridfieldError(f"planner {self.planner!r} needs a vector world, and this map is a grid")
            if self.cspace_on and self.robot is not None:
                from ..geometry.cspace import check_robot_point

                for name in ("start", "goal"):
                    check_robot_point(self._workspace(), self.robot, name, getattr(self, name))
            dmap = self._incremental_dmap() if target is self.cgridmap else None
            self.path, field = plan_with_field(self.planner, target, self.start, self.goal, self.params, resolution=None,
                                               cache=self._plan_cache(target, dmap))
            self.field = field if self.planner == "potential" else None
            if self.planner == "navfn" and isinstance(target, GridMap):  # NavFn's potential, the field it descended
                from ..fields.navfn import navfn

                self.field = navfn(target, np.asarray(self.goal), params=self.params)
        except GridfieldError:
            self.field = self._background_field()
            raise
        if self.field is None:  # a goal found unreachable at once: no field was built
            self.field = self._background_field()
        return self.path

    # -- incremental updates (gridfield.distance.incremental) ---------------------------------------
    # A drawn obstacle is rasterized alone and burnt into the map; a removed one frees its cells
    # (those another obstacle also covers stay occupied with that obstacle's id). The brushfire of
    # the map the planners get (``cgridmap``) is an IncrementalBrushfire, brought up to date with
    # whatever changed since its last use (a drawn or removed obstacle, undo, clear, the C-space)
    # by the cells that differ; the field background and the potential planner reuse its distance
    # map instead of running a full brushfire.
    _incremental: Any = None
    _incremental_for: GridMap | None = None
    #: An update that changes more than this fraction of the cells rebuilds the brushfire instead.
    INCREMENTAL_MAX_FRACTION = 0.125

    def _burn_obstacle(self, ob: Obstacle, *, drawn: NDArray[np.float64] | None = None) -> GridMap:
        """The workspace map with ``ob``'s cells occupied, rasterized as :func:`gridfield.geometry.rasterize.rasterize`
        does (cells already occupied keep their lower id); ``drawn``: the outline to keep in the meta
        of a map without a world."""
        from ..geometry.rasterize import rasterize_obstacle

        gm = self.gridmap
        assert gm is not None
        new = np.zeros(gm.shape, bool)
        hit = rasterize_obstacle(gm.grid, ob)
        if hit is not None:
            (r0, r1, c0, c1), mask = hit
            sl = (slice(r0, r1 + 1), slice(c0, c1 + 1))
            new[sl] = mask & ~gm.occupied[sl]
        ids = None
        if gm.obstacle_id is not None:
            ids = gm.obstacle_id.copy()
            ids[new] = ob.id if ob.id > 0 else int(ids.max(initial=0)) + 1
        meta = dict(gm.meta)
        if drawn is not None:
            meta["drawn"] = [*meta.get("drawn", []), drawn]
        world = self.world if isinstance(gm.world, World) else gm.world
        return GridMap(gm.grid, gm.occupied | new, ids, world, gm.source, meta)

    def _unburn_obstacle(self, ob: Obstacle) -> GridMap:
        """The workspace map without ``ob`` (already removed from ``self.world``): its cells are freed,
        or given to the lowest-id remaining obstacle that covers them (only those are rasterized)."""
        from ..geometry.rasterize import rasterize_obstacle

        gm = self.gridmap
        assert gm is not None and gm.obstacle_id is not None and self.world is not None
        mine = gm.occupied & (gm.obstacle_id == ob.id)
        occ, ids = gm.occupied & ~mine, np.where(mine, 0, gm.obstacle_id).astype(np.int32)
        if mine.any():
            rows, cols = np.nonzero(mine)
            box = (rows.min(), rows.max(), cols.min(), cols.max())
            for other in sorted(self.world.obstacles, key=lambda o: o.id):  # ascending: the lowest id wins
                hit = rasterize_obstacle(gm.grid, other)
                if hit is None:
                    continue
                (r0, r1, c0, c1), mask = hit
                if r0 > box[1] or r1 < box[0] or c0 > box[3] or c1 < box[2]:
                    continue
                sl = (slice(r0, r1 + 1), slice(c0, c1 + 1))
                take = mask & mine[sl] & ~occ[sl]
                ids[sl][take] = other.id
                occ[sl] |= take
        return GridMap(gm.grid, occ, ids, self.world, gm.source, dict(gm.meta))

    def _incremental_sync(self, target: GridMap) -> Any:
        """The IncrementalBrushfire of ``target``: the one kept, updated by the cells where its map and
        ``target`` differ (occupancy or id), or a new one (the first time, another grid, or a change
        of more than :attr:`INCREMENTAL_MAX_FRACTION` of the cells)."""
        from ..distance.incremental import IncrementalBrushfire

        ib = self._incremental
        if ib is not None and self._incremental_for is target:
            return ib
        cur = ib.gridmap if ib is not None else None
        if (cur is None or cur.grid != target.grid or
                (cur.obstacle_id is None) != (target.obstacle_id is None)):
            ib = None
        else:
            freed = cur.occupied & ~target.occupied
            added = target.occupied & ~cur.occupied
            if cur.obstacle_id is not None and target.obstacle_id is not None:
                moved = cur.occupied & target.occupied & (cur.obstacle_id != target.obstacle_id)
            else:
                moved = np.zeros(target.shape, bool)
            n = int(np.count_nonzero(freed)) + int(np.count_nonzero(added)) + int(np.count_nonzero(moved))
            if n > self.INCREMENTAL_MAX_FRACTION * target.occupied.size:
                ib = None
            else:
                out, into = freed | moved, added | moved
                if out.any():
                    ib.update(freed=out)
                if into.any():
                    ids = target.obstacle_id[into] if target.obstacle_id is not None else None
                    ib.update(occupied=into, ids=ids)
        if ib is None:
            ib = IncrementalBrushfire(target, compute_labels=False)
        self._incremental, self._incremental_for = ib, target
        return ib

    def _incremental_dmap(self) -> Any:
        """The incremental distance map of the planning map, when the potential field would compute
        this very one (Khatib model, Euclidean, no saturation; the per-obstacle sum only with world
        obstacle ids, as it then needs no labels); else None (the full brushfire runs)."""
        gm = self.cgridmap
        if self.planner != "potential" or gm is None or self.goal is None:
            return None
        from ..fields.potential import resolve_params

        try:
            p = resolve_params(self.params, unit=gm.grid.resolution)
        except GridfieldError:
            return None
        if p["model"] != "khatib" or p["metric"] != "euclidean" or p["saturate"] is not None or (
                p["repulsion"] != "nearest" and gm.obstacle_id is None):
            return None
        return self._incremental_sync(gm).distance_map

    def _plan_cache(self, target: Any, dmap: Any) -> dict[Any, Any] | None:
        """A :func:`gridfield.planners.plan` cache holding ``dmap``, the brushfire of ``target``
        (:func:`gridfield.following.follower.plan_potential`'s key: map, metric, saturation)."""
        if dmap is None or target is not self.cgridmap:
            return None
        return {("gridmap", target, None): target, ("brushfire", target, "euclidean", None): dmap}
