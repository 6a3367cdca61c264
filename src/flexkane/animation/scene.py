"""Geometry of a finished run, frame by frame: body outlines, deformed beams, traced points.

Everything comes from the run's :class:`~flexkane.results.Results` (so from ``results.npz``): the
model file text gives the outlines, the beam lengths and shape functions and the names of the modal
coordinates; the outputs ``x_<link>``, ``y_<link>``, ``theta_<link>`` give the pose of every body
(mass centre) and every beam (root).

A point at distance x from the root of a beam is drawn at

    r = r_root + R(theta) [x + u(x), y(x)],   y(x) = sum_i Phi_i(x/L) q_i    (eq. 8.15)

in the ground frame, with ``u(x) = sum_k Psi_k(x/L) s_k`` the axial displacement (if the beam has
axial modes) minus ``1/2 int_0^x y'^2 dx`` (the foreshortening, for beams with geometric
stiffening). A magnification factor K multiplies the displacement ``(u, y)``, never the rigid motion.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..results import Results

__all__ = ["Scene", "BodyShape", "BeamShape", "TRACE_NONE", "TRACE_CENTRE_OF_MASS"]

#: ``--trace`` values other than a body or beam name.
TRACE_NONE = "none"
TRACE_CENTRE_OF_MASS = "cm"

#: Stations drawn along every beam.
_STATIONS = 41


@dataclass
class BodyShape:
    """A rigid body as drawn.

    Attributes
    ----------
    name : str
    outline : ndarray, shape (m, 2), or None
        Polygon in the body frame, relative to the mass centre [m]; None draws a marker.
    """

    name: str
    outline: np.ndarray | None


@dataclass
class BeamShape:
    """A beam as drawn: its length and the displacement of its centre line at fixed stations.

    Attributes
    ----------
    name : str
    L : float
        Length [m].
    x : ndarray, shape (s,)
        Stations along the undeformed axis, from the root [m].
    transverse : ndarray, shape (N, s)
        Deflection y(x) of eq. 8.15 at every output time [m].
    axial : ndarray, shape (N, s)
        Displacement along the axis u(x) (axial modes and foreshortening) [m].
    """

    name: str
    L: float
    x: np.ndarray
    transverse: np.ndarray
    axial: np.ndarray


class Scene:
    """The chain at every output time of a run, ready to be drawn.

    Parameters
    ----------
    results : Results
        A finished (or partial) run, e.g. from :func:`flexkane.load_results`.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Output times [s].
    name : str
        Model name.
    bodies : list of BodyShape
    beams : list of BeamShape
    """

    def __init__(self, results: Results):
        from ..model import loads_model
        from ..model.coordinates import coordinate_names
        from ..model.field_values import FieldValues

        if not results.model_text:
            raise ModelError("results.npz", "a run that stored its model file text", "no model text")
        model = loads_model(results.model_text, source="results.npz").validate()
        self.results = results
        self.t = np.asarray(results.t, dtype=float)
        self.name = model.name
        self.partial = bool(results.partial)
        fields = FieldValues(model)

        def number(value, path: str) -> float:
            return fields.value(value, path)

        self.bodies = []
        for name, body in model.bodies.items():
            outline = None
            if body.outline:
                outline = np.array([[number(px, f"bodies.{name}.outline[{i}][0]"),
                                     number(py, f"bodies.{name}.outline[{i}][1]")]
                                    for i, (px, py) in enumerate(body.outline)])
            self.bodies.append(BodyShape(name, outline))
        coordinates = coordinate_names(model)
        self._parameters = fields.parameters
        self.beams = [self._beam_shape(model, coordinates, name, number) for name in model.beams]

    # ------------------------------------------------------------------ construction
    def _beam_shape(self, model, coordinates, name: str, number) -> BeamShape:
        from ..modes.from_spec import beam_shape_family

        beam = model.beams[name]
        L = number(beam.L, f"beams.{name}.L")
        xi = np.linspace(0.0, 1.0, _STATIONS)
        N = len(self.t)
        modes = [c.q for c in coordinates if c.owner == name and c.role == "mode"]
        transverse = np.zeros((N, len(xi)))
        axial = np.zeros((N, len(xi)))
        if modes:
            family = beam_shape_family(model, beam, "shape", self._parameters)
            q = np.column_stack([self._column(m) for m in modes])              # (N, n)
            transverse = q @ family.phi(xi, len(modes))                        # (N, s)
            if beam.geometric_stiffening:
                slope = q @ family.phi(xi, len(modes), deriv=1) / L            # y'(x), (N, s)
                axial -= 0.5 * _cumulative_integral(slope ** 2, xi * L)
        stretch = [c.q for c in coordinates if c.owner == name and c.role == "axial"]
        if stretch:
            family = beam_shape_family(model, beam, "axial_shape", self._parameters)
            s = np.column_stack([self._column(m) for m in stretch])
            axial += s @ family.phi(xi, len(stretch))
        return BeamShape(name, L, xi * L, transverse, axial)

    def _column(self, name: str) -> np.ndarray:
        """A state column or output by name, shape (N,); a coordinate that is not stored is zero."""
        try:
            return np.asarray(self.results[name], dtype=float)
        except KeyError:
            return np.zeros(len(self.t))

    def pose(self, link: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position [m] and angle [rad] of a link frame at every output time, each shape (N,)."""
        try:
            return tuple(np.asarray(self.results[f"{c}_{link}"], dtype=float) for c in ("x", "y", "theta"))
        except KeyError:
            raise ModelError("results.npz", f"outputs x_{link}, y_{link}, theta_{link}",
                             "a run without them") from None

    # ------------------------------------------------------------------ geometry
    def body_polygon(self, body: BodyShape, k: int) -> np.ndarray:
        """Outline of a body at output row k in the ground frame, shape (m, 2) [m]."""
        x, y, th = (a[k] for a in self.pose(body.name))
        if body.outline is None:
            return np.array([[x, y]])
        return _place(body.outline, x, y, th)

    def beam_line(self, beam: BeamShape, k: int, magnify: float = 1.0) -> np.ndarray:
        """Deformed centre line of a beam at output row k in the ground frame, shape (s, 2) [m]."""
        x, y, th = (a[k] for a in self.pose(beam.name))
        local = np.column_stack([beam.x + magnify * beam.axial[k], magnify * beam.transverse[k]])
        return _place(local, x, y, th)

    def beam_axis(self, beam: BeamShape, k: int) -> np.ndarray:
        """Undeformed axis of a beam at output row k, from the root to x = L, shape (2, 2) [m]."""
        x, y, th = (a[k] for a in self.pose(beam.name))
        return _place(np.array([[0.0, 0.0], [beam.L, 0.0]]), x, y, th)

    def trace_names(self) -> list[str]:
        """Points that can be traced: every body (mass centre), every beam (tip), ``cm``, ``none``."""
        return [b.name for b in self.bodies] + [b.name for b in self.beams] + [TRACE_CENTRE_OF_MASS, TRACE_NONE]

    def default_trace(self) -> str:
        """The tip of the last beam, else the mass centre of the last body."""
        if self.beams:
            return self.beams[-1].name
        if self.bodies:
            return self.bodies[-1].name
        return TRACE_NONE

    def trace_label(self, point: str) -> str:
        """Readable name of a traced point."""
        if point == TRACE_CENTRE_OF_MASS:
            return "centre of mass of the system"
        if any(b.name == point for b in self.beams):
            return f"tip of {point}"
        return f"mass centre of {point}"

    def trace(self, point: str, magnify: float = 1.0) -> np.ndarray | None:
        """Path of a point over the whole run, shape (N, 2) [m]; None for ``none``.

        Parameters
        ----------
        point : str
            A body name (its mass centre), a beam name or ``tip_<beam>`` (its tip, drawn with the
            same magnification as the beam), ``cm`` (centre of mass of the system) or ``none``.
        magnify : float
            Magnification of beam displacements [-].
        """
        if point == TRACE_NONE:
            return None
        if point == TRACE_CENTRE_OF_MASS:
            return np.column_stack([self._column("x_cm"), self._column("y_cm")])
        name = point[4:] if point.startswith("tip_") else point
        for beam in self.beams:
            if beam.name == name:
                x, y, th = self.pose(beam.name)
                u = beam.L + magnify * beam.axial[:, -1]
                v = magnify * beam.transverse[:, -1]
                return np.column_stack([x + np.cos(th) * u - np.sin(th) * v, y + np.sin(th) * u + np.cos(th) * v])
        for body in self.bodies:
            if body.name == point:
                x, y, _ = self.pose(body.name)
                return np.column_stack([x, y])
        raise ModelError("--trace", "one of " + ", ".join(self.trace_names()), point)

    def bounds(self, rows: np.ndarray, magnify: float = 1.0, trace: str = TRACE_NONE) -> tuple:
        """Limits ``(xmin, xmax, ymin, ymax)`` [m] that hold the drawing at every row in ``rows``."""
        points = []
        for k in rows:
            for body in self.bodies:
                points.append(self.body_polygon(body, k))
            for beam in self.beams:
                points.append(self.beam_line(beam, k, magnify))
                points.append(self.beam_axis(beam, k))
        path = self.trace(trace, magnify)
        if path is not None:
            points.append(path[rows])
        p = np.vstack(points) if points else np.zeros((1, 2))
        p = p[np.all(np.isfinite(p), axis=1)]
        if not len(p):
            p = np.zeros((1, 2))
        lo, hi = p.min(axis=0), p.max(axis=0)
        span = max(float(np.max(hi - lo)), self.size_scale())
        pad = 0.08 * span
        return lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad

    def size_scale(self) -> float:
        """A length typical of the chain [m]: the longest beam or outline, for markers and margins."""
        sizes = [b.L for b in self.beams]
        sizes += [float(np.ptp(b.outline, axis=0).max()) for b in self.bodies if b.outline is not None]
        return max(sizes) if sizes else 1.0

    def max_deflection(self) -> float:
        """Largest displacement of any beam station over the run [m] (0 without beams)."""
        values = [np.nanmax(np.abs(np.hypot(b.transverse, b.axial))) for b in self.beams if b.transverse.size]
        return float(max(values)) if values else 0.0

    def auto_magnification(self, fraction: float = 0.1) -> float:
        """A round factor (1, 2 or 5 times a power of ten, at least 1) that draws the largest beam
        displacement at about ``fraction`` of the longest beam."""
        largest = self.max_deflection()
        if not self.beams or largest <= 0 or not np.isfinite(largest):
            return 1.0
        target = fraction * max(b.L for b in self.beams) / largest
        if target <= 1:
            return 1.0
        exponent = np.floor(np.log10(target))
        mantissa = max(m for m in (1, 2, 5) if m * 10 ** exponent <= target)
        return float(mantissa * 10 ** exponent)


def _place(local: np.ndarray, x: float, y: float, theta: float) -> np.ndarray:
    """Points given in a frame at (x, y) turned by theta, in the ground frame; shape of ``local``."""
    c, s = np.cos(theta), np.sin(theta)
    return np.column_stack([x + c * local[:, 0] - s * local[:, 1], y + s * local[:, 0] + c * local[:, 1]])


def _cumulative_integral(f: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Trapezoidal ``int_0^x f dx`` along the last axis; same shape as ``f``."""
    steps = 0.5 * (f[..., 1:] + f[..., :-1]) * np.diff(x)
    return np.concatenate([np.zeros(f.shape[:-1] + (1,)), np.cumsum(steps, axis=-1)], axis=-1)
