"""Physics through a sweep: one derivation serves every stiffness, and the beam obeys its scaling laws.

The falling body with its exact cantilever (falling-beam-exact, one mode) starts with q4 = 1e-4 m and
no speed. Linearized, the only elastic force is -H_11 q4 with H_11 proportional to EI (eq. 8.32),
and the rigid modes carry no q4, so q4 oscillates about zero at a frequency proportional to sqrt(EI)
with the amplitude it started with, whatever EI.
"""

import numpy as np
import pytest

import flexkane
from flexkane.sweep import SweepSpec, read_table, run_sweep

EI_VALUES = (20.0, 45.0, 80.0)


def q4_frequency(results) -> float:
    """Angular frequency [rad/s] from the mean spacing of the zero crossings of q4."""
    t, q4 = results.t, results["q4"]
    k = np.nonzero(np.sign(q4[:-1]) * np.sign(q4[1:]) < 0)[0]
    crossings = t[k] - q4[k] * (t[k + 1] - t[k]) / (q4[k + 1] - q4[k])
    assert len(crossings) >= 5
    half_period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    return np.pi / half_period


@pytest.fixture(scope="module")
def stiffness_sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("ei-sweep")
    spec = SweepSpec(vary=("beams.B.EI=" + ",".join(map(str, EI_VALUES)),), t_end=0.6, dt_out=2e-4,
                     rtol=1e-10, atol=1e-13, save_trajectories=True)
    outcome = run_sweep("falling-beam-exact", spec, out=out, workers=1)
    return outcome, read_table(out, as_rows=True), out


def test_stiffness_sweep_derives_once_and_keeps_every_trajectory(stiffness_sweep):
    outcome, rows, out = stiffness_sweep
    assert outcome.structures == 1 and outcome.computed == 3
    assert [r["status"] for r in rows] == ["ok"] * 3
    for row in rows:
        assert (out / "variants" / row["variant"] / "results.npz").is_file()


def test_q4_frequency_scales_like_the_square_root_of_EI(stiffness_sweep):
    _, rows, out = stiffness_sweep
    omega = np.array([q4_frequency(flexkane.load_results(out / "variants" / r["variant"])) for r in rows])
    ei = np.array([r["beams.B.EI"] for r in rows])
    assert list(ei) == list(EI_VALUES)
    np.testing.assert_allclose(omega / np.sqrt(ei), omega[0] / np.sqrt(ei[0]), rtol=2e-3)
    # stiffer than the clamped cantilever alone (eq. 8.7), since the free body moves with the beam
    p1 = 1.8751040687 ** 2 * np.sqrt(ei / (0.21991 * 1.0 ** 4))
    assert np.all(omega > p1)


def test_tip_amplitude_is_the_initial_deflection_and_energy_is_conserved(stiffness_sweep):
    _, rows, _ = stiffness_sweep
    for row in rows:
        # tip deflection Phi_1(L) q4(0) = 2 x 1e-4 m for the normalized cantilever mode
        assert row["max_abs_tip_B"] == pytest.approx(2e-4, rel=1e-3)
        assert row["energy_check"] == "drift" and row["energy_error"] < 1e-8


def test_results_of_the_shared_derivation_equal_a_run_derived_on_its_own(stiffness_sweep):
    _, rows, out = stiffness_sweep
    model = flexkane.builtin_model("falling-beam-exact")
    model.beams["B"].EI = 80.0
    alone = flexkane.simulate(flexkane.compile_model(flexkane.derive(model)), t_end=0.6, dt_out=2e-4,
                              rtol=1e-10, atol=1e-13, model=model)
    swept = flexkane.load_results(out / "variants" / rows[-1]["variant"])
    np.testing.assert_array_equal(swept.state, alone.state)
