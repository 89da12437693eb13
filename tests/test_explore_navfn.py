"""Issue 26: the explorer lists NavFn and shows its potential, on a costmap and on an occupancy map."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

from gridfield.core.grid import Grid, GridMap
from gridfield.explore import PLANNER_SLIDERS, Explorer, available_planners
from gridfield.fields.costmap import inflate
from gridfield.fields.navfn import navfn
from gridfield.planners import plan


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _occupancy() -> GridMap:
    occ = np.zeros((40, 40), bool)
    occ[5:35, 18:22] = True
    return GridMap(Grid(occ.shape, 0.25), occ, source="wall")


@pytest.mark.parametrize("kind", ["occupancy", "costmap"])
def test_the_explorer_plans_with_navfn_and_shows_its_potential(kind) -> None:
    gm = _occupancy()
    target = gm if kind == "occupancy" else inflate(gm, robot_radius=0.2, inflation_radius=0.6)
    assert "navfn" in available_planners(world=False) and PLANNER_SLIDERS["navfn"] == ()
    e = Explorer(target, planner="navfn")
    e.set_start(1.1, 5.1)
    e.set_goal(8.9, 5.1)
    want = plan("navfn", target, (1.1, 5.1), (8.9, 5.1))  # the planner, called directly
    assert e.path is not None and e.path.status == want.status == "reached"
    np.testing.assert_array_equal(e.path.points, want.points)
    ref = navfn(target, (8.9, 5.1))  # NavFn's own potential from the goal
    assert e.field is not None and e.field.kind == "navfn"
    np.testing.assert_array_equal(e.field.potential, ref.value)
    assert e.field_image.get_visible()  # drawn, as every other field
    e.set_planner("wavefront-octile")  # no potential: the background goes
    assert e.field is None and not e.field_image.get_visible()
    e.close()
