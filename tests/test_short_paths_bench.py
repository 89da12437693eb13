"""Issue 46's benchmark pieces (benchmarks/potential_real.py): the exact collision check the short-paths
table counts, and the generated maps, against hand-made cases."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from gridfield.core.grid import Grid, GridMap

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.fixture(scope="module")
def potential_real():
    sys.path.insert(0, str(BENCH))
    try:
        import potential_real

        yield potential_real
    finally:
        sys.path.remove(str(BENCH))


def test_exact_collision_counts_interiors_and_pinches_not_touches(potential_real):
    occ = np.zeros((4, 4), bool)
    occ[1, 1] = True
    gm = GridMap(Grid((4, 4), 0.5, origin=(10.0, 20.0), border="wall"), occ)
    world = lambda cells: np.asarray(cells, dtype=float) * 0.5 + (10.0, 20.0)  # noqa: E731
    hit = potential_real.exact_collision
    assert hit(gm, world([[0.5, 0.5], [2.5, 2.5]]))  # through the blocked square
    assert not hit(gm, world([[0.5, 1.5], [1.5, 2.5]]))  # touches its corner (1, 2) only
    assert not hit(gm, world([[0.5, 2.0], [3.5, 2.0]]))  # along its top edge
    assert hit(gm, world([[0.5, 1.5], [1.6, 2.5]]))  # a hair into it
    pinch = occ.copy()
    pinch[2, 2] = True  # diagonal to (1, 1): they meet at the vertex (2, 2)
    assert hit(GridMap(gm.grid, pinch), world([[1.5, 2.5], [2.5, 1.5]]))
    assert hit(gm, world([[0.5, 0.5], [0.5, 4.5]]))  # out of a wall-bordered grid
    assert not hit(GridMap(Grid((4, 4), 0.5, origin=(10.0, 20.0), border="open"), occ), world([[0.5, 0.5], [0.5, 4.5]]))


def test_generated_maps_are_deterministic_and_have_free_space(potential_real):
    for spec in potential_real.GENERATED[:3]:
        a, b = potential_real.generated_map(spec), potential_real.generated_map(spec)
        assert np.array_equal(a.occupied, b.occupied) and a.shape == (256, 256)
        assert 0.05 < a.occupied.mean() < 0.6
    with pytest.raises(ValueError, match="unknown"):
        potential_real.generated_map("caves:1")
