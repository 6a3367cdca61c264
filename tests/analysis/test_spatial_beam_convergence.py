"""Convergence studies on a spatial beam: modes added per bending plane and of torsion.

Oracles: the clamped frequencies (eq. 8.7 with EI_y for the deflection along z, EI_z for the one
along y; torsion (2k - 1) pi/(2L) sqrt(GJ/rho_Ip)). With the beam's own eigenfunctions
(``clamped-free``, ``torsion-clamped-free``) they are exact for every number of modes; with
Rayleigh-Ritz polynomials (``xi^2, xi^3, ...``) they converge to them from above.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest

from flexkane.analysis import convergence_study
from flexkane.model import loads_model
from spatial_beam_models import EI_Y, EI_Z, GJ, L, RHO, RHO_IP, clamped_spatial_beam

LAMBDA = np.array([1.8751040687119611, 4.6940911329741745, 7.854757438237613])   # eq. 8.4

BEAM = clamped_spatial_beam("clamped-spatial-beam", """
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
shape_z = { family = "polynomial" }
""")


def bending(EI: float) -> np.ndarray:
    return LAMBDA ** 2 * np.sqrt(EI / (RHO * L ** 4))


def torsion(k: int) -> float:
    return (2 * k - 1) * np.pi / (2 * L) * np.sqrt(GJ / RHO_IP)


@pytest.fixture(scope="module")
def study():
    return convergence_study(loads_model(BEAM), [1, 2, 3], count=9)


def test_every_family_of_a_spatial_beam_gets_the_added_modes(study):
    assert [len(row) for row in study.labels] == [3, 6, 9]
    assert sorted(study.labels[-1]) == sorted(f"{kind} {k}" for kind in ("bending y", "bending z", "torsion")
                                              for k in (1, 2, 3))


def test_spatial_beam_frequencies_converge_to_the_analytic_values(study):
    curves = study.curves()
    exact = bending(EI_Y)
    ritz = curves["bending z 1"]
    assert np.all(np.diff(ritz) < 0) and np.all(ritz > exact[0])          # from above
    # the classical Rayleigh-Ritz values of the monomials: sqrt(20); 3.5327 and 34.807 (x^2, x^3)
    unit = np.sqrt(EI_Y / (RHO * L ** 4))
    assert ritz[0] == pytest.approx(np.sqrt(20.0) * unit, rel=1e-10)
    assert ritz[1] == pytest.approx(3.5327 * unit, rel=2e-5)
    assert curves["bending z 2"][1] == pytest.approx(34.807 * unit, rel=2e-5)
    assert ritz[-1] == pytest.approx(exact[0], rel=5e-4)
    assert curves["bending z 2"][-1] == pytest.approx(exact[1], rel=1e-2)
    for k in (1, 2, 3):      # the eigenfunctions give the exact values whatever the count
        present = ~np.isnan(curves[f"bending y {k}"])
        np.testing.assert_allclose(curves[f"bending y {k}"][present], bending(EI_Z)[k - 1], rtol=1e-8)
        np.testing.assert_allclose(curves[f"torsion {k}"][present], torsion(k), rtol=1e-8)
    assert list(np.isnan(curves["torsion 3"])) == [True, True, False]


def test_convergence_csv_of_a_spatial_beam_names_the_motions(study):
    rows = list(csv.DictReader(study.csv_text().splitlines()))
    assert rows[0]["motion_1"] == "bending z 1" and rows[0]["motion_4"] == ""
    assert float(rows[0]["omega_3 [rad/s]"]) == pytest.approx(torsion(1), rel=1e-8)
    assert "bending z 1 [rad/s]" in study.table().splitlines()[0]


@pytest.mark.slow
def test_converge_command_on_a_spatial_beam(tmp_path, capsys):
    from flexkane.cli import main

    path = tmp_path / "beam.toml"
    path.write_text(BEAM)
    out = tmp_path / "v"
    assert main(["converge", str(path), "--n-modes", "1..2", "--count", "6", "--out", str(out)]) == 0
    assert "torsion 1 [rad/s]" in capsys.readouterr().out
    rows = list(csv.DictReader((out / "convergence.csv").read_text().splitlines()))
    assert [r["motion_3"] for r in rows] == ["torsion 1", "torsion 1"]
    assert float(rows[1]["omega_3 [rad/s]"]) == pytest.approx(torsion(1), rel=1e-8)
