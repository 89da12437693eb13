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


#: Test modules whose tests open network clients of dependencies on 127.0.0.1: tornado's websocket client
#: (the web explorer's tests; the explorer itself runs in a subprocess) and distributed's comm pool (the
#: in-process Dask clusters; gridfield's own Client is closed by the CLI). Those libraries leave some closed
#: sockets to the garbage collector, whose ResourceWarning then surfaces in whatever test runs a collection
#: later. They are collected right after the test that made them, with that one warning ignored there.
CLIENT_SOCKET_MODULES = {"test_explore_web", "test_store_cli", "test_store", "test_chunked", "test_bad_input2",
                         "test_sweep_cluster", "test_sweep"}


@pytest.fixture(autouse=True)
def _collect_dependency_sockets(request: pytest.FixtureRequest):
    yield
    module = getattr(request.node, "module", None)
    if module is None or module.__name__.rsplit(".", 1)[-1] not in CLIENT_SOCKET_MODULES:
        return
    import gc
    import warnings

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=r"unclosed <socket\.socket", category=ResourceWarning)
        gc.collect()
