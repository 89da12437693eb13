"""The navigation mesh of a grid map's free space (:func:`navigation_mesh`, :class:`NavMesh`), the
Polyanya search's per-map part, for :mod:`gridfield.exact.anyangle` (a private module; import from there).

The free cells as rectangles (row runs merged across rows, or cut at the gaps in walls: whichever
partition has fewer rectangles), each rectangle's boundary a convex polygon with a vertex wherever
the neighbour across changes, its slots (:data:`SLOT_DTYPE`, the record the compiled search of
:mod:`gridfield.exact._polyanya` reads), the lattice points a taut path may turn at, and the
polygons' connected components. The corners, the visibility graph and the three searches
(:class:`gridfield.exact.anyangle.AnyAngleGraph`, :func:`gridfield.exact.anyangle.grid_graph`,
:func:`gridfield.exact.anyangle.plan_anyangle`) are :mod:`gridfield.exact.anyangle`'s, whose module
text describes the mesh and the search over it.

See Also
--------
gridfield.exact.anyangle : The any-angle searches, and the public home of these names.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


def _one_blocked(blocked_padded: NDArray[np.uint8]) -> NDArray[np.bool_]:
    """The lattice points (shape ``(rows + 1, cols + 1)``, ``[y, x]``) with exactly one blocked cell of the
    four round them: the convex corners, the only points a taut path bends at."""
    B = blocked_padded.astype(np.int8)
    return (B[:-1, :-1] + B[:-1, 1:] + B[1:, :-1] + B[1:, 1:]) == 1


def _cells_at(u: float, v: float) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """The rows and columns of the closed cells holding the lattice point ``(u, v)`` (two of each on a
    cell edge or corner)."""
    cs = (int(u) - 1, int(u)) if u == math.floor(u) else (math.floor(u),)
    rs = (int(v) - 1, int(v)) if v == math.floor(v) else (math.floor(v),)
    return rs, cs


#: One slot of a :class:`NavMesh` (a polygon's vertex and the edge from it; 32 bytes, the record the
#: compiled search reads, so that a polygon's slots are one run of memory).
SLOT_DTYPE = np.dtype([("x", np.float64), ("y", np.float64), ("root", np.int32), ("nb", np.int32),
                       ("nbslot", np.int32), ("pad", np.int32)])


@dataclass(frozen=True, eq=False)
class NavMesh:
    """The navigation mesh of a grid map's free space (lattice units), for the Polyanya search.

    Build it with :func:`navigation_mesh`. The polygons are rectangles of free cells; polygon ``p``
    owns the slots ``pstart[p] .. pstart[p + 1] - 1``: its vertices counter-clockwise, collinear ones
    kept (a vertex wherever the neighbour across the boundary changes), slot ``k`` the vertex
    ``(vx[k], vy[k])`` and the edge to the next slot's vertex, with the polygon ``nb[k]`` across it
    (-1: a blocked cell or the map's outside) in whose slot list the same edge is ``nbslot[k]``.
    ``turn`` flags the lattice points (index ``y * (cols + 1) + x``) where exactly one of the four
    cells round them is blocked (the outside counts as blocked): the only points a taut path bends
    at; ``root[k]`` numbers the slot's vertex among them (-1: not one), the search's per-root index.
    ``labels`` is the polygon of each cell, padded by a frame of -1 like the blocked array.

    Attributes
    ----------
    pstart : ndarray of int64, shape (n_polygons + 1,)
    slots : ndarray of :data:`SLOT_DTYPE`, shape (n_slots,)
        The fields ``x, y, root, nb, nbslot`` (also the properties :attr:`vx`, :attr:`vy`,
        :attr:`root`, :attr:`nb`, :attr:`nbslot`).
    turn : ndarray of uint8, shape ((rows + 1) * (cols + 1),)
    n_roots : int
        The turning points (``turn.sum()``), numbered ``0 .. n_roots - 1`` in lattice order.
    degree : ndarray of int32, shape (n_polygons,)
        The edges of each polygon with a polygon across (1: a dead end, which no shortest path
        enters unless the goal is in it).
    labels : ndarray of int32, shape (rows + 2, cols + 2)
    max_vertices : int
        The most vertices of one polygon.
    component : ndarray of int32, shape (n_polygons,)
        The connected component of each polygon (polygons sharing an edge are connected).

    Examples
    --------
    >>> B = np.ones((4, 5), np.uint8); B[1:3, 1:4] = 0; B[1, 2] = 1     # a 3 x 2 map, one blocked cell
    >>> mesh = navigation_mesh(B)
    >>> mesh.n_polygons, mesh.polygons_at(1.0, 1.0).tolist()            # (1, 1): the lower left cell, the top row
    (3, [0, 1])
    >>> mesh.turn.reshape(3, 4)[1].tolist(), mesh.n_roots               # the blocked cell's two upper corners
    ([0, 1, 1, 0], 2)
    """

    pstart: NDArray[np.int64]
    slots: NDArray[np.void]
    turn: NDArray[np.uint8]
    n_roots: int
    degree: NDArray[np.int32]
    labels: NDArray[np.int32]
    max_vertices: int
    component: NDArray[np.int32]

    @property
    def n_polygons(self) -> int:
        return len(self.pstart) - 1

    @property
    def vx(self) -> NDArray[np.float64]:
        return self.slots["x"]

    @property
    def vy(self) -> NDArray[np.float64]:
        return self.slots["y"]

    @property
    def root(self) -> NDArray[np.int32]:
        return self.slots["root"]

    @property
    def nb(self) -> NDArray[np.int32]:
        return self.slots["nb"]

    @property
    def nbslot(self) -> NDArray[np.int32]:
        return self.slots["nbslot"]

    def polygons_at(self, u: float, v: float) -> NDArray[np.int64]:
        """The polygons holding the lattice point ``(u, v)`` (those of the free closed cells it lies in)."""
        rs, cs = _cells_at(u, v)
        L = self.labels
        return np.array(sorted({int(L[r + 1, c + 1]) for r in rs for c in cs if L[r + 1, c + 1] >= 0}), dtype=np.int64)


def navigation_mesh(blocked_padded: NDArray[np.uint8], split: bool | None = None) -> NavMesh:
    """The navigation mesh of a padded blocked array (:class:`NavMesh`), in numpy without a loop over cells.

    The free cells of each row form maximal runs; runs with the same columns in consecutive rows merge
    into one rectangle. Cutting the runs also at gaps in walls (where both the row above and the row
    below change between blocked and free) makes each room of a room map one rectangle, but adds
    rectangles on random obstacles: of the two partitions the one with fewer rectangles is taken
    (:func:`_rectangles`; fewer polygons, fewer search nodes: 8room_000 14004 -> 10532 polygons,
    0.77x the query time; random512-10-0 keeps its 23854 strips). A lattice point is a vertex of
    every rectangle round it unless the rectangles (and blocked cells) round it meet along one
    straight line through it; each rectangle's vertices are sorted round its boundary, and each edge
    is matched with the same edge, reversed, of the polygon across it. Two cells touching only at a
    corner share no edge, so no path crosses a pinch point. The polygons' connected components (scipy)
    let a search give up at once on a goal in another one.

    Parameters
    ----------
    blocked_padded : ndarray of uint8, shape (rows + 2, cols + 2)
        The blocked cells with a one-cell frame (paths stay on the map, so :class:`AnyAngleGraph`
        passes a blocked frame for either border).
    split : bool, optional
        Whether runs are cut at gaps in walls; by default the partition with fewer rectangles.

    Returns
    -------
    NavMesh

    Examples
    --------
    >>> B = np.ones((5, 5), np.uint8); B[1:4, 1:4] = 0; B[2, 2] = 1     # a 3 x 3 map, its centre blocked
    >>> mesh = navigation_mesh(B)
    >>> mesh.n_polygons, np.diff(mesh.pstart).tolist()         # the left cell, the bottom row, the top row, the right cell
    (4, [4, 6, 6, 4])
    >>> mesh.vx[:4].tolist(), mesh.vy[:4].tolist()            # the left cell's corners, counter-clockwise
    ([0.0, 1.0, 1.0, 0.0], [1.0, 1.0, 2.0, 2.0])
    >>> mesh.nb[:4].tolist()                                   # across its edges: bottom row, centre, top row, outside
    [1, -1, 2, -1]
    """
    free = blocked_padded[1:-1, 1:-1] == 0
    rows, cols = free.shape
    splits = (False, True) if split is None else (split,)
    rid, c0, c1, X0, X1, Y0, Y1 = min((_rectangles(blocked_padded, sp) for sp in splits), key=lambda rect: len(rect[3]))
    L = np.full((rows + 2, cols + 2), -1, dtype=np.int32)
    L[1:-1, 1:-1][free] = np.repeat(rid, c1 - c0)  # free cells in row-major order are the runs in order
    # vertices: lattice points where the labels round them do not meet along one straight line
    sw, se, nw, ne = L[:-1, :-1], L[:-1, 1:], L[1:, :-1], L[1:, 1:]
    py, px = np.nonzero(~((sw == se) & (nw == ne)) & ~((sw == nw) & (se == ne)))
    labs = np.stack([sw[py, px], se[py, px], nw[py, px], ne[py, px]], axis=1)
    keep = labs >= 0
    for j in range(1, 4):  # each polygon once per point
        keep[:, j] &= (labs[:, j:j + 1] != labs[:, :j]).all(axis=1)
    pi, q = np.nonzero(keep)
    lab, x, y = labs[pi, q].astype(np.int64), px[pi].astype(np.int64), py[pi].astype(np.int64)
    x0, y0, x1, y1 = X0[lab], Y0[lab], X1[lab], Y1[lab]
    w, h = x1 - x0, y1 - y0
    # the position along the rectangle's boundary, counter-clockwise from its lower left corner
    t = np.where((y == y0) & (x < x1), x - x0,
                 np.where((x == x1) & (y < y1), w + (y - y0),
                          np.where((y == y1) & (x > x0), w + h + (x1 - x), 2 * w + h + (y1 - y))))
    order = np.lexsort((t, lab))
    lab, x, y = lab[order], x[order], y[order]
    npoly = len(X0)
    pstart = np.zeros(npoly + 1, dtype=np.int64)
    np.cumsum(np.bincount(lab, minlength=npoly), out=pstart[1:])
    nxt = np.arange(1, len(lab) + 1)
    nxt[pstart[1:] - 1] = pstart[:-1]
    xn, yn = x[nxt], y[nxt]
    dx, dy = np.sign(xn - x), np.sign(yn - y)
    # the cell across each edge, on its right: the midpoint moved by half a cell (doubled: integers)
    nb = L[(y + yn - dx) // 2 + 1, (x + xn + dy) // 2 + 1]
    vid = y * (cols + 1) + x
    nl = (cols + 1) * (rows + 1)
    key = vid * nl + vid[nxt]
    so = np.argsort(key)
    has = nb >= 0
    glob = so[np.searchsorted(key[so], vid[nxt][has] * nl + vid[has])]  # the same edge, reversed
    nbslot = np.full(len(lab), -1, dtype=np.int32)
    nbslot[has] = glob - pstart[nb[has]]
    turn = _one_blocked(blocked_padded).astype(np.uint8).ravel()
    degree = np.bincount(lab[has], minlength=npoly).astype(np.int32)
    root = np.cumsum(turn, dtype=np.int32) - 1  # the turning points' numbers, in lattice order
    slots = np.zeros(len(lab), dtype=SLOT_DTYPE)
    slots["x"], slots["y"], slots["nb"], slots["nbslot"] = x, y, nb, nbslot
    slots["root"] = np.where(turn[vid] == 1, root[vid], -1)
    import scipy.sparse
    from scipy.sparse.csgraph import connected_components

    owner = np.repeat(np.arange(npoly), np.diff(pstart))[has]
    adjacency = scipy.sparse.csr_array((np.ones(len(owner), dtype=np.int8), (owner, nb[has])), shape=(npoly, npoly))
    component = connected_components(adjacency, directed=False)[1].astype(np.int32)
    return NavMesh(pstart, slots, turn, int(root[-1]) + 1, degree, L, int(np.diff(pstart).max()) if npoly else 0,
                   component)


def _rectangles(blocked_padded: NDArray[np.uint8], split: bool) -> tuple[NDArray[np.int64], ...]:
    """The free cells as rectangles: row runs, runs with the same columns in consecutive rows merged.

    With ``split``, a run is also cut where both the row above and the row below change between
    blocked and free (a gap in a wall: a room's rows then share its columns, and the room is one
    rectangle). Returns ``rid, c0, c1`` per run (its rectangle, its columns; row-major order) and
    ``X0, X1, Y0, Y1`` per rectangle.

    Examples
    --------
    >>> B = np.ones((5, 6), np.uint8); B[1:4, 1:5] = 0; B[1, 2] = B[3, 2] = 1   # a gap in a wall, column 1
    >>> [len(_rectangles(B, split)[3]) for split in (False, True)]   # 5 strips; the two rooms and the gap
    [5, 3]
    """
    free = blocked_padded[1:-1, 1:-1] == 0
    cols = free.shape[1]
    fp = np.pad(free, ((0, 0), (1, 1)))
    left, right = fp[:, :-1], fp[:, 1:]  # the cells left and right of each lattice column x = 0 .. cols
    start, end = right & ~left, left & ~right
    if split:
        Bb = blocked_padded.astype(bool)
        above, below = Bb[2:], Bb[:-2]  # padded columns: [:, x] is the cell left of lattice x
        gap = (above[:, :-1] != above[:, 1:]) & (below[:, :-1] != below[:, 1:]) & left & right
        start, end = start | gap, end | gap
    r, c0 = np.nonzero(start)
    c1 = np.nonzero(end)[1]
    n = len(r)
    key = c0.astype(np.int64) * (cols + 1) + c1
    order = np.lexsort((r, key))
    ks, rs = key[order], r[order]
    new = np.ones(n, dtype=bool)
    new[1:] = (ks[1:] != ks[:-1]) | (rs[1:] != rs[:-1] + 1)
    rid = np.empty(n, dtype=np.int64)
    rid[order] = np.cumsum(new) - 1
    first = np.flatnonzero(new)
    last = np.append(first[1:], n)[: len(first)] - 1  # (empty without free cells)
    return rid, c0, c1, c0[order[first]], c1[order[first]], rs[first], rs[last] + 1
