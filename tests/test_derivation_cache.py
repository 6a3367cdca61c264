"""On-disk cache of derived equations: hits give the same equations, numbers hit, structure misses."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import flexkane
import flexkane.kane
from flexkane.derivation_cache import cache_path, cached_derive, cached_rhs_source, model_source, structure_signature
from flexkane.model.parts import ShapeSpec
from flexkane.simulation import compile_model


@pytest.fixture
def count_derivations(monkeypatch):
    """Counts the calls of flexkane.kane.derive made by cached_derive."""
    calls = []
    original = flexkane.kane.derive

    def counting(model):
        calls.append(model.name)
        return original(model)

    monkeypatch.setattr(flexkane.kane, "derive", counting)
    return calls


def beam(n=2):
    return flexkane.builtin_model("falling-beam-exact").with_modes(n)


def assert_same_equations(a, b):
    assert a.mass_matrix == b.mass_matrix and a.forcing == b.forcing and a.qdot == b.qdot
    assert a.q == b.q and a.u == b.u and a.constants == b.constants
    assert a.outputs == b.outputs and a.F_r_star == b.F_r_star and a.F_r == b.F_r


def test_cache_hit_gives_the_equations_of_a_fresh_derivation(tmp_path, count_derivations):
    first = cached_derive(beam(), tmp_path)
    second = cached_derive(beam(), tmp_path)
    assert count_derivations == ["falling-beam-exact"] and cache_path(beam(), tmp_path).exists()
    assert second is not first
    assert_same_equations(second, flexkane.derive(beam(), cache=False))
    np.testing.assert_array_equal(second.parameter_vector(), first.parameter_vector())


def test_numeric_changes_hit_the_cache_and_give_their_own_numbers(tmp_path, count_derivations):
    base = flexkane.builtin_model("falling-beam")  # typed root 1.875, literal values below
    base.bodies["RB"].mass = "2*mR"
    cached_derive(base, tmp_path)
    changed = base.copy()
    changed.parameters["EI"] = 50.0                      # parameter value
    changed.bodies["RB"].mass = 3.5                      # another non-zero value: still a symbol
    changed.beams["B"].shape.roots = [1.8751040687]      # typed root
    changed.initial["q3"] = 0.2                          # initial condition
    changed.simulation.t_end = 3.0
    assert structure_signature(changed) == structure_signature(base)
    eom = cached_derive(changed, tmp_path)
    assert len(count_derivations) == 1
    assert eom.model is changed
    fresh = flexkane.derive(changed, cache=False)
    assert_same_equations(eom, fresh)
    np.testing.assert_allclose(eom.parameter_vector(), fresh.parameter_vector(), rtol=1e-14)
    np.testing.assert_array_equal(eom.initial_state(), fresh.initial_state())
    assert eom.parameter_vector(base)[eom.constants.index(eom.chain.symbols.parameters["EI"])] == 35.3


@pytest.mark.parametrize("change", [
    lambda m: m.with_modes(3),
    lambda m: setattr(m.bodies["RB"], "mass", 0) or m,           # a zero is structure
    lambda m: setattr(m.bodies["RB"], "mass", "c") or m,         # another parameter's symbol
    lambda m: setattr(m.beams["B"], "gravity", "midpoint") or m,
    lambda m: setattr(m.beams["B"].shape, "family", "pinned-free") or m,
    lambda m: setattr(m.gravity, "direction", [1, -1]) or m,
    lambda m: m.parameters.update(extra=1.0) or m,                # names of the parameters
], ids=["n_modes", "zero", "parameter", "gravity-model", "family", "gravity-direction",
        "parameter-names"])
def test_structural_changes_change_the_signature(change):
    assert structure_signature(change(beam())) != structure_signature(beam())


def test_tip_mass_ratios_of_a_shape_family_are_numbers():
    arm = flexkane.builtin_model("flexible-arm")
    arm.beams["link"].shape = ShapeSpec("clamped-free-tip-mass", options={"mass_ratio": 0.4})
    heavier = arm.copy()
    heavier.beams["link"].shape.options["mass_ratio"] = 0.8
    assert structure_signature(heavier) == structure_signature(arm)


def test_structural_change_misses_the_cache(tmp_path, count_derivations):
    cached_derive(beam(2), tmp_path)
    eom = cached_derive(beam(3), tmp_path)
    assert len(count_derivations) == 2 and len(eom.u) == 6


def test_time_law_text_is_structure():
    arm = flexkane.builtin_model("flexible-arm")
    other = arm.copy()
    other.joints["shoulder"].torque = "where(t < t1, T0*sin(pi*t/t1), 0)"
    number = arm.copy()
    number.parameters["T0"] = 5.0
    assert structure_signature(other) != structure_signature(arm)
    assert structure_signature(number) == structure_signature(arm)


def test_loop_constraints_with_automatic_dependent_speeds_are_keyed_on_numbers():
    named = flexkane.builtin_model("four-bar")  # names its dependent speeds
    moved = named.copy()
    moved.initial["q_crank"] = 0.5
    assert structure_signature(moved) == structure_signature(named)
    auto, auto_moved = named.copy(), moved.copy()
    for m in (auto, auto_moved):
        for constraint in m.constraints.values():
            constraint.dependent = None
    assert structure_signature(auto_moved) != structure_signature(auto)


def test_damaged_cache_file_is_derived_again(tmp_path, count_derivations):
    cached_derive(beam(1), tmp_path)
    cache_path(beam(1), tmp_path).write_bytes(b"not a pickle")
    eom = cached_derive(beam(1), tmp_path)
    assert len(count_derivations) == 2
    assert_same_equations(eom, flexkane.derive(beam(1), cache=False))


def test_generated_source_is_cached_with_the_equations(tmp_path):
    eom = cached_derive(beam(1), tmp_path)
    source = cached_rhs_source(eom, tmp_path)
    assert source == model_source(eom)
    assert "def rhs(" in source and "def outputs(" in source
    assert list((tmp_path / "derived").glob(f"{eom.derivation_key}-*.module.py"))
    assert cached_rhs_source(cached_derive(beam(1), tmp_path), tmp_path) == source


def test_compiling_cached_equations_does_not_generate_their_code_again(tmp_path, monkeypatch):
    """A sweep's workers compile the equations they receive: the generated code comes from the cache."""
    import flexkane.derivation_cache

    compiled = compile_model(cached_derive(beam(1), tmp_path), tmp_path)

    def refuse(eom):
        raise AssertionError("code generated again")

    monkeypatch.setattr(flexkane.derivation_cache, "model_source", refuse)
    again = compile_model(cached_derive(beam(1), tmp_path), tmp_path)
    assert again.key == compiled.key
    with pytest.raises(AssertionError, match="code generated again"):
        compile_model(flexkane.derive(beam(1), cache=False), tmp_path)


def test_the_package_derive_uses_the_cache_unless_told_not_to(tmp_path, count_derivations):
    first = flexkane.derive(beam(1), cache_dir=tmp_path)
    second = flexkane.derive(beam(1), cache_dir=tmp_path)
    assert count_derivations == ["falling-beam-exact"]
    assert first.derivation_key == second.derivation_key
    fresh = flexkane.derive(beam(1), cache=False, cache_dir=tmp_path)
    assert count_derivations == ["falling-beam-exact"] * 2 and not hasattr(fresh, "derivation_key")
    assert_same_equations(second, fresh)


def test_every_module_a_derivation_reads_keys_the_cache():
    """A change to any source the derivation runs must invalidate the cached equations: every flexkane
    module loaded by a derivation is among the digested sources, or produces no part of the equations
    (errors and messages, the version, which keys the cache itself, and the cache module)."""
    import subprocess
    import sys

    code = ("import sys, flexkane\n"
            "from flexkane.kane.equations import derive\n"
            "derive(flexkane.builtin_model('falling-beam'))\n"
            "print('\\n'.join(m.__file__ for n, m in sorted(sys.modules.items())\n"
            "                 if n.startswith('flexkane') and getattr(m, '__file__', None)))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = {pathlib.Path(line).resolve() for line in done.stdout.split()}
    from flexkane.derivation_cache import equation_sources

    digested = {path.resolve() for path in equation_sources()}
    allowed = {"__init__.py", "errors.py", "_version.py", "natural_order.py", "derivation_cache.py", "atomic.py",
               "extras.py", "interruption.py", "progress.py", "builtin.py"}
    missing = sorted(str(p) for p in loaded - digested if p.name not in allowed or p.parent.name != "flexkane")
    assert not missing, f"modules the derivation loads but the cache key does not read: {missing}"
