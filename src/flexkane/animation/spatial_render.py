"""Drawing of a spatial chain with matplotlib's 3D axes: per-frame polylines seen from a chosen view.

The drawing knows no model: it is given, for every frame, the polylines to draw in the ground frame N
(bodies' outlines, link centre lines, mass-centre markers; :class:`SpatialPolyline`) and optionally the
path of a traced point. A view is the elevation and azimuth of matplotlib's camera [deg]
(``elevation = 90`` looks down the z axis of N; ``azimuth`` turns the camera about it, ``-90`` puts x
to the right). The axes hold every frame with equal scales on x, y and z. The same input gives the
same pixels (no clock, no random state).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from .render import _BEAM, _BODY_EDGE, _BODY_FACE, _TRACE, BlittedFrames, pyplot

__all__ = ["SpatialPolyline", "SpatialDrawing", "check_view", "DEFAULT_VIEW", "POLYLINE_KINDS"]

#: Elevation and azimuth of the camera [deg] when none is given (matplotlib's own default is 30, -60).
DEFAULT_VIEW = (25.0, -60.0)
#: How a polyline is drawn: a body's closed outline, a link's centre line, a beam's deflected centre
#: line, or a marker at one point.
POLYLINE_KINDS = ("outline", "link", "beam", "marker")

_STYLE = {"outline": {"color": _BODY_EDGE, "lw": 1.6},
          "link": {"color": _BEAM, "lw": 2.4, "solid_capstyle": "round"},
          "beam": {"color": _BEAM, "lw": 3.0, "solid_capstyle": "round"},
          "marker": {"color": _BODY_EDGE, "marker": "o", "ms": 6, "mfc": _BODY_FACE, "mew": 1.5, "ls": "none"}}


@dataclass
class SpatialPolyline:
    """One polyline of the drawing, at every frame.

    Attributes
    ----------
    name : str
        What it draws (a body or link name), for legends and messages.
    points : ndarray, shape (F, m, 3)
        Its vertices in the ground frame N at each of the F frames [m].
    kind : str
        One of :data:`POLYLINE_KINDS`; an ``outline`` is drawn closed.
    """

    name: str
    points: np.ndarray
    kind: str = "link"

    def closed_points(self, k: int) -> np.ndarray:
        """The vertices drawn at frame k, shape (m or m + 1, 3) [m] (an outline closed)."""
        p = self.points[k]
        return np.vstack([p, p[:1]]) if self.kind == "outline" and len(p) > 2 else p


def check_view(view) -> tuple[float, float]:
    """A view ``(elevation, azimuth)`` [deg] as two finite floats; None gives :data:`DEFAULT_VIEW`.

    Accepts a pair of numbers or the text ``"ELEV,AZIM"`` (the command line's ``--view``).

    Raises
    ------
    ModelError
        Naming ``--view``: not two finite numbers, or an elevation outside [-90, 90].
    """
    if view is None:
        return DEFAULT_VIEW
    expected = "two numbers ELEVATION,AZIMUTH [deg] (e.g. 25,-60; elevation from -90 to 90)"
    given = view
    if isinstance(view, str):
        parts = view.replace(" ", "").split(",")
        try:
            view = tuple(float(p) for p in parts)
        except ValueError:
            raise ModelError("--view", expected, given) from None
    if not isinstance(view, (tuple, list)) or len(view) != 2 or any(
            isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in view):
        raise ModelError("--view", expected, given)
    elevation, azimuth = float(view[0]), float(view[1])
    if not -90.0 <= elevation <= 90.0:
        raise ModelError("--view", expected, given)
    return elevation, azimuth


def cube_bounds(polylines: list[SpatialPolyline], trace: np.ndarray | None, rows) -> np.ndarray:
    """Limits ``[[xmin, xmax], [ymin, ymax], [zmin, zmax]]`` [m] of a cube holding every polyline at
    the frames ``rows`` and the trace, with a margin; equal spans keep the scales equal."""
    parts = [line.points[np.asarray(rows)].reshape(-1, 3) for line in polylines]
    if trace is not None:
        parts.append(trace[np.asarray(rows)])
    p = np.vstack(parts) if parts else np.zeros((1, 3))
    p = p[np.all(np.isfinite(p), axis=1)]
    if not len(p):
        p = np.zeros((1, 3))
    lo, hi = p.min(axis=0), p.max(axis=0)
    centre = 0.5 * (lo + hi)
    half = 0.55 * max(float(np.max(hi - lo)), 1e-3)
    return np.column_stack([centre - half, centre + half])


class SpatialDrawing(BlittedFrames):
    """A 3D figure of per-frame polylines, redrawn for any frame by :meth:`frame`.

    Parameters
    ----------
    t : ndarray, shape (F,)
        Time of each frame [s], written on it.
    polylines : list of SpatialPolyline
        What is drawn; each holds F frames.
    trace : ndarray, shape (F, 3), optional
        Path of a traced point in N [m], drawn up to the current frame.
    trace_label : str
        Legend of the trace.
    view : (float, float)
        Elevation and azimuth of the camera [deg] (:func:`check_view`).
    title : str
        Figure title.
    rows : array_like of int, optional
        Frames that will be drawn (they set the limits); all by default.
    dpi : int
        Resolution [dots per inch]; the figure is 6.4 x 5.6 inches.
    """

    def __init__(self, t, polylines: list[SpatialPolyline], *, trace: np.ndarray | None = None,
                 trace_label: str = "", view=DEFAULT_VIEW, title: str = "", rows=None, dpi: int = 100):
        t = np.asarray(t, dtype=float)
        for line in polylines:
            if line.kind not in POLYLINE_KINDS:
                raise ValueError(f"polyline {line.name!r}: kind {line.kind!r} is not one of {POLYLINE_KINDS}")
            if line.points.ndim != 3 or line.points.shape[0] != len(t) or line.points.shape[2] != 3:
                raise ValueError(f"polyline {line.name!r}: points of shape (F, m, 3) with F = {len(t)}, "
                                 f"got {line.points.shape}")
        plt = pyplot()
        self.t = t
        self.polylines = list(polylines)
        self.trace = None if trace is None else np.asarray(trace, dtype=float)
        self.view = check_view(view)
        rows = np.arange(len(t)) if rows is None else np.asarray(rows, dtype=int)
        self.bounds = cube_bounds(self.polylines, self.trace, rows)
        self.figure = plt.figure(figsize=(6.4, 5.6), dpi=dpi)
        ax = self.figure.add_subplot(projection="3d")
        self.axes = ax
        ax.view_init(elev=self.view[0], azim=self.view[1])
        ax.set_xlim(*self.bounds[0])
        ax.set_ylim(*self.bounds[1])
        ax.set_zlim(*self.bounds[2])
        ax.set_box_aspect((1.0, 1.0, 1.0))
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        ax.set_title(title, fontsize=10)
        self.lines = []
        for line in self.polylines:
            (artist,) = ax.plot([], [], [], animated=True, **_STYLE[line.kind])
            self.lines.append((line, artist))
        self.trace_line = None
        if self.trace is not None:
            (self.trace_line,) = ax.plot([], [], [], color=_TRACE, lw=1.2, alpha=0.9, animated=True,
                                         label=f"trace: {trace_label}")
            ax.legend(loc="upper right", fontsize=8, framealpha=0.8)
        self.time_text = self.figure.text(0.02, 0.97, "", va="top", ha="left", fontsize=10, family="monospace",
                                          animated=True)
        self.figure.text(0.98, 0.02, f"view: elevation {self.view[0]:g} deg, azimuth {self.view[1]:g} deg",
                         va="bottom", ha="right", fontsize=8, color="0.4")
        self._background = None

    def frame(self, k: int) -> np.ndarray:
        """The image of frame ``k``, shape (height, width, 3), uint8 RGB.

        The axes (panes, grid, labels: fixed, as the view and the limits are) are rendered once; each
        frame restores them and draws the moving lines on them, the trace first.
        """
        for line, artist in self.lines:
            p = line.closed_points(k)
            artist.set_data_3d(p[:, 0], p[:, 1], p[:, 2])
        if self.trace_line is not None:
            done = self.trace[: k + 1]
            self.trace_line.set_data_3d(done[:, 0], done[:, 1], done[:, 2])
        self.time_text.set_text(f"t = {self.t[k]:.3f} s")
        moving = ([self.trace_line] if self.trace_line is not None else []) + [a for _, a in self.lines]
        return self._blit(moving + [self.time_text], self.figure.draw_artist)
