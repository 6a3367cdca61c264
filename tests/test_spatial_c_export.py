"""The exported C of spatial models (Euler parameters: more coordinates than speeds) computes what the
Numba module computes: right-hand side, mass matrix, forcing, kinematic equations and outputs at
random states (helpers of :mod:`test_c_export`), and the header counts q and u apart."""

from __future__ import annotations

import pytest

from test_c_export import _compare_at_random_states, exported, needs_cc  # noqa: F401 (the fixture)


@needs_cc
@pytest.mark.parametrize("name, counts", [("spacecraft-slew", (7, 6)), ("robot-arm-3d", (3, 3))])
def test_c_of_spatial_models_matches_numba(exported, name, counts):  # noqa: F811
    model, numba, lib, prefix, directory = exported(name)
    assert (len(numba.eom.q), len(numba.eom.u)) == counts
    header = (directory / f"{prefix}.h").read_text()
    upper = prefix.upper()
    nq, nu = counts
    for line in (f"#define {upper}_NQ {nq}", f"#define {upper}_NU {nu}", f"#define {upper}_NY {nq + nu}"):
        assert line in header
    _compare_at_random_states(model, numba, lib, prefix)
