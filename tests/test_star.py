"""Star worlds (star-nav): the obstacle functions against shapely, the star-shaped test against the
kernel built from half-planes with shapely, h_lambda on the boundaries and its Jacobian (finite
differences, positive determinant), the navigation function's minima and gradient, the follower from
random starts with an exact collision check, errors and warnings, and the command line."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, Point, Polygon

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.params import REGISTRY
from gridfield.fields import navigation as star  # the star-world names
from gridfield.geometry.world import world_from_dict
from gridfield.io import bundled_map, read_world
from gridfield.planners import PARAMETERS, PLANNERS, plan

C0, R0 = np.array([10.0, 10.0]), 10.0


# ---------------------------------------------------------------------------------------------
# random star worlds (written here, independent of gridfield)
# ---------------------------------------------------------------------------------------------
def random_star_polygon(rng, center, n, rmin=0.9, rmax=2.0):
    """A polygon star-shaped about ``center``: vertices at jittered increasing angles (gaps < pi for n >= 4)."""
    ang = (np.arange(n) + rng.uniform(0.1, 0.9, n)) * 2 * np.pi / n
    rad = rng.uniform(rmin, rmax, n)
    return np.asarray(center) + np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])


def random_star_world(seed, m):
    """``m`` disjoint star polygons (half with their centre given) in the disc workspace of [0, 20]^2."""
    rng = np.random.default_rng(seed)
    entries, shapes = [], []
    while len(entries) < m:
        c = C0 + rng.uniform(-6.5, 6.5, 2)
        v = random_star_polygon(rng, c, int(rng.integers(4, 10)))  # angle gaps < pi
        poly = Polygon(v)
        if np.hypot(*(v - C0).T).max() > R0 - 0.6 or not poly.is_valid or any(poly.distance(s) < 0.6 for s in shapes):
            continue
        shapes.append(poly)
        entries.append({"polygon": {"vertices": v.tolist(), "center": c.tolist()}} if len(entries) % 2 else
                       {"polygon": v.tolist()})
    return world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": entries}), shapes, rng


def random_free_points(rng, shapes, k, margin):
    out = []
    while len(out) < k:
        p = C0 + rng.uniform(-R0, R0, 2)
        if math.dist(p, C0) < R0 - margin and all(s.distance(Point(p)) > margin for s in shapes):
            out.append(p)
    return np.array(out)


def _ccw_edges(poly: Polygon) -> tuple[np.ndarray, np.ndarray]:
    """The edges (start points, unit directions) of a simple polygon's exterior, counter-clockwise."""
    v = np.asarray(shapely.geometry.polygon.orient(poly, 1).exterior.coords)[:-1]
    d = np.roll(v, -1, axis=0) - v
    return v, d / np.hypot(d[:, 0], d[:, 1])[:, None]


def kernel_margin(poly: Polygon, point) -> float:
    """The smallest signed distance of ``point`` to the supporting lines of the polygon's edges.

    The kernel of a simple polygon is the intersection of the inner half-planes of its edges, so the
    point lies in the kernel iff this margin is >= 0 (and at distance > m from it if the margin is < -m).
    Plain arithmetic, no polygon overlay: shapely's intersection with huge half-plane boxes lost the
    whole kernel of a convex triangle (hypothesis seed 112, pinned below).
    """
    a, e = _ccw_edges(poly)
    c = np.asarray(point, dtype=float)
    return float(np.min(e[:, 0] * (c[1] - a[:, 1]) - e[:, 1] * (c[0] - a[:, 0])))


def kernel(poly: Polygon) -> Polygon:
    """The kernel of a simple polygon: its intersection with the inner half-plane of every edge."""
    a, e = _ccw_edges(poly)
    big = 4.0 * max(poly.length, 1.0)  # boxes a few times the polygon's size: no overlay precision loss
    k = poly
    for p, u in zip(a, e, strict=True):
        left = np.array([-u[1], u[0]])  # interior side of a counter-clockwise edge
        k = k.intersection(Polygon([p - big * u, p + big * u, p + big * u + big * left, p - big * u + big * left]))
    return k


# ---------------------------------------------------------------------------------------------
# obstacle functions and the star-shaped test
# ---------------------------------------------------------------------------------------------
@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000))
def test_beta_is_zero_on_the_boundary_negative_inside_positive_outside(seed) -> None:
    w, shapes, rng = random_star_world(seed, 2)
    sw = star.star_world(w, random_free_points(rng, shapes, 1, 0.3)[0])
    q = C0 + rng.uniform(-R0, R0, (400, 2))
    betas, _ = star.star_betas(sw, q)
    for i, poly in enumerate(shapes):
        inside = shapely.contains_xy(poly, q[:, 0], q[:, 1])
        near = shapely.distance(poly.exterior, shapely.points(q)) < 1e-9
        np.testing.assert_array_equal((betas[i + 1] < 0)[~near], inside[~near])
        np.testing.assert_array_equal((betas[i + 1] > 0)[~near], ~inside[~near])
        # points on the boundary (along each edge)
        v = np.asarray(poly.exterior.coords)
        t = rng.uniform(0, 1, (len(v) - 1, 1))
        on = v[:-1] + t * (v[1:] - v[:-1])
        b_on, _ = star.star_betas(sw, on)
        np.testing.assert_allclose(b_on[i + 1], 0.0, atol=1e-12)


def test_beta_gradient_matches_finite_differences_everywhere() -> None:
    w, shapes, rng = random_star_world(3, 3)
    sw = star.star_world(w, random_free_points(rng, shapes, 1, 0.5)[0])
    q = np.vstack([random_free_points(rng, shapes, 200, 0.2), C0 + rng.uniform(-R0, R0, (300, 2))])  # and inside
    eps = 1e-6
    _, g = star.star_betas(sw, q)
    num = np.stack([(star.star_betas(sw, q + eps * e)[0] - star.star_betas(sw, q - eps * e)[0]) / (2 * eps)
                    for e in np.eye(2)], axis=-1)
    np.testing.assert_allclose(g, num, rtol=1e-5, atol=1e-7)  # no kink left: every point, vertex rays included


def random_spiky_polygon(rng, center, n):
    """Star-shaped about ``center`` with radii up to 10x apart between neighbours (thin kernels, many reflex
    vertices)."""
    ang = (np.arange(n) + rng.uniform(0.15, 0.85, n)) * 2 * np.pi / n
    rad = rng.uniform(0.25, 2.6, n)
    return np.asarray(center) + np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])


def random_spiky_world(seed, m):
    rng = np.random.default_rng(seed)
    entries, shapes = [], []
    while len(entries) < m:
        c = C0 + rng.uniform(-6.5, 6.5, 2)
        v = random_spiky_polygon(rng, c, int(rng.integers(6, 20)))
        poly = Polygon(v)
        if np.hypot(*(v - C0).T).max() > R0 - 0.5 or not poly.is_valid or any(poly.distance(s) < 0.5 for s in shapes):
            continue
        shapes.append(poly)
        entries.append({"polygon": {"vertices": v.tolist(), "center": c.tolist()}})
    return world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": entries}), shapes, rng


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 10_000))
def test_spiky_beta_zero_on_shapely_boundary_samples_and_signed_like_shapely(seed) -> None:
    w, shapes, rng = random_spiky_world(seed, 2)
    sw = star.star_world(w, random_free_points(rng, shapes, 1, 0.3)[0])
    for ob, poly in zip(sw.obstacles, shapes, strict=True):
        on = shapely.line_interpolate_point(poly.exterior, rng.uniform(0, 1, 300), normalized=True)
        b, _ = ob.beta(shapely.get_coordinates(on))
        np.testing.assert_allclose(b, 0.0, atol=1e-9)
        q = ob.center + rng.uniform(-3, 3, (2000, 2))
        b, _ = ob.beta(q)
        d = shapely.distance(poly.exterior, shapely.points(q))
        inside = shapely.contains_xy(poly, q[:, 0], q[:, 1])
        far = d > 1e-9
        np.testing.assert_array_equal((b < 0)[far], inside[far])
        np.testing.assert_array_equal((b > 0)[far], ~inside[far])


def one_sided(f, p, tau, h):
    """One-sided first and second differences of ``f`` at ``p`` along ``tau`` from each side."""
    fp = [f(p + k * h * tau) for k in (0, 1, 2)]
    fm = [f(p - k * h * tau) for k in (0, 1, 2)]
    return ((fp[1] - fp[0]) / h, (fp[0] - fm[1]) / h, (fp[2] - 2 * fp[1] + fp[0]) / h**2,
            (fm[0] - 2 * fm[1] + fm[2]) / h**2)


@pytest.mark.parametrize("seed", [5, 6, 7])
def test_beta_is_smooth_across_the_vertex_rays_where_the_gauge_has_a_kink(seed) -> None:
    w, shapes, rng = random_spiky_world(seed, 1)
    ob = star.star_world(w, random_free_points(rng, shapes, 1, 0.3)[0]).obstacles[0]
    v = ob.vertices
    u = (v - ob.center) / np.hypot(*(v - ob.center).T)[:, None]
    tau = np.column_stack([-u[:, 1], u[:, 0]])  # across the ray from the centre through each vertex
    for factor in (0.75, 1.3, 2.0):  # inside (outside the centre's disc function) and outside
        p = ob.center + factor * (v - ob.center)

        def beta(x):
            return ob.beta(x)[0]

        def old(x):  # the gauge's g**2 - 1: the obstacle function before this construction
            return ob.gauge(x)[0] ** 2 - 1

        # one-sided differences from the two sides converge to each other (C^1: their gap shrinks with h;
        # C^2: the one-sided second differences' gap too); across a kink the first-order gap stays
        gaps = [np.abs(np.subtract(*one_sided(beta, p, tau, h)[:2])) for h in (1e-4, 1e-6)]
        assert np.all(gaps[1] <= 0.05 * gaps[0] + 1e-7), (factor, gaps)
        gaps2 = [np.abs(np.subtract(*one_sided(beta, p, tau, h)[2:])) for h in (1e-3, 1e-4)]
        assert np.all(gaps2[1] <= 0.2 * gaps2[0] + 1e-3 * (1 + np.abs(one_sided(beta, p, tau, 1e-4)[2]))), (factor, gaps2)
        old_gaps = [np.abs(np.subtract(*one_sided(old, p, tau, h)[:2])) for h in (1e-4, 1e-6)]
        assert np.median(old_gaps[1]) > 0.5 * np.median(old_gaps[0]) > 1e-3  # the check sees the gauge's kinks
    # on the boundary at a vertex a C^1 function with a corner in its zero set has a vanishing gradient
    np.testing.assert_allclose(ob.beta(v)[1], 0.0, atol=1e-9)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0, 10), st.floats(0, 10)), min_size=3, max_size=9, unique=True),
       st.tuples(st.floats(0, 10), st.floats(0, 10)))
@example([(4, 5), (0, 2.176705049273076), (6, 2.125)], (2, 3))  # a convex triangle the old helper lost
def test_star_shaped_about_a_centre_iff_it_lies_in_the_kernel(vertices, center) -> None:
    poly = Polygon(vertices)
    if not poly.is_valid or poly.area < 0.5:
        return
    margin = kernel_margin(poly, center)
    w = world_from_dict({"bounds": [-40, -40, 50, 50],
                         "obstacles": [{"polygon": {"vertices": list(vertices), "center": list(center)}}]})
    inside = margin > 1e-6
    outside = margin < -1e-6
    if inside:
        star.star_world(w, (5, 45))
    elif outside:
        with pytest.raises(ParameterError, match=r"obstacle 1 \(polygon\) is not star-shaped about its centre"):
            star.star_world(w, (5, 45))


def test_found_centre_lies_in_the_kernel_and_non_star_polygons_are_rejected() -> None:
    comb = [[0, 0], [5, 0], [5, 3], [4, 3], [4, 1], [3, 1], [3, 3], [2, 3], [2, 1], [1, 1], [1, 3], [0, 3]]
    spiral = [[0, 0], [6, 0], [6, 6], [1, 6], [1, 2], [4, 2], [4, 4], [3, 4], [3, 3], [2, 3], [2, 5], [5, 5],
              [5, 1], [0, 1]]
    for shape, ok in ((comb, False), (spiral, False), ([[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]], True)):
        w = world_from_dict({"bounds": [-10, -10, 20, 20], "obstacles": [{"polygon": shape}]})
        if ok:
            sw = star.star_world(w, (15, 15))
            assert kernel(Polygon(shape)).buffer(-1e-9).contains(Point(sw.obstacles[0].center))
        else:
            assert kernel(Polygon(shape)).area < 1e-9
            with pytest.raises(ParameterError, match=r"obstacle 1 \(polygon\) is not star-shaped: no point"):
                star.star_world(w, (15, 15))


# ---------------------------------------------------------------------------------------------
# h_lambda
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("m", [2, 3, 4])
def test_h_maps_each_boundary_onto_its_model_circle_and_fixes_the_workspace_circle_and_goal(m) -> None:
    w, shapes, rng = random_star_world(10 + m, m)
    goal = random_free_points(rng, shapes, 1, 0.5)[0]
    sw = star.star_world(w, goal)
    for ob, poly in zip(sw.obstacles, shapes, strict=True):
        # points just outside the boundary (pushed out along the ray from the centre)
        v = np.asarray(poly.exterior.coords)
        t = rng.uniform(0.05, 0.95, (len(v) - 1, 1))
        on = v[:-1] + t * (v[1:] - v[:-1])
        out = ob.center + (on - ob.center) * (1 + 1e-12)
        assert not shapely.contains_xy(poly, out[:, 0], out[:, 1]).any()
        h, _, _, free = star.star_to_sphere(sw, out, 10.0)
        assert free.all()
        np.testing.assert_allclose(np.hypot(*(h - ob.center).T), ob.model_radius, rtol=1e-6)
    ang = rng.uniform(0, 2 * np.pi, 50)
    rim = C0 + (R0 * (1 - 1e-10)) * np.column_stack([np.cos(ang), np.sin(ang)])
    h, _, _, _ = star.star_to_sphere(sw, rim, 10.0)
    np.testing.assert_allclose(h, rim, atol=1e-6)
    np.testing.assert_allclose(star.star_to_sphere(sw, goal[None, :], 10.0)[0][0], goal, atol=1e-12)


@pytest.mark.parametrize("m", [2, 3, 4])
def test_jacobian_matches_finite_differences_and_has_a_positive_determinant(m) -> None:
    w, shapes, rng = random_star_world(20 + m, m)
    sw = star.star_world(w, random_free_points(rng, shapes, 1, 0.5)[0])
    q = random_free_points(rng, shapes, 2000, 0.02)
    _, jac, _, free = star.star_to_sphere(sw, q, 10.0)
    assert free.all()
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    assert det.min() > 0
    eps = 1e-6
    num = np.stack([(star.star_to_sphere(sw, q + eps * e, 10.0)[0] - star.star_to_sphere(sw, q - eps * e, 10.0)[0])
                    / (2 * eps) for e in np.eye(2)], axis=-1)
    np.testing.assert_allclose(jac, num, rtol=1e-4, atol=1e-4)  # every point: h is smooth (no vertex-ray kink)


def test_small_lambda_folds_and_is_warned_about() -> None:
    w = read_world(bundled_map("star_two.yaml"))
    sw = star.star_world(w, w.goal)
    assert len(star.folds(sw, lam=0.3)) > 0 and len(star.folds(sw, lam=1.0)) == 0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        plan("star-nav", w, w.start, w.goal, {"lambda": 0.3, "kappa": 3, "max_iterations": 5})
    messages = [str(c.message) for c in caught if issubclass(c.category, star.StarNavWarning)]
    assert any(m.startswith("lambda=0.3 is too small: h_lambda folds (Jacobian determinant <= 0)") for m in messages)


# ---------------------------------------------------------------------------------------------
# the navigation function
# ---------------------------------------------------------------------------------------------
def test_gradient_matches_finite_differences_of_phi() -> None:
    w, shapes, rng = random_star_world(31, 3)
    sw = star.star_world(w, random_free_points(rng, shapes, 1, 0.5)[0])
    q = random_free_points(rng, shapes, 300, 0.3)
    phi, grad = star.nav_function(sw, q, kappa=3, lam=10)
    eps = 1e-6
    num = np.column_stack([(star.nav_function(sw, q + eps * e, kappa=3, lam=10)[0]
                            - star.nav_function(sw, q - eps * e, kappa=3, lam=10)[0]) / (2 * eps) for e in np.eye(2)])
    close = np.all(np.abs(num - grad) <= 1e-5 * (1e-3 + np.abs(grad)).max(axis=1, keepdims=True), axis=1)
    assert close.mean() > 0.97
    assert np.all((phi >= 0) & (phi < 1))


def discrete_minima(values, ok):
    """Lattice points strictly lower than their 8 neighbours, all of them in ``ok``."""
    rows, cols = values.shape
    pad = np.pad(values, 1, constant_values=np.inf)
    okp = np.pad(ok, 1, constant_values=False)
    m = ok.copy()
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            if dr or dc:
                m &= okp[1 + dr:1 + dr + rows, 1 + dc:1 + dc + cols] & (values < pad[1 + dr:1 + dr + rows,
                                                                                       1 + dc:1 + dc + cols])
    return m


@pytest.mark.parametrize(("seed", "m"), [(40, 2), (41, 3), (42, 4)])
def test_no_local_minimum_but_the_goal_for_a_large_enough_kappa(seed, m) -> None:
    w, shapes, rng = random_star_world(seed, m)
    goal = random_free_points(rng, shapes, 1, 0.5)[0]
    sw = star.star_world(w, goal)
    kappa = 8.0
    n = 301
    xs = np.linspace(0.013, 19.987, n)  # a lattice unlike the one star-nav checks on
    x, y = np.meshgrid(xs, xs)
    q = np.column_stack([x.ravel(), y.ravel()])
    dx = xs[1] - xs[0]
    # phi**kappa = 1 / (1 + beta / gamma**kappa): compare log(beta/gamma**kappa) to see past phi's saturation
    h, _, _, free = star.star_to_sphere(sw, q, 10.0)
    hq = np.where(free[:, None], h, goal + 1)
    gamma = np.einsum("ij,ij->i", hq - goal, hq - goal)
    log_beta = np.log(np.maximum(R0**2 - np.einsum("ij,ij->i", hq - C0, hq - C0), 1e-300))
    for cx, cy, r in sw.model_discs:
        log_beta += np.log(np.maximum((hq[:, 0] - cx) ** 2 + (hq[:, 1] - cy) ** 2 - r * r, 1e-300))
    with np.errstate(divide="ignore"):
        value = (kappa * np.log(gamma) - log_beta).reshape(x.shape)
    dist = np.full(len(q), R0) - np.hypot(*(q - C0).T)
    for poly in shapes:
        d = shapely.distance(poly, shapely.points(q))
        dist = np.where(shapely.contains_xy(poly, q[:, 0], q[:, 1]), -1.0, np.minimum(dist, d))
    ok = (dist > 3 * dx).reshape(x.shape)
    minima = discrete_minima(value, ok)
    pts = np.column_stack([x[minima], y[minima]])
    assert len(pts) == 1 and math.dist(pts[0], goal) < 2 * dx
    assert star.spurious_minima(sw, kappa=kappa, lam=10.0).shape == (0, 2)


def test_small_kappa_leaves_a_spurious_minimum_detected_and_warned() -> None:
    w = read_world(bundled_map("star_two.yaml"))
    sw = star.star_world(w, w.goal)
    assert len(star.spurious_minima(sw, kappa=1, lam=1)) > 0
    assert len(star.spurious_minima(sw, kappa=3, lam=1)) == 0
    with pytest.warns(star.StarNavWarning, match=r"kappa=1 is too small: phi\(h_lambda\) has \d+ local minim"):
        plan("star-nav", w, w.start, w.goal, {"kappa": 1, "max_iterations": 10})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        p = plan("star-nav", w, w.start, w.goal, {})  # kappa chosen: the smallest with no minimum found
    assert p.reached and p.extra["kappa"] == 3.0 and p.extra["kappa_tried"] == [(3.0, 0)]


# ---------------------------------------------------------------------------------------------
# the follower
# ---------------------------------------------------------------------------------------------
def assert_collision_free(points, shapes):
    line = LineString(points)
    for poly in shapes:
        assert not line.intersects(poly)
    assert np.hypot(*(points - C0).T).max() < R0


@pytest.mark.parametrize(("seed", "m"), [(50, 2), (51, 3), (52, 4)])
def test_follower_reaches_the_goal_from_100_random_starts(seed, m) -> None:
    w, shapes, rng = random_star_world(seed, m)
    goal = random_free_points(rng, shapes, 1, 0.5)[0]
    sw = star.star_world(w, goal)
    kappa, _ = star.choose_kappa(sw, None, 10.0)
    starts = random_free_points(rng, shapes, 100, 0.05)
    results = star.follow_star_nav(sw, starts, kappa=kappa, lam=10.0, step=0.05, tolerance=0.05, max_iterations=6000)
    assert [s for _, s, _ in results] == ["reached"] * 100
    for (pts, _, _), s in zip(results, starts, strict=True):
        np.testing.assert_array_equal(pts[0], s)
        np.testing.assert_array_equal(pts[-1], goal)
        assert_collision_free(pts, shapes)


@pytest.mark.parametrize(("seed", "m"), [(70, 2), (71, 3), (72, 4)])
def test_spiky_worlds_h_on_the_boundaries_positive_jacobian_and_the_follower_from_100_starts(seed, m) -> None:
    w, shapes, rng = random_spiky_world(seed, m)
    goal = random_free_points(rng, shapes, 1, 0.5)[0]
    sw = star.star_world(w, goal)
    lam = float(REGISTRY["lambda"].default)
    for ob, poly in zip(sw.obstacles, shapes, strict=True):  # boundary points (shapely), pushed out a hair
        on = shapely.get_coordinates(shapely.line_interpolate_point(poly.exterior, rng.uniform(0, 1, 200),
                                                                    normalized=True))
        out = ob.center + (on - ob.center) * (1 + 1e-13)
        h, _, _, free = star.star_to_sphere(sw, out[~shapely.contains_xy(poly, out[:, 0], out[:, 1])], lam)
        assert free.mean() > 0.9
        # first order in the push-out (h's Jacobian is large next to a small model disc): 1e-13 -> 1e-6
        np.testing.assert_allclose(np.hypot(*(h[free] - ob.center).T), ob.model_radius, rtol=1e-6)
    q = random_free_points(rng, shapes, 3000, 0.01)
    _, jac, _, free = star.star_to_sphere(sw, q, lam)
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    assert free.all() and det.min() > 0
    kappa, _ = star.choose_kappa(sw, None, lam)
    starts = random_free_points(rng, shapes, 100, 0.05)
    results = star.follow_star_nav(sw, starts, kappa=kappa, lam=lam, step=0.05, tolerance=0.05, max_iterations=6000)
    assert [s for _, s, _ in results] == ["reached"] * 100
    for pts, _, _ in results:
        assert_collision_free(pts, shapes)


def test_planner_through_the_registry_with_a_disc_and_a_polygon() -> None:
    assert PLANNERS["star-nav"][0] == "gridfield.fields.navigation" and "lambda" in PARAMETERS and "kappa" in PARAMETERS
    w = world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": [
        {"circle": {"center": [7, 10], "radius": 2}},
        {"polygon": [[12, 6], [15, 8], [14, 13], [12.5, 10]]}]})
    p = plan("star-nav", w, (2, 10), (18, 10))
    assert p.reached and p.planner == "star-nav"
    assert_collision_free(p.points, [Point(7, 10).buffer(2, quad_segs=64), Polygon([[12, 6], [15, 8], [14, 13],
                                                                                       [12.5, 10]])])
    assert p.min_clearance > 0 and p.length > 16


# ---------------------------------------------------------------------------------------------
# errors
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("obstacles", "goal", "match"), [
    ([{"polygon": [[5, 5], [8, 5], [8, 8], [5, 8]]}, {"polygon": [[7, 7], [9, 7], [9, 9]]}], (15, 15),
     r"obstacles 1 and 2 overlap or touch"),
    ([{"polygon": [[5, 5], [8, 5], [8, 8], [5, 8]]}, {"circle": {"center": [9, 6], "radius": 1}}], (15, 15),
     r"obstacles 1 and 2 overlap or touch"),
    ([{"circle": {"center": [5, 5], "radius": 2}}, {"circle": {"center": [8, 5], "radius": 1}}], (15, 15),
     r"obstacles 1 and 2 overlap or touch"),
    ([{"polygon": [[1, 1], [3, 1], [3, 3]]}], (10, 10), r"obstacle 1 \(polygon\) is not strictly inside the workspace"),
    ([{"segment": [[5, 5], [6, 6]]}], (10, 10), r"obstacle 1 is a segment; star-nav needs polygons"),
    ([{"polygon": {"vertices": [[5, 5], [8, 5], [8, 8], [5, 8]], "center": [9, 9]}}], (15, 15),
     r"obstacle 1 \(polygon\) is not star-shaped about its centre \(9, 9\)"),
    ([{"circle": {"center": [5, 5], "radius": 1}}], (19, 19), r"goal \(19, 19\) lies outside the workspace disc"),
])
def test_clear_errors(obstacles, goal, match) -> None:
    w = world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": obstacles})
    with pytest.raises(ParameterError, match=match):
        plan("star-nav", w, (10, 15), goal)


@pytest.mark.parametrize(("params", "match"), [
    ({"lambda": -1}, r"lambda must be a finite number > 0"),
    ({"lambda": "big"}, r"lambda must be a .*number"),
    ({"kappa": 0}, r"kappa must be a finite number > 0"),  # the registry's rule (tests/test_params_source.py)
    ({"kappa": True}, r"kappa must be a .*number"),
])
def test_parameter_errors(params, match) -> None:
    w = read_world(bundled_map("star_two.yaml"))
    with pytest.raises(ParameterError, match=match):
        plan("star-nav", w, w.start, w.goal, params)


def test_start_outside_the_workspace_disc() -> None:
    w = read_world(bundled_map("star_two.yaml"))
    with pytest.raises(GridfieldError, match=r"start \(0.5, 0.5\) lies outside the workspace disc"):
        plan("star-nav", w, (0.5, 0.5), w.goal)


# ---------------------------------------------------------------------------------------------
# command line
# ---------------------------------------------------------------------------------------------
def run_cli(capsys, *argv):
    from gridfield.cli import main

    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_plan_json_reaches_the_goal(capsys) -> None:
    code, out, err = run_cli(capsys, "plan", str(bundled_map("star_two.yaml")), "--planner", "star-nav", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["status"] == "reached" and d["planner"] == "star-nav"
    assert d["params"]["kappa"] == 3 and d["params"]["lambda"] == 1  # seed 002's


def test_cli_field_surface_writes_the_seed_figures(capsys, tmp_path) -> None:
    f = tmp_path / "star.png"
    code, out, err = run_cli(capsys, "field", str(bundled_map("star_two.yaml")), "--planner", "star-nav",
                             "--resolution", "0.25", "--surface", str(f))
    assert code == 0, err
    assert f.stat().st_size > 10_000 and "star-nav navigation function" in out


def test_cli_star_nav_error_is_one_line(capsys) -> None:
    code, _, err = run_cli(capsys, "plan", str(bundled_map("seed000.yaml")), "--planner", "star-nav")
    assert code == 2 and err.count("\n") == 1 and "star" in err


def test_cli_warning_is_one_line(capsys) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        code, out, err = run_cli(capsys, "plan", str(bundled_map("star_two.yaml")), "--planner", "star-nav",
                                 "--param", "kappa=1")
    assert code == 0 and "local_minimum" in out
    assert err.startswith("gridfield plan: warning: kappa=1 is too small") and err.count("\n") == 1


@pytest.mark.parametrize("seed", range(60, 66))
def test_a_new_users_random_star_world_with_default_parameters(seed) -> None:
    w, shapes, rng = random_star_world(seed, 2 + seed % 3)
    start, goal = random_free_points(rng, shapes, 2, 0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # default lambda, kappa chosen: neither warning
        p = plan("star-nav", w, start, goal)
    assert p.reached
    assert_collision_free(p.points, shapes)


def test_plot_star_world_draws_the_four_panels() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gridfield.plot import plot_star_world

    w = read_world(bundled_map("star_two.yaml"))
    sw = star.star_world(w, w.goal)
    x, y = np.meshgrid(np.linspace(0, 20, 41), np.linspace(0, 20, 41))
    data = star.star_figure_data(sw, kappa=3, lam=1, x=x, y=y, lines=7)
    # the humps: 1 - g**2 at the star centres, 0 outside the obstacles
    assert data["humps"].max() <= 1 and np.all(data["humps"][data["phi"] < 1] == 0)
    p = plan("star-nav", w, w.start, w.goal)
    arts = plot_star_world(data, path=p)
    try:
        assert len(arts) == 4 and len({a.ax for a in arts}) == 4
        assert len(arts[2].extra["lattice"]) == 14  # 7 horizontal and 7 vertical lines, mapped
        assert len(arts[2].obstacles) == 1 + len(sw.obstacles)  # workspace circle and model discs
        assert len(arts[3].paths) == 1
    finally:
        plt.close(arts[0].figure)


def test_the_deprecated_star_module_is_gone() -> None:
    """gridfield.star (a deprecated alias of the navigation package's star-world names) was removed (CHANGELOG)."""
    with pytest.raises(ModuleNotFoundError):
        import gridfield.star  # noqa: F401
    assert star.choose_kappa is not None
