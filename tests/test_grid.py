"""Grid geometry: world <-> cell conversions against brute force, validation of bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap

finite = st.floats(min_value=-1e3, max_value=1e3, allow_nan=False, allow_infinity=False)
resolutions = st.floats(min_value=1e-3, max_value=10.0, allow_nan=False, allow_infinity=False)


@st.composite
def grids(draw, max_side: int = 30) -> Grid:
    shape = (draw(st.integers(1, max_side)), draw(st.integers(1, max_side)))
    return Grid(shape, draw(resolutions), origin=(draw(finite), draw(finite)),
                border=draw(st.sampled_from(["open", "wall"])))


def cell_edges(g: Grid, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """x0, x1, y0, y1 of the squares of cells (row, col), with the documented arithmetic."""
    x0 = g.origin[0] + cells[:, 1] * g.resolution
    x1 = g.origin[0] + (cells[:, 1] + 1) * g.resolution
    y0 = g.origin[1] + cells[:, 0] * g.resolution
    y1 = g.origin[1] + (cells[:, 0] + 1) * g.resolution
    return x0, x1, y0, y1


@given(grids(), st.data())
def test_cell_centre_round_trip(g: Grid, data) -> None:
    rows = data.draw(st.lists(st.integers(0, g.rows - 1), min_size=1, max_size=20))
    cols = data.draw(st.lists(st.integers(0, g.cols - 1), min_size=len(rows), max_size=len(rows)))
    cells = np.stack([rows, cols], axis=1)
    back, inside = g.world_to_cell(g.cell_to_world(cells))
    assert inside.all()
    np.testing.assert_array_equal(back, cells)


@given(grids(), st.lists(st.tuples(finite, finite), min_size=1, max_size=30))
def test_point_lands_in_a_square_containing_it(g: Grid, pts: list) -> None:
    p = np.asarray(pts, dtype=float)
    cells, inside = g.world_to_cell(p)
    x0, x1, y0, y1 = cell_edges(g, cells)
    # half-open intervals as documented, evaluated with the same float arithmetic
    assert np.all((x0 <= p[:, 0]) & (p[:, 0] < x1) & (y0 <= p[:, 1]) & (p[:, 1] < y1))
    expected_inside = (cells[:, 0] >= 0) & (cells[:, 0] < g.rows) & (cells[:, 1] >= 0) & (cells[:, 1] < g.cols)
    np.testing.assert_array_equal(inside, expected_inside)
    np.testing.assert_array_equal(g.contains(p), inside)


@given(grids(max_side=8), st.data())
def test_conversion_agrees_with_brute_force_loop(g: Grid, data) -> None:
    # points on cell boundaries, at centres and at random places, some outside
    xs = g.origin[0] + g.resolution * np.array(
        data.draw(st.lists(st.sampled_from([-1.0, 0.0, 0.5, 1.0, 2.0, 2.25, 3.0, g.cols - 0.5, g.cols, g.cols + 1.0]),
                           min_size=1, max_size=12)))
    ys = g.origin[1] + g.resolution * np.array(
        data.draw(st.lists(st.sampled_from([-1.0, 0.0, 0.5, 1.0, 1.75, g.rows - 1.0, g.rows - 0.5, g.rows]),
                           min_size=len(xs), max_size=len(xs))))
    p = np.stack([xs, ys], axis=1)
    cells, inside = g.world_to_cell(p)
    for k, (x, y) in enumerate(p):
        found = None
        for r in range(g.rows):
            for c in range(g.cols):
                if (g.origin[0] + c * g.resolution <= x < g.origin[0] + (c + 1) * g.resolution
                        and g.origin[1] + r * g.resolution <= y < g.origin[1] + (r + 1) * g.resolution):
                    assert found is None, "cells overlap"
                    found = (r, c)
        if found is None:
            assert not inside[k]
        else:
            assert inside[k]
            assert tuple(cells[k]) == found
        assert g.cell_of(x, y) == found  # the single-point path follows the same rule
    centres = g.cell_to_world(np.array([[r, c] for r in range(g.rows) for c in range(g.cols)]))
    xs_c, ys_c = g.cell_centers()
    expected = np.array([[xs_c[c], ys_c[r]] for r in range(g.rows) for c in range(g.cols)])
    np.testing.assert_allclose(centres, expected, rtol=0, atol=1e-9 * max(1.0, *map(abs, g.bounds)))


@given(grids(), st.lists(st.tuples(finite, finite), min_size=1, max_size=30))
def test_single_point_cell_of_agrees_with_world_to_cell(g: Grid, pts: list) -> None:
    # near the grid too: points at a few cells' distance from random interior positions
    p = np.array(pts)
    p = np.concatenate([p, np.array(g.origin) + np.mod(p, 1.0) * np.array([g.cols, g.rows]) * g.resolution])
    cells, inside = g.world_to_cell(p)
    for (x, y), cell, ins in zip(p, cells, inside, strict=True):
        assert g.cell_of(x, y) == (tuple(int(v) for v in cell) if ins else None)
    assert g.cell_of(math.nan, 0.0) is None and g.cell_of(0.0, math.inf) is None


def test_boundary_points_belong_to_the_upper_cell() -> None:
    g = Grid((100, 100), 0.1)
    k = np.arange(100)
    p = np.stack([k * 0.1, k * 0.1], axis=1)  # exactly origin + k * res, as the grid computes it
    cells, inside = g.world_to_cell(p)
    assert inside.all()
    np.testing.assert_array_equal(cells, np.stack([k, k], axis=1))


def test_outside_points_are_reported_never_wrapped() -> None:
    g = Grid((3, 4), 1.0, origin=(0, 0))
    pts = [[-0.5, 1], [4.0, 1], [1, -1e-12], [1, 3.0], [1e300, 1e300], [-1e300, 0.5], [np.nan, 1], [1, np.inf]]
    cells, inside = g.world_to_cell(pts)
    assert not inside.any()
    assert cells[0, 1] == -1 and cells[1, 1] == 4 and cells[2, 0] == -1 and cells[3, 0] == 3
    assert cells[4, 1] > 0 and cells[5, 1] < 0  # far away stays far away, on the right side
    np.testing.assert_array_equal(cells[6:], -1)
    m = GridMap(g, np.zeros((3, 4), bool))
    assert m.is_free(pts).tolist() == [True] * 6 + [False, False]
    assert not GridMap(g.with_border("wall"), np.zeros((3, 4), bool)).is_free(pts).any()


def test_covering_handles_floating_noise() -> None:
    assert Grid.covering((0, 0, 25, 20), 0.1).shape == (200, 250)
    assert Grid.covering((0, 0, 25, 20), 0.05).shape == (400, 500)
    assert Grid.covering((0, 0, 0.3, 0.7), 0.1).shape == (7, 3)
    g = Grid.covering((0, 0, 25.01, 20), 0.1)  # a genuine remainder adds a column
    assert g.shape == (200, 251)
    assert g.bounds[2] >= 25.01
    assert Grid.covering((-5, -5, 5, 5), 0.4, border="wall").border == "wall"


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"shape": (0, 3), "resolution": 1.0}, "shape must be two positive integers"),
        ({"shape": (3, -1), "resolution": 1.0}, "shape must be two positive integers"),
        ({"shape": (2.5, 3), "resolution": 1.0}, "shape must be two positive integers"),
        ({"shape": (math.inf, 3), "resolution": 1.0}, "shape must be two positive integers"),
        ({"shape": (math.nan, 3), "resolution": 1.0}, "shape must be two positive integers"),
        ({"shape": (3,), "resolution": 1.0}, "shape must be two positive integers"),
        ({"shape": 3, "resolution": 1.0}, "shape must be two positive integers"),
        ({"shape": ("3", 3), "resolution": 1.0}, "shape must be two positive integers"),
        ({"shape": (True, 3), "resolution": 1.0}, "shape must be two positive integers"),
        ({"shape": (3, 3), "resolution": 0.0}, "resolution must be a positive finite number, got 0.0"),
        ({"shape": (3, 3), "resolution": -1.0}, "resolution must be a positive finite number, got -1.0"),
        ({"shape": (3, 3), "resolution": math.nan}, "resolution must be a positive finite number, got nan"),
        ({"shape": (3, 3), "resolution": math.inf}, "resolution must be a positive finite number, got inf"),
        ({"shape": (3, 3), "resolution": "a"}, "resolution must be a positive number"),
        ({"shape": (3, 3), "resolution": 1.0, "origin": (0, math.nan)}, "origin must be finite numbers"),
        ({"shape": (3, 3), "resolution": 1.0, "origin": (math.inf, 0)}, "origin must be finite numbers"),
        ({"shape": (3, 3), "resolution": 1.0, "origin": (0, 0, 0)}, r"origin must be two numbers \(x, y\)"),
        ({"shape": (3, 3), "resolution": 1.0, "origin": None}, r"origin must be two numbers \(x, y\)"),
        ({"shape": (3, 3), "resolution": 1.0, "border": "closed"}, "border must be one of"),
    ],
)
def test_bad_grid_parameters(kwargs: dict, match: str) -> None:
    with pytest.raises(ParameterError, match=match):
        Grid(**kwargs)


@pytest.mark.parametrize(
    ("bounds", "resolution", "match"),
    [
        ((0, 0, 1, 1), 0, "resolution must be a positive finite number"),
        ((0, 0, 1, 1), -0.5, "resolution must be a positive finite number"),
        ((0, 0, 1, 1), math.nan, "resolution must be a positive finite number"),
        ((0, 0, 1, 1), math.inf, "resolution must be a positive finite number"),
        ((0, 0, math.nan, 1), 0.1, "bounds must be finite numbers"),
        ((0, 0, math.inf, 1), 0.1, "bounds must be finite numbers"),
        ((0, 0, 0, 1), 0.1, "max > min"),
        ((0, 2, 1, 1), 0.1, "max > min"),
        ((0, 0, 1), 0.1, r"bounds must be \[xmin, ymin, xmax, ymax\]"),
    ],
)
def test_bad_covering_parameters(bounds: tuple, resolution: float, match: str) -> None:
    with pytest.raises(ParameterError, match=match):
        Grid.covering(bounds, resolution)


def test_bad_point_arrays() -> None:
    g = Grid((2, 2), 1.0)
    with pytest.raises(ParameterError, match=r"points must have shape \(N, 2\)"):
        g.world_to_cell([[1, 2, 3]])
    with pytest.raises(ParameterError, match=r"cells must have shape \(N, 2\)"):
        g.cell_to_world([1, 2, 3])


def test_gridmap_validation_and_check_point() -> None:
    g = Grid((2, 3), 1.0)
    with pytest.raises(GridfieldError, match=r"shape \(3, 2\).*grid has shape \(2, 3\)"):
        GridMap(g, np.zeros((3, 2), bool))
    occ = np.zeros((2, 3), bool)
    occ[0, 1] = True
    m = GridMap(g, occ)
    np.testing.assert_array_equal(m.check_point("start", (0.5, 0.5)), [0.5, 0.5])
    with pytest.raises(GridfieldError, match=r"start \(1.5, 0.5\) lies inside an obstacle"):
        m.check_point("start", (1.5, 0.5))
    with pytest.raises(GridfieldError, match=r"goal .* lies outside the map"):
        m.check_point("goal", (5, 5))
    with pytest.raises(ParameterError, match="goal must be finite numbers"):
        m.check_point("goal", (np.nan, 0.5))


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 40), st.integers(1, 40), st.floats(0.0, 1.0), st.integers(0, 2**31 - 1),
       st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_nearest_free_is_the_brute_force_nearest_free_cell(rows: int, cols: int, fill: float, seed: int,
                                                           fx: float, fy: float) -> None:
    """The suggestion for a start inside an obstacle is the free cell nearest to it, checked against
    every free cell of the map (the distance, since equally near cells may tie)."""
    occ = np.random.default_rng(seed).random((rows, cols)) < fill
    gm = GridMap(Grid((rows, cols), 0.5, origin=(-1.0, 2.0)), occ)
    p = np.array([-1.0 + fx * cols * 0.5 * 0.999, 2.0 + fy * rows * 0.5 * 0.999])
    got = gm.nearest_free(p)
    if occ.all():
        assert got is None
        return
    r0, c0 = int((p[1] - 2.0) // 0.5), int((p[0] + 1.0) // 0.5)
    rr, cc = np.nonzero(~occ)
    best = np.min((rr - r0) ** 2 + (cc - c0) ** 2)
    assert got is not None
    gr, gc = gm.grid.cell_of(*got)
    assert not occ[gr, gc]
    assert (gr - r0) ** 2 + (gc - c0) ** 2 == best


def test_a_start_inside_an_obstacle_is_told_the_nearest_free_point() -> None:
    occ = np.zeros((3, 30), bool)
    occ[:, :20] = True
    gm = GridMap(Grid((3, 30), 1.0), occ)
    with pytest.raises(GridfieldError, match=r"start \(5.5, 1.5\) lies inside an obstacle; the nearest free "
                                             r"cell's centre is \(20.5, 1.5\)"):
        gm.check_point("start", (5.5, 1.5))


def test_a_point_next_to_a_closed_pocket_is_also_told_the_nearest_cell_of_the_open_region() -> None:
    """An obstacle drawn as an outline encloses free cells: the nearest free cell can lie in that pocket,
    from which nothing is reachable, so the error names the nearest cell of the largest free region too."""
    occ = np.zeros((20, 20), bool)
    occ[5:12, 5:12] = True      # a solid box with a one-cell hole (a pocket) at its centre
    occ[8, 8] = False
    gm = GridMap(Grid((20, 20), 1.0), occ)
    with pytest.raises(GridfieldError) as e:
        gm.check_point("goal", (7.5, 8.5))
    msg = str(e.value)
    assert "the nearest free cell's centre is (8.5, 8.5), in a pocket of 1 free cell closed off" in msg
    assert msg.endswith("the nearest cell of the map's largest free region (351 cells) is at (4.5, 8.5)")
