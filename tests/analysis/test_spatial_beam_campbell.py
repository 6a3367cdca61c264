"""Campbell diagrams of a spatial blade: flap, lag and torsion curves from one model, labelled by motion.

Oracles: Southwell's omega_lag^2 = omega_flap^2 - Omega^2 for a uniform blade with EI_y = EI_z on a
hub spinning about an axis normal to it; with one shape function per plane the flap and lag
frequencies are exactly ``omega_f0^2 + K_1 Omega^2`` and ``omega_l0^2 + (K_1 - 1) Omega^2`` (K_1 the
Rayleigh quotient of the centrifugal tension, computed here from the shape function), the torsion
frequency is ``pi/(2L) sqrt(GJ/rho_Ip)``, and the clamped frequencies at rest are eq. 8.7 with EI_y
(flap: deflection along z, out of the plane of rotation) and EI_z (lag).
"""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from flexkane.analysis import campbell_diagram
from flexkane.model import loads_model

LAMBDA_1 = 1.8751040687119611          # first clamped-free root, eq. 8.4
L, RHO, GJ, RHO_IP = 2.0, 1.5, 20.0, 0.02
SPINS = [0.0, 3.0, 6.0]

BLADE = """
dimensions = 3
name = "spinning-blade"

[parameters]
EI_y = {EI_y}
EI_z = {EI_z}

[beams.blade]
L = {L}
rho = {rho}
EI_y = "EI_y"
EI_z = "EI_z"
GJ = {GJ}
rho_Ip = {rho_Ip}
n_modes_y = {n}
n_modes_z = {n}
n_torsion = 1
geometric_stiffening = true

[joints.hub]
type = "revolute"
parent = "ground"
child = "blade"
axis = [0, 0, 1]
"""


def blade(EI_y: float, EI_z: float, n: int) -> object:
    return loads_model(BLADE.format(EI_y=EI_y, EI_z=EI_z, n=n, L=L, rho=RHO, GJ=GJ, rho_Ip=RHO_IP))


def clamped(EI: float) -> float:
    """First clamped-free bending frequency [rad/s], eq. 8.7."""
    return LAMBDA_1 ** 2 * np.sqrt(EI / (RHO * L ** 4))


def southwell_coefficient() -> float:
    """``K_1 = int (L^2 - x^2)/2 Phi_1'^2 dx / int Phi_1^2 dx`` of the first clamped-free mode."""
    from flexkane.modes import get_family

    family = get_family("clamped-free")
    xi, w = np.polynomial.legendre.leggauss(60)
    xi, w = (xi + 1) / 2, w / 2
    x = xi * L
    slope = family.phi(xi, 1, 1)[0] / L
    return float(np.sum(w * (L ** 2 - x ** 2) / 2 * slope ** 2) / np.sum(w * family.phi(xi, 1)[0] ** 2))


@pytest.fixture(scope="module")
def equal():
    """EI_y = EI_z, two shape functions per plane and one of torsion."""
    return campbell_diagram(blade(30.0, 30.0, 2), SPINS)


@pytest.fixture(scope="module")
def unequal():
    """EI_y < EI_z: the flap mode starts below the lag mode and crosses it as the spin rises."""
    spins = [0.0, 2.0, 4.0, 6.0, 8.0]
    return campbell_diagram(blade(10.0, 30.0, 1), spins)


def test_campbell_curves_of_a_blade_are_flap_lag_and_torsion(equal):
    curves = equal.curves()
    assert sorted(curves) == ["flap 1", "flap 2", "lag 1", "lag 2", "torsion 1"]
    for row in equal.participations:
        for share in row:
            assert max(share.values()) > 1 - 1e-9      # uncoupled: each mode is one motion
    assert not equal.unstable.any()


def test_campbell_output_of_an_equal_stiffness_blade_obeys_southwell(equal):
    """omega_lag^2 = omega_flap^2 - Omega^2, mode by mode, read off the labelled curves."""
    curves = equal.curves()
    spins = np.array(SPINS)
    for k in (1, 2):
        np.testing.assert_allclose(curves[f"lag {k}"] ** 2, curves[f"flap {k}"] ** 2 - spins ** 2, rtol=1e-8)
    assert curves["flap 1"][0] == pytest.approx(clamped(30.0), rel=1e-8)


def test_flap_frequencies_rise_with_the_spin(equal):
    curves = equal.curves()
    for k in (1, 2):
        assert np.all(np.diff(curves[f"flap {k}"]) > 0)


def test_torsion_curve_is_labelled_torsion_at_its_analytic_frequency(equal, unequal):
    expected = np.pi / (2 * L) * np.sqrt(GJ / RHO_IP)
    for diagram in (equal, unequal):
        np.testing.assert_allclose(diagram.curves()["torsion 1"], expected, rtol=1e-8)


def test_labels_follow_flap_and_lag_when_unequal_stiffnesses_swap_their_order(unequal):
    """Flap (EI_y) starts below lag (EI_z) and rises faster: the sorted frequencies swap their motions,
    and each labelled curve keeps its own law."""
    spins = unequal.spins
    K = southwell_coefficient()
    curves = unequal.curves()
    np.testing.assert_allclose(curves["flap 1"] ** 2, clamped(10.0) ** 2 + K * spins ** 2, rtol=1e-8)
    np.testing.assert_allclose(curves["lag 1"] ** 2, clamped(30.0) ** 2 + (K - 1) * spins ** 2, rtol=1e-8)
    first = list(unequal.labels[:, 0])
    assert first[0] == "flap 1" and first[-1] == "lag 1"      # the lowest mode changed motion


def test_campbell_csv_and_json_carry_the_labels(unequal):
    data = json.loads(unequal.json_text())
    assert sorted(data["curves"]) == ["flap 1", "lag 1", "torsion 1"]
    assert data["curves"]["lag 1"][0] == pytest.approx(clamped(30.0), rel=1e-8)
    assert [m["label"] for m in data["modes"][0]] == ["flap 1", "lag 1", "torsion 1"]
    assert data["modes"][0][0]["participation"]["flap"] == pytest.approx(1.0, abs=1e-9)
    rows = list(csv.DictReader(unequal.modes_csv_text().splitlines()))
    assert [r["label"] for r in rows if r["Omega [rad/s]"] == "8.0"] == ["lag 1", "flap 1", "torsion 1"]
    assert unequal.table().splitlines()[0].split()[:6] == ["Omega", "[rad/s]", "flap", "1", "[rad/s]", "lag"]


@pytest.mark.slow
def test_campbell_command_writes_labelled_csv_json_and_plot(tmp_path):
    from flexkane.cli import main

    path = tmp_path / "blade.toml"
    path.write_text(BLADE.format(EI_y=10.0, EI_z=30.0, n=1, L=L, rho=RHO, GJ=GJ, rho_Ip=RHO_IP))
    out = tmp_path / "c"
    assert main(["campbell", str(path), "--spin", "0,8", "--out", str(out), "--quiet"]) == 0
    data = json.loads((out / "campbell.json").read_text())
    assert data["spins"] == [0.0, 8.0] and sorted(data["curves"]) == ["flap 1", "lag 1", "torsion 1"]
    assert data["curves"]["flap 1"][0] == pytest.approx(clamped(10.0), rel=1e-8)
    with open(out / "campbell_modes.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["label"] for r in rows if r["Omega [rad/s]"] == "0.0"] == ["flap 1", "lag 1", "torsion 1"]
    assert [r["label"] for r in rows if r["Omega [rad/s]"] == "8.0"] == ["lag 1", "flap 1", "torsion 1"]
    assert float(rows[0]["participation flap"]) == pytest.approx(1.0, abs=1e-9)
    assert (out / "campbell.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (out / "campbell.csv").read_text().splitlines()[0].startswith("Omega [rad/s],omega_1 [rad/s]")
