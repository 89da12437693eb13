"""The commands on a voxel map where a 2-D-only part is asked for: one line on stderr, exit code 2."""

from __future__ import annotations

import pytest

from gridfield.cli import main

from mapdata import TEST_MAPS

CAVE = str(TEST_MAPS / "voxel" / "cave.3dmap.gz")


@pytest.mark.parametrize("argv", [
    ["brushfire", CAVE, "--chunks", "16", "--out", "{tmp}/d.zarr"],
    ["field", CAVE, "--goal", "5.5", "5.5", "5.5", "--chunks", "16", "--out", "{tmp}/f.zarr"],
    ["plan", CAVE, "--start", "5.5", "5.5", "--goal", "5.5", "5.5", "5.5"],
    ["plan", CAVE, "--start", "5.5", "5.5", "5.5", "--goal", "30.5", "30.5", "10.5", "--planner", "visibility"],
    ["plan", CAVE, "--robot-radius", "0.5", "--headings", "8", "--start", "5.5", "5.5", "0", "--goal", "9", "9"],
])
def test_voxel_map_refuses_what_is_2d_only(argv, tmp_path, capsys):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "error:" in err[0] and "Traceback" not in err[0], err
    assert not list(tmp_path.iterdir())  # nothing written
