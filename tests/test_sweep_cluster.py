"""Sweeps on a real (process) Dask cluster: maps travel with the tasks, runs go in batches per map, and a
worker killed mid-sweep costs no row and duplicates none."""

from __future__ import annotations

import os
import shutil
import signal
from pathlib import Path

import gridfield.sweep as sweep_module
from gridfield.io import bundled_map
from gridfield.sweep import load_spec, run_sweep

SPEC = """
output: rows.csv
maps:
  - path: seed000.yaml
    resolution: 0.5
    random_pairs: {n: 8, seed: 3}
  - path: arena/arena.map
    scenarios: arena/arena.map.scen
    limit: 8
planners: [wavefront-octile]
params:
  q_star: [1.0, 2.0]
"""


def _strip(rows: list[dict]) -> list[tuple]:
    return sorted((r["map"], r["planner"], r["params"], r["start_x"], r["start_y"], r["goal_x"], r["goal_y"],
                   r["status"], r["length"], r["steps"]) for r in rows)


def test_a_process_cluster_without_the_map_files_gives_every_row_once_despite_a_killed_worker(
        tmp_path: Path, monkeypatch) -> None:
    import distributed

    data, elsewhere = tmp_path / "data", tmp_path / "elsewhere"
    (data / "arena").mkdir(parents=True)
    elsewhere.mkdir()
    shutil.copy(bundled_map("seed000.yaml"), data / "seed000.yaml")
    for name in ("arena.map", "arena.map.scen"):
        shutil.copy(bundled_map(f"arena/{name}"), data / "arena" / name)
    (data / "spec.yaml").write_text(SPEC)
    monkeypatch.chdir(data)
    runs, _ = load_spec("spec.yaml")
    assert {r.map for r in runs} == {"seed000.yaml", "arena/arena.map"}  # relative: only the submitter can open them
    local = run_sweep(runs, data / "local.csv", workers=1, progress=False)

    # every worker (and any worker restarted after a crash) runs in a folder without the maps
    preload = tmp_path / "chdir_elsewhere.py"
    preload.write_text(f"import os\n\ndef dask_setup(worker):\n    os.chdir({str(elsewhere)!r})\n")
    killed: list[int] = []
    real_append = sweep_module._Journal.append

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                                  preload=[str(preload)], local_directory=str(elsewhere)) as cluster, \
            distributed.Client(cluster) as client:
        assert set(client.run(os.getcwd).values()) == {str(elsewhere)}
        pids = sorted(client.run(os.getpid).values())

        def append_then_kill(self, row):
            written = real_append(self, row)
            if len(self.rows) == 3 and not killed:  # mid-sweep: the other results still sit on the workers
                os.kill(pids[0], signal.SIGKILL)
                killed.append(pids[0])
            return written

        monkeypatch.setattr(sweep_module._Journal, "append", append_then_kill)
        submitted: list[int] = []
        real_submit = client.submit
        monkeypatch.setattr(client, "submit", lambda *a, **k: submitted.append(1) or real_submit(*a, **k))
        remote = run_sweep(runs, data / "remote.csv", scheduler=client, progress=False, batch_size=4)
    assert killed
    assert len(submitted) == len(runs) // 4  # batches per map, not one task per run
    lines = (data / "remote.csv").read_text().splitlines()
    assert len(lines) == len(runs) + 1 and len(set(lines)) == len(lines)
    assert all(r["status"] == "reached" for r in remote)
    assert _strip(remote) == _strip(local)
