"""The octile wavefront against the Moving AI benchmark scenarios (tests/data/maps/movingai).

For a sample of scenarios on EVERY map, the wavefront from the scenario's goal, read at the start,
must equal the reference optimal length (8-connected, octile costs, no corner cutting), within the
precision the file was printed with (MANIFEST §5.1): 6 significant digits 1e-3 absolute (5e-3 for
lengths >= 1000; the generator sometimes printed the last digit one low), 2 decimals 0.005 (+1e-9),
8 decimals 1e-6. GPPC's "no path" markers (length 0, start != goal, rmtst01) must be unreachable.
The path extracted from the field must cost exactly the field's value and never cut a corner.
``benchmarks/movingai_all.py`` runs all 48,737 scenarios.
"""

from __future__ import annotations

import numpy as np
import pytest

from gridfield.fields.navigation import SQRT2, extract_path, wavefront
from gridfield.io import read_movingai_map, read_scen

from mapdata import movingai_pairs

#: scenarios sampled per map (evenly over the file, so every length bucket is represented)
SAMPLE = 10


def tolerance(scen, optimal: np.ndarray) -> np.ndarray:
    """The tolerances of the issue (MANIFEST §5.1) for this file's print format."""
    if scen.precision == "decimals" and scen.digits == 2:
        return np.full(optimal.shape, 0.005 + 1e-9)
    if scen.precision == "decimals":
        return np.full(optimal.shape, 1e-6)
    return np.where(optimal >= 1000, 5e-3, 1e-3)


def sample_indices(scen) -> np.ndarray:
    idx = np.linspace(0, len(scen) - 1, SAMPLE).round().astype(int)
    idx = np.union1d(idx, np.flatnonzero(scen.no_path))  # every "no path" marker
    same = np.flatnonzero(np.all(scen.start_cell == scen.goal_cell, axis=1))
    return np.union1d(idx, same[:1])  # and one start == goal scenario, if any


def check_chain(free: np.ndarray, cells: np.ndarray) -> None:
    step = np.diff(cells, axis=0)
    assert free[cells[:, 0], cells[:, 1]].all()
    assert np.abs(step).max(initial=0) <= 1 and (np.abs(step).sum(axis=1) > 0).all()
    diag = (step[:, 0] != 0) & (step[:, 1] != 0)
    a, s = cells[:-1][diag], step[diag]
    assert free[a[:, 0] + s[:, 0], a[:, 1]].all() and free[a[:, 0], a[:, 1] + s[:, 1]].all()


MAPS = ["16room_000", "64room_000", "8room_000", "AR0011SR", "AcrosstheCape", "Aurora", "Berlin_0_256", "arena",
        "arena2", "brc202d", "den312d", "isound1", "lak303d", "mapf_empty-48-48", "mapf_ht_chantry",
        "mapf_maze-32-32-2", "mapf_random-32-32-10", "mapf_room-64-64-8", "maze512-32-9", "orz100d", "ost003d",
        "random512-10-0", "rmtst01"]


def test_every_map_is_covered(test_maps):
    """The parametrized list below is every map directory, and each .scen holds the count of the data's
    MANIFEST ("Moving AI scenario counts", the number of scenario lines of the file as published)."""
    pairs = movingai_pairs(test_maps)
    assert sorted(m.parent.name for m, _ in pairs) == sorted(MAPS)
    counts = {}
    for line in (test_maps / "MANIFEST.md").read_text().splitlines():
        cols = [c.strip() for c in line.split("|")]
        if len(cols) == 4 and cols[2].isdigit():  # | `name` | count |
            counts[cols[1].strip("`")] = int(cols[2])
    assert counts.keys() == set(MAPS)
    for m, s in pairs:
        assert len(read_scen(s)) == counts[m.parent.name]


@pytest.mark.parametrize("name", MAPS)
def test_octile_wavefront_matches_scenarios(test_maps, name):
    (map_path,) = (test_maps / "movingai" / name).glob("*.map.gz")
    (scen_path,) = (test_maps / "movingai" / name).glob("*.scen.gz")
    gm = read_movingai_map(map_path)
    scen = read_scen(scen_path, map_height=gm.shape[0])
    free = ~gm.occupied
    idx = sample_indices(scen)
    tol = tolerance(scen, scen.optimal)
    for i in idx:
        nav = wavefront(gm, scen.goal_xy[i], connectivity=8, costs="octile")
        assert nav.goal_cell == tuple(scen.goal_cell[i])
        value = nav.value_at(scen.start_xy[i])[0]
        assert value == nav.value[tuple(scen.start_cell[i])]
        path = extract_path(nav, scen.start_xy[i])
        if scen.no_path[i]:
            assert np.isinf(value), f"{name} scenario {i}: a 'no path' marker, but the goal is reachable ({value})"
            assert path.status == "no_path"
            continue
        assert abs(value - scen.optimal[i]) <= tol[i], (
            f"{name} scenario {i}: wavefront {value!r}, reference {scen.optimal[i]!r}")
        assert path.status == "reached"
        cells = path.extra["cells"]
        assert tuple(cells[0]) == tuple(scen.start_cell[i]) and tuple(cells[-1]) == tuple(scen.goal_cell[i])
        check_chain(free, cells)
        diag = np.abs(np.diff(cells, axis=0)).sum(axis=1) == 2
        chain = np.where(diag, SQRT2, 1.0).sum()
        assert chain == pytest.approx(value, rel=1e-12, abs=1e-9)
        assert path.extra["grid_length"] == pytest.approx(value, rel=1e-12, abs=1e-9)
        # start and goal are cell centres here, so the polyline is the chain itself
        assert path.length == pytest.approx(value, rel=1e-12, abs=1e-9)
        np.testing.assert_array_equal(path.points[0], scen.start_xy[i])
        np.testing.assert_array_equal(path.points[-1], scen.goal_xy[i])


def test_rmtst01_no_path_markers(test_maps):
    d = test_maps / "movingai" / "rmtst01"
    gm = read_movingai_map(d / "rmtst01.map.gz")
    scen = read_scen(d / "rmtst01.map.scen.gz")
    assert np.flatnonzero(scen.no_path).tolist() == [4, 9]
    for i in (4, 9):
        nav = wavefront(gm, scen.goal_xy[i], costs="octile")
        assert np.isinf(nav.value_at(scen.start_xy[i])[0])


def test_full_field_equals_scipy_dijkstra_on_a_benchmark_map(test_maps):
    """The whole field, not just the scenario starts, against an independent Dijkstra (den312d)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    d = test_maps / "movingai" / "den312d"
    gm = read_movingai_map(d / "den312d.map.gz")
    scen = read_scen(d / "den312d.map.scen.gz")
    free = ~gm.occupied
    rows, cols = free.shape
    ids = np.arange(rows * cols).reshape(rows, cols)
    src, dst, wts = [], [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        c0, c1 = max(0, -dc), cols - max(0, dc)
        a, b = (slice(0, rows - dr), slice(c0, c1)), (slice(dr, rows), slice(c0 + dc, c1 + dc))
        ok = free[a] & free[b]
        if dr and dc:
            ok &= free[dr:rows, c0:c1] & free[0:rows - dr, c0 + dc:c1 + dc]
        src.append(ids[a][ok])
        dst.append(ids[b][ok])
        wts.append(np.full(int(ok.sum()), SQRT2 if dr and dc else 1.0))
    graph = coo_matrix((np.concatenate(wts), (np.concatenate(src), np.concatenate(dst))), shape=(rows * cols,) * 2)
    for i in (0, len(scen) // 2, len(scen) - 1):
        goal = scen.goal_cell[i]
        ref = dijkstra(graph.tocsr(), directed=False, indices=goal[0] * cols + goal[1]).reshape(rows, cols)
        ref[~free] = np.inf
        nav = wavefront(gm, scen.goal_xy[i], costs="octile")
        assert np.array_equal(np.isinf(nav.value), np.isinf(ref))
        fin = np.isfinite(ref)
        np.testing.assert_allclose(nav.value[fin], ref[fin], rtol=0, atol=1e-9)
