"""The result types that several stages build and read: :class:`DistanceMap` and :class:`Field`, and
:class:`GradientField`, what a follower reads of a field.

A leaf (it imports only ``errors`` and ``grid``), so that :mod:`gridfield.io` can build them when it
reads a field file without importing the algorithms that compute them. Their public homes are
:mod:`gridfield.brushfire` (``DistanceMap``) and :mod:`gridfield.fields.potential` (``Field``), which
re-export them; import them from there. (:class:`gridfield.fields.navigation.NavigationField` stays in
``gridfield.fields.navigation``: its ``clearance`` runs the brushfire, and ``io`` never builds one.)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import GridfieldError
from .grid import Grid, GridMap

__all__ = ["DistanceMap", "Field", "GradientField"]


@dataclass(frozen=True, eq=False)
class DistanceMap:
    """Result of :func:`brushfire`. Every array has the grid's shape.

    Attributes
    ----------
    map : GridMap
        The occupancy map the distances were computed on.
    connectivity : int
        4 or 8: the neighbourhood of the wavefront that numbers ``steps``.
    metric : str
        What ``distance`` measures: ``"chessboard"``, ``"taxicab"`` or ``"euclidean"``.
    steps : ndarray of int32 or None
        Wavefront number: 0 on obstacles, 1 on their neighbours, ... (the textbook's number minus 1).
        ``-1`` everywhere when there is no obstacle at all (empty map, open border). ``None`` when
        computed with ``compute_steps=False``.
    distance : ndarray of float64
        Distance from the cell's centre to the centre of the nearest obstacle cell in world units, by
        ``metric`` (``inf`` where there is none). With ``saturate``, distances ``>= saturate`` are
        replaced by ``far``.
    nearest_row, nearest_col : ndarray of int32 or None
        Cell index (row: along y, col: along x) of the nearest obstacle cell: exactly at ``distance`` by ``metric``; on ties any one
        of the nearest. The wall border's cells are row ``-1`` / ``rows`` or column ``-1`` / ``cols``
        (never a corner of the ring). -1 on both where there is no obstacle. ``None`` when computed
        with ``compute_nearest=False``.
    label : ndarray of int32 or None
        Label of the nearest obstacle: the world obstacle id when the grid was rasterized from a
        world (``GridMap.obstacle_id``), else the 8-connected component number (1-based, numbered in
        raster order of each component's first cell, as ``scipy.ndimage.label``);
        :data:`BORDER_LABEL` for the wall border; 0 where there is no obstacle. Obstacle cells carry
        their own label. ``None`` when computed with ``compute_labels=False``.
    gvd : ndarray of bool or None
        Generalized Voronoi diagram: free cells where the wavefronts of two different labels meet.
        Of each pair of 8-neighbouring free cells with different labels, the one farther from its
        obstacle (by ``distance`` before saturation) is marked; on a tie, the one with the smaller
        label. So the GVD separates the labels' regions (no two 8-neighbouring free cells of
        different labels remain once it is removed), it is one cell thick (an even gap between two
        obstacles gives one column, not two), and every GVD cell is within one cell of equidistant
        from two obstacles. With a wall border the wall is one of the obstacles.
        ``None`` when computed with ``compute_gvd=False``.
    saturate : float or None
        Saturation radius used (seed 004), or None.
    far : float
        Value that replaced saturated distances.
    nearest_layer : ndarray of int32 or None
        On a voxel grid: the layer (index along z) of the nearest obstacle cell, as ``nearest_row`` and
        ``nearest_col`` (a wall border's cells are layer ``-1`` / ``layers`` on the floor and ceiling);
        ``None`` on a 2-D map.

    Examples
    --------
    One obstacle cell on the left edge of a 3 x 5 grid: the wavefront numbers the cells by their
    chessboard distance, and the euclidean metric agrees with ``scipy.ndimage``'s exact transform.

    >>> import numpy as np
    >>> from scipy.ndimage import distance_transform_edt
    >>> from gridfield.distance.brushfire import brushfire
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((3, 5), bool); occ[1, 0] = True
    >>> gm = GridMap(Grid((3, 5), 0.5), occ)
    >>> dm = brushfire(gm)
    >>> dm.steps
    array([[1, 1, 2, 3, 4],
           [0, 1, 2, 3, 4],
           [1, 1, 2, 3, 4]], dtype=int32)
    >>> dm.nearest_row[0, 4], dm.nearest_col[0, 4], dm.label[0, 4]
    (np.int32(1), np.int32(0), np.int32(1))
    >>> bool(np.allclose(brushfire(gm, metric="euclidean").distance, 0.5 * distance_transform_edt(~occ)))
    True
    """

    map: GridMap
    connectivity: int
    metric: str
    steps: NDArray[np.int32] | None
    distance: NDArray[np.float64]
    nearest_row: NDArray[np.int32] | None
    nearest_col: NDArray[np.int32] | None
    label: NDArray[np.int32] | None
    gvd: NDArray[np.bool_] | None
    saturate: float | None = None
    far: float = np.inf
    nearest_layer: NDArray[np.int32] | None = None

    def __repr__(self) -> str:
        parts = [f"shape={self.grid.shape}", f"metric={self.metric!r}"]
        d = self.distance[np.isfinite(self.distance)]
        if d.size:
            parts.append(f"max distance={float(d.max()):.6g}")
        parts.append("labels" if self.label is not None else "no labels")
        return f"DistanceMap({', '.join(parts)})"

    @property
    def grid(self) -> Grid:
        return self.map.grid

    @property
    def nearest_index(self) -> tuple[NDArray[np.int32], ...]:
        """The nearest obstacle cell's index per array axis: ``(nearest_row, nearest_col)``, or on a
        voxel grid ``(nearest_layer, nearest_row, nearest_col)``."""
        if self.nearest_row is None or self.nearest_col is None:
            raise GridfieldError("this distance map was computed with compute_nearest=False; "
                                 "call brushfire(..., compute_nearest=True) to get nearest obstacles")
        if self.nearest_layer is not None:
            return self.nearest_layer, self.nearest_row, self.nearest_col
        return self.nearest_row, self.nearest_col

    def nearest_point(self) -> tuple[NDArray[np.float64], ...]:
        """World coordinates ``(x, y)`` of the centre of each cell's nearest obstacle cell (on a voxel
        grid ``(x, y, z)``: one array per axis).

        NaN where there is no obstacle at all. Wall-border cells lie just outside the grid.

        Examples
        --------
        >>> import numpy as np
        >>> from gridfield.distance.brushfire import brushfire
        >>> from gridfield.core.grid import Grid, GridMap
        >>> occ = np.zeros((1, 4), bool); occ[0, 0] = True
        >>> x, y = brushfire(GridMap(Grid((1, 4), 0.5), occ)).nearest_point()
        >>> x.tolist(), y.tolist()
        ([[0.25, 0.25, 0.25, 0.25]], [[0.25, 0.25, 0.25, 0.25]])
        """
        if self.nearest_row is None or self.nearest_col is None:
            raise GridfieldError("this distance map was computed with compute_nearest=False; "
                                 "call brushfire(..., compute_nearest=True) to get nearest obstacles")
        g = self.grid
        idx = self.nearest_index[::-1]  # along x, y (, z)
        none = np.logical_and.reduce([i == -1 for i in idx]) & (g.border == "open")
        return tuple(np.where(none, np.nan, g.origin[a] + (i + 0.5) * g.resolution) for a, i in enumerate(idx))


@dataclass(frozen=True, eq=False)
class Field:
    """A potential and its gradient on a grid, ready for a gradient-descent follower.

    Attributes
    ----------
    map : GridMap
        The occupancy map the field lives on (``field.grid`` is ``map.grid``).
    potential : ndarray of float64
        ``U`` at the cell centres; ``+inf`` on obstacle cells.
    grad_x, grad_y : ndarray of float64
        ``dU/dx`` and ``dU/dy`` in world units (for ``repulsive_power != 2``: the negative of the
        force model, see the module docstring); 0 on obstacle cells. The force is ``-grad``.
    goal : (float, float) or (float, float, float)
    params : dict
        The full resolved parameters (:func:`resolve_params`; defaults filled in).
    distance : DistanceMap or None
        The distance map behind the repulsion, when there is one.
    grad_z : ndarray of float64 or None
        ``dU/dz`` on a voxel grid; ``None`` on a 2-D map.

    Examples
    --------
    >>> from gridfield.fields.potential import build_field
    >>> occ = np.zeros((3, 4), bool); occ[0, 0] = True
    >>> f = build_field(GridMap(Grid((3, 4), 1.0), occ), (3.5, 2.5), {"q_star": 1.5})
    >>> f.grid.shape, float(f.potential[0, 0]), float(f.grad_x[0, 0])
    ((3, 4), inf, 0.0)
    """

    map: GridMap
    potential: NDArray[np.float64]
    grad_x: NDArray[np.float64]
    grad_y: NDArray[np.float64]
    goal: tuple[float, float]
    params: dict[str, Any]
    distance: DistanceMap | None = None
    grad_z: NDArray[np.float64] | None = None

    def __repr__(self) -> str:
        model = self.params.get("model", "khatib") if self.params else "khatib"
        goal = ", ".join(f"{v:.6g}" for v in self.goal)
        return (f"Field(shape={self.map.grid.shape}, resolution={self.map.grid.resolution:g}, "
                f"goal=({goal}), model={model!r})")

    def __post_init__(self) -> None:
        names = ("potential", "grad_x", "grad_y") + (("grad_z",) if self.map.grid.ndim == 3 else ())
        for name in names:
            a = getattr(self, name)
            if np.shape(a) != self.map.grid.shape:
                raise GridfieldError(f"Field.{name} has shape {np.shape(a)}, but the grid has shape {self.map.grid.shape}")
        if self.map.grid.ndim == 2 and self.grad_z is not None:
            raise GridfieldError("Field.grad_z belongs to a voxel grid's field; this map is 2-D")
        object.__setattr__(self, "goal", tuple(float(v) for v in tuple(self.goal)[:self.map.grid.ndim]))

    @property
    def gradient(self) -> tuple[NDArray[np.float64], ...]:
        """The gradient per world axis: ``(grad_x, grad_y)``, on a voxel grid ``(grad_x, grad_y, grad_z)``."""
        if self.grad_z is not None:
            return self.grad_x, self.grad_y, self.grad_z
        return self.grad_x, self.grad_y

    @property
    def grid(self) -> Grid:
        """The grid geometry (``map.grid``)."""
        return self.map.grid


class GradientField(Protocol):
    """What a follower and the samplers read of a field: a potential and its gradient at the cell centres
    of a grid map (public home :mod:`gridfield.fields.sampling`).

    :class:`Field` and :class:`gridfield.fields.navigation.NavigationField` are gradient fields, and so is any
    object with these read-only attributes (a field's ``distance`` map, when it has one, is used too).

    Attributes
    ----------
    map : GridMap
        The occupancy map the field lives on.
    grid : Grid
        ``map.grid``.
    potential, grad_x, grad_y : ndarray of float64
        The potential (or navigation value) and its derivatives along x and y at the cell centres
        (the force is ``-grad``).
    goal : (x, y)
    params : mapping
        The parameters the field was built with; the follower's given parameters are laid over them.

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> from gridfield.fields.sampling import sample_force
    >>> gm = GridMap(Grid((1, 2), 1.0), np.zeros((1, 2), bool))
    >>> field: GradientField = Field(gm, np.zeros((1, 2)), np.ones((1, 2)), np.zeros((1, 2)), (1.5, 0.5), {})
    >>> sample_force(field, [(0.5, 0.5)], sampling="nearest").tolist()   # the force is -grad
    [[-1.0, -0.0]]
    """

    @property
    def map(self) -> GridMap:
        """The occupancy map the field lives on."""

    @property
    def grid(self) -> Grid:
        """``map.grid``."""

    @property
    def potential(self) -> NDArray[np.float64]:
        """The potential (or navigation value) at the cell centres."""

    @property
    def grad_x(self) -> NDArray[np.float64]:
        """Its derivative along x at the cell centres (the force is ``-grad``)."""

    @property
    def grad_y(self) -> NDArray[np.float64]:
        """Its derivative along y."""

    @property
    def goal(self) -> ArrayLike:
        """The goal ``(x, y)``."""

    @property
    def params(self) -> Mapping[str, Any]:
        """The parameters the field was built with (the follower starts from them; may be empty)."""
