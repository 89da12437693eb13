"""The sweep journal (rows file): crash at any byte, damaged lines, the lock, signals, run errors; spec checks."""

from __future__ import annotations

import math
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import gridfield.sweep as sweep_module
import gridfield.sweep._run as sweep_run  # where run_batch looks up run_one
from gridfield.cli import main
from gridfield.core.errors import GridfieldError, MapFormatError
from gridfield.io import bundled_map
from gridfield.sweep import COLUMNS, Run, load_spec, run_sweep

ROOT = Path(__file__).resolve().parent.parent


def _runs(n: int = 6) -> list[Run]:
    return [Run("maps/m.yaml", 0.5, "potential", (("eta", 1.0 + k % 2),), (0.5 * k, 1.0), (3.0, 0.1 * k)) for k in range(n)]


def _fake_row(run: Run, target=None) -> dict:
    # a status with a comma, quotes and a newline: the row must still be one line of the file
    return {"map": run.map, "planner": run.planner, "params": run.params_json, "start_x": run.start[0],
            "start_y": run.start[1], "goal_x": run.goal[0], "goal_y": run.goal[1],
            "status": 'error: bad "value",\nsecond line' if run.start[0] == 1.0 else "reached",
            "length": 1.5 * run.start[0], "optimal": math.nan, "steps": 3, "ms": 0.25}


def _lines(path: Path) -> list[str]:
    return path.read_text().splitlines()


def test_a_sweep_cut_at_any_byte_resumes_to_exactly_one_row_per_run(tmp_path: Path, monkeypatch) -> None:
    runs = _runs()
    calls: list[tuple] = []
    monkeypatch.setattr(sweep_run, "run_one", lambda r, t=None: calls.append(r.key) or _fake_row(r))
    full = tmp_path / "full.csv"
    run_sweep(runs, full, workers=1, progress=False)
    data = full.read_bytes()
    assert len(_lines(full)) == len(runs) + 1  # the newline in the status did not split the row
    out = tmp_path / "cut.csv"
    for cut in range(len(data) + 1):
        out.write_bytes(data[:cut])
        calls.clear()
        rows = run_sweep(runs, out, workers=1, progress=False)
        complete = max(data[:cut].count(b"\n") - 1, 0)  # whole data lines that survived the cut
        assert len(calls) == len(runs) - complete, cut
        assert sorted(calls) == sorted(r.key for r in runs[complete:]), cut
        assert len(rows) == len(runs)
        assert out.read_bytes() == data, cut  # the repaired and completed file is the uncut one


def test_damaged_and_duplicate_lines_are_dropped_and_their_runs_redone(tmp_path: Path, monkeypatch) -> None:
    runs = _runs()
    monkeypatch.setattr(sweep_run, "run_one", lambda r, t=None: _fake_row(r))
    out = tmp_path / "rows.csv"
    run_sweep(runs, out, workers=1, progress=False)
    lines = _lines(out)
    # the old bug: a partial row glued to the next one (a line of 23 fields), and a row written twice
    glued = lines[2][:30] + lines[3]
    out.write_text("\r\n".join([lines[0], lines[1], glued, lines[4], lines[4], *lines[5:]]) + "\r\n")
    notes: list[str] = []
    redone = []
    monkeypatch.setattr(sweep_run, "run_one", lambda r, t=None: redone.append(r.key) or _fake_row(r))
    rows = run_sweep(runs, out, workers=1, progress=False, notes=notes)
    assert sorted(redone) == sorted([runs[1].key, runs[2].key])
    assert len(rows) == len(runs) and len({(r["start_x"], r["goal_y"]) for r in rows}) == len(runs)
    assert len(_lines(out)) == len(runs) + 1
    assert any("1 damaged line" in n for n in notes) and any("1 duplicate" in n for n in notes)


def test_a_foreign_file_is_not_overwritten(tmp_path: Path) -> None:
    out = tmp_path / "notes.csv"
    out.write_text("a,b,c\n1,2,3\n")
    with pytest.raises(GridfieldError, match="not a rows file"):
        run_sweep(_runs(), out, workers=1, progress=False)
    assert out.read_text() == "a,b,c\n1,2,3\n"


def test_a_second_sweep_on_the_same_file_stops_at_once(tmp_path: Path, monkeypatch) -> None:
    out = tmp_path / "rows.csv"
    holder = sweep_module._Journal(out)  # a sweep in progress
    try:
        with pytest.raises(GridfieldError, match="another sweep is writing"):
            run_sweep(_runs(), out, workers=1, progress=False)
        # from another process, through the command line: one line, exit 2
        spec = tmp_path / "spec.yaml"
        shutil.copy(bundled_map("seed000.yaml"), tmp_path / "seed000.yaml")
        spec.write_text("output: rows.csv\nmaps: [{path: seed000.yaml, resolution: 0.5}]\nplanners: [wavefront]\n")
        proc = subprocess.run([sys.executable, "-m", "gridfield", "sweep", str(spec), "--workers", "1"],
                              capture_output=True, text=True, timeout=120, env={**os.environ, "PYTHONPATH": str(ROOT)})
        assert proc.returncode == 2
        assert proc.stderr.count("\n") == 1 and "another sweep is writing" in proc.stderr
    finally:
        holder.close()
    assert _lines(out) == [",".join(COLUMNS)]  # nothing was written by the refused sweeps


def test_an_exception_in_one_run_becomes_its_error_row(tmp_path: Path, monkeypatch) -> None:
    import gridfield.planners

    real = gridfield.planners.plan

    def flaky(planner, target, start, goal, *a, **k):
        if tuple(start) == (2.0, 2.0):
            raise RuntimeError("a bug\nin a planner")
        return real(planner, target, start, goal, *a, **k)

    monkeypatch.setattr(gridfield.planners, "plan", flaky)
    shutil.copy(bundled_map("seed000.yaml"), tmp_path / "seed000.yaml")
    spec = tmp_path / "spec.yaml"
    spec.write_text("maps: [{path: seed000.yaml, resolution: 0.5, pairs: [[[1, 10], [22, 12]], [[2, 2], [22, 12]]]}]\n"
                    "planners: [wavefront]\n")
    runs, output = load_spec(spec)
    rows = run_sweep(runs, output, workers=1, progress=False)
    status = {(float(r["start_x"]), float(r["start_y"])): r["status"] for r in rows}
    assert status == {(1.0, 10.0): "reached", (2.0, 2.0): "error: RuntimeError: a bug in a planner"}


def _children(pid: int) -> list[int]:
    out = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                fields = (d / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                out.append(int(d.name))
    return out


def _gone(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return True
    return state in ("Z", "X")


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc to list the worker processes")
def test_sigterm_stops_the_workers_and_leaves_a_resumable_file(tmp_path: Path) -> None:
    shutil.copy(bundled_map("seed000.yaml"), tmp_path / "seed000.yaml")
    spec = tmp_path / "spec.yaml"
    spec.write_text("output: rows.csv\nmaps: [{path: seed000.yaml, resolution: 0.25, random_pairs: {n: 150, seed: 1}}]\n"
                    "planners: [potential]\n")
    out = tmp_path / "rows.csv"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-m", "gridfield", "sweep", str(spec), "--workers", "2", "--batch-size",
                             "1", "--no-progress"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and (not out.exists() or len(_lines(out)) < 4):
            time.sleep(0.05)
        workers = _children(proc.pid)
        assert workers, "no worker processes seen"
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 128 + signal.SIGTERM
    assert "stopped by SIGTERM" in err and "Traceback" not in err
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and not all(_gone(p) for p in workers):
        time.sleep(0.05)
    assert all(_gone(p) for p in workers)  # workers and the resource tracker
    written = len(_lines(out)) - 1
    assert 0 < written < 150
    assert main(["sweep", str(spec), "--workers", "1", "--no-progress"]) == 0
    lines = _lines(out)
    assert len(lines) == 151 and len(set(lines)) == 151


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc to list the worker processes")
def test_workers_of_a_killed_sweep_leave_with_it_and_the_file_resumes(tmp_path: Path) -> None:
    shutil.copy(bundled_map("seed000.yaml"), tmp_path / "seed000.yaml")
    spec = tmp_path / "spec.yaml"
    spec.write_text("output: rows.csv\nmaps: [{path: seed000.yaml, resolution: 0.5, random_pairs: {n: 120, seed: 2}}]\n"
                    "planners: [potential]\n")
    out = tmp_path / "rows.csv"
    proc = subprocess.Popen([sys.executable, "-m", "gridfield", "sweep", str(spec), "--workers", "2", "--batch-size",
                             "1", "--no-progress"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            env={**os.environ, "PYTHONPATH": str(ROOT)})
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and (not out.exists() or len(_lines(out)) < 4):
            time.sleep(0.02)
        workers = [p for p in _children(proc.pid) if "spawn_main" in Path(f"/proc/{p}/cmdline").read_text()]
        assert workers
        proc.kill()  # SIGKILL: nothing in the parent runs any more
        proc.wait(timeout=60)
    finally:
        proc.kill()
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and not all(_gone(p) for p in workers):
        time.sleep(0.1)
    assert all(_gone(p) for p in workers)
    assert main(["sweep", str(spec), "--workers", "1", "--no-progress"]) == 0
    lines = _lines(out)
    assert len(lines) == 121 and len(set(lines)) == 121


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc to find the worker processes")
def test_a_worker_killed_mid_sweep_is_replaced_and_no_row_is_lost(tmp_path: Path, monkeypatch) -> None:
    shutil.copy(bundled_map("seed000.yaml"), tmp_path / "seed000.yaml")
    spec = tmp_path / "spec.yaml"
    spec.write_text("maps: [{path: seed000.yaml, resolution: 0.5, random_pairs: {n: 40, seed: 5}}]\n"
                    "planners: [wavefront]\n")
    runs, _ = load_spec(spec)
    reference = run_sweep(runs, tmp_path / "reference.csv", workers=1, progress=False)
    killed: list[int] = []
    real_append = sweep_module._Journal.append

    def append_then_kill(self, row):
        if len(self.rows) == 3 and not killed:  # mid-sweep, from the parent: like the OOM killer
            workers = [p for p in _children(os.getpid()) if "spawn_main" in Path(f"/proc/{p}/cmdline").read_text()]
            os.kill(workers[0], signal.SIGKILL)
            killed.append(workers[0])
        return real_append(self, row)

    monkeypatch.setattr(sweep_module._Journal, "append", append_then_kill)
    rows = run_sweep(runs, tmp_path / "rows.csv", workers=2, batch_size=2, progress=False)
    assert killed
    lines = _lines(tmp_path / "rows.csv")
    assert len(lines) == len(runs) + 1 and len(set(lines)) == len(lines)

    def strip(rs):
        return sorted((r["start_x"], r["start_y"], r["goal_x"], r["goal_y"], r["status"], r["length"]) for r in rs)

    assert strip(rows) == strip(reference)


def _spec(tmp_path: Path, body: str) -> Path:
    shutil.copy(bundled_map("seed000.yaml"), tmp_path / "seed000.yaml")
    (tmp_path / "arena").mkdir(exist_ok=True)
    for name in ("arena.map", "arena.map.scen"):
        shutil.copy(bundled_map(f"arena/{name}"), tmp_path / "arena" / name)
    (tmp_path / "small.map").write_text("type octile\nheight 4\nwidth 5\nmap\n.....\n.....\n.....\n.....\n")
    spec = tmp_path / "spec.yaml"
    spec.write_text(body)
    return spec


W = "maps: [{path: seed000.yaml, resolution: 0.5}]\n"


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("planers: [potential]\n" + W, "unknown key 'planers'; did you mean 'planners'?"),
        ("output: 5\n" + W, "output: must be a file name, got 5"),
        ("maps: [5]", "maps[0]: expected a map file name or a mapping with 'path', got 5"),
        ("maps: [{path: seed000.yaml, resolution: 0.5, random_pair: {n: 2}}]", "did you mean 'random_pairs'?"),
        ("maps: [{path: seed000.yaml, resolution: 0.5, random_pairs: 5}]", "random_pairs: expected a mapping"),
        ("maps: [{path: seed000.yaml, resolution: 0.5, random_pairs: {n: many}}]",
         "random_pairs.n: must be an integer >= 1, got 'many'"),
        ("maps: [{path: seed000.yaml, resolution: 0.5, random_pairs: {n: -3}}]", "must be an integer >= 1, got -3"),
        ("maps: [{path: arena/arena.map, scenarios: arena/arena.map.scen, limit: abc}]",
         "limit: must be an integer >= 1, got 'abc'"),
        ("maps: [{path: seed000.yaml, resolution: -1}]", "resolution: must be a positive finite number, got -1"),
        ("maps: [{path: seed000.yaml, resolution: fine}]", "resolution: must be a positive finite number, got 'fine'"),
        (W + "params: {eta: -1}", "eta must be a finite number >= 0, got -1"),
        (W + "params: {kappa: [2, abc]}", "kappa must be a finite number > 0, got 'abc'"),
        (W + "params: {max_iterations: [10, '10']}", "max_iterations"),
        (W + "params: {eta: []}", "params.eta: an empty list of values gives no runs"),
        ("maps: [{path: small.map, scenarios: arena/arena.map.scen}]",
         "scenario 1 is for a 49 x 49 map (width x height), but small.map is 5 x 4 cells"),
        ("maps: [{path: arena/arena.map, pairs: [[[1.5, 1.5], [3.5, 3.5]]]}]\nplanners: [visibility, sphere-nav]",
         "planner 'sphere-nav' needs a vector world, but arena.map is a grid map"),
        (W + "optimal_any_angle: yes please", "optimal_any_angle must be true or false, got 'yes please'"),
        (W + "optimal_any_angle: 1", "optimal_any_angle must be true or false, got 1"),
        ("maps: [{path: seed000.yaml, resolution: 0.5, optimal_any_angle: 'true'}]",
         "maps[0]: optimal_any_angle must be true or false, got 'true'"),
        ("maps: [{path: seed000.yaml, resolution: 0.5, optimal_any_angel: true}]",
         "unknown key 'optimal_any_angel'; did you mean 'optimal_any_angle'?"),
        ("maps: [{path: seed000.yaml, resolution: 0.5, pairs: [[[1, 10], [22, .nan]]]}]", "pairs[0]: expected"),
        ("maps: [{path: seed000.yaml, resolution: 0.5, limit: 3}]", "limit: limits the scenarios"),
        ("maps: [{path: seed000.yaml, resolution: 0.00003}]", "cells would need about"),
        ("maps: [{path: seed000.yaml, resolution: '0.5'}]", "resolution: must be a positive finite number, got '0.5'"),
        (W + "params: {" + ", ".join(f"{k}: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]" for k in
                                     ("zeta", "eta", "q_star", "d_star", "step", "alpha", "tolerance", "ka", "kr"))
         + "}", "1e+09 combinations x 1 planners exceed 1e+08 runs"),
        ("maps: [{path: seed000.yaml, resolution: 0.5, random_pairs: {n: 1000000000}}]", "the spec expands to 1e+09 runs"),
    ],
)
def test_bad_specs_are_refused_before_anything_runs(tmp_path: Path, body: str, message: str, monkeypatch) -> None:
    monkeypatch.setenv("GRIDFIELD_MAX_CELLS", "1e8")
    spec = _spec(tmp_path, body)
    with pytest.raises(MapFormatError) as e:
        load_spec(spec)
    assert message in str(e.value)
    assert str(spec) in str(e.value)


def test_a_bad_spec_is_one_line_and_exit_2_from_the_command_line(tmp_path: Path, capsys) -> None:
    spec = _spec(tmp_path, W + "params: {kappa: [2, abc]}")
    assert main(["sweep", str(spec), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "kappa" in err
    assert not (tmp_path / "spec.csv").exists()


def test_an_unreachable_scheduler_is_one_line(tmp_path: Path, capsys) -> None:
    spec = _spec(tmp_path, W)
    assert main(["sweep", str(spec), "--scheduler", "nonsense://x", "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cannot connect to the Dask scheduler 'nonsense://x': unknown address scheme" in err
