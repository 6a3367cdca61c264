"""Drawing of the chain with matplotlib: one figure whose artists are moved from frame to frame.

Rigid bodies are filled outlines (a marker for a body without one), beams their deformed centre
lines over their undeformed axes (dashed), the traced point leaves its path behind it, and every
frame shows the time and the magnification of the beam displacements.
"""

from __future__ import annotations

import numpy as np

from .scene import TRACE_NONE, Scene

__all__ = ["BlittedFrames", "FrameDrawing", "pyplot"]

_BODY_FACE = "#c9d6e3"
_BODY_EDGE = "#2b4b6b"
_BEAM = "#c0392b"
_TRACE = "#27ae60"


def pyplot():
    """matplotlib.pyplot on the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def figure_size(bounds: tuple, longest: float = 7.0, shortest: float = 4.8,
                dpi: int = 100) -> tuple[float, float]:
    """Figure size [in] close to the aspect ratio of ``bounds``: the longer side ``longest``, the
    shorter one at least ``shortest``, each an even number of pixels (video encoders need it)."""
    xmin, xmax, ymin, ymax = bounds
    ratio = (ymax - ymin) / max(xmax - xmin, 1e-300)
    if ratio > 1:
        w, h = max(longest / ratio, shortest), longest
    else:
        w, h = longest, max(longest * ratio, shortest)
    return 2 * round(w * dpi / 2) / dpi, 2 * round(h * dpi / 2) / dpi


def fill_axes(ax, bounds: tuple) -> None:
    """Set limits holding ``bounds`` whose data aspect is 1 in the axes box as it is drawn."""
    xmin, xmax, ymin, ymax = bounds
    position = ax.get_position()
    fig_w, fig_h = ax.figure.get_size_inches()
    target = (position.height * fig_h) / max(position.width * fig_w, 1e-9)
    dx, dy = xmax - xmin, ymax - ymin
    if dy / dx < target:
        extra = (dx * target - dy) / 2
        ymin, ymax = ymin - extra, ymax + extra
    else:
        extra = (dy / target - dx) / 2
        xmin, xmax = xmin - extra, xmax + extra
    ax.set_xlim(xmin, xmax)
    ax.set_ylim(ymin, ymax)


class BlittedFrames:
    """Frames of a figure drawn by blitting: the still background is drawn once and cached, each frame
    restores it and draws only the moving artists. Subclasses set ``figure`` and ``_background = None``
    and define ``frame(k)``."""

    def _blit(self, artists, draw) -> np.ndarray:
        """The image of the figure with ``artists`` drawn by ``draw`` over the background, shape
        (height, width, 3), uint8."""
        canvas = self.figure.canvas
        if self._background is None:
            canvas.draw()
            self._background = canvas.copy_from_bbox(self.figure.bbox)
        else:
            canvas.restore_region(self._background)
        for artist in artists:
            draw(artist)
        return np.asarray(canvas.buffer_rgba())[..., :3].copy()

    def save_png(self, k: int, path) -> None:
        """Write frame ``k`` (of output row ``k``) as a PNG file (atomically)."""
        from PIL import Image

        from ..atomic import atomic_writer

        image = Image.fromarray(self.frame(k))
        with atomic_writer(path) as handle:
            image.save(handle, format="PNG", optimize=True)

    def close(self) -> None:
        """Release the figure."""
        pyplot().close(self.figure)


class FrameDrawing(BlittedFrames):
    """A figure of a :class:`Scene`, redrawn for any output row by :meth:`frame`.

    Parameters
    ----------
    scene : Scene
    rows : ndarray of int, shape (F,)
        Output rows that will be drawn (they set the axis limits and the trace).
    magnify : float
        Magnification of beam displacements [-].
    trace : str
        Point whose path is drawn (see :meth:`Scene.trace`).
    dpi : int
        Resolution [dots per inch].
    """

    def __init__(self, scene: Scene, rows: np.ndarray, *, magnify: float = 1.0, trace: str = TRACE_NONE,
                 dpi: int = 100):
        plt = pyplot()
        self.scene = scene
        self.rows = np.asarray(rows, dtype=int)
        self.magnify = float(magnify)
        self.trace_name = trace
        self.path = scene.trace(trace, magnify)
        bounds = scene.bounds(self.rows, magnify, trace)
        self.figure, ax = plt.subplots(figsize=figure_size(bounds, dpi=dpi), dpi=dpi)
        self.axes = ax
        ax.set_xlim(bounds[0], bounds[1])
        ax.set_ylim(bounds[2], bounds[3])
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.grid(alpha=0.25)
        title = scene.name + (" (partial run)" if scene.partial else "")
        ax.set_title(title, fontsize=10)
        self._build_artists()
        for _ in range(2):                  # the limits change the tick labels, which move the box
            self.figure.tight_layout()
            fill_axes(ax, bounds)
        ax.set_aspect("equal", adjustable="box")
        self._background = None

    def _build_artists(self) -> None:
        from matplotlib.patches import Polygon

        ax = self.axes
        scene = self.scene
        self.trace_line = None
        if self.path is not None:
            (self.trace_line,) = ax.plot([], [], color=_TRACE, lw=1.2, alpha=0.9, animated=True,
                                         label=f"trace: {scene.trace_label(self.trace_name)}")
        self.bodies = []
        for body in scene.bodies:
            if body.outline is not None:
                patch = Polygon(np.zeros((len(body.outline), 2)), closed=True, facecolor=_BODY_FACE,
                                edgecolor=_BODY_EDGE, lw=1.5, zorder=3, animated=True)
                ax.add_patch(patch)
                (centre,) = ax.plot([], [], "o", color=_BODY_EDGE, ms=3, zorder=4, animated=True)
            else:
                patch = None
                (centre,) = ax.plot([], [], "o", color=_BODY_EDGE, ms=7, zorder=4, mfc=_BODY_FACE, mew=1.5,
                                    animated=True)
            self.bodies.append((body, patch, centre))
        self.beams = []
        for beam in scene.beams:
            (axis,) = ax.plot([], [], ls="--", color="0.55", lw=0.8, zorder=2, animated=True)
            (line,) = ax.plot([], [], color=_BEAM, lw=2.4, solid_capstyle="round", zorder=5, animated=True)
            self.beams.append((beam, axis, line))
        self.time_text = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", ha="left", fontsize=10,
                                 family="monospace", zorder=6, animated=True)
        note = f"beam deflection x {self.magnify:g}" if scene.beams else ""
        self.magnify_text = ax.text(0.02, 0.91, note, transform=ax.transAxes, va="top", ha="left",
                                    fontsize=9, color=_BEAM, zorder=6)
        if self.trace_line is not None:
            ax.legend(loc="lower right", fontsize=8, framealpha=0.8)

    def _animated(self) -> list:
        artists = [self.trace_line] if self.trace_line is not None else []
        for _, patch, centre in self.bodies:
            artists += [patch, centre] if patch is not None else [centre]
        for _, axis, line in self.beams:
            artists += [axis, line]
        return sorted(artists + [self.time_text], key=lambda a: a.get_zorder())

    def frame(self, k: int) -> np.ndarray:
        """The image of output row ``k``, shape (height, width, 3), uint8 RGB.

        The static part (axes, grid, labels) is rendered once; each frame restores it and draws
        only the moving artists on it.
        """
        scene = self.scene
        for body, patch, centre in self.bodies:
            x, y, _ = (a[k] for a in scene.pose(body.name))
            if patch is not None:
                patch.set_xy(scene.body_polygon(body, k))
            centre.set_data([x], [y])
        for beam, axis, line in self.beams:
            a = scene.beam_axis(beam, k)
            axis.set_data(a[:, 0], a[:, 1])
            c = scene.beam_line(beam, k, self.magnify)
            line.set_data(c[:, 0], c[:, 1])
        if self.trace_line is not None:
            done = self.path[: k + 1]
            self.trace_line.set_data(done[:, 0], done[:, 1])
        self.time_text.set_text(f"t = {scene.t[k]:.3f} s")
        return self._blit(self._animated(), self.axes.draw_artist)
