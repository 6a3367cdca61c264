"""Every built-in model is also a file in examples/, and loading and saving a model round-trips."""

import pathlib

import pytest

import flexkane
from flexkane.builtin import builtin_names, builtin_text

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_every_built_in_model_is_in_examples():
    for name in builtin_names():
        assert (ROOT / "examples" / f"{name}.toml").read_text() == builtin_text(name)


@pytest.mark.parametrize("name", builtin_names())
def test_saving_a_loaded_model_gives_an_equivalent_file(name):
    model = flexkane.builtin_model(name)
    again = flexkane.loads_model(flexkane.dumps_model(model))
    assert again == model
    assert flexkane.dumps_model(again) == flexkane.dumps_model(model)
