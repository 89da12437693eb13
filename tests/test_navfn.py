"""The navfn planner: NavFn's potential and path against Nav2's own navfn.cpp (fixtures), and its planner."""

from __future__ import annotations

import ast
import hashlib
from pathlib import Path

import numpy as np
import pytest

from gridfield.core.grid import Grid, GridMap
from gridfield.fields.costmap import Costmap, inflate
from gridfield.fields.navfn import POT_HIGH, _cycles, _kernels, navfn, navfn_costs, plan_navfn

from mapdata import TEST_MAPS

DATA = Path(__file__).parent / "data" / "navfn"
FIXTURES = sorted(DATA.glob("*.npz"))


def _costmap(fx) -> Costmap:
    from gridfield.io import read

    path = TEST_MAPS / str(fx["map"])
    if not path.exists():  # the fixtures name the maps as published; the suite's copy compresses some
        path = path.with_name(path.name + ".gz")
    return inflate(read(path), **ast.literal_eval(str(fx["options"])))


def test_the_fixtures_hold_at_least_20_queries():
    assert len(FIXTURES) >= 6
    assert sum(len(np.load(f)["start"]) for f in FIXTURES) >= 20


@pytest.mark.parametrize("fixture", FIXTURES, ids=lambda p: p.stem)
def test_potential_and_path_agree_with_nav2_navfn(fixture):
    fx = np.load(fixture)
    cm = _costmap(fx)
    assert hashlib.sha256(cm.cost.tobytes()).hexdigest() == str(fx["cost_sha256"])  # the same costmap
    rows, cols = cm.shape
    k = _kernels()
    so = np.concatenate([[0], np.cumsum(fx["sample_len"])])
    po = np.concatenate([[0], np.cumsum(fx["path_len"])])
    for q, (s, g) in enumerate(zip(fx["start"], fx["goal"], strict=True)):
        cost = navfn_costs(cm, clear=(int(s[0]), int(s[1])))
        pot, _, _ = k.propagate(cost.reshape(-1), cols, rows, int(s[0] * cols + s[1]), int(g[0] * cols + g[1]), True,
                                _cycles(rows, cols))
        assert int(np.count_nonzero(pot < POT_HIGH)) == int(fx["assigned"][q])
        idx = fx["idx"][so[q]:so[q + 1]]
        np.testing.assert_allclose(pot[idx], fx["pot"][so[q]:so[q + 1]], rtol=2.0 ** -23, atol=0)  # measured: bit-identical
        path, status = k.gradient_path(pot, cols, rows, int(g[1]), int(g[0]), int(s[1]), int(s[0]),
                                       max(rows, cols) * 4)
        ref = fx["path"][po[q]:po[q + 1]]
        assert status == 0 and path.shape == ref.shape
        assert float(np.abs(path - ref).max()) <= 0.01


def _empty(rows: int = 12, cols: int = 12, res: float = 1.0) -> Costmap:
    return Costmap.from_costs(Grid((rows, cols), res), np.zeros((rows, cols), np.uint8))


def test_the_potential_on_a_free_line_grows_by_the_neutral_cost():
    nav = navfn(_empty(3, 8), (1.5, 1.5))
    assert nav.value[1, 1:7].tolist() == [0.0, 50.0, 100.0, 150.0, 200.0, 250.0]
    assert np.isinf(nav.value[0]).all() and np.isinf(nav.value[:, -1]).all()  # the blocked ring


def test_the_planar_wave_update_on_an_open_square():
    """Diagonal neighbour: both axis neighbours at 50, so the quadratic fit at ratio 0: 50 + 50 * 0.704."""
    nav = navfn(_empty(5, 5), (2.5, 2.5))
    assert nav.value[3, 3] == pytest.approx(50 + 50 * np.float32(0.704), rel=1e-7)


def test_costs_raise_the_potential_and_blocked_cells_stay_unassigned():
    c = np.zeros((3, 8), np.uint8)
    c[1, 4] = 100
    c[1, 6] = 254
    nav = navfn(Costmap.from_costs(Grid((3, 8), 1.0), c), (1.5, 1.5))
    assert nav.value[1, 4] - nav.value[1, 3] == 50 + 80
    assert np.isinf(nav.value[1, 6])


def test_plan_navfn_goes_round_a_wall_and_ends_at_the_goal():
    occ = np.zeros((30, 30), bool)
    occ[5:25, 14:16] = True
    gm = GridMap(Grid((30, 30), 0.1), occ)
    p = plan_navfn(gm, np.array([0.55, 1.55]), np.array([2.45, 1.55]), {"robot_radius": 0.1, "inflation_radius": 0.3})
    assert p.status == "reached"
    assert p.points[0].tolist() == [0.55, 1.55] and p.points[-1].tolist() == [2.45, 1.55]
    cm = inflate(gm, robot_radius=0.1, inflation_radius=0.3)
    assert (cm.cost_at(p.points) < 253).all()  # never through an inscribed or lethal cell
    assert p.length > 2 * np.hypot(1.0, 1.0)  # round the wall's end, not through it


def test_an_enclosed_goal_is_no_path_or_the_tolerance_point():
    occ = np.zeros((30, 30), bool)
    occ[10:20, 10] = occ[10:20, 19] = occ[10, 10:20] = occ[19, 10:20] = True
    gm = GridMap(Grid((30, 30), 0.1), occ)
    far = plan_navfn(gm, np.array([0.5, 0.5]), np.array([1.5, 1.5]), {"goal_tolerance": 0.0, "robot_radius": 0.0,
                                                                       "inflation_radius": 0.0})
    assert far.status == "no_path" and "unreachable" in far.extra["reason"]
    near = plan_navfn(gm, np.array([0.5, 0.5]), np.array([1.15, 1.15]), {"goal_tolerance": 0.3, "robot_radius": 0.0,
                                                                        "inflation_radius": 0.0})
    assert near.status == "local_minimum" and "goal_tolerance" in near.extra["reason"]
    assert np.abs(near.points[-1] - [1.15, 1.15]).max() <= 0.3 + 1e-9


def test_unknown_cells_are_traversable_only_with_allow_unknown():
    c = np.zeros((5, 9), np.uint8)
    c[:, 4] = 255
    cm = Costmap.from_costs(Grid((5, 9), 1.0), c)
    assert plan_navfn(cm, np.array([1.5, 2.5]), np.array([7.5, 2.5]), {}).status == "reached"
    assert plan_navfn(cm, np.array([1.5, 2.5]), np.array([7.5, 2.5]), {"allow_unknown": "false"}).status == "no_path"


def test_the_planner_is_registered_and_plans_a_costmap_file(tmp_path):
    from gridfield.io import read, write_costmap
    from gridfield.planners import PLANNERS, plan

    assert PLANNERS["navfn"].function == "plan_navfn"
    occ = np.zeros((30, 30), bool)
    occ[5:25, 14:16] = True
    cm = inflate(GridMap(Grid((30, 30), 0.1), occ), robot_radius=0.1, inflation_radius=0.3)
    back = read(write_costmap(tmp_path / "c.yaml", cm))
    a = plan("navfn", back, (0.55, 1.55), (2.45, 1.55))
    b = plan("navfn", GridMap(Grid((30, 30), 0.1), occ), (0.55, 1.55), (2.45, 1.55),
             {"robot_radius": 0.1, "inflation_radius": 0.3})
    assert a.status == b.status == "reached"
    np.testing.assert_array_equal(a.points, b.points)


def test_navfn_costs_are_setcostmaps_translation_for_every_cost():
    c = np.arange(256, dtype=np.uint8).reshape(16, 16)
    cm = Costmap.from_costs(Grid((16, 16), 1.0), c)
    for allow in (True, False):
        got = navfn_costs(cm, allow_unknown=allow, clear=(3, 4))
        v = c.astype(int)
        v[3, 4] = 0
        want = np.where(v < 253, np.minimum([[int(50 + 0.8 * x) for x in row] for row in v], 253),
                        np.where((v == 255) & allow, 253, 254))
        want[0, :] = want[-1, :] = want[:, 0] = want[:, -1] = 254
        np.testing.assert_array_equal(got, want)
