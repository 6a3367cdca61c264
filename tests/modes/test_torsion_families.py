"""Torsion shape families: normalisation, boundary conditions, and frequencies against an
independent Rayleigh-Ritz solution of the torsion of a uniform shaft with a polynomial basis.

Rayleigh-Ritz: ``theta(x) = sum_k a_k N_k(x / L)`` with ``K_kl = int_0^L GJ N_k' N_l' dx`` and
``M_kl = int_0^L rho I_p N_k N_l dx``; ``K a = p^2 M a``. The basis satisfies the geometric
conditions (twist held at a clamped end) and nothing else, so the Ritz values converge to the
exact frequencies from above.
"""

import math

import numpy as np
import pytest
import scipy.linalg

from flexkane.errors import ModelError
from flexkane.modes import family_names, get_family
from flexkane.modes.integrals import gauss_legendre, stiffness_integrals

L, GJ, RHO_IP = 1.7, 240.0, 0.35

# Polynomial bases: shifted Legendre polynomials P_k(2 xi - 1) (well conditioned), times xi at a
# clamped root and (1 - xi) at a clamped tip.
_XI = np.polynomial.Polynomial([0.0, 1.0])


def _legendre(k):
    return np.polynomial.Legendre.basis(k, domain=[0.0, 1.0]).convert(kind=np.polynomial.Polynomial)


# family -> (polynomial basis function k = 1, 2, ..., first frequencies' beta_k)
TORSION = {
    "torsion-clamped-free": (lambda k: _XI * _legendre(k - 1), [math.pi / 2, 3 * math.pi / 2, 5 * math.pi / 2]),
    "torsion-clamped-clamped": (lambda k: _XI * (1 - _XI) * _legendre(k - 1), [math.pi, 2 * math.pi, 3 * math.pi]),
    "torsion-free-free": (lambda k: _legendre(k - 1), [math.pi, 2 * math.pi, 3 * math.pi]),
}


def ritz_frequencies(basis, count, L, GJ, rho_Ip):
    """Rayleigh-Ritz frequencies [rad/s] of a shaft with ``count`` polynomial functions (ascending,
    rigid rotations included as zeros)."""
    xi, w = gauss_legendre(60)
    polynomials = [basis(k) for k in range(1, count + 1)]
    N = np.array([P(xi) for P in polynomials])
    dN = np.array([P.deriv()(xi) for P in polynomials])       # d/dxi
    K = GJ / L * (dN * w) @ dN.T
    M = rho_Ip * L * (N * w) @ N.T
    p2 = scipy.linalg.eigh(K, M, eigvals_only=True)
    return np.sqrt(np.clip(p2, 0.0, None))


def test_torsion_families_are_registered_as_torsion():
    for name in TORSION:
        assert name in family_names()
        assert get_family(name).kind == "torsion"


@pytest.mark.parametrize("name", list(TORSION))
def test_torsion_modes_are_orthonormal_and_meet_their_end_conditions(name):
    family = get_family(name)
    n = 6
    xi, w = gauss_legendre(80)
    theta = family.phi(xi, n)
    np.testing.assert_allclose((theta * w) @ theta.T, np.eye(n), atol=1e-13)
    ends = family.phi(np.array([0.0, 1.0]), n, 0)
    slopes = family.phi(np.array([0.0, 1.0]), n, 1)
    root, tip = name.split("-")[1:]
    for end, index in ((root, 0), (tip, 1)):
        if end == "clamped":
            np.testing.assert_allclose(ends[:, index], 0.0, atol=1e-13)
        else:                       # a free end carries no torque: GJ Theta' = 0
            np.testing.assert_allclose(slopes[:, index], 0.0, atol=1e-12)
    # each is an eigenfunction: Theta'' = -beta^2 Theta
    beta = family.roots(n)
    np.testing.assert_allclose(family.phi(xi, n, 2), -beta[:, None] ** 2 * theta, atol=1e-11 * beta[-1] ** 2)
    if name == "torsion-free-free":        # orthogonal to the rigid rotation, itself normalised
        rigid = family.rigid_phi(xi)
        np.testing.assert_allclose((theta * w) @ rigid.T, 0.0, atol=1e-13)
        assert (rigid * w) @ rigid.T == pytest.approx(1.0)


def test_torsion_clamped_free_is_the_closed_form():
    xi = np.linspace(0.0, 1.0, 11)
    k = np.arange(1, 4)[:, None]
    np.testing.assert_allclose(get_family("torsion-clamped-free").phi(xi, 3),
                               math.sqrt(2) * np.sin((2 * k - 1) * math.pi * xi / 2), atol=1e-15)


@pytest.mark.parametrize("name", list(TORSION))
def test_torsion_frequencies_equal_rayleigh_ritz_with_polynomials(name):
    basis, beta = TORSION[name]
    family = get_family(name)
    p = family.frequencies(3, L, GJ, RHO_IP)
    np.testing.assert_allclose(p, np.array(beta) / L * math.sqrt(GJ / RHO_IP), rtol=1e-15)
    ritz = ritz_frequencies(basis, 12, L, GJ, RHO_IP)
    if name == "torsion-free-free":
        assert ritz[0] < 1e-6 * p[0]        # the rigid rotation
        ritz = ritz[1:]
    assert np.all(ritz[:3] >= p * (1 - 1e-12))
    np.testing.assert_allclose(ritz[:3], p, rtol=1e-7)


def test_torsion_stiffness_integrals_are_the_modal_stiffnesses():
    """``int GJ Theta_k' Theta_l' dx = rho I_p L p_k^2 delta_kl`` (the analogue of eq. 8.9)."""
    family = get_family("torsion-clamped-free")
    H = stiffness_integrals(family, 4, L, GJ)
    p = family.frequencies(4, L, GJ, RHO_IP)
    np.testing.assert_allclose(H, np.diag(RHO_IP * L * p ** 2), rtol=1e-12, atol=1e-9 * H.max())


@pytest.mark.parametrize("args, path", [((3, L, -1.0, RHO_IP), "GJ"), ((3, L, GJ, 0.0), "rho_Ip"),
                                        ((3, 0.0, GJ, RHO_IP), "L")])
def test_torsion_frequencies_refuse_non_positive_values(args, path):
    with pytest.raises(ModelError) as info:
        get_family("torsion-clamped-free").frequencies(*args)
    assert info.value.path == path


def test_bending_shape_given_a_torsion_family_is_refused_naming_the_field():
    from flexkane import Model
    from flexkane.model.parts import Beam, Joint, ShapeSpec

    model = Model(name="m", parameters={})
    model.beams["B"] = Beam(name="B", L=1.0, EI=1.0, rho=1.0, n_modes=2,
                            shape=ShapeSpec(family="torsion-clamped-free"))
    model.joints["clamp"] = Joint(name="clamp", type="weld", parent="ground", child="B")
    with pytest.raises(ModelError) as info:
        model.validate()
    assert info.value.path == "beams.B.shape.family"
    assert "transverse" in str(info.value) and "torsion" in str(info.value)


def test_modes_command_prints_torsion_frequencies_from_GJ_and_rho_Ip(tmp_path, capsys):
    from flexkane.cli import main

    code = main(["modes", "torsion-clamped-free", "--n", "2", "--L", "2", "--GJ", "100", "--rhoIp", "0.25",
                 "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0 and "beta_i" in out
    assert "15.7079632679" in out and "47.1238898038" in out     # (2k-1) pi/4 * sqrt(100/0.25)
    code = main(["modes", "torsion-clamped-free", "--L", "2", "--GJ", "100", "--rho", "0.25",
                 "--out", str(tmp_path / "again")])
    err = capsys.readouterr().err
    assert code == 2 and "--rhoIp" in err
