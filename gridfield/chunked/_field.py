"""The classic potential field (``model: khatib``) chunk by chunk.

With the nearest-obstacle repulsion (``repulsion: nearest``, the default) and an integer repulsive power
0..4 (default 2), every cell's potential and analytic gradient depend on that cell alone: its world
position, the goal and its nearest obstacle cell (an obstacle cell is its own nearest). So each chunk is
one ``map_blocks`` task over the nearest-cell arrays of :func:`gridfield.chunked.distance`, running the
very row loop of :func:`gridfield.fields.potential.build_field` (``_potential_rows.h``, through
:func:`gridfield.chunked._chunked.khatib_block`) with the global row and column indices: the values are
bit-identical to the in-memory field, with no halo. The per-obstacle sum (``repulsion: sum``), other
powers and ``gradient: finite_difference`` are not chunked (one clear error).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.errors import GridfieldError, ParameterError, check_positive, shorten
from ..fields.potential import resolve_params
from ..fields.potential_args import METRIC_CODE, integer_power
from ._distance import _dask_array

__all__ = ["field"]


def _kernel_chunked() -> Any:
    """The compiled kernel module (gridfield/chunked/_chunked.pyx), imported on first use."""
    from . import _chunked  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _chunked


def _khatib_block(nr: NDArray[np.int32], nc: NDArray[np.int32], x0: float, y0: float, res: float, goal: tuple[float, float],
                  p: dict[str, Any], sat: float, block_info: dict[Any, Any] | None = None) -> NDArray[np.float64]:
    kc = _kernel_chunked()

    (r0, _), (c0, _) = block_info[0]["array-location"] if block_info else ((0, 0), (0, 0))
    nr = np.ascontiguousarray(nr, dtype=np.int32)
    nc = np.ascontiguousarray(nc, dtype=np.int32)
    rr = np.arange(r0, r0 + nr.shape[0], dtype=np.int32)[:, None]
    cc = np.arange(c0, c0 + nr.shape[1], dtype=np.int32)[None, :]
    occ = ((nr == rr) & (nc == cc)).view(np.uint8)  # an obstacle cell is its own nearest obstacle
    out = np.empty((3, *nr.shape), np.float64)
    kc.khatib_block(occ, nr, nc, int(r0), int(c0), x0, y0, res, goal[0], goal[1], p["zeta"], p["d_star"],
                    p["d_star"] == 0.0, METRIC_CODE[p["metric"]], p["eta"], p["q_star"],
                    integer_power(p["repulsive_power"]), sat, math.inf, out[0], out[1], out[2])
    return out


def field(
    distance: Any,
    nearest_row: Any,
    nearest_col: Any,
    *,
    goal_cell: tuple[int, ...],
    resolution: float = 1.0,
    origin: tuple[float, ...] = (0.0, 0.0),
    params: Mapping[str, Any] | None = None,
    metric: str = "euclidean",
) -> dict[str, Any]:
    """The classic potential ``U`` and its gradient, chunk by chunk, equal to ``build_field`` bit for bit.

    Parameters
    ----------
    distance, nearest_row, nearest_col : dask.array.Array
        The output of :func:`gridfield.chunked.distance` with ``return_nearest=True`` (same chunks).
    goal_cell : (row, col)
        The goal's cell; the goal is its centre, ``origin + (col + 0.5, row + 0.5) * resolution``.
    resolution : float
        Cell size in world units (as given to :func:`~gridfield.chunked.distance`).
    origin : (x, y)
        World position of the grid's lower-left corner (``Grid.origin``).
    params : mapping, optional
        Potential parameters as for :func:`gridfield.fields.potential.build_field` (lengths in world units,
        resolved with the resolution as the unit); ``model`` must be ``"khatib"`` (the default here),
        ``repulsion`` ``"nearest"``, ``repulsive_power`` an integer 0..4, ``gradient`` ``"analytic"``.
    metric : str
        The metric the nearest cells were computed with (``"euclidean"``: the only one
        :func:`~gridfield.chunked.distance` returns nearest cells for).

    Returns
    -------
    dict of str to dask.array.Array
        ``"U"``, ``"dUdx"``, ``"dUdy"``: float64 with the chunks of ``nearest_row``; obstacle cells have
        ``U = inf`` and a zero gradient.

    Raises
    ------
    ParameterError
        For parameters the chunked field does not compute, arrays of different shapes or chunks, or a
        goal cell outside the grid.
    GridfieldError
        For a goal cell inside an obstacle.

    Examples
    --------
    >>> import dask.array as da, numpy as np
    >>> from gridfield.chunked import distance
    >>> occ = np.zeros((4, 6), bool); occ[:, 0] = True
    >>> d, nr, nc = distance(da.from_array(occ, chunks=2), border="open", return_nearest=True)
    >>> f = field(d, nr, nc, goal_cell=(1, 5), params={"zeta": 0.5, "eta": 1, "q_star": 3})
    >>> round(float(f["U"][1, 2].compute()), 6), round(float(f["dUdx"][1, 2].compute()), 6)
    (2.263889, -1.541667)
    """
    da = _dask_array()
    arrays = (distance, nearest_row, nearest_col)
    if not all(isinstance(a, da.Array) for a in arrays):
        raise ParameterError("distance, nearest_row and nearest_col must be dask arrays (gridfield.chunked.distance "
                             "with return_nearest=True)")
    if len({a.shape for a in arrays}) != 1 or len({a.chunks for a in arrays}) != 1 or distance.ndim != 2:
        raise ParameterError("distance, nearest_row and nearest_col must be 2-D with the same shape and chunks")
    res = check_positive("resolution", resolution)
    try:
        x0, y0 = (float(v) for v in origin)
    except (TypeError, ValueError):
        raise ParameterError(f"origin must be (x, y), got {shorten(origin)}") from None
    if not (math.isfinite(x0) and math.isfinite(y0)):
        raise ParameterError(f"origin must be finite, got {shorten(origin)}")
    given = {"model": "khatib", **dict(params or {})}
    from ..core.params import validate

    given = dict(validate(given))
    p = resolve_params(given, unit=res)
    if "metric" in given and p["metric"] != metric:
        raise ParameterError(f"params ask for metric {p['metric']!r}, but the nearest cells were computed with "
                             f"{metric!r}")
    p["metric"] = metric
    if metric not in METRIC_CODE:
        raise ParameterError(f"metric must be one of {tuple(METRIC_CODE)}, got {shorten(metric)}")
    if p["model"] != "khatib":
        raise ParameterError(f"the chunked field computes model 'khatib' only, got {p['model']!r}")
    if p["repulsion"] != "nearest":
        raise ParameterError(f"the chunked field computes repulsion 'nearest' only, got {p['repulsion']!r}")
    if not 0 <= integer_power(p["repulsive_power"]) <= 4:
        raise ParameterError(f"the chunked field needs an integer repulsive_power 0..4, got {p['repulsive_power']!r}")
    if p["gradient"] != "analytic":
        raise ParameterError(f"the chunked field computes the analytic gradient only, got {p['gradient']!r}")
    try:
        gr, gc = (int(v) for v in goal_cell)
    except (TypeError, ValueError):
        raise ParameterError(f"goal_cell must be (row, col), got {shorten(goal_cell)}") from None
    rows, cols = distance.shape
    if not (0 <= gr < rows and 0 <= gc < cols):
        raise ParameterError(f"goal_cell {(gr, gc)} lies outside the grid of {rows} x {cols} cells")
    gnr, gnc = (int(v) for v in da.compute(nearest_row[gr, gc], nearest_col[gr, gc]))
    if (gnr, gnc) == (gr, gc):
        raise GridfieldError(f"goal_cell {(gr, gc)} lies inside an obstacle")
    goal = (x0 + (gc + 0.5) * res, y0 + (gr + 0.5) * res)  # as Grid.cell_to_world
    sat = math.inf if p["saturate"] is None else float(p["saturate"])
    stacked = da.map_blocks(_khatib_block, nearest_row, nearest_col, x0, y0, res, goal, p, sat, dtype=np.float64,
                            new_axis=0, chunks=((3,), *nearest_row.chunks), meta=np.empty((0, 0, 0), np.float64))
    return {"U": stacked[0], "dUdx": stacked[1], "dUdy": stacked[2]}
