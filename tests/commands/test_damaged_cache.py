"""A damaged cache is made again, with a note, and gives the numbers of an intact one (issue 25 item 5).

Reproducers of two hostile-file defects: a changed constant in the cached generated code of a structure
changed the results with exit 0; a truncated Numba cache file was an ``UnpicklingError`` traceback. Each
test damages one kind of file of a cache that a first run filled, runs ``flexkane run`` again in a new
interpreter and compares its ``results.csv`` with the first run's, byte for byte (one installation).
"""

from __future__ import annotations

import subprocess
import sys

import pytest
from child_env import child_env

from flexkane.checked_cache import discard

RUN = ["run", "falling-beam", "--t-end", "0.3", "--dt-out", "0.01", "--no-plots", "--force"]


def run_cli(cache, out, **variables) -> str:
    """``flexkane run`` with the cache ``cache``; its standard error (exit 0 asserted)."""
    done = subprocess.run([sys.executable, "-m", "flexkane", *RUN, "--out", str(out)], capture_output=True,
                          text=True, env=child_env(FLEXKANE_CACHE_DIR=str(cache), **variables), timeout=900)
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr
    return done.stderr


@pytest.fixture(scope="module")
def filled(tmp_path_factory):
    """A cache that holds falling-beam's equations, code, numbers and machine code; the first run's results."""
    root = tmp_path_factory.mktemp("damaged-cache")
    cache = root / "cache"
    run_cli(cache, root / "first")
    run_cli(cache, root / "second")      # the numbers of the run are stored by then
    return cache, (root / "first" / "results.csv").read_bytes()


def rerun(filled, tmp_path) -> str:
    """Run again on the (damaged) cache: the results are the first run's; return the standard error."""
    cache, expected = filled
    err = run_cli(cache, tmp_path / "again")
    assert (tmp_path / "again" / "results.csv").read_bytes() == expected
    return err


def one(cache, pattern: str):
    found = sorted(cache.glob(pattern))
    assert len(found) == 1, (pattern, found)
    return found[0]


def truncate(path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[:len(data) // 2])


def test_a_changed_constant_in_the_cached_generated_code_is_generated_again(filled, tmp_path):
    cache, _ = filled
    module = one(cache, "derived/*.module.py")
    text = module.read_text()
    assert text.count("(0.5)*L") >= 1       # the beam's half length in its centre of mass
    module.write_text(text.replace("(0.5)*L", "(0.7)*L"))
    err = rerun(filled, tmp_path)
    assert f"flexkane: note: damaged cache file {module} (the generated code of this model structure: digest " \
           "mismatch); generated again" in err
    assert "(0.7)*L" not in module.read_text()


@pytest.mark.parametrize("pattern, what", [
    ("derived/*.pkl", "the equations of this model structure"),
    ("derived/*.manifest.json", "the run manifest of this model structure"),
    ("derived/*.numbers/*.json", "the numbers of this model"),
    ("derived/*.module.py", "the generated code of this model structure"),
])
def test_a_truncated_derived_file_is_made_again_with_a_note(filled, tmp_path, pattern, what):
    cache, _ = filled
    path = one(cache, pattern)
    truncate(path)
    if path.suffix == ".pkl":     # a run whose numbers are cached needs no equations: make it need them
        numbers = one(cache, "derived/*.numbers/*.json")
        discard(numbers)
    err = rerun(filled, tmp_path)
    assert f"damaged cache file {path} ({what}: digest mismatch)" in err


def test_truncated_numba_files_of_a_model_compile_again_with_a_note(filled, tmp_path):
    cache, _ = filled
    index = one(cache, "*/__pycache__/flexkane_generated_*.rhs-*.nbi")
    data = one(cache, "*/__pycache__/flexkane_generated_*.outputs-*.nbc")
    truncate(index)
    truncate(data)
    err = rerun(filled, tmp_path)
    assert "flexkane: note: damaged cache file " in err and "(Numba's compiled code of flexkane_generated_" in err
    assert "compiled again" in err
    assert "compiling the right-hand side of this model structure" in err   # found before the import: a child
    assert rerun(filled, tmp_path / "repaired") == ""      # stored again with digests


@pytest.mark.slow
def test_truncated_numba_files_of_the_integrators_compile_again_with_a_note(tmp_path):
    """With Numba's cache in a directory of the test's own (``NUMBA_CACHE_DIR``), so that the package's is
    not touched: the integrators compile there first (seconds)."""
    numba_cache = tmp_path / "numba"
    cache = tmp_path / "cache"
    run_cli(cache, tmp_path / "first", NUMBA_CACHE_DIR=str(numba_cache))
    run_cli(cache, tmp_path / "second", NUMBA_CACHE_DIR=str(numba_cache))
    expected = (tmp_path / "first" / "results.csv").read_bytes()
    truncate(one(numba_cache, "**/dop853.dop853_chunk-*.nbi"))
    truncate(one(numba_cache, "**/radau.radau5_chunk-*.nbc"))
    err = run_cli(cache, tmp_path / "again", NUMBA_CACHE_DIR=str(numba_cache))
    assert "(Numba's compiled code of dop853: digest mismatch); compiled again" in err
    assert (tmp_path / "again" / "results.csv").read_bytes() == expected
    truncate(one(numba_cache, "**/radau.radau5_chunk-*.nbc"))    # the data alone: found when loaded
    err = run_cli(cache, tmp_path / "last", NUMBA_CACHE_DIR=str(numba_cache))
    assert "(Numba's compiled code of radau: digest mismatch); compiled again" in err
    assert (tmp_path / "last" / "results.csv").read_bytes() == expected
