"""Automatic switching between DOP853 and Radau IIA on DOP853's stiffness test and counted work."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from flexkane.numerics import integrate
from flexkane.numerics.switching import (
    SETTLED_GROWTH, STEP_RATIO, TRIAL_STEPS, WARMUP_CHUNKS_MAX, WARMUP_STEPS, MethodSwitch,
    chunk_work, evaluation_work)


def _warm_up(switch, method, t, h=1e-4):
    """Two warm-up chunks of ``method`` at a settled step size ``h``; returns the time reached."""
    for _ in range(2):
        assert switch.next_chunk() == (method, WARMUP_STEPS)
        switch.record(method, t, t + 1e-3, work=1.0, naccept=WARMUP_STEPS, nstiff=0, h=h)
        t += 1e-3
    return t


def test_stability_limited_dop853_chunk_calls_for_a_radau_trial():
    switch = MethodSwitch("dop853", 0.0, 1.0)
    switch.record("dop853", 0.0, 0.01, work=1e-3, naccept=100, nstiff=10)
    assert switch.next_chunk() == ("dop853", None)  # accuracy-limited: no trial
    switch.record("dop853", 0.01, 0.02, work=1e-3, naccept=100, nstiff=80)
    assert switch.next_chunk() == ("radau", WARMUP_STEPS)  # the trial starts with its warm-up
    _warm_up(switch, "radau", 0.02)
    assert switch.next_chunk() == ("radau", TRIAL_STEPS["radau"])


def test_trial_that_is_faster_by_the_margin_takes_over_and_a_slower_one_does_not():
    switch = MethodSwitch("dop853", 0.0, 1.0)
    switch.record("dop853", 0.0, 0.01, work=1e-2, naccept=100, nstiff=90, h=1e-4)
    t = _warm_up(switch, "radau", 0.01)
    switch.record("radau", t, t + 0.005, work=5e-4, naccept=20, nstiff=0, h=1e-4)
    assert switch.next_chunk() == ("radau", TRIAL_STEPS["radau"] - 20)  # trial goes on
    switch.record("radau", t + 0.005, t + 0.01, work=5e-4, naccept=20, nstiff=0, h=1e-4)  # 10 times faster
    assert switch.current == "radau" and switch.switches == 1
    slow = MethodSwitch("dop853", 0.0, 1.0)
    slow.record("dop853", 0.0, 0.01, work=1e-2, naccept=100, nstiff=90, h=1e-4)
    t = _warm_up(slow, "radau", 0.01)
    slow.record("radau", t, t + 0.01, work=0.9e-2, naccept=40, nstiff=0, h=1e-4)  # within the margin
    assert slow.current == "dop853"
    slow.record("dop853", 0.03, 0.04, work=1e-2, naccept=100, nstiff=90)
    assert slow.next_chunk() == ("dop853", None)  # no new trial before RECHECK_FRACTION


def test_radau_retries_dop853_only_when_it_stops_being_much_faster():
    switch = MethodSwitch("dop853", 0.0, 1.0)
    switch.record("dop853", 0.0, 0.01, work=1e-2, naccept=100, nstiff=90)
    t = _warm_up(switch, "radau", 0.01)
    switch.record("radau", t, 0.02, work=1e-3, naccept=40, nstiff=0)
    switch.record("radau", 0.02, 0.5, work=0.05, naccept=100, nstiff=0)  # still 10 times faster
    assert switch.next_chunk() == ("radau", None)
    switch.record("radau", 0.5, 0.51, work=0.008, naccept=100, nstiff=0)  # now 1.25 times
    assert switch.next_chunk() == ("dop853", WARMUP_STEPS)
    t = _warm_up(switch, "dop853", 0.51)
    assert switch.next_chunk() == ("dop853", TRIAL_STEPS["dop853"])
    assert switch.main_method == "radau"


def test_warm_up_of_a_trial_is_not_judged_and_ends_when_the_step_size_stops_growing():
    # Radau taking over starts with small steps, a fresh Jacobian and LU decompositions: its
    # first chunks cost 100 times more per second than DOP853's; settled, it is 10 times cheaper
    switch = MethodSwitch("dop853", 0.0, 1.0)
    switch.record("dop853", 0.0, 0.01, work=1e-2, naccept=100, nstiff=90, h=1e-5)
    t = 0.01
    for h in (1e-5, 4e-5, 9e-5):  # growing by more than SETTLED_GROWTH: still warming up
        assert switch.next_chunk() == ("radau", WARMUP_STEPS)
        switch.record("radau", t, t + 1e-4, work=1e-2, naccept=WARMUP_STEPS, nstiff=0, h=h)
        t += 1e-4
    assert 9e-5 > SETTLED_GROWTH * 4e-5 and WARMUP_CHUNKS_MAX > 3
    assert switch.next_chunk() == ("radau", WARMUP_STEPS)
    switch.record("radau", t, t + 1e-3, work=1e-2, naccept=WARMUP_STEPS, nstiff=0, h=1e-4)  # settled
    assert switch.next_chunk() == ("radau", TRIAL_STEPS["radau"])  # the judged trial starts
    switch.record("radau", t, t + 0.01, work=1e-3, naccept=TRIAL_STEPS["radau"], nstiff=0, h=1e-4)
    assert switch.current == "radau"  # judged on its settled steps alone (with them: 4 times costlier)


def test_warm_up_ends_after_its_last_chunk_even_if_the_step_size_still_grows():
    switch = MethodSwitch("dop853", 0.0, 1.0)
    switch.record("dop853", 0.0, 0.01, work=1e-2, naccept=100, nstiff=90)
    t, h = 0.01, 1e-6
    for _ in range(WARMUP_CHUNKS_MAX):
        assert switch.next_chunk() == ("radau", WARMUP_STEPS)
        switch.record("radau", t, t + 1e-4, work=1e-2, naccept=WARMUP_STEPS, nstiff=0, h=h)
        t, h = t + 1e-4, 2 * h
    assert switch.next_chunk() == ("radau", TRIAL_STEPS["radau"])


def test_radau_within_the_margin_takes_over_when_its_steps_are_much_longer():
    # equal work per simulated second: Radau's steps follow the motion, DOP853's the fast modes
    for h_radau, expected in ((STEP_RATIO * 1.1e-5, "radau"), (STEP_RATIO * 0.9e-5, "dop853")):
        switch = MethodSwitch("dop853", 0.0, 1.0)
        switch.record("dop853", 0.0, 0.01, work=1e-2, naccept=100, nstiff=90, h=1e-5)
        t = _warm_up(switch, "radau", 0.01, h_radau)
        switch.record("radau", t, t + 0.01, work=1e-2, naccept=40, nstiff=0, h=h_radau)
        assert switch.current == expected
    # DOP853 taking over needs the margin whatever its steps
    switch = MethodSwitch("radau", 0.0, 1.0)
    switch.record("radau", 0.0, 0.3, work=0.3, naccept=100, nstiff=0, h=1e-5)
    t = _warm_up(switch, "dop853", 0.3, 1e-3)
    switch.record("dop853", t, t + 0.01, work=1e-2, naccept=200, nstiff=0, h=1e-3)
    assert switch.current == "radau"


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


def test_auto_keeps_dop853_where_every_mode_must_be_resolved(stiff_chain_module):
    """Lightly damped springs, every mode excited: no method may step over a mode, so DOP853 does
    the least work and ``auto`` is DOP853 throughout, bit for bit, run after run."""
    p = np.array([1, 1, 1, 1, 100, 100, 100, 100, 1e-3, 1e-3, 1e-3, 1e-3], float)
    y0 = np.array([0.1, -0.05, 0.08, -0.02, 0.0, 0.3, -0.2, 0.1])
    t = np.linspace(0.0, 5.0, 101)
    auto = integrate(stiff_chain_module, y0, t, p, rtol=1e-8, atol=1e-10)
    again = integrate(stiff_chain_module, y0, t, p, rtol=1e-8, atol=1e-10)
    dop = integrate(stiff_chain_module, y0, t, p, rtol=1e-8, atol=1e-10, method="dop853")
    assert auto.success and auto.method == "dop853" and auto.method_spans["radau"] == 0.0
    assert auto.y.tobytes() == dop.y.tobytes() == again.y.tobytes()
    assert (auto.nfev, auto.nsteps) == (dop.nfev, dop.nsteps)


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
