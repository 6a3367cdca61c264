"""Outputs of large models go through term tables and parts, and give the written-out values.

The kinetic and strain energies of a beam with n modes are sums of n^2 terms; written out in one
compiled loop they took 25.8 s to compile at 40 modes. Above ``codegen.LONG_SUM_CHARS`` the outputs of
one sample are generated like a large right-hand side (``<name>_row``). Both forms must agree to
round-off, outputs that use u' (driver efforts, through the compiled rhs) included.
"""

import numpy as np
import pytest

import flexkane
from flexkane.derivation_cache import derive, model_source
from flexkane.numerics import codegen
from flexkane.numerics.constant_block import prepared_parameters
from flexkane.numerics.jit_module import build_module, structure_key


def _outputs_both_ways(model, cache, monkeypatch):
    eom = derive(model, cache=False)
    modules = []
    for limit in (10 ** 9, 50):          # written out; every model in tables and parts
        monkeypatch.setattr(codegen, "LONG_SUM_CHARS", limit)
        source = model_source(eom)
        modules.append(build_module(source, structure_key("large-outputs", source), cache))
    rng = np.random.default_rng(3)
    n = len(eom.q) + len(eom.u)
    t = np.linspace(0.0, 0.4, 6)
    Y = rng.uniform(-0.2, 0.2, (6, n))
    p = eom.parameter_vector()
    return modules, [m.outputs(t, Y, prepared_parameters(m, p)) for m in modules]


@pytest.mark.parametrize("name", ["slider-crank", "two-link-flexible-arm"])
def test_outputs_in_term_tables_equal_the_written_out_outputs(name, tmp_path, monkeypatch):
    (plain, large), (a, b) = _outputs_both_ways(flexkane.builtin_model(name), tmp_path, monkeypatch)
    assert not hasattr(plain, "outputs_row") and hasattr(large, "outputs_row")
    assert a.shape == b.shape and plain.OUTPUT_NAMES == large.OUTPUT_NAMES
    if name == "slider-crank":
        assert any(k.startswith("effort_") for k in large.OUTPUT_NAMES)     # u' through the rhs
    np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * np.abs(a).max())


def test_many_modes_put_the_energies_in_term_tables():
    source = model_source(derive(flexkane.builtin_model("falling-beam-exact").with_modes(20), cache=False))
    wrapper = source.split("def outputs(", 1)[1].split("\n\n\n", 1)[0]
    assert "outputs_row_table_sums" in source and "outputs_row(" in wrapper
    assert len(wrapper.splitlines()) < 30           # the loop over samples only, not the sums
