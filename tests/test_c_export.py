"""The exported C (flexkane export MODEL --c DIR) computes what the Numba module computes.

Where a C compiler exists, the two exported files are compiled into a shared library (-O2, warnings
as errors) and called through ctypes: the right-hand side and the outputs equal those of the Numba
module at random states to 1e-12 (relative to the largest entry), the mass matrix equals the
symbolic one and satisfies ``M u' = f`` with the forcing. Models: the chapter's example, the
closed-loop four-bar (also with a stabilized loop), the slider-crank (a crank driven at a
prescribed speed closing a loop over a flexible rod), the arm under a PID law (a controller state
z in y = [q, u, z], a torque saturated by min/max), the arm under a PD law of sensors (joint angle and
rate, tip deflection, strain outputs), a spatial chain whose Numba module sums M by the compiled loop
and, marked slow, spin-up (a prescribed hub speed, geometric stiffening). The header's orders are checked against the run manifest.
"""

from __future__ import annotations

import ctypes
import re
import shutil
import subprocess

import numpy as np
import pytest
import sympy as sp

import flexkane
from flexkane.c_export import c_constants, export_c
from flexkane.derivation_cache import Derivation
from flexkane.errors import ModelError
from flexkane._version import __version__
from flexkane.numerics import build_module, evaluate_outputs, structure_key
from flexkane.numerics.constant_block import prepared_parameters
from flexkane.numerics.c_source import c_identifier

CC = shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler (cc) on this machine")
_DOUBLES = ctypes.POINTER(ctypes.c_double)


def _compile(directory, prefix: str):
    """Compile the exported files into a shared library; return it loaded with ctypes."""
    library = directory / f"lib{prefix}.so"
    result = subprocess.run([CC, "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic", "-shared",
                             "-fPIC", str(directory / f"{prefix}.c"), "-o", str(library), "-lm"],
                            capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stderr
    lib = ctypes.CDLL(str(library))
    for name in ("rhs", "mass_matrix", "forcing", "kinematics", "controller_rates", "outputs"):
        function = getattr(lib, f"{prefix}_{name}")
        function.argtypes = [ctypes.c_double, _DOUBLES, _DOUBLES, _DOUBLES]
        function.restype = ctypes.c_int
    lib[f"{prefix}_solve"].argtypes = [_DOUBLES, _DOUBLES]
    lib[f"{prefix}_solve"].restype = ctypes.c_int
    return lib


def _call(function, t: float, y: np.ndarray, p: np.ndarray, n: int) -> tuple[int, np.ndarray]:
    out = np.full(n, -1.0)
    y, p = np.ascontiguousarray(y, dtype=float), np.ascontiguousarray(p, dtype=float)
    status = function(t, y.ctypes.data_as(_DOUBLES), p.ctypes.data_as(_DOUBLES), out.ctypes.data_as(_DOUBLES))
    return status, out


def _close(a, b, rtol=1e-12):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    scale = max(np.max(np.abs(b)), 1e-300)
    assert np.max(np.abs(a - b)) <= rtol * scale, (np.max(np.abs(a - b)) / scale, a, b)


class _Numba:
    """The generated Numba module of a model (its rhs and outputs; the integrators are not needed)."""

    def __init__(self, model):
        self.derivation = Derivation(model)
        self.eom = self.derivation.eom
        source = self.derivation.source()
        self.module = build_module(source, structure_key(__version__, source))

    def rhs(self, t, y, p):
        dy = np.empty(len(y))
        status = self.module.rhs(float(t), np.asarray(y, dtype=float), prepared_parameters(self.module, p), dy)
        assert status == 0
        return dy


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """Model name -> (model, its Numba module, the loaded C library, prefix, directory)."""
    cache = {}

    def get(name):
        if name not in cache:
            model = flexkane.builtin_model(name)
            directory = tmp_path_factory.mktemp(c_identifier(name))
            files = export_c(model, directory, force=True)
            prefix = c_identifier(model.name)
            assert [f.name for f in files] == [f"{prefix}.h", f"{prefix}.c"]
            cache[name] = (model, _Numba(model), _compile(directory, prefix), prefix, directory)
        return cache[name]
    return get


def _compare_at_random_states(model, numba, lib, prefix: str, count: int = 5) -> dict:
    """rhs, M, f and the outputs of the C library against the Numba module at ``count`` random states.

    Returns the C outputs by name, one array of ``count`` values each.
    """
    eom = numba.eom
    numbers = numba.derivation.numbers(model, ("p", "y0"))
    p, y0 = np.array(numbers["p"]), np.array(numbers["y0"])
    editable = np.array([c.value for c in c_constants(eom, model)[0]])   # the C's p: editable entries only
    nq, nu, nz = len(eom.q), len(eom.u), len(eom.z)
    ny = nq + nu + nz
    assert len(y0) == ny
    outputs = list(eom.compact.outputs)
    rng = np.random.default_rng(18)
    rhs, mass, forcing = (getattr(lib, f"{prefix}_{k}") for k in ("rhs", "mass_matrix", "forcing"))
    seen: dict = {key: [] for key in outputs}
    for _ in range(count):
        t = float(rng.uniform(0.0, 0.5))
        y = y0 + np.concatenate([0.05 * rng.standard_normal(nq), rng.standard_normal(nu), rng.standard_normal(nz)])
        status, dy = _call(rhs, t, y, editable, ny)
        assert status == 0
        _close(dy, numba.rhs(t, y, p))
        status, M = _call(mass, t, y, editable, nu * nu)
        assert status == 0
        M = M.reshape(nu, nu)
        np.testing.assert_array_equal(M, M.T)
        status, f = _call(forcing, t, y, editable, nu)
        assert status == 0
        _close(M @ dy[nq:nq + nu], f, rtol=1e-11)    # M u' = f with u' of the C right-hand side
        status, qdot = _call(getattr(lib, f"{prefix}_kinematics"), t, y, editable, nq)
        assert status == 0
        np.testing.assert_array_equal(qdot, dy[:nq])
        if nz:
            status, zdot = _call(getattr(lib, f"{prefix}_controller_rates"), t, y, editable, nz)
            assert status == 0
            np.testing.assert_array_equal(zdot, dy[nq + nu:])
        status, out = _call(getattr(lib, f"{prefix}_outputs"), t, y, editable, len(outputs))
        assert status == 0
        numba_out = evaluate_outputs(numba.module, np.array([t]), y[None, :], p)
        for k, key in enumerate(outputs):
            _close(out[k], numba_out[key][0])
            seen[key].append(out[k])
    # the mass matrix against the symbolic one (intermediates written out), at the last state
    values = dict(zip(eom.constants, p)) | dict(zip([*eom.q, *eom.u, *eom.z], y)) | {eom.t: t}
    symbolic = np.array(eom.mass_matrix.xreplace({s: sp.Float(v) for s, v in values.items()}).evalf(),
                        dtype=float)
    _close(M, symbolic)
    return {key: np.array(v) for key, v in seen.items()}


@needs_cc
@pytest.mark.parametrize("name", ["falling-beam", "four-bar", "slider-crank",
                                  pytest.param("spin-up", marks=pytest.mark.slow)])
def test_c_matches_numba_at_random_states(exported, name):
    model, numba, lib, prefix, _ = exported(name)
    _compare_at_random_states(model, numba, lib, prefix)


@needs_cc
def test_c_matches_numba_where_the_loop_sums_a_spatial_mass_matrix(tmp_path, monkeypatch):
    """A chain of four bodies on revolute joints about x, y, z, x: the Numba module sums M by the
    compiled loop over pair tables (chosen here: by default from codegen.SPATIAL_MASS_LOOP_MIN_SPEEDS
    speeds), the C writes M out entry by entry."""
    import sys
    from pathlib import Path

    from flexkane.numerics import codegen

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from spatial_mass_loop import revolute_chain

    monkeypatch.setattr(codegen, "SPATIAL_MASS_LOOP_MIN_SPEEDS", 2)
    model = flexkane.loads_model(revolute_chain(4))
    numba = _Numba(model)
    assert "assemble_spatial_mass_matrix(_M, " in numba.derivation.source()
    export_c(model, tmp_path, force=True)
    prefix = c_identifier(model.name)
    _compare_at_random_states(model, numba, _compile(tmp_path, prefix), prefix)


@needs_cc
def test_controller_state_and_saturation_match_numba(exported):
    """flexible-arm-pid: y = [q, u, z], z' = the tracking error, the motor torque saturated at
    +-tau_max through min/max (fmin/fmax in C); the random states reach both sides of the limit."""
    model, numba, lib, prefix, directory = exported("flexible-arm-pid")
    header = (directory / f"{prefix}.h").read_text()
    assert "#define FLEXIBLE_ARM_PID_NZ 1" in header and "#define FLEXIBLE_ARM_PID_NY 9" in header
    assert [n for _, n, _ in _documented(header, "y")][-1] == "error_integral"
    assert "fmin(" in (directory / f"{prefix}.c").read_text()
    seen = _compare_at_random_states(model, numba, lib, prefix, count=12)
    tau_max = model.parameters["tau_max"]
    torque = seen["controller_motor"]
    assert np.isclose(torque, tau_max).any() and np.isclose(torque, -tau_max).any()
    assert (np.abs(torque) < tau_max - 1e-3).any()
    np.testing.assert_array_equal(seen["effort_shoulder"], torque)


@needs_cc
def test_sensor_feedback_matches_numba(exported):
    """flexible-arm-pd: a torque of sensors (joint angle and rate) and a set-point of t; the sensor
    columns (tip deflection, root strain) are outputs of the C file too."""
    model, numba, lib, prefix, _ = exported("flexible-arm-pd")
    seen = _compare_at_random_states(model, numba, lib, prefix)
    assert {"sensor_tip", "sensor_root_strain", "effort_shoulder", "controller_reference"} <= set(seen)
    assert np.all(seen["effort_shoulder"] != 0.0)


@needs_cc
def test_solve_reports_a_singular_mass_matrix(exported):
    _, compiled, lib, prefix, _ = exported("falling-beam")
    nu = len(compiled.eom.u)
    M = np.eye(nu)
    M[1, 1] = 0.0
    b = np.ones(nu)
    assert lib[f"{prefix}_solve"](M.ctypes.data_as(_DOUBLES), b.ctypes.data_as(_DOUBLES)) == 4
    assert np.isnan(b).all()
    M = np.eye(nu)
    M[0, 0] = np.nan
    assert lib[f"{prefix}_solve"](M.ctypes.data_as(_DOUBLES), b.ctypes.data_as(_DOUBLES)) == 2
    M = np.diag(np.arange(1.0, nu + 1))
    M[0, 1] = 0.5             # only the upper triangle is read
    b = np.ones(nu)
    assert lib[f"{prefix}_solve"](M.ctypes.data_as(_DOUBLES), b.ctypes.data_as(_DOUBLES)) == 0
    full = np.diag(np.arange(1.0, nu + 1))
    full[0, 1] = full[1, 0] = 0.5
    _close(full @ b, np.ones(nu))


_PROGRAM = r"""#include <stdio.h>
#include "four_bar.h"

int main(void)
{
    double dy[FOUR_BAR_NY], out[FOUR_BAR_NOUT];
    int k, status = four_bar_rhs(0.25, four_bar_default_y0, four_bar_default_p, dy);
    for (k = 0; k < FOUR_BAR_NY; ++k) printf("%s' %.17g\n", four_bar_state_names[k], dy[k]);
    status |= four_bar_outputs(0.25, four_bar_default_y0, four_bar_default_p, out);
    for (k = 0; k < FOUR_BAR_NOUT; ++k) printf("%s %.17g\n", four_bar_output_names[k], out[k]);
    return status;
}
"""


@needs_cc
def test_a_program_without_python_runs_on_the_default_arrays(exported):
    """A C program calls the exported functions with the model's constants and initial state."""
    model, numba, lib, prefix, directory = exported("four-bar")
    numbers = numba.derivation.numbers(model, ("p", "y0"))
    editable = [c.value for c in c_constants(numba.eom, model)[0]]
    p = np.ctypeslib.as_array((ctypes.c_double * len(editable)).in_dll(lib, f"{prefix}_default_p"))
    np.testing.assert_array_equal(p, editable)
    (directory / "main.c").write_text(_PROGRAM)
    program = directory / "four_bar_program"
    subprocess.run([CC, "-std=c99", "-O2", "-Wall", "-Werror", str(directory / "main.c"), str(directory / "four_bar.c"),
                    "-o", str(program), "-lm"], check=True, capture_output=True)
    printed = subprocess.run([str(program)], check=True, capture_output=True, text=True).stdout.split()
    values = dict(zip(printed[::2], map(float, printed[1::2])))
    dy = numba.rhs(0.25, np.array(numbers["y0"]), np.array(numbers["p"]))
    _close([values[f"{n}'"] for n in numba.derivation.manifest["state_names"]], dy)
    outputs = evaluate_outputs(numba.module, np.array([0.25]), np.array([numbers["y0"]]), np.array(numbers["p"]))
    for key, column in outputs.items():
        _close(values[key], column[0])


def _documented(header: str, array: str) -> list[tuple[int, str, str]]:
    """``(index, name, unit)`` of the lines ``array[k] = name [unit]`` of a header."""
    return [(int(k), name, unit) for k, name, unit in
            re.findall(rf"^ \*   {array}\[(\d+)\] = (\S+) \[([^\]]*)\]", header, flags=re.M)]


def test_header_documents_the_orders_of_the_run_manifest(tmp_path):
    model = flexkane.builtin_model("slider-crank")
    header_path, source_path = export_c(model, tmp_path / "c")
    header = header_path.read_text()
    manifest = Derivation(model).manifest
    states = _documented(header, "y")
    assert [k for k, _, _ in states] == list(range(len(manifest["state_names"])))
    assert [n for _, n, _ in states] == manifest["state_names"]
    assert [u for _, _, u in states] == [manifest["units"][n] for n in manifest["state_names"]]
    constants, frozen = _documented(header, "p"), _documented(header, "frozen")
    derived = re.findall(r"^ \*   (\w+) \[([^\]]*)\] = ", header, flags=re.M)
    editable_, frozen_, derived_ = c_constants(Derivation(model).eom, model)
    assert [n for _, n, _ in constants] == [c.symbol.name for c in editable_]
    assert [n for _, n, _ in frozen] == [c.symbol.name for c in frozen_]
    assert [n for n, _ in derived] == [c.symbol.name for c in derived_]
    # every constant of the equations is a parameter, frozen or computed from them, once
    named = [n for _, n, _ in constants + frozen] + [n for n, _ in derived]
    assert set(manifest["constant_names"]) <= set(named) and len(named) == len(set(named))
    unit = {n: u for _, n, u in constants + frozen} | dict(derived)
    # a modal constant (as the report), a parameter a field names, a field's own constant
    # and a parameter of a time law only: the driver coordinate Omega*t [rad] makes Omega [rad/s]
    assert (unit["H_11"], unit["m1"], unit["L2"], unit["x_crank_pin"], unit["Omega"]) \
        == ("N/m", "kg", "m", "m", "rad/s")
    assert not [line for line in header.splitlines() if line.startswith(" *   p[") and "[?]" in line]
    assert f"#define SLIDER_CRANK_NY {len(manifest['state_names'])}" in header
    assert f"#define SLIDER_CRANK_NP {len(constants)}" in header
    assert f"#define SLIDER_CRANK_NFROZEN {len(frozen)}" in header
    outputs = [n for _, n, _ in _documented(header, "out")]
    assert outputs[:3] == ["x_crank", "y_crank", "theta_crank"] and "constraint_piston_1" in outputs
    source = source_path.read_text()
    assert re.findall(r"#include\s*[<\"]([^>\"]+)", source) == ["math.h", "slider_crank.h"]
    assert re.findall(r"#include\s*[<\"]([^>\"]+)", header) == []


def test_a_parameter_whose_uses_fix_no_unit_is_said_to_have_none_and_why():
    """Omega*k*t [rad] with k a parameter too: neither Omega nor k has a unit of its own."""
    from flexkane.c_export import constant_descriptions

    model = flexkane.builtin_model("slider-crank")
    eom = Derivation(model).eom
    free = model.with_values({"parameters.k": 1.0, "joints.crank.driver.coordinate": "Omega*k*t"})
    units, notes = constant_descriptions(eom, free)
    omega = [s.name for s in eom.constants].index("Omega")
    assert units[omega] == ""
    assert notes[omega] == ("parameter, in joints.crank.driver.coordinate; no unit: its uses do not fix one "
                            "(joints.crank.driver.coordinate [rad] leave it free or disagree)")


def test_names_are_sanitized_and_never_collide(tmp_path):
    """Parameters named like C keywords, math.h functions and macros, the generated functions and the
    functions' arguments stay apart; the model's label cannot end a comment. The loop of this four-bar
    is stabilized (Phi' = -20 Phi), which the C right-hand side does as the Numba one."""
    from flexkane.builtin import builtin_text

    text = builtin_text("four-bar")
    for old, new in (("m1", "pow"), ("m2", "double"), ("m3", "bar_rhs"), ("I1", "NAN"), ("d", "dy"),
                     ("b", "bar_constants"), ("c", "bar_frozen_values")):   # b, c: lengths of derived values
        text = re.sub(rf"\b{old}\b", new, text)
    text = text.replace('name = "four-bar"', 'name = "4 bar */ \\"x\\""')
    text = text.replace('dependent = ["u_coupler", "u_rocker"]',
                        'dependent = ["u_coupler", "u_rocker"]\nstabilization = 20.0')
    model = flexkane.loads_model(text)
    files = export_c(model, tmp_path, prefix="bar")
    header, source = (f.read_text() for f in files)
    for name in ("pow", "double", "bar_rhs", "NAN", "dy", "bar_constants", "bar_frozen_values"):
        assert f"const double {name} = " not in source
    assert '"4 bar * / "x""' in header   # (compiling the header below shows its comments are closed)
    assert "20.0*" in source             # the stabilization rate, in q' of the coordinates
    if CC is not None:   # the same numbers, the loop's stabilization included (states off the loop)
        _compare_at_random_states(model, _Numba(model), _compile(tmp_path, "bar"), "bar")


def test_refuses_a_bad_prefix_and_a_directory_with_files(tmp_path):
    model = flexkane.builtin_model("falling-beam")
    for prefix in ("1abc", "a-b", "int", "sqrt", "_x", ""):
        with pytest.raises(ModelError, match="prefix"):
            export_c(model, tmp_path / "a", prefix=prefix)
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "notes.txt").write_text("mine")
    with pytest.raises(ModelError, match="directory"):
        export_c(model, tmp_path / "b")
    assert sorted(p.name for p in (tmp_path / "b").iterdir()) == ["notes.txt"]
    export_c(model, tmp_path / "b", force=True)
    assert sorted(p.name for p in (tmp_path / "b").iterdir()) == ["falling_beam.c", "falling_beam.h", "notes.txt"]


def test_command_line_export(tmp_path, capsys):
    from flexkane.cli import main

    out = tmp_path / "c"
    assert main(["export", "four-bar", "--c", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["four_bar.c", "four_bar.h"]
    assert "four_bar.h" in capsys.readouterr().out
    assert main(["export", "four-bar", "--c", str(out)]) == 2          # not empty, no --force
    assert "--c" in capsys.readouterr().err
    assert main(["export", "four-bar", "--c", str(out), "--force", "--prefix", "fb", "--set", "m1=0.7"]) == 0
    assert (out / "fb.h").is_file()
    assert "    0.7  /* m1 */," in (out / "fb.c").read_text()       # --set gives the default constants
    assert main(["export", "four-bar", "--c", str(out / "x"), "--prefix", "no good"]) == 2
    assert "--prefix" in capsys.readouterr().err
    assert not (out / "x").exists()
    assert main(["export", "four-bar"]) == 2
    assert "--c" in capsys.readouterr().err
