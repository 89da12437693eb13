"""Batch sweeps: rows, resume, success rates vs individual plans, local pool vs a Dask LocalCluster."""

from __future__ import annotations

import csv
import json
import math
import shutil
from pathlib import Path

import pytest

from gridfield.cli import main
from gridfield.errors import MapFormatError
from gridfield.io import bundled_map
from gridfield.planners import plan
from gridfield.sweep import COLUMNS, load_spec, run_sweep, summarize


def _spec(tmp_path: Path, body: str) -> Path:
    for name in ("seed000.yaml", "seed000_segment.yaml"):
        shutil.copy(bundled_map(name), tmp_path / name)
    (tmp_path / "arena").mkdir()
    for name in ("arena.map", "arena.map.scen"):
        shutil.copy(bundled_map(f"arena/{name}"), tmp_path / "arena" / name)
    spec = tmp_path / "spec.yaml"
    spec.write_text(body)
    return spec


SPEC = """
output: runs.csv
maps:
  - path: seed000.yaml
    resolution: 0.25
    pairs: [[[1, 10], [22, 12]], [[2, 2], [22, 12]]]
  - path: seed000_segment.yaml
    resolution: 0.25
    random_pairs: {n: 3, seed: 4}
planners: [potential, wavefront-octile]
params:
  q_star: [1.5, 2.0]
"""


def _key(row: dict) -> tuple:
    return (row["map"], row["planner"], row["params"], row["start_x"], row["start_y"], row["goal_x"], row["goal_y"])


def test_spec_expands_to_the_product_of_maps_pairs_planners_and_params(tmp_path: Path) -> None:
    runs, output = load_spec(_spec(tmp_path, SPEC))
    assert output == tmp_path / "runs.csv"
    assert len(runs) == (2 + 3) * 2 * 2
    assert {json.loads(r.params_json)["q_star"] for r in runs} == {1.5, 2.0}


def test_rows_match_individual_plan_calls_and_resume_recomputes_nothing(tmp_path: Path, monkeypatch) -> None:
    runs, output = load_spec(_spec(tmp_path, SPEC))
    rows = run_sweep(runs, output, workers=1, progress=False)
    assert len(rows) == len(runs)
    assert list(rows[0]) == list(COLUMNS)
    # each row agrees with a separate `plan` call (status, length)
    from gridfield.io import read

    for run, row in zip(runs, rows, strict=True):
        path = plan(run.planner, read(run.map), run.start, run.goal, dict(run.params), resolution=run.resolution)
        assert row["status"] == path.status
        assert math.isclose(float(row["length"]), path.length, rel_tol=1e-9)
    # success rates on the seed 000 world equal the individual plan calls' outcomes
    summary = {(s["map"], s["planner"], s["params"]): s for s in summarize(rows)}
    for key, s in summary.items():
        mine = [r for r in rows if (r["map"], r["planner"], r["params"]) == key]
        assert s["success_rate"] == sum(r["status"] == "reached" for r in mine) / len(mine)
    # the wavefront is complete: it reaches every goal; potential fields do not always
    assert all(s["success_rate"] == 1.0 for k, s in summary.items() if k[1] == "wavefront-octile")

    # resume: a second run computes nothing (run_one must not be called) and keeps the rows
    import gridfield.sweep as sweep_module

    def boom(run):  # pragma: no cover - must not run
        raise AssertionError("resume recomputed a run")

    monkeypatch.setattr(sweep_module, "run_one", boom)
    again = run_sweep(runs, output, workers=1, progress=False)
    assert [_key(r) for r in again] == [_key(r) for r in rows]


def test_interrupted_sweep_resumes_only_the_missing_runs(tmp_path: Path, monkeypatch) -> None:
    runs, output = load_spec(_spec(tmp_path, SPEC))
    run_sweep(runs[:5], output, workers=1, progress=False)  # as if interrupted after five runs
    import gridfield.sweep as sweep_module

    seen = []
    real = sweep_module.run_one
    monkeypatch.setattr(sweep_module, "run_one", lambda r: seen.append(r.key) or real(r))
    rows = run_sweep(runs, output, workers=1, progress=False)
    assert len(seen) == len(runs) - 5
    assert {r.key for r in runs[:5]}.isdisjoint(seen)
    assert len(rows) == len(runs)


def test_local_pool_and_dask_localcluster_give_the_same_rows(tmp_path: Path) -> None:
    import distributed
    runs, _ = load_spec(_spec(tmp_path, SPEC))
    runs = runs[:8]
    local = run_sweep(runs, tmp_path / "local.csv", workers=2, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        remote = run_sweep(runs, tmp_path / "dask.csv", scheduler=client, progress=False)

    def strip(rows):
        return sorted((_key(r), r["status"], r["length"], r["steps"]) for r in rows)

    assert strip(local) == strip(remote)


def test_movingai_scenarios_carry_their_optimal_length(tmp_path: Path) -> None:
    spec = _spec(tmp_path, """
maps:
  - path: arena/arena.map
    scenarios: arena/arena.map.scen
    limit: 6
planners: [wavefront-octile]
""")
    runs, output = load_spec(spec)
    rows = run_sweep(runs, output, workers=1, progress=False)
    assert len(rows) == 6
    for r in rows:
        assert r["status"] == "reached"
        # the octile wavefront's own grid length equals the benchmark's optimum
        assert float(r["optimal"]) > 0
    s = summarize(rows)[0]
    assert s["success_rate"] == 1.0 and s["length_ratio"] >= 1.0 - 1e-9


def test_cli_sweep_writes_rows_and_summary(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    spec = _spec(tmp_path, SPEC.replace("[potential, wavefront-octile]", "[wavefront-octile]"))
    assert main(["sweep", str(spec), "--workers", "1", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "wrote 10 rows" in out
    with (tmp_path / "runs.summary.csv").open() as f:
        summary = list(csv.DictReader(f))
    assert {s["planner"] for s in summary} == {"wavefront-octile"}


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("maps: []", "maps must be a non-empty list"),
        ("maps: [seed000.yaml]\nplanners: [teleport]", "unknown planner 'teleport'"),
        ("maps: [seed000.yaml]\nparams: {zetta: 1}", "unknown parameter 'zetta'"),
        ("maps: [{resolution: 1}]", "missing key 'path'"),
        ("maps: [{path: seed000.yaml, pairs: [[1, 2]]}]", "pairs[0]"),
    ],
)
def test_bad_specs_name_the_problem(tmp_path: Path, body: str, message: str) -> None:
    with pytest.raises(MapFormatError, match=None) as e:
        load_spec(_spec(tmp_path, body))
    assert message in str(e.value)


def test_maps_are_loaded_and_brushfires_computed_once_per_map(tmp_path: Path, monkeypatch) -> None:
    import gridfield.io
    import gridfield.potential
    import gridfield.sweep as sweep_module

    spec = _spec(tmp_path, SPEC.replace("[potential, wavefront-octile]", "[potential]"))
    runs, output = load_spec(spec)
    monkeypatch.setattr(sweep_module, "_CACHE", {})
    calls = {"read": 0, "brushfire": 0}
    real_read, real_dmap = gridfield.io.read, gridfield.potential.field_distance_map

    def counting_read(*a, **k):
        calls["read"] += 1
        return real_read(*a, **k)

    def counting_dmap(*a, **k):
        calls["brushfire"] += 1
        return real_dmap(*a, **k)

    monkeypatch.setattr(gridfield.io, "read", counting_read)
    monkeypatch.setattr(gridfield.potential, "field_distance_map", counting_dmap)
    rows = run_sweep(runs, output, workers=1, progress=False)
    assert len(rows) == len(runs) == 10
    assert calls == {"read": 2, "brushfire": 2}  # two maps; one metric


def test_bundled_example_sweep_runs_from_the_command_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    spec = bundled_map("sweep_example.yaml")
    runs, _ = load_spec(spec)
    assert len(runs) == (10 + 10) * 2 * 2  # pairs x planners x q_star values
    out = tmp_path / "runs.csv"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    assert "wrote 80 rows" in capsys.readouterr().out
    with out.with_suffix(".summary.csv").open() as f:
        summary = list(csv.DictReader(f))
    octile = [s for s in summary if s["planner"] == "wavefront-octile" and s["map"].endswith("arena.map")]
    assert len(octile) == 2
    for s in octile:  # the Moving AI scenarios' published optimal lengths
        assert float(s["success_rate"]) == 1.0 and float(s["length_ratio"]) == pytest.approx(1.0, abs=1e-6)


def test_optimal_any_angle_column_on_a_moving_ai_map(tmp_path: Path) -> None:
    """The any-angle optimum of each scenario: never above the file's octile optimum, equal to a
    direct plan('visibility') call, and the any-angle potential planner's ratio to it is >= 1."""
    spec = _spec(tmp_path, """
output: runs.csv
maps:
  - path: arena/arena.map
    scenarios: arena/arena.map.scen
    limit: 6
    optimal_any_angle: true
planners: [wavefront-octile, visibility]
""")
    runs, output = load_spec(spec)
    assert all(r.any_angle for r in runs)
    rows = run_sweep(runs, output, workers=1, progress=False)
    from gridfield.io import read_movingai_map

    m = read_movingai_map(tmp_path / "arena" / "arena.map")
    for r in rows:
        opt, any_opt = float(r["optimal"]), float(r["optimal_any_angle"])
        assert any_opt <= opt + 1e-4
        start, goal = (float(r["start_x"]), float(r["start_y"])), (float(r["goal_x"]), float(r["goal_y"]))
        assert any_opt == pytest.approx(plan("visibility", m, start, goal).length, abs=1e-9)
        if r["planner"] == "visibility":
            assert float(r["length"]) == pytest.approx(any_opt, abs=1e-6)
        else:
            assert float(r["length"]) >= any_opt - 1e-9
    s = {x["planner"]: x for x in summarize(rows)}
    assert s["visibility"]["length_ratio_any_angle"] == pytest.approx(1.0, abs=1e-6)
    assert s["wavefront-octile"]["length_ratio_any_angle"] >= 1.0
    with pytest.raises(MapFormatError, match="optimal_any_angle must be true or false"):
        (tmp_path / "bad").mkdir()
        load_spec(_spec(tmp_path / "bad", "maps: [seed000.yaml]\noptimal_any_angle: yes please\n"))


def test_resume_of_a_rows_file_without_the_any_angle_column(tmp_path: Path) -> None:
    """A rows file from before the optimal_any_angle column: resuming appends rows under its header."""
    runs, output = load_spec(_spec(tmp_path, SPEC))
    old_cols = [c for c in COLUMNS if c != "optimal_any_angle"]
    first = run_sweep(runs[:3], output, workers=1, progress=False)
    with output.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=old_cols, extrasaction="ignore")
        w.writeheader()
        w.writerows(first)
    rows = run_sweep(runs, output, workers=1, progress=False)
    assert len(rows) == len(runs) and all(set(r) == set(old_cols) for r in rows)
    assert summarize(rows)  # the summary copes with the missing column
