"""Integrators compiled once: the loops take the model's right-hand side as a first-class function.

A new model structure compiles its own functions only (the package's integrator cache is left as it
is), the numbers through the indirection are those of the loops with the right-hand side called
directly, and the status codes of the right-hand side (2 non-finite, 4 singular mass matrix) reach
the caller.
"""

from __future__ import annotations

from pathlib import Path

import numba
import numpy as np
import pytest
import sympy as sp

from flexkane.numerics import Status, build_module, generate_rhs_source, integrate, structure_key
from flexkane.numerics.dop853 import dop853_chunk
from flexkane.numerics.integrate import compile_integrators, integrator_signatures
from flexkane.numerics.jit_module import integrators_compiled, is_compiled
from flexkane.numerics.radau import fd_jacobian, radau5_chunk
from flexkane.numerics.system_function import SIGNATURE, SystemFunction, direct_chunk, system_function

INTEGRATORS = (dop853_chunk, radau5_chunk, fd_jacobian)
CHUNKS = {"dop853": dop853_chunk, "radau": radau5_chunk}


def _index_files():
    """Numba's cache index file of each integrator function: path -> (bytes, modification time)."""
    files = {}
    for dispatcher in INTEGRATORS:
        path = Path(dispatcher._cache._cache_file._index_path)
        files[path] = (path.read_bytes(), path.stat().st_mtime_ns)
    return files


def test_a_new_model_structure_does_not_recompile_the_integrators(tmp_path, models, pendulum_module):
    compile_integrators(pendulum_module)
    assert integrators_compiled()
    # the signatures the installation's check looks up are those a run calls
    assert all(types in function.overloads for function, types in integrator_signatures())
    signatures = {f.py_func.__name__: list(f.signatures) for f in INTEGRATORS}
    assert all(signatures.values()), signatures
    index = _index_files()
    # a structure this process has never seen: a pendulum with a spring of its own
    t, th, w, m, l, g, k = sp.symbols("t theta omega m l g k_new_structure")
    eom = models.eom(t, [th], [w], [m, l, g, k], [w], [[m * l ** 2]],
                     [-m * g * l * sp.sin(th) - k * th ** 3])
    source = generate_rhs_source(eom)
    key = structure_key(source, "new-structure")
    module = build_module(source, key, tmp_path)
    text = Path(module.__file__).read_text(encoding="utf-8")
    for name in ("dop853_chunk", "radau5_chunk", "fd_jacobian", "starting_step"):
        assert f"def {name}(" not in text  # the loops are not pasted into the model's module
    assert not is_compiled(module)
    compile_integrators(module)
    assert is_compiled(module)
    for method in ("dop853", "radau", "auto"):
        result = integrate(module, [1.0, 0.0], np.linspace(0.0, 1.0, 11), [1.0, 1.0, 9.81, 0.5],
                           rtol=1e-8, atol=1e-10, method=method)
        assert result.status == Status.OK
    # the module compiled its right-hand side into its own cache, the integrators nothing
    cached = {p.name.split(".")[1].split("-")[0] for p in (tmp_path / key / "__pycache__").glob("*.nbi")}
    assert "rhs" in cached and not cached & {"dop853_chunk", "radau5_chunk", "fd_jacobian", "starting_step"}
    assert {f.py_func.__name__: list(f.signatures) for f in INTEGRATORS} == signatures
    assert _index_files() == index


# Last row of the stiff chain over [0, 0.5] s (rtol 1e-8, atol 1e-10) and the counts (nfev, naccept,
# nreject), computed by the loops as they were before the first-class function (each pasted into the
# generated module, calling its right-hand side directly), on another installation. Bit for bit, the
# indirection is checked on this installation by the slow test below; these numbers only pin that the
# loops still take the same steps to the same result. Radau's LU factors and solves come from the
# installed LAPACK/BLAS (and LLVM may contract differently on another processor), so the last bits are
# not portable: on a fresh install (numpy 2.4.6, scipy 1.17.1, numba 0.68.1) one entry of the radau row
# differed by 57 units in the last place (1.0e-14 of the entry, 2e-15 of the row's largest). A tolerance
# of 1e-11 of the row's largest entry admits thousands of times that round-off, amplified over the ~300
# steps, and stays three orders below the integrator's own tolerance (rtol 1e-8): a change
# of a step, of the error estimate or of the method moves the result by about that tolerance and fails.
# The counts are integers decided by comparisons of the error norm with 1; round-off flips such a
# decision only if a norm lies within ~1e-13 of the threshold, so they are compared exactly.
_BEFORE = {
    "dop853": ((12808, 1052, 6), [
        "-0x1.6ff33430d6d80p-5", "0x1.646ea060f25b6p-9", "-0x1.481b597ff4488p-4", "-0x1.29ea30ab748e0p-4",
        "0x1.0ebb98ccbc319p+5", "-0x1.10d3da43d0deap+4", "0x1.a2afa2468e866p+3", "-0x1.057f1834df010p+4"]),
    "radau": ((2423, 318, 1), [
        "-0x1.3a7da9e70ec9bp-2", "-0x1.36d3772f97315p-1", "-0x1.fc438c3ad8befp-2", "-0x1.97b7611b495adp-1",
        "-0x1.77dd037b9f28fp+0", "-0x1.77da733f7c04cp+0", "-0x1.3d2aab932ecd2p+0", "-0x1.3d25ff6c3dc1fp+0"]),
}
#: Relative tolerance (of the row's largest entry) against the numbers of another installation.
_ACROSS_INSTALLATIONS = 1e-11


@pytest.mark.parametrize("method", ["dop853", "radau"])
def test_results_through_the_first_class_function_are_those_of_direct_calls(method, models,
                                                                             stiff_chain_module):
    p = models.BAR_CONSTANTS if method == "dop853" else models.STIFF_CHAIN_CONSTANTS
    runs = [integrate(stiff_chain_module, models.STIFF_CHAIN_Y0, np.linspace(0.0, 0.5, 6), p,
                      rtol=1e-8, atol=1e-10, method=method) for _ in range(2)]
    # on one installation, the same call gives the same bytes
    assert runs[0].y.tobytes() == runs[1].y.tobytes()
    result = runs[0]
    counts, last = _BEFORE[method]
    assert (result.nfev, result.naccept, result.nreject) == counts
    stored = np.array([float.fromhex(v) for v in last])
    np.testing.assert_allclose(result.y[-1], stored, rtol=0,
                               atol=_ACROSS_INSTALLATIONS * np.abs(stored).max())


@pytest.mark.slow
@pytest.mark.parametrize("method", ["dop853", "radau"])
def test_the_indirection_and_a_direct_call_give_the_same_bits(method, models, double_pendulum_module):
    """Compiles the loop with the right-hand side bound (seconds): both must agree bit for bit, and the
    package's cache of the integrators is left alone (the direct loop is an uncached copy)."""
    module = double_pendulum_module
    index = _index_files()
    t_out = np.linspace(0.0, 3.0, 31)
    p = np.array([1.0, 1.5, 1.0, 0.7, 9.81])
    y0 = np.array([1.0, 2.0, 0.0, 0.0])
    runs = []
    for chunk in (CHUNKS[method], direct_chunk(method, module.system_rhs)):
        Y = np.full((t_out.size, 4), np.nan)
        args = (0.0, y0, 0.0, t_out, p, 1e-10, np.full(4, 1e-10), 100_000, Y, -np.inf)
        out = chunk(system_function(module), *args) if chunk is CHUNKS[method] else chunk(*args)
        runs.append((out[3:], Y.tobytes()))
    assert runs[0][0][0] == 0
    assert runs[0] == runs[1]
    assert _index_files() == index


@pytest.mark.parametrize("method", ["dop853", "radau"])
def test_status_codes_of_the_rhs_propagate_through_the_indirection(method, troubled_slider_module):
    system = system_function(troubled_slider_module)
    t_out = np.linspace(0.0, 1.0, 5)
    for q0, p, code in ((0.0, [0.0, 0.0, 1.0], 4),      # mass matrix [[q]] singular at the start
                        (np.nan, [0.0, 0.0, 1.0], 2)):  # non-finite mass matrix
        dy = np.empty(2)
        assert troubled_slider_module.system_rhs(0.0, np.array([q0, 0.0]), np.array(p), dy) == code
        Y = np.full((5, 2), np.nan)
        out = CHUNKS[method](system, 0.0, np.array([q0, 0.0]), 0.0, t_out, np.array(p), 1e-8,
                             np.full(2, 1e-10), 1000, Y, -np.inf)
        assert out[3] == code and out[0] == 0.0
    # reached during a run (q = 1 - t): tests/numerics/test_integrate.py


def test_a_function_of_another_return_type_is_refused():
    @numba.njit
    def returns_a_float(t, y, p, dy):
        return 0.0

    with pytest.raises(TypeError, match="int64"):
        SystemFunction(returns_a_float).__wrapper_address__()
    assert SystemFunction(returns_a_float).signature() == SIGNATURE


def test_one_system_function_per_module(pendulum_module):
    assert system_function(pendulum_module) is system_function(pendulum_module)
    assert system_function(pendulum_module).dispatcher is pendulum_module.system_rhs
