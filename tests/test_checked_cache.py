"""Cache files carry their digest and are used only when it matches (issue 25 item 5: a changed byte in a
cached file changed the results with exit 0)."""

from __future__ import annotations

import hashlib

import pytest

from flexkane import checked_cache
from flexkane.checked_cache import MAX_DIGESTS, digest_path, read_checked, write_checked


@pytest.fixture(autouse=True)
def fresh_notes(monkeypatch):
    """Each test sees the notes of its own damage (they are printed once per process)."""
    monkeypatch.setattr(checked_cache, "_noted", set())


def read(path):
    return read_checked(path, "the test's data", "made again")


def test_a_file_written_with_its_digest_reads_back_and_lists_its_sha256(tmp_path, capsys):
    path = write_checked(tmp_path / "a.json", b'{"x": 1}')
    assert read(path) == b'{"x": 1}'
    assert hashlib.sha256(b'{"x": 1}').hexdigest() in digest_path(path).read_text().split()
    assert capsys.readouterr().err == ""


def test_a_missing_file_is_a_plain_miss_without_a_note(tmp_path, capsys):
    assert read(tmp_path / "missing.pkl") is None
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("damage, reason", [
    (lambda data: data.replace(b"0.5", b"0.7"), "digest mismatch"),     # one changed byte
    (lambda data: data[:len(data) // 2], "digest mismatch"),            # truncated
])
def test_a_damaged_file_is_refused_deleted_and_noted_once(tmp_path, capsys, damage, reason):
    path = write_checked(tmp_path / "a.module.py", b"x = (0.5)*L + b\n")
    path.write_bytes(damage(path.read_bytes()))
    assert read(path) is None
    assert not path.exists() and not digest_path(path).exists()
    err = capsys.readouterr().err
    assert err.startswith(f"flexkane: note: damaged cache file {path} ")
    assert f"the test's data: {reason}); made again" in err
    write_checked(path, b"y = 1\n")
    path.write_bytes(b"y = 2\n")
    assert read(path) is None
    assert capsys.readouterr().err == ""     # the same kind of file: noted once per process


def test_a_file_without_its_digest_is_refused(tmp_path, capsys):
    path = tmp_path / "old.pkl"
    path.write_bytes(b"written without a digest")
    assert read(path) is None
    assert "(the test's data: no digest)" in capsys.readouterr().err


def test_every_content_written_to_a_path_stays_valid_there(tmp_path):
    """Two processes writing one path (two compiling children save one index): whichever content the
    file holds when it is read, its digest was listed before it got there."""
    path = write_checked(tmp_path / "f.nbi", b"first")
    write_checked(path, b"second")
    assert read(path) == b"second"
    path.write_bytes(b"first")        # the other writer's rename came last
    assert read(path) == b"first"


def test_the_list_of_digests_stays_short(tmp_path):
    path = tmp_path / "f.nbi"
    for k in range(3 * MAX_DIGESTS):
        write_checked(path, f"content {k}".encode())
    assert len(digest_path(path).read_text().split()) <= MAX_DIGESTS
    assert read(path) == f"content {3 * MAX_DIGESTS - 1}".encode()
