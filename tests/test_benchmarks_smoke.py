"""Smoke tests of the benchmark suite: each script's ``main`` runs on tiny sizes and prints its table.

No timing is asserted (these are not benchmarks). Peers and OpenCV live in the ``[bench]``
extra: where they are not installed the scripts report them as missing, which is what these
tests then check instead.
"""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parent.parent / "benchmarks"


@pytest.fixture(scope="module")
def bench_modules():
    """benchmarks/run.py, end_to_end.py and peers.py imported as modules."""
    sys.path.insert(0, str(BENCH))
    try:
        import end_to_end
        import peers
        import run

        yield run, end_to_end, peers
    finally:
        sys.path.remove(str(BENCH))


def test_end_to_end_main_tiny(bench_modules, capsys):
    _, end_to_end, _ = bench_modules
    assert end_to_end.main(["--sizes", "48", "--repeat", "1", "--no-tracemalloc"]) == 0
    out = capsys.readouterr().out
    assert "| 48^2 |" in out
    assert "peak RSS" in out


def test_synthetic_map_is_the_same_world_at_every_size(bench_modules):
    _, end_to_end, _ = bench_modules
    small, large = end_to_end.synthetic_occupancy(64), end_to_end.synthetic_occupancy(256)
    assert abs(small.mean() - large.mean()) < 0.02
    gm = end_to_end.synthetic_map(64)
    assert gm.is_free([end_to_end.START, end_to_end.GOAL]).all()


def test_peers_main_tiny(bench_modules, capsys):
    _, _, peers = bench_modules
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # third-party peers' own deprecation warnings
        assert peers.main(["--repeat", "1", "--scale", "0.1"]) == 0
    out = capsys.readouterr().out
    for peer in ("RTB DistanceTransformPlanner", "python-motion-planning AStar", "APF", "cell-by-cell"):
        assert peer in out
    # the cell-by-cell reference needs nothing but gridfield: it always runs and agrees
    line = next(x for x in out.splitlines() if "cell-by-cell" in x)
    assert "max relative |dU|" in line


def test_cell_by_cell_reference_matches_gridfield(bench_modules):
    _, _, peers = bench_modules
    import numpy as np

    from gridfield.core.grid import Grid, GridMap
    from gridfield.fields.potential import build_field

    res, obstacles, goal = 1.0, [(2.5, 3.5)], (8.5, 6.5)
    ref = np.asarray(peers.cell_by_cell_potential(10, 8, res, goal, obstacles, 1.0, 2.0, 3.0)).T
    occ = np.zeros((8, 10), bool)
    occ[3, 2] = True
    field = build_field(GridMap(Grid((8, 10), res), occ), goal, {"zeta": 1.0, "d_star": math.inf, "eta": 2.0, "q_star": 3.0})
    np.testing.assert_allclose(ref[~occ], field.potential[~occ], rtol=1e-12)
    assert np.isinf(ref[3, 2])


def test_run_main_tiny(bench_modules, tmp_path, capsys):
    run, _, _ = bench_modules
    out_file = tmp_path / "results.md"
    code = run.main(["--quick", "--only", "startup", "components", "--sizes", "48", "--repeat", "1",
                     "--startup-repeat", "1", "--out", str(out_file)])
    assert code == 0
    text = out_file.read_text()
    assert "## Targets" in capsys.readouterr().out  # the report goes to stdout too
    for heading in ("# gridfield benchmark results", "## Targets", "## Start-up", "## Components side by side"):
        assert heading in text
    assert "`gridfield --help`" in text
    assert "| Euclidean distance map |" in text


def test_run_reports_missing_area_script(bench_modules):
    run, _, _ = bench_modules
    results: dict = {}
    lines = run.section_areas(quick=True, repeat=1, timeout=10, results=results, scripts=["no_such_area"])
    assert results["areas"] == {"no_such_area": "missing"}
    assert any("**missing**" in x for x in lines)


def test_importtime_parsing(bench_modules):
    run, _, _ = bench_modules
    text = "\n".join([
        "import time: self [us] | cumulative | imported package",
        "import time:       10 |         10 |     shapely.lib",
        "import time:       20 |         30 |   shapely",
        "import time:        5 |         35 | gridfield.geometry.world",
    ])
    records = run.parse_importtime(text)
    assert [r.depth for r in records] == [2, 1, 0]
    assert run.import_chain(records, 0) == ["gridfield.geometry.world", "shapely", "shapely.lib"]


# ----------------------------------------------------------------------------------------------
# benchmarks/potential_real.py (issue 12): the potential planner on Moving AI and ROS maps
# ----------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def potential_real():
    sys.path.insert(0, str(BENCH))
    try:
        import potential_real

        yield potential_real
    finally:
        sys.path.remove(str(BENCH))


def _two_room_ros_root(tmp_path: Path) -> Path:
    """A maps root: the bundled 49x49 arena (Moving AI) and a 20x16 ROS map split by a wall at column 9."""
    import shutil

    import numpy as np

    from gridfield.core.grid import Grid, GridMap
    from gridfield.io import write_ros_map

    root = tmp_path / "maps"
    arena = root / "movingai" / "arena"
    arena.mkdir(parents=True)
    for f in ("arena.map", "arena.map.scen"):
        shutil.copy(BENCH.parent / "maps" / "arena" / f, arena / f)
    occ = np.zeros((16, 20), bool)
    occ[[0, -1], :] = occ[:, [0, -1]] = True
    occ[:, 9] = True  # two rooms: columns 1-8 and 10-18
    occ[5:8, 4:6] = True
    (root / "ros_maps" / "two_rooms").mkdir(parents=True)
    write_ros_map(root / "ros_maps" / "two_rooms" / "map.yaml", GridMap(Grid((16, 20), 0.05, (-1.0, 2.0)), occ))
    return root


def test_ros_pairs_components(potential_real):
    import numpy as np

    free = np.ones((6, 9), bool)
    free[:, 4] = False  # columns 0-3 and 5-8
    pairs = potential_real.ros_pairs(free, 12, "same", 3)
    assert len(pairs) == 15
    for s, g, kind in pairs:
        assert free[s] and free[g] and s != g
        assert kind == ("reachable" if (s[1] < 4) == (g[1] < 4) else "unreachable")
    assert [k for _, _, k in pairs] == ["reachable"] * 12 + ["unreachable"] * 3
    assert pairs == potential_real.ros_pairs(free, 12, "same", 3)  # deterministic
    assert potential_real.ros_pairs(np.ones((3, 3), bool), 2, "any", 5)[2:] == []  # one component: no extra


def test_movingai_sample_spreads_over_buckets(potential_real):
    import numpy as np

    bucket = np.repeat(np.arange(10), 7)
    no_path = np.zeros(70, bool)
    no_path[33] = True
    idx = potential_real.movingai_sample(bucket, no_path, 10)
    assert idx[0] == 0 and idx[-1] == 69 and 33 in idx
    assert sorted(set(bucket[idx].tolist())) == list(range(10))


def test_potential_real_main_tiny(potential_real, tmp_path, capsys):
    import json

    from gridfield.core.path import STATUSES

    root = _two_room_ros_root(tmp_path)
    out, js = tmp_path / "r.md", tmp_path / "r.json"
    code = potential_real.main(["--maps-root", str(root), "--per-map", "3", "--workers", "1", "--label", "before",
                                "--out", str(out), "--json", str(js)])
    assert code == 0
    text = out.read_text()
    assert text == capsys.readouterr().out
    assert "## Potential planner on real maps (before)" in text
    for heading in ("### `defaults`", "### `random_walk`", "### `navigation`", "### Per map", "| **overall** |"):
        assert heading in text
    runs = json.loads(js.read_text())["runs"]
    assert len(runs) == (3 + 3 + 2) * 3  # (arena scenarios + ROS pairs + unreachable ROS pairs) x variants
    assert {r["status"] for r in runs} <= set(STATUSES) | {"error", "n/a"}
    ros = [r for r in runs if r["map"] == "two_rooms"]
    # the octile wavefront reference: reachable exactly within one room, its length at least the straight line
    for r in ros:
        (sx, _), (gx, _) = r["start"], r["goal"]
        same_room = (sx < -1.0 + 0.05 * 9) == (gx < -1.0 + 0.05 * 9)
        assert r["kind"] == ("reachable" if same_room else "unreachable")
        if same_room:
            assert r["optimal"] >= ((sx - gx) ** 2 + (r["start"][1] - r["goal"][1]) ** 2) ** 0.5 - 1e-9
        else:
            assert r["optimal"] is None
    for r in runs:
        if r["status"] == "reached":
            assert r["ratio"] == pytest.approx(r["length"] / r["optimal"])
