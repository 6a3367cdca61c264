"""Modal damping of spatial beams: ``damping_y``, ``damping_z``, ``torsion_damping``, ``axial_damping``.

Oracle: a clamped beam's shape functions are its modes (orthogonal in mass and stiffness), so each
damped mode decays on its own: the eigenvalues of the equations linearized at rest are
``-zeta omega +- i omega sqrt(1 - zeta^2)``, with omega the undamped frequency (eq. 8.7 with EI_z
or EI_y, the torsion and axial values) and zeta the declared ratio: ``Re = -zeta omega``.
"""

import numpy as np
import pytest

import flexkane
from flexkane.errors import ModelError
from flexkane.model import loads_model
from spatial_beam_models import EI_Y, EI_Z, GJ, L, RHO, RHO_IP, clamped_spatial_beam
from test_spatial_rayleigh_beam import mass_stiffness_damping

LAMBDA = np.array([1.8751040687119611, 4.6940911329741745])   # clamped-free roots, eq. 8.4
EA = 400.0   # axial stiffness [N]

DAMPED = clamped_spatial_beam("damped-spatial-beam", f"""
EA = {EA}
n_modes_y = 2
n_modes_z = 2
n_torsion = 1
n_axial = 1
principal_angle = 0.4
damping_y = [0.01, 0.03]
damping_z = 0.02
torsion_damping = [0.05]
axial_damping = 0.04
""", orientation=((0, 1, 1), 0.3))


def test_each_damped_mode_decays_at_its_declared_ratio():
    eom = flexkane.derive(loads_model(DAMPED), cache=False)
    assert [q.name for q in eom.q] == ["q_b_y1", "q_b_y2", "q_b_z1", "q_b_z2", "q_b_t1", "s_b_1"]
    M, K, C = mass_stiffness_damping(eom)
    n = len(eom.q)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    values = np.linalg.eigvals(A)
    values = values[values.imag > 0]
    order = np.argsort(np.abs(values))
    omega = np.abs(values)[order]
    zeta = -values.real[order] / np.abs(values)[order]
    expected = sorted([(LAMBDA[0] ** 2 * np.sqrt(EI_Y / (RHO * L ** 4)), 0.02),
                       (LAMBDA[0] ** 2 * np.sqrt(EI_Z / (RHO * L ** 4)), 0.01),
                       (LAMBDA[1] ** 2 * np.sqrt(EI_Y / (RHO * L ** 4)), 0.02),
                       (LAMBDA[1] ** 2 * np.sqrt(EI_Z / (RHO * L ** 4)), 0.03),
                       (np.pi / (2 * L) * np.sqrt(GJ / RHO_IP), 0.05),
                       (np.pi / (2 * L) * np.sqrt(EA / RHO), 0.04)])
    w_expected, zeta_expected = np.array(expected).T
    np.testing.assert_allclose(omega, w_expected, rtol=1e-6)                # eq. 8.7, torsion, axial
    np.testing.assert_allclose(values.real[order], -zeta_expected * omega, rtol=1e-8)
    np.testing.assert_allclose(zeta, zeta_expected, rtol=1e-8)


def test_modal_damping_of_a_spatial_beam_is_read_written_and_checked():
    from flexkane.model import dumps_model

    model = loads_model(DAMPED)
    beam = model.beams["b"]
    assert (beam.damping_y, beam.damping_z, beam.torsion_damping, beam.axial_damping) == (
        [0.01, 0.03], [0.02], [0.05], [0.04])
    assert loads_model(dumps_model(model)) == model
    with pytest.raises(ModelError, match=r"beams\.b\.damping_y.*1 or 2 modal damping ratios"):
        loads_model(DAMPED.replace("damping_y = [0.01, 0.03]", "damping_y = [0.01, 0.03, 0.02]"))
    with pytest.raises(ModelError, match=r"beams\.b\.damping_z\[0\].*non-negative"):
        loads_model(DAMPED.replace("damping_z = 0.02", "damping_z = -0.02"))
    with pytest.raises(ModelError, match=r"beams\.b\.damping\b.*damping_y, damping_z"):
        loads_model(DAMPED.replace("damping_z = 0.02", "damping = 0.02"))
    with pytest.raises(ModelError, match=r"beams\.b\.rho_Ip.*torsion_damping"):
        loads_model(DAMPED.replace(f"rho_Ip = {RHO_IP}\n", ""))
