"""The derivation cache of spatial models: numbers the equations keep as symbols (inertia tensors,
point coordinates, orientation angles) do not change a model's structure, literal axis components
(exact in the equations) do; equations taken from the cache take the numbers of the model given."""

import numpy as np

import flexkane
from flexkane.derivation_cache import structure_signature
from flexkane.model import loads_model

ARM = """
dimensions = 3
[bodies.A]
mass = 1.0
inertia = [[0.1, 0.01, 0], [0.01, 0.2, 0], [0, 0, 0.3]]
points = {{ P = [0.1, 0.2, {z}] }}
[bodies.B]
mass = 2.0
inertia = [{Ixx}, 0.2, 0.3]
[joints.j1]
type = "spherical"
parent = "ground"
child = "A"
orientation = {{ axis = [1, 0, 0], angle = {angle} }}
[joints.j2]
type = "revolute"
parent = "A"
child = "B"
parent_point = "P"
axis = {axis}
"""


def _model(z=0.3, Ixx=0.1, angle=0.2, axis="[0, 1, 0]"):
    return loads_model(ARM.format(z=z, Ixx=Ixx, angle=angle, axis=axis))


def test_numbers_kept_as_symbols_do_not_change_the_structure_and_axes_do():
    base = structure_signature(_model())
    assert structure_signature(_model(z=0.5, Ixx=0.15, angle=0.4)) == base
    assert structure_signature(_model(axis="[0, 1, 1]")) != base
    assert structure_signature(_model(z=0)) != base          # a literal zero leaves the equations


def test_equations_from_the_cache_take_the_numbers_of_the_model_given(tmp_path):
    first = flexkane.derive(_model(), cache_dir=tmp_path)
    other = _model(z=0.5, Ixx=0.15, angle=0.4)
    cached = flexkane.derive(other, cache_dir=tmp_path)
    fresh = flexkane.derive(other, cache=False)
    assert [s.name for s in cached.constants] == [s.name for s in first.constants]
    assert np.array_equal(cached.parameter_vector(), fresh.parameter_vector())
