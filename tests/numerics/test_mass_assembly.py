"""The mass matrix of a planar or spatial chain summed from twists and composite bodies by the
compiled loop (flexkane.numerics.mass_assembly) equals the mass matrix of the derivation, and
generated code chooses that form by a rule on the structure."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import flexkane
from flexkane.kane.compact import LazyMassMatrix
from flexkane.numerics import codegen, mass_assembly
from flexkane.numerics.codegen import generate_rhs_source
from flexkane.numerics.jit_module import compose_module_source

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "kane"))
from scaling import chain_model  # noqa: E402
from spatial_chains import flexible_arm, pendulum_chain  # noqa: E402
from spatial_models import FREE_UNIVERSAL_PRISMATIC, flexkane_model  # noqa: E402

# a branched chain (two arms on one hub), with a Rayleigh beam and a prismatic joint
BRANCHED = """
name = "branched"
[bodies.hub]
mass = 2.0
inertia = 0.1
points = { left = [0.1, 0.0], right = [-0.1, 0.02] }
[bodies.slider]
mass = 0.3
inertia = 0.01
[bodies.tip]
mass = 0.2
inertia = 0.002
[beams.arm]
L = 0.8
EI = 5.0
rho = 0.4
n_modes = 2
rotary_inertia = 1e-4
[beams.boom]
L = 0.5
EI = 3.0
rho = 0.3
n_modes = 1
[joints.base]
type = "revolute"
parent = "ground"
child = "hub"
[joints.weld_arm]
type = "weld"
parent = "hub"
parent_point = "left"
child = "arm"
[joints.pin_boom]
type = "revolute"
parent = "hub"
parent_point = "right"
child = "boom"
angle = 2.5
[joints.slide]
type = "prismatic"
parent = "arm"
station = 0.8
child = "slider"
[joints.tip_pin]
type = "revolute"
parent = "boom"
station = 0.5
child = "tip"
[simulation]
t_end = 1.0
"""


def _numeric_state(eom, seed: int) -> dict:
    """Random numbers for q, u, t and the constants, and the intermediates evaluated in order."""
    rng = np.random.default_rng(seed)
    values = {eom.t: sp.Float(0.3)}
    values.update({s: sp.Float(rng.uniform(-0.5, 0.5)) for s in [*eom.q, *eom.u]})
    values.update({s: sp.Float(rng.uniform(0.5, 1.5)) for s in eom.constants})
    for symbol, definition in eom.compact.intermediates:
        values[symbol] = sp.sympify(definition).xreplace(values).evalf(20)
    return values


def _loop(assembly):
    """The compiled loop of ``assembly``'s dimensions, as its Python original."""
    loop = mass_assembly.assemble_spatial_mass_matrix if assembly.dimensions == 3 else mass_assembly.assemble_mass_matrix
    return loop.py_func


def _assembled(assembly, values: dict, nu: int) -> np.ndarray:
    """The upper triangle of M from the assembly by the loop (its Python original)."""
    tables = mass_assembly.assembly_tables(assembly)
    number = lambda e: float(sp.sympify(e).xreplace(values))  # noqa: E731
    n_links = len(assembly.parent)
    width = 6 if assembly.dimensions == 3 else 3
    X = np.array([[number(e) for e in assembly.offsets[b]] for b in range(n_links)])
    inertia = np.array([[number(e) for e in assembly.inertia[b]] for b in range(n_links)])
    T = np.array([[number(e) for e in assembly.sources[k][2]] for k in tables.sources]).reshape(-1, width)
    C = np.array([[number(e) for e in assembly.wrenches[w][2]] for w in tables.wrenches]).reshape(-1, width)
    M = np.zeros((nu, nu))
    for (i, j), e in assembly.explicit.items():
        M[i, j] += number(e)
    work = np.empty(tables.work)
    _loop(assembly)(M, X, inertia, T, C, work, tables.poses, tables.momenta, tables.pair_starts,
                    tables.pair_sources, tables.pair_rows, tables.pair_columns)
    return np.triu(M)


_MODELS = {"chain_model(2)": lambda: chain_model(2), "branched": lambda: flexkane.loads_model(BRANCHED),
           "falling-beam": lambda: flexkane.builtin_model("falling-beam"),
           "spherical chain of 3": lambda: flexkane.loads_model(pendulum_chain(3)),
           "free, universal, prismatic": lambda: flexkane_model(FREE_UNIVERSAL_PRISMATIC),
           "spatial arm of 2 flexible links": lambda: flexkane.loads_model(flexible_arm(2, 1))}


@pytest.mark.parametrize("label", [pytest.param("chain_model(2)", marks=pytest.mark.slow),
                                   pytest.param("branched", marks=pytest.mark.slow), "falling-beam",
                                   "spherical chain of 3", "free, universal, prismatic",
                                   "spatial arm of 2 flexible links"])
def test_assembled_mass_matrix_equals_the_derived_one(label):
    eom = flexkane.derive(_MODELS[label](), cache=False)
    assembly = eom.compact.mass_assembly
    assert assembly is not None and assembly.sources
    assert assembly.dimensions == (3 if eom.chain.dimensions == 3 else 2)
    nu = len(eom.u)
    mass = eom.compact.mass_matrix
    mass = mass.formed() if isinstance(mass, LazyMassMatrix) else mass   # its intermediates named first
    for seed in (1, 2):
        values = _numeric_state(eom, seed)
        derived = np.triu(np.array(mass.xreplace(values).evalf(), dtype=float))
        np.testing.assert_allclose(_assembled(assembly, values, nu), derived, rtol=1e-12,
                                   atol=1e-12 * np.max(np.abs(derived)))


def _python_rhs(source: str):
    """The generated ``rhs`` run by Python (decorators removed, the loop's Python original)."""
    text = re.sub(r"^@njit\(.*\)$", "", compose_module_source(source, "test"), flags=re.M)
    namespace: dict = {}
    exec(compile(text, "<generated>", "exec"), namespace)   # our own generated code, not user text
    namespace["assemble_mass_matrix"] = mass_assembly.assemble_mass_matrix.py_func
    namespace["assemble_spatial_mass_matrix"] = mass_assembly.assemble_spatial_mass_matrix.py_func
    return namespace["rhs"]


def _loop_equals_written_out(eom, loop: str = "assemble_mass_matrix", fewer_entries: bool = True):
    looped = generate_rhs_source(eom)
    assert f"{loop}(_M, " in looped and looped == generate_rhs_source(eom)   # deterministic
    written = generate_rhs_source(eom, mass_loop=False)
    assert "assemble_" not in written
    # the entries of M are no longer written out: the source is shorter
    entries = lambda source: len(re.findall(r"^\s+(_M\[\d+, \d+\]|_m\d+_\d+) = ", source, re.M))  # noqa: E731
    assert entries(looped) < entries(written) / 3 or not fewer_entries
    rhs_loop, rhs_written = _python_rhs(looped), _python_rhs(written)
    rng = np.random.default_rng(5)
    n, p = len(eom.q) + len(eom.u), eom.parameter_vector()
    for _ in range(5):
        t, y = float(rng.uniform(0.0, 1.0)), rng.normal(scale=0.5, size=n)
        a, b = np.empty(n), np.empty(n)
        assert rhs_loop(t, y, p, a) == rhs_written(t, y, p, b) == 0
        np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-10 * np.max(np.abs(b)))


@pytest.mark.slow
def test_generated_code_sums_a_long_chains_mass_matrix_by_the_loop():
    eom = flexkane.derive(chain_model(3), cache=False)
    assert len(eom.u) >= codegen.MASS_LOOP_MIN_SPEEDS
    _loop_equals_written_out(eom)


def test_generated_loop_form_equals_the_written_out_form(monkeypatch):
    """The same fact as the slow test above on a chain of two links, the rule's threshold lowered
    (by the planar engine, which derives the planar chains long enough for the planar loop)."""
    from flexkane.kane.equations import derive as derive_afresh

    eom = derive_afresh(chain_model(2), engine="planar")
    assert len(eom.u) < codegen.MASS_LOOP_MIN_SPEEDS   # written out by default (the slow tests)
    monkeypatch.setattr(codegen, "MASS_LOOP_MIN_SPEEDS", 2)
    _loop_equals_written_out(eom)


def test_generated_loop_form_of_a_spatial_chain_equals_the_written_out_form(monkeypatch):
    """The same fact for a chain of two bodies on spherical joints (6 speeds), the loop chosen
    (by default from codegen.SPATIAL_MASS_LOOP_MIN_SPEEDS speeds)."""
    eom = flexkane.derive(flexkane.loads_model(pendulum_chain(2)), cache=False)
    assert "assemble_spatial" not in generate_rhs_source(eom)
    monkeypatch.setattr(codegen, "SPATIAL_MASS_LOOP_MIN_SPEEDS", 2)
    _loop_equals_written_out(eom, "assemble_spatial_mass_matrix")


@pytest.mark.parametrize("name, block", [("spacecraft-flexible-slew", True), ("rotor-blade", False)])
def test_spatial_loop_with_a_constant_block_or_a_driven_speed_equals_the_written_out_form(monkeypatch, name,
                                                                                         block):
    """spacecraft-flexible-slew (16 speeds: a free hub with flexible appendages): its modal mass is
    a constant block factored once per run, the loop sums the rest of M; rotor-blade: a hub driven
    along a prescribed speed, the assembly reduced to the free speeds with the driver's law."""
    eom = flexkane.derive(flexkane.builtin_model(name), cache=False)
    monkeypatch.setattr(codegen, "SPATIAL_MASS_LOOP_MIN_SPEEDS", 2)
    assert ("schur_solve(" in generate_rhs_source(eom)) == block
    # rotor-blade's M is mostly its one beam's modal mass: explicit entries either way
    _loop_equals_written_out(eom, "assemble_spatial_mass_matrix", fewer_entries=block)


@pytest.mark.slow
def test_short_chains_and_the_chapter_example_keep_the_written_out_mass_matrix():
    for model in (chain_model(2), flexkane.builtin_model("flexible-arm")):
        assert "assemble_mass_matrix" not in generate_rhs_source(flexkane.derive(model))


@pytest.mark.slow
def test_closed_chains_have_no_assembly_and_spatial_chains_have_one():
    assert flexkane.derive(flexkane.builtin_model("robot-arm-3d")).compact.mass_assembly.dimensions == 3
    assert flexkane.derive(flexkane.builtin_model("four-bar")).compact.mass_assembly is None


@pytest.mark.slow
def test_generated_right_hand_side_grows_linearly_with_the_links():
    """Code size, which Numba's compile time follows, is linear in the links with the loop: each
    further link adds about as many compiled operations (with M written out, 406, 1,118, 2,496, 7,101
    operations for k = 1, 2, 4, 8)."""
    from flexkane.numerics.code_budget import compiled_operations

    size = {}
    for k in (3, 5, 7):
        source = generate_rhs_source(flexkane.derive(chain_model(k), cache=False))
        size[k] = compiled_operations(source.splitlines())
    first, second = size[5] - size[3], size[7] - size[5]
    assert first > 0 and abs(second - first) < 0.15 * first, size
