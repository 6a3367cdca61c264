"""A command runs with rare full passes of Python's collector (``long_lived_objects``): objects that
outlive the young generations are not walked again and again; cyclic garbage is still freed; the
thresholds are restored after the command."""

from __future__ import annotations

import gc

import pytest

from flexkane.garbage_collection import FULL_PASS_EVERY, long_lived_objects


@pytest.fixture
def passes():
    """Generations of the collector's passes, as they happen."""
    seen = []

    def record(phase, info):
        if phase == "start":
            seen.append(info["generation"])
    gc.callbacks.append(record)
    yield seen
    gc.callbacks.remove(record)


def keep_many() -> list:
    """Long-lived containers, as the libraries a command imports (each tracked by the collector): half
    as many again as the objects alive, so that CPython's default rule (a full pass when the old
    generation grew by a quarter) makes full passes."""
    return [[k] for k in range(len(gc.get_objects()) // 2 + 100_000)]


def test_no_full_pass_over_long_lived_objects_within_and_full_passes_outside(passes):
    gc.collect()
    del passes[:]
    before = gc.get_threshold()
    with long_lived_objects():
        assert gc.get_threshold() == (before[0], before[1], max(before[2], FULL_PASS_EVERY))
        kept = keep_many()
        assert 0 in passes and 1 in passes and 2 not in passes   # young and middle generations only
    assert gc.get_threshold() == before
    del passes[:]
    more = keep_many()
    assert 2 in passes   # the same growth outside: full passes (CPython's default thresholds)
    del kept, more


def test_cyclic_garbage_is_still_freed_within():
    class Node:
        pass

    # (type(o), not isinstance(o, ...): gc's objects may be weak proxies to dead objects, which
    # isinstance would dereference)
    with long_lived_objects():
        gc.collect()
        before = sum(type(o) is Node for o in gc.get_objects())
        for _ in range(5000):   # cycles made and dropped: the young generation's passes free them
            a, b = Node(), Node()
            a.other, b.other = b, a
        del a, b
        gc.collect(1)
        assert sum(type(o) is Node for o in gc.get_objects()) - before < 1000


def test_the_command_line_runs_its_commands_within(monkeypatch, capsys):
    import flexkane.commands.check as check
    from flexkane.cli import main

    seen = []
    monkeypatch.setattr(check, "_handle", lambda args: seen.append(gc.get_threshold()) or 0)
    before = gc.get_threshold()
    assert main(["check", "falling-beam"]) == 0
    assert seen == [(before[0], before[1], max(before[2], FULL_PASS_EVERY))]
    assert gc.get_threshold() == before
