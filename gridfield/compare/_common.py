"""What the convergence study and the batch comparison share: the target (a vector world, or a
grid map's exact polygons and the map), the block factor of a resolution on a grid map, and the
exact optimum of a query. Part of :mod:`gridfield.compare`."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.errors import GridfieldError, ParameterError
from ..geometry.world import World


def optimum_solver(world: Any, *, cache: dict[Any, Any] | None = None
                   ) -> Callable[[NDArray[np.float64], NDArray[np.float64]], float]:
    """``(start, goal) -> exact optimum length`` (NaN for a bad point) on a World or a GridMap: the
    any-angle graph of the grid for a grid map or a world made from one (gridfield.geometry.gridpoly), kept in
    ``cache`` when given (the plan cache: :func:`gridfield.planners.plan` finds the same graph there),
    else the visibility graph of the world (the one ``plan("visibility")`` uses, cached per world).

    Parameters
    ----------
    world : World or GridMap
        Where the optimum is sought.
    cache : dict, optional
        A plan cache (``gridfield.planners.plan(..., cache=)``) to keep the any-angle graph in.

    Returns
    -------
    callable
        ``solver(start, goal)``: the length of the shortest collision-free path (NaN when a point is
        blocked or no path exists).

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "border": "wall",
    ...                      "obstacles": [{"polygon": [[4, 0], [6, 0], [6, 8], [4, 8]]}]})
    >>> solver = optimum_solver(w)
    >>> round(solver(np.array([2.0, 2.0]), np.array([8.0, 2.0])), 4)  # over the corners (4, 8), (6, 8): 2 sqrt(40) + 2
    14.6491
    """
    from ..core.grid import GridMap
    from ..geometry.gridpoly import source_grid

    if isinstance(world, GridMap):
        gm = world if not isinstance(world.world, World) else None
        world = world.world
    else:
        gm = source_grid(world)
    if gm is not None:
        from ..exact.anyangle import grid_graph

        solver: Any = grid_graph(gm, cache=cache)
    else:
        from ..exact.visibility import cached_visibility_graph

        solver = cached_visibility_graph(world, "block")

    def optimum(s: NDArray[np.float64], g: NDArray[np.float64]) -> float:
        try:
            return float(solver.shortest_path(s, g)[1])
        except GridfieldError:
            return math.nan

    return optimum


def _optimum(world: World, start: NDArray[np.float64], goal: NDArray[np.float64]) -> float:
    return optimum_solver(world)(start, goal)


def _as_world(target: Any, what: str) -> tuple[World, Any]:
    """A vector world as is, or a grid map's exact polygons (gridfield.geometry.gridpoly) and the map."""
    from ..core.grid import GridMap

    if isinstance(target, World):
        return target, None
    if isinstance(target, GridMap):
        if isinstance(target.world, World):
            return target.world, None
        from ..geometry.gridpoly import grid_world

        return grid_world(target), target
    raise ParameterError(f"{what} needs a vector World or a GridMap, got {type(target).__name__}")


def _grid_factor(base: Any, h: float) -> int:
    """The integer block factor of resolution ``h`` on a grid map (``k`` cells per cell; ``-m`` for
    ``h`` = the map's resolution / ``m``, a subdivision), or ParameterError."""
    res = base.grid.resolution
    k = int(round(h / res))
    if k >= 1 and abs(k * res - h) <= 1e-9 * h:
        return k
    m = int(round(res / h))
    if m >= 2 and abs(res / m - h) <= 1e-9 * h:
        return -m
    raise ParameterError(f"on a grid map the resolutions must be multiples of the map's resolution {res:g} "
                         f"(coarser grids are block-downsampled) or its integer fractions (finer grids "
                         f"subdivide its cells), got {h:g}")


def _guard_seconds(target: Any, exact_planner: str, params: Any, what: str) -> float:
    """Refuse a comparison up front when the summed estimates of its searches exceed the time limit
    (:func:`gridfield.core.limits.check_stages`): on a grid map the exact planner's stages on its polygons
    and the any-angle optimum; on a vector world the exact potential's descent and the visibility
    graph of the optimum. The grid planners' cost is their cells (the size guard) and is not summed."""
    from ..core.grid import GridMap
    from ..core.limits import check_stages
    from ..core.params import MAX_ITERATIONS
    from ..planners import search_stages

    steps = (params or {}).get("max_iterations")
    steps = MAX_ITERATIONS if steps is None else float(steps)
    if isinstance(target, GridMap) and not isinstance(target.world, World):
        stages = search_stages(exact_planner, target, params)
        if exact_planner != "visibility":
            stages += search_stages("visibility", target, params)  # the optimum (one graph for both)
        return check_stages([(name if name != "any-angle graph" else "any-angle graph (optimum)", work)
                             for name, work in stages], what)
    world = target.world if isinstance(target, GridMap) else target
    if not isinstance(world, World):
        return 0.0
    from ..geometry.gridpoly import source_grid

    vertices = float(sum(len(ob.vertices) for ob in world.obstacles))
    stages = []
    if exact_planner == "exact-potential":
        stages.append(("exact potential", {"obstacle vertex": vertices, "follower step": steps}))
    if source_grid(world) is None:
        stages.append(("visibility graph (optimum)", {"vertex pair": vertices * vertices}))
    return check_stages(stages, what)
