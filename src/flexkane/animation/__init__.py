"""Animation of a run: the chain drawn at its output times, as a GIF (and an MP4 where ffmpeg exists).

Rigid bodies appear as their outlines (``outline`` in the model file; a marker without one), beams as
their deformed centre lines (eq. 8.15, displacements magnified by a factor shown on every frame),
with the time on each frame and the path of a chosen point. Everything is read from the run's
results (``results.npz`` holds the model file text), so any finished run directory can be animated::

    results = flexkane.load_results("out/falling-beam")
    animate(results, "out/falling-beam/animation.gif", magnify=1000)
    render_frame(results, "frame.png", time=0.5, magnify=1000)
"""

from __future__ import annotations

import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ModelError
from ..results import Results
from .scene import TRACE_CENTRE_OF_MASS, TRACE_NONE, Scene
from .writers import MP4_MISSING, GifWriter, Mp4Writer, ffmpeg_executable

__all__ = ["animate", "render_frame", "frame_rows", "resolve_magnification", "check_animation_options",
           "Animation", "Scene", "TRACE_NONE", "TRACE_CENTRE_OF_MASS", "ffmpeg_executable"]


@dataclass
class Animation:
    """What :func:`animate` wrote.

    Attributes
    ----------
    gif : pathlib.Path
    mp4 : pathlib.Path or None
        None when no ffmpeg was found (or none was asked for).
    frames : int
        Number of frames.
    magnify : float
        Magnification of beam displacements used [-].
    trace : str
        Traced point.
    messages : list of str
        Notes for the user (a skipped MP4).
    """

    gif: Path
    mp4: Path | None
    frames: int
    magnify: float
    trace: str
    messages: list = field(default_factory=list)


def frame_rows(n_rows: int, frames: int) -> np.ndarray:
    """Output rows shown as frames: at most ``frames`` of them, evenly spread, first and last included.

    Returns
    -------
    ndarray of int, shape (F,)
    """
    if n_rows < 1:
        raise ModelError("results.npz", "a run with at least one output time", "no output rows")
    if frames < 1:
        raise ModelError("--frames", "a positive number of frames", frames)
    return np.unique(np.round(np.linspace(0, n_rows - 1, min(frames, n_rows))).astype(int))


def resolve_magnification(scene: Scene, magnify) -> float:
    """A positive magnification factor; ``"auto"`` picks a round one (:meth:`Scene.auto_magnification`)."""
    if isinstance(magnify, str) and magnify.strip().lower() == "auto":
        return scene.auto_magnification()
    return _magnification_number(magnify)


def check_animation_options(model, magnify, trace) -> None:
    """Refuse ``magnify`` or ``trace`` (as for :func:`animate`) that an animation of ``model`` could
    not use, with a :class:`~flexkane.errors.ModelError`: checked before a run, not after it."""
    if not (isinstance(magnify, str) and magnify.strip().lower() == "auto"):
        _magnification_number(magnify)
    if trace not in (None, "", "auto"):
        names = [*model.bodies, *model.beams, TRACE_CENTRE_OF_MASS, TRACE_NONE]
        if trace not in names and not (trace.startswith("tip_") and trace[4:] in model.beams):
            raise ModelError("--trace", "one of " + ", ".join(names), trace)


def _magnification_number(magnify) -> float:
    if isinstance(magnify, str):
        try:
            magnify = float(magnify)
        except ValueError:
            raise ModelError("--magnify", "a positive number or 'auto'", magnify) from None
    if not (isinstance(magnify, (int, float)) and np.isfinite(magnify) and magnify > 0):
        raise ModelError("--magnify", "a positive number or 'auto'", magnify)
    return float(magnify)


def _setup(results: Results, magnify, trace):
    scene = Scene(results)
    factor = resolve_magnification(scene, magnify)
    point = scene.default_trace() if trace in (None, "", "auto") else trace
    scene.trace(point, factor)          # an unknown point fails here, before anything is drawn
    return scene, factor, point


def render_frame(results: Results, path, *, time: float | None = None, magnify=1.0, trace=None,
                 dpi: int = 110) -> Path:
    """Write one frame of the animation as a PNG file.

    Parameters
    ----------
    results : Results
    path : str or pathlib.Path
        PNG file to write.
    time : float, optional
        Time of the frame [s]: the output row nearest to it; the last row by default. The trace
        is drawn up to that time.
    magnify : float or "auto"
        Magnification of beam displacements [-].
    trace : str, optional
        Traced point: a body (mass centre), a beam (tip), ``cm`` or ``none``; by default the tip of
        the last beam.
    dpi : int
        Resolution [dots per inch].

    Returns
    -------
    pathlib.Path
    """
    from .render import FrameDrawing

    scene, factor, point = _setup(results, magnify, trace)
    k = len(scene.t) - 1 if time is None else int(np.argmin(np.abs(scene.t - float(time))))
    drawing = FrameDrawing(scene, np.arange(len(scene.t)), magnify=factor, trace=point, dpi=dpi)
    try:
        drawing.save_png(k, Path(path))
    finally:
        drawing.close()
    return Path(path)


def animate(results: Results, gif, *, magnify=1.0, trace=None, fps: float = 20, frames: int = 120,
            mp4: bool = True, dpi: int = 100, progress=None) -> Animation:
    """Write the animation of a run as a GIF and, where ffmpeg is available, as an MP4 beside it.

    Parameters
    ----------
    results : Results
        A run, e.g. ``flexkane.load_results(run_dir)``.
    gif : str or pathlib.Path
        GIF file to write; the MP4 gets the same name with the suffix ``.mp4``.
    magnify : float or "auto"
        Magnification of beam displacements [-], written on every frame.
    trace : str, optional
        Traced point: a body (mass centre), a beam (tip), ``cm`` or ``none``; by default the tip of
        the last beam.
    fps : float
        Frames per second of the movie [1/s].
    frames : int
        Largest number of frames (evenly spread output rows, the first and last included).
    mp4 : bool
        Also write an MP4 (skipped with a message when no ffmpeg is found).
    dpi : int
        Resolution [dots per inch].
    progress : callable, optional
        ``progress(frames_done, frames_total)`` after every frame.

    Returns
    -------
    Animation
    """
    from ..atomic import atomic_writer
    from .render import FrameDrawing

    if not (np.isfinite(fps) and fps > 0):
        raise ModelError("--fps", "a positive number of frames per second", fps)
    gif = Path(gif)
    if gif.suffix.lower() != ".gif":
        raise ModelError("--out", "a file name ending in .gif", str(gif))
    scene, factor, point = _setup(results, magnify, trace)
    rows = frame_rows(len(scene.t), frames)
    messages = []
    mp4_path = gif.with_suffix(".mp4") if mp4 else None
    if mp4 and ffmpeg_executable() is None:
        messages.append(MP4_MISSING)
        mp4_path = None
    drawing = FrameDrawing(scene, rows, magnify=factor, trace=point, dpi=dpi)
    try:
        reference = drawing.frame(int(rows[-1]))
        with atomic_writer(gif, "path") as gif_tmp:
            if mp4_path is None:
                _write(drawing, rows, GifWriter(gif_tmp, fps, reference), None, progress)
            else:
                try:
                    with atomic_writer(mp4_path, "path") as mp4_tmp:
                        _write(drawing, rows, GifWriter(gif_tmp, fps, reference), (mp4_tmp, fps), progress)
                except (subprocess.CalledProcessError, OSError, RuntimeError) as exc:
                    messages.append(f"MP4 skipped: ffmpeg failed ({exc}); the GIF is written")
                    mp4_path = None
                    _write(drawing, rows, GifWriter(gif_tmp, fps, reference), None, progress)
    finally:
        drawing.close()
    return Animation(gif, mp4_path, len(rows), factor, point, messages)


def _write(drawing, rows: np.ndarray, gif, mp4, progress) -> None:
    """Draw every frame once and hand it to the GIF writer and, if ``mp4 = (path, fps)``, to ffmpeg."""
    video = None
    for done, k in enumerate(rows, start=1):
        rgb = drawing.frame(int(k))
        gif.add(rgb)
        if mp4 is not None:
            if video is None:
                video = Mp4Writer(mp4[0], mp4[1], (rgb.shape[1], rgb.shape[0]))
            video.add(rgb)
        if progress is not None:
            progress(done, len(rows))
    gif.close()
    if video is not None:
        video.close()
