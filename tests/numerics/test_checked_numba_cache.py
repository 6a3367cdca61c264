"""Numba's cache files of flexkane's functions are checked before loading: a truncated or changed index or
machine code compiles again with a note, instead of an ``UnpicklingError`` traceback (issue 25 item 5).

A small ``@njit(cache=True)`` function in a file of the test's own stands for the generated modules and
the integrator loops; each import of the file as a new module is a new dispatcher that finds its
machine code in Numba's disk cache, as a new process would.
"""

from __future__ import annotations

import importlib.util
import itertools
import pickle

import numba
import pytest

from flexkane import checked_cache
from flexkane.numerics import checked_numba_cache
from flexkane.numerics.integrate import integrator_signatures

SOURCE = "from numba import njit\n\n\n@njit(cache=True)\ndef twice_plus(x):\n    return 2.0 * x + 0.25\n"
_count = itertools.count()

pytestmark = pytest.mark.skipif(not checked_numba_cache.available(), reason="this Numba's cache classes differ")


@pytest.fixture(autouse=True)
def fresh_notes(monkeypatch):
    monkeypatch.setattr(checked_cache, "_noted", set())


def fresh_import(path, guarded: bool = True):
    """The function of the file at ``path``, from a new module object (a new dispatcher)."""
    spec = importlib.util.spec_from_file_location(f"checked_numba_case_{next(_count)}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    if guarded:
        assert checked_numba_cache.guard_namespace(module.__dict__) == 1
    return module.twice_plus


def cached_function(tmp_path):
    """The file's function compiled once into Numba's disk cache; the paths of its index and data."""
    path = tmp_path / "cached_case.py"
    path.write_text(SOURCE)
    assert fresh_import(path)(1.0) == 2.25
    cache = tmp_path / "__pycache__"
    index, = cache.glob("*.nbi")
    data, = cache.glob("*.nbc")
    return path, index, data


def test_a_function_compiled_with_digests_is_loaded_from_the_cache(tmp_path, capsys):
    path, index, data = cached_function(tmp_path)
    assert checked_cache.digest_path(index).exists() and checked_cache.digest_path(data).exists()
    function = fresh_import(path)
    assert function(2.0) == 4.25
    assert function.stats.cache_hits and not function.stats.cache_misses
    assert capsys.readouterr().err == ""


def test_a_truncated_index_raised_unpickling_error_without_the_guard(tmp_path):
    path, index, _ = cached_function(tmp_path)
    index.write_bytes(index.read_bytes()[:20])
    with pytest.raises((pickle.UnpicklingError, EOFError)):
        fresh_import(path, guarded=False)(1.0)


@pytest.mark.parametrize("damaged", ["index", "data"])
@pytest.mark.parametrize("damage", ["truncated", "one byte changed"])
def test_a_damaged_cache_file_compiles_again_with_a_note(tmp_path, capsys, damaged, damage):
    path, index, data = cached_function(tmp_path)
    target = index if damaged == "index" else data
    content = target.read_bytes()
    if damage == "truncated":
        target.write_bytes(content[:len(content) // 3])
    else:
        middle = len(content) // 2
        target.write_bytes(content[:middle] + bytes([content[middle] ^ 0x01]) + content[middle + 1:])
    function = fresh_import(path)
    assert function(1.0) == 2.25
    assert function.stats.cache_misses     # compiled again, not loaded
    err = capsys.readouterr().err
    assert f"flexkane: note: damaged cache file {target} (Numba's compiled code of cached_case: digest " \
           "mismatch); compiled again" in err and "Traceback" not in err
    again = fresh_import(path)               # stored again, checked: the next process loads it
    assert again(3.0) == 6.25 and again.stats.cache_hits
    assert capsys.readouterr().err == ""


def test_an_entry_is_intact_only_when_its_index_and_data_match_their_digests(tmp_path, capsys):
    path, _, data = cached_function(tmp_path)
    function = fresh_import(path)
    types = (numba.float64,)
    assert checked_numba_cache.entry_intact(function, types)
    assert checked_numba_cache.files_intact(path)
    assert not checked_numba_cache.entry_intact(function, (numba.int32,))     # another signature: not cached
    data.write_bytes(data.read_bytes()[:-1])
    assert not checked_numba_cache.entry_intact(function, types) and not data.exists()
    assert "digest mismatch); compiled again" in capsys.readouterr().err
    assert function(1.0) == 2.25 and function.stats.cache_misses


def test_a_damaged_file_beside_a_module_is_found_before_the_import(tmp_path, capsys):
    path, index, _ = cached_function(tmp_path)
    index.write_bytes(b"")
    assert not checked_numba_cache.files_intact(path) and not index.exists()
    assert f"damaged cache file {index} " in capsys.readouterr().err


def test_a_cache_file_without_a_digest_is_compiled_again(tmp_path, capsys):
    path, index, _ = cached_function(tmp_path)
    checked_cache.digest_path(index).unlink()
    function = fresh_import(path)
    assert function(1.0) == 2.25 and function.stats.cache_misses
    assert "no digest" in capsys.readouterr().err


def test_the_integrator_loops_are_guarded():
    for function, _ in integrator_signatures():
        assert isinstance(function, numba.core.registry.CPUDispatcher)
        assert type(function._cache._cache_file).__name__ == "CheckedIndexDataCacheFile", function


def test_a_file_with_a_matching_digest_that_numba_cannot_read_is_compiled_again(tmp_path, capsys):
    path, index, _ = cached_function(tmp_path)
    checked_cache.write_checked(index, b"not a pickle")
    function = fresh_import(path)
    assert function(1.0) == 2.25 and function.stats.cache_misses
    assert "(Numba's compiled code of cached_case: UnpicklingError); compiled again" in capsys.readouterr().err
