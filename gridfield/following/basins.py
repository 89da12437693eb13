"""Basins of attraction of discrete steepest descent on a potential array.

Each free cell moves to its lowest free 8-neighbour while that is lower (a diagonal move only
when both cells beside it are free: the move passes their common corner; the extra diagonals of a
disc robot's configuration space, :attr:`gridfield.core.grid.GridMap.diagonals`, are not taken: the
basins describe the potential follower, which moves continuously, and for it a passage through a
corner has no width); the cell where this descent ends is the cell's *sink*. The basin of a sink is every cell that descends to it. The
goal's basin is label 1, the other sinks (the potential's discrete local minima) follow by
increasing potential. The navigation escape (:mod:`gridfield.following.escapes`) and the diagnosis
(:mod:`gridfield.following.diagnose`) read these sinks; the ``field`` command and the plots draw them.

Examples
--------
>>> from types import SimpleNamespace
>>> from gridfield.core.grid import Grid, GridMap
>>> g = Grid((1, 5), 1.0)
>>> u = np.array([[1.0, 0.0, 2.0, 1.0, 3.0]])
>>> basins(SimpleNamespace(map=GridMap(g, np.zeros(g.shape, bool)), potential=u, goal=(1.5, 0.5))).label.tolist()
[[1, 1, 1, 2, 2]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..core.grid import Grid
from ..core.results import GradientField

__all__ = ["Basins", "basins", "descent_successor"]


@dataclass(frozen=True, eq=False)
class Basins:
    """Where discrete steepest descent on a potential array ends, for every free cell.

    Attributes
    ----------
    grid : Grid
    label : ndarray of int32, the grid's shape
        0 on obstacles, 1 for cells whose descent ends where the goal cell's descent ends,
        ``k >= 2`` for the other sinks (local minima), numbered by increasing potential.
    minima : ndarray, shape (K, 2)
        World point (cell centre) of the sink of label ``k`` at row ``k - 1``.
    sink : ndarray of intp, the grid's shape
        Flat index of the sink each cell descends to (-1 on obstacles).
    goal_cell : (int, int)
        ``(row, col)`` of the cell containing the goal.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from gridfield.core.grid import GridMap
    >>> g = Grid((1, 4), 1.0)
    >>> b = basins(SimpleNamespace(map=GridMap(g, np.zeros(g.shape, bool)), potential=np.array([[0.0, 1.0, 2.0, 0.5]]),
    ...                            goal=(0.5, 0.5)))
    >>> b, b.goal_cell, b.sink.tolist()
    (Basins(shape=(1, 4), basins=2, goal_fraction=0.5), (0, 0), [[0, 0, 3, 3]])
    """

    grid: Grid
    label: NDArray[np.int32]
    minima: NDArray[np.float64]
    sink: NDArray[np.intp]
    goal_cell: tuple[int, int]

    def __repr__(self) -> str:
        return f"Basins(shape={self.grid.shape}, basins={len(self.minima)}, goal_fraction={self.goal_fraction:.3g})"

    @property
    def goal_fraction(self) -> float:
        """Fraction of the free cells that descend to the goal."""
        free = self.label > 0
        return float((self.label[free] == 1).mean()) if free.any() else math.nan


_NEIGHBOURS = ((-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1))


def descent_successor(potential: NDArray[np.float64], free: NDArray[np.bool_]) -> NDArray[np.intp]:
    """Flat index of each cell's steepest-descent successor: its lowest free 8-neighbour if lower than
    itself (ties: the first in row-major neighbour order), else the cell itself (a sink; also obstacles).

    A diagonal neighbour counts only when both cells beside the diagonal are free too: the move
    between the centres passes their common corner, and the follower never touches an obstacle.

    Parameters
    ----------
    potential : ndarray, shape (rows, cols)
        The potential at the cell centres (NaN counts as ``+inf``).
    free : ndarray of bool, the same shape
        The free cells; obstacle cells are never entered.

    Returns
    -------
    ndarray of intp, shape (rows * cols,)
        The successor's flat (row-major) index per cell.

    Examples
    --------
    >>> u = np.array([[3.0, 2.0, 1.0], [4.0, 5.0, 0.5]])
    >>> descent_successor(u, np.ones(u.shape, bool)).reshape(u.shape)
    array([[1, 5, 5],
           [1, 5, 5]])
    """
    u = np.where(free, np.asarray(potential, dtype=float), np.inf)
    u = np.where(np.isnan(u), np.inf, u)
    rows, cols = u.shape
    pad = np.pad(u, 1, constant_values=np.inf)
    fpad = np.pad(np.asarray(free, dtype=bool), 1, constant_values=False)
    best = u.copy()
    succ = np.arange(rows * cols, dtype=np.intp).reshape(rows, cols)
    r, c = np.indices((rows, cols))
    for dr, dc in _NEIGHBOURS:
        nb = pad[1 + dr: 1 + dr + rows, 1 + dc: 1 + dc + cols]
        if dr and dc:  # a diagonal move passes the corner of both side cells: both must be free
            side = fpad[1 + dr: 1 + dr + rows, 1: 1 + cols] & fpad[1: 1 + rows, 1 + dc: 1 + dc + cols]
            nb = np.where(side, nb, np.inf)
        lower = nb < best
        best = np.where(lower, nb, best)
        succ = np.where(lower, (r + dr) * cols + (c + dc), succ)
    succ = np.where(free, succ, np.arange(rows * cols).reshape(rows, cols))
    return succ.reshape(-1)


def basins(field: GradientField) -> Basins:
    """Basins of attraction of discrete steepest descent on ``field.potential`` (no loop over cells).

    Each free cell moves to its lowest 8-neighbour while that is lower (:func:`descent_successor`);
    the sink of every cell is found by pointer jumping (``succ = succ[succ]``, at most
    ``log2(cells) + 1`` rounds).

    Parameters
    ----------
    field : Field
        Anything with ``map`` (GridMap), ``potential`` (array of the grid's shape) and ``goal``.

    Returns
    -------
    Basins
        Labels (1: the goal's basin), sinks and the sinks' world points.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from gridfield.core.grid import GridMap
    >>> g = Grid((1, 7), 1.0)
    >>> u = np.array([[2.0, 1.0, 2.0, 3.0, 1.5, 0.0, 1.0]])
    >>> f = SimpleNamespace(map=GridMap(g, np.zeros(g.shape, bool)), potential=u, goal=(5.5, 0.5))
    >>> b = basins(f)
    >>> b.label.tolist(), b.minima.tolist()
    ([[2, 2, 2, 1, 1, 1, 1]], [[5.5, 0.5], [1.5, 0.5]])
    """
    grid: Grid = field.map.grid
    free = ~np.asarray(field.map.occupied, dtype=bool)
    succ = descent_successor(np.asarray(field.potential, dtype=float), free)
    for _ in range(math.ceil(math.log2(max(succ.size, 2))) + 1):
        nxt = succ[succ]
        if np.array_equal(nxt, succ):
            break
        succ = nxt
    flat_free = free.reshape(-1)
    sink = np.where(flat_free, succ, -1)
    cells, _ = grid.world_to_cell(np.asarray(field.goal, dtype=float))
    gr = int(np.clip(cells[0, 0], 0, grid.rows - 1))
    gc = int(np.clip(cells[0, 1], 0, grid.cols - 1))
    goal_flat = gr * grid.cols + gc
    goal_sink = int(succ[goal_flat]) if flat_free[goal_flat] else -1
    sinks = np.unique(sink[flat_free])
    u = np.asarray(field.potential, dtype=float).reshape(-1)
    others = sinks[sinks != goal_sink]
    others = others[np.lexsort((others, u[others]))]
    order = np.concatenate([[goal_sink], others]) if goal_sink >= 0 else others
    lab_of = np.zeros(grid.rows * grid.cols + 1, np.int32)  # last slot: obstacles (-1)
    start_label = 1 if goal_sink >= 0 else 2
    lab_of[order] = np.arange(start_label, start_label + len(order), dtype=np.int32)
    label = lab_of[sink].reshape(grid.shape)
    label[~free] = 0
    rr, cc = np.divmod(order, grid.cols)
    minima = grid.cell_to_world(np.stack([rr, cc], axis=1)) if len(order) else np.zeros((0, 2))
    if goal_sink < 0:  # the goal lies in an obstacle cell: no basin 1
        minima = np.vstack([np.full((1, 2), np.nan), minima])
    return Basins(grid, label, minima, sink.reshape(grid.shape), (gr, gc))
