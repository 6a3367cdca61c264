"""Rayleigh beams in 3D: the sections' mass moments of inertia per length ``rho_Iy``, ``rho_Iz``.

Oracles: the exact frequency equation of the clamped-free Rayleigh beam (derived in
tests/kane/test_rayleigh_beam.py), in each principal plane with its own rigidity and rotary inertia,
approached from above by the assumed modes (Rayleigh-Ritz); and the planar engine: a planar Rayleigh
beam run through the spatial engine (``rotary_inertia`` -> ``rho_Iz``) gives the same accelerations
and energies to 1e-10.
"""

import numpy as np
import pytest
import scipy.linalg
import sympy as sp

import flexkane
from flexkane.errors import ModelError
from flexkane.model import as_spatial, loads_model
from test_rayleigh_beam import hub_beam, rayleigh_cantilever_frequencies

N = 4
RAYLEIGH = f"""
dimensions = 3
name = "rayleigh-3d"

[beams.b]
L = 1.0
rho = 1.0
EI_y = 2.0
EI_z = 1.0
rho_Iy = 0.004
rho_Iz = 0.0025
n_modes_y = {N}
n_modes_z = {N}
principal_angle = 0.3

[joints.weld]
type = "weld"
parent = "ground"
child = "b"
orientation = {{ axis = [1, 2, 0.5], angle = 0.7 }}
"""


def mass_stiffness_damping(eom, q=None):
    """M, K = -dF_elastic/dq and C = -dF_damping/du of derived equations at q (default 0), at rest."""
    values = eom.constant_values()
    state = {s: 0.0 for s in eom.q + eom.u} if q is None else q
    M = np.array(eom.mass_matrix.xreplace(values).xreplace(state), dtype=float)
    K = -np.array(sp.Matrix(eom.F_r["elastic"]).xreplace(values).jacobian(eom.q).xreplace(state), dtype=float)
    C = -np.array(sp.Matrix(eom.F_r["damping"]).xreplace(values).jacobian(eom.u).xreplace(state), dtype=float)
    return M, K, C


def test_clamped_rayleigh_beam_frequencies_approach_the_exact_roots_in_each_plane():
    """EI_z = 1 with rho_Iz = 0.0025 (v, along y_p) and EI_y = 2 with rho_Iy = 0.004 (w): the first
    three frequencies of each plane from above, within the assumed-mode error of N = 4 functions;
    the sections' rotation lowers them far more than that."""
    eom = flexkane.derive(loads_model(RAYLEIGH), cache=False)
    M, K, _ = mass_stiffness_damping(eom)
    found = np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True))
    names = [q.name for q in eom.q]
    assert names[:2] == ["q_b_y1", "q_b_y2"] and names[N] == "q_b_z1"
    y = np.sqrt(scipy.linalg.eigh(K[:N, :N], M[:N, :N], eigvals_only=True))[:3]
    z = np.sqrt(scipy.linalg.eigh(K[N:, N:], M[N:, N:], eigvals_only=True))[:3]
    np.testing.assert_allclose(np.sort(found)[:6], np.sort(np.concatenate([y, z])), rtol=1e-12)  # uncoupled
    exact_y = rayleigh_cantilever_frequencies(0.0025, 3)                      # EI = rho = L = 1
    exact_z = np.sqrt(2.0) * rayleigh_cantilever_frequencies(0.004, 3)
    for modal, exact, r2, EI in ((y, exact_y, 0.0025, 1.0), (z, exact_z, 0.004, 2.0)):
        errors = (modal - exact) / exact
        assert np.all(errors > -1e-12), errors                              # Rayleigh-Ritz: from above
        assert np.all(errors < [2e-7, 1e-4, 1e-3]), errors
        euler_bernoulli = np.sqrt(EI) * rayleigh_cantilever_frequencies(0.0, 3)
        assert np.all((euler_bernoulli - exact) / exact > 100 * errors)


def _numeric(eom, t, q, u):
    """u' and the energies of derived equations at one state (exact substitution)."""
    values = eom.constant_values()
    state = {**values, **dict(zip(eom.q, q)), **dict(zip(eom.u, u)), eom.t: t}
    M = np.array(eom.mass_matrix.xreplace(state), dtype=float)
    f = np.array(eom.forcing.xreplace(state), dtype=float).ravel()
    energies = [float(eom.outputs[k].xreplace(state)) for k in ("kinetic", "strain", "energy", "power_nonconservative")]
    return np.linalg.solve(M, f), np.array(energies)


def test_planar_rayleigh_beam_with_modal_damping_through_the_spatial_engine_equals_the_planar_engine():
    """A hub carrying a damped Rayleigh beam with a pendulum at its tip, driven by a torque: as a
    spatial model (rotary_inertia -> rho_Iz, damping -> damping_y) the same accelerations, energies
    and power to 1e-10."""
    planar = hub_beam(6.0, "rI", tip=True, torque="0.3*cos(t)")
    planar.beams["B"].damping = [0.02, 0.05, "0.03"]
    spatial = as_spatial(planar)
    assert spatial.beams["B"].rho_Iz == "rI" and spatial.beams["B"].damping_y == [0.02, 0.05, "0.03"]
    eom2, eom3 = flexkane.derive(planar, cache=False), flexkane.derive(spatial, cache=False)
    assert {"Gr_y1_y2", "Er_y3", "Irz_B"} <= {s.name for s in eom3.constants}
    rng = np.random.default_rng(5)
    for _ in range(2):
        q = rng.uniform(-0.3, 0.3, len(eom2.q))
        u = rng.uniform(-1.0, 1.0, len(eom2.u))
        t = rng.uniform(0.0, 3.0)
        (a2, e2), (a3, e3) = _numeric(eom2, t, q, u), _numeric(eom3, t, q, u)
        assert np.abs(a2).max() > 1e-2
        assert np.abs(a3 - a2).max() <= 1e-10 * np.abs(a2).max()
        assert np.abs(e3 - e2).max() <= 1e-10 * np.abs(e2).max()


def test_rotary_inertia_fields_of_a_spatial_beam_are_checked():
    with pytest.raises(ModelError, match=r"beams\.b\.rho_Iy.*non-negative"):
        loads_model(RAYLEIGH.replace("rho_Iy = 0.004", "rho_Iy = -0.004"))
    with pytest.raises(ModelError, match=r"beams\.b\.rotary_inertia.*rho_Iy and rho_Iz"):
        loads_model(RAYLEIGH.replace("rho_Iy = 0.004", "rotary_inertia = 0.004"))


BLADE = """
dimensions = 3
name = "rayleigh-blade-on-a-ball-joint"

[beams.blade]
L = 1.5
rho = 0.8
EI_y = 20.0
EI_z = 35.0
GJ = 8.0
rho_Ip = 0.05
rho_Iy = 0.02
rho_Iz = 0.03
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
principal_angle = 0.3

[joints.pivot]
type = "spherical"
parent = "ground"
parent_position = [0, 0, 0]
child = "blade"
orientation = { sequence = "zyx", angles = [0.2, -0.3, 0.5] }

[gravity]
g = 9.81
direction = [0, 0.3, -1]
"""


@pytest.mark.slow
def test_spatial_rayleigh_blade_conserves_energy_and_momentum():
    """A blade on a ball joint whose sections turn about both principal axes (and twist): the
    energy's rate is zero along the equations of motion (with gravity), and so are the rates of the
    linear and angular momentum when it floats free (free joint, no gravity), at random states."""
    from test_spatial_beams import _compact_functions, _random_states, _rates

    eom = flexkane.derive(loads_model(BLADE), cache=False)
    assert {"Iry_blade", "Irz_blade", "Gr_z1_z1", "Er_y1"} <= {s.name for s in eom.constants}
    rates = _rates(eom, ("energy", "kinetic"), _random_states(eom, slice(0, 4)))
    assert np.all(np.abs(rates[:, 0]) <= 1e-9 * np.abs(rates[:, 1])), rates
    free = BLADE.replace('type = "spherical"', 'type = "free"').split("[gravity]")[0]
    eom = flexkane.derive(loads_model(free), cache=False)
    names = ("H_x", "H_y", "H_z", "p_x", "p_y", "p_z")
    states = _random_states(eom, slice(3, 7))
    H = _compact_functions(eom, [eom.compact.outputs[n] for n in names[:3]])
    for (q, u), row in zip(states, _rates(eom, names, states)):
        assert np.abs(row).max() <= 1e-9 * np.abs(H(q, u)).max() * max(1.0, np.abs(u).max()), row


def test_equations_report_defines_the_constants_of_the_turning_sections():
    """equations.md of a spatial Rayleigh beam: each constant of the sections' turns, the bending
    and torsion stiffnesses defined with its weight, shape functions and unit."""
    from flexkane.report import constant_rows

    text = RAYLEIGH.replace(f"n_modes_z = {N}", "n_modes_z = 1").replace(f"n_modes_y = {N}", "n_modes_y = 1")
    text = text.replace("principal_angle = 0.3", "principal_angle = 0.3\nGJ = 2.0\nrho_Ip = 0.006\nn_torsion = 1")
    eom = flexkane.derive(loads_model(text), cache=False)
    rows = {row[0]: row[2:4] for row in constant_rows(eom, eom.constant_values())}
    defined = {definition: unit for definition, unit in rows.values()}
    for definition, unit in ((r"\int_0^L \rho I_z\,dx", "kg m^2"),
                             (r"\int_0^L \rho I_y\,\Phi^{z}_{1}'(x)\,\Phi^{z}_{1}'(x)\,dx", "kg"),
                             (r"\int_0^L \rho I_p\,\Theta_{1}(x)\,\Theta_{1}(x)\,dx", "kg m^2"),
                             (r"\int_0^L EI_y\,\Phi^{z}_{1}''\,\Phi^{z}_{1}''\,dx", "N/m"),
                             (r"\int_0^L GJ\,\Theta_{1}'\,\Theta_{1}'\,dx", "N m")):
        assert defined.get(definition) == unit, (definition, sorted(defined))
    from flexkane.report import equations_markdown

    report = equations_markdown(eom, eom.constant_values())
    assert r"\rho I_y\,\Phi^{z}_{1}'(x)" in report and r"\mathrm{Gr}_{z1,z1}" in report
