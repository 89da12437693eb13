"""Test configuration shared by every test module."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

# Headless plotting everywhere, before anything imports pyplot.
os.environ.setdefault("MPLBACKEND", "Agg")

from hypothesis import HealthCheck, settings

# Property tests run on a 2-core CI machine shared with other jobs: no per-example deadline.
# Two profiles: "gridfield" explores (fresh random examples each run, the local example database
# replays what failed before) for developers; "ci" is derandomized (the same examples on every run,
# no database), so a CI run never fails on an example newly drawn for an unrelated change. `CI` set
# (as `.ci/run` runs) selects "ci"; HYPOTHESIS_PROFILE names either explicitly. Every example an
# exploring run has found is pinned with @example in its test, so the CI profile tests it too.
settings.register_profile(
    "gridfield", deadline=None, max_examples=60, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(
    "ci", parent=settings.get_profile("gridfield"), derandomize=True, database=None, print_blob=True
)
HYPOTHESIS_PROFILE = os.environ.get("HYPOTHESIS_PROFILE") or ("ci" if os.environ.get("CI") else "gridfield")
settings.load_profile(HYPOTHESIS_PROFILE)

REPO = Path(__file__).resolve().parent
#: Externally authored maps (Moving AI, ROS, loader and polygon fixtures) the suite reads, in the repository
#: (tests/data/maps/MANIFEST.md names each file's source and licence; tests/mapdata.py reads them).
TEST_MAPS = REPO / "tests" / "data" / "maps"


@pytest.fixture(scope="session")
def test_maps() -> Path:
    """Path of tests/data/maps, the suite's copy of externally authored maps."""
    return TEST_MAPS


@pytest.fixture(scope="session")
def repo_maps() -> Path:
    """The maps bundled with gridfield (maps/ in the repository)."""
    return REPO / "maps"


@pytest.fixture(autouse=True)
def _doctests_compute_in_process(request: pytest.FixtureRequest):
    """The package's doctests (gridfield.chunked, the stores) compute dask arrays on the synchronous
    scheduler: a test of a dead cluster elsewhere in the same xdist worker can leave a distributed client
    registered as the default, and a doctest computing on it would wait for ever."""
    from _pytest.doctest import DoctestItem

    if not isinstance(request.node, DoctestItem):
        yield
        return
    try:
        import dask
    except ImportError:  # the package's doctests that need dask skip without it
        yield
        return
    with dask.config.set(scheduler="synchronous"):
        yield
