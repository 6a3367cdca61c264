"""Atomic output files and the output directory."""

import io
import os

import numpy as np
import pytest

from flexkane import atomic
from flexkane.atomic import (OutputExistsError, atomic_write_bytes, atomic_write_text,
                             atomic_writer, prepare_output_dir)
from flexkane.errors import ModelError


def test_text_and_bytes_are_written_and_replace_the_previous_file(tmp_path):
    target = tmp_path / "results.csv"
    atomic_write_text(target, "old\n")
    atomic_write_text(target, "t,q1\n0,1\n")
    assert target.read_text() == "t,q1\n0,1\n"
    atomic_write_bytes(target, b"\x00\x01")
    assert target.read_bytes() == b"\x00\x01"
    assert os.listdir(tmp_path) == ["results.csv"]


def test_written_file_gets_the_usual_permissions(tmp_path):
    target = tmp_path / "model.toml"
    atomic_write_text(target, "x = 1\n")
    umask = os.umask(0o022)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask


def test_a_failure_while_writing_keeps_the_previous_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "results.npz"
    target.write_bytes(b"previous")
    with pytest.raises(RuntimeError, match="disk on fire"):
        with atomic_writer(target) as handle:
            handle.write(b"half of the new")
            raise RuntimeError("disk on fire")
    assert target.read_bytes() == b"previous"
    assert os.listdir(tmp_path) == ["results.npz"]


def test_a_failure_of_the_rename_keeps_the_previous_file_and_leaves_no_temporary(
        tmp_path, monkeypatch):
    target = tmp_path / "equations.md"
    target.write_text("previous")

    def failing_replace(source, destination):
        raise OSError("rename refused")

    monkeypatch.setattr(atomic.os, "replace", failing_replace)
    with pytest.raises(OSError, match="rename refused"):
        atomic_write_text(target, "new")
    assert target.read_text() == "previous"
    assert os.listdir(tmp_path) == ["equations.md"]


def test_an_interrupted_write_leaves_no_temporary(tmp_path):
    target = tmp_path / "results.csv"
    with pytest.raises(KeyboardInterrupt):
        with atomic_writer(target, "w") as handle:
            handle.write("t,q1\n")
            raise KeyboardInterrupt
    assert os.listdir(tmp_path) == []


def test_path_mode_serves_libraries_that_open_the_file_themselves(tmp_path):
    target = tmp_path / "results.npz"
    with atomic_writer(target, "path") as temporary:
        assert temporary.parent == tmp_path and temporary.suffix == ".npz"
        np.savez(temporary, t=np.arange(3.0))
    with np.load(target) as data:
        np.testing.assert_array_equal(data["t"], [0.0, 1.0, 2.0])
    assert os.listdir(tmp_path) == ["results.npz"]


def test_file_object_mode_serves_writers_of_file_objects(tmp_path):
    target = tmp_path / "results.npz"
    with atomic_writer(target) as handle:
        np.savez(handle, q=np.ones(2))
    with np.load(io.BytesIO(target.read_bytes())) as data:
        np.testing.assert_array_equal(data["q"], [1.0, 1.0])


def test_an_unknown_mode_is_a_programming_error(tmp_path):
    with pytest.raises(ValueError, match="mode"):
        with atomic_writer(tmp_path / "x", "a"):
            pass


def test_output_dir_is_created_with_its_parents(tmp_path):
    out = prepare_output_dir(tmp_path / "runs" / "arm", force=False)
    assert out.is_dir() and out == tmp_path / "runs" / "arm"


def test_an_existing_empty_output_dir_is_accepted(tmp_path):
    assert prepare_output_dir(tmp_path, force=False) == tmp_path


def test_a_non_empty_output_dir_is_refused_without_force(tmp_path):
    (tmp_path / "results.csv").write_text("old")
    with pytest.raises(OutputExistsError) as info:
        prepare_output_dir(tmp_path, force=False)
    error = info.value
    assert isinstance(error, ModelError)
    assert error.path == "--out"
    assert error.expected == "a new or empty directory (or --force to overwrite)"
    assert error.given == str(tmp_path)
    assert "--force" in str(error)


def test_force_keeps_the_directory_and_its_other_files(tmp_path):
    (tmp_path / "notes.txt").write_text("keep me")
    assert prepare_output_dir(tmp_path, force=True) == tmp_path
    assert (tmp_path / "notes.txt").read_text() == "keep me"


def test_an_existing_file_is_not_an_output_dir(tmp_path):
    path = tmp_path / "out"
    path.write_text("")
    with pytest.raises(ModelError, match="a file of that name exists"):
        prepare_output_dir(path, force=True)


# ------------------------------------------------------------------ signals (a command's stop request)
def _signal_self():
    import os
    import signal

    os.kill(os.getpid(), signal.SIGTERM)


def test_a_signal_while_writing_removes_the_temporary_file_and_keeps_the_old_target(tmp_path):
    import pytest

    from flexkane.atomic import atomic_writer
    from flexkane.interruption import StopRequest

    target = tmp_path / "results.csv"
    target.write_text("old\n")
    with pytest.raises(KeyboardInterrupt), StopRequest():
        with atomic_writer(target, "w") as handle:
            handle.write("new, half written")
            _signal_self()
            handle.write(" never reached\n")
    assert target.read_text() == "old\n" and sorted(p.name for p in tmp_path.iterdir()) == ["results.csv"]


def test_a_signal_during_the_rename_is_honoured_once_the_file_is_complete(tmp_path, monkeypatch):
    import os

    import pytest

    from flexkane import atomic
    from flexkane.interruption import StopRequest

    replace = os.replace

    def replace_after_a_signal(source, destination):
        _signal_self()
        replace(source, destination)

    monkeypatch.setattr(atomic.os, "replace", replace_after_a_signal)
    target = tmp_path / "figure.png"
    with pytest.raises(KeyboardInterrupt), StopRequest():
        atomic.atomic_write_bytes(target, b"complete")
    assert target.read_bytes() == b"complete" and [p.name for p in tmp_path.iterdir()] == ["figure.png"]


def test_a_signal_in_a_deferred_section_is_recorded_not_raised(tmp_path):
    from flexkane.atomic import atomic_write_text
    from flexkane.interruption import StopRequest

    with StopRequest() as stop, stop.deferred():
        atomic_write_text(tmp_path / "a.txt", "a")
        _signal_self()
        atomic_write_text(tmp_path / "b.txt", "b")
        assert stop.requested
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.txt"]


def test_every_file_is_replaced_through_the_one_atomic_write():
    """Outputs and caches alike: no module but flexkane.atomic renames a temporary file over a target."""
    import ast
    import pathlib

    src = pathlib.Path(atomic.__file__).resolve().parent
    renames = []
    for path in sorted(src.rglob("*.py")):
        if path.name == "atomic.py" and path.parent == src:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                    and node.func.attr in ("replace", "rename", "mkstemp") \
                    and getattr(node.func.value, "id", None) in ("os", "tempfile"):
                renames.append(f"{path.relative_to(src)}:{node.lineno}")
    assert not renames, renames


def test_derivation_cache_files_are_written_whole(tmp_path):
    from flexkane import derivation_cache
    from flexkane.builtin import builtin_model

    model = builtin_model("pendulum-beam")
    derivation_cache.cached_derive(model, cache_dir=tmp_path)
    written = [p for p in tmp_path.rglob("*") if p.is_file()]
    assert written and not [p for p in written if p.name.startswith(".")]   # no temporary file left
    umask = os.umask(0o022)
    os.umask(umask)
    assert all(p.stat().st_mode & 0o777 == 0o666 & ~umask for p in written)


def _count_syncs(monkeypatch):
    """Record the fsyncs of atomic: ('file', name) for a file's data, ('dir', path) for a directory."""
    synced = []
    real = os.fsync

    def fsync(fd):
        path = os.readlink(f"/proc/self/fd/{fd}") if os.path.exists("/proc/self/fd") else str(fd)
        synced.append(("dir" if os.path.isdir(path) else "file", path))
        real(fd)

    monkeypatch.setattr(atomic.os, "fsync", fsync)
    return synced


@pytest.mark.skipif(not os.path.exists("/proc/self/fd"), reason="names of open files from /proc")
def test_each_file_syncs_its_data_once_and_its_directory_after_the_rename(tmp_path, monkeypatch):
    synced = _count_syncs(monkeypatch)
    atomic_write_text(tmp_path / "a.csv", "a\n")
    assert [kind for kind, _ in synced] == ["file", "dir"] and synced[1][1] == str(tmp_path)
    assert ".a.csv." in synced[0][1]   # the temporary file's data, before the rename
    synced.clear()
    with atomic_writer(tmp_path / "b.png", "path") as path:
        path.write_bytes(b"png")
    assert [kind for kind, _ in synced] == ["file", "dir"]


@pytest.mark.skipif(not os.path.exists("/proc/self/fd"), reason="names of open files from /proc")
def test_a_batch_syncs_every_file_and_each_directory_once_at_its_end(tmp_path, monkeypatch):
    synced = _count_syncs(monkeypatch)
    other = tmp_path / "cache"
    other.mkdir()
    (tmp_path / "c.csv").write_text("previous")
    with pytest.raises(RuntimeError, match="disk on fire"):
        with atomic.directory_syncs_batched():
            atomic_write_text(tmp_path / "a.csv", "a\n")
            with atomic.directory_syncs_batched():   # nested: the outer batch syncs
                atomic_write_text(tmp_path / "b.csv", "b\n")
            atomic_write_text(other / "x.json", "{}")
            assert [kind for kind, _ in synced] == ["file"] * 3   # no directory yet
            with atomic_writer(tmp_path / "c.csv", "w") as handle:
                handle.write("half")
                raise RuntimeError("disk on fire")
    assert [kind for kind, _ in synced] == ["file"] * 3 + ["dir"] * 2
    assert sorted(path for kind, path in synced if kind == "dir") == sorted([str(tmp_path), str(other)])
    assert (tmp_path / "a.csv").read_text() == "a\n" and (tmp_path / "b.csv").read_text() == "b\n"
    assert (tmp_path / "c.csv").read_text() == "previous"
    assert sorted(os.listdir(tmp_path)) == ["a.csv", "b.csv", "c.csv", "cache"]
    synced.clear()
    atomic_write_text(tmp_path / "d.csv", "d\n")     # after the batch: synced at once again
    assert [kind for kind, _ in synced] == ["file", "dir"]
