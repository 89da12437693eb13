"""The nearest obstacle's label and the GVD across chunks, bit-identical to the in-memory brushfire.

The label of a cell's nearest obstacle needs the label array at a cell that may lie in another chunk.
The separable Euclidean transform already says where to look, one axis at a time: the column pass gives
each cell ``(i, c)`` the row ``vr[i, c]`` of the nearest obstacle in its column, and the row pass picks
the column ``nc[i, j]`` whose column-nearest obstacle is nearest, so that the nearest obstacle of
``(i, j)`` is ``(vr[i, nc], nc)``. Its label is therefore two gathers, each inside the blocks the passes
already use: ``L1[i, c] = label[vr[i, c], c]`` on whole columns, then ``L[i, j] = L1[i, nc[i, j]]`` on
whole rows. A nearest cell outside the grid (the wall ring) gives :data:`gridfield.distance.brushfire.BORDER_LABEL`,
and an open map without obstacles labels 0, as in memory.

The GVD looks at each cell's 8 neighbours (:func:`gridfield.distance.brushfire.brushfire`'s rule: of two
neighbouring free cells with different nearest labels, the one farther from its obstacle; on a tie, the
smaller label), so it is one ``map_overlap`` with a one-cell halo and no padding at the map's edge.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.errors import ParameterError, check_positive
from ..distance.brushfire import BORDER_LABEL
from ._distance import (
    BORDERS,
    _check_choice,
    _column_pass,
    _dask_array,
    _gather_columns,
    _row_pass_nearest,
    _scratch_path,
    _via_store,
    check_occupied,
    strip_chunks,
)
from ._labels import labels

__all__ = ["gvd"]

def _kernel_brushfire() -> Any:
    """The compiled kernel module (gridfield/distance/_brushfire.pyx), imported on first use."""
    from ..distance import _brushfire  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _brushfire


def _gather_rows(nc: NDArray[np.int32], l1: NDArray[np.int32], outside: int) -> NDArray[np.int32]:
    """Whole rows: ``l1[i, nc[i, j]]``, ``outside`` where ``nc`` is outside the grid."""
    cols = l1.shape[1]
    inside = (nc >= 0) & (nc < cols)
    rows = np.broadcast_to(np.arange(l1.shape[0])[:, None], nc.shape)
    out = np.full(nc.shape, outside, np.int32)
    out[inside] = l1[rows[inside], nc[inside]]
    return out


def _gvd_block(label: NDArray[np.int32], dist: NDArray[np.float64], occ: NDArray[np.bool_]) -> NDArray[np.bool_]:
    kb = _kernel_brushfire()
    label = np.ascontiguousarray(label, dtype=np.int32)
    dist = np.ascontiguousarray(dist, dtype=np.float64)
    occ8 = np.ascontiguousarray(occ, dtype=bool).view(np.uint8)
    out = np.zeros(label.shape, bool)
    kb.gvd_rows(0, label.shape[0], label, dist, occ8, out.view(np.uint8))
    return out


def gvd(occupied: Any, *, resolution: float = 1.0, border: str = "wall",
        scratch: Any = None) -> tuple[Any, Any, Any]:
    """The Euclidean distance, the label of each cell's nearest obstacle and the GVD, chunk by chunk.

    Equal bit for bit to ``brushfire(GridMap(grid, occupied), metric="euclidean")``'s ``distance``,
    ``label`` and ``gvd`` for a map without given obstacle ids (the labels are the 8-connected obstacle
    components, numbered as :func:`labels` and the in-memory brushfire number them).

    Parameters
    ----------
    occupied : dask.array.Array
        2-D boolean occupancy, ``True`` = obstacle; its chunks set the tasks' sizes.
    resolution : float
        Cell size in world units (of the distance).
    border : {"wall", "open"}
        What lies outside the grid, as ``Grid.border``.
    scratch : str or path-like, optional
        The temporary store between the passes, as :func:`~gridfield.chunked.distance`'s (a directory or a
        URL, inside :func:`~gridfield.chunked.scratch_dir`): the column pass writes its strips and the
        gathered column labels there, and each output chunk is one task reading its rows back, so no strip
        of whole rows is rechunked through the workers' memory. Without it, task rechunks join the passes.

    Returns
    -------
    distance, label, gvd : dask.array.Array
        ``float64``, ``int32`` (``-1``: the wall; 0 on an open map without obstacles) and ``bool``, with ``occupied``'s chunks.

    Raises
    ------
    ParameterError
        For an unknown border, a non-positive resolution or an occupancy that is not 2-D boolean.

    Examples
    --------
    >>> import dask.array as da, numpy as np
    >>> occ = np.zeros((5, 7), bool); occ[:, 0] = occ[:, 6] = True
    >>> d, lab, g = gvd(da.from_array(occ, chunks=3), border="open")
    >>> np.flatnonzero(g.compute()[2]).tolist(), lab.compute()[2].tolist()
    ([3], [1, 1, 1, 1, 2, 2, 2])
    >>> from gridfield.chunked import scratch_dir
    >>> with scratch_dir("memory://doc/gvd.scratch") as s:   # the passes meet in a store (here in memory)
    ...     g2 = gvd(da.from_array(occ, chunks=3), border="open", scratch=s)[2].compute()
    >>> bool((g2 == g.compute()).all())
    True
    """
    da = _dask_array()
    occupied = check_occupied(occupied)
    border = _check_choice("border", border, BORDERS)
    res = check_positive("resolution", resolution)
    wall = border == "wall"
    rows, cols = occupied.shape
    if rows == 0 or cols == 0:
        raise ParameterError(f"the occupancy is empty (shape {occupied.shape})")
    lab = labels(occupied)
    # beyond the grid: the wall's label; with an open border only a map without obstacles has no nearest
    # obstacle, and its labels are 0 in memory
    outside = BORDER_LABEL if wall else 0
    if scratch is not None:
        dist, _, _, label = _via_store(occupied, _scratch_path(scratch), wall, res, True, labels=lab,
                                       outside=outside)
        g = da.map_overlap(_gvd_block, label, dist, occupied, depth=1, boundary="none", trim=True, dtype=bool,
                           meta=np.empty((0, 0), bool))
        return dist, label, g
    col_chunks, row_chunks = strip_chunks(occupied)
    strips = occupied.rechunk(col_chunks, method="tasks")
    vr = strips.map_blocks(_column_pass, wall, dtype=np.int32, meta=np.empty((0, 0), np.int32))
    l1 = da.map_blocks(_gather_columns, vr, lab.rechunk(col_chunks, method="tasks"), outside, dtype=np.int32,
                       meta=np.empty((0, 0), np.int32))
    vr_rows = vr.rechunk(row_chunks, method="tasks")
    dist, _, nc = _row_pass_nearest(vr_rows, rows, wall, res)
    label = da.map_blocks(_gather_rows, nc, l1.rechunk(row_chunks, method="tasks"), outside, dtype=np.int32,
                          meta=np.empty((0, 0), np.int32)).rechunk(occupied.chunks, method="tasks")
    dist = dist.rechunk(occupied.chunks, method="tasks")
    g = da.map_overlap(_gvd_block, label, dist, occupied, depth=1, boundary="none", trim=True, dtype=bool,
                       meta=np.empty((0, 0), bool))
    return dist, label, g
