"""The escapes from a local minimum: the moves :func:`gridfield.following.descent.descend` makes when it stalls.

``random_walk`` (:func:`random_jump`) and ``potential_increase`` (:func:`potential_increase`, seed
000's bonus question) see the field only through callables, like ``descend``; ``navigation``
(:class:`NavigationEscape`, its moves taken by :func:`navigation_moves`) follows the grid's
navigation function. How many tries, and when an escape counts as a success, is ``descend``'s
rule (:mod:`gridfield.following.descent`).

The navigation escape
---------------------
``escape="navigation"`` (:func:`gridfield.following.follower.follow`): at a local minimum of the potential the
follower drives down the octile wavefront from the goal (:func:`gridfield.fields.navigation.wavefront`,
the exact shortest-path cost over 8-connected moves that never cut a corner, on the occupancy alone:
a disc robot's diagonals through a corner, :attr:`gridfield.core.grid.GridMap.diagonals`, have no width
for the follower, which the escape hands back to), cell centre by cell
centre, until it enters a cell whose discrete steepest descent on the potential ends in the goal's
sink (the goal's basin of :func:`gridfield.following.basins.basins`: from a cell of another minimum's basin
the potential would lead the follower straight into that minimum); there the potential descent
resumes. A stall inside the goal's basin (one the discrete descent does not see) drives all the
way.

It does not start at the stall point: the follower's jitter before the stall was detected stays
out of the path. :meth:`gridfield.following.descent.Rules.dither_starts` names where the dithering may have
begun (the first point of the stretch the stop rule looked at, the first point of the longest tail
within the confined rule's box) and :func:`navigation_cut` starts the escape from the point of the
current descent (those, the current point, or the one with the least path length plus navigation
value) from which the path so far plus the way on to the goal (:meth:`NavigationEscape.way_length`)
is shortest; the points after it are dropped. At the end of every navigation run the path's loops
are cut (:func:`cut_loops`: a return to within two steps of a point is joined to it by a free
segment). Both only shorten the path (for an escape driven to the goal, never longer than from the
current point), and the classic field without this escape is untouched. Two rules make it complete:

- each escape must start at a lower navigation value than the one before; when it does not (the
  potential led the follower back uphill), the escape drives all the way to the goal;
- the last escape allowed by ``escape_tries`` drives all the way to the goal too.

So when the goal is reachable, the follower reaches it. Every move of the escape is a step between
neighbouring free cell centres, so it never touches an obstacle. On a map with an ``open`` border the
navigation function also runs through a one-cell free ring around the grid (open space, where the
follower may go too).

Examples
--------
>>> import numpy as np
>>> from gridfield.core.grid import Grid, GridMap
>>> from types import SimpleNamespace
>>> occ = np.zeros((5, 5), bool); occ[1:4, 2] = True
>>> gm = GridMap(Grid((5, 5), 1.0, border="wall"), occ)
>>> f = SimpleNamespace(map=gm, potential=np.zeros((5, 5)), goal=(4.5, 2.5))
>>> esc = NavigationEscape(f)
>>> [tuple(q) for q in esc((0.5, 2.5), final=True)]
[(0.5, 1.5), (1.5, 0.5), (2.5, 0.5), (3.5, 0.5), (3.5, 1.5), (4.5, 2.5)]
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.grid import Grid, GridMap
from ..core.results import GradientField

__all__ = ["NavigationEscape", "cut_loops", "navigation_cut", "navigation_finish", "navigation_map", "navigation_moves",
           "potential_increase", "random_jump"]

Point = tuple[float, float]
Blocked = Callable[[Point, Point], bool] | None

#: Rejected random-walk jumps (blocked) before a try counts as failed.
_JUMP_SAMPLES = 100
#: Sub-steps of the potential-increase escape before it gives up.
_ESCAPE_SUBSTEPS = 60
#: Relative margin of the navigation escape's length comparisons (:func:`navigation_cut`,
#: :func:`cut_loops`): lengths within it count as equal, so that a map at another resolution
#: (every length scaled) makes the same choices in spite of rounding.
_TIE = 1e-9
#: The points after each one that the loop cut checks directly (:func:`cut_loops`); farther ones
#: only where a square around the point holds one.
_AHEAD = 8


def random_jump(x: float, y: float, radius: float, rng: np.random.Generator, blocked: Blocked = None) -> list[Point]:
    """The random-walk escape's jump from ``(x, y)``: a length ``r ~ U(0, radius]`` in a uniform direction.

    A blocked jump is drawn again, up to 100 times (two draws from ``rng`` per jump: length, then
    angle).

    Parameters
    ----------
    x, y : float
        The stall point.
    radius : float
        The longest jump (``escape_radius``).
    rng : numpy.random.Generator
    blocked : callable, optional
        ``blocked(p, q) -> bool``; ``None``: nothing blocks.

    Returns
    -------
    list of (float, float)
        The one point jumped to, or ``[]`` when every draw was blocked.

    Examples
    --------
    >>> (q,) = random_jump(0.0, 0.0, 2.0, np.random.default_rng(0))
    >>> 0.0 < math.hypot(*q) <= 2.0
    True
    >>> random_jump(0.0, 0.0, 2.0, np.random.default_rng(0), blocked=lambda p, q: True)
    []
    """
    for _ in range(_JUMP_SAMPLES):
        r = radius * (1.0 - rng.random())
        th = 2.0 * math.pi * rng.random()
        q = (x + r * math.cos(th), y + r * math.sin(th))
        if blocked is None or not blocked((x, y), q):
            return [q]
    return []


def potential_increase(x: float, y: float, force: Callable[[Point], tuple[float, float]],
                       attraction: Callable[[Point], tuple[float, float]], potential: Callable[[Point], float], *,
                       first_step: float, repeat: int = 0, blocked: Blocked = None) -> tuple[list[Point], float]:
    """The Khatib-potential escape ``Path_generator_esc``: climb out of a local minimum along the repulsion.

    From the stall point move along ``F_rep + 0.05 * F_attr`` (``F_rep = F - F_attr``) with a step
    that starts at ``first_step`` and grows by 1.25 per sub-step, until the potential is at least
    ``1.25**(repeat + 1)`` times the minimum's (the seed's 25 %; a repeated escape from the same
    minimum must climb higher, or it would retrace the same jump). At most 60 sub-steps; a blocked
    sub-step fails the escape.

    Parameters
    ----------
    x, y : float
        The stall point.
    force, attraction : callable
        ``(x, y) -> (fx, fy)``: the whole force and its attractive part.
    potential : callable
        ``(x, y) -> U``.
    first_step : float
        The first sub-step's length (``descend``'s step).
    repeat : int
        Escapes tried before from the same minimum.
    blocked : callable, optional

    Returns
    -------
    moves : list of (float, float)
        The sub-steps' points, ``[]`` when the escape failed.
    required : float
        The potential the escape had to reach.

    Examples
    --------
    A repulsion that pushes to +x out of a bowl ``U = x^2`` with no attraction:

    >>> moves, required = potential_increase(0.1, 0.0, lambda p: (1.0, 0.0), lambda p: (0.0, 0.0),
    ...                                      lambda p: p[0] ** 2, first_step=0.1)
    >>> round(required, 4), len(moves), moves[-1][0] ** 2 >= required
    (0.0125, 1, True)
    """
    fx, fy = force((x, y))
    fax, fay = attraction((x, y))
    ux = float(fx) - float(fax) + 0.05 * float(fax)
    uy = float(fy) - float(fay) + 0.05 * float(fay)
    un = math.hypot(ux, uy)
    u0 = float(potential((x, y)))
    bar = 1.25 ** (repeat + 1) * u0
    moves: list[Point] = []
    if un > 0 and math.isfinite(un):
        px, py, eps = x, y, first_step
        for _ in range(_ESCAPE_SUBSTEPS):
            q = (px + eps * ux / un, py + eps * uy / un)
            if blocked is not None and blocked((px, py), q):
                return [], bar
            moves.append(q)
            px, py = q
            eps *= 1.25
            if float(potential(q)) >= bar:
                return moves, bar
        return [], bar
    return moves, bar


def navigation_moves(navigate: Callable[..., list[Point]], x: float, y: float, *, final: bool,
                     blocked: Blocked = None) -> list[Point]:
    """The navigation escape's moves from ``(x, y)``: ``navigate``'s points, up to the first blocked one.

    Parameters
    ----------
    navigate : callable
        ``navigate((x, y), final=bool) -> [points]`` (a :class:`NavigationEscape`).
    x, y : float
        The stall point.
    final : bool
        Drive all the way to the goal (the last try).
    blocked : callable, optional

    Returns
    -------
    list of (float, float)

    Examples
    --------
    >>> navigation_moves(lambda p, final: [(1.0, 0.0), (2.0, 0.0), (3.0, 0.0)], 0.0, 0.0, final=True,
    ...                  blocked=lambda p, q: q[0] > 2.5)
    [(1.0, 0.0), (2.0, 0.0)]
    """
    moves: list[Point] = []
    for q in navigate((x, y), final=final):
        if blocked is not None and blocked(moves[-1] if moves else (x, y), q):
            break  # (never with NavigationEscape: its moves join free cell centres) keep what is free
        moves.append(q)
    return moves


def navigation_cut(navigate: Callable[..., list[Point]], xs: Sequence[float], ys: Sequence[float],
                   candidates: Sequence[int], since: int | None = None) -> int:
    """Where the navigation escape starts: the point of the path ``xs, ys`` from which the path so
    far plus the way on down the navigation function to the goal is shortest.

    The points after it (the follower's jitter before the stall was detected, or the whole descent
    into the minimum's basin when going back is shorter) are cut from the path before the escape.
    Looked at: ``candidates`` (point indices, ascending, the last one the current point: where
    the dithering began, :meth:`gridfield.following.descent.Rules.dither_starts`) and, when ``navigate`` has
    ``values`` (:meth:`NavigationEscape.values`), the point of the stretch from ``since`` (the
    first point of the current descent; default: the first candidate) that minimizes the path
    length to it plus its navigation value. Each is scored with the path length to it plus
    ``navigate.way_length`` (the exact length of the escape driven to the goal); the lowest
    score wins, ties the earliest. So an escape that drives to the goal never makes the path
    longer than one from the current point. A ``navigate`` without ``way_length`` (a plain
    callable) gets the first candidate.

    Parameters
    ----------
    navigate : callable
        A :class:`NavigationEscape`, or any ``navigate(point, final=...)`` callable.
    xs, ys : sequence of float
        The path so far; its last point is the current one.
    candidates : sequence of int
    since : int, optional

    Returns
    -------
    int
        The index of the point to start the escape from.

    Examples
    --------
    The way on is the straight line to (10, 0): the jitter after index 1 is cut, since the way from
    there is shorter than the jitter and the way from its end:

    >>> def navigate(p, final=False):
    ...     return []
    >>> navigate.way_length = lambda p: math.dist(p, (10.0, 0.0))
    >>> navigation_cut(navigate, [0.0, 1.0, 2.0, 1.5, 2.0], [0.0, 0.0, 0.0, 0.5, 0.0], [1, 4])
    1
    """
    lo = int(candidates[0]) if since is None else min(int(since), int(candidates[0]))
    length_of = getattr(navigate, "way_length", None)
    if length_of is None:
        return int(candidates[0])
    px, py = np.asarray(xs[lo:], dtype=float), np.asarray(ys[lo:], dtype=float)
    along = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(px), np.diff(py)))])  # path length from lo
    looked = {int(c) for c in candidates}
    values_of = getattr(navigate, "values", None)
    if values_of is not None:
        est = along + values_of(px, py)
        if np.isfinite(est).any():  # the first within a relative 1e-9 of the least (ties do not depend on the scale)
            looked.add(lo + int(np.argmax(est <= est.min() * (1.0 + _TIE))))
    best, pick = math.inf, int(candidates[0])
    for c in sorted(looked):
        total = float(along[c - lo]) + float(length_of((float(xs[c]), float(ys[c]))))
        if total < best * (1.0 - _TIE):
            best, pick = total, c
    return pick


def _thick_blocked(blocked: Callable[[Point, Point], bool], p: NDArray[np.float64], q: NDArray[np.float64],
                   margin: float) -> bool:
    """Whether the move ``p -> q`` or one of its two copies shifted sideways by ``margin`` is
    blocked: a shortcut that only grazes an obstacle's corner counts as blocked at every
    resolution (whether the exact corner blocks is decided by rounding)."""
    d = q - p
    n = float(np.hypot(d[0], d[1]))
    if blocked((float(p[0]), float(p[1])), (float(q[0]), float(q[1]))):
        return True
    if n == 0.0:
        return False
    ox, oy = -margin * float(d[1]) / n, margin * float(d[0]) / n
    return any(blocked((float(p[0]) + sx * ox, float(p[1]) + sx * oy), (float(q[0]) + sx * ox, float(q[1]) + sx * oy))
               for sx in (1.0, -1.0))


def cut_loops(points: NDArray[np.float64], radius: float, blocked: Blocked = None) -> NDArray[np.intp]:
    """The points of a path to keep so that it never comes back within ``radius`` of a point it left.

    From the start, each kept point is followed by the farthest-on point of the path within
    ``radius`` of it whose straight move from it is free (``blocked``), or else by the next point;
    the points in between (a loop: the follower's jitter or a detour that came back) are dropped.
    A shortcut counts as free only when its two copies shifted sideways by ``1e-6 * radius`` are
    free too (one that grazes an obstacle's corner is not taken, at any resolution).
    The first and the last point are always kept, every new move is a free segment no longer than
    ``radius``, and by the triangle inequality the path never gets longer. Used by the ``navigation``
    escape on every run (:func:`gridfield.following.descent.descend`, :func:`gridfield.following.follower.follow_many`).

    Parameters
    ----------
    points : ndarray, shape (N, 2)
    radius : float
        How close a return counts as a revisit (:attr:`gridfield.following.descent.Rules.box`; a return to
        within a relative ``1e-9`` of it does not count).
    blocked : callable, optional
        ``blocked(p, q) -> bool``; ``None``: nothing blocks.

    Returns
    -------
    ndarray of intp
        The indices of the points kept, ascending (``0`` and ``N - 1`` included).

    Examples
    --------
    A path that jitters about (2, 0) before it goes on:

    >>> pts = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.1, 0.9], [2.0, 0.1], [3.0, 0.0]])
    >>> cut_loops(pts, 0.5).tolist()
    [0, 1, 2, 4, 5]
    >>> cut_loops(pts, 0.5, blocked=lambda p, q: True).tolist()
    [0, 1, 2, 3, 4, 5]
    """
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    if n < 3:
        return np.arange(n, dtype=np.intp)
    r = radius * (1.0 - _TIE)  # a return to exactly ``radius`` (cell centres on a lattice) does not count
    margin = _TIE * 1e3 * radius
    # the next _AHEAD points of each point, within r or not (the common case: no return from farther on)
    k = np.arange(2, _AHEAD + 1)
    ahead = np.arange(n)[:, None] + k[None, :]
    a = np.minimum(ahead, n - 1)
    close = (np.hypot(pts[a, 0] - pts[:, None, 0], pts[a, 1] - pts[:, None, 1]) <= r) & (ahead < n)
    # the points binned into squares of side r (the points within r of one lie in its 3 x 3 squares),
    # each square's largest index: a point may have a return from farther on only if a square
    # around it holds a point more than _AHEAD on
    key = np.floor(pts / r).astype(np.int64)
    key -= key.min(axis=0)
    width = int(key[:, 1].max()) + 3
    code = (key[:, 0] + 1) * width + key[:, 1] + 1
    order = np.argsort(code, kind="stable")
    sc = code[order]
    first = np.flatnonzero(np.concatenate([[True], sc[1:] != sc[:-1]]))
    ucode, top = sc[first], np.maximum.reduceat(order, first)
    far = np.zeros(n, bool)
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            nb = code + dx * width + dy
            at = np.minimum(np.searchsorted(ucode, nb), len(ucode) - 1)
            far |= (ucode[at] == nb) & (top[at] > np.arange(n) + _AHEAD)
    kept = [0]
    i = 0
    while i < n - 1:
        if far[i]:  # all the points within r of it, from its 3 x 3 squares
            nb = code[i] + np.array([dx * width + dy for dx in (-1, 0, 1) for dy in (-1, 0, 1)])
            lo, hi = np.searchsorted(sc, nb, side="left"), np.searchsorted(sc, nb, side="right")
            near = np.concatenate([order[u:v] for u, v in zip(lo.tolist(), hi.tolist(), strict=True)])
            near = near[near > i + 1]
            near = np.sort(near[np.hypot(pts[near, 0] - pts[i, 0], pts[near, 1] - pts[i, 1]) <= r])
        else:
            near = i + k[close[i]]
        nxt = i + 1
        for j in near[::-1].tolist() if near.size else ():  # the farthest-on first
            if blocked is None or not _thick_blocked(blocked, pts[i], pts[j], margin):
                nxt = j
                break
        kept.append(nxt)
        i = nxt
    return np.asarray(kept, dtype=np.intp)


def navigation_finish(navigate: Callable[..., list[Point]], x: float, y: float,
                      blocked: Blocked = None) -> list[Point] | None:
    """The finish of a reached run whose straight last hop to the goal is blocked: ``navigate``'s
    moves from ``(x, y)`` down to the goal, all of them or none.

    Unlike :func:`navigation_moves` (an escape keeps what is free), a finish must arrive: ``None``
    when ``navigate`` gives no moves or one of them is blocked.

    Parameters
    ----------
    navigate : callable
        ``navigate((x, y), final=True) -> [points]`` (a :class:`NavigationEscape`).
    x, y : float
        The run's last point.
    blocked : callable, optional

    Returns
    -------
    list of (float, float), or None

    Examples
    --------
    >>> nav = lambda p, final: [(1.0, 0.0), (2.0, 0.0)]
    >>> navigation_finish(nav, 0.0, 0.0, blocked=lambda p, q: False)
    [(1.0, 0.0), (2.0, 0.0)]
    >>> navigation_finish(nav, 0.0, 0.0, blocked=lambda p, q: q[0] > 1.5) is None
    True
    """
    hop = navigate((x, y), final=True)
    if not hop or (blocked is not None and any(blocked(a, b) for a, b in zip([(x, y), *hop[:-1]], hop, strict=True))):
        return None
    return hop


def navigation_map(gridmap: GridMap) -> GridMap:
    """The map the navigation escape and the reachability check search: ``gridmap`` itself for a
    ``wall`` border, else ``gridmap`` inside a one-cell free ring (open space around the grid).

    Parameters
    ----------
    gridmap : GridMap

    Returns
    -------
    GridMap
        With a ``wall`` border: ``gridmap`` itself; otherwise a map two cells wider and taller, with
        a ``wall`` border and the same resolution, shifted by one cell.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> m = navigation_map(GridMap(Grid((2, 3), 0.5, (1.0, 1.0)), np.zeros((2, 3), bool)))
    >>> m.grid.shape, m.grid.origin
    ((4, 5), (0.5, 0.5))
    """
    g = gridmap.grid
    if g.border == "wall":
        return gridmap
    res = g.resolution
    ring = Grid((g.rows + 2, g.cols + 2), res, (g.origin[0] - res, g.origin[1] - res), border="wall")
    occ = np.pad(np.asarray(gridmap.occupied, dtype=bool), 1, constant_values=False)
    return GridMap(ring, occ)


class NavigationEscape:
    """The navigation escape of a grid field (see the module docstring).

    Parameters
    ----------
    field : Field-like
        Has ``map`` (GridMap), ``potential`` (array) and ``goal``.

    Call it as ``escape(point, final=...)``: the moves (world points: the cell centres of the way
    down the wavefront, from the cell holding ``point`` (unless ``point`` is its centre) up to the
    first cell of the goal's basin) to drive from ``point``, or ``[]`` when the goal cannot be
    reached from there.
    ``final=True`` (or an escape that starts no lower on the wavefront than the last one) drives
    all the way to the goal.

    Examples
    --------
    A wall between a local minimum (the cell at (1.5, 1.5)) and the goal: the escape drives over
    the wall's end until the descent on the potential leads to the goal:

    >>> from types import SimpleNamespace
    >>> occ = np.zeros((3, 4), bool); occ[0:2, 2] = True
    >>> gm = GridMap(Grid((3, 4), 1.0, border="wall"), occ)
    >>> u = np.array([[1.0, 0.5, np.inf, 0.0], [0.5, 0.2, np.inf, 0.1], [1.0, 0.8, 0.6, 0.3]])
    >>> esc = NavigationEscape(SimpleNamespace(map=gm, potential=u, goal=(3.5, 0.5)))
    >>> esc.value((1.5, 1.5)) > esc.value((3.5, 1.5))
    True
    >>> [tuple(q) for q in esc((1.5, 1.5))]      # (2.5, 2.5) is the first cell that descends to the goal
    [(1.5, 2.5), (2.5, 2.5)]

    A column of obstacle cells splits a 5 x 5 map. With a ``wall`` border the goal cannot be
    reached; with an ``open`` border the escape goes round through the free ring below the grid:

    >>> occ = np.zeros((5, 5), bool); occ[:, 2] = True
    >>> def escape(border):
    ...     gm = GridMap(Grid((5, 5), 1.0, border=border), occ)
    ...     return NavigationEscape(SimpleNamespace(map=gm, potential=np.zeros((5, 5)), goal=(4.5, 2.5)))
    >>> escape("wall")((0.5, 2.5))
    []
    >>> moves = escape("open")((0.5, 2.5), final=True)
    >>> [float(y) for x, y in moves]
    [1.5, 0.5, -0.5, -0.5, -0.5, 0.5, 1.5, 2.5]
    """

    def __init__(self, field: GradientField) -> None:
        self.field = field
        self.gridmap: GridMap = field.map
        self.goal = np.asarray(field.goal, dtype=float).reshape(2)
        self._last_value = math.inf

    @cached_property
    def _frame(self) -> tuple[float, float, float]:
        """``(x0, y0, res)`` of :func:`navigation_map`: the wavefront runs in its cell units, so that
        its ties (and so the escape's path in cells) do not depend on the map's resolution."""
        g = navigation_map(self.gridmap).grid
        return float(g.origin[0]), float(g.origin[1]), float(g.resolution)

    def _to_cells(self, point: Point) -> Point:
        x0, y0, res = self._frame
        return ((float(point[0]) - x0) / res, (float(point[1]) - y0) / res)

    @cached_property
    def nav(self) -> Any:
        """The octile wavefront from the goal on :func:`navigation_map`, in cell units (unit cells,
        origin at its lower-left corner); computed on first use."""
        from ..fields.navigation import wavefront

        nm = navigation_map(self.gridmap)
        unit = GridMap(Grid(nm.grid.shape, 1.0, border="wall"), nm.occupied)
        return wavefront(unit, self._to_cells(tuple(self.goal)), costs="octile")

    @cached_property
    def sink(self) -> NDArray[np.intp]:
        """Each grid cell's discrete descent sink on the potential (:func:`gridfield.following.basins.basins`)."""
        return np.asarray(self._basins.sink)

    def value(self, point: Point) -> float:
        """The navigation value (octile distance to the goal, in cells) at the cell containing ``point``."""
        u, v = self._to_cells(point)
        cell = self.nav.grid.cell_of(u, v)
        return math.inf if cell is None else float(self.nav.value[cell])

    @cached_property
    def _basins(self) -> Any:
        """The basins of the discrete descent on the potential (:func:`gridfield.following.basins.basins`)."""
        from .basins import basins

        return basins(self.field)

    def _way(self, point: Point) -> tuple[list[Point], NDArray[np.float64], NDArray[np.intp], int, float]:
        """The whole way down the wavefront from ``point``: ``(lead, chain, cells, first, value)``.

        ``lead`` is the straight move back into the ring around an open map (or ``[]``), ``chain``
        the world points after it down to the goal, ``cells`` the grid cells (row, col) of the
        descent on :func:`navigation_map`, ``first`` the index in ``chain`` of ``cells[0]``'s centre
        (-1 when the point is that centre itself, so not in ``chain``), ``value`` the navigation
        value at the start cell (``inf``: the goal cannot be reached, ``chain`` empty)."""
        from ..fields.navigation import extract_path

        lead: list[Point] = []
        if self.nav.grid.cell_of(*self._to_cells(point)) is None:
            # out in the open space around an open map: straight back to the ring around the grid
            # (the segment stays outside the grid, so it is free)
            g = self.gridmap.grid
            half = 0.5 * g.resolution
            xmin, ymin, xmax, ymax = g.bounds
            point = (min(max(float(point[0]), xmin - half), xmax + half),
                     min(max(float(point[1]), ymin - half), ymax + half))
            lead = [point]
        v = self.value(point)
        if not math.isfinite(v):
            return [], np.zeros((0, 2)), np.zeros((0, 2), np.intp), 0, v
        u = self._to_cells(point)
        path = extract_path(self.nav, u, method="descent")
        x0, y0, res = self._frame
        chain = path.points[1:] * res + np.array([x0, y0])
        chain[-1] = self.goal  # exactly
        cells = np.asarray(path.extra["cells"])
        r0, c0 = int(cells[0, 0]), int(cells[0, 1])
        first = -1 if (u[0], u[1]) == (c0 + 0.5, r0 + 0.5) else 0  # extract_path lists the start cell's centre once
        return lead, chain, cells, first, v

    def values(self, xs: NDArray[np.float64], ys: NDArray[np.float64]) -> NDArray[np.float64]:
        """The navigation values at many world points, as lengths (cell units times the resolution;
        ``inf`` outside the navigation map or where the goal cannot be reached).

        Examples
        --------
        >>> from types import SimpleNamespace
        >>> gm = GridMap(Grid((3, 3), 0.5, border="wall"), np.zeros((3, 3), bool))
        >>> esc = NavigationEscape(SimpleNamespace(map=gm, potential=np.zeros((3, 3)), goal=(1.25, 0.25)))
        >>> esc.values(np.array([0.25, 1.4, 9.0]), np.array([0.25, 1.2, 0.0])).tolist()   # 2 cells of 0.5
        [1.0, 1.0, inf]
        """
        x0, y0, res = self._frame
        val = np.asarray(self.nav.value, dtype=float)
        c = np.floor((np.asarray(xs, dtype=float) - x0) / res)
        r = np.floor((np.asarray(ys, dtype=float) - y0) / res)
        ok = (r >= 0) & (r < val.shape[0]) & (c >= 0) & (c < val.shape[1])
        ri, ci = np.where(ok, r, 0).astype(np.intp), np.where(ok, c, 0).astype(np.intp)
        return np.where(ok, val[ri, ci] * res, np.inf)

    def way_length(self, point: Point) -> float:
        """The length of the way from ``point`` all the way down the wavefront to the goal (the
        moves of ``escape(point, final=True)``, from ``point``), without changing the escape's state
        (the navigation value the next escape must beat); ``inf`` when the goal cannot be reached.

        Examples
        --------
        >>> from types import SimpleNamespace
        >>> gm = GridMap(Grid((3, 3), 1.0, border="wall"), np.zeros((3, 3), bool))
        >>> esc = NavigationEscape(SimpleNamespace(map=gm, potential=np.zeros((3, 3)), goal=(2.5, 0.5)))
        >>> esc.way_length((0.5, 0.5)), esc.way_length((0.5, 2.5)) == 2 * math.sqrt(2)
        (2.0, True)
        """
        lead, chain, _, _, v = self._way(point)
        if not math.isfinite(v):
            return math.inf
        pts = np.vstack([np.asarray([point, *lead], dtype=float).reshape(-1, 2), chain])
        return float(np.hypot(*np.diff(pts, axis=0).T).sum())

    def __call__(self, point: Point, *, final: bool = False) -> list[Point]:
        lead, chain, cells, first, v = self._way(point)
        if not math.isfinite(v):
            return []
        drive_all = final or v >= self._last_value
        self._last_value = v
        if not drive_all:
            g = self.gridmap.grid
            shift = 0 if g.border == "wall" else 1  # the ring around an open map
            r, c = cells[:, 0] - shift, cells[:, 1] - shift
            inside = (r >= 0) & (r < g.rows) & (c >= 0) & (c < g.cols)
            rc = np.clip(r, 0, g.rows - 1), np.clip(c, 0, g.cols - 1)
            sink = np.where(inside, self.sink[rc], -1)
            gr, gc = self._basins.goal_cell
            goal_sink = int(self.sink[gr, gc])
            own = sink[0]
            # hand back to the potential at the first cell whose discrete descent ends in the
            # goal's sink (a cell of another minimum's basin would lead the follower into that
            # minimum next); from the goal's own basin (a stall the discrete descent does not
            # see) drive all the way
            ahead = np.flatnonzero(inside & (sink == goal_sink) & (own != goal_sink) & (goal_sink >= 0))
            if len(ahead):  # cells[k]'s centre is chain[k + first]
                chain = chain[: int(ahead[0]) + first + 1]
        return lead + [(float(x), float(y)) for x, y in chain]
