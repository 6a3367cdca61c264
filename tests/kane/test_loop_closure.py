"""One closure of the loop constraints for planar and spatial chains (kane.loop_closure).

Its unknowns are the coordinates of the dependent speeds (all four Euler parameters of a joint with
a dependent angular speed); every other coordinate is returned as given, bit for bit.
"""

import pathlib

import numpy as np
import pytest

import flexkane
from flexkane.kane.loop_closure import closure_unknowns

HERE = pathlib.Path(__file__).parent / "spatial_loops"


def _rotation(e):
    e0, e1, e2, e3 = e
    return np.array([[1 - 2 * (e2 ** 2 + e3 ** 2), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                     [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 ** 2 + e3 ** 2), 2 * (e2 * e3 - e0 * e1)],
                     [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 ** 2 + e2 ** 2)]])


@pytest.mark.slow
def test_free_block_on_a_line_closes_by_its_dependent_translations_only():
    """A free block's point P held on a vertical ground line, body-frame speeds vx, vy dependent:
    the closure moves x and y only (along N's axes, where moving along the dependent speeds'
    directions C e_x, C e_y would also move z); z and the Euler parameters stay the user's, and P
    lands on the line (closed form: P's x, y in N are the line's)."""
    model = flexkane.load_model(HERE / "block_on_line.toml")
    eom = flexkane.derive(model, cache=False)
    names = [q.name for q in eom.q]
    assert [q.name for q in closure_unknowns(eom)] == ["q_float_x", "q_float_y"]
    values = eom.constant_values()
    guess = eom.initial_state(model)[:len(eom.q)]
    for x, y in ((0.0, 0.0), (1.0, -2.0)):
        q = guess.copy()
        q[names.index("q_float_x")], q[names.index("q_float_y")] = x, y
        closed = eom.project_coordinates(q.copy(), values)
        kept = [k for k, n in enumerate(names) if n not in ("q_float_x", "q_float_y")]
        assert closed[kept].tobytes() == q[kept].tobytes()
        r = closed[:3]
        e = closed[3:7]
        P = r + _rotation(e) @ np.array([0.05, -0.02, 0.1])
        assert np.abs(P[:2] - [0.2, 0.1]).max() <= 1e-13, P
