"""The 3D animation: per-frame polylines drawn on matplotlib's 3D axes from a chosen view, as a GIF.

Synthetic data only (no derivation): frames are written, the view decides where a line appears on
the image, the same input gives the same bytes, and a spatial run's bodies are placed by their
outputs (mass centre and 3-2-1 angles).
"""

from __future__ import annotations

import pathlib

import numpy as np
import pytest
from PIL import Image

from flexkane.animation import SpatialPolyline, animate, animate_polylines, check_animation_options, render_frame
from flexkane.animation.render import _BEAM, _TRACE
from flexkane.animation.spatial_render import SpatialDrawing, check_view
from flexkane.animation.spatial_scene import SpatialScene
from flexkane.cli import main
from flexkane.errors import ModelError
from flexkane.model import dumps_model, load_model
from flexkane.model.orientation import sequence_matrix
from flexkane.results import Results

ARM = pathlib.Path(__file__).parent / "model" / "spatial_models" / "two-body-arm.toml"


def _pixels(image: np.ndarray, colour: str, tolerance: int = 40) -> np.ndarray:
    rgb = np.array([int(colour[i:i + 2], 16) for i in (1, 3, 5)])
    return np.all(np.abs(image[..., :3].astype(int) - rgb) <= tolerance, axis=-1)


def _spinning_arm(rows: int = 12):
    """An arm from the origin to a tip circling at height 0.5 m, and the tip's path."""
    t = np.linspace(0.0, 1.0, rows)
    points = np.zeros((rows, 2, 3))
    points[:, 1] = np.column_stack([np.cos(2 * np.pi * t), np.sin(2 * np.pi * t), np.full(rows, 0.5)])
    return t, [SpatialPolyline("arm", points, "link"), SpatialPolyline("tip", points[:, 1:], "marker")], points[:, 1]


def test_frames_are_written_and_bytes_repeat(tmp_path):
    t, lines, path = _spinning_arm()
    first = animate_polylines(t, lines, tmp_path / "a.gif", trace=path, trace_label="tip", mp4=False, frames=8)
    again = animate_polylines(t, lines, tmp_path / "b.gif", trace=path, trace_label="tip", mp4=False, frames=8)
    assert first.frames == 8 and first.mp4 is None
    gif = Image.open(first.gif)
    assert gif.n_frames == 8
    assert first.gif.read_bytes() == again.gif.read_bytes()
    gif.seek(7)
    last = np.asarray(gif.convert("RGB"))
    assert _pixels(last, _BEAM).sum() > 50 and _pixels(last, _TRACE).sum() > 50


def _extent(image: np.ndarray) -> tuple[int, int]:
    ys, xs = np.nonzero(_pixels(image, _BEAM))
    return int(np.ptp(xs)), int(np.ptp(ys))


@pytest.mark.parametrize("direction, view, shape", [
    ((1, 0, 0), (90, -90), "wide"),      # top view: x to the right
    ((0, 1, 0), (90, -90), "tall"),      # top view: y up the image
    ((0, 0, 1), (0, -90), "tall"),       # front view: z up the image
    ((1, 0, 0), (0, -90), "wide"),       # front view: x to the right
    ((0, 1, 0), (0, 0), "wide"),         # seen from +x: y to the right
])
def test_the_view_decides_where_a_line_appears(direction, view, shape):
    t = np.array([0.0])
    box = np.array([[[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]]])
    line = np.array([[[0.0, 0.0, 0.0], direction]], dtype=float)
    drawing = SpatialDrawing(t, [SpatialPolyline("box", box, "marker"), SpatialPolyline("line", line, "link")],
                             view=view)
    try:
        assert (drawing.axes.elev, drawing.axes.azim) == view
        wide, tall = _extent(drawing.frame(0))
    finally:
        drawing.close()
    if shape == "wide":
        assert wide > 100 and tall < 10
    else:
        assert tall > 100 and wide < 10


def test_a_line_along_the_line_of_sight_is_not_seen_as_a_line():
    t = np.array([0.0])
    line = np.array([[[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]])
    drawing = SpatialDrawing(t, [SpatialPolyline("line", line, "link")], view=(0, 0))
    try:
        wide, tall = _extent(drawing.frame(0)) if _pixels(drawing.frame(0), _BEAM).any() else (0, 0)
    finally:
        drawing.close()
    assert wide < 10 and tall < 10


@pytest.mark.parametrize("view", ["25", "a,b", "100,0", (1, 2, 3), (float("nan"), 0), "1,2,3"])
def test_bad_views_are_refused_naming_the_option(view):
    with pytest.raises(ModelError, match="--view: expected two numbers ELEVATION,AZIMUTH"):
        check_view(view)
    assert check_view("10, -30") == (10.0, -30.0) and check_view(None) == (25.0, -60.0)


def _spatial_results(rows: int = 10) -> Results:
    """A made-up run of the two-body arm: every body's mass centre and 3-2-1 angles as outputs."""
    model = load_model(ARM)
    t = np.linspace(0.0, 1.0, rows)
    outputs = {}
    for k, body in enumerate(model.bodies):
        outputs[f"x_{body}"] = np.cos(t + k)
        outputs[f"y_{body}"] = np.sin(t + k)
        outputs[f"z_{body}"] = 0.1 * k + t
        outputs[f"yaw_{body}"] = 0.7 * t + k
        outputs[f"pitch_{body}"] = 0.3 * t - 0.2
        outputs[f"roll_{body}"] = -1.1 * t
    return Results(t=t, state=np.zeros((rows, 0)), state_names=[], outputs=outputs, model_text=dumps_model(model))


def test_bodies_are_placed_by_their_mass_centre_and_3_2_1_angles():
    results = _spatial_results()
    model = load_model(ARM)
    scene = SpatialScene(results, model)
    lines = {line.name: line for line in scene.polylines()}
    bob = lines["bob"]                                 # outline [[0, 0, L], [0, 0, 0]], L = 0.5
    assert bob.kind == "outline" and bob.points.shape == (10, 2, 3)
    arm2 = lines["bob (mass centre)"]
    for k in (0, 4, 9):
        r = np.array([results[f"{c}_bob"][k] for c in "xyz"])
        C = sequence_matrix("zyx", [results[f"{a}_bob"][k] for a in ("yaw", "pitch", "roll")])
        assert np.allclose(bob.points[k], r + (C @ np.array([[0, 0, 0.5], [0, 0, 0]]).T).T, rtol=0, atol=1e-14)
        assert np.allclose(arm2.points[k, 0], r, rtol=0, atol=0)
    assert "arm2" not in lines                        # no outline and no points: a marker only
    assert np.array_equal(scene.trace("arm2"), np.column_stack([results[f"{c}_arm2"] for c in "xyz"]))
    with pytest.raises(ModelError, match="--trace"):
        scene.trace("nobody")


def test_a_spatial_run_animates_and_renders_a_frame_from_the_view(tmp_path):
    results = _spatial_results()
    movie = animate(results, tmp_path / "arm.gif", mp4=False, frames=5, view=(90, -90), trace="bob")
    assert movie.frames == 5 and Image.open(movie.gif).n_frames == 5 and movie.trace == "bob"
    png = render_frame(results, tmp_path / "frame.png", time=0.5, view="0,-90")
    assert Image.open(png).size == (704, 616)          # 6.4 x 5.6 in at the default 110 dpi


def test_view_is_for_spatial_models_only(tmp_path):
    import flexkane

    planar = flexkane.builtin_model("four-bar")
    with pytest.raises(ModelError, match="--view: expected no view for a planar model"):
        check_animation_options(planar, "1", None, (30, 0))
    check_animation_options(planar, "1", None, None)
    spatial = load_model(ARM)
    check_animation_options(spatial, "1", "bob", "30,0")
    with pytest.raises(ModelError, match="--trace"):
        check_animation_options(spatial, "1", "tip_bob", None)


def test_flexkane_animate_takes_a_view(tmp_path, capsys):
    run = tmp_path / "run"
    run.mkdir()
    _spatial_results().write(run)
    assert main(["animate", str(run), "--view", "90,-90", "--frames", "4", "--no-mp4", "--quiet"]) == 0
    assert Image.open(run / "animation.gif").n_frames == 4
    assert main(["animate", str(run), "--view", "90", "--no-mp4", "--quiet"]) == 2
    assert "--view: expected two numbers" in capsys.readouterr().err


def test_euler_parameter_outputs_place_a_body_as_its_3_2_1_angles_do():
    """Where a run has e0_<b> .. e3_<b>, the drawing uses them: the same placement as yaw/pitch/roll."""
    from flexkane.model.orientation import matrix_quaternion

    results = _spatial_results()
    model = load_model(ARM)
    by_angles = SpatialScene(results, model).polylines()
    for body in model.bodies:
        e = np.array([matrix_quaternion(sequence_matrix("zyx", [results[f"{a}_{body}"][k]
                                                                for a in ("yaw", "pitch", "roll")]))
                      for k in range(len(results.t))])
        for j in range(4):
            results.outputs[f"e{j}_{body}"] = e[:, j]
        for a in ("yaw", "pitch", "roll"):
            results.outputs[f"{a}_{body}"] = np.full(len(results.t), np.nan)   # not read any more
    by_parameters = SpatialScene(results, model).polylines()
    for one, two in zip(by_angles, by_parameters):
        assert one.name == two.name
        assert np.allclose(one.points, two.points, rtol=0, atol=1e-14)


def test_a_body_without_outline_is_drawn_between_its_points_and_its_mass_centre():
    model = load_model(ARM)
    model.bodies["arm2"].points = {"top": (0, 0, 0.3)}
    results = _spatial_results()
    results.model_text = dumps_model(model)
    lines = {line.name: line for line in SpatialScene(results, model).polylines()}
    r = np.column_stack([results[f"{c}_arm2"] for c in "xyz"])
    assert lines["arm2"].kind == "link" and lines["arm2"].points.shape == (10, 2, 3)
    assert np.allclose(lines["arm2"].points[:, 1], r, rtol=0, atol=1e-15)
    assert np.allclose(np.linalg.norm(lines["arm2"].points[:, 0] - r, axis=1), 0.3, rtol=1e-14)
    model.bodies["arm2"].points = {"a": (0, 0, 0.3), "b": (0, 0, -0.3), "c": (0.1, 0, 0)}
    lines = {line.name: line for line in SpatialScene(results, model).polylines()}
    assert lines["arm2"].points.shape == (10, 5, 3)      # a, centre, b, centre, c
    assert np.allclose(lines["arm2"].points[:, 3], r, rtol=0, atol=1e-15)
