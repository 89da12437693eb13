"""The size guard in bytes per job: each command and planner is sized by its measured peak bytes per
cell against the memory available (a sweep times its workers), a raised guard that runs out of
memory anyway is one line, and an empty ``GRIDFIELD_MAX_CELLS`` is refused like ``--max-cells``."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import gridfield.core.limits as limits
from gridfield.cli import main
from gridfield.core.errors import ParameterError, SizeLimitError
from gridfield.core.grid import Grid
from gridfield.io import bundled_map, write_npz

N = 200  # a 200 x 200 free map: 40000 cells


@pytest.fixture
def free_map(tmp_path: Path) -> Path:
    path = tmp_path / "free.npz"
    write_npz(path, {"occupied": np.zeros((N, N), bool)}, Grid((N, N), 1.0))
    return path


@pytest.fixture
def memory(monkeypatch: pytest.MonkeyPatch):
    """Set the memory the guard sees as available (bytes), with no user limit in force."""
    monkeypatch.delenv(limits.ENV_VAR, raising=False)

    def set_available(n: int | None) -> None:
        monkeypatch.setattr(limits, "available_memory", lambda: n)

    return set_available


def _plan(path: Path, planner: str, *extra: str) -> list[str]:
    return ["plan", str(path), "--planner", planner, "--start", "1.5", "1.5", "--goal", f"{N - 2}.5", f"{N - 2}.5",
            *extra]


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def test_each_planner_is_sized_by_its_own_bytes_per_cell(free_map: Path, memory, capsys) -> None:
    cells = N * N
    potential, wavefront = (limits.job_bytes_per_cell(f"plan:{p}") for p in ("potential", "wavefront-octile"))
    assert potential > wavefront
    # a budget between the two estimates: the wavefront plans, the potential planner is refused
    budget = (potential + wavefront) / 2 * cells
    memory(int(budget / limits.MEMORY_FRACTION))
    assert main(_plan(free_map, "wavefront-octile")) == 0
    capsys.readouterr()
    assert main(_plan(free_map, "potential")) == 2
    err = _one_line(capsys)
    assert f"{N} x {N} = {cells} cells" in err and "plan:potential" in err
    assert limits._bytes(potential * cells) in err  # the estimate ...
    assert limits._bytes(budget) in err  # ... the limit ...
    assert "--max-cells" in err and "GRIDFIELD_MAX_CELLS" in err  # ... and how to raise it
    # the user's own limit in cells replaces the estimate
    assert main(_plan(free_map, "potential", "--max-cells", "1e6")) == 0
    capsys.readouterr()


def test_commands_are_refused_before_the_map_is_loaded(free_map: Path, memory, monkeypatch, capsys) -> None:
    import gridfield.io._npz as npz

    memory(1000)  # 500 bytes of budget: every command is refused at the .npz header
    monkeypatch.setattr(np.lib.npyio.NpzFile, "__getitem__", lambda *a: pytest.fail("the array was loaded"))
    assert npz  # the reader checks the header before any array is read
    for argv in (["brushfire", str(free_map)], ["field", str(free_map), "--goal", "5", "5"],
                 ["info", str(free_map)], _plan(free_map, "fmm")):
        assert main(argv) == 2
        assert "more than the limit of" in _one_line(capsys)


def test_the_default_rule_is_the_stricter_of_cells_and_bytes(memory) -> None:
    memory(10**15)  # plenty of memory: the cell limit still holds
    with limits.job("plan:potential"), pytest.raises(SizeLimitError, match=r"more than the limit of \d+ cells"):
        limits.check_cells((limits.default_max_cells() + 1, 1), "grid")
    memory(None)  # memory unknown: the cell limit alone
    with limits.job("plan:potential"):
        assert limits.check_cells((1000, 1000), "grid") == 10**6


def test_a_sweep_is_sized_per_worker_times_workers(tmp_path: Path, memory, capsys) -> None:
    spec = tmp_path / "spec.yaml"
    seed = bundled_map("seed000.yaml")
    spec.write_text(f"maps: [{{path: {seed}, resolution: 0.25, pairs: [[[1, 10], [22, 12]]]}}]\n"
                    "planners: [wavefront-octile]\n")
    cells = 80 * 100
    per_worker = limits.job_bytes_per_cell("plan:wavefront-octile") * cells  # the spec's one planner
    memory(int(per_worker * 2.5 / limits.MEMORY_FRACTION))  # room for two workers, not for three
    assert main(["sweep", str(spec), "--workers", "3"]) == 2
    err = _one_line(capsys)
    assert "x 3 workers" in err and "fewer workers" in err and f"{cells} cells" in err
    assert not (tmp_path / "spec.csv").exists()
    assert main(["sweep", str(spec), "--workers", "2"]) == 0
    capsys.readouterr()
    assert (tmp_path / "spec.csv").exists()


def test_running_out_of_memory_under_a_raised_guard_is_one_line(monkeypatch, capsys) -> None:
    import gridfield.cli.info as info

    def boom(args):
        np.empty((10**7, 10**7), bool)  # 100 TB: numpy's _ArrayMemoryError (a MemoryError subclass)
        raise MemoryError("Unable to allocate 91 TiB")  # where the system would promise that much

    monkeypatch.setattr(info, "describe", boom)
    assert main(["info", str(bundled_map("seed000.yaml")), "--max-cells", "1e12"]) == 2
    err = _one_line(capsys)
    assert err.startswith("gridfield info: error: ") and "out of memory" in err and "Unable to allocate" in err


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="relies on Linux refusing a 40 TB allocation")
@pytest.mark.parametrize("how", ["option", "env"])
def test_a_real_huge_allocation_under_a_raised_guard_names_the_grid(how: str, monkeypatch, capsys) -> None:
    overcommit = Path("/proc/sys/vm/overcommit_memory")
    if overcommit.exists() and overcommit.read_text().strip() == "1":
        pytest.skip("overcommit_memory=1 would accept the allocation")
    argv = ["info", str(bundled_map("seed000.yaml")), "--resolution", "0.00001"]
    if how == "option":
        argv += ["--max-cells", "1e13"]
    else:
        monkeypatch.setenv(limits.ENV_VAR, "1e13")
    assert main(argv) == 2
    err = _one_line(capsys)
    assert "out of memory" in err and "2000000 x 2500000" in err  # the grid that was being built


def test_sweep_runs_that_run_out_of_memory_get_a_clear_status(monkeypatch) -> None:
    import gridfield.planners
    from gridfield.sweep import Run, run_one

    def boom(*a, **k):
        raise MemoryError("Unable to allocate 8.00 GiB for an array")

    monkeypatch.setattr(gridfield.planners, "plan", boom)
    row = run_one(Run(str(bundled_map("seed000.yaml")), 0.5, "potential", (), (1.0, 10.0), (22.0, 12.0)))
    assert row["status"].startswith("error: potential on seed000.yaml at resolution 0.5: out of memory")
    assert "MemoryError:" not in row["status"] and math.isnan(row["length"])


@pytest.mark.parametrize("value", ["", " ", "lots", "0", "-5", "nan", "inf"])
def test_an_empty_or_junk_environment_limit_is_refused_like_the_option(value: str, monkeypatch, capsys) -> None:
    monkeypatch.setenv(limits.ENV_VAR, value)
    with pytest.raises(ParameterError, match=f"{limits.ENV_VAR} must be a positive number of cells, got {value!r}"):
        limits.max_cells()
    assert main(["info", str(bundled_map("arena/arena.map"))]) == 2
    assert f"{limits.ENV_VAR} must be a positive number of cells" in _one_line(capsys)
    assert main(["info", str(bundled_map("arena/arena.map")), "--max-cells", value or "''"]) == 2
    assert "--max-cells must be a positive number of cells" in _one_line(capsys)
