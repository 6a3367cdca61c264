"""The 3D animation draws spatial beams as their deflected centre lines (issue 17, item 5).

Synthetic runs (no derivation): a beam welded to the ground in a turned frame, its root placed and
turned by the outputs ``x_<b>, y_<b>, z_<b>``, ``e0_<b> .. e3_<b>``, its modal coordinates given as
states. The drawn line is checked point by point against the clamped-free shape functions and the
foreshortening integrated independently (Gauss-Legendre), and ``flexkane animate`` is checked to
draw the beam where its deflection puts it.
"""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from flexkane.animation.render import _BEAM
from flexkane.animation.spatial_scene import SpatialScene
from flexkane.cli import main
from flexkane.model import loads_model
from flexkane.model.orientation import matrix_quaternion, sequence_matrix
from flexkane.modes import get_family
from flexkane.results import Results

BEAM = """
name = "turned-beam"
dimensions = 3

[bodies.base]
mass = 1.0
inertia = [0.01, 0.01, 0.01]
points = { clamp = [0.1, 0, 0] }

[beams.b]
L = 1.5
rho = 1.0
EI_y = 10.0
EI_z = 20.0
n_modes_y = 2
n_modes_z = 1
principal_angle = 0.3
geometric_stiffening = true

[joints.base]
type = "weld"
parent = "ground"
child = "base"
parent_position = [0, 0, 0]

[joints.root]
type = "weld"
parent = "base"
parent_point = "clamp"
child = "b"
"""


def _run(q_y1=0.05, q_y2=-0.01, q_z1=0.08, rows=5) -> Results:
    """Rows of a beam whose root moves and turns, with fixed modal coordinates."""
    t = np.linspace(0.0, 1.0, rows)
    outputs = {}
    for body, offset in (("base", 0.0), ("b", 0.1)):
        outputs[f"x_{body}"] = 0.2 * t + offset
        outputs[f"y_{body}"] = -0.1 * t
        outputs[f"z_{body}"] = 0.3 + 0 * t
        e = np.array([matrix_quaternion(sequence_matrix("zyx", [0.8 * tk, -0.4, 0.2])) for tk in t])
        for k in range(4):
            outputs[f"e{k}_{body}"] = e[:, k]
    names = ["q_b_y1", "q_b_y2", "q_b_z1"]
    state = np.tile([q_y1, q_y2, q_z1], (rows, 1))
    return Results(t=t, state=state, state_names=names, outputs=outputs, model_text=BEAM)


def _expected_tip(results, k, L=1.5, beta=0.3):
    """The tip in N from the clamped-free functions and a Gauss-Legendre foreshortening."""
    family = get_family("clamped-free")
    q_y = np.array([results["q_b_y1"][k], results["q_b_y2"][k]])
    q_z = np.array([results["q_b_z1"][k]])
    v = family.phi(np.array([1.0]), 2)[:, 0] @ q_y
    w = family.phi(np.array([1.0]), 1)[:, 0] @ q_z
    xi, weights = np.polynomial.legendre.leggauss(40)
    xi = (xi + 1) / 2
    slope_y = q_y @ family.phi(xi, 2, deriv=1) / L
    slope_z = q_z @ family.phi(xi, 1, deriv=1) / L
    shortening = 0.5 * L * np.sum(weights / 2 * (slope_y ** 2 + slope_z ** 2))
    local = np.array([L - shortening, np.cos(beta) * v - np.sin(beta) * w, np.sin(beta) * v + np.cos(beta) * w])
    r = np.array([results[f"{c}_b"][k] for c in "xyz"])
    C = sequence_matrix("zyx", [0.8 * results.t[k], -0.4, 0.2])
    return r + C @ local, v, w, shortening


def test_spatial_beam_is_drawn_deflected_in_both_planes_and_foreshortened():
    results = _run()
    model = loads_model(BEAM)
    scene = SpatialScene(results, model)
    lines = {line.name: line for line in scene.polylines()}
    beam = lines["b"]
    assert beam.kind == "beam" and beam.points.shape == (5, 41, 3)
    for k in (0, 2, 4):
        tip, v, w, shortening = _expected_tip(results, k)
        assert abs(v) > 0.05 and abs(w) > 0.1 and shortening > 1e-3
        # trapezoidal foreshortening on 41 stations: 1e-5 of its value
        assert np.linalg.norm(beam.points[k, -1] - tip) < 1e-5 * shortening
        assert np.allclose(beam.points[k, 0], [results[f"{c}_b"][k] for c in "xyz"], rtol=0, atol=1e-15)
    assert np.allclose(scene.trace("b"), beam.points[:, -1], rtol=0, atol=0)
    assert scene.trace_label("b") == "tip of b"


def test_magnification_scales_the_beam_displacements_only():
    results = _run()
    model = loads_model(BEAM)
    one, ten = (SpatialScene(results, model, magnify=m) for m in (1.0, 10.0))
    still = SpatialScene(_run(0.0, 0.0, 0.0), model)
    beam = {s: {line.name: line for line in s.polylines()}["b"].points for s in (one, ten, still)}
    assert np.allclose(beam[ten] - beam[still], 10 * (beam[one] - beam[still]), rtol=1e-12, atol=1e-14)
    auto = SpatialScene(_run(5e-5, 0.0, 0.0), model, magnify="auto")
    assert auto.magnify in (100.0, 200.0, 500.0, 1000.0)      # a round factor, at least 1


def _beam_rows(image: np.ndarray) -> int:
    """Number of image rows the beam's colour spans."""
    rgb = np.array([int(_BEAM[i:i + 2], 16) for i in (1, 3, 5)])
    ys, _ = np.nonzero(np.all(np.abs(image[..., :3].astype(int) - rgb) <= 40, axis=-1))
    return int(np.ptp(ys))


def test_flexkane_animate_draws_the_deflected_beam(tmp_path):
    """Seen from the side (the x-z plane, elevation 0), the root fixed: the beam straight in the first
    frame and bent by q_z1 in the last spans more image rows there."""
    results = _run(0.0, 0.0, 0.0)
    results.state[:, 2] = np.linspace(0.0, 0.25, len(results.t))     # q_b_z1 grows
    for body in ("base", "b"):                                        # root at rest, frames not turned
        for c in "xyz":
            results.outputs[f"{c}_{body}"] = np.zeros(len(results.t))
        for k in range(4):
            results.outputs[f"e{k}_{body}"] = np.full(len(results.t), 1.0 if k == 0 else 0.0)
    results.write(tmp_path)
    assert main(["animate", str(tmp_path), "--view", "0,-90", "--frames", "2", "--no-mp4", "--quiet",
                 "--trace", "b"]) == 0
    gif = Image.open(tmp_path / "animation.gif")
    assert gif.n_frames == 2
    rows = []
    for k in range(2):
        gif.seek(k)
        rows.append(_beam_rows(np.asarray(gif.convert("RGB"))))
    assert rows[1] > rows[0] + 20, rows
