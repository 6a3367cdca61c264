"""The Python API in the conventions of the ecosystem: Model.with_values is --set, simulate takes
t_span, t_eval and y0 as solve_ivp does, Results has success, status, message, t, y (n_states, n_t)
and to_dataframe, and the errors are exported from flexkane."""

import numpy as np
import pytest

import flexkane
from flexkane.commands._common import apply_settings


@pytest.fixture(scope="module")
def compiled():
    return flexkane.compile_model(flexkane.derive(flexkane.builtin_model("falling-beam")))


@pytest.fixture(scope="module")
def reference(compiled):
    return flexkane.simulate(compiled, t_end=0.2, dt_out=0.01, rtol=1e-10, atol=1e-12)


def test_with_values_gives_the_model_that_set_gives():
    base = flexkane.builtin_model("falling-beam")
    settings = ["beams.B.EI=20", "u3=2", "g=5", "bodies.RB.points.Q=[0.1, 0]", "beams.B.rho=2*0.3"]
    values = {"beams.B.EI": 20, "u3": 2, "g": 5, "bodies.RB.points.Q": [0.1, 0], "beams.B.rho": "2*0.3"}
    via_python = base.with_values(values)
    assert flexkane.dumps_model(via_python) == flexkane.dumps_model(apply_settings(base, settings).validate())
    assert via_python.beams["B"].EI == 20 and base.beams["B"].EI != 20     # a copy; the base is unchanged


def test_with_values_reports_keys_not_options():
    base = flexkane.builtin_model("falling-beam")
    with pytest.raises(flexkane.ModelError) as info:
        base.with_values({"beams.B.EI": -1})
    assert info.value.path == "beams.B.EI" and "--set" not in str(info.value)
    with pytest.raises(flexkane.ModelError) as info:
        base.with_values({"beams.NOPE.EI": 1})
    assert "NOPE" in str(info.value)
    with pytest.raises(flexkane.ModelError) as info:
        base.with_values([("beams.B.EI", 1)])
    assert info.value.path == "values"


def test_results_follow_solve_ivp(reference):
    n = len(reference.state_names)
    assert reference.y.shape == (n, len(reference.t)) == reference.state.T.shape
    assert np.array_equal(reference.y[reference.state_names.index("q3")], reference["q3"])
    assert reference.success is True and reference.status == 0
    assert "reached t = 0.2" in reference.message


def test_a_failed_run_says_so_like_solve_ivp(compiled):
    failed = flexkane.simulate(compiled, t_end=0.2, dt_out=0.01, max_steps=2)
    assert failed.success is False and failed.status == -1 and "max_steps" in failed.message


def test_t_eval_gives_the_rows_of_the_dense_output_at_those_times(compiled, reference):
    times = [0.03, 0.1, 0.2]
    run = flexkane.simulate(compiled, t_span=(0.0, 0.2), t_eval=times, rtol=1e-10, atol=1e-12)
    assert list(run.t) == times and run.y.shape == (len(run.state_names), 3)
    rows = [int(round(t / 0.01)) for t in times]
    np.testing.assert_allclose(run.state, reference.state[rows], rtol=1e-7, atol=1e-9)
    alone = flexkane.simulate(compiled, t_eval=np.linspace(0.0, 0.2, 21), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(alone.state, reference.state, rtol=1e-7, atol=1e-9)


def test_t_span_and_y0_continue_a_run_where_it_stopped(compiled, reference):
    middle = reference.state[10]
    rest = flexkane.simulate(compiled, t_span=(0.1, 0.2), dt_out=0.01, y0=middle, rtol=1e-10, atol=1e-12)
    assert rest.t[0] == 0.1 and rest.t[-1] == 0.2 and len(rest.t) == 11
    np.testing.assert_array_equal(rest.state[0], middle)
    np.testing.assert_allclose(rest.state[-1], reference.state[-1], rtol=1e-6, atol=1e-8)


@pytest.mark.parametrize("arguments, path, text", [
    ({"t_end": 1.0, "t_span": (0, 1)}, "t_span", "not both"),
    ({"t_span": (0, 1), "dt_out": 0.1, "t_eval": [0, 1]}, "t_eval", "not both"),
    ({"t_span": (1.0, 0.5)}, "t_span", "t1 > t0"),
    ({"t_span": (0, 1, 2)}, "t_span", "pair"),
    ({"t_span": (0, float("nan"))}, "t_span[1]", "finite"),
    ({"t_span": (0, 1), "t_eval": [0.5, 2.0]}, "t_eval", "within t_span"),
    ({"t_span": (0, 1), "t_eval": [0.5, 0.2]}, "t_eval", "increasing"),
    ({"t_eval": [0.3]}, "t_eval", "at least two"),
    ({"t_end": 1.0, "y0": [1.0, 2.0]}, "y0", "8 numbers (q1, q2, q3, q4, u1, u2, u3, u4)"),
    ({"t_end": 1.0, "y0": [np.nan] * 8}, "y0", "finite"),
    ({"t_end": -1.0}, "t_end", "positive"),
])
def test_invalid_or_conflicting_times_and_states_are_refused_by_name(compiled, arguments, path, text):
    with pytest.raises(flexkane.ModelError) as info:
        flexkane.simulate(compiled, **arguments)
    assert info.value.path == path and text in str(info.value), str(info.value)
    assert "--" not in str(info.value)


def test_to_dataframe_holds_the_states_and_outputs_by_time(reference):
    pandas = pytest.importorskip("pandas")
    frame = reference.to_dataframe()
    assert isinstance(frame, pandas.DataFrame) and frame.index.name == "t"
    assert list(frame.columns[:len(reference.state_names)]) == reference.state_names
    np.testing.assert_array_equal(frame["energy"].to_numpy(), reference["energy"])
    np.testing.assert_array_equal(frame.index.to_numpy(), reference.t)


def test_to_dataframe_without_pandas_names_the_package_and_the_extra(reference, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pandas", None)     # as if it were not installed: import fails
    with pytest.raises(flexkane.MissingExtraError) as info:
        reference.to_dataframe()
    assert "'pandas'" in str(info.value) and "flexkane[dataframe]" in str(info.value)
    assert isinstance(info.value, ImportError)


def test_errors_are_exported_from_the_package():
    from flexkane.errors import ModelError, SolverFailure

    assert flexkane.ModelError is ModelError and flexkane.SolverFailure is SolverFailure
    assert {"ModelError", "SolverFailure", "MissingExtraError"} <= set(flexkane.__all__)
