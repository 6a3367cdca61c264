"""A spatial chain whose generated right-hand side sums M by the compiled loop over pair tables
(flexkane.numerics.mass_assembly.assemble_spatial_mass_matrix) moves as physics says: with no
force doing work, the energy balance E - E0 - W of a run is the integration error alone, and it
falls with the tolerance."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import flexkane
from flexkane.derivation_cache import model_source
from flexkane.numerics import codegen
from flexkane.simulation import compile_model

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from spatial_chains import pendulum_chain  # noqa: E402


@pytest.mark.slow
def test_energy_balance_of_a_long_spatial_chain_summed_by_the_loop(monkeypatch):
    """Four bodies on spherical joints (12 speeds, full inertia tensors, offset points) swinging
    under gravity for 2 s."""
    monkeypatch.setattr(codegen, "SPATIAL_MASS_LOOP_MIN_SPEEDS", 9)
    eom = flexkane.derive(flexkane.loads_model(pendulum_chain(4)), cache=False)
    assert len(eom.u) == 12 and "assemble_spatial_mass_matrix(_M, " in model_source(eom)
    compiled = compile_model(eom)
    balance = {}
    for rtol in (1e-6, 1e-9):
        result = flexkane.simulate(compiled, t_end=2.0, dt_out=0.01, rtol=rtol, atol=rtol * 1e-2)
        energy = np.abs(result.outputs["kinetic"]).max()
        balance[rtol] = np.abs(result.outputs["energy_balance"]).max() / energy
    assert balance[1e-9] < 1e-7 and balance[1e-9] < balance[1e-6] / 10, balance
