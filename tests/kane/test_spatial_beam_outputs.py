"""Per-beam outputs of spatial beams: tip deflections in both principal planes, slopes and twist.

Oracles: a clamped beam's static tip deflections under a tip force, ``F L^3 / (3 EI)`` in each
principal plane (the modal approximation converges), and its tip twist under a tip torque, which for
the torsion modes ``sqrt(2) sin((2k - 1) pi x / (2L))`` is ``T L / GJ * 8/pi^2 sum_k 1/(2k - 1)^2``
exactly (the modal static solution, tending to ``T L / GJ``); the strain energy column equals the
work of the loads on the static deflection, ``1/2 (F_y v(L) + F_z w(L) + T theta(L))`` (Clapeyron).
"""

import numpy as np
import pytest

import flexkane
from flexkane.model import loads_model

L, EI_Y, EI_Z, GJ = 1.2, 5.0, 9.0, 3.0
FY, FZ, T = 0.02, -0.03, 0.004
N_TORSION = 3

LOADED = f"""
dimensions = 3
name = "tip-loaded-spatial-beam"

[beams.b]
static_corrections = false   # the oracle is the Ritz solution in the clamped-free modes
L = {L}
rho = 0.7
EI_y = {EI_Y}
EI_z = {EI_Z}
GJ = {GJ}
rho_Ip = 0.01
n_modes_y = 4
n_modes_z = 4
n_torsion = {N_TORSION}

[joints.weld]
type = "weld"
parent = "ground"
child = "b"

[loads.tip]
body = "b"
station = {L}
force = [0, {FY}, {FZ}]
torque = [{T}, 0, 0]
frame = "ground"
"""


@pytest.fixture(scope="module")
def static():
    """The derived equations, their linear static solution ``K q = F`` (at rest the generalized
    inertia forces vanish: the elastic forces ``-K q`` balance the loads' generalized forces at
    q = 0) and the outputs there."""
    import sympy as sp

    eom = flexkane.derive(loads_model(LOADED), cache=False)
    values = eom.constant_values()
    zero = {q: 0 for q in eom.q}
    elastic = sp.Matrix(eom.F_r["elastic"]).xreplace(values)
    K = -np.array(elastic.jacobian(eom.q), dtype=float)
    F = np.array([float(f.xreplace(values).xreplace(zero)) for f in eom.F_r["loads"]])
    q = np.linalg.solve(K, F)
    state = dict(zip(eom.q + eom.u, np.concatenate([q, np.zeros(len(eom.u))])))
    outputs = {name: float(expr.xreplace({**values, **state, eom.t: 0.0})) for name, expr in eom.outputs.items()}
    return eom, outputs


def test_tip_force_gives_the_cantilever_deflection_in_each_principal_plane(static):
    _, out = static
    assert abs(out["tip_b_y"] - FY * L ** 3 / (3 * EI_Z)) <= 1e-3 * abs(out["tip_b_y"])
    assert abs(out["tip_b_z"] - FZ * L ** 3 / (3 * EI_Y)) <= 1e-3 * abs(out["tip_b_z"])
    # slopes F L^2 / (2 EI)
    assert abs(out["slope_b_y"] - FY * L ** 2 / (2 * EI_Z)) <= 1e-2 * abs(out["slope_b_y"])
    assert abs(out["slope_b_z"] - FZ * L ** 2 / (2 * EI_Y)) <= 1e-2 * abs(out["slope_b_z"])


def test_tip_torque_gives_the_modal_static_twist(static):
    _, out = static
    truncation = 8 / np.pi ** 2 * sum(1 / (2 * k - 1) ** 2 for k in range(1, N_TORSION + 1))
    assert out["twist_b"] == pytest.approx(T * L / GJ * truncation, rel=1e-10)
    assert abs(out["twist_b"] - T * L / GJ) <= 0.07 * T * L / GJ     # converging to T L / GJ (3 modes: 4 %)


def test_strain_energy_column_is_the_work_of_the_tip_loads(static):
    _, out = static
    work = (FY * out["tip_b_y"] + FZ * out["tip_b_z"] + T * out["twist_b"]) / 2
    assert out["strain"] == pytest.approx(work, rel=1e-10)
    assert out["energy"] == pytest.approx(out["strain"], rel=1e-12)      # at rest, no gravity


def test_tip_outputs_are_columns_with_units(static):
    from flexkane.run_manifest import units

    eom, _ = static
    unit = units(eom)
    assert {name: unit[name] for name in ("tip_b_y", "tip_b_z", "slope_b_y", "slope_b_z", "twist_b")} == {
        "tip_b_y": "m", "tip_b_z": "m", "slope_b_y": "rad", "slope_b_z": "rad", "twist_b": "rad"}
