"""A generated module is imported only as generated: its file is compared with its text just before the
import, and Python's bytecode of it (``__pycache__/*.pyc`` in flexkane's cache) carries a digest
(issue 25 item 5: a changed byte in a cached module changed the results)."""

from __future__ import annotations

import sys

import pytest

from flexkane import checked_cache
from flexkane.numerics import build_module, generate_rhs_source, structure_key


@pytest.fixture(autouse=True)
def fresh_notes(monkeypatch):
    monkeypatch.setattr(checked_cache, "_noted", set())


def build_afresh(source, key, cache):
    """:func:`build_module` as a new process would (the module not imported yet)."""
    sys.modules.pop(f"flexkane_generated_{key}", None)
    return build_module(source, key, cache)


def test_a_changed_module_file_is_written_again_before_the_import(tmp_path, models, capsys):
    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, "changed-file")
    module = build_afresh(source, key, tmp_path)
    path = tmp_path / key / f"flexkane_generated_{key}.py"
    text = path.read_text()
    path.write_text(text.replace("def rhs(", "def rhs_changed(", 1))
    again = build_afresh(source, key, tmp_path)
    assert path.read_text() == text and hasattr(again, "rhs") and again is not module
    assert f"flexkane: note: damaged cache file {path} (a generated module: its text is not the one " \
           "generated); written again" in capsys.readouterr().err


def test_damaged_bytecode_of_a_generated_module_is_compiled_again(tmp_path, models, monkeypatch, capsys):
    monkeypatch.setattr(sys, "dont_write_bytecode", False)
    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, "bytecode")
    build_afresh(source, key, tmp_path)
    pyc, = (tmp_path / key / "__pycache__").glob("*.pyc")
    assert checked_cache.digest_path(pyc).exists()
    intact = pyc.read_bytes()
    pyc.write_bytes(intact[:len(intact) // 2])     # a bad marshal: ValueError from Python's own loader
    module = build_afresh(source, key, tmp_path)
    assert hasattr(module, "rhs") and hasattr(module, "system_rhs")
    assert f"damaged cache file {pyc} (Python's bytecode of a generated module: digest mismatch); compiled " \
           "again" in capsys.readouterr().err
    assert pyc.read_bytes() == intact      # stored again
