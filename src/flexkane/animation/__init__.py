"""Animation of a run: the chain drawn at its output times, as a GIF (and an MP4 where ffmpeg exists).

Rigid bodies appear as their outlines (``outline`` in the model file; a marker without one), beams as
their deformed centre lines (eq. 8.15, displacements magnified by a factor shown on every frame),
with the time on each frame and the path of a chosen point. Everything is read from the run's
results (``results.npz`` holds the model file text), so any finished run directory can be animated::

    results = flexkane.load_results("out/falling-beam")
    animate(results, "out/falling-beam/animation.gif", magnify=1000)
    render_frame(results, "frame.png", time=0.5, magnify=1000)

A spatial model (``dimensions = 3``) is drawn on matplotlib's 3D axes from a chosen ``view``
(elevation, azimuth [deg]): its bodies' outlines (or centre lines between their points) placed by the
outputs ``x_<b>, y_<b>, z_<b>`` and ``yaw_<b>, pitch_<b>, roll_<b>`` (:mod:`.spatial_scene`), beams as
their deflected centre lines (displacements magnified alike).
:func:`animate_polylines` draws any per-frame 3D polylines (:mod:`.spatial_render`), with no model.
"""

from __future__ import annotations

import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ModelError
from ..results import Results
from .scene import TRACE_CENTRE_OF_MASS, TRACE_NONE, Scene
from .spatial_render import DEFAULT_VIEW, SpatialPolyline, check_view
from .writers import MP4_MISSING, GifWriter, Mp4Writer, ffmpeg_executable

__all__ = ["animate", "animate_polylines", "render_frame", "frame_rows", "resolve_magnification",
           "check_animation_options", "Animation", "Scene", "SpatialPolyline", "TRACE_NONE", "TRACE_CENTRE_OF_MASS",
           "DEFAULT_VIEW", "ffmpeg_executable"]


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
    magnify : float or None
        Magnification of beam displacements used [-]; None for a model without beams.
    trace : str
        Traced point.
    messages : list of str
        Notes for the user (a skipped MP4).
    """

    gif: Path
    mp4: Path | None
    frames: int
    magnify: float | None
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


def check_animation_options(model, magnify, trace, view=None) -> None:
    """Refuse ``magnify``, ``trace`` or ``view`` (as for :func:`animate`) that an animation of ``model``
    could not use, with a :class:`~flexkane.errors.ModelError`: checked before a run, not after it."""
    if not (isinstance(magnify, str) and magnify.strip().lower() == "auto"):
        _magnification_number(magnify)
    _check_view_for(model.dimensions, view)
    if trace not in (None, "", "auto") and model.dimensions == 3:
        names = [*model.bodies, *model.beams, TRACE_CENTRE_OF_MASS, TRACE_NONE]
        if trace not in names:
            raise ModelError("--trace", "one of " + ", ".join(names), trace)
    elif trace not in (None, "", "auto"):
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


def _check_view_for(dimensions: int, view) -> tuple[float, float] | None:
    """The view of a spatial model's drawing (checked); a planar model takes none."""
    if dimensions == 3:
        return check_view(view)
    if view is not None:
        raise ModelError("--view", "no view for a planar model (it is drawn in its plane); a view is for models "
                         "with dimensions = 3", view)
    return None


def _model_of(results: Results):
    from ..model import loads_model

    if not results.model_text:
        raise ModelError("results.npz", "a run that stored its model file text", "no model text")
    return loads_model(results.model_text, source="results.npz")


def _spatial_drawing(results: Results, model, trace, view, rows, dpi: int, magnify=1.0):
    """The 3D drawing of a spatial model's run, the traced point and the beams' magnification."""
    from .spatial_render import SpatialDrawing
    from .spatial_scene import SpatialScene

    auto = isinstance(magnify, str) and magnify.strip().lower() == "auto"
    scene = SpatialScene(results, model, "auto" if auto else _magnification_number(magnify))
    point = scene.default_trace() if trace in (None, "", "auto") else trace
    path = scene.trace(point)
    title = scene.name + (" (partial run)" if scene.partial else "")
    if scene.beams and scene.magnify != 1.0:
        title += f", beam displacements x {scene.magnify:g}"
    drawing = SpatialDrawing(scene.t, scene.polylines(), trace=path, trace_label=scene.trace_label(point),
                             view=view, title=title, rows=rows, dpi=dpi)
    return drawing, point, scene.magnify


def _setup(results: Results, magnify, trace):
    scene = Scene(results)
    factor = resolve_magnification(scene, magnify)
    point = scene.default_trace() if trace in (None, "", "auto") else trace
    scene.trace(point, factor)          # an unknown point fails here, before anything is drawn
    return scene, factor, point


def render_frame(results: Results, path, *, time: float | None = None, magnify=1.0, trace=None,
                 dpi: int = 110, view=None) -> Path:
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
    view : (float, float) or str, optional
        Spatial models: elevation and azimuth of the camera [deg] (``"25,-60"`` as text);
        :data:`DEFAULT_VIEW` by default. Planar models take none.

    Returns
    -------
    pathlib.Path
    """
    from .render import FrameDrawing

    model = _model_of(results)
    view = _check_view_for(model.dimensions, view)
    if model.dimensions == 3:
        t = np.asarray(results.t, dtype=float)
        k = len(t) - 1 if time is None else int(np.argmin(np.abs(t - float(time))))
        drawing, _, _ = _spatial_drawing(results, model, trace, view, None, dpi, magnify)
        try:
            drawing.save_png(k, Path(path))
        finally:
            drawing.close()
        return Path(path)
    scene, factor, point = _setup(results, magnify, trace)
    k = len(scene.t) - 1 if time is None else int(np.argmin(np.abs(scene.t - float(time))))
    drawing = FrameDrawing(scene, np.arange(len(scene.t)), magnify=factor, trace=point, dpi=dpi)
    try:
        drawing.save_png(k, Path(path))
    finally:
        drawing.close()
    return Path(path)


def animate(results: Results, gif, *, magnify=1.0, trace=None, fps: float = 20, frames: int = 120,
            mp4: bool = True, dpi: int = 100, progress=None, view=None) -> Animation:
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
    view : (float, float) or str, optional
        Spatial models: elevation and azimuth of the camera [deg]; :data:`DEFAULT_VIEW` by default.
        Planar models take none.

    Returns
    -------
    Animation
    """
    from .render import FrameDrawing

    gif = _check_movie(gif, fps)
    model = _model_of(results)
    view = _check_view_for(model.dimensions, view)
    if model.dimensions == 3:
        rows = frame_rows(len(results.t), frames)
        drawing, point, factor = _spatial_drawing(results, model, trace, view, rows, dpi, magnify)
        return _write_movie(drawing, rows, gif, fps, mp4, progress, factor if model.beams else None, point)
    scene, factor, point = _setup(results, magnify, trace)
    rows = frame_rows(len(scene.t), frames)
    drawing = FrameDrawing(scene, rows, magnify=factor, trace=point, dpi=dpi)
    return _write_movie(drawing, rows, gif, fps, mp4, progress, factor if scene.beams else None, point)


def animate_polylines(t, polylines: list[SpatialPolyline], gif, *, trace=None, trace_label: str = "", view=None,
                      title: str = "", fps: float = 20, frames: int = 120, mp4: bool = True, dpi: int = 100,
                      progress=None) -> Animation:
    """Write a GIF (and an MP4 where ffmpeg exists) of 3D polylines given frame by frame.

    Parameters
    ----------
    t : array_like, shape (N,)
        Time of each row [s].
    polylines : list of SpatialPolyline
        What is drawn, each with points of shape (N, m, 3) in the ground frame [m].
    gif : str or pathlib.Path
        GIF file to write (``.gif``).
    trace : ndarray, shape (N, 3), optional
        Path of a point drawn up to the current frame [m].
    trace_label : str
        Its legend.
    view : (float, float) or str, optional
        Elevation and azimuth of the camera [deg]; :data:`DEFAULT_VIEW` by default.
    title : str
    fps, frames, mp4, dpi, progress
        As for :func:`animate`.

    Returns
    -------
    Animation
        ``magnify`` 1 and ``trace`` the trace's label.
    """
    from .spatial_render import SpatialDrawing

    gif = _check_movie(gif, fps)
    view = check_view(view)
    t = np.asarray(t, dtype=float)
    rows = frame_rows(len(t), frames)
    drawing = SpatialDrawing(t, polylines, trace=trace, trace_label=trace_label, view=view, title=title, rows=rows,
                             dpi=dpi)
    return _write_movie(drawing, rows, gif, fps, mp4, progress, 1.0, trace_label or "none")


def _check_movie(gif, fps) -> Path:
    if not (isinstance(fps, (int, float)) and np.isfinite(fps) and fps > 0):
        raise ModelError("--fps", "a positive number of frames per second", fps)
    gif = Path(gif)
    if gif.suffix.lower() != ".gif":
        raise ModelError("--out", "a file name ending in .gif", str(gif))
    return gif


def _write_movie(drawing, rows: np.ndarray, gif: Path, fps: float, mp4: bool, progress, factor: float | None,
                 point: str) -> Animation:
    """Write the frames ``rows`` of a drawing (:class:`~.render.FrameDrawing` or
    :class:`~.spatial_render.SpatialDrawing`) as a GIF and, where ffmpeg exists, an MP4; closes it."""
    from ..atomic import atomic_writer

    messages = []
    mp4_path = gif.with_suffix(".mp4") if mp4 else None
    if mp4 and ffmpeg_executable() is None:
        messages.append(MP4_MISSING)
        mp4_path = None
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
