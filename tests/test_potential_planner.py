"""The potential planner on the maps people bring (issue: follower safety, scaled defaults, hints,
the navigation escape, Moving AI scenarios on the command line).

Oracles: shapely's exact geometry for "no segment crosses an occupied cell", the octile wavefront
(tested against the Moving AI optimal lengths in test_movingai.py) and a 4-connected labelling by
scipy for reachability, hand formulas for the scaled defaults.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from gridfield.cli import main
from gridfield.core.errors import ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.core.params import REGISTRY, balanced_eta, parse, resolve, validate
from gridfield.fields.potential import build_field
from gridfield.io import read_movingai_map, read_scen
from gridfield.planners import plan, plan_with_field

from mapdata import movingai_pairs

REPO = Path(__file__).resolve().parent.parent


# ------------------------------------------------------------------------------------------------
# an independent check: no path segment enters the interior of an occupied cell
# ------------------------------------------------------------------------------------------------
def occupied_interiors(gm: GridMap) -> shapely.STRtree:
    """The occupied cells' open squares (shrunk by 1e-9 of a cell) in a spatial index, exact geometry."""
    g = gm.grid
    eps = 1e-9 * g.resolution
    r, c = np.nonzero(gm.occupied)
    x0 = g.origin[0] + c * g.resolution
    y0 = g.origin[1] + r * g.resolution
    return shapely.STRtree(shapely.box(x0 + eps, y0 + eps, x0 + g.resolution - eps, y0 + g.resolution - eps))


def assert_path_free(gm: GridMap, points: np.ndarray) -> None:
    pts = np.asarray(points, dtype=float)
    assert np.isfinite(pts).all()
    if len(pts) >= 2:
        segments = shapely.linestrings(np.stack([pts[:-1], pts[1:]], axis=1))
        seg, _box = occupied_interiors(gm).query(segments, predicate="intersects")
        assert not len(seg), f"segment {seg[:1]} of the path enters an occupied cell"
    if gm.grid.border == "wall":
        xmin, ymin, xmax, ymax = gm.grid.bounds
        assert (pts[:, 0] >= xmin).all() and (pts[:, 0] <= xmax).all()
        assert (pts[:, 1] >= ymin).all() and (pts[:, 1] <= ymax).all()


@st.composite
def random_maps(draw):
    rows, cols = draw(st.integers(6, 18)), draw(st.integers(6, 18))
    seed = draw(st.integers(0, 2**31 - 1))
    density = draw(st.sampled_from([0.1, 0.25, 0.4]))
    border = draw(st.sampled_from(["open", "wall"]))
    res = draw(st.sampled_from([1.0, 0.05]))
    rng = np.random.default_rng(seed)
    occ = rng.random((rows, cols)) < density
    free = np.flatnonzero(~occ)
    if len(free) < 2:
        occ[0, 0] = occ[-1, -1] = False
        free = np.flatnonzero(~occ)
    i, j = rng.choice(free, 2, replace=False)
    g = Grid((rows, cols), res, border=border)
    gm = GridMap(g, occ)
    centres = g.cell_to_world(np.array([divmod(int(i), cols), divmod(int(j), cols)]))
    jitter = rng.uniform(-0.4, 0.4, (2, 2)) * res  # anywhere in the cell, not only at its centre
    return gm, centres[0] + jitter[0], centres[1] + jitter[1]


VARIANTS = [
    {},
    {"step_rule": "scaled", "alpha": 0.05},
    {"sampling": "nearest"},
    {"escape": "random_walk"},
    {"escape": "potential_increase"},
    {"escape": "navigation"},
    {"step": 3.0},  # steps of 3 cells (scaled below): the fallbacks must shorten them near walls
    {"zeta": 1.0, "d_star": math.inf, "eta": 0.0},  # no repulsion at all: attraction drives into walls
]


@settings(max_examples=40)
@given(case=random_maps())
def test_no_step_of_any_rule_or_escape_enters_an_obstacle(case):
    gm, start, goal = case
    h = gm.grid.resolution
    for variant in VARIANTS:
        params = {k: (v * h if k == "step" else v) for k, v in variant.items()}
        p = plan("potential", gm, start, goal, {"model": "khatib", **params})
        assert p.status in ("reached", "local_minimum", "max_iterations", "no_path"), (variant, p.status)
        assert_path_free(gm, p.points)
        if p.status != "reached":
            assert p.extra.get("hint"), (variant, p.status)


@settings(max_examples=30)
@given(case=random_maps())
def test_follow_many_and_basins_never_enter_an_obstacle(case):
    from gridfield.following.follower import basins, follow_many

    gm, _start, goal = case
    if not gm.is_free(goal)[0]:
        return
    f = build_field(gm, goal)
    free_cells = np.argwhere(~gm.occupied)
    starts = gm.grid.cell_to_world(free_cells[:12])
    for path in follow_many(f, starts):
        assert path.status != "collision"
        assert_path_free(gm, path.points)
    # every descent move of the basins joins two cells with a free straight segment
    b = basins(f)
    succ = b.sink  # sinks; check the one-step successors instead
    from gridfield.following.follower import descent_successor

    nxt = descent_successor(f.potential, ~gm.occupied)
    flat = np.flatnonzero(~gm.occupied.reshape(-1))
    src = np.column_stack(np.divmod(flat, gm.grid.cols))
    dst = np.column_stack(np.divmod(nxt[flat], gm.grid.cols))
    a, z = gm.grid.cell_to_world(src), gm.grid.cell_to_world(dst)
    moved = np.any(a != z, axis=1)
    if moved.any():
        lines = shapely.linestrings(np.stack([a[moved], z[moved]], axis=1))
        assert not len(occupied_interiors(gm).query(lines, predicate="intersects")[0])
    assert succ.shape == gm.grid.shape


# ------------------------------------------------------------------------------------------------
# the navigation escape is complete
# ------------------------------------------------------------------------------------------------
def reachable(gm: GridMap, start, goal) -> bool:
    """4-connected free regions (scipy), with a free ring around an open map: the octile wavefront's
    rule (a diagonal move that cuts no corner is two orthogonal ones)."""
    occ = gm.occupied
    if gm.grid.border == "open":
        occ = np.pad(occ, 1, constant_values=False)
    lab = ndimage.label(~occ)[0]
    off = 1 if gm.grid.border == "open" else 0
    (a,), (b,) = gm.grid.world_to_cell(np.array([start]))[0], gm.grid.world_to_cell(np.array([goal]))[0]
    return bool(lab[a[0] + off, a[1] + off] == lab[b[0] + off, b[1] + off])


@settings(max_examples=40)
@given(case=random_maps())
def test_navigation_escape_reaches_every_reachable_goal(case):
    gm, start, goal = case
    p = plan("potential", gm, start, goal, {"model": "khatib", "escape": "navigation"})
    if reachable(gm, start, goal):
        assert p.status == "reached", p.extra.get("hint")
        assert np.allclose(p.end, goal)
    else:
        assert p.status == "no_path" and "cannot be reached" in p.extra["hint"] and len(p.points) == 1


def test_navigation_escape_on_every_moving_ai_map(test_maps):
    """A sample of scenarios on every Moving AI map in tests/data/maps: defaults never collide or
    crash and carry a hint when they fail; with escape navigation every reachable goal is reached."""
    pairs = movingai_pairs(test_maps)
    assert len(pairs) >= 20
    for map_file, scen_file in pairs:
        gm = read_movingai_map(map_file)
        scen = read_scen(scen_file, map_height=gm.grid.rows)
        cache: dict = {}
        for i in np.linspace(0, len(scen) - 1, 3).round().astype(int):
            s, g = scen.start_xy[i], scen.goal_xy[i]
            if not (gm.is_free(s)[0] and gm.is_free(g)[0]):
                continue
            d = plan("potential", gm, s, g, {"model": "khatib"}, cache=cache)
            assert d.status != "collision" and (d.reached or d.extra.get("hint")), (map_file.name, i)
            n = plan("potential", gm, s, g, {"model": "khatib", "escape": "navigation"}, cache=cache)
            if scen.no_path[i]:
                assert n.status == "no_path", (map_file.name, i)
                continue
            assert n.status == "reached", (map_file.name, i, n.extra.get("hint"))
            assert_path_free(gm, n.points)
            # the potential path is any-angle, so never much longer than twice the octile optimum here
            assert n.length >= scen.optimal[i] / 1.0824 - 1.0


def test_navigation_segments_are_recorded_and_drawn():
    from gridfield.io import bundled_map
    from gridfield.plot import plot_map

    gm = read_movingai_map(bundled_map("arena/arena.map"))
    scen = read_scen(bundled_map("arena/arena.map.scen"), map_height=gm.grid.rows)
    p = plan("potential", gm, scen.start_xy[159], scen.goal_xy[159], {"model": "khatib", "escape": "navigation"})
    assert p.reached and p.extra["navigation_segments"]
    i0, i1 = p.extra["navigation_segments"][0]
    assert 0 <= i0 < i1 < len(p.points)
    art = plot_map(gm, paths=[p])
    assert len(art.extra["navigation"]) == len(p.extra["navigation_segments"])


# ------------------------------------------------------------------------------------------------
# defaults that scale with the map
# ------------------------------------------------------------------------------------------------
def test_same_map_at_two_resolutions_gives_the_same_path_in_cells():
    rng = np.random.default_rng(7)
    occ = rng.random((30, 40)) < 0.2
    occ[2, 2] = occ[27, 37] = False
    paths = []
    for h in (1.0, 0.05):
        gm = GridMap(Grid(occ.shape, h, (3.0 * h, -2.0 * h), border="wall"), occ)
        s = gm.grid.cell_to_world(np.array([[2, 2]]))[0]
        g = gm.grid.cell_to_world(np.array([[27, 37]]))[0]
        for esc in ("none", "navigation"):
            p = plan("potential", gm, s, g, {"model": "khatib", "escape": esc})
            paths.append((p.status, (p.points - gm.grid.origin) / h))
    assert paths[0][0] == paths[2][0] and paths[1][0] == paths[3][0] == "reached"
    np.testing.assert_allclose(paths[0][1], paths[2][1], atol=1e-6)
    np.testing.assert_allclose(paths[1][1], paths[3][1], atol=1e-6)


def test_scaled_defaults_follow_their_rules():
    for unit in (1.0, 0.05, 0.03):
        r = resolve({}, unit=unit)
        assert r["q_star"] == pytest.approx(4 * unit) and r["d_star"] == pytest.approx(8 * unit)
        assert r["step"] == pytest.approx(unit) and r["tolerance"] == pytest.approx(unit)
        assert r["escape_radius"] == pytest.approx(6 * unit)
        # balanced: the repulsive force eta*(1/D - 1/q*)/D**2 at D = q*/2 equals zeta*d_star
        D = r["q_star"] / 2
        assert r["eta"] * (1 / D - 1 / r["q_star"]) / D**2 == pytest.approx(r["zeta"] * r["d_star"])
    # given values always win (the seeds' worlds)
    r = resolve({"q_star": 2.0, "d_star": math.inf, "eta": 1.0, "step": 0.1}, unit=0.05)
    assert (r["q_star"], r["d_star"], r["eta"], r["step"]) == (2.0, math.inf, 1.0, 0.1)
    # a given q_star rescales the balanced gain and d_star with it
    r = resolve({"q_star": 1.0}, unit=0.05)
    assert r["d_star"] == 2.0 and r["eta"] == pytest.approx(balanced_eta(1.0, 2.0, 1.0, 2.0, 0.05))


def test_balanced_gain_wins_near_a_wall_in_the_field():
    """In a built field, one cell from a wall the force points away from it, far from the goal."""
    occ = np.zeros((20, 60), bool)
    occ[:, 30] = True
    gm = GridMap(Grid(occ.shape, 0.05, border="wall"), occ)
    f = build_field(gm, (2.9, 0.5))  # goal beyond the wall on the right
    # the cell left of the wall, middle row: the x force -dU/dx must push left (away from the wall)
    assert -f.grad_x[10, 29] < 0
    # two cells off a wall the attraction (conic, 8 cells * zeta) still beats nothing: free space pulls right
    assert -f.grad_x[10, 10] > 0


def test_every_registry_entry_checks_its_own_default_and_has_help():
    for name, spec in REGISTRY.items():
        assert spec.check(spec.default) == spec.default or spec.default is None
        assert spec.meaning and spec.planners, name
        if spec.default is None and spec.kind in ("number", "integer"):
            assert spec.scale or spec.allow_none, name


@pytest.mark.parametrize(("params", "words"), [
    ({"step": "abc"}, "step must be a finite number > 0, got 'abc'"),
    ({"kappa": "abc"}, "kappa must be a finite number > 0"),
    ({"max_iterations": "10"}, "max_iterations must be an integer"),
    ({"q_star": math.nan}, "q_star must be a number > 0"),
    ({"escape": "teleport"}, "escape must be one of 'none', 'random_walk', 'potential_increase', 'navigation'"),
    ({"planers": 1}, "unknown parameter 'planers'"),
    ({"workspace_center": [1, "x"]}, "workspace_center must be two numbers"),
])
def test_bad_values_are_named(params, words):
    with pytest.raises(ParameterError, match=words.replace("(", r"\(").replace(")", r"\)")):
        validate(params)


def test_parse_follows_the_parameter_type():
    assert parse("connectivity", "4") == 4 and parse("alpha", "0.1,0.2") == (0.1, 0.2)
    assert parse("d_star", "inf") == math.inf and parse("seed", "none") is None
    assert parse("workspace_center", "1,2") == (1.0, 2.0)


def test_plan_accepts_a_mapping_and_rejects_other_params():
    gm = GridMap(Grid((5, 5), 1.0), np.zeros((5, 5), bool))
    assert plan("potential", gm, (0.5, 0.5), (4.5, 4.5), {"q_star": 1.0}).reached
    with pytest.raises(TypeError, match="params must be a mapping"):
        plan("potential", gm, (0.5, 0.5), (4.5, 4.5), [1, 2])  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="target must be a World"):
        plan("potential", None, (0.5, 0.5), (4.5, 4.5))  # type: ignore[arg-type]


# ------------------------------------------------------------------------------------------------
# hints
# ------------------------------------------------------------------------------------------------
def corridor_map() -> tuple[GridMap, tuple[float, float], tuple[float, float]]:
    """Two rooms joined by a corridor 3 cells wide: narrower than 2 q_star (8 cells)."""
    occ = np.zeros((31, 61), bool)
    occ[:, 30] = True
    occ[:14, 28:33] = True
    occ[17:, 28:33] = True
    occ[14:17, 30] = False
    occ[14:17, 28:33] = False
    return GridMap(Grid(occ.shape, 0.05, border="wall"), occ), (0.5, 0.2), (2.6, 1.3)


def test_hint_names_the_passage_and_its_q_star_works():
    gm, s, g = corridor_map()
    p = plan("potential", gm, s, g, {"model": "khatib"})
    assert p.status == "local_minimum"
    d = p.extra["diagnosis"]
    assert d["reachable"] and 0 < d["basin_share"] <= 1
    # the corridor is 3 cells wide: its centre line is 2 cells from the walls
    assert d["passage"]["clearance"] == pytest.approx(0.1)
    assert 1.4 <= d["passage"]["at"][0] <= 1.65  # in the corridor (x in [1.4, 1.65))
    assert "try --q-star" in p.extra["hint"] and "--escape navigation reaches it" in p.extra["hint"]
    assert plan("potential", gm, s, g, {"model": "khatib", "q_star": d["suggest"]["q_star"]}).reached
    assert plan("potential", gm, s, g, {"model": "khatib", "escape": "navigation"}).reached


def test_unreachable_goal_is_no_path_at_once():
    occ = np.zeros((10, 10), bool)
    occ[:, 5] = True
    gm = GridMap(Grid((10, 10), 1.0, border="wall"), occ)
    p = plan("potential", gm, (1.5, 1.5), (8.5, 8.5))
    assert p.status == "no_path" and p.iterations == 0 and len(p.points) == 1
    assert "cannot be reached" in p.extra["hint"]
    # around an open border the same goal is reachable
    gm_open = GridMap(Grid((10, 10), 1.0, border="open"), occ)
    assert plan("potential", gm_open, (1.5, 1.5), (8.5, 8.5), {"escape": "navigation"}).reached


# ------------------------------------------------------------------------------------------------
# the command line
# ------------------------------------------------------------------------------------------------
def test_plan_help_lists_every_parameter(capsys):
    assert main(["plan", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    for name, spec in REGISTRY.items():
        if spec.flag:
            assert f"--{name.replace('_', '-')}" in text, name
        else:
            assert f"{name}:" in text, name
        assert "".join(spec.meaning.split()) in "".join(text.split()), name  # (argparse wraps at hyphens too)
    assert "default: 4 cells" in text


@pytest.mark.parametrize("argv", [
    ["--planner", "fmm", "--param", "step=abc"],
    ["--planner", "wavefront", "--step", "abc"],
    ["--planner", "potential", "--escape", "teleport"],
])
def test_bad_parameter_values_are_one_line_exit_2(argv, capsys):
    code = main(["plan", str(REPO / "maps" / "arena" / "arena.map"), "--start", "1.5", "41.5",
                 "--goal", "47.5", "2.5", *argv])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "error:" in err


def test_sphere_nav_bad_kappa_and_workspace(capsys, tmp_path):
    world = tmp_path / "disc.yaml"
    world.write_text("bounds: [0, 0, 10, 10]\nobstacles:\n  - circle: {center: [5, 5], radius: 1}\n"
                     "start: [2, 5.5]\ngoal: [8, 4.5]\n")
    assert main(["plan", str(world), "--planner", "sphere-nav", "--param", "kappa=abc"]) == 2
    assert "kappa" in capsys.readouterr().err
    code = main(["plan", str(world), "--planner", "sphere-nav", "--param", "workspace_center=5,5",
                 "--param", "workspace_radius=4.9", "--json"])
    assert code == 0
    assert json.loads(capsys.readouterr().out)["planner"] == "sphere-nav"


def test_plan_scenario_json_has_optimal_and_times(capsys):
    m = REPO / "maps" / "arena"
    code = main(["plan", str(m / "arena.map"), "--scenario", str(m / "arena.map.scen"), "--index", "159",
                 "--escape", "navigation", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["status"] == "reached" and out["optimal"] == pytest.approx(62.1543)
    line = (m / "arena.map.scen").read_text().splitlines()[1 + 159].split("\t")
    sx, sy, height = int(line[4]), int(line[5]), int(line[3])
    assert out["path"][0] == [sx + 0.5, height - 1 - sy + 0.5]  # the file's y grows downward
    assert out["seconds"] >= out["field_seconds"] + out["follow_seconds"] - 1e-9
    assert out["hint"] is None and out["params"]["escape"] == "navigation"
    assert out["params"]["q_star"] == 4.0  # the resolved values are reported


def test_plan_text_prints_the_hint(capsys):
    m = REPO / "maps" / "arena"
    assert main(["plan", str(m / "arena.map"), "--scenario", str(m / "arena.map.scen"), "--index", "159",
                 "--param", "model=khatib"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("potential: local_minimum") and "(octile optimum 62.15)" in lines[0]
    assert lines[1].startswith("hint: ") and "--escape navigation" in lines[1]


def test_scenario_errors(capsys):
    m = REPO / "maps" / "arena"
    assert main(["plan", str(m / "arena.map"), "--scenario", str(m / "arena.map.scen"), "--index", "999"]) == 2
    assert "out of range" in capsys.readouterr().err
    assert main(["plan", str(REPO / "maps" / "seed000.yaml"), "--scenario", str(m / "arena.map.scen")]) == 2
    assert "error:" in capsys.readouterr().err


def test_sum_repulsion_without_labels_is_a_clear_error():
    from gridfield.distance.brushfire import brushfire
    from gridfield.fields.potential import repulsive

    occ = np.zeros((8, 8), bool)
    occ[3:5, 3:5] = True
    d = brushfire(GridMap(Grid((8, 8), 1.0), occ), compute_labels=False, compute_gvd=False)
    with pytest.raises(ParameterError, match="needs obstacle labels"):
        repulsive(d, mode="sum")
    labelled = brushfire(GridMap(Grid((8, 8), 1.0), occ))
    U, _, _ = repulsive(labelled, mode="sum", eta=1.0, q_star=3.0)
    assert np.isfinite(U[~occ]).all() and U[2, 2] > 0 and U[0, 0] == 0  # sqrt 2 and sqrt 18 from it


def test_a_reached_run_ends_at_the_goal_even_when_the_last_hop_is_blocked():
    """Arena, q_star 1: the run from (1.5, 45.5) gets within the tolerance of (3.5, 47.5) where the
    straight hop to the goal crosses a corner-only gap. It used to report ``reached`` with the path
    stopping 0.84 short, so its length (2.0) was below the straight line (2.83). It must end at the
    goal along free moves, follow and follow_many alike, and no reached path may be shorter than the
    straight line on any arena scenario."""
    from shapely.geometry import LineString, box

    from gridfield.following.follower import follow_many
    from gridfield.io import bundled_map

    gm = read_movingai_map(bundled_map("arena/arena.map"))
    start, goal = (1.5, 45.5), (3.5, 47.5)
    path, field = plan_with_field("potential", gm, start, goal, {"model": "khatib", "q_star": 1.0})
    many = follow_many(field, [start])[0]
    rows, cols = np.nonzero(gm.occupied)
    obstacles = shapely.union_all([box(c, r, c + 1, r + 1) for r, c in zip(rows, cols, strict=True)])
    for p in (path, many):
        assert p.status == "reached" and p.extra["goal_appended"]
        assert tuple(p.points[-1]) == goal
        assert p.length >= math.dist(start, goal) - 1e-9
        assert not LineString(p.points).relate_pattern(obstacles, "T********")  # never inside an obstacle
    scen = read_scen(bundled_map("arena/arena.map.scen"), map_height=gm.grid.rows)
    for k in range(0, len(scen), 7):
        s, g = tuple(scen.start_xy[k]), tuple(scen.goal_xy[k])
        p = plan("potential", gm, s, g, {"model": "khatib", "q_star": 1.0})
        if p.status == "reached":
            assert tuple(p.points[-1]) == g and p.length >= math.dist(s, g) - 1e-9


# the navigation escape's hand-back (the first cell of the goal's basin): tests/test_escapes.py
