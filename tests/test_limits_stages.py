"""Issue 29's last bounds: commands of several searches refuse up front on the sum of their estimates,
the long searches show their progress on stderr (when asked or on a terminal), and the API sizes its
grids in bytes before allocating them."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import gridfield.core._time_guard as time_guard
import gridfield.core.limits as limits
import gridfield.exact.anyangle as anyangle
import gridfield.geometry.gridpoly as gridpoly
from gridfield.cli import main
from gridfield.core.errors import SizeLimitError
from gridfield.core.grid import Grid, GridMap
from gridfield.distance.brushfire import brushfire
from gridfield.fields.potential import build_field
from gridfield.io import write_npz
from gridfield.planners import plan


def _noise(n: int, p: float, seed: int = 0) -> GridMap:
    occ = np.random.default_rng(seed).random((n, n)) < p
    occ[0, 0] = occ[-1, -1] = False
    return GridMap(Grid((n, n), 1.0), occ, source=f"noise {n}x{n}")


def _npz(tmp_path, gm: GridMap) -> str:
    path = tmp_path / "noise.npz"
    write_npz(path, {"occupied": gm.occupied}, gm.grid)
    return str(path)


def _no_polygons(monkeypatch) -> None:
    def refuse(*a, **k):
        raise AssertionError("the polygons were built before the refusal")

    monkeypatch.setattr(gridpoly, "grid_world", refuse)


# -- the counts the estimates use, against the structures they predict ------------------------------


@settings(max_examples=30, deadline=None)
@given(arrays(np.bool_, st.tuples(st.integers(1, 9), st.integers(1, 9))))
def test_grid_map_work_counts_what_the_searches_build(occ) -> None:
    gm = GridMap(Grid(occ.shape, 1.0), occ.copy())
    work = limits.grid_map_work(occ)
    assert work["blocked run"] == gridpoly.blocked_runs(occ)[0].size
    assert work["convex corner"] == anyangle.convex_corners(anyangle._padded_blocked(gm))[0].size
    polygons = gridpoly._polygons(gm)  # the exact polygons (shapely union), their exterior and hole vertices
    vertices = sum(len(p.exterior.coords) - 1 + sum(len(r.coords) - 1 for r in p.interiors) for p in polygons)
    assert work["obstacle vertex"] == vertices


def test_the_union_estimate_grows_faster_than_the_runs() -> None:
    one, four = (limits.estimate_seconds({"blocked run": n}) for n in (10_000, 40_000))
    assert four / one == pytest.approx(4**1.35)


# -- summed estimates, refused up front -------------------------------------------------------------


def _between(stages) -> float:
    """A limit above every stage's estimate but below their sum."""
    parts = [limits.estimate_seconds(w) for _, w in stages]
    assert len(parts) >= 2 and max(parts) < sum(parts)
    return (max(parts) + sum(parts)) / 2


def test_plan_exact_potential_on_a_grid_map_is_refused_on_its_summed_stages(tmp_path, monkeypatch, capsys) -> None:
    gm = _noise(48, 0.2, seed=1)
    from gridfield.planners import search_stages

    stages = search_stages("exact-potential", gm)
    assert [name for name, _ in stages] == ["exact polygons", "exact potential"]
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, repr(_between(stages)))
    _no_polygons(monkeypatch)
    t0 = time.perf_counter()
    with pytest.raises(SizeLimitError, match=r"exact polygons about .* \+ exact potential about .* in all"):
        plan("exact-potential", gm, (0.5, 47.5), (47.5, 0.5))
    assert time.perf_counter() - t0 < 2
    assert main(["plan", _npz(tmp_path, gm), "--planner", "exact-potential", "--start", "0.5", "47.5",
                 "--goal", "47.5", "0.5"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and limits.SECONDS_ENV_VAR in err and " in all, more than the limit" in err


def test_compare_on_a_grid_map_sums_the_exact_planner_and_the_optimum(tmp_path, monkeypatch, capsys) -> None:
    gm = _noise(48, 0.2, seed=2)
    from gridfield.planners import search_stages

    assert search_stages("visibility", gm) == []  # the optimum's default search (Polyanya) has no long stage
    monkeypatch.setattr(anyangle, "SEARCH", "graph")  # the graph search's visibility graph has one
    stages = search_stages("exact-potential", gm) + search_stages("visibility", gm)
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, repr(_between(stages)))
    _no_polygons(monkeypatch)
    assert main(["compare", _npz(tmp_path, gm), "--start", "0.5", "47.5", "--goal", "47.5", "0.5",
                 "--exact-planner", "exact-potential"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "exact polygons about" in err and "any-angle graph (optimum) about" in err and " in all" in err


def test_compare_on_a_vector_world_sums_the_descent_and_the_visibility_graph(monkeypatch) -> None:
    from gridfield.compare import convergence_study
    from gridfield.geometry.world import world_from_dict

    w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})
    descent = limits.estimate_seconds({"obstacle vertex": 4, "follower step": 10_000})
    graph = limits.estimate_seconds({"vertex pair": 16})
    monkeypatch.setenv(limits.SECONDS_ENV_VAR, repr(descent + graph / 2))  # the descent alone fits
    with pytest.raises(SizeLimitError, match=r"exact potential about .* would take about .* in all"):
        convergence_study(w, [1, 5], [9, 5], [1.0])


# -- progress ---------------------------------------------------------------------------------------


def _slow_graph(monkeypatch) -> None:
    """The any-angle planner on its graph search, whose visibility graph (checked by its corner count)
    takes 0.3 s longer to build (the default Polyanya search has no such long step)."""
    graph = anyangle.AnyAngleGraph._graph

    def slow(self):
        built = "edges" in self._lazy
        out = graph(self)
        if not built:
            time.sleep(0.3)
        return out

    monkeypatch.setattr(anyangle, "SEARCH", "graph")
    monkeypatch.setattr(anyangle.AnyAngleGraph, "_graph", slow)
    # progress() reads its figures from the module that defines it (limits re-exports them)
    monkeypatch.setattr(time_guard, "PROGRESS_SECONDS", 0.0)
    monkeypatch.setattr(time_guard, "PROGRESS_INTERVAL", 0.02)


def test_a_long_search_shows_its_progress_when_asked(tmp_path, monkeypatch, capsys) -> None:
    gm = _noise(24, 0.2, seed=3)
    _slow_graph(monkeypatch)
    monkeypatch.setenv(limits.PROGRESS_ENV_VAR, "1")
    assert main(["plan", _npz(tmp_path, gm), "--planner", "visibility", "--start", "0.5", "23.5",
                 "--goal", "23.5", "0.5"]) == 0
    out, err = capsys.readouterr()
    assert "any-angle graph of" in err and "s elapsed of about" in err and "s estimated" in err
    assert err.endswith("\r") and err.split("\r")[-2].strip() == ""  # the line is erased before the output
    assert "elapsed" not in out and out.startswith("visibility: reached")


def test_no_progress_when_not_asked_and_not_a_terminal(tmp_path, monkeypatch, capsys) -> None:
    gm = _noise(24, 0.2, seed=3)
    _slow_graph(monkeypatch)
    monkeypatch.delenv(limits.PROGRESS_ENV_VAR, raising=False)
    assert main(["plan", _npz(tmp_path, gm), "--planner", "visibility", "--start", "0.5", "23.5",
                 "--goal", "23.5", "0.5"]) == 0
    assert capsys.readouterr().err == ""


# -- the byte guard of the API ----------------------------------------------------------------------


@pytest.fixture
def small_memory(monkeypatch):
    """500 kB available now: a 100 x 100 grid's brushfire (48 B/cell: 480 kB) is over half of it."""
    monkeypatch.delenv(limits.ENV_VAR, raising=False)
    monkeypatch.setattr(limits, "available_memory", lambda: 500_000)


def _free_map(n: int) -> GridMap:
    occ = np.zeros((n, n), bool)
    occ[n // 2, 2:-2] = True
    return GridMap(Grid((n, n), 1.0), occ, source="free map")


@pytest.mark.parametrize("call, job", [
    (lambda gm: plan("wavefront", gm, (1.5, 1.5), (98.5, 98.5)), "plan:wavefront"),
    (lambda gm: build_field(gm, (98.5, 98.5)), "field"),
    (lambda gm: brushfire(gm), "brushfire"),
])
def test_the_api_refuses_a_grid_over_half_the_available_memory(small_memory, call, job) -> None:
    need = 100 * 100 * limits.JOB_BYTES_PER_CELL[job]
    assert need > 250_000
    with pytest.raises(SizeLimitError, match=rf"{job} on 100 x 100 = 10000 cells would need about "
                                             rf"{limits._bytes(need)}.*more than the limit of 250 kB"):
        call(_free_map(100))


def test_the_api_guard_lets_small_grids_and_a_user_limit_through(small_memory) -> None:
    assert brushfire(_free_map(20)).distance.shape == (20, 20)  # 19 kB
    with limits.override(10**6):  # the user's limit in cells replaces the estimate
        assert brushfire(_free_map(100)).distance.shape == (100, 100)
