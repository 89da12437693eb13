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

    from gridfield.grid import Grid, GridMap
    from gridfield.potential import build_field

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
        "import time:        5 |         35 | gridfield.world",
    ])
    records = run.parse_importtime(text)
    assert [r.depth for r in records] == [2, 1, 0]
    assert run.import_chain(records, 0) == ["gridfield.world", "shapely", "shapely.lib"]
