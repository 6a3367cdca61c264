"""Shared fixtures: built-in models, and an isolated cache directory for compiled models."""

import os
import pathlib
import tempfile

import pytest

# Compiled models go to one cache directory per test session (Numba's on-disk cache included), so the
# suite never depends on, nor pollutes, the user's cache.
os.environ.setdefault("FLEXKANE_CACHE_DIR", tempfile.mkdtemp(prefix="flexkane-test-cache-"))

ROOT = pathlib.Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def examples_dir() -> pathlib.Path:
    return ROOT / "examples"
