"""Every navigation-function planner ends ``reached`` at its goal, reports the parameters it used, and
says why when it cannot reach (issue: fmm stopped 0.014 m from the goal as ``local_minimum``)."""

from __future__ import annotations

import numpy as np
import pytest

from gridfield.core.grid import Grid, GridMap
from gridfield.fields.navigation import NavigationField, extract_path
from gridfield.planners import plan


def _flat_field(kind: str) -> NavigationField:
    """A 1 x 6 corridor whose value has a flat spot (cells 1 and 2 equal): a follower that needs a
    strictly lower neighbour stops there, short of the goal in cell 0."""
    gm = GridMap(Grid((1, 6), 1.0), np.zeros((1, 6), bool))
    return NavigationField(gm, np.array([[0.0, 1.0, 1.0, 2.0, 3.0, 4.0]]), np.array([0.5, 0.5]), (0, 0), kind, {}, {})


@pytest.mark.parametrize("method", ["gradient", "descent"])
def test_a_flat_spot_is_finished_on_the_wavefront(method: str) -> None:
    p = extract_path(_flat_field("fmm" if method == "gradient" else "harmonic"), (5.5, 0.5), method=method)
    assert p.status == "reached" and p.points[-1].tolist() == [0.5, 0.5]
    assert p.extra["finished_by"] == "wavefront"
    assert np.all(np.diff(p.points[:, 0]) < 0)  # straight down the corridor, no step back
    assert p.params["method"] == method


def test_a_flat_spot_cut_off_from_the_goal_says_why() -> None:
    gm = GridMap(Grid((1, 6), 1.0), np.array([[False, True, False, False, False, False]]))
    nav = NavigationField(gm, np.array([[0.0, np.inf, 1.0, 2.0, 3.0, 4.0]]), np.array([0.5, 0.5]), (0, 0), "fmm", {}, {})
    p = extract_path(nav, (5.5, 0.5))
    assert p.status == "local_minimum" and "no free path" in p.extra["reason"] and p.hint == p.extra["reason"]


def _maze() -> tuple[GridMap, tuple[float, float], tuple[float, float]]:
    rng = np.random.default_rng(3)
    occ = rng.random((60, 80)) < 0.22
    occ[:3, :3] = occ[-3:, -3:] = False
    return GridMap(Grid(occ.shape, 0.02, origin=(-0.3, 0.1)), occ), (-0.27, 0.13), (1.27, 1.27)


@pytest.mark.parametrize("planner", ["wavefront", "wavefront-octile", "fmm", "harmonic"])
def test_navigation_planners_reach_and_report_their_parameters(planner: str) -> None:
    pytest.importorskip("skfmm") if planner == "fmm" else None
    gm, s, g = _maze()
    p = plan(planner, gm, s, g)
    assert p.status == "reached", p.hint
    assert np.hypot(*(p.end - np.array(g))) <= 1e-12
    assert "method" in p.params
    if p.params["method"] == "gradient":
        res = gm.grid.resolution
        assert 0 < p.params["step"] <= res and p.params["tolerance"] == pytest.approx(0.5 * res)
        assert p.params["max_iterations"] > 0
        json_params = p.to_json()["params"]
        assert {"step", "tolerance", "max_iterations", "method"} <= json_params.keys()
