"""`gridfield plan`: the JSON contract (README.md, ``plan --json``), parameter precedence and one-line errors."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from gridfield.cli import main
from gridfield.io import bundled_map, read_world
from gridfield.planners import plan

KEYS = {"planner", "status", "path", "end", "length", "iterations", "min_clearance", "params", "seconds",
        "field_seconds", "follow_seconds", "hint", "startup_seconds"}  # (+ "infinite" when a value is)
STATUSES = {"reached", "local_minimum", "collision", "max_iterations", "no_path"}


def _plan_json(capsys: pytest.CaptureFixture[str], *argv: str) -> dict:
    assert main(["plan", *argv, "--json"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert len(out) == 1, "plan --json prints exactly one line"
    return json.loads(out[0])


@pytest.mark.parametrize("planner", ["potential", "exact-potential", "visibility", "wavefront-octile"])
def test_plan_json_contract_on_seed000(capsys: pytest.CaptureFixture[str], planner: str) -> None:
    world = bundled_map("seed000.yaml")
    doc = _plan_json(capsys, str(world), "--planner", planner, "--resolution", "0.1")
    assert set(doc) - {"infinite"} == KEYS
    assert doc["planner"] == planner
    assert doc["status"] in STATUSES
    path = np.asarray(doc["path"], dtype=float)
    assert path.ndim == 2 and path.shape[1] == 2
    assert np.allclose(path[0], [1, 10], atol=0.1)  # starts at the world file's start
    assert doc["end"] == doc["path"][-1]
    # length is the polyline length of the returned path, not something else
    assert math.isclose(doc["length"], float(np.hypot(*np.diff(path, axis=0).T).sum()), rel_tol=1e-9)
    assert doc["seconds"] >= 0 and isinstance(doc["iterations"], int)
    # every planner gets around the three polygons of seed 000 (straight line is 21.1 long)
    assert doc["status"] == "reached"
    assert np.hypot(*(path[-1] - [22, 12])) <= 0.11
    assert doc["length"] > math.hypot(21, 2)


def test_command_line_parameters_override_the_world_file(capsys: pytest.CaptureFixture[str]) -> None:
    world = bundled_map("seed000.yaml")
    base = _plan_json(capsys, str(world), "--planner", "exact-potential")
    assert base["params"]["q_star"] == read_world(world).params["q_star"] == 2.0
    over = _plan_json(capsys, str(world), "--planner", "exact-potential", "--q-star", "1.5", "--param", "step=0.2")
    assert over["params"]["q_star"] == 1.5 and over["params"]["step"] == 0.2
    assert over["iterations"] < base["iterations"]  # twice the step, about half the steps


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--start", "-3", "10"], "start (-3, 10) lies outside"),
        (["--start", "8", "13"], "start (8, 13) lies inside"),
        (["--goal", "nan", "1"], "goal"),
        (["--planner", "exact-potential", "--step", "-1"], "step"),
        (["--param", "zetta=2"], "unknown parameter 'zetta'; did you mean 'zeta'?"),
        (["--param", "zeta"], "--param expects KEY=VALUE"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(capsys: pytest.CaptureFixture[str], argv: list[str], message: str) -> None:
    code = main(["plan", str(bundled_map("seed000.yaml")), "--resolution", "0.25", *argv])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1, err
    assert message in err


def test_missing_map_file(capsys: pytest.CaptureFixture[str], tmp_path) -> None:
    assert main(["plan", str(tmp_path / "nope.yaml"), "--start", "1", "1", "--goal", "2", "2"]) == 2
    err = capsys.readouterr().err
    assert "nope.yaml" in err and len(err.strip().splitlines()) == 1


def test_grid_map_without_endpoints_asks_for_them(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", str(bundled_map("arena/arena.map"))]) == 2
    assert "--start X Y" in capsys.readouterr().err


def test_plan_records_its_query_for_figures() -> None:
    """A Path from plan() carries its start and goal, so a figure of a stalled path still marks the goal."""
    path = plan("exact-potential", read_world(bundled_map("seed000_segment.yaml")), (1, 10), (22, 12))
    assert path.status == "local_minimum"
    assert path.extra["goal"] == (22.0, 12.0) and path.extra["start"] == (1.0, 10.0)
