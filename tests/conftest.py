"""Shared fixtures: built-in models, and an isolated cache directory for compiled models."""

import os
import pathlib
import tempfile

import pytest

# Compiled models go to one cache directory per test session (Numba's on-disk cache included), so the
# suite never depends on, nor pollutes, the user's cache. With pytest-xdist the controller imports this
# file before it starts its workers, which inherit the variable: the workers share the one cache, as a
# sweep's Dask workers do (derivations, generated modules and Numba's files are written atomically), and
# a structure one worker compiled the other loads.
os.environ.setdefault("FLEXKANE_CACHE_DIR", tempfile.mkdtemp(prefix="flexkane-test-cache-"))

ROOT = pathlib.Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def examples_dir() -> pathlib.Path:
    return ROOT / "examples"
