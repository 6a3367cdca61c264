"""A long chain's mass matrix is formed entry by entry when read, and is the written-out one.

Where generated code sums M from its assembly (planar, no drivers, no closed loops, at least
``LAZY_MASS_MIN_SPEEDS`` speeds), ``derive`` forms no entry of the symbolic M until something reads
it; the equations, the constants, the generated code and M itself are those of the written-out form.
"""

from __future__ import annotations

import pickle
import sys
from pathlib import Path

import pytest
import sympy as sp

from flexkane.derivation_cache import model_source
from flexkane.kane import equations
from flexkane.kane.compact import LazyMassMatrix
from flexkane.kane.inertia import LAZY_MASS_MIN_SPEEDS, SPATIAL_LAZY_MASS_MIN_SPEEDS
from flexkane.numerics import codegen

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from scaling import chain_model  # noqa: E402

_EQUATIONS: dict = {}


def _derived(lazy: bool):
    """chain_model(3) (9 speeds), derived with the entries of M formed when read (derive's default
    for this structure) or at once."""
    if lazy not in _EQUATIONS:
        _EQUATIONS[lazy] = equations.derive(chain_model(3), lazy_mass=None if lazy else False)
    return _EQUATIONS[lazy]


def test_the_threshold_is_the_one_of_the_compiled_loop():
    assert LAZY_MASS_MIN_SPEEDS == codegen.MASS_LOOP_MIN_SPEEDS == codegen.UNROLL_LDL_MAX + 1
    assert SPATIAL_LAZY_MASS_MIN_SPEEDS == codegen.SPATIAL_MASS_LOOP_MIN_SPEEDS


def test_generated_code_reads_only_the_diagonal_of_a_long_chains_mass_matrix():
    """Deriving and generating the code of chain_model(3) forms the 9 diagonal entries (the test
    for a constant block), not the 45 of the upper triangle."""
    lazy_eom = _derived(True)
    mass = lazy_eom.compact.mass_matrix
    assert isinstance(mass, LazyMassMatrix) and len(lazy_eom.u) >= LAZY_MASS_MIN_SPEEDS
    assert not mass.inertia.terms._entry                  # nothing formed by derive
    assert "assemble_mass_matrix(_M, " in model_source(lazy_eom)
    assert sorted(mass.inertia.terms._entry) == [(r, r) for r in range(len(lazy_eom.u))]


@pytest.mark.slow
def test_generated_code_of_the_lazy_and_the_written_out_mass_matrix_is_the_same():
    assert model_source(equations.derive(chain_model(3))) == model_source(_derived(False))


def test_lazily_formed_equations_are_the_written_out_ones():
    lazy_eom, eager = _derived(True), _derived(False)
    assert isinstance(eager.compact.mass_matrix, sp.MatrixBase)
    assert lazy_eom.constants == eager.constants
    assert lazy_eom.forcing == eager.forcing
    again = pickle.loads(pickle.dumps(lazy_eom))          # the derivation cache stores it so
    assert lazy_eom.mass_matrix == eager.mass_matrix
    assert again.mass_matrix == eager.mass_matrix
    assert list(lazy_eom.compact_forces["F_r_star"]) == list(eager.compact_forces["F_r_star"])
    assert lazy_eom.F_r_star == eager.F_r_star
    # the entries named new intermediates: the compact equations took their definitions
    assert {s for s, _ in lazy_eom.intermediates} == {s for s, _ in eager.intermediates}
    assert sp.Matrix(lazy_eom.compact.mass_matrix) == eager.compact.mass_matrix


def test_lazy_mass_matrix_of_a_branched_chain_with_a_rayleigh_beam_and_a_slider():
    """Entries of every kind (a branch, a Rayleigh beam's rotary terms, a prismatic joint) formed
    when read are the written-out ones, and so are the constants."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "numerics"))
    from test_mass_assembly import BRANCHED

    import flexkane

    lazy_eom = equations.derive(flexkane.loads_model(BRANCHED), lazy_mass=True)
    eager = equations.derive(flexkane.loads_model(BRANCHED), lazy_mass=False)
    assert isinstance(lazy_eom.compact.mass_matrix, LazyMassMatrix)
    assert lazy_eom.constants == eager.constants
    assert lazy_eom.mass_matrix == eager.mass_matrix


@pytest.mark.parametrize("label", ["spherical chain of 3", "spatial arm of 2 flexible links"])
def test_lazy_mass_matrix_of_a_spatial_chain_is_the_written_out_one(label):
    """A spatial chain's entries (spherical joints; flexible links with their sections' turns and a
    payload moved by the modes) formed when read are the written-out ones, and so are the
    constants and the forcing."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
    from spatial_chains import flexible_arm, pendulum_chain

    import flexkane

    text = {"spherical chain of 3": lambda: pendulum_chain(3),
            "spatial arm of 2 flexible links": lambda: flexible_arm(2, 1)}[label]()
    lazy_eom = equations.derive(flexkane.loads_model(text), lazy_mass=True)
    eager = equations.derive(flexkane.loads_model(text))     # by default: below the spatial threshold
    mass = lazy_eom.compact.mass_matrix
    assert len(eager.u) < SPATIAL_LAZY_MASS_MIN_SPEEDS and isinstance(eager.compact.mass_matrix, sp.MatrixBase)
    assert isinstance(mass, LazyMassMatrix)
    assert not mass.inertia.terms._entry                  # nothing formed by derive
    assert lazy_eom.compact.mass_assembly.dimensions == 3
    assert lazy_eom.constants == eager.constants
    assert lazy_eom.compact.forcing == eager.compact.forcing
    assert sp.Matrix(mass) == eager.compact.mass_matrix
    assert {s for s, _ in lazy_eom.intermediates} == {s for s, _ in eager.intermediates}
