"""Batch sweeps: rows, resume, success rates vs individual plans, local pool vs a Dask LocalCluster."""

from __future__ import annotations

import csv
import json
import math
import shutil
from pathlib import Path

import pytest

from gridfield.cli import main
from gridfield.core.errors import MapFormatError
from gridfield.io import bundled_map
from gridfield.planners import plan
from gridfield.sweep import COLUMNS, load_spec, run_sweep, summarize

from mapdata import MOVINGAI, raw


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
    import gridfield.sweep._run as sweep_run  # where run_batch looks up run_one and the map cache

    def boom(run, target=None):  # pragma: no cover - must not run
        raise AssertionError("resume recomputed a run")

    monkeypatch.setattr(sweep_run, "run_one", boom)
    again = run_sweep(runs, output, workers=1, progress=False)
    assert [_key(r) for r in again] == [_key(r) for r in rows]


def test_interrupted_sweep_resumes_only_the_missing_runs(tmp_path: Path, monkeypatch) -> None:
    runs, output = load_spec(_spec(tmp_path, SPEC))
    run_sweep(runs[:5], output, workers=1, progress=False)  # as if interrupted after five runs
    import gridfield.sweep._run as sweep_run  # where run_batch looks up run_one and the map cache

    seen = []
    real = sweep_run.run_one
    monkeypatch.setattr(sweep_run, "run_one", lambda r, t=None: seen.append(r.key) or real(r, t))
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
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
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
    import gridfield.fields.potential
    import gridfield.io
    import gridfield.sweep._run as sweep_run  # where run_batch looks up run_one and the map cache

    spec = _spec(tmp_path, SPEC.replace("[potential, wavefront-octile]", "[potential]"))
    runs, output = load_spec(spec)
    monkeypatch.setattr(sweep_run, "_CACHE", {})
    calls = {"read": 0, "brushfire": 0}
    real_read, real_dmap = gridfield.io.read, gridfield.fields.potential.field_distance_map

    def counting_read(*a, **k):
        calls["read"] += 1
        return real_read(*a, **k)

    def counting_dmap(*a, **k):
        calls["brushfire"] += 1
        return real_dmap(*a, **k)

    monkeypatch.setattr(gridfield.io, "read", counting_read)
    monkeypatch.setattr(gridfield.fields.potential, "field_distance_map", counting_dmap)
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
        assert float(s["length_ratio_any_angle"]) >= 1.0 - 1e-9  # optimal_any_angle: true on the arena entry
    assert all(math.isnan(float(s["length_ratio_any_angle"])) for s in summary if s["map"].endswith("seed000.yaml"))


# ----------------------------------------------------------------------------------------
# optimal_any_angle: the exact any-angle optimum of every query, beside the scenario's octile one
# ----------------------------------------------------------------------------------------
DEN312D = MOVINGAI / "den312d" / "den312d.map.gz"


def _den312d_spec(tmp_path: Path, n: int = 8, extra: str = "") -> Path:
    """A spec on den312d (65 x 81, tests/data/maps) with ``n`` scenarios spread over its whole .scen file."""
    lines = raw(DEN312D.parent / "den312d.map.scen.gz").decode().splitlines()
    body = [ln for ln in lines[1:] if ln.strip()]
    picked = [body[round(k * (len(body) - 1) / (n - 1))] for k in range(n)]
    (tmp_path / "den.scen").write_text("\n".join([lines[0], *picked]) + "\n")
    spec = tmp_path / "spec.yaml"
    spec.write_text(f"""
output: rows.csv
maps:
  - path: {DEN312D}
    scenarios: den.scen
    optimal_any_angle: true
planners: [wavefront-octile, visibility]
params:
  q_star: [1.0, 2.0]
{extra}""")
    return spec


def _count_graph_builds(monkeypatch) -> list[int]:
    """Count the any-angle graph builds from now on (the module and sweep caches emptied)."""
    from collections import OrderedDict

    import gridfield.exact.anyangle as anyangle
    import gridfield.sweep._run as sweep_run  # where run_batch looks up run_one and the map cache

    monkeypatch.setattr(sweep_run, "_CACHE", {})
    monkeypatch.setattr(anyangle, "_GRAPHS", OrderedDict())
    builds: list[int] = []
    real = anyangle._build
    monkeypatch.setattr(anyangle, "_build", lambda gm: builds.append(1) or real(gm))
    return builds


def test_optimal_any_angle_column_is_the_visibility_optimum_on_a_moving_ai_map(tmp_path: Path, monkeypatch) -> None:
    """Scenarios spread over den312d: the column equals a separate plan('visibility') call, lies between
    the straight line and the file's octile optimum, and the octile wavefront's ratio to it is >= 1
    (> 1 somewhere: the column is not the octile optimum). One graph for the map, one solve per query."""
    import gridfield.compare

    runs, output = load_spec(_den312d_spec(tmp_path))
    assert len(runs) == 8 * 2 * 2 and all(r.any_angle for r in runs)
    builds = _count_graph_builds(monkeypatch)
    solved: list[tuple] = []
    real_fn = gridfield.compare.optimum_solver

    def counting_fn(world, **kw):
        solve = real_fn(world, **kw)
        return lambda s, g: solved.append((tuple(s), tuple(g))) or solve(s, g)

    monkeypatch.setattr(gridfield.compare, "optimum_solver", counting_fn)
    rows = run_sweep(runs, output, workers=1, progress=False)
    assert builds == [1]  # shared by both planners, both parameter sets and the column
    assert sorted(solved) == sorted({(r.start, r.goal) for r in runs})  # each query solved once
    monkeypatch.undo()

    from gridfield.io import read_movingai_map

    m = read_movingai_map(DEN312D)
    ratios = []
    for r in rows:
        assert r["status"] == "reached"
        start, goal = (float(r["start_x"]), float(r["start_y"])), (float(r["goal_x"]), float(r["goal_y"]))
        any_opt = float(r["optimal_any_angle"])
        assert any_opt == pytest.approx(plan("visibility", m, start, goal).length, abs=1e-9)
        assert math.dist(start, goal) - 1e-9 <= any_opt <= float(r["optimal"]) + 1e-4  # .scen: 5 decimals
        if r["planner"] == "visibility":
            assert float(r["length"]) == pytest.approx(any_opt, abs=1e-9)
        else:
            ratios.append(float(r["length"]) / any_opt)
    assert min(ratios) >= 1 - 1e-9 and max(ratios) > 1.01
    s = {(x["planner"], x["params"]): x for x in summarize(rows)}
    for (planner, _), x in s.items():
        if planner == "visibility":
            assert x["length_ratio_any_angle"] == pytest.approx(1.0, abs=1e-9)
        else:
            assert x["length_ratio_any_angle"] == pytest.approx(sum(ratios) / len(ratios), rel=1e-12)
            assert x["length_ratio_any_angle"] >= 1 - 1e-9 and x["length_ratio"] == pytest.approx(1.0, abs=1e-4)


def test_optimal_any_angle_graph_is_built_once_across_dask_batches(tmp_path: Path, monkeypatch) -> None:
    """Eight batches of one map on a (threaded) Dask worker: the shipped map's graph is built once."""
    import distributed

    runs, output = load_spec(_den312d_spec(tmp_path, n=4))
    builds = _count_graph_builds(monkeypatch)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        rows = run_sweep(runs, output, scheduler=client, progress=False, batch_size=2)
    assert len(rows) == len(runs) == 16
    assert builds == [1]
    assert all(math.isfinite(float(r["optimal_any_angle"])) for r in rows)


def test_a_rows_file_from_before_the_any_angle_column_resumes(tmp_path: Path, monkeypatch) -> None:
    """A rows file written before optimal_any_angle existed (12 columns) is resumed: its rows are kept
    (nan in the new column) and not recomputed, the missing runs get the column (the visibility optimum
    of the vector world), and the file gets the current header."""
    spec = _spec(tmp_path, SPEC + "optimal_any_angle: true\n")
    runs, output = load_spec(spec)
    run_sweep(runs[:4], output, workers=1, progress=False)
    old = [",".join(COLUMNS[:-1])] + [ln.rsplit(",", 1)[0] for ln in output.read_text().splitlines()[1:]]
    output.write_text("\n".join(old) + "\n")  # as the sweep wrote it before the column

    import gridfield.sweep._run as sweep_run  # where run_batch looks up run_one and the map cache

    seen: list[tuple] = []
    real = sweep_run.run_one
    monkeypatch.setattr(sweep_run, "run_one", lambda r, t=None: seen.append(r.key) or real(r, t))
    notes: list[str] = []
    rows = run_sweep(runs, output, workers=1, progress=False, notes=notes)
    assert sorted(seen) == sorted(r.key for r in runs[4:])
    assert any("added the column optimal_any_angle" in n for n in notes)
    lines = output.read_text().splitlines()
    assert lines[0] == ",".join(COLUMNS) and len(lines) == len(runs) + 1
    assert [_key(r) for r in rows[:4]] == [_key(dict(zip(COLUMNS, f, strict=True))) for f in csv.reader(lines[1:5])]
    assert all(r["optimal_any_angle"] == "nan" for r in rows[:4])

    from gridfield.io import read

    for run, r in zip(runs[4:], rows[4:], strict=True):
        assert float(r["optimal_any_angle"]) == pytest.approx(plan("visibility", read(run.map), run.start,
                                                                   run.goal).length, abs=1e-9)
    for s in summarize(rows):  # the groups of the old rows have no any-angle ratio, the others have one
        old_group = s["map"] == runs[0].map and s["planner"] == runs[0].planner
        assert math.isnan(s["length_ratio_any_angle"]) == (old_group or s["success_rate"] == 0)
    seen.clear()
    assert len(run_sweep(runs, output, workers=1, progress=False)) == len(runs) and not seen  # nothing redone


def test_optimal_any_angle_in_spawned_workers_equals_one_process(tmp_path: Path) -> None:
    """Runs pickled to a spawned local pool carry the flag: the column is the same as in one process."""
    runs, _ = load_spec(_den312d_spec(tmp_path, n=4))
    one = run_sweep(runs, tmp_path / "one.csv", workers=1, progress=False)
    pool = run_sweep(runs, tmp_path / "pool.csv", workers=2, batch_size=4, progress=False)

    def strip(rows):
        return sorted((_key(r), r["status"], r["length"], r["optimal_any_angle"]) for r in rows)

    assert strip(pool) == strip(one)
    assert all(math.isfinite(float(r["optimal_any_angle"])) for r in pool)
