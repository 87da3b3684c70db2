"""Shared fixtures: the package from addon/ and the shared hair files next to the repository."""

import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "addon"))

SHARED_DATA = REPO.parent / "shared" / "data"


@pytest.fixture(scope="session")
def shared_data():
    """../shared/data/hairutil; a fresh clone has no ../shared, which is an error, not a skip."""
    folder = SHARED_DATA / "hairutil"
    if not folder.is_dir():
        pytest.fail(f"shared test data missing: {folder} (tests need ../shared/data next to the repository)")
    return folder
