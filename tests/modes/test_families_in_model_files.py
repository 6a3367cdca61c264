"""Every shape-function family can be chosen per beam in a model file (issue 4)."""

import numpy as np
import pytest

import flexkane

TEMPLATE = """
name = "family-{family}"
[parameters]
L = 1.0
EI = 2.0
rho = 0.5
[beams.beam]
L = "L"
EI = "EI"
rho = "rho"
n_modes = 3
shape = {shape}
[joints.clamp]
type = "weld"
parent = "ground"
child = "beam"
"""

SHAPES = {
    "clamped-free": '"clamped-free"',
    "pinned-free": '"pinned-free"',
    "pinned-pinned": '"pinned-pinned"',
    "clamped-pinned": '"clamped-pinned"',
    "clamped-clamped": '"clamped-clamped"',
    "free-free": '"free-free"',
    "clamped-free-tip-mass": '{ family = "clamped-free-tip-mass", mass_ratio = 0.5, inertia_ratio = 0.01 }',
    "polynomial": '"polynomial"',
    "expression": '{ family = "expression", expressions = ["xi**2", "xi**3", "xi**4"], boundary = "clamped-free" }',
}


@pytest.mark.parametrize("family", sorted(SHAPES))
def test_family_can_be_chosen_per_beam_in_a_model_file(family):
    model = flexkane.loads_model(TEMPLATE.format(family=family, shape=SHAPES[family]))
    eom = flexkane.derive(model)
    values = eom.constant_values()
    H = np.array([[values[eom.kinematics.constants["beam"].stiffness(i, j)] for j in (1, 2, 3)] for i in (1, 2, 3)])
    # the stiffness matrix of eq. 8.32 is symmetric and, for these beams, positive semi-definite
    assert np.allclose(H, H.T)
    assert np.linalg.eigvalsh(H).min() > -1e-9 * np.abs(H).max()
    assert flexkane.loads_model(flexkane.dumps_model(model)) == model


def test_an_expression_not_admissible_at_the_clamp_is_refused():
    text = TEMPLATE.format(family="bad", shape='{ family = "expression", expressions = ["xi", "xi**2", "xi**3"], '
                                               'boundary = "clamped-free" }')
    with pytest.raises(flexkane.errors.ModelError, match="beams.beam.shape"):
        flexkane.loads_model(text)
