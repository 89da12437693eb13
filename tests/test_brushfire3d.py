"""The brushfire of voxel grids (issue 44): gridfield.distance.brushfire on 3-D GridMaps.

References are independent of the kernels: scipy.ndimage's exact transforms (a wall border = the grid
padded with obstacles), ``ndimage.label`` for the components, and plain brute-force searches over all
obstacle voxels (and the wall's shell) for the nearest voxel and its tie rule.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy import ndimage

from gridfield.core.errors import ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.distance.brushfire import BORDER_LABEL, brushfire

SHAPES = [(5, 6, 7), (1, 8, 9), (9, 1, 4), (6, 5, 1), (1, 1, 6), (1, 1, 1), (12, 10, 11)]


def _map(occ, border="open", res=0.5, origin=(0.0, 0.0, 0.0)):
    return GridMap(Grid(occ.shape, res, origin, border), occ)


def _ref(occ, border, fn, **kw):
    """scipy's transform of the free voxels; a wall border as a pad of obstacles."""
    if border == "wall":
        return fn(~np.pad(occ, 1, constant_values=True), **kw)[1:-1, 1:-1, 1:-1]
    return fn(~occ, **kw)


def _sites(occ, border):
    """All obstacle voxels, and the wall's shell across the six faces: (layer, row, col) rows."""
    sites = [np.argwhere(occ)]
    if border == "wall":
        L, R, C = occ.shape
        for (a, n), (b, m), (c, k) in [((0, L), (1, R), (2, C)), ((1, R), (0, L), (2, C)), ((2, C), (0, L), (1, R))]:
            for v in (-1, n):
                u, w = np.meshgrid(np.arange(m), np.arange(k), indexing="ij")
                s = np.empty((u.size, 3), int)
                s[:, a], s[:, b], s[:, c] = v, u.ravel(), w.ravel()
                sites.append(s)
    return np.concatenate(sites)


def _brute_nearest(occ, border):
    """The nearest site of every voxel by squared distance, ties: smallest col, then row, then layer."""
    sites = _sites(occ, border)
    cells = np.argwhere(np.ones(occ.shape, bool))
    d2 = ((cells[:, None, :] - sites[None, :, :]) ** 2).sum(axis=2)
    best = d2.min(axis=1)
    # lexicographic key among the nearest: (col, row, layer)
    key = np.where(d2 == best[:, None], (sites[:, 2] * 10**6 + sites[:, 1] * 10**3 + sites[:, 0])[None, :] + 10**9,
                   np.iinfo(np.int64).max)
    pick = sites[key.argmin(axis=1)]
    return best.reshape(occ.shape), tuple(pick[:, a].reshape(occ.shape) for a in range(3))


def _random(shape, p, seed):
    return np.random.default_rng(seed).random(shape) < p


@pytest.mark.parametrize("border", ["open", "wall"])
@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("p", [0.03, 0.2, 0.6])
def test_euclidean_matches_scipy_and_brute_force_ties(shape, p, border):
    """Distance exactly scipy's EDT (times the resolution); the nearest voxel exactly the brute force's,
    tie rule included (smallest col, then row, then layer; the wall's indices -1 / n as numbers)."""
    occ = _random(shape, p, hash((shape, p)) % 1000)
    if border == "open" and not occ.any():
        occ.flat[0] = True
    d = brushfire(_map(occ, border), metric="euclidean")
    assert np.array_equal(d.distance, 0.5 * _ref(occ, border, ndimage.distance_transform_edt))
    best, nearest = _brute_nearest(occ, border)
    assert np.array_equal(d.distance, 0.5 * np.sqrt(best))
    for got, want in zip(d.nearest_index, nearest, strict=True):
        assert np.array_equal(got, want)
    assert d.nearest_layer is not None and d.nearest_layer.dtype == np.int16


def test_euclidean_ties_in_a_cube():
    """Eight obstacles at the corners of a cube: the centre's nearest is the corner of smallest (col, row, layer)."""
    occ = np.zeros((3, 3, 3), bool)
    for z, y, x in itertools.product((0, 2), repeat=3):
        occ[z, y, x] = True
    d = brushfire(_map(occ), metric="euclidean")
    assert [int(a[1, 1, 1]) for a in d.nearest_index] == [0, 0, 0]
    occ[0, 0, 0] = False
    d = brushfire(_map(occ), metric="euclidean")
    assert [int(a[1, 1, 1]) for a in d.nearest_index] == [2, 0, 0]  # col 0, row 0, then the larger layer


@pytest.mark.parametrize("border", ["open", "wall"])
@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize(("connectivity", "metric"), [(26, "chessboard"), (6, "taxicab")])
def test_chamfer_matches_scipy_cdt(shape, connectivity, metric, border):
    """steps and distance exactly scipy's distance_transform_cdt; the nearest voxel lies exactly at that distance."""
    occ = _random(shape, 0.1, 7)
    if border == "open" and not occ.any():
        occ.flat[-1] = True
    d = brushfire(_map(occ, border), connectivity=connectivity)
    ref = _ref(occ, border, ndimage.distance_transform_cdt, metric=metric)
    assert d.metric == metric and d.connectivity == connectivity
    assert d.steps.dtype == np.int32 and np.array_equal(d.steps, ref)
    assert np.array_equal(d.distance, 0.5 * ref)
    idx = np.indices(shape)
    diff = [np.abs(a.astype(int) - i) for a, i in zip(d.nearest_index, idx, strict=True)]
    at = np.maximum.reduce(diff) if metric == "chessboard" else sum(diff)
    assert np.array_equal(at, ref)
    sites = {tuple(s) for s in _sites(occ, border)}
    assert all(tuple(int(a[c]) for a in d.nearest_index) in sites for c in np.ndindex(shape))


@pytest.mark.parametrize(("connectivity", "metric", "steps_metric"),
                         [(26, "taxicab", "chessboard"), (6, "chessboard", "taxicab"), (26, "euclidean", "chessboard"),
                          (6, "euclidean", "taxicab")])
def test_steps_follow_the_connectivity_distance_the_metric(connectivity, metric, steps_metric):
    occ = _random((7, 8, 9), 0.05, 3)
    d = brushfire(_map(occ, "wall"), connectivity=connectivity, metric=metric)
    assert np.array_equal(d.steps, _ref(occ, "wall", ndimage.distance_transform_cdt, metric=steps_metric))
    fn = ndimage.distance_transform_edt if metric == "euclidean" else ndimage.distance_transform_cdt
    kw = {} if metric == "euclidean" else {"metric": metric}
    assert np.array_equal(d.distance, 0.5 * _ref(occ, "wall", fn, **kw))


@pytest.mark.parametrize("metric", ["euclidean", "chessboard", "taxicab"])
@pytest.mark.parametrize("border", ["open", "wall"])
def test_labels_are_26_connected_components(metric, border):
    """label = ndimage.label(occ, 26-connected) at the nearest voxel; BORDER_LABEL where that is the wall."""
    occ = _random((9, 10, 11), 0.04, 11)
    d = brushfire(_map(occ, border), connectivity=6 if metric == "taxicab" else 26, metric=metric)
    comp, _ = ndimage.label(occ, structure=np.ones((3, 3, 3), bool))
    nl, nr, nc = (a.astype(int) for a in d.nearest_index)
    inside = (nl >= 0) & (nl < 9) & (nr >= 0) & (nr < 10) & (nc >= 0) & (nc < 11)
    want = np.where(inside, comp[np.clip(nl, 0, 8), np.clip(nr, 0, 9), np.clip(nc, 0, 10)], BORDER_LABEL)
    assert np.array_equal(d.label, want)
    assert np.array_equal(d.label[occ], comp[occ])
    assert (border == "wall") == bool((d.label == BORDER_LABEL).any())


def _brute_gvd(label, key, occ):
    """2-D's rule over the 26 neighbours, by shifting whole arrays."""
    L, R, C = occ.shape
    pad = lambda a, v: np.pad(a, 1, constant_values=v)  # noqa: E731
    lp, kp, fp = pad(label, 0), pad(key, 0.0), pad(occ, True)
    mark = np.zeros(occ.shape, bool)
    for dz, dy, dx in itertools.product((-1, 0, 1), repeat=3):
        sl = (slice(1 + dz, 1 + dz + L), slice(1 + dy, 1 + dy + R), slice(1 + dx, 1 + dx + C))
        lb, kb, fb = lp[sl], kp[sl], fp[sl]
        mark |= (label != lb) & ~fb & ((key > kb) | ((key == kb) & (label < lb)))
    return mark & ~occ


@pytest.mark.parametrize("metric", ["euclidean", "chessboard"])
def test_gvd_rule_and_separation(metric):
    occ = _random((10, 12, 9), 0.03, 5)
    d = brushfire(_map(occ, "wall"), metric=metric)
    assert np.array_equal(d.gvd, _brute_gvd(d.label, d.distance, occ))
    # removing the GVD leaves no two 26-neighbouring free voxels of different labels
    rest = ~occ & ~d.gvd
    assert not _brute_gvd(np.where(rest, d.label, 0), np.zeros(occ.shape), ~rest).any()


def test_gvd_between_two_walls_of_obstacles():
    occ = np.zeros((3, 4, 7), bool)
    occ[:, :, 0] = occ[:, :, 6] = True
    d = brushfire(_map(occ), metric="euclidean")
    assert np.array_equal(np.argwhere(d.gvd)[:, 2], np.full(12, 3))
    assert np.array_equal(np.unique(d.label), [1, 2])


def test_saturation_and_far():
    occ = _random((6, 7, 8), 0.05, 2)
    occ[0, 0, 0] = True
    full = brushfire(_map(occ), metric="euclidean")
    sat = brushfire(_map(occ), metric="euclidean", saturate=1.0, far=-1.0)
    assert np.array_equal(sat.distance, np.where(full.distance >= 1.0, -1.0, full.distance))
    assert np.array_equal(sat.steps, full.steps) and np.array_equal(sat.gvd, full.gvd)
    assert all(np.array_equal(a, b) for a, b in zip(sat.nearest_index, full.nearest_index, strict=True))
    assert sat.saturate == 1.0 and sat.far == -1.0


@pytest.mark.parametrize("metric", ["euclidean", "chessboard", "taxicab"])
def test_empty_map(metric):
    occ = np.zeros((3, 4, 5), bool)
    conn = 6 if metric == "taxicab" else 26
    d = brushfire(_map(occ), metric=metric, connectivity=conn)
    assert np.isinf(d.distance).all() and (d.steps == -1).all() and (d.label == 0).all() and not d.gvd.any()
    assert all((a == -1).all() for a in d.nearest_index)
    assert np.isnan(d.nearest_point()[0]).all()
    sat = brushfire(_map(occ), metric=metric, connectivity=conn, saturate=1.0, far=9.0)
    assert (sat.distance == 9.0).all()
    w = brushfire(_map(occ, "wall"), metric=metric, connectivity=conn)  # the wall is the only obstacle
    assert (w.label == BORDER_LABEL).all()
    ref = _ref(occ, "wall", ndimage.distance_transform_edt if metric == "euclidean" else
               ndimage.distance_transform_cdt, **({} if metric == "euclidean" else {"metric": metric}))
    assert np.array_equal(w.distance, 0.5 * ref)


@pytest.mark.parametrize("metric", ["euclidean", "chessboard"])
def test_full_map(metric):
    occ = np.ones((2, 3, 4), bool)
    d = brushfire(_map(occ, "wall"), metric=metric)
    assert (d.distance == 0).all() and (d.steps == 0).all() and not d.gvd.any()
    assert all(np.array_equal(a, i) for a, i in zip(d.nearest_index, np.indices(occ.shape), strict=True))
    assert (d.label == 1).all()


def test_nearest_point_and_dtypes():
    occ = np.zeros((2, 3, 4), bool)
    occ[1, 2, 3] = True
    d = brushfire(_map(occ, res=0.5, origin=(1.0, 2.0, 3.0)), metric="euclidean")
    x, y, z = d.nearest_point()
    assert (x == 1.0 + 3.5 * 0.5).all() and (y == 2.0 + 2.5 * 0.5).all() and (z == 3.0 + 1.5 * 0.5).all()
    assert d.distance.dtype == np.float64 and d.label.dtype == np.int32 and d.gvd.dtype == bool
    assert {a.dtype for a in d.nearest_index} == {np.dtype(np.int16)}
    assert d.steps.dtype == np.int32


@pytest.mark.parametrize("threads", [1, 2])
def test_flags_and_threads(threads):
    occ = _random((8, 9, 10), 0.1, 4)
    full = brushfire(_map(occ), metric="euclidean", threads=threads)
    only = brushfire(_map(occ), metric="euclidean", compute_nearest=False, compute_labels=False, compute_steps=False,
                     threads=threads)
    assert np.array_equal(only.distance, full.distance)
    assert only.nearest_layer is None and only.nearest_row is None and only.label is None and only.steps is None
    assert only.gvd is None
    labels_only = brushfire(_map(occ), metric="chessboard", compute_nearest=False, threads=threads)
    assert labels_only.nearest_layer is None and labels_only.label is not None
    assert np.array_equal(labels_only.label, brushfire(_map(occ), threads=1).label)
    assert np.array_equal(brushfire(_map(occ), compute_gvd=False).label, labels_only.label)


@pytest.mark.parametrize("connectivity", [4, 8, 5, True])
def test_bad_connectivity_on_voxels(connectivity):
    with pytest.raises(ParameterError, match="connectivity must be 6 or 26 on a voxel grid"):
        brushfire(_map(np.zeros((2, 2, 2), bool)), connectivity=connectivity)


@pytest.mark.parametrize("connectivity", [6, 26])
def test_voxel_connectivity_on_a_2d_map(connectivity):
    with pytest.raises(ParameterError, match=r"connectivity must be 4 or 8, got \d+ \(26 and 6 are for voxel grids\)"):
        brushfire(GridMap(Grid((2, 2), 1.0), np.zeros((2, 2), bool)), connectivity=connectivity)


def test_2d_default_is_unchanged():
    occ = np.zeros((3, 5), bool)
    occ[1, 0] = True
    d = brushfire(GridMap(Grid((3, 5), 1.0), occ))
    assert d.connectivity == 8 and d.metric == "chessboard" and d.nearest_layer is None


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(arrays(bool, st.tuples(st.integers(1, 6), st.integers(1, 6), st.integers(1, 6))),
       st.sampled_from(["open", "wall"]), st.sampled_from(["euclidean", "chessboard", "taxicab"]))
def test_random_maps(occ, border, metric):
    """Any map: scipy's distance; the nearest voxel at exactly that distance (Euclidean: the brute force's)."""
    if border == "open" and not occ.any():
        return
    conn = 6 if metric == "taxicab" else 26
    d = brushfire(_map(occ, border, res=1.0), metric=metric, connectivity=conn)
    if metric == "euclidean":
        best, nearest = _brute_nearest(occ, border)
        assert np.array_equal(d.distance, np.sqrt(best))
        assert all(np.array_equal(a, b) for a, b in zip(d.nearest_index, nearest, strict=True))
        assert np.array_equal(d.distance, _ref(occ, border, ndimage.distance_transform_edt))
    else:
        ref = _ref(occ, border, ndimage.distance_transform_cdt, metric=metric)
        assert np.array_equal(d.distance, ref) and np.array_equal(d.steps, ref)
    assert np.array_equal(d.gvd, _brute_gvd(d.label, d.distance, occ))


def test_cli_summary_on_a_voxel_map(monkeypatch, capsys):
    """``gridfield brushfire`` on a 3-D GridMap (its reader stubbed: 3-D files are the readers' issue)."""
    import argparse

    from gridfield.cli import brushfire as cli

    occ = np.zeros((3, 4, 5), bool)
    occ[1, 2, 3] = True
    gm = _map(occ, "wall")
    monkeypatch.setattr(cli, "_load", lambda args: gm)
    parser = argparse.ArgumentParser()
    cli.add_parser(parser.add_subparsers())
    for extra, conn in [([], 26), (["--connectivity", "6", "--metric", "euclidean"], 6)]:
        args = parser.parse_args(["brushfire", "voxels.npy", *extra])
        assert cli.run(args) == 0
        out = capsys.readouterr().out
        d = brushfire(gm, connectivity=conn, metric="euclidean" if extra else None)
        assert out.startswith(f"brushfire 3x4x5 cells of 0.5 ({conn}-connected steps, {d.metric} distance, wall border)")
        assert f"{int(d.gvd.sum())} GVD cells, 1 obstacle label + wall" in out
