"""The exact (vector-world) potential-field planner: forces, potential, blocking, clearance, errors."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Point
from shapely.ops import nearest_points

import gridfield.exact.continuous as exact_mod
from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.exact.continuous import ExactField, plan_exact_potential
from gridfield.geometry.world import world_from_dict
from gridfield.io import bundled_map, read_world
from gridfield.planners import plan


@pytest.fixture(scope="module")
def seg_world():
    return read_world(bundled_map("seed000_segment.yaml"))


@pytest.fixture(scope="module")
def mixed_world():
    return world_from_dict({
        "bounds": [0, 0, 20, 12],
        "border": "wall",
        "obstacles": [
            {"circle": {"center": [6, 6], "radius": 1.5}},
            {"polygon": [[10, 2], [13, 2], [13, 5], [10, 5]]},
            {"segment": [[15, 7], [15, 11]]},
            {"polygon": [[2, 9], [3, 9], [2.5, 10]]},
        ],
    })


def free_points(world, n, rng, margin=0.05):
    xmin, ymin, xmax, ymax = world.bounds
    pts = rng.uniform([xmin + margin, ymin + margin], [xmax - margin, ymax - margin], (4 * n, 2))
    d = world.distance(pts)
    return pts[d > margin][:n]


@pytest.mark.parametrize("repulsion", ["sum", "nearest"])
@pytest.mark.parametrize("d_star", [math.inf, 3.0, 0.0])
def test_power_two_force_is_minus_the_gradient_of_the_potential(mixed_world, repulsion, d_star):
    f = ExactField(mixed_world, (18.0, 3.0), {"zeta": 0.7, "d_star": d_star, "eta": 1.3, "q_star": 2.5,
                                              "repulsive_power": 2, "repulsion": repulsion})
    rng = np.random.default_rng(1)
    h = 1e-6
    for x, y in free_points(mixed_world, 80, rng, margin=0.2):
        fx, fy = f.force((x, y))
        gx = (f.potential((x + h, y)) - f.potential((x - h, y))) / (2 * h)
        gy = (f.potential((x, y + h)) - f.potential((x, y - h))) / (2 * h)
        scale = max(1.0, math.hypot(fx, fy))
        assert abs(fx + gx) < 2e-4 * scale and abs(fy + gy) < 2e-4 * scale, (x, y)


def test_power_three_sum_is_the_seed_formula(seg_world):
    f = ExactField(seg_world, seg_world.goal, seg_world.params)
    rng = np.random.default_rng(2)
    for x, y in free_points(seg_world, 50, rng, margin=0.1):
        fx, fy = -(x - 22.0), -(y - 12.0)
        for ob in seg_world.obstacles:
            near = nearest_points(ob.geometry, Point(x, y))[0]
            d = math.hypot(x - near.x, y - near.y)
            if d < 2.0:
                mag = (1 / d - 1 / 2.0) / d**3
                fx += mag * (x - near.x) / d
                fy += mag * (y - near.y) / d
        assert f.force((x, y)) == pytest.approx((fx, fy), rel=1e-9, abs=1e-9)


def test_nearest_repulsion_uses_one_obstacle(seg_world):
    params = {**seg_world.params, "repulsion": "nearest", "zeta": 0.0}
    f = ExactField(seg_world, seg_world.goal, params)
    p = (17.0, 9.0)  # 0.5 from the segment, about 1.1 from polygon 3
    fx, fy = f.force(p)
    assert fy == pytest.approx(0.0, abs=1e-12) and fx < 0  # pushed straight away from the segment only
    fs = ExactField(seg_world, seg_world.goal, {**params, "repulsion": "sum"}).force(p)
    assert fs[1] != pytest.approx(0.0, abs=1e-6)


def test_circles_are_exact(mixed_world):
    f = ExactField(mixed_world, (18.0, 3.0), {"zeta": 0.0, "q_star": 3.0, "repulsive_power": 2})
    near = f.closest((6.0, 9.0))
    d, cx, cy = min(near)
    assert (d, cx, cy) == pytest.approx((1.5, 6.0, 7.5))
    # the polygon outline of the circle is inscribed: its distance is a little larger
    outline = mixed_world.obstacles[0].geometry.distance(Point(6.0, 9.0))
    assert 0 <= outline - d < 1.5 * 2e-3


def test_wall_border_repels(mixed_world):
    f = ExactField(mixed_world, (18.0, 3.0), {"zeta": 0.0, "eta": 1.0, "q_star": 1.0, "repulsive_power": 2})
    fx, fy = f.force((8.0, 0.5))  # 0.5 above the bottom wall, far from obstacles
    assert fx == pytest.approx(0.0, abs=1e-12) and fy == pytest.approx(1.0 * (2 - 1) / 0.25)


def test_saturate_cuts_the_repulsion(seg_world):
    params = {**seg_world.params, "zeta": 0.0}
    p = (17.0, 9.0)
    assert ExactField(seg_world, seg_world.goal, {**params, "saturate": 0.4}).force(p) == pytest.approx((0.0, 0.0))
    assert ExactField(seg_world, seg_world.goal, {**params, "saturate": 0.6}).force(p) != pytest.approx((0.0, 0.0))


def test_strtree_path_equals_brute_force(monkeypatch):
    rng = np.random.default_rng(5)
    obstacles = [{"rectangle": [float(x), float(y), float(x) + 0.6, float(y) + 0.6]}
                 for x, y in rng.uniform(0.5, 18.5, (14, 2))]
    w = world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": obstacles})
    for repulsion in ("sum", "nearest"):
        params = {"q_star": 1.5, "repulsion": repulsion, "repulsive_power": 3}
        tree = ExactField(w, (19.5, 19.5), params)
        assert tree._tree is not None
        monkeypatch.setattr(exact_mod, "_TREE_MIN", 1000)
        brute = ExactField(w, (19.5, 19.5), params)
        monkeypatch.undo()
        assert brute._tree is None
        for p in free_points(w, 60, rng, margin=0.05):
            assert tree.force(tuple(p)) == pytest.approx(brute.force(tuple(p)), rel=1e-12, abs=1e-12)


def test_blocked_matches_dense_sampling(mixed_world):
    f = ExactField(mixed_world, (18.0, 3.0))
    rng = np.random.default_rng(7)
    starts = free_points(mixed_world, 300, rng, margin=0.3)
    for p in starts:
        q = p + rng.normal(0, 2.0, 2)
        t = np.linspace(0, 1, 2001)[:, None]
        samples = p + t * (q - p)
        xmin, ymin, xmax, ymax = mixed_world.bounds
        outside = np.any((samples[:, 0] <= xmin) | (samples[:, 0] >= xmax) | (samples[:, 1] <= ymin)
                         | (samples[:, 1] >= ymax))
        hit = outside or bool(np.any(mixed_world.distance(samples) <= 0.0))
        if hit != f.blocked(tuple(p), tuple(q)):
            # only a graze thinner than the sampling can disagree
            seg = shapely.linestrings([p, q])
            gap = min(ob.distance(np.asarray(shapely.get_coordinates(shapely.shortest_line(ob.geometry, seg))))
                      .min() for ob in mixed_world.obstacles)
            assert gap < 1e-2


def test_open_border_lets_the_path_leave_the_bounds():
    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}]})
    f = ExactField(w, (9.0, 9.0))
    assert not f.blocked((9.5, 9.5), (10.5, 10.5))
    ww = world_from_dict({"bounds": [0, 0, 10, 10], "border": "wall",
                          "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}]})
    assert ExactField(ww, (9.0, 9.0)).blocked((9.5, 9.5), (10.5, 10.5))


def test_exact_clearance_matches_sampling(mixed_world):
    path = np.array([[1.0, 1.0], [8.5, 3.5], [14.0, 6.0], [16.0, 9.0], [19.0, 10.0]])
    t = np.linspace(0, 1, 4001)[:, None]
    dense = np.vstack([a + t * (b - a) for a, b in itertools.pairwise(path)])
    assert mixed_world.clearance(path) == pytest.approx(mixed_world.distance(dense).min(), abs=2e-3)
    assert mixed_world.clearance(path[:1]) == pytest.approx(mixed_world.distance(path[:1])[0])


def test_errors(seg_world, mixed_world):
    with pytest.raises(GridfieldError, match=r"start \(8, 14\) lies inside obstacle 1"):
        plan_exact_potential(seg_world, (8.0, 14.0), seg_world.goal, seg_world.params)
    with pytest.raises(GridfieldError, match=r"goal .* outside the world bounds"):
        plan_exact_potential(seg_world, seg_world.start, (30.0, 12.0), seg_world.params)
    with pytest.raises(ParameterError, match="model 'khatib' only"):
        plan_exact_potential(seg_world, seg_world.start, seg_world.goal, {"model": "vortex"})
    with pytest.raises(ParameterError, match=r"step must be .*> 0"):
        plan_exact_potential(seg_world, seg_world.start, seg_world.goal, {"step": 0})
    with pytest.raises(ParameterError, match="eta"):
        plan_exact_potential(seg_world, seg_world.start, seg_world.goal, {"eta": math.nan})
    with pytest.raises(ParameterError, match="needs a World"):
        plan_exact_potential("seed000.yaml", (1, 1), (2, 2), {})  # type: ignore[arg-type]
    f = ExactField(mixed_world, (18.0, 3.0))
    with pytest.raises(GridfieldError, match="inside or on an obstacle"):
        f.force((11.0, 3.0))


def test_same_core_as_the_grid_follower(seg_world):
    """Escapes and stop rules come from follow.descend: reproducible random walks, the seed's escape."""
    params = {**seg_world.params, "escape": "random_walk", "escape_tries": 10, "seed": 3}
    a = plan_exact_potential(seg_world, seg_world.start, seg_world.goal, params)
    b = plan_exact_potential(seg_world, seg_world.start, seg_world.goal, params)
    assert np.array_equal(a.points, b.points) and a.extra["escapes_tried"] >= 1
    assert a.status == "reached" and a.extra["escapes_succeeded"] == 1
    pi = plan_exact_potential(seg_world, seg_world.start, seg_world.goal,
                              {**seg_world.params, "escape": "potential_increase"})
    assert pi.status == "reached" and (pi.extra["escapes_tried"], pi.extra["escapes_succeeded"]) == (1, 1)
    (e,) = pi.extra["escapes"]
    f = ExactField(seg_world, seg_world.goal, seg_world.params)
    assert f.potential(tuple(e["to"])) >= 1.25 * f.potential(tuple(e["from"]))
    # scaled rule with gradient threshold (seed 004's stop) on the same world
    sc = plan_exact_potential(seg_world, seg_world.start, seg_world.goal,
                              {**seg_world.params, "step_rule": "scaled", "alpha": 0.02, "min_speed": 0.01,
                               "gradient_threshold": 0.05})
    assert sc.status == "local_minimum"
    assert math.dist(sc.extra["stall_point"], (16.95116793, 9.05178306)) < 0.05


def test_registry_runs_the_exact_planner(seg_world):
    p = plan("exact-potential", seg_world, seg_world.start, seg_world.goal)
    assert p.planner == "exact-potential" and p.status == "local_minimum"
    assert p.params["repulsion"] == "sum" and p.params["step"] == 0.1
    assert p.min_clearance > 0 and p.seconds > 0
