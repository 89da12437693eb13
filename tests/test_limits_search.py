"""The searches that grow with a map's detail (the any-angle corner graph, a grid map's exact polygons,
a vector visibility graph, the exact potential) estimate their time before they start and refuse
above GRIDFIELD_MAX_SECONDS, in well under a second; where they run, their results are unchanged."""

from __future__ import annotations

import time

import numpy as np
import pytest

import gridfield.core.limits as limits
from gridfield.cli import main
from gridfield.core.errors import ParameterError, SizeLimitError
from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.world import world_from_dict
from gridfield.io import bundled_map, read_world, write_npz
from gridfield.planners import plan


def _noise(n: int, p: float, seed: int = 0) -> GridMap:
    occ = np.random.default_rng(seed).random((n, n)) < p
    occ[0, 0] = occ[-1, -1] = False
    return GridMap(Grid((n, n), 1.0), occ, source=f"noise {n}x{n}")


def _refused_fast(call) -> str:
    t0 = time.perf_counter()
    with pytest.raises(SizeLimitError) as e:
        call()
    assert time.perf_counter() - t0 < 5  # generous (shared machine): nothing was built
    msg = str(e.value)
    assert "would take about" in msg and limits.SECONDS_ENV_VAR in msg
    return msg


def test_the_any_angle_graph_is_refused_by_its_corner_count(monkeypatch) -> None:
    """The visibility graph (the ``graph`` search) grows with the corners: refused up front under a limit
    just below its estimate, the graph kernel never run. The default search (Polyanya, a navigation mesh
    linear in the cells) is not: under the same limit it answers."""
    import gridfield.exact.anyangle as anyangle

    gm = _noise(96, 0.3)
    corners = anyangle.convex_corners(anyangle._padded_blocked(gm))[0].size
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, str(0.9 * corners * limits.SECONDS_PER["convex corner"]))
    graph = anyangle.grid_graph(gm, cache={})  # the corners only: not refused
    assert anyangle.SEARCH == "polyanya"
    p = plan("visibility", gm, (0.5, 0.5), (95.5, 95.5), cache={})
    assert p.status in ("reached", "no_path") and "edges" not in p.extra

    def no_graph(*a, **k):
        raise AssertionError("the graph kernel ran before the refusal")

    monkeypatch.setattr(anyangle._kernel_occlusion(), "visibility_edges_culled", no_graph, raising=False)
    msg = _refused_fast(lambda: graph.edges)
    assert f"{corners} convex corners" in msg and "any-angle graph of noise 96x96" in msg
    msg = _refused_fast(lambda: graph.shortest_path((0.5, 0.5), (95.5, 95.5), search="graph"))
    assert "any-angle graph of noise 96x96" in msg


def test_a_grid_maps_exact_polygons_are_refused_by_their_run_count(monkeypatch) -> None:
    from gridfield.geometry.gridpoly import blocked_runs, grid_world

    gm = _noise(64, 0.3, seed=1)
    runs = blocked_runs(gm.occupied)[0].size
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, str(0.9 * runs * limits.SECONDS_PER["blocked run"]))
    msg = _refused_fast(lambda: grid_world(gm))
    assert f"{runs} blocked runs" in msg and "exact polygons of noise 64x64" in msg


def test_a_vector_visibility_graph_is_refused_by_its_vertex_pairs(monkeypatch) -> None:
    rng = np.random.default_rng(2)
    obstacles = [{"circle": {"center": [float(x), float(y)], "radius": 0.2}} for x, y in rng.uniform(1, 19, (8, 2))]
    w = world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": obstacles})
    n = sum(len(ob.vertices) for ob in w.obstacles)
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, str(0.9 * n * n * limits.SECONDS_PER["vertex pair"]))
    msg = _refused_fast(lambda: plan("visibility", w, (0.1, 0.1), (19.9, 19.9)))
    assert f"{n * n} vertex pairs" in msg


def test_the_exact_potential_is_refused_by_its_geometry_and_steps(monkeypatch, capsys) -> None:
    w = read_world(bundled_map("seed000.yaml"))
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, "0.01")
    msg = _refused_fast(lambda: plan("exact-potential", w, w.start, w.goal, {"max_iterations": 10**6}))
    assert "1000000 follower steps" in msg and "exact potential of" in msg
    assert main(["plan", str(bundled_map("seed000.yaml")), "--planner", "exact-potential",
                 "--max-iterations", "1000000"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "would take about" in err


def test_where_they_run_the_results_are_unchanged(monkeypatch) -> None:
    """The estimate only reads the map: the same plans with no limit and with the default one."""
    gm = _noise(48, 0.2, seed=3)
    w = read_world(bundled_map("seed000.yaml"))
    runs = [("visibility", gm, (0.5, 0.5), (47.5, 47.5)), ("visibility", w, w.start, w.goal),
            ("exact-potential", w, w.start, w.goal)]
    default = [plan(p, t, s, g).points for p, t, s, g in runs]
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, "inf")
    from gridfield.exact import anyangle, visibility

    anyangle._GRAPHS.clear()
    visibility._CACHE.clear()
    for (p, t, s, g), before in zip(runs, default, strict=True):
        assert np.array_equal(plan(p, t, s, g).points, before)


@pytest.mark.parametrize("value", ["", "0", "-1", "soon"])
def test_a_malformed_time_limit_is_refused(value: str, monkeypatch) -> None:
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, value)
    with pytest.raises(ParameterError, match=f"{limits.SECONDS_ENV_VAR} must be a positive number of seconds"):
        limits.max_seconds()


def test_the_cli_refuses_a_long_compare_in_one_line(tmp_path, monkeypatch, capsys) -> None:
    gm = _noise(64, 0.3, seed=4)
    path = tmp_path / "noise.npz"
    write_npz(path, {"occupied": gm.occupied}, gm.grid)
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, "0.05")
    assert main(["compare", str(path), "--start", "0.5", "0.5", "--goal", "63.5", "63.5"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "would take about" in err and "Traceback" not in err
