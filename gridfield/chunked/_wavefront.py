"""The grid navigation function (wavefront) across chunks: tile-wise Dijkstra with boundary exchange.

Each round runs, on every chunk with a one-cell halo, Dijkstra's algorithm from every cell of the
extended block that has a finite value (its value the start: the goal's 0, the values the neighbouring
chunks reached in the halo, and the chunk's own values of the previous round), over the block's free
cells with the wavefront's moves (4 neighbours at cost 1, the diagonals at ``sqrt(2)`` (octile) or 1
(unit), no corner cutting, on the occupancy alone: a disc robot's diagonals through a corner,
:attr:`gridfield.core.grid.GridMap.diagonals`, are not taken, as the complete field ``nf1`` with
``attraction: octile`` that it computes does not take them in memory either). A value only ever falls, and each is the cost of a real path (a sum of
step costs, added in path order as the in-memory Dial queue adds them), so the rounds end, when no
chunk changes, at the values of :func:`gridfield.fields.navigation.wavefront` on the whole map, bit for bit.
How many rounds that takes depends on how often the shortest paths cross chunk seams, back and forth in
a maze; a straight corridor across ``k`` chunks needs about ``k + 1``.

The per-chunk search is :func:`scipy.sparse.csgraph.dijkstra` on the block's graph with one virtual
source joined to every started cell by an edge of its value (cells at value 0, such as the goal, are
sources of their own: a sparse graph cannot hold an edge of weight 0).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.errors import GridfieldError, ParameterError, shorten
from ._distance import _dask_array, check_occupied

__all__ = ["nf1_octile_field", "wavefront"]

COSTS = ("octile", "unit")


def _kernel_eikonal() -> Any:
    """The compiled kernel module (gridfield/fields/_eikonal.pyx), imported on first use."""
    from ..fields import _eikonal  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _eikonal


def _tile(u: NDArray[np.float64], occ: NDArray[np.bool_], diag: float) -> NDArray[np.float64]:
    """One extended block: the least path cost to every free cell from the started cells."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    rows, cols = u.shape
    free = ~np.asarray(occ, dtype=bool)
    started = free & np.isfinite(u)
    if not started.any():
        return u.copy()
    idx = np.full((rows, cols), -1, np.int64)
    n = int(free.sum())
    idx[free] = np.arange(n)
    src, dst, wt = [], [], []
    for dr, dc, w in ((0, 1, 1.0), (1, 0, 1.0), (1, 1, diag), (1, -1, diag)):
        a = free[max(0, -dr):rows - max(0, dr), max(0, -dc):cols - max(0, dc)]
        b = free[max(0, dr):rows + min(0, dr) or None, max(0, dc):cols + min(0, dc) or None]
        ok = a & b
        ia = idx[max(0, -dr):rows - max(0, dr), max(0, -dc):cols - max(0, dc)][ok]
        ib = idx[max(0, dr):rows + min(0, dr) or None, max(0, dc):cols + min(0, dc) or None][ok]
        if dr and dc:  # no corner cutting: both side cells free
            r0, c0 = np.nonzero(ok)
            r0 = r0 + max(0, -dr)
            c0 = c0 + max(0, -dc)
            side = free[r0 + dr, c0] & free[r0, c0 + dc]
            ia, ib = ia[side], ib[side]
        src += [ia, ib]
        dst += [ib, ia]
        wt += [np.full(ia.size, w), np.full(ia.size, w)]
    cells = idx[started]
    vals = u[started]
    zero = vals == 0.0
    s = n  # the virtual source
    src += [np.full(int((~zero).sum()), s, np.int64)]
    dst += [cells[~zero]]
    wt += [vals[~zero]]
    graph = coo_matrix((np.concatenate(wt), (np.concatenate(src), np.concatenate(dst))), shape=(n + 1, n + 1)).tocsr()
    sources = np.concatenate([[s], cells[zero]]).astype(np.int64)
    d = dijkstra(graph, directed=True, indices=sources, min_only=True)
    out = np.full((rows, cols), np.inf)
    out[free] = d[:n]
    return out


def wavefront(occupied: Any, goal_cell: tuple[int, ...], *, costs: str = "octile",
              max_rounds: int | None = None) -> tuple[Any, int]:
    """The wavefront (grid navigation function) of a chunked occupancy, exact, by rounds of tile-wise
    Dijkstra with boundary exchange (see the module notes).

    The rounds run on the active Dask scheduler (a ``distributed.Client`` when one is set): each round's
    result is persisted and compared with the previous one, so this function computes, unlike the
    other functions of :mod:`gridfield.chunked`.

    Parameters
    ----------
    occupied : dask.array.Array
        2-D boolean occupancy, ``True`` = obstacle. Outside the grid nothing is free (as in memory).
    goal_cell : (int, int)
        ``(row, col)`` of the goal, a free cell; its value is 0.
    costs : {"octile", "unit"}
        The diagonal step's cost: ``sqrt(2)`` or 1 (the 4 orthogonal steps cost 1).
    max_rounds : int, optional
        Give up (an error) after this many rounds; default the number of chunks plus 2, times 4.

    Returns
    -------
    value : dask.array.Array
        ``float64`` with ``occupied``'s chunks (persisted): the path cost in cells, ``inf`` on obstacles
        and cells the goal cannot reach; equal to ``gridfield.fields.navigation.wavefront(gridmap, goal,
        costs=costs).value`` (8-connected) on a map without :attr:`~gridfield.core.grid.GridMap.diagonals`.
    rounds : int
        How many rounds ran (the last one changed nothing).

    Raises
    ------
    ParameterError
        For an unknown ``costs``, a goal outside the grid or on an obstacle, or a bad ``max_rounds``.
    GridfieldError
        When the rounds do not settle within ``max_rounds``.

    Examples
    --------
    >>> import dask.array as da, numpy as np
    >>> occ = np.zeros((3, 6), bool); occ[:2, 3] = True
    >>> v, rounds = wavefront(da.from_array(occ, chunks=2), (0, 0))
    >>> v.compute().round(3).tolist()[0], rounds > 1
    ([0.0, 1.0, 2.0, inf, 6.828, 7.243], True)
    """
    da = _dask_array()
    occupied = check_occupied(occupied)
    if costs not in COSTS:
        raise ParameterError(f"costs must be one of {', '.join(map(repr, COSTS))}, got {shorten(costs)}")
    rows, cols = occupied.shape
    try:
        gr, gc = (int(v) for v in goal_cell)
    except (TypeError, ValueError):
        raise ParameterError(f"goal_cell must be (row, col), got {shorten(goal_cell)}") from None
    if not (0 <= gr < rows and 0 <= gc < cols):
        raise ParameterError(f"goal_cell {(gr, gc)} lies outside the grid of shape {(rows, cols)}")
    if bool(occupied[gr, gc].compute()):
        raise ParameterError(f"goal_cell {(gr, gc)} lies inside an obstacle")
    nblocks = math.prod(len(c) for c in occupied.chunks)
    limit = 4 * (nblocks + 2) if max_rounds is None else int(max_rounds)
    if limit < 1:
        raise ParameterError(f"max_rounds must be at least 1, got {shorten(max_rounds)}")
    diag = math.sqrt(2.0) if costs == "octile" else 1.0

    def start(block: NDArray[np.bool_], block_info: dict[Any, Any] | None = None) -> NDArray[np.float64]:
        out = np.full(block.shape, np.inf)
        (r0, r1), (c0, c1) = block_info[0]["array-location"] if block_info else ((0, block.shape[0]), (0, block.shape[1]))
        if r0 <= gr < r1 and c0 <= gc < c1:
            out[gr - r0, gc - c0] = 0.0
        return out

    u = occupied.map_blocks(start, dtype=np.float64, meta=np.empty((0, 0), np.float64)).persist()
    for rounds in range(1, limit + 1):
        new = da.map_overlap(_tile, u, occupied, depth=[1, 1], boundary=[np.inf, True], trim=True,
                             dtype=np.float64, meta=np.empty((0, 0), np.float64), diag=diag)
        new = new.persist()
        if not bool((new < u).any().compute()):
            return new, rounds
        u = new
    raise GridfieldError(f"the chunked wavefront did not settle in {limit} rounds (max_rounds); raise it or use "
                         "larger chunks")


def _upwind_block(u: NDArray[np.float64], res: float, axis: int) -> NDArray[np.float64]:
    """One component of the upwind gradient (the in-memory field's rule) of an extended block."""

    g: NDArray[np.float64] = _kernel_eikonal().upwind(np.ascontiguousarray(u, dtype=np.float64), True)[axis]
    if res != 1.0:
        g /= res
    return g


def nf1_octile_field(occupied: Any, goal_cell: tuple[int, ...], *, resolution: float = 1.0,
                     max_rounds: int | None = None) -> tuple[dict[str, Any], int]:
    """The complete model ``nf1`` with ``attraction: octile`` (the octile wavefront as the potential: one
    minimum, the goal) and its gradient, chunk by chunk: equal bit for bit to
    ``gridfield.fields.navfield.nav_field(gridmap, goal, {"model": "nf1", "attraction": "octile"})``'s
    ``potential``, ``grad_x`` and ``grad_y`` on a wall-bordered map, the goal at the centre of ``goal_cell``.

    Parameters
    ----------
    occupied : dask.array.Array
        2-D boolean occupancy (the grid's border a wall: nothing free outside).
    goal_cell : (int, int)
        The goal's cell ``(row, col)``, free.
    resolution : float
        Cell size: the potential is in world units, its gradient per world unit.
    max_rounds : int, optional
        As for :func:`wavefront`.

    Returns
    -------
    arrays : dict
        ``{"U", "dUdx", "dUdy"}``, ``float64`` dask arrays with ``occupied``'s chunks (the gradient by the
        upwind differences of the in-memory field, a one-cell halo).
    rounds : int
        The wavefront's rounds.

    Examples
    --------
    >>> import dask.array as da, numpy as np
    >>> f, _ = nf1_octile_field(da.from_array(np.zeros((3, 4), bool), chunks=2), (0, 0), resolution=0.5)
    >>> f["U"].compute()[2].round(3).tolist(), f["dUdx"].compute()[0].tolist()
    ([1.0, 1.207, 1.414, 1.914], [0.0, 1.0, 1.0, 1.0])
    """
    da = _dask_array()
    from ..core.errors import check_positive

    res = check_positive("resolution", resolution)
    v, rounds = wavefront(occupied, goal_cell, costs="octile", max_rounds=max_rounds)
    u = v * res if res != 1.0 else v
    gx, gy = (da.map_overlap(_upwind_block, u, depth=1, boundary=np.inf, trim=True, res=res, axis=axis,
                             dtype=np.float64, meta=np.empty((0, 0), np.float64)) for axis in (0, 1))
    return {"U": u, "dUdx": gx, "dUdy": gy}, rounds
