"""Static correction shapes and the polynomial torsion and axial families.

Oracles: the statics of a cantilever (tip deflection P L^3 / (3 EI) under a tip force, tip slope
M L / EI under a tip moment, tip twist T L / GJ under a tip torque, tip stretch F L / EA under an
axial force), reproduced exactly by a Ritz solution in a basis that holds the static shapes and
missed by the modes alone (whose free-tip conditions cannot carry the load); the Rayleigh quotient,
an upper bound of the first frequency; the admissibility of the functions at a clamped root.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import scipy.linalg

import flexkane
from flexkane.errors import ModelError
from flexkane.modes import get_family
from flexkane.modes.from_spec import beam_shape_family, tip_attachments
from flexkane.modes.integrals import mass_integrals, stiffness_integrals
from flexkane.modes.static_correction import StaticCorrection

L, EI, GJ, EA, RHO = 1.3, 2.0e3, 7.0e2, 5.0e6, 2.5


def ritz_tip_response(family, n: int, rigidity: float, deriv: int) -> float:
    """Tip value (``deriv = 0``) or tip slope (1) of the Ritz solution under a unit tip load that
    works on that value: ``K q = Phi^(deriv)(L)``, response ``Phi^(deriv)(L) . q``."""
    K = stiffness_integrals(family, n, L, rigidity)
    load = family.phi(np.ones(1), n, deriv)[:, 0] / L ** deriv
    return float(load @ np.linalg.solve(K, load))


@pytest.mark.parametrize("base, n, rigidity, deriv, exact", [
    ("clamped-free", 3, EI, 0, L ** 3 / (3 * EI)),          # deflection under a tip force
    ("clamped-free", 3, EI, 1, L / EI),                      # slope under a tip moment
    ("torsion-clamped-free", 2, GJ, 0, L / GJ),              # twist under a tip torque
    ("axial-fixed-free", 2, EA, 0, L / EA),                  # stretch under a tip force
])
def test_corrected_basis_gives_the_exact_static_tip_response_the_modes_miss(base, n, rigidity, deriv, exact):
    family = get_family(base)
    corrected = StaticCorrection(family, n)
    assert ritz_tip_response(corrected, n, rigidity, deriv) == pytest.approx(exact, rel=1e-10)
    assert abs(ritz_tip_response(family, n, rigidity, deriv) / exact - 1) > 1e-3


@pytest.mark.parametrize("base, n", [("clamped-free", 6), ("torsion-clamped-free", 5), ("axial-fixed-free", 1),
                                     ("clamped-free-tip-mass", 4)])
def test_correction_shapes_are_admissible_mass_orthonormal_and_follow_the_modes(base, n):
    family = get_family(base, **({"mass_ratio": 0.5, "inertia_ratio": 0.0} if base.endswith("tip-mass") else {}))
    corrected = StaticCorrection(family, n)
    k = 2 if family.kind == "transverse" else 1
    kept = n - min(k, n - 1)              # the family's first function always stays
    xi = np.linspace(0.0, 1.0, 41)
    if kept:
        np.testing.assert_allclose(corrected.phi(xi, kept), family.phi(xi, kept), rtol=0, atol=1e-12)
    corrected.admissibility(family.boundary)
    G = mass_integrals(corrected, n, 1.0, 1.0).G
    added = slice(kept, n)
    np.testing.assert_allclose(G[added, added], np.eye(n - kept), atol=1e-10)
    np.testing.assert_allclose(G[:kept, added], 0.0, atol=1e-10)
    assert corrected.corrections() == n - kept
    assert np.linalg.cond(G) < 1e3


def test_derivatives_of_the_corrected_functions_are_those_of_their_values():
    corrected = StaticCorrection(get_family("clamped-free"), 4)
    xi = np.linspace(0.05, 0.95, 7)
    step = 1e-6
    for deriv in range(4):
        numeric = (corrected.phi(xi + step, 4, deriv) - corrected.phi(xi - step, 4, deriv)) / (2 * step)
        np.testing.assert_allclose(corrected.phi(xi, 4, deriv + 1), numeric, rtol=1e-6, atol=1e-5)


def test_dependent_correction_is_dropped_with_a_message_and_the_mass_matrix_stays_regular():
    """Monomials xi^2 .. xi^5 already span the static tip shapes (cubics): both are dropped, with a
    warning each, and the next monomials take their places (the same space as the family's)."""
    family = get_family("polynomial")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        corrected = StaticCorrection(family, 4, "beams.b.shape")
    messages = [str(w.message) for w in caught]
    assert [m.split(" is spanned")[0] for m in messages] == [
        "beams.b.shape: the static correction shape of a unit tip force",
        "beams.b.shape: the static correction shape of a unit tip moment"]
    assert all("dropped, the next function of the family takes its place" in m for m in messages)
    assert corrected.corrections() == 0
    G = mass_integrals(corrected, 4, L, RHO).G
    assert np.linalg.cond(G) < 1e8
    frequencies = [np.sqrt(scipy.linalg.eigh(stiffness_integrals(f, 4, L, EI), mass_integrals(f, 4, L, RHO).G,
                                             eigvals_only=True)[0]) for f in (family, corrected)]
    assert frequencies[1] == pytest.approx(frequencies[0], rel=1e-9)


def test_a_family_without_a_clamped_root_and_free_tip_gets_no_corrections():
    with pytest.raises(ModelError, match="a family with a clamped \\(or fixed\\) root and a free tip"):
        StaticCorrection(get_family("pinned-pinned"), 3, "beams.b.shape")


@pytest.mark.parametrize("name, kind, beta", [("torsion-polynomial", "torsion", math.pi / 2),
                                              ("axial-polynomial", "axial", math.pi / 2)])
def test_polynomial_torsion_and_axial_families_converge_to_the_first_wave_frequency(name, kind, beta):
    family = get_family(name)
    assert family.kind == kind and family.boundary == "fixed-free"
    family.admissibility("fixed-free")
    np.testing.assert_allclose(family.phi(np.array([0.5]), 3, 0)[:, 0], [0.5, 0.25, 0.125])
    np.testing.assert_allclose(family.phi(np.array([0.5]), 3, 1)[:, 0], [1.0, 1.0, 0.75])
    M = mass_integrals(family, 7, 1.0, 1.0).G
    K = stiffness_integrals(family, 7, 1.0, 1.0)
    lowest = np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True)[0])
    assert lowest == pytest.approx(beta, rel=1e-9) and lowest >= beta


TIP_MODEL = """
name = "tip"
[parameters]
L = 1.3
[bodies.mass]
mass = 2.0
inertia = 0.01
[beams.b]
L = "L"
EI = 2000.0
rho = 2.5
n_modes = 3
{extra}
[joints.clamp]
type = "weld"
parent = "ground"
child = "b"
parent_position = [0, 0]
[joints.tip]
type = "weld"
parent = "b"
station = "{station}"
child = "mass"
"""


def test_a_beam_carrying_a_body_at_its_tip_gets_the_corrections_by_default():
    model = flexkane.loads_model(TIP_MODEL.format(extra="", station="L"))
    beam = model.beams["b"]
    assert beam.static_corrections is True
    assert tip_attachments(model, beam, {"L": 1.3}) == ("joints.tip.station",)
    family = beam_shape_family(model, beam, "shape", {"L": 1.3})
    assert isinstance(family, StaticCorrection) and family.corrections() == 2


def test_static_corrections_false_keeps_the_family_and_round_trips():
    model = flexkane.loads_model(TIP_MODEL.format(extra="static_corrections = false", station="L"))
    assert beam_shape_family(model, model.beams["b"], "shape", {"L": 1.3}) == get_family("clamped-free")
    again = flexkane.loads_model(flexkane.dumps_model(model))
    assert again.beams["b"].static_corrections is False


def test_a_station_short_of_the_tip_adds_no_corrections():
    model = flexkane.loads_model(TIP_MODEL.format(extra="", station="L/2"))
    assert tip_attachments(model, model.beams["b"], {"L": 1.3}) == ()
    assert beam_shape_family(model, model.beams["b"], "shape", {"L": 1.3}) == get_family("clamped-free")


def test_static_corrections_must_be_true_or_false():
    with pytest.raises(ModelError) as caught:
        flexkane.loads_model(TIP_MODEL.format(extra='static_corrections = "yes"', station="L"))
    assert caught.value.path == "beams.b.static_corrections"
    assert "true or false" in caught.value.expected and caught.value.given == "yes"


def test_tip_mass_on_the_corrected_basis_is_closer_to_the_exact_frequency():
    """A cantilever with a tip mass M = rho L: exact first frequency from the tip-mass family's
    eigenvalue; three functions with the corrections beat three clamped-free modes."""
    exact = get_family("clamped-free-tip-mass", mass_ratio=1.0, inertia_ratio=0.0).frequencies(1, L, EI, RHO)[0]

    def first(family):
        M = mass_integrals(family, 3, L, RHO).G
        tip = family.phi(np.ones(1), 3)[:, 0]
        M = M + RHO * L * np.outer(tip, tip)
        return np.sqrt(scipy.linalg.eigh(stiffness_integrals(family, 3, L, EI), M, eigvals_only=True)[0])

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        corrected = StaticCorrection(get_family("clamped-free"), 3)
    modes = first(get_family("clamped-free")) / exact - 1
    assert 0 < first(corrected) / exact - 1 < modes / 10


def test_user_expressions_get_the_correction_shapes_of_their_use():
    """Expressions of xi serve any basis: in a torsion basis the correction is the twist under a tip
    torque (xi), not a bending shape."""
    import sympy

    xi = sympy.Symbol("xi")
    family = get_family("expression", expressions=[sympy.sin(sympy.pi * xi / 2), sympy.sin(3 * sympy.pi * xi / 2)],
                        boundary="fixed-free")
    corrected = StaticCorrection(family, 2, "beams.b.torsion_shape", kind="torsion")
    assert corrected.kind == "torsion" and corrected.corrections() == 1
    assert ritz_tip_response(corrected, 2, GJ, 0) == pytest.approx(L / GJ, rel=1e-10)
