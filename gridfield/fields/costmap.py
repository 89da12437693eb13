"""Nav2 costmaps: the inflated cost grid of ROS 2 Nav2's ``costmap_2d`` and queries on it.

:func:`inflate` turns an occupancy grid into the costs of Nav2's inflation layer, evaluated on
gridfield's exact Euclidean brushfire (:func:`gridfield.distance.brushfire.brushfire`, ``metric="euclidean"``):
with ``d`` the distance in cells from a cell's centre to the centre of the nearest obstacle cell,
``r`` the resolution, ``R_i`` the inscribed (robot) radius and ``K`` the cost scaling factor,

- ``254`` (``LETHAL_OBSTACLE``) at ``d = 0``,
- ``253`` (``INSCRIBED_INFLATED_OBSTACLE``) while ``d * r <= R_i``,
- ``int(252 * exp(-K * (d * r - R_i)))`` (truncated, as C's ``(unsigned char)`` cast) for
  ``d <= ceil(inflation_radius / r)`` (``Costmap2D::cellDistance``),
- ``0`` (``FREE_SPACE``) beyond,

which is ``InflationLayer::computeCost`` (nav2_costmap_2d ``inflation_layer.hpp``) with the
constants of ``cost_values.hpp``. The older (legacy) layer evaluates it on the exact distance; the
current layer (``lut_precision=100``, its ``COST_LUT_PRECISION``) first rounds the float32 distance
to 1/100 cell (``(unsigned)(d * 100 + 0.5f)``, capped at ``ceil(R / r) * 100 + 1``) and looks the
cost up in a table of ``computeCost(k / 100)``. Unknown cells kept as ``255`` (``NO_INFORMATION``)
stay unknown unless the inflation gives them ``253`` or more, as the layer's update does.

A :class:`Costmap` is a :class:`~gridfield.core.grid.GridMap` (its cells of cost ``>= 253`` are the
occupied ones: lethal, inscribed and unknown), so every gridfield planner plans on it; the
``navfn`` planner (:mod:`gridfield.fields.navfn`) reads its costs. :meth:`Costmap.distance`,
:meth:`Costmap.gradient`, :meth:`Costmap.nearest_obstacle` and :meth:`Costmap.cost` answer queries at
many points at once. Reading and writing: :func:`gridfield.io.write_costmap`,
:func:`gridfield.io.read_costmap` (a ROS map_server YAML + PGM in ``mode: raw``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import ParameterError
from ..core.grid import GridMap

__all__ = [
    "FREE_SPACE",
    "INSCRIBED_INFLATED_OBSTACLE",
    "LETHAL_OBSTACLE",
    "MAX_NON_OBSTACLE",
    "NO_INFORMATION",
    "Costmap",
    "compute_cost",
    "inflate",
]

#: The cost values of nav2_costmap_2d (``cost_values.hpp``).
NO_INFORMATION = 255
LETHAL_OBSTACLE = 254
INSCRIBED_INFLATED_OBSTACLE = 253
MAX_NON_OBSTACLE = 252
FREE_SPACE = 0

#: Defaults of Nav2's costmap (``robot_radius``) and inflation layer (``inflation_radius``, ``cost_scaling_factor``).
DEFAULT_ROBOT_RADIUS = 0.1
DEFAULT_INFLATION_RADIUS = 0.55
DEFAULT_COST_SCALING_FACTOR = 10.0
#: ``COST_LUT_PRECISION`` of the current inflation layer: distances rounded to 1/100 cell.
NAV2_LUT_PRECISION = 100


def _kernel_navfn() -> Any:
    """The compiled kernel module (gridfield/fields/_navfn.pyx), imported on first use."""
    from . import _navfn  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _navfn


def _number(name: str, value: Any, *, minimum: float = 0.0) -> float:
    try:
        if isinstance(value, bool):
            raise TypeError
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a finite number >= {minimum:g}, got {value!r}") from None
    if not (math.isfinite(v) and v >= minimum):
        raise ParameterError(f"{name} must be a finite number >= {minimum:g}, got {value!r}")
    return v


def _check_inflation(robot_radius: Any, inflation_radius: Any, cost_scaling_factor: Any,
                     lut_precision: Any) -> tuple[float, float, float, int | None]:
    r = _number("robot_radius", robot_radius)
    big_r = _number("inflation_radius", inflation_radius)
    k = _number("cost_scaling_factor", cost_scaling_factor)
    if big_r < r:
        raise ParameterError(f"inflation_radius ({big_r:g}) is smaller than robot_radius ({r:g}): the inflation must "
                             "cover at least the robot's inscribed radius")
    if lut_precision is not None:
        if isinstance(lut_precision, bool) or not isinstance(lut_precision, int | np.integer) or lut_precision < 1:
            raise ParameterError(f"lut_precision must be None (exact distances) or an integer >= 1 (Nav2: 100), "
                                 f"got {lut_precision!r}")
        lut_precision = int(lut_precision)
    return r, big_r, k, lut_precision


def compute_cost(distance: ArrayLike, *, resolution: float, robot_radius: float = DEFAULT_ROBOT_RADIUS,
                 cost_scaling_factor: float = DEFAULT_COST_SCALING_FACTOR) -> NDArray[np.uint8]:
    """Nav2's ``computeCost``: the cost of a cell at ``distance`` cells from the nearest obstacle.

    Parameters
    ----------
    distance : array_like
        Distances in cells (float64).
    resolution : float
        Cell size (m).
    robot_radius : float
        The inscribed radius (m).
    cost_scaling_factor : float
        ``K`` of the exponential decay (1/m).

    Returns
    -------
    ndarray of uint8
        254 at 0, 253 within the inscribed radius, else ``int(252 * exp(-K * (d * resolution - robot_radius)))``
        (no cut-off at the inflation radius: :func:`inflate` applies it).

    Examples
    --------
    >>> compute_cost([0.0, 1.0, 2.0, 3.0, 20.0], resolution=0.05).tolist()
    [254, 253, 253, 152, 0]
    """
    d = np.asarray(distance, dtype=np.float64)
    with np.errstate(over="ignore"):
        factor = np.exp(-1.0 * cost_scaling_factor * (d * resolution - robot_radius))
    decayed = np.trunc(np.float64(INSCRIBED_INFLATED_OBSTACLE - 1) * np.minimum(factor, 1.0))
    out = np.where(d == 0, LETHAL_OBSTACLE,
                   np.where(d * resolution <= robot_radius, INSCRIBED_INFLATED_OBSTACLE, decayed))
    return out.astype(np.uint8)


@dataclass(frozen=True, eq=False)
class Costmap(GridMap):
    """A Nav2 cost grid (uint8 costs 0..255) that is also the occupancy map of its blocked cells.

    Attributes
    ----------
    cost : ndarray of uint8, shape ``grid.shape``
        Costs in gridfield's row order (row 0 = lowest y), the values of ``cost_values.hpp``.
    inflation : mapping
        How the costs were made (``robot_radius``, ``inflation_radius``, ``cost_scaling_factor``,
        ``lut_precision``, ``keep_unknown``); empty when unknown.

    ``occupied`` (the :class:`GridMap` part) is ``cost >= 253``: lethal, inscribed and unknown cells.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((1, 8), bool); occ[0, 0] = True
    >>> cm = inflate(GridMap(Grid((1, 8), 0.05), occ), robot_radius=0.05, inflation_radius=0.25)
    >>> cm.cost.tolist()
    [[254, 253, 152, 92, 56, 34, 0, 0]]
    >>> cm.occupied.tolist()
    [[True, True, False, False, False, False, False, False]]
    >>> cm.cost_at([[0.125, 0.025]]).tolist(), cm.distance([[0.125, 0.025]]).round(3).tolist()
    ([152], [0.1])
    """

    cost: NDArray[np.uint8] = field(default_factory=lambda: np.zeros((0, 0), np.uint8))
    inflation: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        c = np.asarray(self.cost)
        if c.dtype != np.uint8:
            raise ParameterError(f"costmap costs must be an array of uint8 (0..255), got dtype {c.dtype}")
        if c.shape != self.grid.shape:
            raise ParameterError(f"costmap costs have shape {c.shape}, but the grid has shape {self.grid.shape}")
        object.__setattr__(self, "cost", np.ascontiguousarray(c))
        super().__post_init__()

    def __repr__(self) -> str:
        g = self.grid
        lethal = float(np.count_nonzero(self.cost == LETHAL_OBSTACLE)) / max(self.cost.size, 1)
        return (f"Costmap(shape={g.shape}, resolution={g.resolution:g}, origin={g.origin}, lethal={lethal:.1%}, "
                f"inflation={dict(self.inflation)})")

    @classmethod
    def from_costs(cls, gridmap_or_grid: Any, cost: ArrayLike, inflation: Mapping[str, Any] | None = None,
                   *, source: str = "", meta: dict[str, Any] | None = None) -> Costmap:
        """A Costmap from a cost array on a grid (a :class:`Grid` or a :class:`GridMap`'s).

        Examples
        --------
        >>> import numpy as np
        >>> from gridfield.core.grid import Grid
        >>> Costmap.from_costs(Grid((1, 3), 1.0), np.array([[0, 253, 255]], np.uint8)).occupied.tolist()
        [[False, True, True]]
        """
        grid = getattr(gridmap_or_grid, "grid", gridmap_or_grid)
        c = np.asarray(cost)
        if c.dtype != np.uint8:
            raise ParameterError(f"costmap costs must be an array of uint8 (0..255), got dtype {c.dtype}")
        if c.shape != grid.shape:
            raise ParameterError(f"costmap costs have shape {c.shape}, but the grid has shape {grid.shape}")
        return cls(grid, c >= INSCRIBED_INFLATED_OBSTACLE, source=source, meta=dict(meta or {}), cost=c,
                   inflation=dict(inflation or {}))

    def as_gridmap(self) -> GridMap:
        """The plain :class:`GridMap` of the blocked cells (``cost >= 253``)."""
        return GridMap(self.grid, self.occupied, source=self.source, meta=dict(self.meta))

    # ------------------------------------------------------------------------------------------
    # queries
    # ------------------------------------------------------------------------------------------
    @cached_property
    def _nearest(self) -> tuple[NDArray[np.float64], NDArray[np.int32], NDArray[np.int32]]:
        """Distance (world units) of each cell centre to the nearest lethal cell centre, and that cell."""
        from ..distance.brushfire import brushfire

        lethal = GridMap(self.grid.with_border("open"), self.cost == LETHAL_OBSTACLE)
        dm = brushfire(lethal, metric="euclidean", compute_steps=False, compute_labels=False, compute_gvd=False)
        assert dm.nearest_row is not None and dm.nearest_col is not None
        return (np.ascontiguousarray(dm.distance, dtype=np.float64), np.ascontiguousarray(dm.nearest_row, np.int32),
                np.ascontiguousarray(dm.nearest_col, np.int32))

    def _query(self, points: ArrayLike) -> tuple[Any, NDArray[np.float64], float, float, float]:
        from ..core.coords import as_points

        p = np.ascontiguousarray(as_points(points, "points"), dtype=np.float64)
        x0, y0 = self.grid.origin
        return _kernel_navfn(), p, float(x0), float(y0), float(self.grid.resolution)

    def cost_at(self, points: ArrayLike) -> NDArray[np.uint8]:
        """The cost of the cell containing each world point (255, no information, outside the grid).

        Parameters
        ----------
        points : array_like, shape (N, 2) or (2,)

        Returns
        -------
        ndarray of uint8, shape (N,)

        Examples
        --------
        >>> import numpy as np
        >>> from gridfield.core.grid import Grid
        >>> cm = Costmap.from_costs(Grid((1, 2), 1.0), np.array([[7, 9]], np.uint8))
        >>> cm.cost_at([[0.5, 0.5], [1.5, 0.2], [5.0, 0.0]]).tolist()
        [7, 9, 255]
        """
        k, p, x0, y0, res = self._query(points)
        out: NDArray[np.uint8] = k.query_cost(self.cost, p, x0, y0, res)
        return out

    def distance(self, points: ArrayLike) -> NDArray[np.float64]:
        """Distance to the nearest lethal cell: bilinear between the four nearest cell centres' exact
        Euclidean distances (exact at cell centres); ``nan`` outside the grid, ``inf`` without obstacles.

        Parameters
        ----------
        points : array_like, shape (N, 2) or (2,)
            World points.

        Returns
        -------
        ndarray of float64, shape (N,)
            World units (the distance between cell centres, as the inflation uses).

        Examples
        --------
        >>> import numpy as np
        >>> from gridfield.core.grid import Grid
        >>> cm = Costmap.from_costs(Grid((1, 4), 1.0), np.array([[254, 0, 0, 0]], np.uint8))
        >>> cm.distance([[2.5, 0.5], [3.0, 0.5], [9.0, 0.5]]).tolist()
        [2.0, 2.5, nan]
        """
        k, p, x0, y0, res = self._query(points)
        d = self._nearest[0]
        out: NDArray[np.float64] = k.query_bilinear(d, d, p, x0, y0, res, False)
        return out

    @cached_property
    def _unit_gradient(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        d, nr, nc = self._nearest
        rows, cols = np.indices(self.grid.shape)
        with np.errstate(invalid="ignore", divide="ignore"):
            gx = np.where((d > 0) & np.isfinite(d), (cols - nc) * self.grid.resolution / d, 0.0)
            gy = np.where((d > 0) & np.isfinite(d), (rows - nr) * self.grid.resolution / d, 0.0)
        return np.ascontiguousarray(gx, dtype=np.float64), np.ascontiguousarray(gy, dtype=np.float64)

    def gradient(self, points: ArrayLike) -> NDArray[np.float64]:
        """Gradient of :meth:`distance`'s exact field: at each cell centre the unit vector away from its
        nearest lethal cell (0 on lethal cells and without obstacles), bilinear in between.

        Parameters
        ----------
        points : array_like, shape (N, 2) or (2,)

        Returns
        -------
        ndarray of float64, shape (N, 2)
            ``(d/dx, d/dy)``; ``nan`` outside the grid.

        Examples
        --------
        >>> import numpy as np
        >>> from gridfield.core.grid import Grid
        >>> cm = Costmap.from_costs(Grid((1, 4), 1.0), np.array([[254, 0, 0, 0]], np.uint8))
        >>> cm.gradient([[2.5, 0.5]]).tolist()
        [[1.0, 0.0]]
        """
        k, p, x0, y0, res = self._query(points)
        gx, gy = self._unit_gradient
        out: NDArray[np.float64] = k.query_bilinear(gx, gy, p, x0, y0, res, True)
        return out

    def nearest_obstacle(self, points: ArrayLike) -> NDArray[np.float64]:
        """The centre of the lethal cell nearest to each point, among the nearest lethal cells of the
        four surrounding cell centres (exact at cell centres); ``nan`` outside the grid or without obstacles.

        Parameters
        ----------
        points : array_like, shape (N, 2) or (2,)

        Returns
        -------
        ndarray of float64, shape (N, 2)
            World coordinates.

        Examples
        --------
        >>> import numpy as np
        >>> from gridfield.core.grid import Grid
        >>> cm = Costmap.from_costs(Grid((2, 4), 1.0), np.array([[254, 0, 0, 0], [0, 0, 0, 254]], np.uint8))
        >>> cm.nearest_obstacle([[1.2, 0.5], [2.9, 1.4]]).tolist()
        [[0.5, 0.5], [3.5, 1.5]]
        """
        k, p, x0, y0, res = self._query(points)
        _, nr, nc = self._nearest
        out: NDArray[np.float64] = k.query_nearest(nr, nc, p, x0, y0, res)
        return out


def inflate(
    gridmap: GridMap,
    *,
    robot_radius: float = DEFAULT_ROBOT_RADIUS,
    inflation_radius: float = DEFAULT_INFLATION_RADIUS,
    cost_scaling_factor: float = DEFAULT_COST_SCALING_FACTOR,
    keep_unknown: bool = False,
    unknown: ArrayLike | None = None,
    lut_precision: int | None = None,
) -> Costmap:
    """The Nav2 inflated costmap of an occupancy grid (see the module docstring for the rule).

    Parameters
    ----------
    gridmap : GridMap
        Occupied cells are the lethal obstacles (of a :class:`Costmap`: its cells of cost 254). Outside the grid is not an obstacle (Nav2's
        inflation does not inflate the map's edge), whatever ``gridmap.grid.border`` says.
    robot_radius : float
        The inscribed radius (m), ``>= 0`` (Nav2's ``robot_radius`` default 0.1).
    inflation_radius : float
        Radius (m) up to which costs are spread, ``>= robot_radius`` (default 0.55).
    cost_scaling_factor : float
        Exponential decay rate (1/m), ``>= 0`` (default 10).
    keep_unknown : bool
        Keep the cells of ``unknown`` at 255 (no information) unless the inflation gives them 253 or
        254, as Nav2 does with ``inflate_unknown: false``; unknown cells are never obstacles themselves.
    unknown : array of bool, optional
        The unknown cells (e.g. ``ros_occupancy_values(yaml) == -1``); needed with ``keep_unknown``.
    lut_precision : int, optional
        ``None``: the exact distance (the legacy layer). ``100``: the current layer's lookup table
        (distances rounded to 1/100 cell in float32).

    Returns
    -------
    Costmap

    Raises
    ------
    ParameterError
        A negative radius or factor, ``inflation_radius < robot_radius``, ``keep_unknown`` without
        an ``unknown`` mask of the grid's shape.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((1, 14), bool); occ[0, 0] = True
    >>> inflate(GridMap(Grid((1, 14), 0.05), occ)).cost.tolist()
    [[254, 253, 253, 152, 92, 56, 34, 20, 12, 7, 4, 2, 0, 0]]
    >>> inflate(GridMap(Grid((1, 14), 0.05), occ), lut_precision=100).cost[0, :4].tolist()
    [254, 253, 253, 152]
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"gridmap must be a GridMap, got {type(gridmap).__name__}")
    r, big_r, k, lut = _check_inflation(robot_radius, inflation_radius, cost_scaling_factor, lut_precision)
    grid = gridmap.grid
    res = grid.resolution
    # a costmap's own obstacles are its lethal cells (not the inscribed or unknown ones it blocks)
    obstacles = gridmap.cost == LETHAL_OBSTACLE if isinstance(gridmap, Costmap) else np.asarray(gridmap.occupied, bool)
    unk: NDArray[np.bool_] | None = None
    if keep_unknown:
        if unknown is None:
            raise ParameterError("keep_unknown needs the unknown cells (unknown=mask of the grid's shape)")
        unk = np.asarray(unknown)
        if unk.shape != grid.shape or unk.dtype != np.bool_:
            raise ParameterError(f"unknown must be a bool array of shape {grid.shape}, got {unk.dtype} {unk.shape}")
        obstacles = obstacles & ~unk
    elif unknown is not None:
        raise ParameterError("unknown is read only with keep_unknown=True")
    from ..distance.brushfire import brushfire

    dm = brushfire(GridMap(grid.with_border("open"), obstacles), metric="euclidean", compute_steps=False,
                   compute_nearest=False, compute_labels=False, compute_gvd=False)
    cells = dm.distance / res  # exact up to rounding: squared integer distances
    with np.errstate(invalid="ignore", over="ignore"):
        n = np.rint(np.where(np.isfinite(cells), cells * cells, -1.0))
    reach = float(max(0.0, math.ceil(big_r / res)))  # Costmap2D::cellDistance
    within = (n >= 0) & (n <= reach * reach)
    nn = n[within]
    if lut is None:
        costs = compute_cost(np.sqrt(nn), resolution=res, robot_radius=r, cost_scaling_factor=k)
    else:
        d32 = np.sqrt(nn.astype(np.float32))
        lut_max = int(reach) * lut + 1
        scaled = np.minimum((d32 * np.float32(lut) + np.float32(0.5)).astype(np.int64), lut_max)
        table = compute_cost(np.arange(lut_max + 1, dtype=np.float64) / lut, resolution=res, robot_radius=r,
                             cost_scaling_factor=k)
        costs = table[scaled]
    cost = np.zeros(grid.shape, dtype=np.uint8)
    cost[within] = costs
    if unk is not None:
        cost = np.where(unk & (cost < INSCRIBED_INFLATED_OBSTACLE), np.uint8(NO_INFORMATION), cost)
    inflation = {"robot_radius": r, "inflation_radius": big_r, "cost_scaling_factor": k, "lut_precision": lut,
                 "keep_unknown": bool(keep_unknown)}
    return Costmap.from_costs(grid, cost.astype(np.uint8), inflation, source=gridmap.source,
                              meta={**gridmap.meta, "costmap": "inflated"})
