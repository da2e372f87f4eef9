"""Shared fixtures: the shared real BVH folder, and small hand-made skeletons with known geometry."""

from pathlib import Path

import pytest

from tests.helpers import SHARED_BVH, SHARED_LIBRARY


@pytest.fixture(scope="session")
def shared_bvh_dir() -> Path:
    """The shared real BVH files (skipped when the folder is absent)."""
    if not SHARED_BVH.is_dir():
        pytest.skip(f"shared BVH data not found at {SHARED_BVH}")
    return SHARED_BVH


@pytest.fixture(scope="session")
def shared_library_dir() -> Path:
    """The shared BVH library (Bandai gestures ... and ReActIdle files; skipped when the folder is absent)."""
    if not SHARED_LIBRARY.is_dir():
        pytest.skip(f"shared BVH library not found at {SHARED_LIBRARY}")
    return SHARED_LIBRARY
