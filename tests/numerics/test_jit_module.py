"""Generated modules on disk: keys, atomic writing, and Numba's cache across processes."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from child_env import child_env

from flexkane.numerics import build_module, generate_rhs_source, structure_key
from flexkane.numerics.dop853 import dop853_chunk
from flexkane.numerics.jit_module import compose_module_source
from flexkane.numerics.system_function import system_function


def test_structure_key_is_deterministic_and_depends_on_every_part():
    assert structure_key("a", "b") == structure_key("a", "b")
    assert structure_key("a", "b") != structure_key("ab")
    assert len(structure_key("x")) == 32


def test_same_key_in_one_process_returns_the_same_module(tmp_path, models):
    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, "same-process")
    first = build_module(source, key, tmp_path)
    assert build_module(source, key, tmp_path) is first
    path = tmp_path / key / f"flexkane_generated_{key}.py"
    assert Path(first.__file__) == path
    assert not [p for p in path.parent.iterdir() if p.suffix == ".tmp"]


def test_invalid_key_is_rejected(tmp_path):
    with pytest.raises(ValueError, match="key"):
        build_module("", "../escape", tmp_path)


_CHILD = textwrap.dedent("""
    import json, sys, time
    tic = time.perf_counter()
    import numpy as np
    from flexkane.numerics import build_module
    from flexkane.numerics.dop853 import dop853_chunk
    from flexkane.numerics.system_function import system_function
    source, key, cache = sys.argv[1:4]
    module = build_module(open(source).read(), key, cache)
    imported = time.perf_counter()
    t = np.linspace(0.0, 1.0, 11)
    Y = np.empty((11, 2))
    out = dop853_chunk(system_function(module), 0.0, np.array([1.0, 0.0]), 0.0, t,
                       np.array([1.0, 1.0, 9.81]), 1e-8, np.full(2, 1e-8), 10000, Y, -np.inf)
    done = time.perf_counter()
    print(json.dumps({"import": imported - tic, "first_call": done - imported,
                      "status": int(out[3]), "y_end": Y[-1].tolist()}))
""")


def _run_child(script, source_file, key, cache):
    out = subprocess.run([sys.executable, str(script), str(source_file), key, str(cache)],
                         capture_output=True, text=True, env=child_env(), check=True, timeout=300)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_second_process_loads_numba_cache(tmp_path, models, pendulum_module):
    """A child process building the session's pendulum key loads the compiled code from disk."""
    dop853_chunk(system_function(pendulum_module), 0.0, np.array([1.0, 0.0]), 0.0,
                 np.linspace(0.0, 1.0, 11), np.array([1.0, 1.0, 9.81]), 1e-8, np.full(2, 1e-8), 10000,
                 np.empty((11, 2)), -np.inf)  # compiled (and cached) in this process
    path = Path(pendulum_module.__file__)
    key = path.parent.name
    source = generate_rhs_source(models.pendulum())
    assert structure_key(source) == key
    source_file = tmp_path / "source.py"
    source_file.write_text(source)
    script = tmp_path / "child.py"
    script.write_text(_CHILD)
    warm = _run_child(script, source_file, key, path.parents[1])
    print(f"\ncached load in a new process: import {warm['import']:.2f} s, "
          f"first call {warm['first_call']:.2f} s")
    assert warm["status"] == 0
    assert list((path.parent / "__pycache__").glob("*.nbi"))


_BUILDER = textwrap.dedent("""
    import sys
    from flexkane.numerics import build_module
    source, key, cache = sys.argv[1:4]
    module = build_module(open(source).read(), key, cache)
    print(module.NQ + module.NU)
""")


def test_processes_building_the_same_key_at_once_leave_one_intact_file(tmp_path, models):
    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, "race")
    (tmp_path / "source.py").write_text(source)
    (tmp_path / "builder.py").write_text(_BUILDER)
    children = [subprocess.Popen([sys.executable, str(tmp_path / "builder.py"),
                                  str(tmp_path / "source.py"), key, str(tmp_path / "cache")],
                                 stdout=subprocess.PIPE, text=True, env=child_env())
                for _ in range(2)]
    outputs = [child.communicate(timeout=300)[0] for child in children]
    assert [child.returncode for child in children] == [0, 0]
    assert [out.strip() for out in outputs] == ["2", "2"]
    written = (tmp_path / "cache" / key / f"flexkane_generated_{key}.py").read_text()
    assert written == compose_module_source(source, key)
    assert not list((tmp_path / "cache" / key).glob("*.tmp"))


@pytest.mark.slow
def test_a_new_structure_is_compiled_by_a_child_process_into_the_cache(tmp_path, models):
    """With in_subprocess, a child process compiles the right-hand side into Numba's cache (and marks
    the module compiled); this process then loads it from there. The integrators are the package's,
    not the module's."""
    from flexkane.numerics import jit_module

    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, "child-compile")
    announced = []
    with jit_module.compile_in_subprocess(announce=lambda: announced.append(True)):
        module = build_module(source, key, tmp_path)
    directory = tmp_path / key
    cached = {p.name.split(".")[1].split("-")[0] for p in (directory / "__pycache__").glob("*.nbi")}
    assert "rhs" in cached and not cached & {"fd_jacobian", "dop853_chunk", "radau5_chunk"}
    assert jit_module.integrators_compiled()
    assert announced == [True] and list(directory.glob("*.compiled"))
    dy = np.empty(2)
    assert module.rhs(0.0, np.array([1.0, 0.0]), np.array([1.0, 1.0, 9.81]), dy) == 0
    assert np.all(np.isfinite(dy))
    with jit_module.compile_in_subprocess(announce=lambda: announced.append(True)):
        build_module(source, key, tmp_path)                 # compiled already: no child, no announce
    assert announced == [True]


def test_code_too_deeply_nested_for_python_is_a_model_error(tmp_path):
    from flexkane.errors import ModelError
    from flexkane.numerics.jit_module import build_module

    deep = "+".join(["1.0"] * 200_000)   # a sum nested deeper than Python's compiler recurses
    with pytest.raises(ModelError, match="model size"):
        build_module(f"X = {deep}\n", "deeply_nested", tmp_path, in_subprocess=False)


@pytest.mark.parametrize("model_compiled, integrators, callbacks, expected", [
    (True, False, "both", ["integrators"]),          # first run of an installation, model known
    (False, False, "both", ["integrators", "model"]),
    (False, False, "one", ["model"]),                # one callback announces once
    (False, True, "both", ["model"]),
    (True, True, "both", []),                        # nothing to compile: no child
])
def test_the_child_compiles_and_announces_what_is_missing(tmp_path, monkeypatch, models, model_compiled,
                                                          integrators, callbacks, expected):
    from flexkane.numerics import jit_module

    children = []
    monkeypatch.setattr(jit_module, "_compile_in_child",
                        lambda path, meanwhile=None, loops=True: children.append(path) or True)
    monkeypatch.setattr(jit_module, "integrators_compiled", lambda: integrators)
    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, f"announce-{model_compiled}-{integrators}-{callbacks}")
    path = tmp_path / key / f"flexkane_generated_{key}.py"
    if model_compiled:  # the marker a child leaves after compiling the module
        path.parent.mkdir(parents=True)
        text = compose_module_source(source, key)
        path.write_text(text, encoding="utf-8")
        jit_module._write_marker(path)
    said = []
    extra = {"announce_integrators": lambda: said.append("integrators")} if callbacks == "both" else {}
    with jit_module.compile_in_subprocess(announce=lambda: said.append("model"), **extra):
        build_module(source, key, tmp_path)
    assert said == (expected if callbacks == "both" else expected[:1])
    assert children == ([path] if expected else [])


@pytest.mark.parametrize("fork", [True, False], ids=["fork", "new-interpreter"])
def test_a_failing_compile_child_reports_failure_and_leaves_no_marker(tmp_path, monkeypatch, fork):
    from flexkane.numerics import jit_module

    if fork and not jit_module._fork_allowed():
        pytest.skip("no fork here (not Linux, or other threads)")
    monkeypatch.setattr(jit_module, "_fork_allowed", lambda: fork)
    path = tmp_path / "flexkane_generated_broken.py"
    path.write_text("raise RuntimeError('a module that cannot be imported')\n", encoding="utf-8")
    meanwhile = []
    assert jit_module._compile_in_child(path, meanwhile=lambda: meanwhile.append(True)) is False
    assert meanwhile == [True] and not jit_module._compiled_marker(path).exists()


def test_a_forked_child_compiles_a_new_structure_into_the_cache(tmp_path, models):
    from flexkane.numerics import jit_module

    if not jit_module._fork_allowed():
        pytest.skip("no fork here (not Linux, or other threads)")
    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, "forked-child")
    path = tmp_path / key / f"flexkane_generated_{key}.py"
    path.parent.mkdir()
    path.write_text(compose_module_source(source, key), encoding="utf-8")
    assert jit_module._compile_in_child(path) is True
    assert jit_module._compiled_marker(path).exists()
    assert list((path.parent / "__pycache__").glob("*rhs*.nbi"))
    module = build_module(source, key, tmp_path, in_subprocess=False)
    assert jit_module.is_compiled(module)  # in the disk cache: this process loads, not compiles


def test_the_forks_compile_motion_and_outputs_apart_and_mark_the_module_only_when_both_succeed(
        tmp_path, monkeypatch, models):
    """Two forks compile the right-hand side and the outputs side by side; a failure of either
    (here the outputs, made to fail in this process before the forks inherit it) leaves no marker,
    while the other's work is kept in Numba's cache."""
    import importlib

    from flexkane.numerics import jit_module

    integrate = importlib.import_module("flexkane.numerics.integrate")   # the module, not the function
    if not jit_module._fork_allowed():
        pytest.skip("no fork here (not Linux, or other threads)")
    assert jit_module._PARTS == ("motion", "outputs")
    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, "forks-apart")
    path = tmp_path / key / f"flexkane_generated_{key}.py"
    path.parent.mkdir()
    path.write_text(compose_module_source(source, key), encoding="utf-8")

    def failing(module):
        raise RuntimeError("the outputs part fails")

    monkeypatch.setattr(integrate, "compile_outputs", failing)
    assert jit_module._compile_in_child(path, loops=False) is False
    assert not jit_module._compiled_marker(path).exists()
    assert list((path.parent / "__pycache__").glob("*rhs*.nbi"))   # the motion fork compiled it
    monkeypatch.undo()
    assert jit_module._compile_in_child(path, loops=False) is True
    assert jit_module._compiled_marker(path).exists()


@pytest.mark.parametrize("integrators", [True, False])
def test_the_callers_meanwhile_work_runs_while_a_child_compiles_and_the_child_skips_cached_loops(
        tmp_path, monkeypatch, models, integrators):
    """compile_in_subprocess(meanwhile=...) hands the caller's work to the wait for the child (once per
    child, never when nothing is compiled); the child compiles the integrator loops only when their
    cache lacks them."""
    from flexkane.numerics import jit_module

    children = []

    def child(path, meanwhile=None, loops=True):
        children.append(loops)
        meanwhile()
        return True

    monkeypatch.setattr(jit_module, "_compile_in_child", child)
    monkeypatch.setattr(jit_module, "integrators_compiled", lambda: integrators)
    monkeypatch.setattr(sys.modules["flexkane.numerics.integrate"], "load_integrators", lambda: None)
    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, f"meanwhile-{integrators}")
    done = []
    with jit_module.compile_in_subprocess(meanwhile=lambda: done.append(True)):
        build_module(source, key, tmp_path)
    assert done == [True] and children == [not integrators]
    path = tmp_path / key / f"flexkane_generated_{key}.py"
    jit_module._write_marker(path)
    monkeypatch.setattr(jit_module, "integrators_compiled", lambda: True)
    with jit_module.compile_in_subprocess(meanwhile=lambda: done.append(True)):
        build_module(source, key, tmp_path)   # compiled: no child, no meanwhile work
    assert done == [True] and len(children) == 1
