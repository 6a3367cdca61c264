"""The cache of analysis results (flexkane.result_cache): a repeated linearize, campbell or converge is
answered from disk with the same files and lines; a changed value or option, a damaged file or --no-cache
computes again."""

import base64
import json

import pytest

import flexkane.analysis
from flexkane import result_cache
from flexkane.analysis.linearization import Linearization
from flexkane.cli import main

ARM = ["linearize", "flexible-arm", "--n-modes", "1"]


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    """An empty cache of its own (results and derivations), so that the first command computes; the
    notes of damaged cache files printed afresh."""
    from flexkane import checked_cache

    directory = tmp_path / "cache"
    monkeypatch.setenv("FLEXKANE_CACHE_DIR", str(directory))
    monkeypatch.setattr(checked_cache, "_noted", set())
    return directory


@pytest.fixture
def linearizations(monkeypatch):
    """Counts the numeric linear models formed (the Jacobians and their evaluation)."""
    calls = []
    at = Linearization.at

    def counted(self, *args, **kwargs):
        calls.append(self.model.name)
        return at(self, *args, **kwargs)

    monkeypatch.setattr(Linearization, "at", counted)
    return calls


def run(argv, out, capsys):
    """Exit code, printed lines but the last (which names ``out``) and the files written, by name."""
    code = main([*argv, "--out", str(out)])
    printed = capsys.readouterr().out.splitlines()
    assert printed[-1].endswith(str(out))
    return code, printed[:-1], {p.name: p.read_bytes() for p in sorted(out.iterdir())}


def stored_files(cache_dir):
    return sorted((cache_dir / "analyses").glob("*.json"))


def test_repeated_linearize_is_answered_from_the_cache_with_the_same_files_and_lines(
        cache_dir, linearizations, tmp_path, capsys):
    first = run(ARM, tmp_path / "first", capsys)
    assert first[0] == 0 and len(linearizations) == 1
    second = run(ARM, tmp_path / "second", capsys)
    assert len(linearizations) == 1          # no Jacobian formed or evaluated again
    assert second == first
    assert sorted(first[2]) == ["linear_model.mat", "linear_model.npz", "mode_shapes.png", "modes.csv"]


def test_files_from_the_cache_are_those_of_a_computation_without_it(cache_dir, linearizations, tmp_path, capsys):
    run(ARM, tmp_path / "stored", capsys)
    cached = run(ARM, tmp_path / "cached", capsys)
    fresh = run([*ARM, "--no-cache"], tmp_path / "fresh", capsys)
    assert len(linearizations) == 2          # --no-cache computes
    assert fresh == cached


def test_no_cache_neither_reads_nor_stores_a_result(cache_dir, linearizations, tmp_path, capsys):
    run([*ARM, "--no-cache"], tmp_path / "a", capsys)
    run([*ARM, "--no-cache"], tmp_path / "b", capsys)
    assert len(linearizations) == 2 and stored_files(cache_dir) == []


@pytest.mark.parametrize("change", [["--set", "EI=13"], ["--set", "m_tip=0.3"], ["--about", "rest"],
                                    ["--n-modes", "2"], ["--export", "control"], ["--t0", "1.0"]],
                         ids=["stiffness", "payload", "operating-point", "mode-count", "export", "time"])
def test_a_changed_value_or_option_is_computed_again(cache_dir, linearizations, tmp_path, capsys, change):
    base = run(ARM, tmp_path / "base", capsys)
    changed = run([*ARM, *change], tmp_path / "changed", capsys)
    assert len(linearizations) == 2
    assert changed[0] == 0 and len(stored_files(cache_dir)) == 2
    assert changed[1:] != base[1:]


def _rewrite(path, edit):
    stored = json.loads(path.read_text())
    edit(stored)
    path.write_text(json.dumps(stored))


def _flip_a_byte_of_a_file(stored):
    data = bytearray(base64.b64decode(stored["files"]["modes.csv"]))
    data[10] ^= 1
    stored["files"]["modes.csv"] = base64.b64encode(bytes(data)).decode()


@pytest.mark.parametrize("damage", ["truncated", "not-json", "changed-byte", "changed-line", "other-key"])
def test_a_damaged_cached_result_is_computed_again_with_a_note(cache_dir, linearizations, tmp_path, capsys, damage):
    first = run(ARM, tmp_path / "first", capsys)
    (path,) = stored_files(cache_dir)
    if damage == "truncated":
        path.write_bytes(path.read_bytes()[:1000])
    elif damage == "not-json":
        path.write_bytes(b"\x00\xff" * 50)
    elif damage == "changed-byte":
        _rewrite(path, _flip_a_byte_of_a_file)
    elif damage == "changed-line":
        _rewrite(path, lambda s: s["lines"].__setitem__(0, "flexible-arm: a line edited by hand"))
    else:
        _rewrite(path, lambda s: s.__setitem__("key", "0" * 64))
    code = main([*ARM, "--out", str(tmp_path / "again")])
    captured = capsys.readouterr()
    assert code == 0 and len(linearizations) == 2
    assert "damaged cache file" in captured.err and "computed again" in captured.err and str(path) in captured.err
    assert {p.name: p.read_bytes() for p in (tmp_path / "again").iterdir()} == first[2]
    assert result_cache.load_result(path.stem) is not None     # replaced by the new result


def test_a_stored_file_name_with_a_directory_is_refused(cache_dir, tmp_path, capsys):
    key = "a" * 64
    result_cache.store_result(key, result_cache.AnalysisResult({"../outside.csv": b"x"}, ["line"]))
    assert result_cache.load_result(key) is None
    assert "damaged cache file" in capsys.readouterr().err


def test_only_the_newest_results_are_kept(cache_dir, monkeypatch):
    monkeypatch.setattr(result_cache, "LIMIT", 3)
    keys = [f"{k:064x}" for k in range(5)]
    for key in keys:
        result_cache.store_result(key, result_cache.AnalysisResult({"a.csv": key.encode()}, []))
    assert [p.stem for p in stored_files(cache_dir)] == sorted(keys[2:])


def _counting(monkeypatch, name):
    calls = []
    function = getattr(flexkane.analysis, name)

    def counted(*args, **kwargs):
        calls.append(args)
        return function(*args, **kwargs)

    monkeypatch.setattr(flexkane.analysis, name, counted)
    return calls


@pytest.mark.parametrize("function, argv, changed, files", [
    ("campbell_diagram", ["campbell", "spin-up", "--n-modes", "1", "--spin", "0:2:2"], ["--spin", "0:3:2"],
     ["campbell.csv", "campbell.json", "campbell.png", "campbell_modes.csv"]),
    ("convergence_study", ["converge", "flexible-arm", "--n-modes", "1..2", "--count", "2"], ["--set", "rho=0.7"],
     ["convergence.csv", "convergence_verdicts.csv"])], ids=["campbell", "converge"])
def test_repeated_spin_and_mode_count_studies_are_answered_from_the_cache(
        cache_dir, tmp_path, capsys, monkeypatch, function, argv, changed, files):
    calls = _counting(monkeypatch, function)
    first = run(argv, tmp_path / "first", capsys)
    second = run(argv, tmp_path / "second", capsys)
    assert len(calls) == 1 and second == first and sorted(first[2]) == files
    third = run([*argv, *changed], tmp_path / "third", capsys)
    assert len(calls) == 2 and third[2][files[0]] != first[2][files[0]]
