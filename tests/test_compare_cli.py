"""``gridfield compare`` as a newcomer meets it: every row's reason in the table, unusable resolutions
skipped with a word, ``--scenario F --index N``, numbers (never strings) in ``--json``, and a plot
only of resolutions that ran."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gridfield.cli import main
from gridfield.compare import convergence_study
from gridfield.io import bundled_map, read, read_scen

ARENA = str(bundled_map("arena/arena.map"))
SCEN = str(bundled_map("arena/arena.map.scen"))


def test_readmes_old_example_gives_each_rows_reason(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["compare", ARENA, "--start", "1.5", "37.5", "--goal", "45.5", "3.5", "--planner", "wavefront-octile",
                 "--exact-planner", "visibility"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = [line.split() for line in out[2:6]]
    assert [r[0] for r in rows] == ["8", "4", "2", "1"]
    assert [r[4] for r in rows] == ["skipped", "skipped", "skipped", "reached"]
    # each skipped row's reason, in words, under the table
    for h in ("8", "4", "2"):
        assert any(line.startswith(f"  resolution {h}: skipped: the start's cell") and "blocked at this resolution"
                   in line for line in out)
    assert "not enough positive errors" not in "\n".join(out)
    assert out[-1] == "observed order (error ~ h^p): needs two resolutions that ran, 1 did"


def test_skipped_rows_only_where_a_point_is_blocked() -> None:
    from gridfield.gridpoly import block_downsample

    gm = read(ARENA)
    rows = convergence_study(gm, (10, 10), (42, 42), [8, 4, 2, 1], grid_planner="wavefront-octile",
                             exact_planner="visibility")
    for r in rows:
        coarse = block_downsample(gm, int(r["resolution"]))
        blocked = not (coarse.is_free([(10, 10)])[0] and coarse.is_free([(42, 42)])[0])
        assert r["status"].startswith("skipped: ") == blocked, r
        assert not r["status"].startswith("error")


def test_compare_takes_a_scenario(capsys: pytest.CaptureFixture[str]) -> None:
    gm = read(ARENA)
    scen = read_scen(SCEN, map_height=gm.grid.rows)
    assert main(["compare", ARENA, "--scenario", SCEN, "--index", "159", "--planner", "wavefront-octile",
                 "--exact-planner", "visibility", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert np.allclose(doc["start"], scen.start_xy[159]) and np.allclose(doc["goal"], scen.goal_xy[159])
    assert doc["optimal"] == pytest.approx(float(scen.optimal[159]))
    # the octile wavefront at the map's own resolution is the scenario's optimum
    assert doc["rows"][-1]["length"] == pytest.approx(doc["optimal"], abs=0.01)


def _strings(v: object) -> list[object]:
    if isinstance(v, dict):
        return [s for x in v.values() for s in _strings(x)]
    if isinstance(v, list):
        return [s for x in v for s in _strings(x)]
    return [v] if isinstance(v, str) and v.lower().lstrip("+-") in ("inf", "nan") else []


def test_compare_json_has_no_strings_for_numbers(capsys: pytest.CaptureFixture[str]) -> None:
    # potential at 8: the goal is not reached and some lengths are infinite
    assert main(["compare", str(bundled_map("seed000_segment.yaml")), "--resolutions", "0.4", "0.2",
                 "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert _strings(doc) == []


def test_plot_needs_two_resolutions_that_ran(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "c.png"
    assert main(["compare", ARENA, "--start", "1.5", "37.5", "--goal", "45.5", "3.5", "--planner", "wavefront-octile",
                 "--exact-planner", "visibility", "--plot", str(f)]) == 2
    assert "needs two resolutions that ran, 1 did" in capsys.readouterr().err and not f.exists()
    assert main(["compare", ARENA, "--start", "10", "10", "--goal", "42", "42", "--planner", "wavefront-octile",
                 "--exact-planner", "visibility", "--plot", str(f)]) == 0
    assert f.is_file()


def test_the_default_exact_planner_is_what_the_grid_planner_converges_to(capsys: pytest.CaptureFixture[str]) -> None:
    """The potential planner's default model (complete) converges to the shortest path, so compare sets it
    against ``visibility``; the classic field (a world file's ``model: khatib``, or ``--param``) against
    ``exact-potential``, as before."""
    assert main(["compare", ARENA, "--scenario", SCEN, "--index", "10", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["exact_planner"] == "visibility"
    reached = [r for r in out["rows"] if r["status"] == "reached"]
    assert reached and all(r["exact_status"] == "reached" for r in reached)
    # against the shortest path, the complete field's length ratio is at least 1 (up to rounding)
    assert all(r["length_ratio"] >= 1 - 1e-9 for r in reached)
    assert main(["compare", str(bundled_map("seed000.yaml")), "--resolutions", "0.4", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["exact_planner"] == "exact-potential"  # the file says khatib
    assert main(["compare", ARENA, "--scenario", SCEN, "--index", "10", "--param", "model=khatib", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["exact_planner"] == "exact-potential"
