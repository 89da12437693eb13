"""IncrementalBrushfire on voxel grids (issue 44): after every update, equal to a full recompute.

References, independent of the code under test: ``scipy.ndimage.distance_transform_edt`` (open
border; with a wall border on the map padded by one voxel of obstacles on every face, the wall
shell) for the distances, and a brute-force search over every obstacle voxel (wall shell included)
for the nearest voxel by the tie rule (smallest squared distance, then col, row, layer).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy import ndimage

from gridfield.core.errors import ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.distance.brushfire import BORDER_LABEL
from gridfield.distance.incremental import IncrementalBrushfire

RES = 0.25


def _scipy_distance(occ: np.ndarray, wall: bool) -> np.ndarray:
    """Distances (world units, ``sqrt(d2) * RES`` as the full transform computes them) by scipy."""
    if wall:
        pad = np.pad(occ, 1, constant_values=True)
        _, idx = ndimage.distance_transform_edt(~pad, return_indices=True)
        ii = np.indices(pad.shape)
        d2 = sum((idx[a] - ii[a]) ** 2 for a in range(3))[1:-1, 1:-1, 1:-1]
    elif not occ.any():
        return np.full(occ.shape, np.inf)
    else:
        _, idx = ndimage.distance_transform_edt(~occ, return_indices=True)
        ii = np.indices(occ.shape)
        d2 = sum((idx[a] - ii[a]) ** 2 for a in range(3))
    return np.sqrt(d2.astype(np.float64)) * RES


def _brute_nearest(occ: np.ndarray, wall: bool) -> np.ndarray:
    """(layer, row, col) of each voxel's nearest obstacle voxel by the tie rule, by brute force;
    ``(-1, -1, -1)`` where there is none. Shape ``occ.(*shape, 3)``."""
    shape = occ.shape
    sites = [np.argwhere(occ)]
    if wall:  # the shell: one coordinate just outside, the others inside
        for axis, n in enumerate(shape):
            for v in (-1, n):
                axes = [np.arange(m) for m in shape]
                axes[axis] = np.array([v])
                sites.append(np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3))
    s = np.concatenate(sites).reshape(-1, 3)
    cells = np.indices(shape).reshape(3, -1).T
    if not len(s):
        return np.full((*shape, 3), -1)
    d2 = ((cells[:, None, :] - s[None, :, :]) ** 2).sum(-1)
    order = np.lexsort((s[:, 0], s[:, 1], s[:, 2]))  # col, then row, then layer
    rank = np.empty(len(s), np.int64)
    rank[order] = np.arange(len(s))
    best = np.argmin(d2 * len(s) + rank[None, :], axis=1)
    return s[best].reshape((*shape, 3))


def _assert_equal_to_recompute(ib: IncrementalBrushfire, occ: np.ndarray, wall: bool, tie_rule: bool = True) -> None:
    dm = ib.distance_map
    assert np.array_equal(ib.gridmap.occupied, occ)
    want = _scipy_distance(occ, wall)
    assert np.array_equal(dm.distance, want)  # the very floats
    nl, nr, nc = dm.nearest_index
    got = np.stack([nl, nr, nc], -1)
    if tie_rule:
        assert np.array_equal(got, _brute_nearest(occ, wall))
    if np.isfinite(want).any():  # a nearest obstacle at exactly that distance
        ii = np.indices(occ.shape)
        d2 = (nl - ii[0]) ** 2 + (nr - ii[1]) ** 2 + (nc - ii[2]) ** 2
        assert np.array_equal(np.sqrt(d2.astype(np.float64)) * RES, want)


def _map(occ: np.ndarray, wall: bool, **kw: object) -> GridMap:
    return GridMap(Grid(occ.shape, RES, origin=(1.0, -2.0, 0.5), border="wall" if wall else "open"), occ, **kw)


def _block(z: int, r: int, c: int, d: int, h: int, w: int) -> np.ndarray:
    return np.stack(np.meshgrid(np.arange(z, z + d), np.arange(r, r + h), np.arange(c, c + w), indexing="ij"),
                    -1).reshape(-1, 3)


@st.composite
def _scenario(draw: st.DrawFn) -> tuple[np.ndarray, bool, list[tuple[np.ndarray, np.ndarray]]]:
    shape = (draw(st.integers(1, 6)), draw(st.integers(1, 7)), draw(st.integers(1, 7)))
    size = int(np.prod(shape))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    occ = rng.random(shape) < draw(st.sampled_from([0.0, 0.05, 0.2, 0.5]))
    wall = draw(st.booleans())
    steps = []
    for _ in range(draw(st.integers(1, 5))):
        add = rng.random(shape) < draw(st.sampled_from([0.0, 0.05, 0.2]))
        rem = (rng.random(shape) < draw(st.sampled_from([0.0, 0.1, 0.5]))) & ~add
        if draw(st.booleans()) and size > 1:  # sometimes a box instead of scattered voxels
            z, r, c = (int(rng.integers(0, n)) for n in shape)
            box = np.zeros(shape, bool)
            box[z:z + 3, r:r + 3, c:c + 3] = True
            add, rem = (box, np.zeros(shape, bool)) if draw(st.booleans()) else (np.zeros(shape, bool), box)
        steps.append((add, rem))
    return occ, wall, steps


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_scenario())
def test_random_updates_equal_a_recompute(case: tuple[np.ndarray, bool, list[tuple[np.ndarray, np.ndarray]]]) -> None:
    """Insertions and removals (scattered voxels and boxes, masks and voxel lists), open and wall
    border: distances, nearest voxels (tie rule included) and occupancy equal a recompute after
    every update, and the returned box holds every voxel that changed."""
    occ, wall, steps = case
    ib = IncrementalBrushfire(_map(occ, wall), compute_labels=False)
    assert type(ib).__name__ == "IncrementalBrushfire3D" and isinstance(ib, IncrementalBrushfire)
    _assert_equal_to_recompute(ib, occ, wall)
    for i, (add, rem) in enumerate(steps):
        before = [a.copy() for a in (ib.distance_map.distance, *ib.distance_map.nearest_index)]
        old = occ.copy()
        if i % 2:
            box = ib.update(occupied=np.argwhere(add), freed=np.argwhere(rem))
        else:
            box = ib.update(occupied=add, freed=rem)
        occ = (occ | add) & ~rem
        _assert_equal_to_recompute(ib, occ, wall)
        diff = (occ != old)
        for b, a in zip(before, (ib.distance_map.distance, *ib.distance_map.nearest_index), strict=True):
            diff |= b != a
        if box is None:
            assert not diff.any()
        else:
            inside = np.zeros(occ.shape, bool)
            inside[box[0]:box[1], box[2]:box[3], box[4]:box[5]] = True
            assert not (diff & ~inside).any()


@pytest.mark.parametrize("wall", [False, True])
@pytest.mark.parametrize("corner", [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)])
def test_blocks_on_the_border_faces_and_corners(wall: bool, corner: tuple[int, int, int]) -> None:
    """A 4^3 block inserted at a corner of the grid (touching three faces) or against one face, then
    removed again: equal to a recompute each time, wall and open border."""
    rng = np.random.default_rng(7)
    shape = (9, 10, 11)
    occ = rng.random(shape) < 0.08
    ib = IncrementalBrushfire(_map(occ, wall), compute_labels=False)
    origin = [0 if k == 0 else n - 4 for k, n in zip(corner, shape, strict=True)]
    cells = _block(*origin, 4, 4, 4)
    new = cells[~occ[cells[:, 0], cells[:, 1], cells[:, 2]]]
    ib.update(occupied=cells)
    occ2 = occ.copy()
    occ2[cells[:, 0], cells[:, 1], cells[:, 2]] = True
    _assert_equal_to_recompute(ib, occ2, wall)
    ib.update(freed=new)
    _assert_equal_to_recompute(ib, occ, wall)
    ib.update(freed=cells)  # the whole block, the voxels that were there before too
    occ2[cells[:, 0], cells[:, 1], cells[:, 2]] = False
    _assert_equal_to_recompute(ib, occ2, wall)


@pytest.mark.parametrize("wall", [False, True])
def test_a_single_voxel_at_each_corner_and_face(wall: bool) -> None:
    """One voxel at a time on each of the 8 corners and the 6 face centres of an empty grid, each
    inserted and then removed (the empty map again: no obstacle, or only the wall)."""
    shape = (5, 6, 7)
    occ = np.zeros(shape, bool)
    ib = IncrementalBrushfire(_map(occ, wall), compute_labels=False)
    spots = [(z, r, c) for z in (0, 4) for r in (0, 5) for c in (0, 6)]
    spots += [(0, 3, 3), (4, 3, 3), (2, 0, 3), (2, 5, 3), (2, 3, 0), (2, 3, 6)]
    for v in spots:
        ib.update(occupied=[v])
        one = occ.copy()
        one[v] = True
        _assert_equal_to_recompute(ib, one, wall)
        ib.update(freed=[v])
        _assert_equal_to_recompute(ib, occ, wall)


@pytest.mark.parametrize("wall", [False, True])
def test_emptying_and_filling_the_map(wall: bool) -> None:
    """Free every voxel (open border: nothing is reached, distance inf and nearest (-1, -1, -1)),
    then occupy every voxel (distance 0 everywhere, each voxel its own nearest), then empty again."""
    rng = np.random.default_rng(3)
    shape = (6, 5, 8)
    occ = rng.random(shape) < 0.3
    ib = IncrementalBrushfire(_map(occ, wall), compute_labels=False)
    ib.update(freed=np.ones(shape, bool))
    empty = np.zeros(shape, bool)
    _assert_equal_to_recompute(ib, empty, wall)
    if not wall:
        assert np.isinf(ib.distance_map.distance).all()
        assert all((a == -1).all() for a in ib.distance_map.nearest_index)
    ib.update(occupied=np.ones(shape, bool))
    full = np.ones(shape, bool)
    _assert_equal_to_recompute(ib, full, wall)
    assert (ib.distance_map.distance == 0).all()
    assert np.array_equal(np.stack(ib.distance_map.nearest_index), np.indices(shape))
    ib.update(freed=full)
    _assert_equal_to_recompute(ib, empty, wall)


def test_a_cube_removed_from_a_full_map_far_from_the_rest() -> None:
    """A big change: an 8^3 cube of a dense block freed, so its centre voxels look far for the
    nearest obstacle (the removal window must grow), then a single far obstacle alone."""
    shape = (12, 12, 12)
    occ = np.ones(shape, bool)
    ib = IncrementalBrushfire(_map(occ, False), compute_labels=False)
    cube = _block(2, 2, 2, 8, 8, 8)
    ib.update(freed=cube)
    occ[2:10, 2:10, 2:10] = False
    _assert_equal_to_recompute(ib, occ, False)
    lone = np.zeros(shape, bool)
    lone[11, 0, 5] = True
    ib.update(freed=np.argwhere(occ & ~lone))
    _assert_equal_to_recompute(ib, lone, False)


def test_labels_from_obstacle_ids_follow_the_nearest_voxel() -> None:
    """With obstacle ids, labels (the default then) are the id of the nearest obstacle voxel after
    every update (a recompute: ids gathered at the brute-force nearest voxel), wall border included."""
    rng = np.random.default_rng(11)
    shape = (5, 6, 7)
    occ = rng.random(shape) < 0.1
    ids = np.where(occ, rng.integers(1, 4, shape), 0).astype(np.int32)
    ib = IncrementalBrushfire(_map(occ, True, obstacle_id=ids))
    for step in range(6):
        add = rng.random(shape) < 0.04
        rem = (rng.random(shape) < 0.3) & occ & ~add
        ib.update(occupied=np.argwhere(add & ~occ), freed=rem, ids=10 + step)
        ids = np.where(rem, 0, ids)
        ids = np.where(add & ~occ, 10 + step, ids)
        occ = (occ | add) & ~rem
        _assert_equal_to_recompute(ib, occ, True)
        near = _brute_nearest(occ, True)
        inside = ((near >= 0) & (near < np.array(shape))).all(-1)
        want = np.full(shape, BORDER_LABEL, np.int32)
        want[inside] = ids[near[inside][:, 0], near[inside][:, 1], near[inside][:, 2]]
        assert np.array_equal(ib.distance_map.label, want)
        assert np.array_equal(ib.gridmap.obstacle_id, ids)


def test_component_labels_are_26_connected_in_raster_order() -> None:
    """Without ids, compute_labels=True gives the 26-connected components (scipy.ndimage.label's
    numbering) of the nearest obstacle, relabelled after a change; the default keeps none."""
    occ = np.zeros((4, 5, 6), bool)
    occ[0, 0, 0] = occ[1, 1, 1] = True  # diagonal neighbours: one component
    occ[3, 4, 5] = True
    ib = IncrementalBrushfire(_map(occ, False), compute_labels=True)
    assert IncrementalBrushfire(_map(occ, False)).distance_map.label is None
    for add in ([], [(2, 2, 2)], [(3, 3, 4)]):  # (2, 2, 2) joins the first; (3, 3, 4) joins them all
        if add:
            ib.update(occupied=add)
            for v in add:
                occ[v] = True
        comp, _ = ndimage.label(occ, structure=np.ones((3, 3, 3), bool))
        nl, nr, nc = ib.distance_map.nearest_index
        assert np.array_equal(ib.distance_map.label, comp[nl, nr, nc])


def test_the_distance_map_of_a_voxel_grid() -> None:
    """The DistanceMap carries nearest_layer and the world geometry; nearest_point in (x, y, z)."""
    occ = np.zeros((3, 4, 5), bool)
    occ[2, 1, 4] = True
    ib = IncrementalBrushfire(_map(occ, False))
    dm = ib.distance_map
    assert dm.nearest_layer is not None and dm.steps is None and dm.gvd is None and dm.metric == "euclidean"
    x, y, z = (a[0, 0, 0] for a in dm.nearest_point())
    assert (x, y, z) == pytest.approx((1.0 + 4.5 * RES, -2.0 + 1.5 * RES, 0.5 + 2.5 * RES))
    assert "shape=(3, 4, 5)" in repr(ib)


def test_bad_input_is_a_clear_error() -> None:
    occ = np.zeros((3, 4, 5), bool)
    occ[1, 1, 1] = True
    ib = IncrementalBrushfire(_map(occ, False))
    with pytest.raises(ParameterError, match=r"voxel \(3, 0, 0\) lies outside the grid of shape \(3, 4, 5\)"):
        ib.update(occupied=[[3, 0, 0]])
    with pytest.raises(ParameterError, match=r"integer voxels \(layer, row, col\) of shape \(N, 3\)"):
        ib.update(occupied=[[1, 2]])
    with pytest.raises(ParameterError, match=r"boolean mask must have the grid's shape"):
        ib.update(freed=np.zeros((3, 4), bool))
    with pytest.raises(ParameterError, match=r"voxel \(0, 0, 0\) is both occupied and freed"):
        ib.update(occupied=[[0, 0, 0]], freed=[[0, 0, 0]])
    with pytest.raises(ParameterError, match="ids are only for maps with world obstacle ids"):
        ib.update(occupied=[[0, 0, 0]], ids=3)
    with pytest.raises(ParameterError, match="the GVD is 2-D only"):
        IncrementalBrushfire(_map(occ, False), compute_gvd=True)
    with pytest.raises(ParameterError, match="metric='euclidean' only"):
        IncrementalBrushfire(_map(occ, False), metric="taxicab")
    assert ib.update(occupied=[[1, 1, 1]]) is None and ib.last_window is None  # already occupied: no change
    _assert_equal_to_recompute(ib, occ, False)


def test_two_d_maps_are_unchanged() -> None:
    """A 2-D map still makes the 2-D class (the same type and results as before)."""
    occ = np.zeros((1, 7), bool)
    occ[0, 0] = True
    ib = IncrementalBrushfire(GridMap(Grid((1, 7), 1.0), occ))
    assert type(ib) is IncrementalBrushfire
    assert ib.update(occupied=[[0, 6]]) == (0, 1, 4, 7)
    assert ib.distance_map.nearest_layer is None


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_removals_on_a_sparse_map_reach_far(seed: int) -> None:
    """A sparse 14 x 16 x 18 map (1 % blocked): a removed obstacle's orphans find their next nearest
    obstacle far away, beyond the first removal window (which must grow to be exact)."""
    rng = np.random.default_rng(seed)
    shape = (14, 16, 18)
    occ = rng.random(shape) < 0.01
    occ[7, 8, 9] = True
    ib = IncrementalBrushfire(_map(occ, False), compute_labels=False)
    for v in np.argwhere(occ)[:6]:
        ib.update(freed=[v])
        occ[tuple(v)] = False
        _assert_equal_to_recompute(ib, occ, False)
