"""Test configuration shared by every test module."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

# Headless plotting everywhere, before anything imports pyplot.
os.environ.setdefault("MPLBACKEND", "Agg")

from hypothesis import HealthCheck, settings

# Property tests run on a 2-core CI machine shared with other jobs: no per-example deadline.
settings.register_profile(
    "gridfield", deadline=None, max_examples=60, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("gridfield")

REPO = Path(__file__).resolve().parent
#: Externally authored maps (Moving AI, ROS, polygon fixtures) beside the repository.
SHARED_MAPS = REPO.parent / "shared" / "maps"


@pytest.fixture(scope="session")
def shared_maps() -> Path:
    """Path of ../shared/maps; the suite needs it (CI checks out shared/ beside the repository)."""
    if not SHARED_MAPS.is_dir():
        pytest.fail(f"test data folder {SHARED_MAPS} is missing: check out shared/ beside the repository")
    return SHARED_MAPS


@pytest.fixture(scope="session")
def repo_maps() -> Path:
    """The maps bundled with gridfield (maps/ in the repository)."""
    return REPO / "maps"
