"""What a planned nf1 query keeps between the queries of one map (issue 25): the march setup
(``gridfield.fields.navfield._MarchSetup``: the compiled Marcher's arrays) and recycled output arrays.

The fields of the queries must not change when later queries run while anything still refers to
them (a Field, a view, a buffer), the results must equal a fresh march's, and nothing is kept once
the map's distance map (the planner's ``cache``) is gone.
"""

from __future__ import annotations

import gc

import numpy as np
import pytest

from gridfield.core.grid import Grid, GridMap
from gridfield.distance.brushfire import brushfire
from gridfield.fields import navfield
from gridfield.planners import plan, plan_with_field


def _world() -> GridMap:
    rng = np.random.default_rng(7)
    occ = rng.random((60, 80)) < 0.2
    occ[25:35, 10:70] = True
    occ[28:32, 40] = False
    return GridMap(Grid((60, 80), 0.5, border="wall"), occ)


def _free_points(gm: GridMap, n: int, seed: int) -> np.ndarray:
    cells = np.argwhere(~gm.occupied)
    pick = np.random.default_rng(seed).choice(len(cells), n, replace=False)
    return gm.grid.cell_to_world(cells[pick])


@pytest.mark.parametrize("params", [{}, {"clearance_band": 0}])
def test_kept_fields_are_not_overwritten_and_equal_fresh_ones(params):
    gm = _world()
    pts = _free_points(gm, 12, 1)
    cache: dict = {}
    kept = []
    for k in range(0, 12, 2):
        path, field = plan_with_field("potential", gm, pts[k], pts[k + 1], params, cache=cache)
        kept.append((field, field.potential.copy(), field.grad_x.copy(), field.grad_y.copy(), path.points.copy()))
    view = kept[0][0].potential[5:10]  # only a view of the first field's U survives
    view_copy = view.copy()
    first = kept[0][1:]
    del kept[0]
    for k in range(0, 12, 2):  # more queries, which may recycle only arrays nothing refers to
        plan("potential", gm, pts[k + 1], pts[k], params, cache=cache)
    for field, u, gx, gy, _ in kept:
        assert np.array_equal(field.potential, u) and np.array_equal(field.grad_x, gx)
        assert np.array_equal(field.grad_y, gy)
    assert np.array_equal(view, view_copy)
    # the same query on a fresh cache (no kept setup, no recycled arrays) gives the same bits
    path, field = plan_with_field("potential", gm, pts[0], pts[1], params, cache={})
    assert field.potential.tobytes() == first[0].tobytes()
    assert field.grad_x.tobytes() == first[1].tobytes() and field.grad_y.tobytes() == first[2].tobytes()
    assert path.points.tobytes() == first[3].tobytes()


def test_recycled_arrays_are_reused_once_dropped():
    gm = _world()
    pts = _free_points(gm, 4, 2)
    cache: dict = {}
    _, f1 = plan_with_field("potential", gm, pts[0], pts[1], {}, cache=cache)
    ids = {id(f1.potential), id(f1.grad_x), id(f1.grad_y)}
    del f1
    _, f2 = plan_with_field("potential", gm, pts[2], pts[3], {}, cache=cache)
    if navfield._REFCOUNTS:
        assert {id(f2.potential), id(f2.grad_x), id(f2.grad_y)} == ids


def test_the_setup_goes_with_the_cache():
    gm = _world()
    pts = _free_points(gm, 2, 3)
    cache: dict = {}
    plan("potential", gm, pts[0], pts[1], {}, cache=cache)
    assert navfield._setups and navfield._bands
    del cache
    gc.collect()
    assert not navfield._setups and not navfield._bands
    plan("potential", gm, pts[0], pts[1], {})  # no cache: nothing kept after the call
    gc.collect()
    assert not navfield._setups


def test_a_busy_setup_marches_on_a_fresh_marcher():
    gm = _world()
    pts = _free_points(gm, 2, 4)
    dmap = brushfire(gm, metric="euclidean", compute_labels=False, compute_gvd=False)
    ref = navfield.nav_field(gm, pts[1], {}, dmap=dmap, stop_at=pts[0])
    setup = navfield._setups[0][1]
    assert setup.lock.acquire(blocking=False)  # as if another thread were marching on it
    try:
        got = navfield.nav_field(gm, pts[1], {}, dmap=dmap, stop_at=pts[0])
    finally:
        setup.lock.release()
    assert got.potential.tobytes() == ref.potential.tobytes() and got.grad_x.tobytes() == ref.grad_x.tobytes()


def test_alternating_models_keep_their_setups():
    """A comparison of models on one map (the default's clearance band, then plain nf1, query after query)
    marches each on its own kept setup instead of rebuilding one in turn (the benchmark of issue 25 runs
    its variants so); the values are those of fresh setups."""
    gm = _world()
    pts = _free_points(gm, 6, 5)
    cache: dict = {}
    seen: dict[str, set[int]] = {"band": set(), "plain": set()}
    got = []
    for i in range(0, 6, 2):
        for name, params in (("band", {}), ("plain", {"clearance_band": 0})):
            _, f = plan_with_field("potential", gm, pts[i], pts[i + 1], params, cache=cache)
            seen[name].add(id(navfield._setups[0][1]))
            got.append((i, params, f.potential.tobytes()))
            del f
    assert len(seen["band"]) == 1 and len(seen["plain"]) == 1 and seen["band"] != seen["plain"]
    assert len(navfield._setups) <= navfield.KEPT_SETUPS
    del cache
    gc.collect()
    for i, params, values in got:  # no cache: a fresh setup each
        assert navfield.nav_field(gm, pts[i + 1], params, stop_at=pts[i]).potential.tobytes() == values
