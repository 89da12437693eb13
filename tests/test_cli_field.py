"""`gridfield field --planner`: the navigation functions' fields through the field command."""

from __future__ import annotations

import numpy as np
import pytest

from gridfield.cli import main
from gridfield.fields.potential import Field
from gridfield.following.follower import basins
from gridfield.io import bundled_map, read_npz_arrays


def _field_from_npz(path) -> Field:
    from gridfield.core.grid import GridMap

    arrays, grid = read_npz_arrays(path)
    return Field(GridMap(grid, arrays["occupied"]), arrays["potential"], arrays["grad_x"], arrays["grad_y"],
                 goal=(0.0, 0.0), params={})


@pytest.mark.parametrize("planner", ["wavefront-octile", "harmonic", "fmm"])
def test_navigation_functions_have_one_basin_where_the_potential_field_has_several(tmp_path, capsys, planner):
    world = str(bundled_map("seed000_segment.yaml"))
    assert main(["field", world, "--resolution", "0.25", "--npz", str(tmp_path / "pot.npz")]) == 0
    assert main(["field", world, "--resolution", "0.25", "--planner", planner,
                 "--npz", str(tmp_path / "nav.npz")]) == 0
    assert f"{planner} navigation function" in capsys.readouterr().out
    pot, nav = _field_from_npz(tmp_path / "pot.npz"), _field_from_npz(tmp_path / "nav.npz")
    assert len(basins(pot).minima) > 1  # the segment traps the potential field (seed 000)
    b = basins(nav)
    free = ~nav.map.occupied & np.isfinite(nav.potential)
    assert len(b.minima) == 1 and np.all(b.label[free] == 1)  # complete: every free cell descends to the goal


def test_field_planner_choices_are_checked(capsys):
    assert main(["field", str(bundled_map("seed000.yaml")), "--planner", "teleport"]) == 2
    assert "invalid choice: 'teleport'" in capsys.readouterr().err


@pytest.mark.parametrize(("args", "split"), [
    ([], False),                                   # the default complete model: its brushfire is inside the build
    (["--param", "model=khatib"], True),           # the classic field: the brushfire is computed and timed apart
    (["--planner", "wavefront-octile"], False),
])
def test_field_times_the_brushfire_apart_only_where_it_is_computed_apart(args, split, capsys):
    # nf1 printed "(brushfire 0.0 ms, potential N ms)" though its build computed the brushfire
    assert main(["field", str(bundled_map("arena/arena.map")), "--goal", "45.5", "3.5", *args]) == 0
    out = capsys.readouterr().out
    assert ("(brushfire " in out) == split and ("(its distance maps included)" in out) == (not split), out
    assert "brushfire 0.0 ms" not in out
