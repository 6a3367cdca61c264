"""Mutated model files through ``flexkane check`` and ``flexkane run``: exit code 0, 2 or 3, never a
traceback, and bounded work per file.

The files are mutants of the example files and the built-in models (:mod:`model_mutations`, from a
fixed seed) and of the hypothesis strategies of ``test_model_fuzz.py`` (derandomized), so a failure
reproduces on every machine. Time and memory are bounded without any clock: the files go through
child processes whose CPU time and address space are limited with ``setrlimit``; a file that
exceeds its limit kills its child with SIGXCPU (or SIGKILL, or a MemoryError), and the test names it.

Limits (each a wide margin over the largest use measured on a loaded 2-core machine):

* ``check``: :data:`CHECK_CPU_SECONDS` CPU seconds per file (measured: at most 0.7 s over 2,050
  files; most take 0.01 s);
* ``run``: :data:`RUN_CPU_SECONDS` CPU seconds for the run process and as much for its compiling
  child (measured: at most 19 s for the two together, a first compile included; a run from the
  cache takes about 2 s; the margin absorbs a slower machine and a larger new structure);
* :data:`ADDRESS_SPACE` bytes of address space for every process (measured resident memory: at most
  250 MB for a checking child, 360 MB for a run; NumPy, SymPy, Numba and LLVM map more than they use,
  so the address space is set well above).
"""

from __future__ import annotations

import json
import os
import pathlib
import random
import resource
import signal
import subprocess
import sys

import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from model_mutations import base_texts, mutated_files, runnable_mutant
from test_model_fuzz import BASES, _mutate

SRC = pathlib.Path(__file__).resolve().parents[2] / "src"
CHECK_CPU_SECONDS = 60
RUN_CPU_SECONDS = 120
ADDRESS_SPACE = 4 * 1024**3
BATCH = 100

#: A child process checking a batch of files in-process, one JSON line per file:
#: [index, exit code, the file's messages, CPU seconds, largest resident set so far [KB]].
#: Before each file, the soft CPU limit is moved to the CPU time used so far plus the per-file limit.
_CHECKER = """
import contextlib, io, json, resource, sys, traceback
from flexkane.cli import main
limit, cases = int(sys.argv[1]), json.load(open(sys.argv[2]))
def cpu():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime
hard = resource.getrlimit(resource.RLIMIT_CPU)[1]
for index, (path, options) in enumerate(cases):
    start = cpu()
    resource.setrlimit(resource.RLIMIT_CPU, (int(start) + 1 + limit, hard))
    sys.stderr.write(f"{index}\\n")
    sys.stderr.flush()
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        try:
            code = main(["check", path, *options])
        except SystemExit as exc:
            code = exc.code
        except BaseException:
            traceback.print_exc()
            code = "exception"
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps([index, code, out.getvalue()[-4000:], cpu() - start, peak]), flush=True)
"""


def _limits(cpu_seconds: int, hard_cpu: int):
    """preexec_fn of a child: CPU and address-space limits (SIGXCPU past the soft CPU limit)."""
    def apply():
        resource.setrlimit(resource.RLIMIT_CPU, (cpu_seconds, hard_cpu))
        resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
    return apply


def _environment(tmp_path) -> dict:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")]))
    env.setdefault("FLEXKANE_CACHE_DIR", str(tmp_path / "cache"))
    env["MPLBACKEND"] = "Agg"
    return env


def check_files(files: list[tuple[str, bytes, list[str]]], tmp_path: pathlib.Path) -> list[dict]:
    """Check ``files`` ((description, bytes, options of check) triples) in batches of child
    processes; assert the outcome of each; return their measurements."""
    folder = tmp_path / "files"
    folder.mkdir(exist_ok=True)
    measured, problems = [], []
    for first in range(0, len(files), BATCH):
        batch = files[first:first + BATCH]
        paths = []
        for k, (_, body, options) in enumerate(batch, start=first):
            path = folder / f"mutant_{k:05d}.toml"
            path.write_bytes(body)
            paths.append([str(path), options])
        (folder / "batch.json").write_text(json.dumps(paths))
        hard = CHECK_CPU_SECONDS * (len(batch) + 1) + 60
        child = subprocess.Popen([sys.executable, "-c", _CHECKER, str(CHECK_CPU_SECONDS), str(folder / "batch.json")],
                                 stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 text=True, env=_environment(tmp_path),
                                 preexec_fn=_limits(CHECK_CPU_SECONDS + 60, hard))
        out, err = child.communicate()
        started = [int(line) for line in err.split() if line.isdigit()]
        rows = [json.loads(line) for line in out.splitlines() if line.startswith("[")]
        if child.returncode != 0 or len(rows) != len(batch):
            last = first + (started[-1] if started else 0)
            ended = signal.Signals(-child.returncode).name if child.returncode < 0 else child.returncode
            problems.append(f"the checking child ended with {ended} (SIGXCPU: over the CPU limit) at "
                            f"{files[last][0]} ({folder / f'mutant_{last:05d}.toml'}):\n{err[-3000:]}")
        for index, code, text, cpu, peak in rows:
            what = f"{files[first + index][0]} ({paths[index][0]}): {text}"
            if code not in (0, 2):
                problems.append(f"exit {code}: {what}")
            elif "Traceback" in text or "MemoryError" in text:
                problems.append(what)
            elif code == 2 and not text.startswith(("flexkane: error: ", "usage: ")):
                problems.append(f"message: {what}")
            measured.append({"code": code, "cpu": cpu, "peak_kb": peak})
    assert not problems, f"{len(problems)} problem(s):\n" + "\n".join(problems[:20])
    return measured


def run_file(text: str, tmp_path: pathlib.Path, case: str, options: list[str], plots: bool = False) -> dict:
    """``flexkane run`` of one file in a child process under the CPU and memory limits."""
    folder = tmp_path / case
    folder.mkdir()
    (folder / "model.toml").write_text(text, "utf-8")
    args = [sys.executable, "-m", "flexkane", "run", "model.toml", "--quiet",
            *([] if plots else ["--no-plots"]), *options]
    child = subprocess.Popen(args, cwd=folder, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=_environment(tmp_path),
                             preexec_fn=_limits(RUN_CPU_SECONDS, RUN_CPU_SECONDS + 10))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out, err = child.communicate()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)   # the run and its compiling child, if any
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    return {"code": child.returncode, "out": out + err, "folder": folder, "cpu": cpu, "peak_kb": after.ru_maxrss}


# --------------------------------------------------------------------------------------- check
def _hypothesis_files(count: int, seed_label: str) -> list[tuple[str, bytes, list[str]]]:
    """``count`` mutants from the strategies of test_model_fuzz.py (derandomized: the same files on
    every run)."""
    files = []

    @settings(max_examples=count, derandomize=True, database=None, deadline=None,
              suppress_health_check=list(HealthCheck))
    @given(st.data())
    def collect(data):
        base = data.draw(st.sampled_from(BASES))
        try:
            files.append((f"hypothesis {seed_label} {base}", tomli_w.dumps(_mutate(data.draw, base)).encode(), []))
        except (TypeError, ValueError):   # not representable in TOML
            pass

    collect()
    return files


def _summary(measured: list[dict]) -> str:
    codes = {c: sum(m["code"] == c for m in measured) for c in sorted({m["code"] for m in measured})}
    return (f"{len(measured)} files, exit codes {codes}, CPU at most {max(m['cpu'] for m in measured):.2f} s "
            f"per file, resident memory at most {max(m['peak_kb'] for m in measured) / 1024:.0f} MB")


def test_a_few_hundred_mutated_files_pass_check_with_exit_0_or_2(tmp_path):
    files = mutated_files(seed=15, count=250) + _hypothesis_files(60, "default")
    measured = check_files(files, tmp_path)
    assert len(measured) >= 300
    assert {0, 2} <= {m["code"] for m in measured}     # both valid and refused files were made
    print(_summary(measured))


@pytest.mark.slow
def test_two_thousand_mutated_files_pass_check_with_exit_0_or_2(tmp_path):
    files = mutated_files(seed=2015, count=1800) + _hypothesis_files(250, "slow")
    measured = check_files(files, tmp_path)
    assert len(measured) >= 2000
    print(_summary(measured))


# ----------------------------------------------------------------------------------------- run
#: Options of ``flexkane run`` at and beyond their limits (none that lengthens a run).
RUN_OPTIONS = (["--t-end", "0"], ["--t-end", "1e-320"], ["--t-end", "nan"], ["--dt-out", "1e-320"],
               ["--dt-out", "-1"], ["--rtol", "0"], ["--rtol", "1e-300"], ["--atol", "inf"], ["--max-steps", "0"],
               ["--max-steps", "1"], ["--method", "radau"], ["--animate", "--magnify", "nan"],
               ["--animate", "--trace", "nowhere"], ["--animate", "--magnify", "auto", "--trace", "cm"],
               ["--set", "g=1e300"], ["--set", "q_pivot=1e300"], ["--n-modes", "0"], ["--n-modes", "41"],
               ["--trace", "nowhere"], ["--out", ""], ["--out", "model.toml"], ["--force"])


def _run_cases(seed: int, count: int, bases: tuple[str, ...]) -> list[tuple[str, str, list[str]]]:
    """``count`` runnable mutants of ``bases``, one in five also given options of RUN_OPTIONS."""
    rng = random.Random(seed)
    texts = base_texts()
    cases = []
    for k in range(count):
        base = rng.choice(bases)
        what, text = runnable_mutant(rng, texts[base], t_end=0.02)
        options = list(rng.choice(RUN_OPTIONS)) if rng.random() < 0.2 else []
        cases.append((f"{base} #{k} {what} {' '.join(options)}", text, options))
    return cases


def _check_runs(cases, tmp_path):
    results, problems = [], []
    for k, (what, text, options) in enumerate(cases):
        result = run_file(text, tmp_path, f"case{k:03d}", options, plots=k % 10 == 9)
        killed = signal.Signals(-result["code"]).name if result["code"] < 0 else ""
        if result["code"] not in (0, 2, 3):
            problems.append(f"exit {result['code']} {killed}: {what}\n{text}\n{result['out'][-3000:]}")
        elif "Traceback" in result["out"] or "MemoryError" in result["out"]:
            problems.append(f"{what}\n{text}\n{result['out'][-3000:]}")
        elif result["code"] == 0 and not list(result["folder"].glob("**/results.npz")):
            problems.append(f"no results.npz: {what}\n{result['out']}")
        entries = {p.name for p in tmp_path.iterdir()}   # nothing written beside the cases' folders
        assert entries <= {"cache", "files"} | {f"case{j:03d}" for j in range(len(cases))}, entries
        results.append(result)
    assert not problems, f"{len(problems)} problem(s):\n" + "\n".join(problems[:10])
    print(_summary(results))
    return [r["code"] for r in results]


def test_a_handful_of_mutated_files_run_with_exit_0_2_or_3(tmp_path):
    codes = _check_runs(_run_cases(seed=15, count=5, bases=("pendulum-beam",)), tmp_path)
    assert len(codes) == 5


@pytest.mark.slow
def test_a_hundred_mutated_files_run_with_exit_0_2_or_3(tmp_path):
    bases = ("pendulum-beam", "four-bar", "flexible-arm", "slider-crank", "falling-beam")
    codes = _check_runs(_run_cases(seed=2015, count=100, bases=bases), tmp_path)
    assert len(codes) == 100 and codes.count(0) >= 10


def test_the_limits_stop_a_child_that_exceeds_them():
    """The harness can fail: endless work ends with SIGXCPU, a 5 GB allocation with a MemoryError."""
    spin = subprocess.run([sys.executable, "-c", "while True: pass"], preexec_fn=_limits(1, 5))
    assert spin.returncode == -signal.SIGXCPU
    grab = subprocess.run([sys.executable, "-c", "b = bytearray(5 * 1024**3)"], capture_output=True, text=True,
                          preexec_fn=_limits(30, 35))
    assert grab.returncode == 1 and "MemoryError" in grab.stderr
