"""The chunked driver: failures with partial rows, interruption, progress, method choice."""

from __future__ import annotations

import numpy as np
import pytest

from flexkane.errors import ModelError
from flexkane.numerics import Status, choose_method, integrate


def test_singular_mass_matrix_at_start_is_status_4(troubled_slider_module):
    t = np.linspace(0.0, 1.0, 11)
    result = integrate(troubled_slider_module, [0.0, 0.0], t, [1.0, 0.0, 1.0], rtol=1e-8,
                       atol=1e-8, method="dop853")
    assert result.status == Status.SINGULAR_MASS_MATRIX
    assert "singular mass matrix at t = 0 s" in result.message
    assert result.n_valid == 1 and result.t_reached == 0.0


@pytest.mark.parametrize("method", ["dop853", "radau"])
def test_mass_matrix_becoming_singular_stops_there_with_partial_rows(
        troubled_slider_module, method):
    t = np.linspace(0.0, 2.0, 21)  # mass q = 1 - t vanishes at t = 1
    result = integrate(troubled_slider_module, [1.0, 0.0], t, [1.0, 0.0, 3.0], rtol=1e-8,
                       atol=1e-8, method=method)
    assert result.status == Status.SINGULAR_MASS_MATRIX
    assert result.t_reached == pytest.approx(1.0, abs=1e-6)
    assert result.n_valid in (10, 11) and result.y.shape == (result.n_valid, 2)
    np.testing.assert_allclose(result.y[:, 1], 3.0 * result.t, atol=1e-7)


@pytest.mark.parametrize("method", ["dop853", "radau"])
def test_blow_up_stops_near_singularity_with_accurate_partial_rows(troubled_slider_module, method):
    t = np.linspace(0.0, 2.0, 201)  # q = 1 / (1 - t)
    result = integrate(troubled_slider_module, [1.0, 0.0], t, [0.0, 1.0, 0.0], rtol=1e-8,
                       atol=1e-8, method=method)
    assert result.status in (Status.STEP_TOO_SMALL, Status.NON_FINITE)
    assert 0.99 < result.t_reached < 1.0 + 1e-6
    assert f"{result.t_reached:.6g}" in result.message
    assert result.n_valid in (100, 101)  # the row at t = 1 only if the solver jumped past
    before = result.t < 1.0
    np.testing.assert_allclose(result.y[before, 0], 1.0 / (1.0 - result.t[before]), rtol=1e-5)


def test_max_steps_gives_status_3_and_advice(pendulum_module):
    t = np.linspace(0.0, 10.0, 11)
    result = integrate(pendulum_module, [1.0, 0.0], t, [1.0, 1.0, 9.81], rtol=1e-10,
                       atol=1e-10, method="dop853", max_steps=20)
    assert result.status == Status.MAX_STEPS
    assert "max_steps" in result.message and result.nsteps == 20
    assert 0 < result.n_valid < 11


def test_progress_is_called_and_keyboard_interrupt_returns_partial_rows(pendulum_module):
    t = np.linspace(0.0, 10.0, 1001)
    calls = []

    def progress(t_reached, t_end):
        calls.append((t_reached, t_end))
        if len(calls) == 3:
            raise KeyboardInterrupt

    result = integrate(pendulum_module, [1.0, 0.0], t, [1.0, 1.0, 9.81], rtol=1e-8,
                       atol=1e-8, method="dop853", progress=progress)
    assert result.status == Status.INTERRUPTED
    assert calls[0][1] == 10.0 and calls[0][0] < calls[1][0] < calls[2][0]
    assert result.t_reached == calls[2][0] and result.n_valid == np.sum(t <= calls[2][0])
    assert np.all(np.isfinite(result.y))


def test_progress_reaches_the_end(pendulum_module):
    t = np.linspace(0.0, 10.0, 101)
    calls = []
    result = integrate(pendulum_module, [1.0, 0.0], t, [1.0, 1.0, 9.81], rtol=1e-8,
                       atol=1e-8, method="dop853", progress=lambda a, b: calls.append(a))
    assert result.success and result.n_valid == 101 and calls[-1] == 10.0
    assert 10 <= len(calls) <= 200


def test_auto_chooses_radau_for_stiff_chain_and_dop853_for_lightly_damped_bar(
        models, stiff_chain_module):
    y0 = models.STIFF_CHAIN_Y0
    assert choose_method(stiff_chain_module, 0.0, y0, models.STIFF_CHAIN_CONSTANTS, 2.0,
                         1e-8) == "radau"
    assert choose_method(stiff_chain_module, 0.0, y0, models.BAR_CONSTANTS, 2.0,
                         1e-8) == "dop853"
    t = np.linspace(0.0, 0.1, 11)
    result = integrate(stiff_chain_module, y0, t, models.STIFF_CHAIN_CONSTANTS, rtol=1e-8,
                       atol=1e-10)
    assert result.method == "radau" and result.success


def test_auto_keeps_dop853_for_pendulum(pendulum_module):
    assert choose_method(pendulum_module, 0.0, np.array([1.0, 0.0]),
                         np.array([1.0, 1.0, 9.81]), 10.0, 1e-6) == "dop853"


@pytest.mark.parametrize("kwargs, path", [
    ({"y0": [1.0]}, "y0"),
    ({"p": [1.0]}, "p"),
    ({"t_out": [0.0, 1.0, 1.0]}, "t_out"),
    ({"rtol": 0.0}, "rtol"),
    ({"atol": -1.0}, "atol"),
    ({"method": "euler"}, "method"),
])
def test_invalid_arguments_name_the_argument(pendulum_module, kwargs, path):
    args = {"y0": [1.0, 0.0], "t_out": [0.0, 1.0], "p": [1.0, 1.0, 9.81], "rtol": 1e-6,
            "atol": 1e-6, "method": "dop853"}
    args.update(kwargs)
    with pytest.raises(ModelError, match=path):
        integrate(pendulum_module, args.pop("y0"), args.pop("t_out"), args.pop("p"), **args)


def test_single_output_time_returns_initial_state(pendulum_module):
    result = integrate(pendulum_module, [1.0, 0.5], [3.0], [1.0, 1.0, 9.81], rtol=1e-6,
                       atol=1e-6, method="dop853")
    assert result.success and result.n_valid == 1
    np.testing.assert_array_equal(result.y, [[1.0, 0.5]])
