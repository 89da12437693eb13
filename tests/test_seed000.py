"""Seed 000 (Zafari, Robotics HW6): the published outcomes, exactly (vector world) and on grids.

Start (1, 10), goal (22, 12), zeta = eta = 1, q_star = 2, repulsive power 3, repulsion summed over
obstacles, normalized step 0.1, stop within 0.1 of the goal (maps/seed000*.yaml).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import root

from gridfield.exact.continuous import ExactField, plan_exact_potential
from gridfield.following.follower import plan_potential
from gridfield.geometry.rasterize import rasterize
from gridfield.io import bundled_map, read_world

#: The equilibrium of the continuous field near the segment (F = 0), see test_equilibrium.
EQUILIBRIUM = (16.95116793, 9.05178306)


@pytest.fixture(scope="module")
def base():
    return read_world(bundled_map("seed000.yaml"))


@pytest.fixture(scope="module")
def segment():
    return read_world(bundled_map("seed000_segment.yaml"))


@pytest.fixture(scope="module")
def exact_base(base):
    return plan_exact_potential(base, base.start, base.goal, base.params)


def test_world_files_hold_the_seed_parameters(base, segment):
    for w in (base, segment):
        assert (w.start, w.goal) == ((1.0, 10.0), (22.0, 12.0))
        p = w.params
        assert (p["zeta"], p["eta"], p["q_star"], p["repulsive_power"], p["repulsion"]) == (1.0, 1.0, 2.0, 3, "sum")
        assert (p["step_rule"], p["step"], p["tolerance"]) == ("normalized", 0.1, 0.1)
    assert len(segment.obstacles) == len(base.obstacles) + 1


def test_exact_base_world_reaches_the_goal(exact_base):
    p = exact_base
    assert p.status == "reached" and p.planner == "exact-potential"
    assert p.iterations == 247
    # 248 visited points (start + 247 steps) and the goal appended, as the seed's P = [P Xf]
    assert len(p.points) == 249 and p.extra["goal_appended"]
    np.testing.assert_allclose(p.points[0], [1.0, 10.0])
    np.testing.assert_allclose(p.points[-1], [22.0, 12.0])
    np.testing.assert_allclose(p.points[-2], [21.95041, 11.96262], atol=1e-3)
    assert p.length == pytest.approx(24.76210, abs=1e-3)
    assert math.dist(p.points[-2], (22.0, 12.0)) < 0.1
    steps = np.hypot(*np.diff(p.points[:-1], axis=0).T)
    np.testing.assert_allclose(steps, 0.1, rtol=1e-9)  # 247 steps of 0.1: 24.7 before the goal hop
    assert p.min_clearance == pytest.approx(0.48881, abs=1e-3)


def test_exact_segment_world_stalls_where_the_seed_says(segment):
    p = plan_exact_potential(segment, segment.start, segment.goal, segment.params)
    assert p.status == "local_minimum" and p.extra["stop_reason"] == "oscillation"
    assert p.iterations == 213
    a, b = sorted(p.extra["oscillation"])
    np.testing.assert_allclose(a, [16.87405, 9.05761], atol=1e-3)
    np.testing.assert_allclose(b, [16.96967, 9.02833], atol=1e-3)
    # the seed reports (16.97, 9.028): the point of the pair with the smaller force
    np.testing.assert_allclose(p.extra["stall_point"], [16.970, 9.028], atol=1e-3)
    assert math.dist(p.end, segment.goal) > 0.1
    # the stalled run is 213 steps of 0.1
    assert p.length == pytest.approx(21.3, abs=1e-9)


def test_equilibrium(segment):
    f = ExactField(segment, segment.goal, segment.params)
    sol = root(lambda v: f.force((v[0], v[1])), x0=[16.95, 9.05], tol=1e-12)
    np.testing.assert_allclose(sol.x, EQUILIBRIUM, atol=1e-6)
    # the stall pair brackets it: each is about one step (0.1) from the other, 0.03 from it
    assert math.dist(EQUILIBRIUM, (16.96967, 9.02833)) < 0.035


# ----------------------------------------------------------------------------------------------
# grids
# ----------------------------------------------------------------------------------------------
def test_grid_base_world_reaches_with_nearly_the_exact_length(base, exact_base):
    gm = rasterize(base, 0.05)
    p = plan_potential(gm, base.start, base.goal, base.params)
    assert p.status == "reached"
    assert p.length == pytest.approx(exact_base.length, rel=0.02)
    # the grid path stays close to the exact one: every grid vertex is within a few cells of it
    import shapely

    exact_line = shapely.linestrings(exact_base.points)
    gap = shapely.distance(exact_line, shapely.points(p.points)).max()
    assert gap < 0.3


@pytest.mark.slow
def test_grid_segment_world_stall_converges_to_the_equilibrium(segment):
    """Distance of the grid stall point to the continuous equilibrium at h = 0.1, 0.05, 0.025.

    Measured: 0.166, 0.093, 0.068 (and 0.034 at h = 0.0125).
    """
    dist = {}
    for h in (0.1, 0.05, 0.025):
        gm = rasterize(segment, h)
        p = plan_potential(gm, segment.start, segment.goal, segment.params)
        assert p.status == "local_minimum", h
        assert p.extra["stop_reason"] in ("oscillation", "no_progress")
        assert math.dist(p.end, segment.goal) > 0.1
        dist[h] = math.dist(p.extra["stall_point"], EQUILIBRIUM)
    assert dist[0.05] < 0.15
    assert dist[0.1] > dist[0.05] > dist[0.025]
    assert dist[0.025] < 0.08


def test_grid_stall_is_caught_by_the_progress_window_too(segment):
    """On the grid the follower settles into its 2-cycle only slowly; a short no-progress window
    stops it earlier, at the same stall point."""
    from gridfield.fields.potential import build_field
    from gridfield.following.follower import descend, grid_blocked, grid_sampler

    gm = rasterize(segment, 0.05)
    f = build_field(gm, segment.goal, segment.params)
    kw = {"step": 0.1, "tolerance": 0.1, "blocked": grid_blocked(gm), "confine_window": 0}
    runs = {}
    # revisit_tolerance=0 is the seed's exact test current_pos == P(:, end-2)
    for name, window, rt in (("window", 30, 0.0), ("exact_return", 0, 0.0), ("default", 200, None)):
        p = descend(grid_sampler(f), segment.start, segment.goal, progress_window=window, revisit_tolerance=rt, **kw)
        assert p.status == "local_minimum"
        runs[name] = (p.iterations, p.extra["stop_reason"], p.extra["stall_point"])
    assert runs["window"][1] == "no_progress"
    assert runs["exact_return"][1] == runs["default"][1] == "oscillation"
    assert runs["window"][0] < runs["default"][0] < runs["exact_return"][0]
    for _, _, stall in runs.values():
        assert math.dist(stall, EQUILIBRIUM) < 0.1
