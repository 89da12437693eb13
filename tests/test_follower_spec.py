"""One specification of the follower: follow (descend) and follow_many agree on every rule.

For every step rule, sampling, border, stop rule and escape, on random maps, the vectorized
follow_many gives exactly the points, status, iterations, stop reason and stall point of the scalar
follow (escapes: follow_many hands the stalled points to follow, so the results must still agree;
the navigation escape's cuts, of the jitter before a stall and of the loops of every run, are
exercised in these cases).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from gridfield.core.grid import Grid, GridMap
from gridfield.fields.potential import build_field
from gridfield.following.follower import follow, follow_many

RULES = [
    {"step_rule": "normalized"},
    {"step_rule": "scaled", "alpha": 0.02},
    {"step_rule": "scaled", "alpha": 0.02, "min_speed": 0.3},
]
SAMPLINGS = ["bilinear", "nearest"]
BORDERS = ["open", "wall"]
STOPS = [
    {},                                             # defaults: confined jitter, progress window, oscillation
    {"confine_window": 0, "progress_window": 30},   # the progress window alone
    {"confine_window": 0, "progress_window": 0},    # oscillation only
    {"gradient_threshold": 0.5},                    # small gradient
    {"max_iterations": 25},                         # the step budget
    {"zeta": 1.0, "d_star": float("inf"), "eta": 0.0},  # no repulsion: pressed onto walls (blocked, sliding)
]
ESCAPES = [{}, {"escape": "random_walk", "escape_tries": 3}, {"escape": "navigation"},
           {"escape": "navigation", "escape_tries": 1}]


def random_field(border: str, seed: int):
    rng = np.random.default_rng(seed)
    occ = rng.random((22, 30)) < 0.18
    occ[2:4, 2:4] = False
    gm = GridMap(Grid(occ.shape, 0.5, (-1.0, 2.0), border=border), occ)
    free = np.argwhere(~occ)
    goal = gm.grid.cell_to_world(free[rng.integers(len(free))][None, :])[0]
    starts = gm.grid.cell_to_world(free[rng.choice(len(free), 12, replace=False)])
    starts = starts + rng.uniform(-0.2, 0.2, starts.shape)
    return build_field(gm, goal), starts


@pytest.mark.parametrize(("rule", "sampling", "border"), list(itertools.product(RULES, SAMPLINGS, BORDERS)))
def test_follow_many_equals_follow_for_every_rule(rule, sampling, border):
    f, starts = random_field(border, seed=len(str(rule)) + 7 * SAMPLINGS.index(sampling) + BORDERS.index(border))
    seen = set()
    for stop, esc in itertools.product(STOPS, ESCAPES):
        params = {**rule, "sampling": sampling, **stop, **esc}
        many = follow_many(f, starts, params=params)
        for s, pm in zip(starts, many, strict=True):
            p1 = follow(f, s, params=params)
            seen.add((p1.status, p1.extra.get("stop_reason")))
            assert (pm.status, pm.iterations) == (p1.status, p1.iterations), params
            np.testing.assert_array_equal(pm.points, p1.points)
            for key in ("stop_reason", "stall_point", "blocked_at", "slid_steps", "goal_appended"):
                assert pm.extra.get(key) == p1.extra.get(key), (key, params)
    statuses = {st for st, _ in seen}
    assert "reached" in statuses and "local_minimum" in statuses


def test_every_stop_rule_is_exercised():
    """The cases above reach each stop reason at least once (so the equality covers them)."""
    reasons = set()
    for border, rule, seed in itertools.product(BORDERS, RULES, (3, 4)):
        f, starts = random_field(border, seed=seed)
        for stop in STOPS:
            for p in follow_many(f, starts, params={**rule, **stop}):
                reasons.add(p.extra["stop_reason"])
    assert {"goal", "no_progress", "confined", "oscillation", "small_gradient", "max_iterations",
            "blocked"} <= reasons, reasons


def test_the_navigation_cuts_are_exercised():
    """In the cases above, navigation escapes drop the jitter before a stall, and follow_many's own
    runs (never stalled, so not handed to follow) get their loops cut like descend's."""
    dropped = looped = 0
    for border, rule, sampling in itertools.product(BORDERS, RULES, SAMPLINGS):
        f, starts = random_field(border, seed=len(str(rule)) + 7 * SAMPLINGS.index(sampling) + BORDERS.index(border))
        for stop in ({}, {"confine_window": 0, "progress_window": 0, "max_iterations": 300}):
            base = {**rule, "sampling": sampling, **stop}
            pairs = zip(follow_many(f, starts, params={**base, "escape": "navigation"}), follow_many(f, starts, params=base),
                        strict=True)
            for pm, p0 in pairs:
                dropped += sum(e.get("dropped", 0) > 0 for e in pm.extra["escapes"])
                if not pm.extra["escapes"]:  # the run of the classic field, its loops cut
                    assert p0.status == pm.status and p0.iterations == pm.iterations
                    assert len(pm.points) <= len(p0.points) and pm.length <= p0.length + 1e-9
                    assert pm.points[0].tolist() == p0.points[0].tolist() and pm.end.tolist() == p0.end.tolist()
                    looped += len(pm.points) < len(p0.points)
    assert dropped and looped, (dropped, looped)
