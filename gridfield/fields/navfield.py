"""Complete potential models: numerical navigation functions for the ``potential`` planner.

The classic field (:mod:`gridfield.fields.potential`, ``model="khatib"``) has local minima in every
concavity. The models here are the numerical potential fields of Barraquand, Langlois & Latombe
("Numerical potential field techniques for robot path planning", IEEE Trans. SMC 22(2), 1992;
Latombe, *Robot Motion Planning*, 1991, ch. 7): on every free component they have exactly one
minimum, the goal, so the follower (:mod:`gridfield.follow`, unchanged) reaches every reachable
goal. Each gives the usual :class:`~gridfield.fields.potential.Field` (``U``, ``dU/dx``, ``dU/dy``
computed once).

``model="nf1"``
    ``U`` is the obstacle-aware distance to the goal over the free cells. ``attraction="eikonal"``
    (default): the first-order fast marching solution of ``|grad U| = 1`` on the 4- and the
    diagonal 8-neighbour stencils (:mod:`gridfield.fields._eikonal`), so that the gradient paths run
    at any angle; ``attraction="octile"``: the octile wavefront of ``wavefront-octile`` (the same
    values, except that a disc robot's diagonals through a corner, :attr:`GridMap.diagonals
    <gridfield.core.grid.GridMap.diagonals>`, are not taken: the follower moves continuously, and such a
    passage has no width for it; the march does not cross one either). Latombe's NF1 is the L1 wavefront; the Euclidean version is the one a gradient
    follower needs (no staircase). With ``attraction="eikonal"`` the front is slowed near
    obstacles by the **clearance band** (the potential planner's default, issue 25): slowness
    ``1 + band_gain * (1 - D / clearance_band)**2`` for ``D < clearance_band`` (``D`` the brushfire
    distance; :func:`band_cost`; registry defaults 6 cells and 0.5). The slowness is bounded (at
    most ``1 + band_gain``, at a wall), so the path keeps off the walls by up to ``clearance_band``
    where that is cheap, runs along the middle of a passage narrower than ``2 clearance_band``
    (where the slowness is least), and still passes a one-cell door. The potential planner then pulls
    the descended path taut (:mod:`gridfield.following.taut`, issue 46: string pulling of its own
    vertices) without bringing it closer to an obstacle than ``min(clearance_band, the clearance the
    descended path had nearby)``, so the band's clearance is kept and its detours are not: on the test
    maps (tests/data/maps) the band costs about 1.5 % of length (median, Moving AI: 1.024 of the
    any-angle optimum against 1.008 without it) for 3.6 cells of minimum clearance instead of 1.0
    (median, ROS; benchmarks/README.md). ``clearance_band=0`` (or ``band_gain=0``) is the plain
    distance, the shortest way, grazing the corners.
``model="nf2"``
    Latombe's NF2: the skeleton of the free space (the brushfire's GVD, plus the medial axis inside
    one obstacle's concavities, see :func:`skeleton`), the goal joined to it by steepest ascent of
    the clearance, and a wavefront from the goal that runs along the skeleton at speed 1 and
    elsewhere at speed ``1 / NF2_OFF_SKELETON_COST`` (3), so that from every other cell the
    descent first climbs onto the skeleton and then follows it. Latombe propagates along the
    skeleton only and then down from it; the slow front off the skeleton is what bridges the gaps a
    grid skeleton has (one-cell doors) without a second minimum. Paths keep the largest clearance
    the map allows, at the price of length.
``model="nf-blend"``
    The eikonal distance with the brushfire repulsion as a traversal cost: the front moves at speed
    ``1 / (1 + clearance_gain * (q_star / D - 1)**2)`` within ``q_star`` of an obstacle (``D`` the
    brushfire distance), speed 1 beyond (as Nav2's NavFn plans on an inflated costmap). It keeps off
    the walls like the Khatib field, and it has no spurious minimum *by construction*: ``U`` is
    a travel time from the goal, so every cell but the goal has a lower neighbour, whatever
    ``q_star`` and ``clearance_gain`` are (no condition on the passage width). The price is
    length: the path trades up to ``clearance_gain`` times the extra cost for clearance.

Why one minimum (what :func:`gridfield.following.basins.basins` checks): the march accepts cells by
increasing value and gives every cell a value strictly above its smallest accepted 4-neighbour (the
upwind update ``u >= min(a, b) + ...``), and the skeleton values of NF2 are a shortest-path tree
(each cell above its parent). So discrete steepest descent from every reached cell ends at the goal.

``border`` is honoured as the wavefronts do: with ``"open"`` the fronts run on the map inside a
one-cell free ring (:func:`gridfield.following.escapes.navigation_map`'s rule), and the field lives on that
ringed map (:func:`work_maps`; ``Field.map`` is then two cells wider and taller than the given
map), so that the follower can pass round the grid where the shortest way does; with ``"wall"``
the fronts stop at the grid's edge and the field lives on the map itself. Cells the front never reaches (other free
components) hold ``inf``; obstacle cells ``inf`` and zero gradients.

A planned query (``stop_at``, the start) settles only what the follower reads: the march is
ordered by ``U + w h`` (:data:`ASTAR_WEIGHT` ``w``, ``h`` the Euclidean distance in cells to the
start, scaled by the smallest slowness; NavFn's A* mode does the same with ``w = 1``) and stops once
every cell of key up to ``U(start) +`` :data:`STOP_MARGIN_CELLS` is settled. With ``w <= 1`` the
heuristic is admissible and that holds a band round the shortest way (along it ``U + w h <=
U(start)``); the default ``w = 1.25`` is weighted A* (Pohl 1970): the front races ahead towards the
start instead of settling that band (3 x fewer cells on the 512 x 512 Moving AI room and random maps
than ``w = 1``, and 5 x fewer than the plain order), at the price of the guarantee that the settled
cells hold the shortest way (weighted A*'s bound: a way at most ``w`` times longer). Measured on the
634 queries of ``benchmarks/potential_real.py`` the descended paths' lengths (before the taut
post-pass) are those of ``w = 1`` (Moving AI median / p95 1.035 / 1.106 of the any-angle optimum, ROS
1.010 / 1.035; ``benchmarks/README.md``, stop 38). The A*
order is not causal for the stencils either: a two-neighbour update's second neighbour may be
accepted after the cell (for ``w <= 1/sqrt 2`` the smaller one never is, as ``u - a >= spacing /
sqrt 2``), which gives the cell a one-sided, higher value; so the truncated values exceed the full
march's off the way to the start (by up to a few cells on 512 x 512 maps; along a straight way they
agree). Each settled cell still lies strictly above an accepted neighbour, whatever ``w``, so the
field keeps one minimum among its settled cells and the follower's path stays on them
(``tests/test_nf_astar.py``; lengths within 2 % and half a cell of the whole field's). The kernel
can re-accept a lowered cell (label correcting, ``reopen``), which restores the values but may cost
more than the plain-order march (:data:`ASTAR_REOPEN_CELLS`): it is off. The whole-map fields (plots,
``gridfield field``, basins) march in plain order.

The gradient arrays are upwind differences (the rule of :func:`gridfield.fields.navigation.upwind_gradient`,
compiled): along each axis the difference towards the lower neighbour, the direction the front
came from (for a planned query computed by the march itself over its settled cells, zero elsewhere;
a diagonal's side cells need only be free, the march's rule, since a free side cell on the rim may be
unsettled).

The planned queries of one map (a planner's ``cache`` keeps its brushfire) share what does not
depend on the goal: the compiled march's copies of the free mask and the clearance band's slowness
and its work arrays (only the cells a march touched are reset after it), and the arrays of an
earlier query's field that nothing refers to any more are written again instead of new ones
(:class:`_MarchSetup`; one per slowness, the band's and the plain distance's, up to
:data:`KEPT_SETUPS` kept); the values are the same bits as a fresh march's.

Examples
--------
>>> from gridfield.core.grid import Grid, GridMap
>>> occ = np.zeros((10, 10), bool); occ[4:6, 0:7] = True
>>> gm = GridMap(Grid((10, 10), 1.0, border="wall"), occ)
>>> f = nav_field(gm, (2.5, 8.5), {"model": "nf1", "clearance_band": 0})   # the plain distance
>>> bool(np.isinf(f.potential[occ]).all()), round(float(f.potential[1, 2]), 2)
(True, 14.19)
>>> round(float(nav_field(gm, (2.5, 8.5), {"model": "nf1"}).potential[1, 2]), 2)   # with the clearance band
17.67
"""

from __future__ import annotations

import math
import sys
import threading
import weakref
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import ParameterError
from ..core.grid import GridMap
from ..distance.brushfire import DistanceMap, brushfire
from ._nfmodels import NF2_OFF_SKELETON_COST, band_cost, blend_cost, nf2_cost, nf_skeleton, skeleton, work_maps

# the skeleton's constants and NF2's valley: not used here, importable from here as before the split
from ._nfmodels import NF2_VALLEY_CELLS as NF2_VALLEY_CELLS
from ._nfmodels import SKELETON_MIN_CLEARANCE as SKELETON_MIN_CLEARANCE
from ._nfmodels import SKELETON_SPREAD2 as SKELETON_SPREAD2

__all__ = ["NF_MODELS", "band_cost", "blend_cost", "eikonal", "nav_field", "nf2_cost", "nf_potential", "nf_skeleton", "skeleton",
           "work_maps"]

#: The complete models (values of the ``model`` parameter built here).
NF_MODELS: tuple[str, ...] = ("nf1", "nf2", "nf-blend")
#: The follower's progress window for these models: off (0). The distance to the goal may grow for
#: a long way along a detour (a maze), which the no-progress rule would take for a stall; a field
#: with one minimum cannot trap the follower, and the step budget still bounds it.
NF_PROGRESS_WINDOW = 0
#: The follower's sampling for ``nf-blend`` unless given: ``nearest`` (the cell's own upwind
#: gradient). The blend's slowness is steep next to walls (up to ``1 + 9 clearance_gain`` with the
#: default ``q_star`` of 4 cells), and the bilinear blend of a one-cell door's steep side cells
#: turns the follower's one-cell steps across the door instead of through it.
NF_BLEND_SAMPLING = "nearest"
#: Cells beyond the start's value the march settles when it is told where the start is (a planned
#: query): the follower's bilinear samples around the path read cells up to ~sqrt 2 cells higher.
STOP_MARGIN_CELLS = 4.0
#: Width (cells) of the buckets of the march's priority queue: values agree with an exact
#: (binary-heap) march to about this (``tests/test_nf.py``).
BUCKET_CELLS = 0.125
#: Weight ``w`` of the A*-ordered truncated march of a planned query (``stop_at``): the front is
#: ordered by ``U + w * h``, ``h`` the Euclidean distance (cells) to the start times the smallest
#: slowness, and stops once every cell of key up to ``U(start) + STOP_MARGIN_CELLS`` is settled.
#: ``w <= 1`` keeps the heuristic admissible (the shortest way is settled); above 1 it is weighted A*
#: (the way found at most ``w`` times longer; measured: as long as with 1, see the module text), the
#: default 1.25 (0.7 before, which settles 1.5-2 x the cells of 1; 1 settles about 3 x the cells of 1.25); 0 is
#: the plain (Dijkstra-ordered) march.
ASTAR_WEIGHT = 1.25
#: The truncated march re-accepts a settled cell whose value drops by more than this (cells):
#: never (inf). A finite tolerance (1e-6) gives the full march's values (within 0.13 cell) but,
#: measured on three 512 x 512 Moving AI maps, costs 0.7-7 x the plain-order truncated march
#: (7 x on maze512-32-9: cascades of small drops).
ASTAR_REOPEN_CELLS = math.inf
#: The largest slowness the march takes: its bucket queue has ``~11 * slowness`` buckets (27 MB of
#: bucket heads at 1e5), and ``nf-blend`` with a huge ``clearance_gain`` (1e15) crashed the process.
MAX_SLOWNESS = 1e5
SQRT2 = math.sqrt(2.0)


def _kernels() -> Any:
    """The compiled kernel module (gridfield/fields/_eikonal.pyx), imported on first use."""
    from . import _eikonal  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _eikonal


def _ring(gridmap: GridMap) -> tuple[NDArray[np.bool_], int]:
    """The free mask the fronts run on and the offset of the grid in it (1 with an open border)."""
    free = ~np.asarray(gridmap.occupied, dtype=bool)
    if gridmap.grid.border == "wall":
        return free, 0
    return np.pad(free, 1, constant_values=True), 1


def _sources(gridmap: GridMap, free: NDArray[np.bool_], off: int, goals: ArrayLike
             ) -> tuple[tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]], list[tuple[int, int]]]:
    """The fixed sources of every goal (:func:`_goal_sources`, checked to lie in free cells) and the
    goal cells, in the coordinates of the (possibly ringed) mask ``free``."""
    grid = gridmap.grid
    res = grid.resolution
    pts = np.asarray(goals, dtype=float)
    pts = pts.reshape(1, 2) if pts.shape == (2,) else pts
    rr, cc, vv, cells = [], [], [], []
    for p in pts:
        g = gridmap.check_point("goal", p)
        cell = grid.cell_of(g[0], g[1])
        assert cell is not None
        cx, cy = grid.origin[0] + (cell[1] + 0.5) * res, grid.origin[1] + (cell[0] + 0.5) * res
        r, c, v = _goal_sources(free, (cell[0] + off, cell[1] + off), ((g[0] - cx) / res, (g[1] - cy) / res))
        rr.append(r)
        cc.append(c)
        vv.append(v)
        cells.append((cell[0] + off, cell[1] + off))
    return (np.concatenate(rr), np.concatenate(cc), np.concatenate(vv)), cells


def _goal_sources(free: NDArray[np.bool_], cell: tuple[int, int], offset: tuple[float, float]
                  ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """The goal cell and its free 8-neighbours (no corner cutting) at their exact Euclidean
    distance (cells) from the goal point; ``offset``: the goal's position in its cell, in cells,
    from the cell centre."""
    r0, c0 = cell
    rows, cols = free.shape
    rr, cc, vv = [r0], [c0], [math.hypot(offset[0], offset[1])]
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            r, c = r0 + dr, c0 + dc
            if (dr, dc) == (0, 0) or not (0 <= r < rows and 0 <= c < cols) or not free[r, c]:
                continue
            if dr and dc and not (free[r0 + dr, c0] and free[r0, c0 + dc]):
                continue
            rr.append(r)
            cc.append(c)
            vv.append(math.hypot(dc - offset[0], dr - offset[1]))
    return np.array(rr, np.int64), np.array(cc, np.int64), np.array(vv)


def eikonal(gridmap: GridMap, goal: ArrayLike, *, cost: NDArray[np.float64] | None = None,
            stop_at: ArrayLike | None = None, margin: float = STOP_MARGIN_CELLS) -> NDArray[np.float64]:
    """The obstacle-aware Euclidean distance (or travel time) to ``goal`` over the free cells, by
    fast marching (first-order upwind on the 4- and 8-neighbour stencils), in world units.

    Parameters
    ----------
    gridmap : GridMap
        Its ``border`` is honoured (open: the front may pass round the grid through a one-cell ring).
    goal : (x, y), or an array of shape (k, 2)
        In a free cell; several goals (one per free component, say) start the front together.
    cost : ndarray, optional
        Slowness per cell (``1 / speed``, finite and >= 1 on free cells); default 1 everywhere.
    stop_at : (x, y), optional
        Settle only the cells up to this point's value plus ``margin`` cells (``inf`` beyond).
    margin : float
        See ``stop_at``.

    Returns
    -------
    ndarray of float64, the grid's shape
        ``inf`` on obstacles and cells the front does not reach.

    Examples
    --------
    On an empty grid the values are close to the straight-line distance:

    >>> from gridfield.core.grid import Grid
    >>> t = eikonal(GridMap(Grid((40, 40), 1.0), np.zeros((40, 40), bool)), (0.5, 0.5))
    >>> round(float(t[30, 40 - 1]) / math.hypot(30, 39), 3)
    1.006
    """
    return _eikonal(gridmap, goal, cost, stop_at, margin)[0]


def _eikonal(gridmap: GridMap, goal: ArrayLike, cost: NDArray[np.float64] | None, stop_at: ArrayLike | None,
             margin: float, gradient: bool = False, owner: DistanceMap | None = None
             ) -> tuple[NDArray[np.float64], tuple[NDArray[np.float64], NDArray[np.float64]] | None]:
    """:func:`eikonal`, and with ``gradient`` (and a ``wall`` border) the upwind gradient arrays of
    its values computed by the march itself (:func:`_march`; ``None`` otherwise). ``owner``: the
    distance map the march setup is kept with (:func:`_march_setup`)."""
    grid = gridmap.grid
    free, off = _ring(gridmap)
    res = grid.resolution
    src, _ = _sources(gridmap, free, off, goal)
    sr = sc = -1
    if stop_at is not None:
        s = grid.cell_of(*_xy(stop_at))
        if s is not None:
            sr, sc = s[0] + off, s[1] + off
    setup = _march_setup(free, cost, off, owner)
    if off:
        t, _ = _march(setup, src, sr, sc, margin)
        t = t[1:-1, 1:-1]
        t *= res
        return np.ascontiguousarray(t), None
    return _march(setup, src, sr, sc, margin, scale=res, gradient=gradient)


class _MarchSetup:
    """The goal-independent part of a march on one map: the free mask, the largest and smallest
    slowness and the compiled :class:`~gridfield.fields._eikonal.Marcher` (its copies of the mask
    and slowness, its work arrays), which a lock keeps to one march at a time.

    Parameters
    ----------
    free : ndarray of bool
        The mask the front runs on (ringed by ``off`` cells).
    source : ndarray of float64 or None
        The slowness of the map inside the ring (``inf`` on obstacles); ``None``: 1 everywhere.
    off : int
        The ring's width (0 or 1).
    """

    __slots__ = ("free", "lo", "lock", "marcher", "off", "pool", "source", "top")

    def __init__(self, free: NDArray[np.bool_], source: NDArray[np.float64] | None, off: int) -> None:
        self.free, self.source, self.off = free, source, off  # the slowness given, to recognise it
        cost = self.cost()
        top = float(cost[~np.isnan(cost)].max()) if cost.size else 1.0
        if top > MAX_SLOWNESS:
            raise ParameterError(f"the field's slowness reaches {top:.3g}, above the march's limit {MAX_SLOWNESS:g} "
                                 "(nf-blend: lower clearance_gain or q_star)")
        self.top = top
        self.lo = float(cost[~np.isnan(cost)].min()) if cost.size else 1.0
        self.marcher = _kernels().Marcher(free.view(np.uint8), cost)
        self.lock = threading.Lock()
        self.pool: list[tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]] = []

    def cost(self) -> NDArray[np.float64]:
        """The slowness the march reads: ``inf`` made 1, ringed by ``off`` cells of 1 (empty: 1 everywhere)."""
        if self.source is None:
            return np.empty((0, 0))
        cst = np.where(np.isfinite(self.source), self.source, 1.0)
        if self.off:
            cst = np.pad(cst, self.off, constant_values=1.0)
        return np.ascontiguousarray(cst, dtype=np.float64)

    def run(self, *args: Any, gradient: bool = False) -> tuple[Any, ...]:
        """:meth:`Marcher.run` on this setup's marcher, or on a fresh one while it is busy (threads).
        A gradient march writes into a recycled output triple (:meth:`_outputs`) when one is free."""
        if self.lock.acquire(blocking=False):
            try:
                into = self._outputs() if gradient else (None, None, None)
                return self.marcher.run(*args, gradient, *into)  # type: ignore[no-any-return]
            finally:
                self.lock.release()
        return _kernels().Marcher(self.free.view(np.uint8), self.cost()).run(*args, gradient)  # type: ignore[no-any-return]

    def _outputs(self) -> tuple[NDArray[np.float64], ...] | tuple[None, None, None]:
        """Arrays for a planned march's ``U``, ``gx``, ``gy`` that nothing but this pool refers to
        any more (the field of an earlier query that the planner dropped: no array, view or buffer
        of them is alive), or new ones kept in the pool (at most :data:`OUTPUT_POOL`); ``None``
        when the interpreter's reference counts cannot tell (not CPython, or free-threaded).
        Writing into memory already mapped saves the page faults of fresh map-sized arrays
        (about 1 ms per 2 MB array on the 2-core test machine)."""
        if not _REFCOUNTS:
            return None, None, None
        for trio in self.pool:
            if _unused(trio):
                return trio
        if len(self.pool) >= OUTPUT_POOL:
            return None, None, None
        shape = (self.free.shape[0], self.free.shape[1])
        trio = (np.empty(shape), np.empty(shape), np.empty(shape))
        self.pool.append(trio)
        return trio


#: Output triples (``U``, ``gx``, ``gy``) a march setup keeps for recycling (:meth:`_MarchSetup._outputs`).
OUTPUT_POOL = 2
#: Whether ``sys.getrefcount`` tells when an array is no longer used (CPython with its GIL).
_REFCOUNTS = sys.implementation.name == "cpython" and getattr(sys, "_is_gil_enabled", lambda: True)()


def _unused(trio: tuple[NDArray[np.float64], ...]) -> bool:
    """Whether the arrays of ``trio`` have no reference but the pool's tuple (the counts below are
    the tuple's, the loop variable's and ``getrefcount``'s argument's): no Field, view or buffer
    export of them is alive."""
    return all(sys.getrefcount(a) == 3 for a in trio)


#: The reusable march setups (:func:`_march_setup`) kept, the most recent first, each with a weak
#: reference to the distance map it serves: the planned queries of one map march on the same free mask
#: and slowness, so the map-sized copies, allocations and initialisations happen once per map and
#: slowness instead of once per query (about 5 ms on a 512 x 512 map). Up to :data:`KEPT_SETUPS` are
#: kept, so that queries alternating between the default's clearance band and the plain distance (a
#: comparison of models on one map) do not rebuild them in turn. Each holds about 30 bytes per cell (the
#: marcher's arrays) and up to :data:`OUTPUT_POOL` output triples (24 bytes per cell each) until its
#: distance map dies (a planner's ``cache`` dropped) or newer setups push it out.
_setups: list[tuple[Any, _MarchSetup]] = []
#: How many reusable march setups are kept (:data:`_setups`).
KEPT_SETUPS = 3


def _kept(entries: list[Any], match: Any) -> Any:
    """The first entry of a most-recent-first list (:data:`_setups`, :data:`_bands`) that ``match``
    accepts, moved to the front; ``None`` when there is none."""
    for i, e in enumerate(entries):
        if match(e):
            entries.insert(0, entries.pop(i))
            return e
    return None


def _keep(entries: list[Any], entry: Any) -> None:
    """Put ``entry`` at the front of a most-recent-first list, keeping the last :data:`KEPT_SETUPS`."""
    entries.insert(0, entry)
    del entries[KEPT_SETUPS:]


def _forget_setup(ref: Any) -> None:
    """Drop the kept march setups (and the band's slowness) whose map's distance map ``ref`` died."""
    _setups[:] = [e for e in _setups if e[0] is not ref]
    _bands[:] = [e for e in _bands if e[0] is not ref]


def _march_setup(free: NDArray[np.bool_], cost: NDArray[np.float64] | None, off: int,
                 owner: DistanceMap | None = None) -> _MarchSetup:
    """The :class:`_MarchSetup` of the mask ``free`` (ringed by ``off`` cells) and the slowness
    ``cost`` (of the map inside the ring; ``None``: 1 everywhere). With ``owner`` (the distance map
    of the queries' map, which a planner's ``cache`` keeps), it is kept while ``owner`` lives and
    reused when ``cost`` is ``None`` or the clearance band's kept slowness (:func:`_band_cost_of`:
    read-only, so it cannot change) and the mask is a kept one's; built fresh otherwise."""
    reusable = owner is not None and (cost is None or any(cost is b[3] for b in _bands))
    if reusable:
        hit = _kept(_setups, lambda e: (e[0]() is owner and e[1].source is cost and e[1].free.shape == free.shape
                                        and np.array_equal(e[1].free, free)))
        if hit is not None:
            return hit[1]
    setup = _MarchSetup(np.ascontiguousarray(free, dtype=bool), cost, off)
    if reusable:
        _keep(_setups, (weakref.ref(owner, _forget_setup), setup))
    return setup


def _march(setup: _MarchSetup, src: tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]], sr: int,
           sc: int, margin: float, *, scale: float = 1.0, gradient: bool = False
           ) -> tuple[NDArray[np.float64], tuple[NDArray[np.float64], NDArray[np.float64]] | None]:
    """The compiled march (bucket queue of width :data:`BUCKET_CELLS`) from the sources, sorted here;
    with a stop cell, A*-ordered (:data:`ASTAR_WEIGHT`). Returns the values times ``scale`` and, with
    ``gradient``, their upwind gradient (:func:`nav_field`'s rule for a planned query, divided by
    ``scale``), else ``None``."""
    order = np.argsort(src[2], kind="stable")
    r, c, v = (np.ascontiguousarray(a[order]) for a in src)
    # the heuristic must not exceed the cheapest travel time per cell (slowness >= lo everywhere)
    hw = ASTAR_WEIGHT * min(setup.lo, 1.0) if sr >= 0 else 0.0
    out = setup.run(r, c, v, True, sr, sc, float(margin), BUCKET_CELLS, max(setup.top, 1.0), hw, ASTAR_REOPEN_CELLS,
                    scale, gradient=gradient)
    return out[0], ((out[3], out[4]) if gradient else None)


def _xy(p: ArrayLike) -> tuple[float, float]:
    a = np.asarray(p, dtype=float).reshape(-1)
    return float(a[0]), float(a[1])


def _nf2_values(gridmap: GridMap, goals: ArrayLike, dmap: DistanceMap, sk: NDArray[np.bool_],
                stop_at: ArrayLike | None, cost_map: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """NF2's U (world units): the travel time from the goal(s) at speed 1 along the skeleton and
    each goal's steepest ascent of the clearance onto it, and slower off it (:func:`nf2_cost`)."""
    k = _kernels()
    grid = gridmap.grid
    free, off = _ring(gridmap)
    skel = np.pad(sk, off, constant_values=False) if off else sk
    dist = np.where(np.isfinite(dmap.distance), dmap.distance, 0.0)
    if off:
        dist = np.pad(dist, 1, constant_values=0.0)
    cost = nf2_cost(sk) if cost_map is None else cost_map
    cost = np.pad(cost, 1, constant_values=NF2_OFF_SKELETON_COST) if off else cost.copy()
    src, cells = _sources(gridmap, free, off, goals)
    for r0, c0 in cells:
        climb = k.ascend(dist, free.view(np.uint8), skel.view(np.uint8), r0, c0)
        cost[climb[:, 0], climb[:, 1]] = 1.0
    src = (src[0], src[1], src[2] * cost[src[0], src[1]])
    res = grid.resolution
    sr = sc = -1
    if stop_at is not None:
        s = grid.cell_of(*_xy(stop_at))
        if s is not None:
            sr, sc = s[0] + off, s[1] + off
    u, _ = _march(_MarchSetup(free, cost, 0), src, sr, sc, STOP_MARGIN_CELLS * NF2_OFF_SKELETON_COST)
    if off:
        u = u[1:-1, 1:-1]
    return np.ascontiguousarray(u * res)


#: The last clearance bands' slownesses and what each was computed from (a weak reference to the
#: distance map, band, gain), the most recent first: the queries of one map (a planner's ``cache`` holds
#: its brushfire) reuse it instead of recomputing a map-sized array per query (~60 ms on a 1.7 M-cell
#: map); dropped when that distance map dies (:func:`_forget_setup`).
_bands: list[tuple[Any, float, float, NDArray[np.float64]]] = []


def _band_cost_of(dmap: DistanceMap, band: float, gain: float) -> NDArray[np.float64]:
    """:func:`band_cost`, reused (read-only) while the same distance map, band and gain come back (the
    last :data:`KEPT_SETUPS` kept, so that a field built on another map between two queries does not
    push out the slowness the kept march setup of the queries' map was made with)."""
    hit = _kept(_bands, lambda e: e[0]() is dmap and e[1] == band and e[2] == gain)
    if hit is not None:
        return hit[3]
    cost = band_cost(dmap, band, gain)
    cost.setflags(write=False)
    _keep(_bands, (weakref.ref(dmap, _forget_setup), band, gain, cost))
    return cost


def nf_potential(gridmap: GridMap, goals: ArrayLike, params: Mapping[str, Any] | None = None, *,
                 dmap: DistanceMap | None = None,
                 skel: tuple[NDArray[np.bool_], NDArray[np.float64]] | None = None,
                 stop_at: ArrayLike | None = None) -> tuple[NDArray[np.float64], dict[str, Any], GridMap, DistanceMap]:
    """The potential array of a complete model, from one goal or several (one per free component:
    the components' fields in one array, as :func:`gridfield.following.basins.basins` checks them).

    Parameters
    ----------
    gridmap : GridMap
    goals : (x, y) or array of shape (k, 2)
        In free cells (several: the fronts start together; ``attraction='octile'`` takes one).
    params : mapping, optional
        As for :func:`nav_field` (``model`` defaults to ``"nf1"`` here).
    dmap, skel, stop_at
        As for :func:`nav_field`.

    Returns
    -------
    U : ndarray of float64
        On the first map of :func:`work_maps`.
    params : dict
        Resolved.
    work : GridMap
        The map ``U`` lives on (:func:`work_maps`).
    dmap : DistanceMap
        The brushfire used (of the second map of :func:`work_maps`).

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> occ = np.zeros((1, 5), bool); occ[0, 2] = True
    >>> U, p, work, _ = nf_potential(GridMap(Grid((1, 5), 1.0, border="wall"), occ), [(0.5, 0.5), (4.5, 0.5)])
    >>> U.tolist(), p["model"]
    ([[0.0, 1.0, inf, 1.0, 0.0]], 'nf1')
    """
    U, p, work, dmap, _ = _nf_values(gridmap, goals, params, dmap, skel, stop_at)
    return U, p, work, dmap


def _nf_values(gridmap: GridMap, goals: ArrayLike, params: Mapping[str, Any] | None, dmap: DistanceMap | None,
               skel: tuple[NDArray[np.bool_], NDArray[np.float64]] | None, stop_at: ArrayLike | None,
               gradient: bool = False
               ) -> tuple[NDArray[np.float64], dict[str, Any], GridMap, DistanceMap,
                          tuple[NDArray[np.float64], NDArray[np.float64]] | None]:
    """:func:`nf_potential`, and with ``gradient`` the gradient arrays of a planned query's eikonal
    march (:func:`_eikonal`) when the march made them (``None`` otherwise: NF2, octile)."""
    from ..core.params import resolve_field

    grad = None
    p = resolve_field({"model": "nf1", **dict(params or {})}, unit=gridmap.grid.resolution)
    model = p["model"]
    if model not in NF_MODELS:
        raise ParameterError(f"nav_field builds the models {NF_MODELS}, got model={model!r}")
    g = np.asarray(goals, dtype=float)
    work, around = work_maps(gridmap)
    if dmap is not None and (dmap.metric != "euclidean" or dmap.grid.shape != work.grid.shape):
        raise ParameterError(f"the {model} model needs a Euclidean brushfire of work_maps(gridmap)[1] (shape "
                             f"{work.grid.shape}), got metric {dmap.metric!r}, shape {dmap.grid.shape}")
    if model == "nf2":
        if dmap is None or dmap.gvd is None:
            dmap, sk, cost = nf_skeleton(around)
        elif skel is None:
            sk = skeleton(dmap)
            cost = nf2_cost(sk)
        else:
            sk, cost = skel
        U = _nf2_values(work, g, dmap, sk, stop_at, cost)
    else:
        if dmap is None:
            dmap = brushfire(around, metric="euclidean", compute_labels=False, compute_gvd=False)
        want = gradient and stop_at is not None
        if model == "nf-blend":
            U, grad = _eikonal(work, g, blend_cost(dmap, p["q_star"], p["clearance_gain"]), stop_at,
                               STOP_MARGIN_CELLS, want)
        elif p["attraction"] == "octile":
            from .navigation import wavefront

            if np.asarray(g, dtype=float).size != 2:
                raise ParameterError("attraction='octile' (the octile wavefront) takes one goal")
            # the Moving AI rule alone: a follower moves continuously, and a diagonal through a corner of a
            # disc robot's C-space (GridMap.diagonals, a discrete step) has no width for it
            plain = work if work.diagonals is None else work.with_occupied(work.occupied, diagonals=None)
            U = np.ascontiguousarray(wavefront(plain, g, costs="octile").value)
        elif p["clearance_band"] > 0 and p["band_gain"] > 0:
            U, grad = _eikonal(work, g, _band_cost_of(dmap, p["clearance_band"], p["band_gain"]), stop_at,
                               STOP_MARGIN_CELLS, want, dmap)
        else:
            U, grad = _eikonal(work, g, None, stop_at, STOP_MARGIN_CELLS, want, dmap)
    return U, p, work, dmap, grad


def nav_field(gridmap: GridMap, goal: ArrayLike, params: Mapping[str, Any] | None = None, *,
              dmap: DistanceMap | None = None,
              skel: tuple[NDArray[np.bool_], NDArray[np.float64]] | None = None,
              stop_at: ArrayLike | None = None) -> Any:
    """The :class:`~gridfield.fields.potential.Field` of a complete model (``model`` one of :data:`NF_MODELS`).

    Parameters
    ----------
    gridmap : GridMap
    goal : (x, y)
        In a free cell.
    params : mapping, optional
        Resolved or raw parameters (:func:`gridfield.fields.potential.resolve_params`); read: ``model``,
        ``attraction``, ``clearance_band`` and ``band_gain`` (nf1), ``q_star`` and ``clearance_gain`` (nf-blend).
    dmap : DistanceMap, optional
        A Euclidean brushfire of ``gridmap`` to reuse (``Field.distance``; NF2 needs its labels and GVD).
    skel : (ndarray of bool, ndarray of float64), optional
        NF2's :func:`skeleton` of ``dmap`` and its :func:`nf2_cost`, to reuse (see :func:`nf_skeleton`).
    stop_at : (x, y), optional
        The start of a planned query: the fronts settle only the cells up to its value plus
        :data:`STOP_MARGIN_CELLS` cells (``inf`` beyond), which is all the follower reads. Leave it
        out for the whole field (plots, basins).

    Returns
    -------
    Field
        ``params`` resolved, with ``progress_window`` 0 unless given (:data:`NF_PROGRESS_WINDOW`).

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> gm = GridMap(Grid((6, 6), 1.0, border="wall"), np.zeros((6, 6), bool))
    >>> f = nav_field(gm, (0.5, 0.5), {"model": "nf1", "attraction": "octile"})
    >>> round(float(f.potential[5, 5]), 4), f.params["model"], f.params["progress_window"]
    (7.0711, 'nf1', 0)
    """
    if gridmap.grid.ndim == 3:  # a voxel grid: gridfield.fields.navfield3d
        from .navfield3d import nav_field3d

        return nav_field3d(gridmap, goal, params, stop_at=stop_at)
    from ..core.results import Field

    U, p, work, dmap, grad = _nf_values(gridmap, goal, params, dmap, skel, stop_at, gradient=True)
    g = gridmap.check_point("goal", goal)
    goal_xy = (float(g[0]), float(g[1]))
    given = dict(params or {})
    res = gridmap.grid.resolution
    if grad is not None:  # made by the march over its settled cells (the rule below, divided by res)
        gx, gy = grad
    else:
        if stop_at is None:
            gx, gy = _kernels().upwind(U, True)
        else:  # a truncated march: the gradient over the settled cells' bounding box only (zero beyond)
            gx, gy = np.zeros(U.shape), np.zeros(U.shape)
            fin = np.isfinite(U)
            rows, cols = np.flatnonzero(fin.any(axis=1)), np.flatnonzero(fin.any(axis=0))
            if rows.size:
                box = (slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1))
                free = np.ascontiguousarray(~np.asarray(work.occupied, dtype=bool)[box]).view(np.uint8)
                gx[box], gy[box] = _kernels().upwind(np.ascontiguousarray(U[box]), True, free)
        if res != 1.0:
            gx /= res
            gy /= res
    if "progress_window" not in given:
        p["progress_window"] = NF_PROGRESS_WINDOW
    if p["model"] == "nf-blend" and "sampling" not in given:
        p["sampling"] = NF_BLEND_SAMPLING
    return Field(work, U, gx, gy, goal_xy, p, dmap)
