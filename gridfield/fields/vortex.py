"""The vortex field: the lattice, the field, and the follower's step scaling.

The vortex field is sampled on a lattice of nodes (``X = -5:0.4:5``, both ends included): a
repulsive charge at the start, a quadratic attraction to the goal, and charges sampled on a circle
around each circular obstacle, with a rotational term that turns the follower around the circles
(:func:`vortex_field`). As a gridfield :class:`~gridfield.core.grid.Grid` the nodes are the cell
centres (:func:`vortex_lattice`); :func:`gridfield.fields.potential.build_field` builds this field for
``model="vortex"``. The rotational part has no potential, so the follower cannot use a normalized
step: its nearest-node follower moves from node to node with steps scaled by the matrix 2-norms of the
two force arrays (:func:`_vortex_norms`, read by :func:`gridfield.following.follower.follow`).

Examples
--------
>>> f = vortex_field(Grid((13, 13), 0.5, (-3.25, -3.25)), [[0.0, 0.0, 1.0]], (0, 3), (0, -3), ko=1.0)
>>> f.grid.shape, f.params["model"], float(f.potential[6, 6])
((13, 13), 'vortex', inf)
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.coords import as_xy
from ..core.errors import GridfieldError, ParameterError
from ..core.grid import Grid, GridMap
from ..core.params import FIELD_GROUPS, Vortex, check, known, names, resolve
from ..core.results import Field, GradientField
from ..distance.brushfire import brushfire

__all__ = ["vortex_field", "vortex_follower_params", "vortex_lattice", "vortex_model_field"]


def vortex_lattice(bounds: Sequence[float], spacing: float, *, border: str = "open") -> Grid:
    """The grid whose cell **centres** are the vortex field's lattice nodes ``xmin:spacing:xmax`` (MATLAB colon).

    The vortex field is sampled at ``X = -5:0.4:5`` (26 nodes per axis, both ends included). As a
    gridfield :class:`Grid` that is 26 x 26 cells of size 0.4 with origin ``(-5.2, -5.2)``: the
    grid covers half a spacing beyond the bounds on each side.

    Parameters
    ----------
    bounds : (xmin, ymin, xmax, ymax)
        The first and last nodes along each axis (the last one where the colon range ends).
    spacing : float
        Node spacing (> 0).
    border : {"open", "wall"}

    Returns
    -------
    Grid
        Cell size ``spacing``, cell centres on the nodes.

    Examples
    --------
    >>> g = vortex_lattice((-5, -5, 5, 5), 0.4)
    >>> g.shape, g.origin, round(float(g.cell_centers()[0][-1]), 12)
    ((26, 26), (-5.2, -5.2), 5.0)
    """
    spacing = check("spacing", spacing)
    xmin, ymin, xmax, ymax = (float(b) for b in bounds)
    from ..core.limits import check_cells

    check_cells(((ymax - ymin) / spacing + 1, (xmax - xmin) / spacing + 1), f"vortex lattice at spacing {spacing:g}")
    nx = math.floor((xmax - xmin) / spacing + 1e-9) + 1
    ny = math.floor((ymax - ymin) / spacing + 1e-9) + 1
    return Grid((ny, nx), spacing, (xmin - spacing / 2, ymin - spacing / 2), border)  # type: ignore[arg-type]


def _circles_of(obj: Any) -> NDArray[np.float64]:
    from ..geometry.world import World

    if isinstance(obj, World):
        bad = [ob for ob in obj.obstacles if ob.kind != "circle"]
        if bad:
            raise ParameterError(
                f"the vortex model samples charges on circles; obstacle {bad[0].id} is a {bad[0].kind}"
            )
        return np.array([(*cast("tuple[float, float]", ob.center), ob.radius) for ob in obj.obstacles], dtype=np.float64).reshape(-1, 3)
    c = np.asarray(obj, dtype=np.float64)
    if c.ndim != 2 or c.shape[1] != 3 or not np.all(np.isfinite(c)) or np.any(c[:, 2] <= 0):
        raise ParameterError(f"circles must be rows (cx, cy, radius) with radius > 0, got {obj!r}")
    return c


def vortex_field(
    grid: Grid | GridMap | None,
    circles: Any,
    start: ArrayLike,
    goal: ArrayLike,
    *,
    ka: float = 25.0,
    kr: float = 30.0,
    ko: float = 5.0,
    sample_radius: float | None = None,
    spacing: float | None = None,
) -> Field:
    """The vortex field: start repulsion, goal attraction, boundary charges with a rotational term.

    On the lattice nodes (the cell centres of ``grid``):

    - ``Vr = kr / |q - start|``, ``Va = 0.5*ka*|q - goal|**2``,
    - ``Vo = sum_i ko / |q - s_i|`` over samples ``s_i`` on a circle of radius ``sample_radius``
      around each obstacle circle's centre, at angles ``th = (0 : 0.1*spacing : 2)*pi`` (MATLAB
      colon, so 0 and 2*pi both appear: the sample at angle 0 counts twice, as in the seed),
    - gradients by :func:`numpy.gradient` at the lattice spacing (MATLAB ``gradient``):
      ``fX = -dVr/dx - dVa/dx - dVo/dx - dVo/dy``, ``fY = -dVr/dy - dVa/dy - dVo/dy + dVo/dx``.

    The returned :class:`Field` has ``potential = Vr + Va + Vo`` and ``(grad_x, grad_y) = -(fX, fY)``
    (the force is ``-grad`` as for every Field; the rotational part has no potential). Obstacle
    cells (conservative rasterization of the circles on the lattice cells) hold ``+inf`` and zero
    gradients. The seed writes the samples as ``xo - cx`` (centred on ``(-cx, -cy)``); here they are
    centred on ``(cx, cy)``, which is the same set for the seed's mirror-symmetric pair of circles.

    Parameters
    ----------
    grid : Grid, GridMap or None
        The lattice (its cell centres are the nodes). A GridMap also supplies the occupancy.
        ``None``: :func:`vortex_lattice` of the world's bounds at ``spacing``.
    circles : World or array of rows (cx, cy, radius)
        A World must hold only circles.
    start, goal : (x, y)
    ka, kr, ko : float
        Gains (>= 0); the seed's 25, 30, 5 converge, ``ko = 10`` does not.
    sample_radius : float, optional
        Radius of the charge circles (default 1.05 x each circle's radius: the seed's 2.1).
    spacing : float, optional
        Lattice spacing; only with ``grid=None`` (else it must equal ``grid.resolution``).

    Returns
    -------
    Field
        ``model="vortex"`` in its params; ``distance`` is the Euclidean brushfire of its map.

    Examples
    --------
    >>> f = vortex_field(Grid((13, 13), 0.5, (-3.25, -3.25)), [[0.0, 0.0, 1.0]], (0, 3), (0, -3), ko=1.0)
    >>> f.grid.shape, float(f.potential[6, 6]), bool(np.isfinite(f.potential[0, 0]))
    ((13, 13), inf, True)
    """
    from ..geometry.world import World

    cir = _circles_of(circles)
    start_xy, goal_xy = as_xy(start, "start"), as_xy(goal, "goal")
    ka, kr, ko = check("ka", ka), check("kr", kr), check("ko", ko)
    if sample_radius is not None:
        sample_radius = check("sample_radius", sample_radius)
    gridmap: GridMap | None = grid if isinstance(grid, GridMap) else None
    if grid is None:
        if not isinstance(circles, World):
            raise ParameterError("vortex_field needs a grid or a World (for its bounds) when grid is None")
        if spacing is None:
            raise ParameterError("vortex_field needs spacing (the lattice spacing) when grid is None")
        lattice = vortex_lattice(circles.bounds, spacing, border=circles.border)
    else:
        lattice = grid.grid if isinstance(grid, GridMap) else grid
        if spacing is not None and not math.isclose(check("spacing", spacing), lattice.resolution):
            raise ParameterError(f"spacing {spacing:g} differs from the grid's resolution {lattice.resolution:g}")
    h = lattice.resolution
    if gridmap is None:
        if isinstance(circles, World):
            from ..geometry.rasterize import rasterize

            gridmap = rasterize(circles, h, bounds=lattice.bounds)
            if gridmap.grid.shape != lattice.shape:  # pragma: no cover - Grid.covering rounding
                raise GridfieldError(f"lattice {lattice.shape} and rasterized grid {gridmap.grid.shape} differ")
            gridmap = GridMap(lattice, gridmap.occupied, gridmap.obstacle_id, circles, circles.source)
        else:
            gridmap = GridMap(lattice, _circle_occupancy(lattice, cir))

    xs, ys = lattice.cell_centers()
    X, Y = np.meshgrid(xs, ys)
    Vr = np.zeros_like(X)
    if kr:  # (kr = 0: no charge, not 0 / 0 at a node on the start)
        with np.errstate(divide="ignore"):
            Vr = kr / np.hypot(X - start_xy[0], Y - start_xy[1])
    Va = 0.5 * ka * ((X - goal_xy[0]) ** 2 + (Y - goal_xy[1]) ** 2)
    n_th = math.floor(2.0 / (0.1 * h) + 1e-9) + 1
    th = np.arange(n_th) * (0.1 * h) * np.pi
    Vo = np.zeros_like(X)
    # a node on a sample (or within ko / DBL_MAX of it: a tiny sample_radius puts every sample on
    # the circle's centre) has an infinite charge potential, not an overflow warning
    with np.errstate(divide="ignore", over="ignore"):
        for cx, cy, r in cir if ko else ():  # (ko = 0: no charges, not 0 / 0 at a node on a sample)
            rad = sample_radius if sample_radius is not None else 1.05 * r
            for xo, yo in zip(cx + rad * np.cos(th), cy + rad * np.sin(th), strict=True):
                Vo += ko / np.hypot(X - xo, Y - yo)
    with np.errstate(invalid="ignore"):
        fyr, fxr = _np_gradient(Vr, h)
        fya, fxa = _np_gradient(Va, h)
        fyo, fxo = _np_gradient(Vo, h)
        fX = -fxr - fxa - fxo - fyo
        fY = -fyr - fya - fyo + fxo
        U = Vr + Va + Vo
    occ = gridmap.occupied
    U[occ] = np.inf
    gx, gy = -fX, -fY
    gx[occ] = 0.0
    gy[occ] = 0.0
    # the field's parameters as potential.resolve_params resolves them: the field concerns, resolved at
    # unit 1; the vortex model is defined by finite differences on its lattice
    full = resolve({"model": "vortex", "ka": ka, "kr": kr, "ko": ko, "spacing": h, "sample_radius": sample_radius},
                   unit=1.0)
    params = {k: full[k] for k in names(*FIELD_GROUPS)}
    params["gradient"] = "finite_difference"
    return Field(gridmap, U, gx, gy, goal_xy, params, brushfire(gridmap, metric="euclidean"))


def _np_gradient(V: NDArray[np.float64], h: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(dV/dy, dV/dx)`` like MATLAB's ``gradient`` (central inside, one-sided at the edges)."""
    if min(V.shape) < 2:
        raise ParameterError(f"the vortex lattice needs at least 2 x 2 nodes, got {V.shape}")
    gy, gx = np.gradient(V, h, h)
    return np.asarray(gy, dtype=np.float64), np.asarray(gx, dtype=np.float64)


def _circle_occupancy(grid: Grid, circles: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Cells whose closed square meets a closed disc."""
    xs, ys = grid.cell_centers()
    half = grid.resolution / 2
    occ = np.zeros(grid.shape, bool)
    for cx, cy, r in circles:
        dx = np.maximum(np.abs(xs - cx) - half, 0.0)
        dy = np.maximum(np.abs(ys - cy) - half, 0.0)
        occ |= dx[None, :] ** 2 + dy[:, None] ** 2 <= r * r
    return occ


def vortex_model_field(gridmap: GridMap, goal: ArrayLike, p: Mapping[str, Any]) -> Field:
    """The vortex model's Field for :func:`gridfield.fields.potential.build_field` (``model="vortex"``): the
    field of :func:`vortex_field` on the lattice of the map's world.

    Parameters
    ----------
    gridmap : GridMap
        A map rasterized from a world of circles with a start point (``gridmap.world``).
    goal : (x, y)
        The goal.
    p : mapping
        Resolved field parameters (:func:`gridfield.fields.potential.resolve_params`): ``ka``, ``kr``, ``ko``,
        ``sample_radius`` and ``spacing`` (None: the map's resolution).

    Returns
    -------
    Field
        On the lattice of spacing ``spacing`` over the world's bounds; its ``params`` are ``p`` with the
        spacing used.

    Raises
    ------
    ParameterError
        A map without a vector world, a world without a start, or obstacles that are not circles.

    Examples
    --------
    >>> from gridfield.io import bundled_map, read_world
    >>> from gridfield.fields.potential import resolve_params
    >>> from gridfield.geometry.rasterize import rasterize
    >>> w = read_world(bundled_map("seed003_circles.yaml"))
    >>> f = vortex_model_field(rasterize(w, 0.4), w.goal, resolve_params(w.params, unit=0.4))
    >>> f.map.shape, f.params["spacing"]
    ((26, 26), 0.4)
    """
    from ..geometry.world import World

    world = gridmap.world
    if not isinstance(world, World) or world.start is None:
        raise ParameterError(
            "the vortex model needs a world file with circle obstacles and a start point "
            f"({gridmap.source or 'this map'} has {'no start' if isinstance(world, World) else 'no vector world'})"
        )
    spacing = p["spacing"] if p["spacing"] is not None else gridmap.grid.resolution
    lattice = vortex_lattice(world.bounds, spacing, border=world.border)
    _circles_of(world)  # reject non-circles before rasterizing
    from ..geometry.rasterize import rasterize

    raster = rasterize(world, spacing, bounds=lattice.bounds)
    lattice_map = GridMap(lattice, raster.occupied, raster.obstacle_id, world, world.source)
    g = lattice_map.check_point("goal", goal)
    field = vortex_field(lattice_map, world, world.start, g, ka=p["ka"], kr=p["kr"], ko=p["ko"],
                         sample_radius=p["sample_radius"])
    return Field(field.map, field.potential, field.grad_x, field.grad_y, field.goal, {**p, "spacing": spacing},
                 field.distance)


def _vortex_norms(field: GradientField, params: Mapping[str, Any]) -> tuple[float, float]:
    """Matrix 2-norms of the vortex field's force components ``fX``, ``fY`` over the whole lattice.

    The seed's arrays are defined everywhere, inside the circles too, while a Field holds zeros on
    obstacle cells; the norms are therefore taken from the same field rebuilt on the lattice without
    occupancy (when the field's map carries its world), else from the field's own arrays.
    """
    from ..geometry.world import World

    world = getattr(field.map, "world", None)
    gx, gy = field.grad_x, field.grad_y
    if isinstance(world, World) and world.start is not None:
        open_map = GridMap(field.map.grid, np.zeros(field.map.grid.shape, bool))
        v = known(params).group(Vortex)
        full = vortex_field(open_map, world, world.start, field.goal, ka=float(v.ka), kr=float(v.kr), ko=float(v.ko),
                            sample_radius=v.sample_radius)
        gx, gy = full.grad_x, full.grad_y
    nx = float(np.linalg.norm(np.asarray(gx, dtype=float), 2))
    ny = float(np.linalg.norm(np.asarray(gy, dtype=float), 2))
    if not (nx > 0 and ny > 0 and math.isfinite(nx) and math.isfinite(ny)):
        raise GridfieldError(f"the vortex field's force components have matrix norms {nx:g}, {ny:g}; "
                             "cannot scale the steps (the nearest-node follower divides by them)")
    return nx, ny


def vortex_follower_params(field: GradientField, params: Mapping[str, Any]) -> dict[str, Any]:
    """The follower parameters of the vortex field's nearest-node follower on a vortex Field
    (what :func:`gridfield.following.follower.follow_field` uses for ``model="vortex"``).

    The nearest-node follower steps ``x += spacing * (Fx / ||fX||_2, Fy / ||fY||_2)``, where ``||.||_2`` is the
    matrix 2-norm (largest singular value) of each force component's array: the scaled rule with
    one gain per axis, nearest-node sampling, tolerance 0.4 and no jitter rule (given values win,
    except the step rule).

    Parameters
    ----------
    field : GradientField
        A vortex Field (:func:`vortex_model_field`).
    params : mapping
        The follower and field parameters given.

    Returns
    -------
    dict
        ``params`` with ``sampling``, ``tolerance``, ``confine_window`` defaulted, ``step_rule="scaled"``
        and ``alpha`` the per-axis gains ``(spacing / ||fX||_2, spacing / ||fY||_2)``.

    Examples
    --------
    >>> from gridfield.io import bundled_map, read_world
    >>> from gridfield.fields.potential import build_field
    >>> from gridfield.geometry.rasterize import rasterize
    >>> w = read_world(bundled_map("seed003_circles.yaml"))
    >>> f = build_field(rasterize(w, 0.4), w.goal, w.params)
    >>> p = vortex_follower_params(f, w.params)
    >>> p["step_rule"], p["sampling"], [round(a, 6) for a in p["alpha"]]
    ('scaled', 'nearest', [0.000293, 0.000131])
    """
    merged = dict(params)
    spacing = known(merged).group(Vortex).spacing
    spacing = field.map.grid.resolution if spacing is None else float(spacing)  # the registry's scale rule
    merged.setdefault("sampling", "nearest")
    merged.setdefault("tolerance", 0.4)
    merged.setdefault("confine_window", 0)  # the nearest-node follower: no jitter rule
    merged["step_rule"] = "scaled"
    nx, ny = _vortex_norms(field, merged)
    merged["alpha"] = (spacing / nx, spacing / ny)
    return merged
