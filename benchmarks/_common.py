"""Helpers shared by the benchmarks: timing, compiled models, tip deflections, the machine."""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import time
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

import numpy as np
import sympy as sp

import flexkane
from flexkane.numerics import build_module, generate_rhs_source, integrate, structure_key


def best_time(function, repeat: int = 5, min_total: float = 0.3) -> float:
    """Smallest wall time [s] of ``repeat`` calls (more calls while their total is below
    ``min_total``): the machine is shared, the minimum is the least disturbed measurement."""
    times = []
    while len(times) < repeat or (sum(times) < min_total and len(times) < 200):
        tic = time.perf_counter()
        function()
        times.append(time.perf_counter() - tic)
    return min(times)


@dataclass
class Built:
    """A model derived and compiled, with the time of each stage [s]."""

    model: object
    eom: object
    module: object
    p: np.ndarray
    y0: np.ndarray
    derive_time: float
    codegen_time: float
    compile_time: float
    rhs_compile_time: float = 0.0


def build(model, compile_integrators: tuple[str, ...] = ("dop853",)) -> Built:
    """Derive, generate and compile ``model`` (the rhs and the given integrator loops).

    ``compile_time`` is the Numba compilation (or cache load) of the right-hand side and of the
    integrator loops, measured by calling each once on a tiny span; ``rhs_compile_time`` the part
    of it spent on the right-hand side (the module import included).
    """
    tic = time.perf_counter()
    eom = flexkane.derive(model)
    derived = time.perf_counter()
    source = generate_rhs_source(eom)
    generated = time.perf_counter()
    module = build_module(source, structure_key(source))
    p, y0 = eom.parameter_vector(), eom.initial_state()
    dy = np.empty_like(y0)
    module.rhs(0.0, y0, p, dy)
    rhs_compiled = time.perf_counter()
    for method in compile_integrators:
        integrate(module, y0, np.array([0.0, 1e-6]), p, rtol=1e-6, atol=1e-8, method=method)
    compiled = time.perf_counter()
    return Built(model, eom, module, p, y0, derived - tic, generated - derived, compiled - generated,
                 rhs_compiled - generated)


def tip_function(eom, beam: str):
    """Vectorised ``tip(Y, p) -> (N,)``: transverse tip deflection of ``beam`` [m] from states Y."""
    expr = eom.outputs[f"tip_{beam}"]
    f = sp.lambdify([*eom.q, *eom.constants], expr, "numpy")
    nq = len(eom.q)
    return lambda Y, p: np.broadcast_to(np.asarray(f(*Y[:, :nq].T, *p), dtype=float), (Y.shape[0],))


def relative_error(values: np.ndarray, reference: np.ndarray) -> float:
    """max |values - reference| / max |reference| over the samples."""
    return float(np.max(np.abs(values - reference)) / np.max(np.abs(reference)))


def machine_info() -> dict:
    """CPU (from lscpu), Python and package versions, load average."""
    info = {"python": sys.version.split()[0], "platform": platform.platform()}
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, timeout=10).stdout
        fields = dict(line.split(":", 1) for line in out.splitlines() if ":" in line)
        for key in ("Model name", "CPU(s)", "Thread(s) per core", "Core(s) per socket", "CPU max MHz",
                    "L2 cache", "L3 cache", "Hypervisor vendor"):
            if key in fields:
                info[key] = fields[key].strip()
    except (OSError, subprocess.SubprocessError):
        info["Model name"] = platform.processor() or "unknown"
    versions = {}
    for package in ("flexkane", "numpy", "scipy", "sympy", "numba", "llvmlite", "exudyn", "dask",
                    "distributed"):
        try:
            versions[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            pass
    info["packages"] = versions
    info["load_average"] = os.getloadavg()[0]
    return info


def machine_sentence(machine: dict | None) -> str:
    """" Machine: CPU model, CPUs, Python." for a section's text ("" without ``machine``)."""
    if not machine:
        return ""
    return (f" Machine: {machine.get('Model name', '?')}, {machine.get('CPU(s)', '?')} CPUs, "
            f"Python {machine.get('python', '?')}.")


def fmt_time(seconds: float) -> str:
    """Seconds in a readable unit."""
    if seconds >= 1.0:
        return f"{seconds:.2f} s"
    if seconds >= 1e-3:
        return f"{seconds * 1e3:.2f} ms"
    if seconds >= 1e-6:
        return f"{seconds * 1e6:.2f} us"
    return f"{seconds * 1e9:.0f} ns"


def write_section(lines: list[str], section: str, path: Path | None = None) -> None:
    """Put a section into RESULTS.md, replacing an earlier one that starts with the heading
    ``section`` (up to the next ``## `` heading)."""
    path = path or Path(__file__).resolve().parent / "RESULTS.md"
    text = path.read_text(encoding="utf-8") if path.exists() else "# flexkane benchmarks\n"
    block = "\n".join(lines).rstrip() + "\n"
    start = text.find(section)
    if start < 0:
        text = text.rstrip() + "\n\n" + block
    else:
        following = text.find("\n## ", start + len(section))
        text = text[:start] + block + ("\n" + text[following + 1:] if following >= 0 else "")
    path.write_text(text, encoding="utf-8")


def section_main(run, markdown, section: str) -> dict:
    """Command line of a benchmark with a section of its own in RESULTS.md: ``run()`` measures,
    ``markdown(result, machine)`` writes the section (printed; put into RESULTS.md with ``--write``)."""
    machine = machine_info()
    result = run()
    lines = markdown(result, machine)
    print("\n".join(lines))
    if "--write" in sys.argv:
        write_section(lines, section)
        print("written: benchmarks/RESULTS.md")
    return result
