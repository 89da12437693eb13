"""Voxel grids: the 3-D :class:`Grid`, :class:`GridMap`, :class:`Path` and :class:`Field` against the
conventions written in :mod:`gridfield.core.grid` (index 0 the lowest coordinate on every axis,
points ``(x, y, z)``, cells ``(layer, row, col)``)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gridfield import Grid, GridMap, Path
from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.results import Field


def test_shape_origin_bounds():
    g = Grid((4, 3, 2), 0.5, origin=(1.0, 2.0, 3.0))
    assert g.ndim == 3 and (g.layers, g.rows, g.cols) == (4, 3, 2)
    assert g.bounds == (1.0, 2.0, 3.0, 2.0, 3.5, 5.0)
    assert Grid((4, 3, 2), 1.0).origin == (0.0, 0.0, 0.0)
    xs, ys, zs = g.cell_centers()
    assert xs.tolist() == [1.25, 1.75] and ys.tolist() == [2.25, 2.75, 3.25] and zs[-1] == 4.75


@pytest.mark.parametrize("shape", [(2,), (1, 2, 3, 4), (0, 2, 2), (2, 2.5, 2)])
def test_bad_shapes(shape):
    with pytest.raises(ParameterError, match="three"):
        Grid(shape, 1.0)


def test_origin_must_match_the_dimension():
    with pytest.raises(ParameterError, match=r"three numbers \(x, y, z\)"):
        Grid((2, 2, 2), 1.0, origin=(0.0, 1.0))
    with pytest.raises(ParameterError, match=r"two numbers \(x, y\)"):
        Grid((2, 2), 1.0, origin=(0.0, 1.0, 2.0))


def test_covering_3d():
    g = Grid.covering((0, 0, 0, 3, 2, 1.1), 0.5)
    assert g.shape == (3, 4, 6) and g.origin == (0.0, 0.0, 0.0)
    with pytest.raises(ParameterError, match="max > min"):
        Grid.covering((0, 0, 1, 3, 2, 1), 0.5)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(-3, 9), st.floats(-3, 9), st.floats(-3, 9)), min_size=1, max_size=20))
def test_world_to_cell_is_the_floor_rule(points):
    g = Grid((5, 4, 3), 0.75, origin=(-1.0, 0.5, 2.0))
    p = np.array(points)
    cells, inside = g.world_to_cell(p)
    want = np.floor((p - np.array(g.origin)) / g.resolution).astype(int)[:, ::-1]  # (layer, row, col)
    # the floor rule up to points on a boundary within rounding
    near = np.abs((p - np.array(g.origin)) / g.resolution - np.round((p - np.array(g.origin)) / g.resolution)) < 1e-9
    ok = ~near.any(axis=1)
    assert (cells[ok] == want[ok]).all()
    shape = np.array(g.shape)
    assert (inside[ok] == ((want[ok] >= 0) & (want[ok] < shape)).all(axis=1)).all()
    for q, c, i in zip(p, cells, inside, strict=True):
        one = g.cell_of(*q)
        assert (one is not None) == bool(i)
        if one is not None:
            assert one == tuple(c)
    # centres map back to their cells
    back, inside2 = g.world_to_cell(g.cell_to_world(cells[inside]))
    assert inside2.all() and (back == cells[inside]).all()


def _map(seed=0, shape=(6, 7, 8), p=0.3):
    occ = np.random.default_rng(seed).random(shape) < p
    return GridMap(Grid(shape, 0.5, origin=(0.0, 0.0, 0.0)), occ)


def test_is_free_and_check_point():
    gm = _map()
    cells = np.argwhere(np.ones(gm.shape, bool))
    pts = gm.grid.cell_to_world(cells)
    assert (gm.is_free(pts) == ~gm.occupied[tuple(cells.T)]).all()
    free = pts[gm.is_free(pts)][0]
    assert gm.check_point("start", free).shape == (3,)
    blocked = pts[~gm.is_free(pts)][0]
    with pytest.raises(GridfieldError, match=r"start \(.*\) lies inside an obstacle; the nearest free cell"):
        gm.check_point("start", blocked)
    with pytest.raises(GridfieldError, match=r"z in \[0, 3\)"):
        gm.check_point("goal", (1.0, 1.0, 9.0))
    with pytest.raises(ParameterError, match="three numbers X Y Z"):
        gm.check_point("goal", (1.0, 1.0))


@pytest.mark.parametrize("seed", range(5))
def test_nearest_free_is_the_brute_force_nearest(seed):
    gm = _map(seed, p=0.7)
    rng = np.random.default_rng(seed + 100)
    for _ in range(10):
        q = rng.uniform(0, 3, 3)
        got = gm.nearest_free(q)
        c = np.array(gm.grid.world_to_cell(q)[0][0])
        c = np.clip(c, 0, np.array(gm.shape) - 1)
        free = np.argwhere(~gm.occupied)
        d2 = ((free - c) ** 2).sum(axis=1)
        best = free[d2 == d2.min()]
        assert any(np.allclose(got, gm.grid.cell_to_world(b)[0]) for b in best)


def test_diagonals_are_2d_only():
    with pytest.raises(ParameterError, match="voxel grid has none"):
        GridMap(Grid((2, 2, 2), 1.0), np.zeros((2, 2, 2), bool), diagonals=np.zeros((1, 1), np.uint8))


def test_path_3d():
    p = Path(np.array([[0.0, 0.0, 0.0], [2.0, 3.0, 6.0], [2.0, 3.0, 7.0]]), "reached", "demo")
    assert p.points.shape == (3, 3) and math.isclose(p.length, 8.0)
    j = json.loads(json.dumps(p.to_json()))
    assert j["path"][1] == [2.0, 3.0, 6.0] and j["end"] == [2.0, 3.0, 7.0]
    assert "end=(2, 3, 7)" in repr(p)
    assert Path(np.zeros((0, 3)), "no_path", "demo").end.shape == (3,)


def test_field_3d_needs_grad_z():
    gm = _map()
    z = np.zeros(gm.shape)
    f = Field(gm, z, z, z, (0.25, 0.25, 0.25), {}, grad_z=z)
    assert f.goal == (0.25, 0.25, 0.25) and len(f.gradient) == 3
    with pytest.raises(GridfieldError, match="grad_z"):
        Field(gm, z, z, z, (0.25, 0.25, 0.25), {})
