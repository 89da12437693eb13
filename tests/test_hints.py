"""The hint of a failed potential run holds: a ``--q-star`` is proposed only when a re-run with it
reached, one trap gets one description whatever the start, and ``Path.hint`` exposes it."""

from __future__ import annotations

import re

import numpy as np
import pytest

from gridfield.core.grid import Grid, GridMap
from gridfield.io import bundled_map, read
from gridfield.planners import plan

#: the classic field (the potential planner defaults to the complete nf1 model, which does not stall)
KHATIB = {"model": "khatib"}


def cup_map() -> GridMap:
    """A cup open towards the starts (left), the goal behind its bottom (right): one trap."""
    occ = np.zeros((40, 40), bool)
    occ[12:29, 20] = True
    occ[12, 13:21] = True
    occ[28, 13:21] = True
    return GridMap(Grid(occ.shape, 1.0, border="wall"), occ)


def test_one_trap_one_description_whatever_the_start() -> None:
    gm = cup_map()
    goal = (35.5, 20.5)
    starts = [(8.5, 15.5), (5.5, 25.5), (15.5, 20.5), (10.5, 19.5)]
    paths = [plan("potential", gm, s, goal, KHATIB) for s in starts]
    assert all(p.status == "local_minimum" for p in paths)
    ends = {tuple(np.round(p.end, 3)) for p in paths}
    assert len(ends) > 1  # the runs stop at different points of the trap ...
    assert len({p.hint for p in paths}) == 1, [p.hint for p in paths]  # ... and get one description
    d = paths[0].extra["diagnosis"]
    # the trap is named by the cell where discrete steepest descent ends: inside the cup
    assert 13 < d["trap"][0] < 20 and 12 < d["trap"][1] < 28
    assert f"({d['trap'][0]:.3g}, {d['trap'][1]:.3g})" in paths[0].hint


def _suggested(hint: str) -> float | None:
    m = re.search(r"try --q-star ([0-9.e+-]+)", hint)
    return float(m.group(1)) if m else None


def test_a_suggested_q_star_was_tried_and_reaches() -> None:
    """seed000_segment: today's hint proposed --q-star 1.35, which stalls again (and proposes 1.02, ...)."""
    world = read(bundled_map("seed000_segment.yaml"))
    from gridfield.geometry.rasterize import as_gridmap

    gm = as_gridmap(world)
    params = dict(world.params)
    p = plan("potential", gm, world.start, world.goal, params)
    assert p.status == "local_minimum" and p.hint
    d = p.extra["diagnosis"]
    q = _suggested(p.hint)
    if q is not None:
        assert d["suggest"] == {"q_star": q} and [q, "reached"] in d["tried"]
        assert plan("potential", gm, world.start, world.goal, {**params, "q_star": q}).reached
    else:  # what is true: the passage, and what was tried
        assert "passage" in d and all(status != "reached" for _, status in d.get("tried", []))
        assert "--escape navigation reaches it" in p.hint
    assert plan("potential", gm, world.start, world.goal, {**params, "escape": "navigation"}).reached


def test_arena_suggestion_reaches_as_readme_shows() -> None:
    from gridfield.io import read_scen

    gm = read(bundled_map("arena/arena.map"))
    sc = read_scen(bundled_map("arena/arena.map.scen"), map_height=gm.grid.rows)
    s, g = sc.start_xy[159], sc.goal_xy[159]
    p = plan("potential", gm, s, g, KHATIB)
    assert p.status == "local_minimum"
    q = _suggested(p.hint)
    assert q == pytest.approx(0.9)
    assert plan("potential", gm, s, g, {**KHATIB, "q_star": q}).reached


def test_path_hint_property_and_json() -> None:
    gm = cup_map()
    p = plan("potential", gm, (8.5, 15.5), (35.5, 20.5), KHATIB)
    assert p.hint == p.extra["hint"] and p.to_json()["hint"] == p.hint
    assert plan("potential", gm, (25.5, 20.5), (35.5, 20.5), KHATIB).hint is None
