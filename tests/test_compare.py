"""Grid-vs-exact comparison: metrics on hand-made paths, distance-map errors against the analytic
distance of a circle, the convergence study (fakes and the real seed 000 worlds), batch, CLI."""

from __future__ import annotations

import itertools
import json
import math
import sys
import types

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gridfield.cli import main
from gridfield.compare import (
    STUDY_COLUMNS,
    batch_compare,
    collides,
    convergence_study,
    discrete_frechet,
    distance_map_errors,
    end_error,
    final_point,
    hausdorff,
    length_ratio,
    min_clearance,
    observed_order,
    resample,
    status_agreement,
    study_errors,
    study_orders,
)
from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.path import Path
from gridfield.distance.brushfire import brushfire
from gridfield.geometry.rasterize import rasterize
from gridfield.geometry.world import world_from_dict
from gridfield.io import bundled_map, read_world
from gridfield.planners import PLANNERS, Planner

SQRT2 = math.sqrt(2.0)


# ----------------------------------------------------------------------------------------
# slow references
# ----------------------------------------------------------------------------------------
def frechet_reference(p, q):
    """Textbook O(N*M) table of the discrete Fréchet distance (Eiter & Mannila)."""
    n, m = len(p), len(q)
    d = np.hypot(*(p[:, None, :] - q[None, :, :]).transpose(2, 0, 1))
    ca = np.full((n, m), np.inf)
    for i, j in itertools.product(range(n), range(m)):
        if i == 0 and j == 0:
            ca[i, j] = d[0, 0]
        else:
            prev = min(ca[i - 1, j] if i else np.inf, ca[i, j - 1] if j else np.inf,
                       ca[i - 1, j - 1] if i and j else np.inf)
            ca[i, j] = max(d[i, j], prev)
    return ca[-1, -1]


def hausdorff_reference(p, q):
    d = np.hypot(*(p[:, None, :] - q[None, :, :]).transpose(2, 0, 1))
    return max(d.min(axis=1).max(), d.min(axis=0).max())


# ----------------------------------------------------------------------------------------
# curve metrics
# ----------------------------------------------------------------------------------------
def test_parallel_segments_at_distance_one():
    a, b = [[0, 0], [1, 0]], [[0, 1], [1, 1]]
    assert hausdorff(a, b) == 1.0 and discrete_frechet(a, b) == 1.0
    assert hausdorff(a, b, spacing=0.1) == pytest.approx(1.0)
    assert discrete_frechet(a, b, spacing=0.1) == pytest.approx(1.0)


def test_backtracking_path_frechet_exceeds_hausdorff():
    back = np.array([[0, 0], [2, 0], [1, 0], [3, 0]], float)  # goes to 2, back to 1, on to 3
    straight = np.array([[0, 0], [3, 0]], float)
    assert hausdorff(back, straight, spacing=0.01) == pytest.approx(0.0, abs=1e-12)
    assert discrete_frechet(back, straight, spacing=0.01) == pytest.approx(0.5, abs=0.005)
    # the same curve walked backwards is as far as its two ends are apart
    assert discrete_frechet(straight, straight[::-1]) == 3.0
    assert hausdorff(straight, straight[::-1]) == 0.0


def test_frechet_and_hausdorff_match_brute_force():
    rng = np.random.default_rng(1)
    for _ in range(40):
        p = rng.normal(size=(rng.integers(1, 12), 2))
        q = rng.normal(size=(rng.integers(1, 15), 2))
        f = discrete_frechet(p, q)
        assert f == pytest.approx(frechet_reference(p, q), rel=1e-12)
        assert f == pytest.approx(discrete_frechet(q, p), rel=1e-12)  # symmetric
        h = hausdorff(p, q)
        assert h == pytest.approx(hausdorff_reference(p, q), rel=1e-12)
        assert f >= h - 1e-12  # a coupling covers every point


def test_resample_keeps_vertices_and_bounds_gaps():
    p = np.array([[0, 0], [1, 0], [1, 0], [1, 2.5]], float)
    r = resample(p, 0.3)
    assert np.allclose(r[0], p[0]) and np.allclose(r[-1], p[-1])
    for v in p:
        assert np.min(np.hypot(*(r - v).T)) == 0.0
    gaps = np.hypot(*np.diff(r, axis=0).T)
    assert gaps.max() <= 0.3 + 1e-12
    with pytest.raises(ParameterError, match="spacing must be a positive"):
        resample(p, 0)


def test_length_ratio_end_error_status():
    p = Path(np.array([[0, 0], [3, 4]], float), "reached", "a")
    assert length_ratio(p, 5.0) == 1.0 and length_ratio(p, [[0, 0], [0, 10]]) == 0.5
    assert math.isnan(length_ratio(p, 0.0)) and math.isnan(length_ratio(p, math.inf))
    stuck_a = Path(np.array([[0, 0], [1, 0], [1.1, 0]]), "local_minimum", "a", extra={"stall_point": [1.0, 0.0]})
    stuck_b = Path(np.array([[0, 0], [1, 0.3], [1.0, 0.4]]), "local_minimum", "b", extra={"stall_point": [1.0, 0.4]})
    assert final_point(stuck_a).tolist() == [1.0, 0.0]
    assert end_error(stuck_a, stuck_b) == pytest.approx(0.4)
    assert end_error([[0, 0], [1, 1]], [[5, 5], [1, 2]]) == 1.0
    assert status_agreement(stuck_a, stuck_b) and not status_agreement(p, stuck_a)
    with pytest.raises(ParameterError, match=r"a must be points of shape \(N, 2\)"):
        hausdorff(np.zeros((3, 3)), [[0, 0]])
    with pytest.raises(ParameterError, match="b has no points"):
        discrete_frechet([[0, 0]], np.zeros((0, 2)))


# ----------------------------------------------------------------------------------------
# paths against the world
# ----------------------------------------------------------------------------------------
@pytest.fixture
def box_world():
    return world_from_dict({"bounds": [0, 0, 10, 10], "border": "wall",
                            "obstacles": [{"rectangle": [4, 4, 6, 6]}, {"segment": [[8, 1], [8, 3]]},
                                          {"circle": {"center": [2, 8], "radius": 1}}]})


def test_min_clearance_is_exact_along_segments(box_world):
    # the vertices are 2 away from the square, the segment between them passes 0.5 below it
    assert min_clearance(box_world, [[3, 2], [5, 3.5], [7, 2]]) == pytest.approx(0.5)
    assert min_clearance(box_world, [[0.5, 5], [3, 5]]) == pytest.approx(0.5)  # the wall at x = 0
    assert min_clearance(box_world, [[3, 4], [5, 4]]) == 0.0  # along the square's edge
    assert min_clearance(box_world, [[2, 6.5], [5, 6.5]]) == pytest.approx(0.5)  # below the circle


def test_collides_tells_touching_from_entering(box_world):
    assert not collides(box_world, [[3, 4], [5, 4], [6, 4]])  # along an edge
    assert not collides(box_world, [[3, 3], [4, 4], [3, 5]])  # bouncing off a corner
    assert collides(box_world, [[3, 5], [7, 5]])  # through the square
    assert collides(box_world, [[7, 2], [9, 2]])  # across the segment
    assert collides(box_world, [[7, 2], [8, 2], [9, 2.5]])  # across it through a path vertex
    assert not collides(box_world, [[7, 2], [8, 2], [7, 2.5]])  # touching it and turning back
    assert not collides(box_world, [[7, 3], [9, 3]])  # round its end point
    assert not collides(box_world, [[1, 7], [3, 7]])  # tangent to the circle
    assert collides(box_world, [[1, 7.5], [3, 7.5]])  # through the circle
    assert collides(box_world, [[9, 9], [11, 9]])  # through the wall border


# ----------------------------------------------------------------------------------------
# distance maps against the analytic distance of one circle
# ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("h", [0.5, 0.25])
def test_distance_map_errors_single_circle(h):
    c, r = np.array([5.3, 4.9]), 1.7
    world = world_from_dict({"bounds": [0, 0, 12, 10], "obstacles": [{"circle": {"center": c.tolist(), "radius": r}}]})
    res = distance_map_errors(world, h)
    assert set(res) == {"chessboard", "taxicab", "euclidean"}
    # independent recomputation against the analytic distance |x - c| - r
    gm = rasterize(world, h)
    xs, ys = gm.grid.cell_centers()
    X, Y = np.meshgrid(xs, ys)
    free = ~gm.occupied
    exact = np.hypot(X[free] - c[0], Y[free] - c[1]) - r
    half_diag = h / SQRT2  # an occupied cell's centre lies within this of the circle
    for metric, stats in res.items():
        d = brushfire(gm, connectivity=4 if metric == "taxicab" else 8, metric=metric).distance[free]
        err = d - exact
        assert stats["max"] == pytest.approx(np.abs(err).max()) and stats["mean"] == pytest.approx(np.abs(err).mean())
        assert stats["bias"] == pytest.approx(err.mean()) and stats["cells"] == free.sum()
        assert sum(b["cells"] for b in stats["bands"]) == stats["cells"]
        # bounds from the metric's distortion of Euclidean length
        if metric == "euclidean":
            lo, hi = -half_diag, half_diag
        elif metric == "chessboard":
            lo, hi = (exact - half_diag) / SQRT2 - exact, half_diag
        else:
            lo, hi = -half_diag, SQRT2 * (exact + half_diag) - exact
        assert np.all(err >= lo - 1e-9) and np.all(err <= hi + 1e-9), metric
        for b in stats["bands"]:
            if b["cells"]:
                assert b["mean"] <= b["max"] + 1e-15
    assert res["euclidean"]["max"] <= half_diag
    far = [b for b in res["chessboard"]["bands"] if b["lo"] >= 8 * h and b["cells"]]
    assert far and all(b["bias"] < 0 for b in far)  # chessboard underestimates far away
    assert all(b["bias"] > 0 for b in res["taxicab"]["bands"] if b["lo"] >= 8 * h and b["cells"])


def test_distance_map_errors_bad_input():
    w = world_from_dict({"bounds": [0, 0, 4, 4], "obstacles": [{"rectangle": [1, 1, 2, 2]}]})
    with pytest.raises(ParameterError, match="metric must be one of"):
        distance_map_errors(w, 0.5, metrics=["manhattan"])
    with pytest.raises(ParameterError, match="bands must be increasing"):
        distance_map_errors(w, 0.5, bands=[1.0, 0.5])
    out = distance_map_errors(w, 0.5, metrics=["euclidean"], bands=[0, 1, math.inf])
    assert [b["hi"] for b in out["euclidean"]["bands"]] == [1.0, math.inf]


# ----------------------------------------------------------------------------------------
# observed order and the convergence study
# ----------------------------------------------------------------------------------------
def test_observed_order():
    h = np.array([0.4, 0.2, 0.1, 0.05])
    assert observed_order(h, 3 * h**1.5) == pytest.approx(1.5)
    noisy = 2 * h * np.array([1.1, 0.9, 1.05, 0.97])
    assert observed_order(h, noisy) == pytest.approx(1.0, abs=0.1)
    assert observed_order(h, [0.1, 0, np.nan, 0.01]) == pytest.approx(math.log(10) / math.log(8))
    assert math.isnan(observed_order([0.1], [0.1]))
    with pytest.raises(ParameterError, match="differ in length"):
        observed_order([0.1, 0.2], [1.0])


def _importing_fakes(monkeypatch, prefix: str) -> None:
    """Let the planner table load this test's throwaway modules (``prefix...``): gridfield imports its own
    planner modules by explicit statements only (``planners._module``), so a test module is imported here."""
    import importlib

    from gridfield import planners

    real = planners._module
    monkeypatch.setattr(planners, "_module", lambda name: importlib.import_module(name) if name.startswith(prefix)
                        else real(name))


@pytest.fixture
def fake_grid_planner(monkeypatch):
    """A 'grid planner' whose path bulges h away from the straight line: Hausdorff = h."""
    module = types.ModuleType("fake_compare_planners")

    def plan_bulge(gridmap, start, goal, params, *, cache=None):  # every planner takes cache=None
        h = gridmap.grid.resolution
        mid = (start + goal) / 2 + np.array([0.0, h])
        return Path(np.array([start, mid, goal]), "reached", "bulge", seconds=1e-3, extra={"build_seconds": 2e-3})

    module.plan_bulge = plan_bulge
    monkeypatch.setitem(sys.modules, "fake_compare_planners", module)
    monkeypatch.setitem(PLANNERS, "bulge", Planner("fake_compare_planners", "plan_bulge", "grid"))
    _importing_fakes(monkeypatch, "fake_compare_")
    return "bulge"


def test_convergence_study_with_a_fake_grid_planner(fake_grid_planner):
    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [8, 8, 9, 9]}]})
    hs = [0.4, 0.2, 0.1]
    rows = convergence_study(w, [1, 1], [7, 1], hs, grid_planner=fake_grid_planner, exact_planner="visibility")
    assert [r["resolution"] for r in rows] == hs
    for r, h in zip(rows, hs, strict=True):
        assert list(r) == list(STUDY_COLUMNS)
        assert r["cells"] == round(10 / h) ** 2
        assert r["hausdorff"] == pytest.approx(h) and r["frechet"] == pytest.approx(h, abs=h / 8)
        assert r["length_ratio"] == pytest.approx(math.hypot(3, h) / 3)
        assert r["length_ratio_optimal"] == r["length_ratio"]  # the exact planner is the optimum here
        assert r["end_error"] == 0.0 and r["status_agree"] and not r["collides"]
        assert r["plan_ms"] == pytest.approx(1.0) and r["build_ms"] >= 2.0
        assert r["min_clearance"] == pytest.approx(math.hypot(1, 7))  # (7, 1) to the corner (8, 8)
    orders = study_orders(rows)
    assert orders["hausdorff"] == pytest.approx(1.0) and orders["length_error"] == pytest.approx(2.0, abs=0.05)
    assert math.isnan(orders["end_error"])


def test_convergence_study_plumbing_visibility_both_sides():
    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})
    rows = convergence_study(w, [1, 5], [9, 5], [1.0, 0.5], grid_planner="visibility", exact_planner="visibility")
    assert all(r["hausdorff"] == 0 and r["length_ratio"] == 1 and r["min_clearance"] == 0 for r in rows)


def test_convergence_study_bad_input():
    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})
    with pytest.raises(ParameterError, match="exact_planner must work on vector worlds"):
        convergence_study(w, [1, 5], [9, 5], [0.5], exact_planner="potential")
    with pytest.raises(ParameterError, match="resolution must be a positive"):
        convergence_study(w, [1, 5], [9, 5], [0.5, -1])
    with pytest.raises(ParameterError, match="at least one resolution"):
        convergence_study(w, [1, 5], [9, 5], [])
    with pytest.raises(GridfieldError, match=r"start \(5, 5\) lies inside obstacle 1"):
        convergence_study(w, [5, 5], [9, 5], [0.5])


def test_seed000_errors_shrink_with_the_resolution():
    w = read_world(bundled_map("seed000.yaml"))
    hs = [0.4, 0.2, 0.1, 0.05]
    rows = convergence_study(w, w.start, w.goal, hs)
    assert all(r["status"] == r["exact_status"] == "reached" for r in rows)
    errs = study_errors(rows)
    for name in ("hausdorff", "frechet", "length_error"):
        assert np.all(np.diff(errs[name]) < 0), (name, errs[name])
    orders = study_orders(rows)
    assert orders["hausdorff"] == pytest.approx(1.0, abs=0.3)
    assert rows[-1]["hausdorff"] < 0.1
    assert all(r["min_clearance"] > 0 and not r["collides"] for r in rows)
    assert all(r["length_ratio_optimal"] >= 1.0 for r in rows)  # nothing beats the visibility optimum


def test_seed000_segment_stall_point_converges():
    w = read_world(bundled_map("seed000_segment.yaml"))
    hs = [0.4, 0.2, 0.1, 0.05]
    rows = convergence_study(w, w.start, w.goal, hs)
    assert all(r["status"] == r["exact_status"] == "local_minimum" for r in rows)
    errs = study_errors(rows)
    assert np.all(np.diff(errs["end_error"]) < 0) and np.all(np.diff(errs["hausdorff"]) < 0)
    assert all(math.isnan(v) for v in errs["length_error"])  # stalled: lengths are not compared
    orders = study_orders(rows)
    assert orders["end_error"] > 0.5 and orders["hausdorff"] > 0.5


# ----------------------------------------------------------------------------------------
# batch comparison
# ----------------------------------------------------------------------------------------
def test_batch_compare_on_seed000(monkeypatch):
    w = read_world(bundled_map("seed000.yaml"))
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)  # the tqdm bar runs
    out = batch_compare(w, 4, resolution=0.2, seed=3,
                        planners=("potential", "exact-potential", "wavefront-octile", "visibility"))
    assert out["pairs"] == 4 and len(out["rows"]) == 4 and out["skipped"] == {}
    s = out["planners"]
    assert s["visibility"]["success_rate"] == 1.0 and s["visibility"]["length_ratio"]["max"] == pytest.approx(1.0)
    # a complete planner on a conservative grid: always there, never shorter than the optimum
    assert s["wavefront-octile"]["success_rate"] == 1.0
    assert s["wavefront-octile"]["length_ratio"]["mean"] >= 1.0
    tol = w.params["tolerance"]
    for row in out["rows"]:
        assert w.distance([row["start"], row["goal"]]).min() > 0.2
        for name in ("potential", "exact-potential"):
            r = row[name]
            if r["status"] == "reached":  # may stop up to `tolerance` short of the goal
                assert r["length"] >= row["optimal_length"] - tol - 1e-9
    for name in ("potential", "exact-potential"):
        assert 0.0 <= s[name]["success_rate"] <= 1.0
        assert sum(s[name]["statuses"].values()) == 4
    assert 0.0 <= s["potential"]["agreement_with_exact"] <= 1.0
    again = batch_compare(w, 4, resolution=0.2, seed=3, planners=("visibility",), progress=False)
    assert [r["start"] for r in again["rows"]] == [r["start"] for r in out["rows"]]  # same seed, same pairs


def _fake_planner_module(tmp_path, monkeypatch, name, first_line):
    """A PLANNERS entry ``name`` whose module (written to tmp_path) starts with ``first_line``."""
    module = f"fake_compare_{name}"
    (tmp_path / f"{module}.py").write_text(f"{first_line}\n\ndef plan(gridmap, start, goal, params, *, cache=None):\n    pass\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, module, raising=False)
    monkeypatch.setitem(PLANNERS, name, Planner(module, "plan", "grid"))
    _importing_fakes(monkeypatch, "fake_compare_")


def test_batch_compare_reports_missing_planners_and_bad_input(tmp_path, monkeypatch):
    # a planner whose optional third-party dependency is not installed is skipped, saying so
    _fake_planner_module(tmp_path, monkeypatch, "missing", "import no_such_optional_dependency")
    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})
    out = batch_compare(w, 2, resolution=0.5, planners=("visibility", "missing"), progress=False)
    assert list(out["skipped"]) == ["missing"] and list(out["planners"]) == ["visibility"]
    assert "not available in this installation" in out["skipped"]["missing"]
    assert "no_such_optional_dependency" in out["skipped"]["missing"]
    with pytest.raises(ParameterError, match="n_pairs must be a positive integer"):
        batch_compare(w, 0, resolution=0.5)
    walled = world_from_dict({"bounds": [0, 0, 1, 1], "border": "wall", "obstacles": [{"rectangle": [0, 0, 1, 0.9]}]})
    with pytest.raises(GridfieldError, match="connected free start/goal pairs"):
        batch_compare(walled, 2, resolution=0.5, planners=("visibility",), progress=False)


def test_batch_compare_does_not_skip_a_broken_gridfield_planner(tmp_path, monkeypatch):
    """A gridfield import that fails, or a registry entry naming no function, is a bug: it is raised,
    never reported as a skipped planner."""
    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})
    _fake_planner_module(tmp_path, monkeypatch, "broken", "from gridfield.core.path import NoSuchName")
    with pytest.raises(ImportError, match="NoSuchName"):
        batch_compare(w, 2, resolution=0.5, planners=("visibility", "broken"), progress=False)
    monkeypatch.setitem(PLANNERS, "typo", Planner("gridfield.following.follower", "plan_potentail", "grid"))
    with pytest.raises(AttributeError, match=r"PLANNERS\['typo'\]"):
        batch_compare(w, 2, resolution=0.5, planners=("visibility", "typo"), progress=False)


# ----------------------------------------------------------------------------------------
# command line
# ----------------------------------------------------------------------------------------
def test_cli_compare_json(capsys):
    rc = main(["compare", str(bundled_map("seed000.yaml")), "--resolutions", "0.4", "0.2", "--json"])
    out, err = capsys.readouterr()
    assert rc == 0, err
    lines = out.strip().splitlines()
    assert len(lines) == 1
    data = json.loads(lines[0])
    assert set(data) >= {"world", "rows", "order"}
    assert [r["resolution"] for r in data["rows"]] == [0.4, 0.2]
    assert set(data["rows"][0]) == set(STUDY_COLUMNS)
    assert data["start"] == [1.0, 10.0] and data["goal"] == [22.0, 12.0]  # from the world file
    assert data["order"]["hausdorff"] > 0 and data["order"]["end_error"] is None  # both reached: no end error


def test_cli_compare_table_and_plot(capsys, tmp_path):
    fig = tmp_path / "conv.png"
    rc = main(["compare", str(bundled_map("seed000_segment.yaml")), "--start", "1", "10", "--goal", "22", "12",
               "--resolutions", "0.4", "0.2", "--planner", "potential", "--plot", str(fig)])
    out, err = capsys.readouterr()
    assert rc == 0, err
    assert "Hausdorff" in out and "local_minimum" in out and "observed order" in out
    assert fig.stat().st_size > 0


def test_cli_compare_batch(capsys):
    rc = main(["compare", str(bundled_map("seed000.yaml")), "--batch", "2", "--resolution", "0.4", "--json",
               "--no-progress"])
    out, err = capsys.readouterr()
    assert rc == 0, err
    data = json.loads(out)
    assert data["pairs"] == 2 and "potential" in data["planners"]


def test_cli_compare_errors(capsys):
    rc = main(["compare", str(bundled_map("turtlebot3_world/map.yaml"))])  # a grid map: fine, but no start
    assert rc == 2 and "names no start; pass --start X Y" in capsys.readouterr().err
    rc = main(["compare", str(bundled_map("seed000.yaml")), "--start", "8", "14"])
    assert rc == 2 and "start (8, 14) lies inside obstacle 1" in capsys.readouterr().err
    rc = main(["compare", str(bundled_map("seed000.yaml")), "--batch", "2", "--plot", "x.png"])
    assert rc == 2 and "--plot draws the convergence study" in capsys.readouterr().err
    rc = main(["compare", str(bundled_map("seed000.yaml")), "--resolutions", "0"])
    assert rc == 2 and "resolution must be a positive" in capsys.readouterr().err


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(1, 6), m=st.integers(1, 6))
def test_max_deviation_against_brute_force_point_segment_distances(seed, n, m):
    """max_deviation is the largest distance of the path's points to the reference polyline,
    checked against point-to-segment distances written out in numpy."""
    from gridfield.compare import max_deviation

    rng = np.random.default_rng(seed)
    p, q = rng.uniform(-5, 5, (n, 2)), rng.uniform(-5, 5, (m, 2))
    if m == 1:
        want = np.hypot(*(p - q[0]).T).max()
    else:
        a, b = q[:-1], q[1:]
        ab = b - a
        t = np.clip(((p[:, None, :] - a) * ab).sum(-1) / (ab * ab).sum(-1), 0.0, 1.0)
        closest = a + t[..., None] * ab
        want = np.hypot(*(p[:, None, :] - closest).transpose(2, 0, 1)).min(axis=1).max()
    assert max_deviation(p, q) == pytest.approx(want, abs=1e-12)
    with pytest.raises(ParameterError, match="path has no points"):
        max_deviation(np.empty((0, 2)), q)
