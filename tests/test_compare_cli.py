"""``gridfield compare`` as a newcomer meets it: every row's reason in the table, unusable resolutions
skipped with a word, ``--scenario F --index N``, numbers (never strings) in ``--json``, and a plot
of the resolutions that ran (one is enough)."""

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
                 "--exact-planner", "visibility", "--resolutions", "8", "4", "2", "1"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = [line.split() for line in out[2:6]]
    assert [r[0] for r in rows] == ["8", "4", "2", "1"]
    assert [r[4] for r in rows] == ["skipped", "skipped", "skipped", "reached"]
    # each skipped row's reason, in words, under the table
    for h in ("8", "4", "2"):
        assert any(line.startswith(f"  resolution {h}: skipped: the start's cell") and "blocked at this resolution"
                   in line for line in out)
    assert "not enough positive errors" not in "\n".join(out)
    assert out[-1] == "observed order (error ~ h^p): needs two resolutions that found a path, 1 did"


def test_skipped_rows_only_where_a_point_is_blocked() -> None:
    from gridfield.geometry.gridpoly import block_downsample

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
    (own,) = [r for r in doc["rows"] if r["resolution"] == 1]
    assert own["length"] == pytest.approx(doc["optimal"], abs=0.01)


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


ONE_RAN = [ARENA, "--start", "1.5", "37.5", "--goal", "45.5", "3.5", "--planner", "wavefront-octile",
           "--exact-planner", "visibility", "--resolutions", "8", "4", "2", "1"]  # only 1 has both points free


def test_plot_with_one_resolution_that_ran_draws_it(tmp_path, capsys: pytest.CaptureFixture[str],
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    """A plot of one resolution is still a plot: exit 0, the table, and the figure of that row's errors
    (the values drawn are the ones --json reports for the row; no slope line, which needs two)."""
    from PIL import Image

    import gridfield.plot

    assert main(["compare", *ONE_RAN, "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    ran = [r for r in rows if r["status"] == "reached"]
    assert [r["resolution"] for r in rows] == [8, 4, 2, 1] and [r["resolution"] for r in ran] == [1]
    drawn = []
    real = gridfield.plot.plot_convergence
    monkeypatch.setattr(gridfield.plot, "plot_convergence", lambda *a, **k: drawn.append(real(*a, **k)) or drawn[-1])
    f = tmp_path / "c.png"
    assert main(["compare", *ONE_RAN, "--plot", str(f)]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    out = captured.out.splitlines()
    assert [line.split()[4] for line in out[2:6]] == ["skipped", "skipped", "skipped", "reached"]  # the table
    assert out[-1] == f"wrote {f} (one resolution ran: its errors, no order)"
    with Image.open(f) as im:
        assert im.format == "PNG" and len(set(np.asarray(im.convert("L")).ravel().tolist())) > 2
    (art,) = drawn
    points = {line.get_label(): (list(line.get_xdata()), list(line.get_ydata())) for line in art.paths}
    row = ran[0]
    assert points == {"Hausdorff": ([1.0], [row["hausdorff"]]), "Frechet": ([1.0], [row["frechet"]]),
                      "|length ratio - 1|": ([1.0], [pytest.approx(abs(row["length_ratio"] - 1))])}
    assert art.extra["reference"] == [] and "one resolution" in art.ax.get_title()


def test_plot_when_no_resolution_ran_says_so_in_one_line(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "c.png"
    assert main(["compare", *ONE_RAN, "--resolutions", "8", "4", "--plot", str(f)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert [line.split()[4] for line in out[2:4]] == ["skipped", "skipped"]
    assert out[-1].startswith(f"no plot written to {f}: none of the 2 resolutions ran (see the table)")
    assert not f.exists()
    assert main(["compare", ARENA, "--start", "10", "10", "--goal", "42", "42", "--planner", "wavefront-octile",
                 "--exact-planner", "visibility", "--plot", str(f)]) == 0
    assert f.is_file() and capsys.readouterr().out.splitlines()[-1] == f"wrote {f}"


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


def test_a_grid_maps_default_resolutions_subdivide_so_that_two_run(capsys: pytest.CaptureFixture[str]) -> None:
    """README's old example on arena ran at one resolution only (the coarse cells block the start), so the
    study said "needs two resolutions"; the default now also splits the map's cells (x1/2, x1/4), where
    the points are as free as at the map's own resolution, and the order is estimated."""
    assert main(["compare", ARENA, "--start", "1.5", "37.5", "--goal", "45.5", "3.5", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [r["resolution"] for r in doc["rows"]] == [4, 2, 1, 0.5, 0.25]
    ran = [r for r in doc["rows"] if r["status"] == "reached"]
    assert [r["resolution"] for r in ran] == [1, 0.5, 0.25]
    # the finer grids come closer to the any-angle optimum (the exact side)
    ratios = [r["length_ratio"] for r in ran]
    assert ratios[0] > ratios[1] > ratios[2] >= 1.0 - 1e-9, ratios
    assert doc["order"]["hausdorff"] is not None and doc["order"]["hausdorff"] > 0


def test_subdivide_keeps_the_free_space() -> None:
    from gridfield.geometry.gridpoly import grid_world, subdivide

    gm = read(ARENA)
    fine = subdivide(gm, 3)
    assert fine.grid.resolution == pytest.approx(gm.grid.resolution / 3) and fine.grid.origin == gm.grid.origin
    assert np.array_equal(fine.occupied, np.kron(gm.occupied.astype(int), np.ones((3, 3), int)).astype(bool))
    assert grid_world(fine).obstacles and sum(o.geometry.area for o in grid_world(fine).obstacles) == pytest.approx(
        sum(o.geometry.area for o in grid_world(gm).obstacles))


def _gap_map(tmp_path) -> str:
    """A 16 x 16 Moving AI map split by a wall in column 8 with a one-cell gap at row 5 (file rows count
    from the top): halving the resolution (block_downsample, conservative) closes the gap."""
    rows = []
    for r in range(16):
        rows.append("".join("@" if c == 8 and r != 10 else "." for c in range(16)))
    f = tmp_path / "gap.map"
    f.write_text("type octile\nheight 16\nwidth 16\nmap\n" + "\n".join(rows) + "\n")
    return str(f)


def test_a_resolution_that_closes_the_way_is_said_and_left_out_of_the_order(tmp_path, capsys) -> None:
    """At h = 2 the conservative grid closes the one-cell gap: the row says no_path, its errors are '-' (a
    start-only path measures no discretization error; before: len/exact 0.0000 and a Hausdorff of the
    start's distance to the exact path, fitted into the observed order), the reason is under the table."""
    from gridfield.compare import no_path_at_resolution, study_errors

    f = _gap_map(tmp_path)
    gm = read(f)
    rows = convergence_study(gm, (2.5, 8.5), (13.5, 8.5), [2, 1, 0.5], grid_planner="wavefront-octile",
                             exact_planner="visibility")
    assert [r["status"] for r in rows] == ["no_path", "reached", "reached"]
    assert [no_path_at_resolution(r) for r in rows] == [True, False, False]
    assert np.isnan(rows[0]["length_ratio"])
    errs = study_errors(rows)
    assert all(np.isnan(errs[k][0]) for k in errs) and not np.isnan(errs["hausdorff"][1])

    assert main(["compare", f, "--start", "2.5", "8.5", "--goal", "13.5", "8.5", "--planner", "wavefront-octile",
                 "--exact-planner", "visibility", "--resolutions", "2", "1", "0.5"]) == 0
    out = capsys.readouterr().out.splitlines()
    first = out[2].split()
    assert first[:6] == ["2", "64", first[2], first[3], "no_path", "reached"]
    assert first[6:11] == ["-"] * 5  # len/exact, len/opt, Hausdorff, Frechet, stall err
    assert any(line.startswith("  resolution 2: no_path: the grid at this resolution") and "left out of the observed"
               in line for line in out)
    assert out[-1].startswith("observed order (error ~ h^p): ")
    assert "needs two" not in out[-1]


def test_a_no_path_row_has_no_clearance(tmp_path, capsys) -> None:
    """A row whose grid planner found no path has no clearance (its one point is the start: before, the column
    showed the start's clearance): NaN from the API, '-' in the table (as its len/exact), null in --json, while
    the rows that reached keep theirs."""
    f = _gap_map(tmp_path)
    argv = ["compare", f, "--start", "2.5", "8.5", "--goal", "13.5", "8.5", "--planner", "wavefront-octile",
            "--exact-planner", "visibility", "--resolutions", "2", "1"]
    rows = convergence_study(read(f), (2.5, 8.5), (13.5, 8.5), [2, 1], grid_planner="wavefront-octile",
                             exact_planner="visibility")
    assert [r["status"] for r in rows] == ["no_path", "reached"]
    assert np.isnan(rows[0]["min_clearance"]) and np.isnan(rows[0]["length_ratio"])
    assert rows[1]["min_clearance"] > 0

    assert main(argv) == 0
    table = capsys.readouterr().out.splitlines()[2:4]
    cells = [line.split() for line in table]
    assert cells[0][4] == "no_path" and cells[0][6] == "-" and cells[0][11] == "-", table
    assert len(cells[0]) == len(cells[1]) == 12, table  # the column is there, '-' keeps the table's shape
    assert float(cells[1][11]) == pytest.approx(rows[1]["min_clearance"], abs=1e-4)

    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["rows"][0]["min_clearance"] is None and doc["rows"][0]["length_ratio"] is None
    assert doc["rows"][1]["min_clearance"] == pytest.approx(rows[1]["min_clearance"])
