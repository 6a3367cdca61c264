"""One check of run settings and one list of integration methods, whoever supplies the settings.

``flexkane.simulate``/``flexkane run`` (arguments), a model's ``[simulation]`` table and a sweep's
settings are checked by ``validate_run_arguments``: the same bad value gets the same message.
"""

import argparse

import pytest

from flexkane.errors import ModelError
from flexkane.builtin import builtin_model
from flexkane.model import Simulation
from flexkane.model.parts import INTEGRATION_METHODS, METHODS
from flexkane.model.validate import MAX_OUTPUT_ROWS, validate_run_arguments

GOOD = {"t_end": 1.0, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10, "method": "auto", "max_steps": None}
BAD = [("rtol", 2.0), ("rtol", 0.0), ("atol", -1e-9), ("t_end", float("nan")), ("dt_out", 1e-3 / MAX_OUTPUT_ROWS),
       ("method", "rk45"), ("max_steps", 0), ("max_steps", 2.5)]


def problem(call) -> ModelError:
    with pytest.raises(ModelError) as info:
        call()
    return info.value


@pytest.mark.parametrize("key, value", BAD)
def test_a_bad_setting_gets_one_message_from_every_source(key, value):
    from flexkane.sweep.spec import SweepSpec

    settings = {**GOOD, key: value}
    direct = problem(lambda: validate_run_arguments(**settings))
    assert direct.path == key
    model = builtin_model("four-bar")
    model.simulation = Simulation(**settings)
    table = problem(model.validate)
    assert (table.path, table.expected, table.given) == (f"simulation.{key}", direct.expected, direct.given)
    sweep = problem(lambda: SweepSpec(**{"t_end": 1.0, key: value}))
    assert (sweep.path, sweep.expected, sweep.given) == (key, direct.expected, direct.given)


def test_the_output_grid_is_bounded_by_the_same_check():
    from flexkane.simulation import output_grid

    direct = problem(lambda: validate_run_arguments(**{**GOOD, "dt_out": 1e-9}))
    grid = problem(lambda: output_grid(1.0, 1e-9))
    assert (grid.path, grid.expected) == (direct.path, direct.expected)


def test_settings_a_sweep_leaves_to_the_model_are_not_required():
    from flexkane.sweep.spec import SweepSpec

    assert SweepSpec().t_end is None


def test_one_list_of_integration_methods():
    from flexkane.cli import build_parser
    from flexkane.numerics.integrate import METHODS as KERNELS

    assert METHODS == ("auto", *INTEGRATION_METHODS)
    assert tuple(KERNELS) == INTEGRATION_METHODS
    parser = build_parser()
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name in ("run", "sweep"):
        method = next(a for a in commands.choices[name]._actions if a.dest == "method")
        assert tuple(method.choices) == METHODS, name
