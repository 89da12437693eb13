"""Potentials and gradient arrays (gridfield.fields.potential) against closed forms and brute force."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given
from hypothesis import strategies as st
from scipy import ndimage

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.core.params import FIELD_GROUPS, names
from gridfield.distance.brushfire import brushfire
from gridfield.fields.potential import (
    Field,
    attractive,
    build_field,
    field_distance_map,
    finite_difference_gradient,
    repulsive,
    resolve_params,
    vortex_field,
    vortex_lattice,
)
from gridfield.geometry.rasterize import rasterize
from gridfield.geometry.world import world_from_dict
from gridfield.io import bundled_map, load_field, read_world, save_field

#: what build_field reads and keeps, in Field.params's order (the old potential.DEFAULTS)
FIELD_NAMES = ("zeta", "d_star", "eta", "q_star", "repulsive_power", "repulsion", "metric", "gradient", "saturate",
               "model", "ka", "kr", "ko", "spacing", "sample_radius")


def centres(grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    xs, ys = grid.cell_centers()
    return np.meshgrid(xs, ys)


def blocks_map(border: str = "open") -> GridMap:
    """40 x 56 cells of 0.25 with four rectangular blocks (convex: D is C1 within each label)."""
    occ = np.zeros((40, 56), bool)
    occ[5:12, 6:20] = True
    occ[25:33, 10:14] = True
    occ[15:30, 35:45] = True
    occ[2:4, 48:53] = True
    return GridMap(Grid((40, 56), 0.25, border=border), occ)


# ------------------------------------------------------------------------------------------------
# parameters
# ------------------------------------------------------------------------------------------------
def test_resolve_params_defaults_and_passthrough():
    p = resolve_params(None, unit=0.5)
    # the field's parameters (params.FIELD_GROUPS), written out here as the reference
    assert list(p) == list(FIELD_NAMES) == list(names(*FIELD_GROUPS))
    # scaled defaults: q_star 4 cells, d_star 2 q_star, eta balancing the force at q_star/2
    assert (p["zeta"], p["d_star"], p["q_star"], p["repulsive_power"]) == (1.0, 4.0, 2.0, 2.0)
    rep_at_half = p["eta"] * (1 / 1.0 - 1 / 2.0) / 1.0**2
    assert rep_at_half == pytest.approx(p["zeta"] * p["d_star"])
    assert (p["repulsion"], p["metric"], p["gradient"], p["model"]) == ("nearest", "euclidean", "analytic", "khatib")
    q = resolve_params({"zeta": 3, "step": 0.1, "alpha": 2.0, "tolerance": 0.1})
    assert q["zeta"] == 3.0 and isinstance(q["zeta"], float)
    assert (q["step"], q["alpha"], q["tolerance"]) == (0.1, 2.0, 0.1)


@pytest.mark.parametrize(
    ("params", "words"),
    [
        ({"zeta": -1}, ["zeta", ">= 0", "-1"]),
        ({"eta": -0.5}, ["eta", "-0.5"]),
        ({"eta": math.inf}, ["eta", "finite"]),
        ({"zeta": math.nan}, ["zeta"]),
        ({"q_star": 0}, ["q_star", "> 0"]),
        ({"q_star": -2}, ["q_star"]),
        ({"d_star": -1}, ["d_star"]),
        ({"repulsive_power": -1}, ["repulsive_power"]),
        ({"saturate": 0}, ["saturate"]),
        ({"ko": -5}, ["ko"]),
        ({"spacing": 0}, ["spacing"]),
        ({"zeta": "big"}, ["zeta", "'big'"]),
        ({"eta": True}, ["eta", "True"]),
        ({"repulsion": "all"}, ["repulsion", "'nearest'", "'sum'", "'all'"]),
        ({"metric": "manhattan"}, ["metric", "'euclidean'", "'chessboard'", "'taxicab'"]),
        ({"gradient": "numeric"}, ["gradient", "'analytic'", "'finite_difference'"]),
        ({"model": "harmonic"}, ["model", "'khatib'", "'vortex'"]),
        ({"zetta": 1}, ["zetta", "did you mean 'zeta'"]),
        ({"repulsive_power": 3, "gradient": "finite_difference"}, ["finite_difference", "repulsive_power"]),
        ({"model": "vortex", "gradient": "analytic"}, ["vortex", "finite_difference"]),
    ],
)
def test_bad_params_raise_with_a_clear_message(params, words):
    with pytest.raises(ParameterError) as e:
        resolve_params(params)
    msg = str(e.value)
    assert "\n" not in msg
    for w in words:
        assert w in msg, (w, msg)
    occ = np.zeros((4, 4), bool)
    with pytest.raises(ParameterError):
        build_field(GridMap(Grid((4, 4), 1.0), occ), (1.5, 1.5), params)


def test_array_functions_check_their_options():
    gm = blocks_map()
    d = brushfire(gm, metric="euclidean")
    with pytest.raises(ParameterError, match="mode must be one of 'nearest', 'sum'"):
        repulsive(d, mode="both")
    with pytest.raises(ParameterError, match="q_star"):
        repulsive(d, q_star=0.0)
    with pytest.raises(ParameterError, match="power=2"):
        repulsive(d, power=3, gradient="finite_difference")
    with pytest.raises(ParameterError, match="zeta"):
        attractive(gm.grid, (1, 1), zeta=-1)
    with pytest.raises(ParameterError, match="goal"):
        attractive(gm.grid, (1, math.nan))


def test_goal_outside_or_inside_an_obstacle():
    gm = blocks_map()
    with pytest.raises(GridfieldError, match="inside an obstacle"):
        build_field(gm, (3.0, 2.0))
    with pytest.raises(GridfieldError, match="outside the map"):
        build_field(gm, (30.0, 2.0))
    with pytest.raises(ParameterError):
        build_field(gm, (math.nan, 2.0))


# ------------------------------------------------------------------------------------------------
# attractive
# ------------------------------------------------------------------------------------------------
@given(
    zeta=st.floats(0.01, 10), d_star=st.floats(0.05, 20), angle=st.floats(0, 2 * math.pi),
    gx=st.floats(-5, 5), gy=st.floats(-5, 5),
)
def test_attractive_continuous_at_d_star(zeta, d_star, angle, gx, gy):
    eps = 1e-7 * max(d_star, 1.0)
    # a one-row grid whose two cell centres lie just inside and just outside d_star along `angle`
    ux, uy = math.cos(angle), math.sin(angle)
    inside = (gx + (d_star - eps) * ux, gy + (d_star - eps) * uy)
    outside = (gx + (d_star + eps) * ux, gy + (d_star + eps) * uy)
    vals = []
    for px, py in (inside, outside):
        grid = Grid((1, 1), 1e-3, (px - 5e-4, py - 5e-4))
        U, ax, ay = attractive(grid, (gx, gy), zeta=zeta, d_star=d_star)
        vals.append((U[0, 0], ax[0, 0], ay[0, 0]))
    (u0, x0, y0), (u1, x1, y1) = vals
    scale = zeta * d_star
    assert abs(u1 - u0) <= 4 * eps * scale + 1e-9 * scale * d_star
    assert math.hypot(x1 - x0, y1 - y0) <= 4 * eps * zeta + 1e-9 * scale
    # the value at d_star is 0.5*zeta*d_star**2 and the gradient magnitude zeta*d_star
    assert abs(u0 - 0.5 * zeta * d_star**2) <= 2 * eps * scale + 1e-12 * scale * d_star
    assert abs(math.hypot(x1, y1) - zeta * d_star) <= 1e-9 * scale


@given(zeta=st.floats(0, 5), d_star=st.sampled_from([math.inf, 0.0, 0.7, 3.0]),
       gx=st.floats(-1, 6), gy=st.floats(-1, 4))
def test_attractive_closed_forms(zeta, d_star, gx, gy):
    grid = Grid((9, 13), 0.5, (-0.3, -0.2))
    X, Y = centres(grid)
    dx, dy = X - gx, Y - gy
    d = np.hypot(dx, dy)
    U, ax, ay = attractive(grid, (gx, gy), zeta=zeta, d_star=d_star)
    with np.errstate(divide="ignore", invalid="ignore"):
        if d_star == math.inf:
            eU, k = 0.5 * zeta * d**2, np.full_like(d, zeta)
        elif d_star == 0.0:
            eU, k = zeta * d, np.where(d > 0, zeta / d, 0.0)
        else:
            quad = d <= d_star
            eU = np.where(quad, 0.5 * zeta * d**2, d_star * zeta * d - 0.5 * zeta * d_star**2)
            k = np.where(quad, zeta, zeta * d_star / d)
    np.testing.assert_allclose(U, eU, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(ax, k * dx, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(ay, k * dy, rtol=1e-12, atol=1e-12)
    assert U.dtype == ax.dtype == ay.dtype == np.float64


# ------------------------------------------------------------------------------------------------
# repulsive: closed forms where D is known exactly
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("power", [2, 3, 2.5, 0, 1, 4, 7])
def test_repulsive_single_obstacle_cell(power):
    res, eta, q = 0.5, 1.7, 3.2
    occ = np.zeros((15, 17), bool)
    occ[6, 8] = True
    gm = GridMap(Grid((15, 17), res, (1.0, -2.0)), occ)
    U, gx, gy = repulsive(brushfire(gm, metric="euclidean"), eta=eta, q_star=q, power=power)
    X, Y = centres(gm.grid)
    vx, vy = X - (1.0 + 8.5 * res), Y - (-2.0 + 6.5 * res)
    D = np.hypot(vx, vy)
    free = ~occ
    inside = free & (q > D)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = 1 / D - 1 / q
        eU = np.where(inside, 0.5 * eta * s**2, 0.0)
        m = np.where(inside, eta * s / D**power, 0.0)
        egx, egy = -m * vx / D, -m * vy / D
    np.testing.assert_allclose(U[free], eU[free], rtol=1e-12, atol=0)
    np.testing.assert_allclose(gx[free], egx[free], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(gy[free], egy[free], rtol=1e-12, atol=1e-15)
    assert np.all(U[free & (q <= D)] == 0) and np.all(gx[free & (q <= D)] == 0)
    assert U[6, 8] == np.inf and gx[6, 8] == 0 and gy[6, 8] == 0


def test_repulsive_straight_wall_and_wall_border():
    res, eta, q = 0.25, 2.0, 1.6
    occ = np.zeros((12, 20), bool)
    occ[0, :] = True  # a straight wall along the bottom row: D = row * res
    gm = GridMap(Grid((12, 20), res), occ)
    for mode in ("nearest", "sum"):
        U, gx, gy = repulsive(brushfire(gm, metric="euclidean"), eta=eta, q_star=q, mode=mode)
        D = np.arange(12)[:, None] * res * np.ones((1, 20))
        with np.errstate(divide="ignore"):
            s = 1 / D - 1 / q
        inside = (D > 0) & (q > D)
        np.testing.assert_allclose(U[1:], np.where(inside, 0.5 * eta * s**2, 0.0)[1:], rtol=1e-12)
        np.testing.assert_allclose(gy[1:], np.where(inside, -eta * s / D**2, 0.0)[1:], rtol=1e-12)
        assert np.all(gx[1:] == 0)
    # an empty map with a wall border: the wall is a ring of cells just outside the grid
    wall = GridMap(Grid((12, 20), res, border="wall"), np.zeros((12, 20), bool))
    U, gx, gy = repulsive(brushfire(wall, metric="euclidean"), eta=eta, q_star=q, mode="sum")
    Un, gxn, gyn = repulsive(brushfire(wall, metric="euclidean"), eta=eta, q_star=q, mode="nearest")
    r, c = np.indices((12, 20)) + 1  # distances in cells to the ring below and to the ring on the left
    D = np.minimum.reduce([r, 13 - r, c, 21 - c]) * res
    np.testing.assert_allclose(Un, np.where(q > D, 0.5 * eta * (1 / D - 1 / q) ** 2, 0.0), rtol=1e-12)
    # 'sum' adds the one wall term; away from the corners' diagonals it equals 'nearest'
    unique = np.sort(np.stack([r, 13 - r, c, 21 - c]), axis=0)
    unique = unique[0] < unique[1]
    np.testing.assert_allclose(U, Un, rtol=1e-12)
    np.testing.assert_allclose(gx[unique], gxn[unique], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(gy[unique], gyn[unique], rtol=1e-12, atol=1e-15)
    assert gyn[0, 10] < 0 < gyn[11, 10]  # U falls away from the wall: the force (-grad) points inwards


@pytest.mark.parametrize(("metric", "formula"), [
    ("chessboard", lambda a, b: np.maximum(abs(a), abs(b))),
    ("taxicab", lambda a, b: abs(a) + abs(b)),
])
def test_repulsive_other_metrics(metric, formula):
    occ = np.zeros((9, 9), bool)
    occ[4, 4] = True
    gm = GridMap(Grid((9, 9), 1.0), occ)
    p = {"zeta": 0.0, "eta": 1.0, "q_star": 10.0, "metric": metric}
    f = build_field(gm, (0.5, 0.5), p)
    r, c = np.indices((9, 9)) - 4
    with np.errstate(divide="ignore"):
        D = formula(r, c).astype(float)
        eU = 0.5 * (1 / D - 1 / 10) ** 2
    free = ~occ
    np.testing.assert_allclose(f.potential[free], eU[free], rtol=1e-12)
    # the direction is the Euclidean one from the nearest obstacle cell
    force = np.stack([-f.grad_x, -f.grad_y])[:, free]
    np.testing.assert_allclose(force / np.hypot(*force), np.stack([c, r])[:, free] / np.hypot(r, c)[free], atol=1e-12)
    assert f.params["metric"] == metric and f.distance is not None and f.distance.metric == metric


@pytest.mark.parametrize("repulsion", ["nearest", "sum"])
def test_map_without_obstacles_is_pure_attraction(repulsion):
    gm = GridMap(Grid((6, 7), 0.5, (-1.0, 2.0)), np.zeros((6, 7), bool))
    f = build_field(gm, (0.3, 3.1), {"zeta": 2.0, "d_star": 1.0, "repulsion": repulsion})
    Ua, ax, ay = attractive(gm.grid, (0.3, 3.1), zeta=2.0, d_star=1.0)
    np.testing.assert_array_equal(f.potential, Ua)
    np.testing.assert_array_equal(f.grad_x, ax)
    np.testing.assert_array_equal(f.grad_y, ay)
    assert f.distance is not None and np.all(np.isinf(f.distance.distance))


def test_saturated_distance_seed004():
    gm = blocks_map()
    d = brushfire(gm, metric="euclidean")
    q, R = 3.0, 1.0
    U0, gx0, gy0 = repulsive(d, q_star=q)
    U1, gx1, gy1 = repulsive(d, q_star=q, saturate=R)
    near = ~gm.occupied & (d.distance < R)
    beyond = ~gm.occupied & (d.distance >= R)
    np.testing.assert_array_equal(U1[near], U0[near])
    np.testing.assert_array_equal(gx1[near], gx0[near])
    np.testing.assert_array_equal(gy1[near], gy0[near])
    assert np.all(U1[beyond] == 0) and np.all(gx1[beyond] == 0) and np.all(gy1[beyond] == 0)
    assert np.any(U0[beyond] > 0)
    # the same through build_field (brushfire's own saturate) and for the sum mode
    for rep in ("nearest", "sum"):
        f = build_field(gm, (13.0, 9.5), {"zeta": 0.0, "eta": 1.0, "q_star": q, "saturate": R, "repulsion": rep})
        np.testing.assert_allclose(f.potential[~gm.occupied], U1[~gm.occupied], rtol=1e-12)
        assert f.distance is not None and f.distance.saturate == R


# ------------------------------------------------------------------------------------------------
# analytic gradients agree with finite differences of U
# ------------------------------------------------------------------------------------------------
_BLOCKS: dict[str, tuple[GridMap, object]] = {}


@given(
    goal=st.tuples(st.floats(0.05, 13.95), st.floats(0.05, 9.95)),
    zeta=st.floats(0.0, 3.0), eta=st.floats(0.0, 5.0), q_star=st.floats(0.3, 6.0),
    d_star=st.one_of(st.just(math.inf), st.just(0.0), st.floats(0.2, 10.0)),
    repulsion=st.sampled_from(["nearest", "sum"]), border=st.sampled_from(["open", "wall"]),
)
def test_analytic_gradient_matches_finite_differences(goal, zeta, eta, q_star, d_star, repulsion, border):
    if border not in _BLOCKS:
        gm = blocks_map(border)
        _BLOCKS[border] = gm, brushfire(gm, metric="euclidean")
    gm, dmap = _BLOCKS[border]
    if not gm.is_free(goal)[0]:
        return
    params = {"zeta": zeta, "eta": eta, "q_star": q_star, "d_star": d_star, "repulsion": repulsion}
    f = build_field(gm, goal, params, dmap=dmap)
    fd = build_field(gm, goal, {**params, "gradient": "finite_difference"}, dmap=dmap)
    np.testing.assert_array_equal(fd.potential, f.potential)
    fx, fy = fd.grad_x, fd.grad_y
    res = gm.grid.resolution
    d = f.distance
    assert d is not None
    # where to compare: the whole 3 x 3 stencil free, of one label, off the GVD, D > 2 cells,
    # not inside the grid's outermost ring, and more than 2 cells from the goal (conic kink).
    # U is only C1 where D crosses q_star and where the goal distance crosses d_star: there central
    # differences are first-order accurate only, so stencils straddling those are left out too.
    # The blocks are convex, but the wall is not: its distance has ridges along the diagonals
    # from the corners, which the stencil must not cross either.
    D = d.distance / res
    ok = ndimage.maximum_filter(d.label, 3) == ndimage.minimum_filter(d.label, 3)
    ok &= ~ndimage.maximum_filter(gm.occupied | d.gvd, 3)
    ok &= ndimage.minimum_filter(D, 3) > 2
    if border == "wall":
        r, c = np.indices(gm.shape)
        sides = np.sort(np.stack([r + 1, gm.shape[0] - r, c + 1, gm.shape[1] - c]), axis=0)
        ok &= ~ndimage.maximum_filter(sides[1] - sides[0] <= 1, 3)
    X, Y = centres(gm.grid)
    dg = np.hypot(X - goal[0], Y - goal[1])
    ok &= dg > 2 * res
    ok &= np.abs(dg - d_star) > 1.5 * res
    if repulsion == "nearest":
        ok &= np.abs(d.distance - q_star) > 1.5 * res
    else:  # any obstacle's own distance may cross q_star: keep to cells with every obstacle far or near
        per_obstacle = [ndimage.distance_transform_edt(~(gm.occupied & (d.label == i))) * res
                        for i in np.unique(d.label[gm.occupied])]
        if border == "wall":
            per_obstacle.append(np.minimum.reduce([r + 1, gm.shape[0] - r, c + 1, gm.shape[1] - c]) * res)
        for dist_i in per_obstacle:
            ok &= np.abs(dist_i - q_star) > 1.5 * res
    ok[[0, -1], :] = ok[:, [0, -1]] = False
    # central differences of U equal the Simpson average of the analytic gradient over the stencil
    # (exact for the quadratic attraction, O(h**4) for smooth terms)
    sx = np.zeros_like(fx)
    sy = np.zeros_like(fy)
    sx[:, 1:-1] = (f.grad_x[:, :-2] + 4 * f.grad_x[:, 1:-1] + f.grad_x[:, 2:]) / 6
    sy[1:-1, :] = (f.grad_y[:-2, :] + 4 * f.grad_y[1:-1, :] + f.grad_y[2:, :]) / 6
    _, ax, ay = attractive(gm.grid, goal, zeta=zeta, d_star=d_star)
    _, rx, ry = repulsive(d, eta=eta, q_star=q_star, mode=repulsion)
    scale = ndimage.maximum_filter(np.hypot(ax, ay) + np.hypot(rx, ry), 3) + 1e-12
    err = np.hypot(fx - sx, fy - sy) / scale
    assert np.all(err[ok] <= 0.1), float(err[ok].max())
    # and the gradient arrays are those of U: zero-parameter sanity
    assert np.all(f.grad_x[gm.occupied] == 0) and np.all(fd.grad_x[gm.occupied] == 0)


def test_finite_difference_gradient_handles_inf():
    grid = Grid((5, 6), 0.5, (2.0, 1.0))
    X, Y = centres(grid)
    U = 3 * X - 2 * Y + 0.5 * X * Y
    gx, gy = finite_difference_gradient(U, grid)
    np.testing.assert_allclose(gx, 3 + 0.5 * Y, rtol=1e-12)  # linear along each axis: exact
    np.testing.assert_allclose(gy, -2 + 0.5 * X, rtol=1e-12)
    U2 = U.copy()
    U2[2, 3] = np.inf
    gx2, gy2 = finite_difference_gradient(U2, grid)
    assert np.all(np.isfinite(gx2)) and np.all(np.isfinite(gy2))
    assert gx2[2, 3] == 0 and gy2[2, 3] == 0
    np.testing.assert_allclose(gx2[2, 2], (U[2, 2] - U[2, 1]) / 0.5)  # one-sided away from the inf
    np.testing.assert_allclose(gx2[2, 4], (U[2, 5] - U[2, 4]) / 0.5)
    np.testing.assert_allclose(gy2[1, 3], (U[1, 3] - U[0, 3]) / 0.5)
    U3 = np.full((1, 3), np.inf)
    U3[0, 1] = 1.0
    assert finite_difference_gradient(U3, Grid((1, 3), 1.0))[0].tolist() == [[0.0, 0.0, 0.0]]


# ------------------------------------------------------------------------------------------------
# 'sum' mode against a plain per-obstacle brute force
# ------------------------------------------------------------------------------------------------
def brute_force_sum(gm: GridMap, eta: float, q: float, power: float):
    """Per obstacle id (and the wall), on the full grid: D to the nearest of its cell centres."""
    grid = gm.grid
    res = grid.resolution
    rows, cols = grid.shape
    R, C = np.indices(grid.shape)
    U = np.zeros(grid.shape)
    GX = np.zeros(grid.shape)
    GY = np.zeros(grid.shape)
    unique_everywhere = np.ones(grid.shape, bool)
    groups = [np.argwhere(gm.obstacle_id == i) for i in np.unique(gm.obstacle_id[gm.occupied])]
    if grid.border == "wall":
        ring = [(-1, c) for c in range(-1, cols + 1)] + [(rows, c) for c in range(-1, cols + 1)]
        ring += [(r, -1) for r in range(rows)] + [(r, cols) for r in range(rows)]
        groups.append(np.array(ring))
    for cells in groups:
        vr = R[..., None] - cells[:, 0]  # (rows, cols, n)
        vc = C[..., None] - cells[:, 1]
        d2 = vr**2 + vc**2
        k = np.argmin(d2, axis=-1)
        dmin = np.take_along_axis(d2, k[..., None], -1)[..., 0]
        unique_everywhere &= (d2 == dmin[..., None]).sum(-1) == 1
        fr = np.take_along_axis(vr, k[..., None], -1)[..., 0]
        fc = np.take_along_axis(vc, k[..., None], -1)[..., 0]
        D = np.sqrt(dmin) * res
        inside = (D > 0) & (q > D)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = 1 / D - 1 / q
            m = eta * s / D**power
            U += np.where(inside, 0.5 * eta * s**2, 0)
            GX -= np.where(inside, m * fc / np.sqrt(dmin), 0)
            GY -= np.where(inside, m * fr / np.sqrt(dmin), 0)
    U[gm.occupied] = np.inf
    GX[gm.occupied] = GY[gm.occupied] = 0
    return U, GX, GY, unique_everywhere


@pytest.mark.parametrize(("border", "q", "power"), [("open", 1.5, 3), ("wall", 0.9, 2), ("open", 100.0, 2)])
def test_sum_mode_equals_brute_force(border, q, power):
    w = world_from_dict({
        "bounds": [0, 0, 8, 6], "border": border,
        "obstacles": [
            {"polygon": [[1, 1], [2.6, 1.2], [1.8, 2.7]]},
            {"circle": {"center": [5.0, 4.0], "radius": 0.8}},
            {"segment": [[6.5, 0.5], [7.5, 2.5]]},
            {"polygon": [[2.0, 4.0], [3.4, 4.0], [3.4, 5.2], [2.0, 5.2], [2.7, 4.6]]},  # not convex
            {"circle": {"center": [5.6, 4.6], "radius": 0.5}},  # overlaps the other circle
        ],
    })
    gm = rasterize(w, 0.2)
    U, gx, gy = repulsive(brushfire(gm, metric="euclidean"), eta=1.3, q_star=q, power=power, mode="sum")
    bU, bgx, bgy, unique = brute_force_sum(gm, 1.3, q, power)
    np.testing.assert_allclose(U, bU, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(gx[unique], bgx[unique], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(gy[unique], bgy[unique], rtol=1e-10, atol=1e-12)
    assert unique.mean() > 0.8
    # with one obstacle per label, 'sum' >= 'nearest' everywhere, equal where one obstacle is in range
    Un, _, _ = repulsive(brushfire(gm, metric="euclidean"), eta=1.3, q_star=q, power=power)
    free = ~gm.occupied
    assert np.all(U[free] >= Un[free] * (1 - 1e-12))


def test_sum_mode_without_obstacle_ids_uses_components():
    gm = blocks_map()
    assert gm.obstacle_id is None
    U, _, _ = repulsive(brushfire(gm, metric="euclidean"), q_star=1.0, mode="sum")
    ids = ndimage.label(gm.occupied, np.ones((3, 3)))[0]
    bU, _, _, _ = brute_force_sum(GridMap(gm.grid, gm.occupied, ids), 1.0, 1.0, 2)
    np.testing.assert_allclose(U, bU, rtol=1e-12)


# ------------------------------------------------------------------------------------------------
# seed 000: grid force vs the exact continuous force
# ------------------------------------------------------------------------------------------------
def test_seed000_force_direction_matches_exact_geometry():
    w = read_world(bundled_map("seed000.yaml"))
    gm = rasterize(w, 0.1)
    f = build_field(gm, w.goal, dict(w.params))
    p = f.params
    assert (p["repulsion"], p["repulsive_power"], p["q_star"], p["eta"], p["zeta"]) == ("sum", 3.0, 2.0, 1.0, 1.0)
    _, rx, ry = repulsive(f.distance, eta=1.0, q_star=2.0, power=3, mode="sum")
    X, Y = centres(gm.grid)
    free = ~gm.occupied
    pts = np.c_[X[free], Y[free]]
    dist = np.sort(np.stack([ob.distance(pts) for ob in w.obstacles]), axis=0)
    # points within reach of exactly one obstacle (away from the GVD), 1 <= D <= 1.9
    pick = np.flatnonzero((dist[0] >= 1.0) & (dist[0] <= 1.9) & (dist[1] > 2.2))[::25]
    assert len(pick) > 20
    cells = np.argwhere(free)[pick]
    for (r, c), q in zip(cells, pts[pick], strict=True):
        f_att = -(q - np.asarray(w.goal))
        f_rep = np.zeros(2)
        for ob in w.obstacles:
            near = shapely.get_coordinates(shapely.shortest_line(ob.geometry, shapely.Point(q)))[0]
            v = q - near
            d = np.hypot(*v)
            if d < 2.0:
                f_rep += (1 / d - 1 / 2.0) / d**3 * v / d
        exact = f_att + f_rep
        grid_total = -np.array([f.grad_x[r, c], f.grad_y[r, c]])
        grid_rep = -np.array([rx[r, c], ry[r, c]])

        def angle(a, b):
            return math.degrees(math.acos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1)))

        assert angle(grid_total, exact) < 5.0, (q, grid_total, exact)
        assert angle(grid_rep, f_rep) < 6.0, (q, grid_rep, f_rep)
        # D is the distance to the nearest occupied cell's centre: never more than the exact
        # distance plus half a diagonal cell, so the grid repulsion errs on the strong side
        ratio = np.linalg.norm(grid_rep) / np.linalg.norm(f_rep)
        assert 0.9 < ratio < 2.0, (q, ratio)


# ------------------------------------------------------------------------------------------------
# seed 003: the vortex field
# ------------------------------------------------------------------------------------------------
def seed003_arrays(Ka=25.0, Kr=30.0, Ko=5.0):
    """Seed 003's MATLAB program, line by line in numpy (meshgrid rows are y, like MATLAB)."""
    dh = 0.4
    X = np.arange(-5, 5 + dh / 2, dh)
    Y = np.arange(-5, 5 + dh / 2, dh)
    X, Y = np.meshgrid(X, Y)
    x0 = [0, 4]
    xT = [0, -4]
    Vr = Kr / np.sqrt((X - x0[0]) ** 2 + (Y - x0[1]) ** 2)
    fyr, fxr = np.gradient(Vr, dh, dh)  # MATLAB [fx, fy] = gradient(V, dh, dh)
    Va = 0.5 * Ka * ((X - xT[0]) ** 2 + (Y - xT[1]) ** 2)
    fya, fxa = np.gradient(Va, dh, dh)
    cx1, cy1, cx2, cy2 = 1, 0, -1, 0
    rad = 2 + 0.1
    th = np.arange(0, 2 + 0.1 * dh / 2, 0.1 * dh) * np.pi
    xo = rad * np.cos(th)
    yo = rad * np.sin(th)
    xo1, yo1 = xo - cx1, yo - cy1  # sic: the seed subtracts the centre
    xo2, yo2 = xo - cx2, yo - cy2
    Vo = np.zeros_like(Vr)
    for i in range(len(th)):
        Vo1 = Ko / np.sqrt((X - xo1[i]) ** 2 + (Y - yo1[i]) ** 2)
        Vo2 = Ko / np.sqrt((X - xo2[i]) ** 2 + (Y - yo2[i]) ** 2)
        Vo = Vo + Vo1 + Vo2
    fyo, fxo = np.gradient(Vo, dh, dh)
    fX = -fxr - fxa - fxo - fyo
    fY = -fyr - fya - fyo + fxo
    return X, Y, Vr + Va + Vo, fX, fY, len(th)


@pytest.mark.parametrize("ko", [5.0, 10.0])
def test_vortex_field_reproduces_seed003(ko):
    X, Y, V, fX, fY, n_th = seed003_arrays(Ko=ko)
    assert X.shape == (26, 26) and n_th == 51
    w = read_world(bundled_map("seed003_circles.yaml"))
    gm = rasterize(w, 0.4)  # the world's own raster: 25 x 25 cells, NOT the seed's nodes
    f = build_field(gm, w.goal, {**w.params, "ko": ko})
    assert f.grid.shape == (26, 26) and f.grid.origin == pytest.approx((-5.2, -5.2)) and f.grid.resolution == 0.4
    xs, ys = f.grid.cell_centers()
    np.testing.assert_allclose(xs, X[0], atol=1e-12)
    np.testing.assert_allclose(ys, Y[:, 0], atol=1e-12)
    free = ~f.map.occupied
    assert 0 < f.map.occupied.sum() < 26 * 26 / 2
    np.testing.assert_allclose(f.potential[free], V[free], rtol=1e-12)
    np.testing.assert_allclose(-f.grad_x[free], fX[free], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(-f.grad_y[free], fY[free], rtol=1e-9, atol=1e-9)
    assert np.all(f.potential[~free] == np.inf) and np.all(f.grad_x[~free] == 0) and np.all(f.grad_y[~free] == 0)
    # obstacle cells: closed squares that meet a disc
    half = 0.2
    for cx in (1.0, -1.0):
        dx = np.maximum(np.abs(X - cx) - half, 0)
        dy = np.maximum(np.abs(Y) - half, 0)
        assert np.all(f.map.occupied[np.hypot(dx, dy) < 2 - 1e-9])
    assert f.params["model"] == "vortex" and f.params["spacing"] == 0.4 and f.params["gradient"] == "finite_difference"
    # the array-level function on circles gives the same arrays
    g = vortex_field(vortex_lattice(w.bounds, 0.4), [[1, 0, 2], [-1, 0, 2]], w.start, w.goal, ka=25, kr=30, ko=ko,
                     sample_radius=2.1)
    np.testing.assert_allclose(g.potential[free], V[free], rtol=1e-12)
    np.testing.assert_array_equal(g.map.occupied, f.map.occupied)


def test_vortex_needs_circles_and_a_start():
    w = read_world(bundled_map("seed000.yaml"))
    with pytest.raises(ParameterError, match="circles"):
        build_field(rasterize(w, 0.5), w.goal, {"model": "vortex"})
    occ = np.zeros((5, 5), bool)
    with pytest.raises(ParameterError, match="start"):
        build_field(GridMap(Grid((5, 5), 1.0), occ), (2.5, 2.5), {"model": "vortex"})


# ------------------------------------------------------------------------------------------------
# every model: obstacle cells, dtypes, npz round trip
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("params", [
    {},
    {"repulsion": "sum", "repulsive_power": 3},
    {"gradient": "finite_difference"},
    {"saturate": 0.5, "q_star": 1.0},
    {"d_star": 0.0, "repulsive_power": 1.5},
    {"metric": "taxicab", "repulsion": "sum"},
])
def test_obstacle_cells_are_inf_with_zero_gradient(params):
    gm = blocks_map("wall")
    f = build_field(gm, (13.0, 9.5), params)
    assert isinstance(f, Field) and f.grid is gm.grid and f.map is gm
    for a in (f.potential, f.grad_x, f.grad_y):
        assert a.dtype == np.float64 and a.shape == gm.shape
    occ = gm.occupied
    assert np.all(f.potential[occ] == np.inf)
    assert np.all(f.grad_x[occ] == 0) and np.all(f.grad_y[occ] == 0)
    assert np.all(np.isfinite(f.potential[~occ])) and np.all(np.isfinite(f.grad_x)) and np.all(np.isfinite(f.grad_y))
    assert f.goal == (13.0, 9.5)
    assert set(FIELD_NAMES) <= set(f.params)


def test_build_field_is_attractive_plus_repulsive():
    gm = blocks_map()
    d = brushfire(gm, metric="euclidean")
    p = {"zeta": 0.7, "d_star": 2.0, "eta": 3.0, "q_star": 1.2, "repulsive_power": 3}
    f = build_field(gm, (13.0, 9.5), p, dmap=d)
    assert f.distance is d
    Ua, ax, ay = attractive(gm.grid, (13.0, 9.5), zeta=0.7, d_star=2.0)
    Ur, rx, ry = repulsive(d, eta=3.0, q_star=1.2, power=3)
    free = ~gm.occupied
    np.testing.assert_allclose(f.potential[free], (Ua + Ur)[free], rtol=1e-13)
    np.testing.assert_allclose(f.grad_x, ax * free + rx, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(f.grad_y, ay * free + ry, rtol=1e-13, atol=1e-15)
    with pytest.raises(ParameterError, match="metric"):
        build_field(gm, (13.0, 9.5), {"metric": "chessboard"}, dmap=d)


def test_field_npz_round_trip(tmp_path):
    w = read_world(bundled_map("seed000.yaml"))
    f = build_field(rasterize(w, 0.25), w.goal, dict(w.params))
    save_field(tmp_path / "f.npz", f)
    g = load_field(tmp_path / "f.npz")
    for name in ("potential", "grad_x", "grad_y"):
        np.testing.assert_array_equal(getattr(g, name), getattr(f, name))
    np.testing.assert_array_equal(g.map.occupied, f.map.occupied)
    np.testing.assert_array_equal(g.map.obstacle_id, f.map.obstacle_id)
    assert g.grid == f.grid and g.goal == f.goal and g.params == f.params
    assert g.distance is not None and f.distance is not None
    for name in ("steps", "distance", "nearest_row", "nearest_col", "label", "gvd"):
        np.testing.assert_array_equal(getattr(g.distance, name), getattr(f.distance, name))
    assert g.params["d_star"] == math.inf
    assert f.distance.steps is None  # build_field's own brushfire skips the steps no potential reads
    # a field over a full distance map (as `gridfield field --npz` writes) keeps its steps
    full = field_distance_map(f.map, f.params, labels=True, steps=True)
    save_field(tmp_path / "full.npz", build_field(f.map, w.goal, dict(w.params), dmap=full))
    loaded = load_field(tmp_path / "full.npz").distance
    assert loaded is not None and loaded.steps is not None
    np.testing.assert_array_equal(loaded.steps, full.steps)
    # a field rebuilt from the loaded map and distance map is the same field
    h = build_field(g.map, g.goal, g.params, dmap=g.distance)
    np.testing.assert_array_equal(h.potential, f.potential)
    # the vortex field too
    v = build_field(rasterize(read_world(bundled_map("seed003_circles.yaml")), 0.4), (0, -4), {"model": "vortex"})
    assert v.params["model"] == "vortex"
    save_field(tmp_path / "v.npz", v)
    assert load_field(tmp_path / "v.npz").params == v.params


def test_load_field_rejects_other_files(tmp_path):
    from gridfield.core.errors import MapFormatError

    np.savez(tmp_path / "x.npz", occupied=np.zeros((2, 2), bool))
    with pytest.raises(MapFormatError, match="save_field"):
        load_field(tmp_path / "x.npz")
    with pytest.raises(MapFormatError, match="no such file"):
        load_field(tmp_path / "missing.npz")


# ------------------------------------------------------------------------------------------------
# the command line
# ------------------------------------------------------------------------------------------------
def test_cli_field_writes_arrays_and_figures(tmp_path, capsys):
    from gridfield.cli import main
    from gridfield.io import read_npz_arrays

    world = bundled_map("seed000.yaml")
    out = {k: tmp_path / f"{k}.{'npz' if k == 'npz' else 'png'}" for k in ("npz", "plot", "surface", "basins")}
    argv = [str(world), "--resolution", "0.25", "--repulsion", "nearest", "--q-star", "1.5"]
    for k, f in out.items():
        argv += [f"--{k}", str(f)]
    assert main(["field", *argv]) == 0
    text = capsys.readouterr().out
    assert "field 80x100 cells of 0.25" in text and "nearest repulsion, p=3" in text and "U in [" in text
    for f in out.values():
        assert f.exists() and f.stat().st_size > 0
    arrays, grid = read_npz_arrays(out["npz"])
    assert {"occupied", "distance", "label", "gvd", "potential", "grad_x", "grad_y"} <= set(arrays)
    assert grid.resolution == 0.25 and grid.origin == (0.0, 0.0)
    # the world's params, overridden by the command line's
    w = read_world(world)
    f = build_field(rasterize(w, 0.25), w.goal, {**w.params, "repulsion": "nearest", "q_star": 1.5})
    np.testing.assert_array_equal(arrays["potential"], f.potential)
    np.testing.assert_array_equal(arrays["grad_y"], f.grad_y)


def test_cli_field_vortex_and_goal_option(tmp_path, capsys):
    from gridfield.cli import main

    assert main(["field", str(bundled_map("seed003_circles.yaml")), "--npz", str(tmp_path / "v.npz")]) == 0
    assert "26x26 cells of 0.4 (vortex" in capsys.readouterr().out
    assert main(["field", str(bundled_map("seed000.yaml")), "--resolution", "0.5", "--goal", "2", "2",
                 "--param", "saturate=1.0", "--param", "repulsion=sum"]) == 0
    assert "goal (2, 2)" in capsys.readouterr().out


@pytest.mark.parametrize(("extra", "words"), [
    (["--goal", "5", "12"], "inside an obstacle"),
    (["--goal", "50", "12"], "outside the map"),
    (["--param", "zeta=nan"], "nan"),
    (["--param", "q_star=0"], "q_star"),
    (["--repulsion", "everything"], "repulsion must be one of"),
    (["--param", "zetta=1"], "did you mean 'zeta'"),
])
def test_cli_field_errors_are_one_line_and_exit_2(extra, words, capsys):
    from gridfield.cli import main

    assert main(["field", str(bundled_map("seed000.yaml")), "--resolution", "0.5", *extra]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("gridfield field: error:") and words in err, err
    assert captured.out == ""


def test_cli_field_needs_a_goal(tmp_path, capsys):
    from gridfield.cli import main

    (tmp_path / "w.yaml").write_text("bounds: [0, 0, 4, 4]\nresolution: 0.5\nobstacles:\n"
                                     "  - circle: {center: [2, 2], radius: 0.5}\n")
    assert main(["field", str(tmp_path / "w.yaml")]) == 2
    assert "--goal X Y" in capsys.readouterr().err
    assert main(["field", str(tmp_path / "w.yaml"), "--goal", "0.25", "0.25", "--plot", str(tmp_path / "no" / "p.png")]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_saved_field_reads_back_as_a_map(tmp_path) -> None:
    """A save_field file is also a gridfield .npz map (its goal/params entries are metadata)."""
    from gridfield.io import read

    occ = np.zeros((5, 7), bool)
    occ[2, 3] = True
    gm = GridMap(Grid((5, 7), 0.5, origin=(1.0, -2.0)), occ)
    f = build_field(gm, (4.25, -0.25), {"q_star": 1.0})
    save_field(tmp_path / "f.npz", f)
    back = read(tmp_path / "f.npz")
    assert back.grid == gm.grid
    assert np.array_equal(back.occupied, occ)
