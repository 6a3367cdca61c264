"""Animation of runs (flexkane animate, run --animate) and the progress bar it shares with run.

Frames are checked by their pixels: the colours of the body outline, the beam and the trace must be
there, and the time must be written; every built-in model must draw.
"""

import io
import shutil

import numpy as np
import pytest
from PIL import Image

import flexkane
from flexkane.animation import Scene, animate, frame_rows, render_frame
from flexkane.animation.render import _BEAM, _BODY_FACE, _TRACE
from flexkane.cli import main
from flexkane.model import dumps_model
from flexkane.progress import ProgressBar
from flexkane.results import Results
from flexkane.numerics import evaluate_outputs


def synthetic_results(name: str, rows: int = 30) -> Results:
    """Results of a built-in model along a made-up trajectory (no integration): the initial state
    plus a slow oscillation of every coordinate and speed, with the outputs evaluated on it."""
    model = flexkane.builtin_model(name)
    eom = flexkane.derive(model)
    values = eom.constant_values(model)
    p = np.array([values[s] for s in eom.constants])
    t = np.linspace(0.0, 1.0, rows)
    y0 = eom.initial_state(model)
    state = y0 + 0.05 * np.outer(np.sin(2 * np.pi * t), np.ones(len(y0)))
    outputs = evaluate_outputs(flexkane.compile_model(eom).module, t, state, p)   # compiled outputs
    return Results(t=t, state=state, state_names=eom.state_names, outputs=outputs,
                   model_text=dumps_model(model), parameters={s.name: values[s] for s in eom.constants})


def pixels_of(image: np.ndarray, colour: str, tolerance: int = 40) -> int:
    """Number of pixels within ``tolerance`` (per channel) of a colour given as #rrggbb."""
    rgb = np.array([int(colour[i:i + 2], 16) for i in (1, 3, 5)])
    return int(np.all(np.abs(image[..., :3].astype(int) - rgb) <= tolerance, axis=-1).sum())


def dark_pixels(image: np.ndarray) -> int:
    return int((image[..., :3].max(axis=-1) < 80).sum())


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    """A short run of the chapter's exact model made with ``flexkane run --animate``."""
    out = tmp_path_factory.mktemp("anim") / "fbe"
    assert main(["run", "falling-beam-exact", "--out", str(out), "--quiet", "--t-end", "0.3",
                 "--dt-out", "0.005", "--animate", "--magnify", "auto"]) == 0
    return out


def test_run_with_animate_writes_a_gif_and_the_equations(run_dir):
    gif = Image.open(run_dir / "animation.gif")
    assert gif.n_frames == 61                            # 61 output rows, fewer than 120 frames
    assert (run_dir / "equations.tex").stat().st_size > 1000


def test_animate_command_works_from_results_npz_alone(run_dir, tmp_path, capsys):
    lone = tmp_path / "copy"
    lone.mkdir()
    shutil.copy(run_dir / "results.npz", lone / "results.npz")
    assert main(["animate", str(lone), "--frames", "12", "--fps", "10", "--magnify", "300",
                 "--trace", "RB"]) == 0
    out = capsys.readouterr()
    gif = Image.open(lone / "animation.gif")
    assert gif.n_frames == 12
    assert "x 300" in out.out and "trace RB" in out.out
    if flexkane.animation.ffmpeg_executable():
        assert (lone / "animation.mp4").stat().st_size > 1000
    else:
        assert "MP4 skipped" in out.err


def test_mp4_is_skipped_with_a_message_when_no_ffmpeg_is_found(run_dir, tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(flexkane.animation, "ffmpeg_executable", lambda: None)
    out = tmp_path / "movie.gif"
    assert main(["animate", str(run_dir), "--frames", "3", "--out", str(out), "--quiet"]) == 0
    assert out.exists() and not out.with_suffix(".mp4").exists()
    err = capsys.readouterr().err
    assert "MP4 skipped" in err and "pip install imageio-ffmpeg" in err


def test_a_frame_shows_the_body_the_deformed_beam_the_trace_and_the_time(run_dir, tmp_path):
    res = flexkane.load_results(run_dir)
    path = render_frame(res, tmp_path / "frame.png", time=0.25, magnify=500)
    image = np.asarray(Image.open(path).convert("RGB"))
    assert pixels_of(image, _BODY_FACE, 8) > 500        # the filled outline of RB
    assert pixels_of(image, _BEAM, 30) > 150            # the beam's centre line
    assert pixels_of(image, _TRACE, 30) > 50            # the path of the beam's tip
    h, w, _ = image.shape
    assert dark_pixels(image[: h // 6, : w // 2]) > 100  # "t = 0.250 s" and the title at the top left


def test_every_builtin_model_draws_its_bodies_and_beams(tmp_path):
    for name in flexkane.builtin_names():
        if flexkane.builtin_model(name).dimensions == 3:
            continue            # drawn on 3D axes: tests/test_spatial_animation.py, tests/commands
        res = synthetic_results(name)
        scene = Scene(res)
        image = np.asarray(Image.open(render_frame(res, tmp_path / f"{name}.png", magnify=2)).convert("RGB"))
        if scene.beams:
            assert pixels_of(image, _BEAM, 30) > 100, name
        if any(b.outline is not None for b in scene.bodies):
            assert pixels_of(image, "#2b4b6b", 40) > 30, name     # outline edges


def test_magnification_multiplies_the_drawn_deflection_only():
    res = synthetic_results("pendulum-beam", rows=5)
    scene = Scene(res)
    beam = scene.beams[0]
    axis = scene.beam_axis(beam, 3)
    direction = (axis[1] - axis[0]) / beam.L
    normal = np.array([-direction[1], direction[0]])
    offsets = [(scene.beam_line(beam, 3, k) - axis[0]) @ normal for k in (1.0, 7.0)]
    np.testing.assert_allclose(offsets[1], 7.0 * offsets[0], atol=1e-12)
    np.testing.assert_allclose(offsets[0][-1], res["tip_rod"][3], rtol=1e-12)   # tip deflection y(L)
    np.testing.assert_allclose(scene.beam_line(beam, 3, 7.0)[0], axis[0], atol=1e-12)   # the root stays


def test_auto_magnification_is_a_round_factor_drawing_a_tenth_of_the_beam(run_dir):
    scene = Scene(flexkane.load_results(run_dir))
    k = scene.auto_magnification()
    mantissa = k / 10 ** np.floor(np.log10(k))
    assert round(mantissa, 9) in (1, 2, 5)
    assert 0.04 <= k * scene.max_deflection() / scene.beams[0].L <= 0.1
    assert Scene(synthetic_results("falling-beam-exact", rows=5)).auto_magnification() == 1.0   # visible


def test_unknown_trace_point_is_a_usage_error_listing_the_choices(run_dir, capsys):
    assert main(["animate", str(run_dir), "--trace", "elbow", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "--trace" in err and "RB" in err and "cm" in err and "Traceback" not in err


def test_animate_refuses_a_directory_without_results(tmp_path, capsys):
    assert main(["animate", str(tmp_path)]) == 2
    assert "results.npz" in capsys.readouterr().err


def test_frame_rows_are_evenly_spread_with_first_and_last():
    rows = frame_rows(1001, 120)
    assert rows[0] == 0 and rows[-1] == 1000 and len(rows) == 120
    assert list(frame_rows(5, 120)) == [0, 1, 2, 3, 4]


def test_animate_reports_progress_per_frame(run_dir, tmp_path):
    seen = []
    movie = animate(flexkane.load_results(run_dir), tmp_path / "a.gif", frames=4, mp4=False,
                    progress=lambda done, total: seen.append((done, total)))
    assert seen == [(1, 4), (2, 4), (3, 4), (4, 4)] and movie.mp4 is None


# ---------------------------------------------------------------------- progress bar
class FakeTerminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_draws_on_a_terminal_after_its_delay():
    stream = FakeTerminal()
    with ProgressBar(2.0, unit="s", delay=0.0, stream=stream) as bar:
        bar.update(0.5)
        bar.update(2.0)
    text = stream.getvalue()
    assert "\r[" in text and "0.5/2 s" in text and "2/2 s" in text
    assert "[" + "#" * 30 + "]" in text and text.endswith("\n")


def test_progress_bar_is_silent_off_a_terminal_when_quiet_and_for_short_runs():
    plain = io.StringIO()
    with ProgressBar(1.0, delay=0.0, stream=plain) as bar:
        bar.update(1.0)
    quiet, short = FakeTerminal(), FakeTerminal()
    with ProgressBar(1.0, delay=0.0, enabled=False, stream=quiet) as bar:
        bar.update(1.0)
    with ProgressBar(1.0, delay=60.0, stream=short) as bar:
        bar.update(1.0)
    assert plain.getvalue() == quiet.getvalue() == short.getvalue() == ""


def test_animate_of_a_model_without_beams_names_no_beam_magnification(tmp_path, capsys):
    synthetic_results("four-bar", rows=8).write(tmp_path)
    assert main(["animate", str(tmp_path), "--frames", "3", "--no-mp4"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("animation: 3 frames, trace ") and "beam deflection" not in out
