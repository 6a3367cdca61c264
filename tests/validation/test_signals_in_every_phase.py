"""SIGTERM and SIGINT in every phase of ``flexkane run`` (derive, compile, write, equations and plots):
exit 130 and no traceback, results written atomically first and complete, no temporary file left.

The signal is sent deterministically: either by the run itself, from a patched function of the phase
(the command line runs in a subprocess through ``python -c``), or, for the compilation, right after
the run announced it on standard error (a first compilation takes seconds). Time bounds are the
generous timeouts of the subprocesses, never a wall-clock assertion.
"""

import os
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import flexkane

# Runs the command line (argv[2:]) after patching ``argv[1]`` ("module:function") so that its first
# call sends the signal named by $FK_SIGNAL to this process, then carries on.
SIGNALLING_CLI = textwrap.dedent("""
    import importlib, os, signal, sys
    target, args = sys.argv[1], sys.argv[2:]
    module_name, name = target.split(":")
    owner = importlib.import_module(module_name)
    if "." in name:
        cls, name = name.split(".")
        owner = getattr(owner, cls)
    original = getattr(owner, name)
    calls = []
    main_process = os.getpid()
    def patched(*a, **k):
        if os.environ.get("FK_WHERE") == ("fork" if os.getpid() == main_process else "main"):
            return original(*a, **k)   # a signal sent by the main process only, or by a fork only
        calls.append(1)
        if len(calls) == int(os.environ.get("FK_CALL", "1")):
            print("FK: signal sent", file=sys.stderr, flush=True)
            os.kill(os.getpid(), getattr(signal, os.environ["FK_SIGNAL"]))
            if os.environ.get("FK_LOOP"):  # a long phase: keep doing its work until stopped
                while True:
                    original(*a, **k)
        return original(*a, **k)
    setattr(owner, name, patched)
    from flexkane.cli import main
    sys.exit(main(args))
""")


def _run_signalling(target, args, sig="SIGTERM", call=1, loop=False, env=None, timeout=120):
    environment = dict(os.environ, FK_SIGNAL=sig, FK_CALL=str(call), **(env or {}))
    if loop:
        environment["FK_LOOP"] = "1"
    return subprocess.run([sys.executable, "-c", SIGNALLING_CLI, target, *args], stdin=subprocess.DEVNULL,
                          capture_output=True, text=True, env=environment, timeout=timeout)


def _temporary_files(directory):
    return [p.name for p in directory.rglob("*") if p.name.startswith(".") or ".tmp" in p.name]


@pytest.fixture(scope="module")
def run_args(torque_pendulum, torque_pendulum_file):
    """A short run of the (already compiled) torque pendulum; add --out."""
    return ["run", str(torque_pendulum_file), "--t-end", "0.5", "--dt-out", "0.01", "--set", "t1=1e9"]


@pytest.fixture(scope="module")
def reference(run_args, tmp_path_factory):
    """The same run, not interrupted: (its directory, its results)."""
    out = tmp_path_factory.mktemp("reference") / "run"
    process = subprocess.run([sys.executable, "-m", "flexkane", *run_args, "--out", str(out), "--quiet"],
                             capture_output=True, text=True, env=dict(os.environ), timeout=300)
    assert process.returncode == 0, process.stderr
    return out, flexkane.load_results(out)


@pytest.mark.parametrize("sig", ["SIGTERM", "SIGINT"])
def test_a_signal_while_results_csv_is_written_is_deferred_until_every_result_is_complete(
        run_args, reference, tmp_path, sig):
    out = tmp_path / "run"
    process = _run_signalling("flexkane.results:csv_text", [*run_args, "--out", str(out)], sig)
    assert process.returncode == 130, process.stderr
    assert "Traceback" not in process.stderr
    assert "interrupted after the integration; complete files in" in process.stderr
    for name in ("results.csv", "results.npz", "model.toml"):
        assert name in process.stderr and (out / name).is_file()
    assert not (out / "equations.md").exists()        # the rest is skipped: the stop is honoured at once
    assert (out / "results.csv").read_bytes() == (reference[0] / "results.csv").read_bytes()
    saved = flexkane.load_results(out)
    assert not saved.partial
    np.testing.assert_array_equal(saved.state, reference[1].state)
    assert not list(out.glob("*.png")) and not _temporary_files(out)


@pytest.mark.parametrize("sig, where", [("SIGTERM", "main"), ("SIGINT", "main"), ("SIGTERM", "fork")])
def test_a_signal_while_a_plot_is_saved_exits_130_naming_the_complete_files(run_args, reference, tmp_path, sig,
                                                                            where):
    """The signal comes inside the second figure's savefig of the main process (the third figure: the
    run draws every other one in a fork), or of the fork (the fourth), while its temporary file exists."""
    out = tmp_path / "run"
    process = _run_signalling("matplotlib.figure:Figure.savefig", [*run_args, "--out", str(out)], sig, call=2,
                              env={"FK_WHERE": where})
    assert process.returncode == 130, process.stderr
    assert "Traceback" not in process.stderr and "FK: signal sent" in process.stderr
    assert not _temporary_files(out)
    plots = sorted(p.name for p in out.glob("*.png"))
    # the figures before the interrupted one in the process interrupted (one), and those the other one
    # had completed when it was stopped with it (none to two)
    assert 1 <= len(plots) <= 3 and ("q_pin.png" in plots or where == "fork")
    message = process.stderr.split("complete files in", 1)[1]
    assert all(name in message for name in plots + ["results.csv", "results.npz", "equations.md", "equations.tex"])
    for name in plots + ["results.csv"]:
        assert (out / name).read_bytes() == (reference[0] / name).read_bytes()


def test_sigterm_during_the_derivation_exits_130_without_writing_results(torque_pendulum_file, tmp_path):
    """The derivation (pure Python, made long here by repeating it) stops at once (the signal comes
    once it is announced: from the function that derive runs within its progress line)."""
    out = tmp_path / "run"
    process = _run_signalling("flexkane.kane.equations:_derive", ["run", str(torque_pendulum_file), "--out", str(out)],
                              loop=True, env={"FLEXKANE_CACHE_DIR": str(tmp_path / "cache")}, timeout=60)
    assert process.returncode == 130, process.stderr
    assert "Traceback" not in process.stderr and "flexkane: interrupted" in process.stderr
    assert "deriving the equations of motion" in process.stderr
    assert not out.exists() or not list(out.iterdir())   # the unused new directory is removed


@pytest.mark.slow
def test_sigterm_during_a_first_compilation_stops_the_compiler_and_exits_130(tmp_path):
    """A first compilation runs in a child process; SIGTERM once it is announced stops both."""
    cache = tmp_path / "cache"
    out = tmp_path / "run"
    process = subprocess.Popen([sys.executable, "-m", "flexkane", "run", "pendulum-beam", "--t-end", "0.1",
                                "--out", str(out)], stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True,
                               env=dict(os.environ, FLEXKANE_CACHE_DIR=str(cache)))
    try:
        lines = []
        for line in process.stderr:
            lines.append(line)
            if "compiling the right-hand side" in line:
                break
        assert "compiling the right-hand side" in "".join(lines), "".join(lines)
        process.send_signal(signal.SIGTERM)
        _, rest = process.communicate(timeout=300)       # a hang guard; the stop is shown by the missing .compiled
    finally:
        if process.poll() is None:
            process.kill()
    err = "".join(lines) + rest
    assert process.returncode == 130, err
    assert "Traceback" not in err and "flexkane: interrupted" in err
    assert not list(cache.rglob("*.compiled"))          # the compiling child was stopped, not finished
    assert not out.exists() or not list(out.iterdir())   # the unused new directory is removed


def test_a_signal_while_the_equations_are_written_stops_them_at_once(run_args, reference, tmp_path):
    """The equations report (minutes for the largest models) is not deferred: the results are.
    (``--no-cache``: a repeated run takes the report's text from the cache instead of writing it.)"""
    out = tmp_path / "run"
    process = _run_signalling("flexkane.report:printed_structure", [*run_args, "--no-cache", "--out", str(out)],
                              loop=True,
                              timeout=120)
    assert process.returncode == 130, process.stderr
    assert "Traceback" not in process.stderr and "interrupted after the integration" in process.stderr
    assert (out / "results.csv").read_bytes() == (reference[0] / "results.csv").read_bytes()
    assert not (out / "equations.md").exists() and not list(out.glob("*.png")) and not _temporary_files(out)
