"""Automatic switching between DOP853 and Radau IIA on DOP853's stiffness test and counted work."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from flexkane.numerics import integrate
from flexkane.numerics.switching import MethodSwitch, TRIAL_STEPS, chunk_work, evaluation_work


def test_stability_limited_dop853_chunk_calls_for_a_radau_trial():
    switch = MethodSwitch("dop853", 0.0, 1.0)
    switch.record("dop853", 0.0, 0.01, work=1e-3, naccept=100, nstiff=10)
    assert switch.next_chunk() == ("dop853", None)  # accuracy-limited: no trial
    switch.record("dop853", 0.01, 0.02, work=1e-3, naccept=100, nstiff=80)
    assert switch.next_chunk() == ("radau", TRIAL_STEPS["radau"])


def test_trial_that_is_faster_by_the_margin_takes_over_and_a_slower_one_does_not():
    switch = MethodSwitch("dop853", 0.0, 1.0)
    switch.record("dop853", 0.0, 0.01, work=1e-2, naccept=100, nstiff=90)
    switch.record("radau", 0.01, 0.015, work=5e-4, naccept=20, nstiff=0)
    assert switch.next_chunk() == ("radau", TRIAL_STEPS["radau"] - 20)  # trial goes on
    switch.record("radau", 0.015, 0.02, work=5e-4, naccept=20, nstiff=0)  # 10 times faster
    assert switch.current == "radau" and switch.switches == 1
    slow = MethodSwitch("dop853", 0.0, 1.0)
    slow.record("dop853", 0.0, 0.01, work=1e-2, naccept=100, nstiff=90)
    slow.record("radau", 0.01, 0.02, work=0.9e-2, naccept=40, nstiff=0)  # within the margin
    assert slow.current == "dop853"
    slow.record("dop853", 0.02, 0.03, work=1e-2, naccept=100, nstiff=90)
    assert slow.next_chunk() == ("dop853", None)  # no new trial before RECHECK_FRACTION


def test_radau_retries_dop853_only_when_it_stops_being_much_faster():
    switch = MethodSwitch("dop853", 0.0, 1.0)
    switch.record("dop853", 0.0, 0.01, work=1e-2, naccept=100, nstiff=90)
    switch.record("radau", 0.01, 0.02, work=1e-3, naccept=40, nstiff=0)
    switch.record("radau", 0.02, 0.5, work=0.05, naccept=100, nstiff=0)  # still 10 times faster
    assert switch.next_chunk() == ("radau", None)
    switch.record("radau", 0.5, 0.51, work=0.008, naccept=100, nstiff=0)  # now 1.25 times
    assert switch.next_chunk() == ("dop853", TRIAL_STEPS["dop853"])
    assert switch.main_method == "radau"


def test_auto_switches_to_radau_on_slow_mode_of_a_stiff_bar(models, stiff_chain_module):
    """Masses joined by stiff springs, held by a soft one: the motion is the slow mode alone.

    DOP853 is held at its stability limit by the stiff modes (about 200 rad/s) that carry no
    amplitude; Radau follows the slow mode (about 0.5 rad/s) with long steps.
    """
    p = np.array([1, 1, 1, 1, 1, 1e4, 1e4, 1e4, 1e-3, 1e-3, 1e-3, 1e-3], float)
    A = models.stiff_chain_matrix(p)
    lam, vec = np.linalg.eig(A)
    slow = np.argmin(np.abs(lam))
    y0 = np.real(vec[:, slow] / vec[0, slow]) * 0.1
    t = np.linspace(0.0, 20.0, 201)
    auto = integrate(stiff_chain_module, y0, t, p, rtol=1e-4, atol=1e-6)
    dop = integrate(stiff_chain_module, y0, t, p, rtol=1e-4, atol=1e-6, method="dop853")
    assert auto.success and auto.method == "radau"
    assert auto.method_spans["radau"] > 15.0
    assert auto.nfev < 0.5 * dop.nfev
    np.testing.assert_allclose(auto.y[:, 0], dop.y[:, 0], atol=2e-3)


def test_work_model_charges_radau_for_its_linear_algebra():
    dop = chunk_work("dop853", 8, 100, nfev=1200, nsteps=100)
    radau = chunk_work("radau", 8, 100, nfev=1200, nsteps=100, nlu=50)
    assert dop == 1200 * (evaluation_work(100, 8) + 14 * 8)
    assert radau > dop  # same evaluations, plus back substitutions and LU decompositions
    assert chunk_work("radau", 8, 100, 1200, 100, nlu=60) > radau
    # a larger system costs more per decomposition, cubically
    assert chunk_work("radau", 80, 100, 0, 0, nlu=1) > 500 * chunk_work("radau", 8, 100, 0, 0, nlu=1)


def _spin(seconds: float) -> subprocess.Popen:
    """A process keeping one core busy for ``seconds`` (a loaded machine)."""
    return subprocess.Popen([sys.executable, "-c",
                             f"import time\nend = time.time() + {seconds}\nwhile time.time() < end: pass"])


def test_automatic_choice_is_the_same_under_load(models, stiff_chain_module):
    """The choice is made from counted work: a busy core beside one of two runs changes nothing."""
    p = np.array([1, 1, 1, 1, 1, 1e4, 1e4, 1e4, 1e-3, 1e-3, 1e-3, 1e-3], float)
    lam, vec = np.linalg.eig(models.stiff_chain_matrix(p))
    slow = np.argmin(np.abs(lam))
    y0 = np.real(vec[:, slow] / vec[0, slow]) * 0.1
    t = np.linspace(0.0, 20.0, 201)
    quiet = integrate(stiff_chain_module, y0, t, p, rtol=1e-4, atol=1e-6)
    busy = _spin(60.0)
    try:
        loaded = integrate(stiff_chain_module, y0, t, p, rtol=1e-4, atol=1e-6)
    finally:
        busy.kill()
        busy.wait()
    assert quiet.method_spans["dop853"] > 0 and quiet.method_spans["radau"] > 0  # it switched
    assert quiet.method_spans == loaded.method_spans
    assert (quiet.nfev, quiet.nsteps) == (loaded.nfev, loaded.nsteps)
    assert quiet.y.tobytes() == loaded.y.tobytes()
