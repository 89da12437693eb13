"""Command-line details a newcomer meets: "did you mean" for a misspelt flag, a start whose coarse cell
is blocked (not "inside an obstacle"), start-up time apart from the plan's, no strings for numbers in
the JSON, and MP4 animations without a system ffmpeg (the ``[video]`` extra) or a message naming it."""

from __future__ import annotations

import json
import re
import sys

import pytest

from gridfield.cli import main
from gridfield.io import bundled_map


def test_misspelt_flag_gets_did_you_mean(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", str(bundled_map("seed000.yaml")), "--planer", "fmm"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "unrecognized arguments: --planer fmm" in err and "did you mean --planner?" in err
    assert err.startswith("gridfield plan: error:") and "gridfield plan --help" in err


def test_two_misspelt_flags_each_get_theirs(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["brushfire", str(bundled_map("seed000.yaml")), "--metrc", "euclidean", "--conectivity", "4"]) == 2
    err = capsys.readouterr().err
    assert "--metrc: did you mean --metric?" in err and "--conectivity: did you mean --connectivity?" in err


@pytest.mark.parametrize(("words", "hint"), [
    (["--model", "khatib"], "did you mean --param model=khatib?"),
    (["--clearance-band=0"], "did you mean --param clearance_band=0?"),
    (["--attraction"], "did you mean --param attraction=VALUE?"),
])
def test_a_parameter_given_as_a_flag_is_pointed_to_param(words, hint, capsys: pytest.CaptureFixture[str]) -> None:
    # a newcomer writes --model khatib (README: "the classic field is one flag away"); it was answered
    # "did you mean --help?"
    assert main(["plan", str(bundled_map("seed000.yaml")), *words]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and hint in err, err
    # and the hint works
    key, value = hint.split("--param ")[1].rstrip("?").split("=")
    if value != "VALUE":
        assert main(["plan", str(bundled_map("seed000.yaml")), "--param", f"{key}={value}", "--json"]) == 0
        assert json.loads(capsys.readouterr().out)["params"][key] == (float(value) if key == "clearance_band" else value)


def test_a_blocked_coarse_cell_is_not_called_an_obstacle(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", str(bundled_map("seed000.yaml")), "--resolution", "5"]) == 2
    err = capsys.readouterr().err
    assert "inside an obstacle" not in err
    assert "start (1, 10) is free, but its cell of the 5 grid is blocked" in err and "finer --resolution" in err


def test_plan_prints_start_up_apart(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", str(bundled_map("seed000.yaml")), "--resolution", "0.2", "--planner", "wavefront"]) == 0
    line = capsys.readouterr().out.splitlines()[0]
    assert re.search(r", [0-9.]+ ms \(\+ [0-9]+ ms start-up\)$", line), line


def _strings_for_numbers(v: object, where: str = "") -> list[str]:
    if isinstance(v, str):
        return [where] if v.strip().lower().lstrip("+-") in ("inf", "infinity", "nan") else []
    if isinstance(v, dict):
        return [w for k, x in v.items() for w in _strings_for_numbers(x, f"{where}.{k}")]
    if isinstance(v, list):
        return [w for i, x in enumerate(v) for w in _strings_for_numbers(x, f"{where}[{i}]")]
    return []


def test_plan_json_has_no_strings_for_numbers(capsys: pytest.CaptureFixture[str]) -> None:
    # seed000_segment's params give d_star: inf
    assert main(["plan", str(bundled_map("seed000_segment.yaml")), "--planner", "wavefront", "--json",
                 "--resolution", "0.2"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert _strings_for_numbers(doc) == []
    assert doc["params"]["d_star"] is None and doc["infinite"] == {"params.d_star": 1}
    assert isinstance(doc["startup_seconds"], float) and doc["startup_seconds"] >= 0


def test_mp4_without_ffmpeg_names_the_extra(tmp_path, monkeypatch, capsys) -> None:
    import matplotlib

    monkeypatch.setitem(matplotlib.rcParams, "animation.ffmpeg_path", str(tmp_path / "no-ffmpeg"))
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)  # not installed
    assert main(["plan", str(bundled_map("seed000.yaml")), "--resolution", "0.5", "--animate",
                 str(tmp_path / "a.mp4")]) == 2
    err = capsys.readouterr().err
    assert "gridfield[video]" in err and len(err.strip().splitlines()) == 1


def test_mp4_with_the_video_extra(tmp_path, monkeypatch) -> None:
    pytest.importorskip("imageio_ffmpeg")
    import matplotlib
    import numpy as np

    from gridfield.core.grid import Grid, GridMap
    from gridfield.core.path import Path
    from gridfield.plot import save_plan_animation

    monkeypatch.setitem(matplotlib.rcParams, "animation.ffmpeg_path", str(tmp_path / "no-ffmpeg"))  # no system one
    gm = GridMap(Grid((8, 8), 1.0), np.zeros((8, 8), bool))
    path = Path(np.array([[0.5, 0.5], [3.5, 3.5], [7.5, 7.5]]), "reached", "demo")
    out = save_plan_animation(tmp_path / "a.mp4", gm, path, max_frames=3, dpi=40)
    assert out.read_bytes()[4:8] == b"ftyp"  # an MP4 container, written with imageio-ffmpeg's binary
