"""The potential planner on voxel grids: the default complete field nf1 (navfield3d) and its follower
(following/follow3d) reach, every segment clear of every blocked voxel by an exact test written here;
the classic Khatib field (potential3d) against finite differences of its formula; bad input."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.fields.navfield import nav_field
from gridfield.fields.potential import build_field
from gridfield.planners import plan


def segment_touches_blocked(occ, p, q):
    """Whether segment p -> q (cell units, array order) meets the closed cube of a blocked voxel or leaves
    the grid: a slab test of every voxel of the segment's bounding box grown by one."""
    lo = np.floor(np.minimum(p, q)).astype(int) - 1
    hi = np.floor(np.maximum(p, q)).astype(int) + 1
    n = np.array(occ.shape)
    if (np.minimum(p, q) < 0).any() or (np.maximum(p, q) > n).any():
        return True
    for cube in itertools.product(*[range(lo[a], hi[a] + 1) for a in range(3)]):
        inside = all(0 <= cube[a] < n[a] for a in range(3))
        if inside and not occ[cube]:
            continue
        t0, t1 = 0.0, 1.0
        ok = True
        for a in range(3):
            d = q[a] - p[a]
            if d == 0:
                if not cube[a] <= p[a] <= cube[a] + 1:
                    ok = False
                    break
                continue
            u, v = sorted(((cube[a] - p[a]) / d, (cube[a] + 1 - p[a]) / d))
            t0, t1 = max(t0, u), min(t1, v)
            if t0 > t1:
                ok = False
                break
        if ok:
            return True
    return False


def assert_clear(gm, points):
    g = gm.grid
    q = ((points - np.asarray(g.origin)) / g.resolution)[:, ::-1]
    for a, b in itertools.pairwise(q):
        assert not segment_touches_blocked(gm.occupied, a, b), (a, b)


def rooms(n=16):
    """Four rooms (a wall across x and one across z), one door through each wall."""
    occ = np.zeros((n, n, n), bool)
    m = n // 2
    occ[:, :, m] = True
    occ[m, :, :] = True
    occ[2:4, 2:4, m] = False  # door in the x wall (lower half)
    occ[m, 10:12, 12:14] = False  # hatch in the floor between the layers
    occ[m + 3:m + 5, 12:14, m] = False  # door in the x wall (upper half)
    return occ


def maze(n=15):
    """Walls across y every third row, each with one gap, alternating ends (a zig-zag)."""
    occ = np.zeros((n, n, n), bool)
    for i, r in enumerate(range(2, n - 1, 3)):
        occ[:, r, :] = True
        if i % 2:
            occ[:2, r, :2] = False
        else:
            occ[-2:, r, -2:] = False
    return occ


def endpoints(occ, rng):
    free = np.argwhere(~occ)
    a, b = free[rng.choice(len(free), 2, replace=False)]
    return a, b


@pytest.mark.parametrize("border", ["open", "wall"])
@pytest.mark.parametrize("name", ["rooms", "maze"])
def test_default_planner_reaches_structured_maps(name, border):
    occ = rooms() if name == "rooms" else maze()
    gm = GridMap(Grid(occ.shape, 0.25, border=border), occ)
    g = gm.grid
    if name == "rooms":
        s, e = g.cell_to_world([[1, 1, 1], [14, 14, 14]])
    else:
        s, e = g.cell_to_world([[7, 0, 7], [7, 14, 7]])
    p = plan("potential", gm, s, e)
    assert p.status == "reached" and p.params["model"] == "nf1"
    assert p.points.shape[1] == 3
    np.testing.assert_array_equal(p.points[0], s)
    np.testing.assert_array_equal(p.points[-1], e)
    assert_clear(gm, p.points)
    opt = plan("wavefront-octile", gm, s, e)
    assert opt.status == "reached"
    assert_clear(gm, opt.points)
    # within a bound of the 26-neighbour optimum (the clearance band may lengthen the way)
    assert p.length <= 1.3 * opt.length + 2 * g.resolution
    straight = float(np.linalg.norm(e - s))
    assert p.length >= straight - 1e-9


@settings(max_examples=12, deadline=None)
@given(st.integers(0, 2**31 - 1), st.sampled_from([0.1, 0.2, 0.3]), st.sampled_from(["open", "wall"]))
def test_default_planner_reaches_random_maps(seed, frac, border):
    rng = np.random.default_rng(seed)
    occ = rng.random((12, 12, 12)) < frac
    gm = GridMap(Grid(occ.shape, 0.5, border=border), occ)
    a, b = endpoints(occ, rng)
    s, e = gm.grid.cell_to_world([a, b])
    opt = plan("wavefront-octile", gm, s, e)
    p = plan("potential", gm, s, e)
    if opt.status == "no_path":
        assert p.status == "no_path" and "cannot be reached" in p.hint
        return
    assert p.status == "reached", p.extra
    np.testing.assert_array_equal(p.points[-1], e)
    assert_clear(gm, p.points)
    assert p.length <= 1.3 * opt.length + 2 * gm.grid.resolution


def test_nf1_field_is_a_navigation_function():
    """Every settled voxel but the goal has a lower allowed neighbour (the field's single minimum)."""
    from gridfield.fields.navigation3d import voxel_descent

    occ = rooms()
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    f = nav_field(gm, (1.5, 1.5, 1.5))
    assert f.grad_z is not None and f.params["model"] == "nf1"
    fin = np.argwhere(np.isfinite(f.potential))
    rng = np.random.default_rng(0)
    for cell in fin[rng.choice(len(fin), 30, replace=False)]:
        _, reached = voxel_descent(gm, f.potential, gm.grid.cell_to_world(cell)[0])
        assert reached
    assert np.isinf(f.potential[occ]).all() and (f.grad_x[occ] == 0).all()


def test_khatib_gradient_matches_finite_differences():
    occ = np.zeros((10, 10, 10), bool)
    occ[4:6, 4:6, 4:6] = True
    gm = GridMap(Grid(occ.shape, 0.5), occ)
    goal = np.array([4.75, 4.75, 0.25])
    params = {"model": "khatib", "zeta": 1.5, "d_star": 2.0, "eta": 0.8, "q_star": 1.2}
    f = build_field(gm, goal, params)
    assert f.grad_z is not None
    obst = gm.grid.cell_to_world(np.argwhere(occ))

    def U(x, nearest):
        d = np.linalg.norm(x - goal)
        att = 0.5 * 1.5 * d * d if d <= 2.0 else 2.0 * 1.5 * d - 0.5 * 1.5 * 4.0
        D = np.linalg.norm(x - nearest)
        rep = 0.5 * 0.8 * (1 / D - 1 / 1.2) ** 2 if D < 1.2 else 0.0
        return att + rep

    h = 1e-6
    for cell in np.argwhere(~occ):
        x = gm.grid.cell_to_world(cell)[0]
        dists = np.linalg.norm(obst - x, axis=1)
        k = int(np.argmin(dists))
        if np.sum(np.isclose(dists, dists[k])) > 1:
            continue  # a tie of nearest obstacles: the gradient is one-sided there
        num = [(U(x + h * e, obst[k]) - U(x - h * e, obst[k])) / (2 * h) for e in np.eye(3)]
        got = [f.grad_x[tuple(cell)], f.grad_y[tuple(cell)], f.grad_z[tuple(cell)]]
        np.testing.assert_allclose(got, num, rtol=1e-5, atol=1e-6)
        assert math.isclose(f.potential[tuple(cell)], U(x, obst[k]), rel_tol=1e-12)


def test_khatib_stalls_in_a_cup_and_says_so():
    """The classic field has a local minimum in front of a cup; the default nf1 goes round."""
    occ = np.zeros((9, 12, 9), bool)
    occ[2:7, 7, 2:7] = True  # the cup's bottom, facing the start
    occ[2:7, 3:7, 2] = occ[2:7, 3:7, 6] = True
    occ[2, 3:7, 2:7] = occ[6, 3:7, 2:7] = True
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    s, e = (4.5, 4.5, 4.5), (4.5, 10.5, 4.5)
    k = plan("potential", gm, s, e, {"model": "khatib"})
    assert k.status == "local_minimum" and "nf1" in k.hint
    assert_clear(gm, k.points)
    p = plan("potential", gm, s, e)
    assert p.status == "reached"
    assert_clear(gm, p.points)


def test_json_and_bad_input():
    gm = GridMap(Grid((4, 4, 4), 1.0), np.zeros((4, 4, 4), bool))
    p = plan("potential", gm, (0.5, 0.5, 0.5), (3.5, 3.5, 3.5))
    j = p.to_json()
    assert j["path"][0] == [0.5, 0.5, 0.5] and j["path"][-1] == [3.5, 3.5, 3.5] and j["status"] == "reached"
    with pytest.raises(ParameterError, match="three numbers X Y Z"):
        plan("potential", gm, (0.5, 0.5), (3.5, 3.5, 3.5))
    with pytest.raises(GridfieldError, match="outside the map"):
        plan("potential", gm, (0.5, 0.5, 4.5), (3.5, 3.5, 3.5))
    with pytest.raises(ParameterError, match="2-D model"):
        plan("potential", gm, (0.5, 0.5, 0.5), (3.5, 3.5, 3.5), {"model": "nf2"})
    with pytest.raises(ParameterError, match="repulsion='sum' is a 2-D option"):
        build_field(gm, (3.5, 3.5, 3.5), {"model": "khatib", "repulsion": "sum"})
    with pytest.raises(ParameterError, match="escape='navigation' is a 2-D follower option"):
        plan("potential", gm, (0.5, 0.5, 0.5), (3.5, 3.5, 3.5), {"model": "khatib", "escape": "navigation"})
    gm2 = GridMap(Grid((4, 4), 1.0), np.zeros((4, 4), bool))
    with pytest.raises(ParameterError, match=r"start must be two finite numbers \(x, y\)"):
        plan("potential", gm2, (0.5, 0.5, 0.5), (3.5, 3.5))


def test_cli_plans_on_a_voxel_grid(monkeypatch, capsys):
    """``gridfield plan MAP --start X Y Z --goal X Y Z`` on a voxel grid (the map's reader stood in for:
    the .3dmap reader is another module's), text and --json."""
    import json

    import gridfield.cli._common as common
    from gridfield.cli import main

    occ = maze()
    gm = GridMap(Grid(occ.shape, 1.0), occ)
    monkeypatch.setattr(common, "_read_target", lambda args: gm)
    assert main(["plan", "maze.3dmap", "--start", "7.5", "0.5", "7.5", "--goal", "7.5", "14.5", "7.5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "reached" and out["path"][0] == [7.5, 0.5, 7.5] and out["path"][-1] == [7.5, 14.5, 7.5]
    assert_clear(gm, np.array(out["path"]))
    assert main(["plan", "maze.3dmap", "--start", "7.5", "0.5", "7.5", "--goal", "7.5", "14.5", "7.5",
                 "--planner", "wavefront-octile"]) == 0
    assert "wavefront-octile: reached" in capsys.readouterr().out
    assert main(["plan", "maze.3dmap", "--start", "7.5", "0.5", "--goal", "7.5", "14.5", "7.5"]) != 0
    assert "--start needs three numbers X Y Z on the voxel grid maze.3dmap, got 2" in capsys.readouterr().err
    assert main(["plan", "maze.3dmap", "--start", "7.5", "0.5", "7.5", "--goal", "7.5", "14.5", "7.5",
                 "--planner", "fmm"]) != 0
    assert "planner 'fmm' plans on 2-D maps" in capsys.readouterr().err


def test_cli_scenario_on_a_voxel_map(tmp_path, capsys):
    """``gridfield plan M.3dmap --scenario S.3dscen --index N`` through the voxel readers: the scenario's
    optimum reported, the 26-neighbour path's length equal to it."""
    import json

    from gridfield.cli import main

    m = tmp_path / "cube.3dmap"
    m.write_text("voxel 4 4 4\n2 0 3\n0 3 1\n")  # off both ways
    sc = tmp_path / "cube.3dscen"
    sc.write_text(f"version 1\ncube.3dmap\n0 0 0 3 3 3 {3 * math.sqrt(3):.6f} 1.0\n0 0 0 3 0 0 3.0 1.0\n")
    assert main(["plan", str(m), "--scenario", str(sc), "--index", "1", "--planner", "wavefront-octile", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "reached" and out["optimal"] == 3.0 and math.isclose(out["length"], 3.0)
    assert out["path"][0] == [0.5, 0.5, 0.5] and out["path"][-1] == [3.5, 0.5, 0.5]
    assert main(["plan", str(m), "--scenario", str(sc), "--planner", "wavefront-octile", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert math.isclose(out["length"], out["optimal"], rel_tol=1e-6)
    assert main(["plan", str(m), "--scenario", str(sc), "--index", "5"]) != 0
    assert "--index 5 is out of range" in capsys.readouterr().err
