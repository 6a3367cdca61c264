"""Model files of spatial loops and spatial distributed loads: read, validated and written back."""

import pathlib

import pytest

from flexkane.errors import ModelError
from flexkane.model import dumps_model, load_model, loads_model

LOOPS = pathlib.Path(__file__).resolve().parents[1] / "kane" / "spatial_loops"


@pytest.mark.parametrize("name", ["rssr", "axis_pendulum", "welded_pair", "spatial_slider_crank"])
def test_spatial_loop_models_round_trip(name):
    model = load_model(LOOPS / f"{name}.toml")
    assert model.dimensions == 3 and model.constraints
    assert loads_model(dumps_model(model)) == model


def test_weld_orientation_and_line_axis_are_read():
    weld = load_model(LOOPS / "welded_pair.toml").constraints["glue"]
    assert weld.type == "weld" and weld.orientation.axis == (0, 1, 0) and weld.orientation.angle == 0.4
    line = load_model(LOOPS / "axis_pendulum.toml").constraints["line"]
    assert line.type == "point_on_line" and line.axis == (0, 1, 0)


def test_spatial_distributed_load_has_fz_and_round_trips():
    text = """
dimensions = 3
name = "loaded"
[beams.b]
L = 1.0
rho = 1.0
EI_y = 1.0
EI_z = 1.0
n_modes_z = 1
[joints.w]
type = "weld"
parent = "ground"
child = "b"
[distributed_loads.q]
beam = "b"
fz = "-2*x"
frame = "ground"
"""
    model = loads_model(text)
    assert model.distributed_loads["q"].fz == "-2*x"
    assert loads_model(dumps_model(model)) == model
    with pytest.raises(ModelError, match=r"distributed_loads\.q: expected a non-zero component fx or fy or fz"):
        loads_model(text.replace('fz = "-2*x"', "fz = 0"))
