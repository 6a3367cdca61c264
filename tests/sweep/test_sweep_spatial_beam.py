"""A sweep over a spatial beam's stiffness: one derivation, and each variant vibrates at eq. 8.7.

A clamped spatial beam (one shape function per bending plane and of torsion, no spin, no gravity)
released from ``q_b_z1 = A`` vibrates in its first mode along z alone: ``q_b_z1(t) = A cos(p_1 t)``,
``p_1 = lambda_1^2 sqrt(EI_y / (rho L^4))`` (eq. 8.7 with EI_y), whatever EI_y; one derivation
serves every value of the parameter.
"""

import numpy as np
import pytest

from flexkane.model import loads_model
from flexkane.sweep import RunSettings, SweepSpec, make_variants, read_table, run_sweep
from flexkane.sweep.structure import group_by_structure

LAMBDA_1 = 1.8751040687119611
L, RHO, A, T_END = 1.2, 0.7, 0.01, 0.35
EI_VALUES = (5.0, 20.0)

BEAM = f"""
dimensions = 3
name = "clamped-spatial-beam"

[parameters]
EI_y = 5.0

[beams.b]
L = {L}
rho = {RHO}
EI_y = "EI_y"
EI_z = 9.0
GJ = 3.0
rho_Ip = 0.01
n_modes_y = 1
n_modes_z = 1
n_torsion = 1

[joints.weld]
type = "weld"
parent = "ground"
child = "b"

[initial]
q_b_z1 = {A}
"""


def test_variants_of_a_spatial_beam_stiffness_share_one_structure():
    """The grouping a sweep derives by (cheap: no derivation): the parameter EI_y changes numbers only,
    the number of shape functions per plane changes the structure."""
    model = loads_model(BEAM)
    for vary, groups in ((("EI_y=5,20,40",), 1), (("beams.b.n_modes_z=1,2",), 2)):
        spec = SweepSpec(vary=vary, t_end=T_END, dt_out=T_END)
        assert len(group_by_structure(make_variants(model, spec, RunSettings.resolve(spec, model)))) == groups


@pytest.mark.slow
def test_sweep_over_the_flexural_rigidity_of_a_spatial_beam(tmp_path):
    pytest.importorskip("dask")
    pytest.importorskip("pyarrow")
    path = tmp_path / "beam.toml"
    path.write_text(BEAM)
    spec = SweepSpec(vary=("EI_y=" + ",".join(map(str, EI_VALUES)),), t_end=T_END, dt_out=T_END,
                     rtol=1e-11, atol=1e-14)
    outcome = run_sweep(str(path), spec, out=tmp_path / "sweep", workers=1)
    assert outcome.structures == 1 and outcome.computed == 2
    rows = read_table(tmp_path / "sweep", as_rows=True)
    assert [r["status"] for r in rows] == ["ok", "ok"]
    for row in rows:
        p1 = LAMBDA_1 ** 2 * np.sqrt(row["EI_y"] / (RHO * L ** 4))
        assert row["final_q_b_z1"] == pytest.approx(A * np.cos(p1 * T_END), rel=1e-7, abs=1e-12)
        assert abs(row["final_q_b_y1"]) < 1e-14 and abs(row["final_q_b_t1"]) < 1e-14
