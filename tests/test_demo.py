"""``gridfield demo``: the files and the summary rows it writes (quick mode)."""

from __future__ import annotations

import csv
import re
import time

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import pytest
from PIL import Image

from gridfield.cli import main
from gridfield.core.errors import GridfieldError
from gridfield.demo import DEMO_PARTS, SUMMARY_COLUMNS, crop_to_known, demo, format_table, run_demo
from gridfield.io import bundled_map, read_ros_map

PNG = b"\x89PNG\r\n\x1a\n"
@pytest.fixture(scope="module")
def quick_demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    lines: list[str] = []
    plt.close("all")  # figures an earlier test of this worker left open are not the demo's
    t0 = time.perf_counter()
    result = demo(out, quick=True, log=lines.append)
    seconds = time.perf_counter() - t0
    yield result, lines, seconds
    plt.close("all")


#: Every file the demo writes: a fixed list (a part that silently went missing fails here).
EXPECTED_FILES = {
    "maps.png", "summary.md", "summary.csv", "seed000_paths.png", "seed000_segment_potential.png",
    "seed000_surface.png", "seed000_segment_basins.png", "seed000_segment_follower.gif", "seed003_vortex.png",
    "turtlebot3.png", "arena.png", "arena_classic_vs_complete.png", "convergence.png", "seed002_star_world.png", "moving_obstacle.gif",
}


def expected_files() -> set[str]:
    return set(EXPECTED_FILES)


def test_demo_writes_the_expected_files(quick_demo):
    result, _, seconds = quick_demo
    names = {f.name for f in result.files}
    assert names == expected_files()
    for f in result.files:
        assert f.parent == result.out_dir and f.is_file() and f.stat().st_size > 0
        if f.suffix == ".png":
            assert f.read_bytes()[:8] == PNG
            with Image.open(f) as im:
                assert im.size[0] >= 400
        if f.suffix == ".gif":
            assert f.read_bytes()[:6] == b"GIF89a"
            with Image.open(f) as im:
                assert 2 <= im.n_frames <= 30
    assert plt.get_fignums() == []
    # no wall-time bound here: the quick demo takes about 22 s on an idle 2-core machine and over 60 s
    # when other jobs share it (a time limit in a unit test fails on load, not on a bug)
    assert seconds > 0


def test_demo_summary_rows(quick_demo):
    result, _, _ = quick_demo
    rows = result.rows
    for r in rows:
        assert tuple(r) == SUMMARY_COLUMNS
        assert r["status"] in ("reached", "local_minimum", "collision", "max_iterations", "no_path")
        assert r["length"] >= 0 and r["steps"] >= 0 and r["ms"] >= 0
    by = {(r["map"], r["planner"]): r for r in rows}
    # the published outcomes: seed 000 reaches, its segment variant stalls near (16.97, 9.028)
    assert by[("seed000", "potential")]["status"] == "reached"
    seg = by[("seed000_segment", "potential")]
    assert seg["status"] == "local_minimum" and "stalls at (16.9" in seg["note"]
    assert by[("seed000", "exact-potential")]["status"] == "reached"
    # the model column: the seed worlds ask for the classic field, the grid maps run the default nf1
    assert by[("seed000", "potential")]["model"] == "khatib" and by[("turtlebot3", "potential")]["model"] == "nf1"
    assert by[("arena", "wavefront-octile")]["model"] == "" and by[("star_two", "star-nav")]["model"] == ""
    assert by[("seed000_segment", "exact-potential")]["status"] == "local_minimum"
    # seed 003: Ko = 5 converges, Ko = 10 does not
    assert by[("seed003 Ko=5", "potential")]["status"] == "reached"
    assert by[("seed003 Ko=10", "potential")]["status"] != "reached"
    assert ("turtlebot3", "potential") in by and ("arena", "potential") in by
    for name in ("turtlebot3", "arena"):
        assert by[(name, "wavefront-octile")]["status"] == "reached"
    # the arena wavefront path is the scenario's optimal octile length
    arena = by[("arena", "wavefront-octile")]
    optimal = float(arena["note"].split("optimal ")[1].split(";")[0])
    assert arena["length"] == pytest.approx(optimal, abs=1e-3)
    # the grid maps run with the defaults, and a stall carries the hint and its navigation escape
    assert "default parameters" in by[("turtlebot3", "potential")]["note"]
    arena_rows = [r for r in rows if r["map"] == "arena" and r["planner"] == "potential"]
    if arena_rows[0]["status"] != "reached":
        assert "hint:" in arena_rows[0]["note"] and arena_rows[1]["status"] == "reached"


def test_demo_summary_files_match_the_rows(quick_demo):
    result, _, _ = quick_demo
    with (result.out_dir / "summary.csv").open(newline="") as fh:
        table = list(csv.DictReader(fh))
    assert [tuple(r) for r in table] == [SUMMARY_COLUMNS] * len(table)
    assert [r["planner"] for r in table] == [r["planner"] for r in result.rows]
    assert [r["status"] for r in table] == [r["status"] for r in result.rows]
    md = (result.out_dir / "summary.md").read_text()
    assert md.startswith("# gridfield demo")
    assert "| part" in md and "![maps](maps.png)" in md
    assert result.skipped == []


def _table_cells(line: str) -> list[str]:
    """The cells of a Markdown table row (split at the pipes that are not escaped)."""
    return [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]


def _listed(text: str) -> dict[int, str]:
    """The items of the numbered lists of a Markdown text, by number, their wrapped lines joined."""
    items = re.findall(r"^(\d+)\. (.*(?:\n {3,}\S.*)*)", text, flags=re.M)
    return {int(n): " ".join(item.split()) for n, item in items}


def test_demo_summary_md_reads_well_in_a_terminal_and_a_renderer(quick_demo):
    """summary.md's table pads no column to the longest hint (it did: every row was 500 characters wide): the
    notes are listed under it, numbered, wrapped; the table is one valid GitHub table of the summary's rows."""
    result, _, _ = quick_demo
    md = (result.out_dir / "summary.md").read_text(encoding="utf-8")
    lines = md.splitlines()
    assert [line for line in lines if len(line) > 120] == []
    table = [line for line in lines if line.startswith("|")]
    start = lines.index(table[0])
    assert lines[start:start + len(table)] == table  # one block
    assert {len(re.findall(r"(?<!\\)\|", line)) for line in table} == {len(SUMMARY_COLUMNS) + 1}
    assert _table_cells(table[0]) == list(SUMMARY_COLUMNS)
    assert re.fullmatch(r"\|(-+\|)+", table[1])
    rows = [_table_cells(line) for line in table[2:]]
    assert len(rows) == len(result.rows) and max(len(c) for row in rows for c in row) <= 60
    listed = _listed(md)
    note = SUMMARY_COLUMNS.index("note")
    for cells, r in zip(rows, result.rows, strict=True):
        assert cells[SUMMARY_COLUMNS.index("planner")] == r["planner"]
        if r["note"]:
            n = int(cells[note].removeprefix("see "))
            assert listed[n] == " ".join(f"{r['map']}, {r['planner']}: {r['note']}".split())
        else:
            assert cells[note] == ""
    assert any(len(r["note"]) > 200 for r in result.rows)  # a hint: what used to pad the column


def test_format_table_lists_long_text_under_the_table():
    from gridfield.demo import wrap_item

    rows = [{"map": "m", "planner": "p", "status": "x" * 70, "note": "a|b " + "word - " * 40},
            {"map": "n", "planner": "q", "status": "reached", "note": ""}]
    text = format_table(rows, ("map", "planner", "status", "note"))
    lines = text.splitlines()
    assert _table_cells(lines[2]) == ["m", "p", "see 1", "see 2"] and _table_cells(lines[3]) == ["n", "q", "reached", ""]
    assert _listed(text) == {1: f"m, p: {'x' * 70}", 2: " ".join(f"m, p: a|b {'word - ' * 40}".split())}
    assert max(map(len, lines)) <= 100
    # a wrapped line never starts with what would open a Markdown block (a list item)
    assert not any(line.lstrip().startswith("- ") for line in lines[5:])
    assert format_table([{"map": "a|b"}], ("map",)).splitlines()[2] == "| a\\|b |"
    assert wrap_item("x " * 3, "- ", width=4) == "- x\n  x\n  x"


def test_demo_logs_each_part_and_the_warm_up(quick_demo):
    _result, lines, _ = quick_demo
    for part in DEMO_PARTS:
        assert any(line.startswith(f"{part}:") for line in lines), part
    assert lines[0].startswith("warm-up:") and "not part of any time" in lines[0]


def test_run_demo_returns_rows_for_a_subset(tmp_path):
    rows = run_demo(tmp_path, quick=True, parts=["maps"])
    assert rows == []
    assert (tmp_path / "maps.png").read_bytes()[:8] == PNG
    assert (tmp_path / "summary.md").is_file()


def test_demo_errors(tmp_path):
    with pytest.raises(GridfieldError, match="unknown demo part"):
        demo(tmp_path, parts=["everything"])
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(GridfieldError, match="not a folder"):
        demo(f)


def test_cli_demo_prints_the_table_and_where_the_files_are(tmp_path, capsys):
    out = tmp_path / "d"
    assert main(["demo", "--out", str(out), "--quick", "--part", "maps", "--part", "seed003"]) == 0
    text = capsys.readouterr().out
    assert "| part" in text and "wrote" in text and str(out.resolve()) in text
    assert (out / "maps.png").is_file()
    assert "seed003 Ko=5" in text and (out / "seed003_vortex.png").is_file()


def test_format_table_and_crop():
    assert format_table([]).splitlines()[0].startswith("| part")
    gm = read_ros_map(bundled_map("turtlebot3_world/map.yaml"))
    c = crop_to_known(gm)
    assert c.shape[0] < gm.shape[0] and c.shape[1] < gm.shape[1]
    assert (~c.occupied).sum() == (~gm.occupied).sum()  # every free cell kept
    assert c.grid.resolution == gm.grid.resolution


def test_demo_parts_draw_the_fields_their_plans_built(tmp_path, monkeypatch):
    """seed003 plans twice (Ko 5 and 10) and draws both fields: two builds, not four."""
    import gridfield.demo._parts as demo_parts
    import gridfield.fields.potential as potential

    calls = []
    real = potential.build_field

    def counting(*a, **k):
        calls.append(1)
        return real(*a, **k)

    monkeypatch.setattr(potential, "build_field", counting)
    run = demo_parts._Run(tmp_path, True, lambda _line: None)
    demo_parts._part_seed003(run)
    plt.close("all")
    assert len(calls) == 2 and len(run.result.rows) == 2
    assert (tmp_path / "seed003_vortex.png").read_bytes()[:8] == PNG


def test_arena_shows_the_classic_stall_next_to_the_complete_field(tmp_path, monkeypatch):
    """issue 25: on the arena the classic field (model: khatib) stalls and the complete one (nf1)
    reaches; one figure, two panels, checked on its artists against the scenario file's goal."""
    import numpy as np

    import gridfield.demo._parts as demo_parts
    from gridfield.io import read_movingai_map, read_scen

    figures = {}
    run = demo_parts._Run(tmp_path, True, lambda _line: None)
    monkeypatch.setattr(run, "save", lambda fig, name: figures.setdefault(name, fig))
    demo_parts._part_arena(run)
    gm = read_movingai_map(bundled_map("arena/arena.map"))
    scen = read_scen(bundled_map("arena/arena.map.scen"), map_height=gm.shape[0])
    i = int(np.argmax(scen.optimal))
    goal = scen.goal_xy[i]
    try:
        fig = figures["arena_classic_vs_complete.png"]
        axes = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
        assert len(axes) == 2
        classic, complete = axes
        assert "khatib" in classic.get_title() and "local_minimum" in classic.get_title()
        assert "nf1" in complete.get_title() and "reached" in complete.get_title()
        # the stall marker: drawn inside the classic panel's axes, away from the goal; none on the other
        stalls = [c for c in classic.collections if c.get_label() == "stall point"]
        assert len(stalls) == 1
        (x, y), = stalls[0].get_offsets().tolist()
        x0, x1 = classic.get_xlim()
        y0, y1 = classic.get_ylim()
        assert x0 < x < x1 and y0 < y < y1
        assert np.hypot(x - goal[0], y - goal[1]) > 1.0
        assert not [c for c in complete.collections if c.get_label() == "stall point"]
        assert any(t.get_text().startswith("hint:") for t in classic.texts)
        # the complete run's path ends at the goal, the classic one's does not
        (line,) = [ln for ln in complete.get_lines() if ln.get_label().startswith("potential")]
        end = np.array([line.get_xdata()[-1], line.get_ydata()[-1]], float)
        assert np.hypot(*(end - goal)) <= 0.5
        (line,) = [ln for ln in classic.get_lines() if ln.get_label().startswith("potential")]
        end = np.array([line.get_xdata()[-1], line.get_ydata()[-1]], float)
        assert np.hypot(*(end - goal)) > 1.0
    finally:
        for f in figures.values():
            plt.close(f)
    # the table: both runs, with status, length and model
    rows = {r["model"]: r for r in run.result.rows if r["planner"] == "potential"}
    assert rows["khatib"]["status"] == "local_minimum" and "hint:" in rows["khatib"]["note"]
    assert rows["nf1"]["status"] == "reached" and rows["nf1"]["length"] > 0
    assert any("khatib" in n and "nf1" in n for n in run.result.notes)
