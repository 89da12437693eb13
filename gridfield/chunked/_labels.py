"""8-connected obstacle components across chunks, numbered as the in-memory labels.

Each chunk is labelled on its own (``scipy.ndimage.label``, 8-connected); the provisional labels of all
chunks get global numbers by an offset per chunk. The labels that touch across a chunk seam (the last row
of a block row against the first row of the next, shifted by -1, 0, +1 columns; the same for columns,
which covers the corners) are joined by ``scipy.sparse.csgraph.connected_components`` on the client,
over the seams only. Each component is then numbered by the raster position of its first cell (the
smallest first cell of its pieces: inside a chunk, local raster order is global raster order), as
``scipy.ndimage.label`` and :func:`gridfield.distance.brushfire.brushfire` number them, and one ``map_blocks``
relabels the chunks through the lookup table. The per-chunk labelling runs twice (once for the seams and
first cells, which are small and gathered, once for the result); nothing of a chunk's size is gathered.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.errors import ParameterError
from ._distance import check_occupied

__all__ = ["labels"]

_EIGHT = np.ones((3, 3), bool)


def _label_block(block: NDArray[np.bool_]) -> NDArray[np.int32]:
    from scipy import ndimage

    lab: NDArray[np.integer[Any]]  # scipy's labels (int32 by default)
    lab, _ = ndimage.label(np.asarray(block, dtype=bool), structure=_EIGHT)
    return lab.astype(np.int32, copy=False)


def _summary(block: NDArray[np.bool_], r0: int, c0: int, cols: int) -> tuple[Any, ...]:
    """Count, first-cell global raster index per label, and the four edges of the local labels."""
    lab = _label_block(block)
    n = int(lab.max()) if lab.size else 0
    flat = lab.ravel()
    idx = np.flatnonzero(flat)
    _, first = np.unique(flat[idx], return_index=True)
    loc = idx[first]
    w = lab.shape[1]
    firsts = (r0 + loc // w).astype(np.int64) * cols + (c0 + loc % w)
    return n, firsts, lab[0].copy(), lab[-1].copy(), lab[:, 0].copy(), lab[:, -1].copy()


def _relabel(block: NDArray[np.bool_], offset: int, lut: NDArray[np.int32]) -> NDArray[np.int32]:
    lab = _label_block(block).astype(np.int64)
    return lut[np.where(lab > 0, lab + offset, 0)]


def labels(occupied: Any) -> Any:
    """Labels of the 8-connected obstacle components of a chunked occupancy grid.

    Parameters
    ----------
    occupied : dask.array.Array
        2-D boolean occupancy (``True`` = obstacle).

    Returns
    -------
    dask.array.Array
        ``int32`` with ``occupied``'s chunks: 0 on free cells, components numbered 1.. in raster order of
        their first cell, equal to ``scipy.ndimage.label(occ, structure=np.ones((3, 3)))`` and to
        :func:`gridfield.distance.brushfire.brushfire`'s ``label`` on the obstacle cells.

    Examples
    --------
    >>> import dask.array as da, numpy as np
    >>> occ = np.zeros((4, 4), bool); occ[1, 1] = occ[2, 2] = occ[0, 3] = True
    >>> labels(da.from_array(occ, chunks=2)).compute()
    array([[0, 0, 0, 1],
           [0, 2, 0, 0],
           [0, 0, 2, 0],
           [0, 0, 0, 0]], dtype=int32)
    """
    try:
        import dask.array as da
        from dask.base import compute
        from dask.delayed import delayed
    except ImportError:
        raise ParameterError("gridfield.chunked needs Dask: pip install 'gridfield[dask]'") from None
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    occupied = check_occupied(occupied)
    cols = occupied.shape[1]
    roffs = np.concatenate([[0], np.cumsum(occupied.chunks[0])[:-1]]).astype(int)
    coffs = np.concatenate([[0], np.cumsum(occupied.chunks[1])[:-1]]).astype(int)
    blocks = occupied.to_delayed()
    nbr, nbc = blocks.shape
    summ = compute(*[delayed(_summary)(blocks[i, j], int(roffs[i]), int(coffs[j]), cols)
                      for i in range(nbr) for j in range(nbc)])
    counts = np.array([s[0] for s in summ], np.int64).reshape(nbr, nbc)
    offsets = np.concatenate([[0], np.cumsum(counts.ravel())[:-1]]).reshape(nbr, nbc)
    total = int(counts.sum())

    def glob(a: NDArray[np.int32], off: int) -> NDArray[np.int64]:
        a = a.astype(np.int64)
        return np.where(a > 0, a + off, 0)

    def pairs(x: NDArray[np.int64], y: NDArray[np.int64]) -> list[NDArray[np.int64]]:
        out = []
        for d in (-1, 0, 1):
            a = x[max(0, -d): len(x) - max(0, d)]
            b = y[max(0, d): len(y) - max(0, -d)]
            m = (a > 0) & (b > 0)
            out.append(np.stack([a[m], b[m]]))
        return out

    edges: list[NDArray[np.int64]] = []
    s = np.empty((nbr, nbc, 6), dtype=object)  # filled element by element: never broadcast into a 3-D array
    for k, parts in enumerate(summ):
        for m, part in enumerate(parts):
            s[k // nbc, k % nbc, m] = part
    for i in range(nbr - 1):  # horizontal seams: last row of block row i, first of i + 1
        x = np.concatenate([glob(s[i, j, 3], offsets[i, j]) for j in range(nbc)])
        y = np.concatenate([glob(s[i + 1, j, 2], offsets[i + 1, j]) for j in range(nbc)])
        edges += pairs(x, y)
    for j in range(nbc - 1):  # vertical seams: last column of block column j, first of j + 1
        x = np.concatenate([glob(s[i, j, 5], offsets[i, j]) for i in range(nbr)])
        y = np.concatenate([glob(s[i, j + 1, 4], offsets[i, j + 1]) for i in range(nbr)])
        edges += pairs(x, y)
    lut = np.zeros(total + 1, np.int32)
    if total:
        e = np.concatenate(edges, axis=1) - 1 if edges else np.zeros((2, 0), np.int64)
        graph = coo_matrix((np.ones(e.shape[1], np.int8), (e[0], e[1])), shape=(total, total))
        _, comp = connected_components(graph, directed=False)
        firsts = np.concatenate([s[i, j, 1] for i in range(nbr) for j in range(nbc)])
        first_of = np.full(int(comp.max()) + 1, np.iinfo(np.int64).max)
        np.minimum.at(first_of, comp, firsts)
        rank = np.empty_like(first_of)
        rank[np.argsort(first_of, kind="stable")] = np.arange(1, len(first_of) + 1)
        lut[1:] = rank[comp]
    return da.map_blocks(lambda b, block_id=None: _relabel(b, int(offsets[block_id]), lut), occupied,
                         dtype=np.int32, meta=np.empty((0, 0), np.int32))
