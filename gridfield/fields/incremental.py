"""Fields after a map change: a potential field recomputed in the changed window only, and a wavefront
navigation function recomputed only when the change touches the region its search reached.

The map change comes from :class:`~gridfield.distance.incremental.IncrementalBrushfire` (the distance
layer): its :meth:`~gridfield.distance.incremental.IncrementalBrushfire.update` returns the window every
changed cell and nearest obstacle lies in, which :func:`update_field` recomputes with the row loop of
:func:`~gridfield.fields.potential.build_field` (the compiled ``khatib_window``), so the values equal a
full rebuild.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.errors import GridfieldError, ParameterError
from ..core.grid import GridMap
from ..core.results import Field
from ..distance.brushfire import DistanceMap
from ..distance.incremental import IncrementalBrushfire, Window
from .navigation import NavigationField, wavefront
from .potential_args import METRIC_CODE, integer_power, saturation

__all__ = ["update_field", "update_navigation"]


def _kernel_incremental() -> Any:
    """The compiled kernel module (gridfield/distance/_incremental.pyx), imported on first use."""
    from ..distance import _incremental  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _incremental


def update_field(field: Field, dmap: DistanceMap | IncrementalBrushfire, window: Window | None) -> Field:
    """The potential field ``field`` after a map change, recomputed in ``window`` only.

    Parameters
    ----------
    field : Field
        A field of :func:`gridfield.fields.potential.build_field` on the map before the change (Khatib
        model, nearest-obstacle repulsion, analytic gradient, ``repulsive_power`` 0-4); its arrays
        are updated **in place**.
    dmap : DistanceMap or IncrementalBrushfire
        The distance map after the change (Euclidean, same grid). The field reads only the nearest
        obstacles; an IncrementalBrushfire whose component labels an update renumbered relabels
        them here (its ``distance_map``), so build it with ``compute_labels=False`` when only
        fields are wanted.
    window : tuple or None
        ``(r0, r1, c0, c1)``: every cell whose occupancy or nearest obstacle changed lies inside,
        as returned by :meth:`IncrementalBrushfire.update`; None: nothing to do.

    Returns
    -------
    Field
        A field with the updated arrays, the new map and distance map; equal to a full
        ``build_field`` on the new map with the same goal and parameters.

    Raises
    ------
    ParameterError
        For a field this window update cannot reproduce (another model, per-obstacle sum,
        finite-difference gradient, another power), or a distance map of another grid or metric.
    GridfieldError
        When the change occupies the goal.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.fields.potential import build_field
    >>> occ = np.zeros((8, 8), bool); occ[0, :] = True
    >>> ib = IncrementalBrushfire(GridMap(Grid((8, 8), 1.0), occ), compute_labels=False)
    >>> f = build_field(ib.gridmap, (7.5, 7.5), {"q_star": 2.0}, dmap=ib.distance_map)
    >>> f = update_field(f, ib, ib.update(occupied=[[4, 2]]))
    >>> g = build_field(ib.gridmap, (7.5, 7.5), {"q_star": 2.0})
    >>> bool(np.array_equal(f.potential, g.potential) and np.array_equal(f.grad_x, g.grad_x))
    True
    """
    if not isinstance(field, Field):
        raise ParameterError(f"update_field needs a Field, got {type(field).__name__}")
    if isinstance(dmap, IncrementalBrushfire):
        dmap = dmap.distance_map
    if not isinstance(dmap, DistanceMap) or dmap.grid.shape != field.grid.shape:
        raise ParameterError("dmap must be the distance map (or IncrementalBrushfire) of the field's grid")
    p = field.params
    ipow = integer_power(p["repulsive_power"])
    if p["model"] != "khatib" or p["repulsion"] != "nearest" or p["gradient"] != "analytic" or not 0 <= ipow <= 4:
        raise ParameterError("update_field updates Khatib fields with repulsion='nearest', gradient='analytic' and "
                             f"an integer repulsive_power 0-4; rebuild this one with build_field (params {p!r})")
    if p["metric"] != dmap.metric:
        raise ParameterError(f"the field uses metric {p['metric']!r}, the distance map {dmap.metric!r}")
    dmap.map.check_point("goal", field.goal)  # as build_field: the change may not cover the goal
    out = Field(dmap.map, field.potential, field.grad_x, field.grad_y, field.goal, p, dmap)
    if window is None:
        return out
    rows, cols = field.grid.shape
    try:
        r0, r1, c0, c1 = (int(v) for v in window)
    except (TypeError, ValueError):
        raise ParameterError(f"window must be (r0, r1, c0, c1), got {window!r}") from None
    if not (0 <= r0 <= r1 <= rows and 0 <= c0 <= c1 <= cols):
        raise ParameterError(f"window {window!r} does not lie in the grid of shape {(rows, cols)}")
    if dmap.nearest_row is None or dmap.nearest_col is None:
        raise GridfieldError("the distance map has no nearest obstacles (compute_nearest=False)")
    sat, far = saturation(dmap, p["saturate"])
    g = field.grid
    occ = np.ascontiguousarray(dmap.map.occupied, dtype=bool)
    _kernel_incremental().khatib_window(r0, r1, c0, c1, occ, np.ascontiguousarray(dmap.nearest_row, np.int32),
                             np.ascontiguousarray(dmap.nearest_col, np.int32), g.origin[0], g.origin[1],
                             g.resolution, field.goal[0], field.goal[1], p["zeta"], p["d_star"],
                             p["d_star"] == 0.0, METRIC_CODE[dmap.metric], p["eta"], p["q_star"], ipow, sat,
                             far, field.potential, field.grad_x, field.grad_y)
    return out


def update_navigation(nav: Any, gridmap: GridMap, window: Window | None) -> Any:
    """A wavefront navigation function after a map change: the same values when the change does not
    touch the region the search reached, else recomputed on the new map.

    The search only ever looks at the cells next to the ones it reached (finite values), so when no
    cell of ``window`` grown by one cell has a finite value, the change (occupancy, and with it the
    Euclidean distance behind a clearance cost, all inside ``window``) cannot alter any value.

    Parameters
    ----------
    nav : NavigationField
        Of :func:`gridfield.fields.navigation.wavefront` on the map before the change.
    gridmap : GridMap
        The map after the change (e.g. :attr:`IncrementalBrushfire.gridmap`).
    window : tuple or None
        Every cell whose occupancy or Euclidean distance changed lies inside, as returned by
        :meth:`IncrementalBrushfire.update`; None: nothing changed.

    Returns
    -------
    NavigationField
        ``nav`` itself on the new map, or :func:`~gridfield.fields.navigation.wavefront` of the new map with
        ``nav``'s parameters (a search that was stopped early with ``stop_at`` is redone in full).

    Raises
    ------
    ParameterError
        For a navigation function of another kind, or a map of another grid.
    GridfieldError
        When the change occupies the goal.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.fields.navigation import wavefront
    >>> occ = np.zeros((3, 9), bool); occ[:, 3] = True          # a wall: the right part is unreachable
    >>> ib = IncrementalBrushfire(GridMap(Grid((3, 9), 1.0), occ), compute_labels=False)
    >>> nav = wavefront(ib.gridmap, (0.5, 0.5))
    >>> window = ib.update(occupied=[[1, 7]])                  # beyond the wall: the search never got there
    >>> update_navigation(nav, ib.gridmap, window).value is nav.value
    True
    >>> window = ib.update(freed=[[1, 3]])                     # a door opens
    >>> float(update_navigation(nav, ib.gridmap, window).value[1, 8])
    9.0
    """
    import dataclasses


    if not isinstance(nav, NavigationField) or nav.kind != "wavefront":
        raise ParameterError("update_navigation updates wavefront navigation functions; recompute "
                             f"{getattr(nav, 'kind', type(nav).__name__)!r} fields with navigation_field")
    if not isinstance(gridmap, GridMap) or gridmap.shape != nav.map.shape:
        raise ParameterError("gridmap must be the changed map of the navigation function's grid")
    if window is None:
        return dataclasses.replace(nav, map=gridmap)
    rows, cols = gridmap.shape
    r0, r1, c0, c1 = (int(v) for v in window)
    near = nav.value[max(0, r0 - 1):min(rows, r1 + 1), max(0, c0 - 1):min(cols, c1 + 1)]
    if not np.isfinite(near).any():
        return dataclasses.replace(nav, map=gridmap)
    p = nav.params
    return wavefront(gridmap, nav.goal, connectivity=p["connectivity"], costs=p["costs"],
                     clearance_weight=p["clearance_weight"], q_star=p["q_star"])
