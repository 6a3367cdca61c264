"""Geometry of a finished run of a spatial model, frame by frame, as polylines in the ground frame.

From the run's outputs (``x_<b>, y_<b>, z_<b>``: a body's mass centre in N [m]; ``e0_<b> .. e3_<b>``:
the Euler parameters of its frame in N, or else ``yaw_<b>, pitch_<b>, roll_<b>``: its 3-2-1 body-fixed
angles [rad], ``C = Cz(yaw) Cy(pitch) Cx(roll)``) and the model file text stored with them, every body
becomes

* its outline (``outline``, a closed polyline in the body frame), if it has one;
* else a centre line from each of its named points to its mass centre (a link between its joints;
  from its one point to its mass centre if it has one);
* a marker at its mass centre;

and every beam its deflected centre line (outputs ``x_<b>, y_<b>, z_<b>`` and ``e0_<b> .. e3_<b>``: the
root and the beam frame B in N; the modal coordinates of the run's states), the point at distance x
from the root at ``r + C (x + u, cos(beta) v - sin(beta) w, sin(beta) v + cos(beta) w)`` with
``v = sum Phi^y_i q_yi``, ``w = sum Phi^z_j q_zj``, ``beta`` the principal angle and ``u`` the axial
modes minus the foreshortening ``1/2 int_0^x (v'^2 + w'^2) dx`` of a beam with geometric stiffening
(as the engine places it, :mod:`flexkane.kane.spatial_beam`).

A vertex ``p`` given in the body frame (from the mass centre) is drawn at ``r + C p``.
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..model.orientation import quaternion_matrices, sequence_matrices
from ..results import Results
from .spatial_render import SpatialPolyline

__all__ = ["SpatialScene"]

_POSE = ("x", "y", "z", "yaw", "pitch", "roll")
#: Stations drawn along every beam.
_STATIONS = 41


class SpatialScene:
    """A spatial chain at the output rows of a run, as :class:`SpatialPolyline` s.

    Parameters
    ----------
    results : Results
        A finished (or partial) run of a model with ``dimensions = 3``.
    model : Model
        The run's model (validated), read from ``results.model_text``.
    magnify : float or "auto"
        Magnification of the beams' displacements [-] (never of the rigid motion); ``"auto"`` a round
        factor that draws the largest at about a tenth of the longest beam.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Output times [s].
    name : str
        Model name.
    partial : bool
    magnify : float
        The magnification used.
    """

    def __init__(self, results: Results, model, magnify=1.0):
        from ..model.field_values import FieldValues

        self.results = results
        self.t = np.asarray(results.t, dtype=float)
        self.name = model.name
        self.partial = bool(results.partial)
        fields = FieldValues(model)
        self.shapes = {}
        for name, body in model.bodies.items():
            def vertices(points, path):
                return np.array([[fields.value(c, f"{path}[{i}][{k}]") for k, c in enumerate(p)]
                                 for i, p in enumerate(points)]).reshape(-1, 3)

            if body.outline:
                self.shapes[name] = ("outline", vertices(body.outline, f"bodies.{name}.outline"))
            elif body.points:
                local = vertices(list(body.points.values()), f"bodies.{name}.points")
                stick = np.zeros((max(2 * len(local) - 1, 2), 3))
                stick[0::2] = local                 # point, centre, point, ..., point (one point: to the centre)
                self.shapes[name] = ("link", stick)
            else:
                self.shapes[name] = None
        shapes = {name: self._beam_local(model, name, fields) for name in model.beams}
        self.magnify = _magnification(magnify, shapes)
        self.beams = {name: line + self.magnify * displacement for name, (line, displacement) in shapes.items()}

    def _beam_local(self, model, name: str, fields) -> tuple[np.ndarray, np.ndarray]:
        """A beam's undeformed centre line in its own frame B, shape (s, 3), and the displacement of its
        stations at every output row, shape (N, s, 3) [m]."""
        from ..modes.from_spec import beam_shape_family
        from .scene import _cumulative_integral

        beam = model.beams[name]
        path = f"beams.{name}"
        L = fields.value(beam.L, f"{path}.L")
        xi = np.linspace(0.0, 1.0, _STATIONS)
        rows = len(self.t)
        local = np.zeros((rows, len(xi), 3))
        bend, slope2 = {}, np.zeros((rows, len(xi)))
        for key, count, spec in (("y", beam.n_modes_y, beam.shape_y), ("z", beam.n_modes_z, beam.shape_z)):
            bend[key] = np.zeros((rows, len(xi)))
            if count:
                family = beam_shape_family(model, beam, f"shape_{key}", fields.parameters)
                q = np.column_stack([self._column(f"q_{name}_{key}{i}") for i in range(1, count + 1)])
                bend[key] = q @ family.phi(xi, count)
                slope2 += (q @ family.phi(xi, count, deriv=1) / L) ** 2
        if beam.geometric_stiffening:
            local[:, :, 0] -= 0.5 * _cumulative_integral(slope2, xi * L)
        if beam.n_axial:
            family = beam_shape_family(model, beam, "axial_shape", fields.parameters)
            s = np.column_stack([self._column(f"s_{name}_{k}") for k in range(1, beam.n_axial + 1)])
            local[:, :, 0] += s @ family.phi(xi, beam.n_axial)
        beta = fields.value(beam.principal_angle, f"{path}.principal_angle") if beam.principal_angle is not None \
            else 0.0
        local[:, :, 1] = np.cos(beta) * bend["y"] - np.sin(beta) * bend["z"]
        local[:, :, 2] = np.sin(beta) * bend["y"] + np.cos(beta) * bend["z"]
        line = np.zeros((len(xi), 3))
        line[:, 0] = xi * L
        return line, local

    def _column(self, name: str) -> np.ndarray:
        """A state column by name, shape (N,); a coordinate the run does not store is zero."""
        try:
            return np.asarray(self.results[name], dtype=float)
        except KeyError:
            return np.zeros(len(self.t))

    def pose(self, body: str) -> tuple[np.ndarray, np.ndarray]:
        """Mass centre in N [m], shape (N, 3), and direction cosines of the body frame, shape (N, 3, 3):
        from the Euler parameters where the run has them (no singularity), else the 3-2-1 angles."""
        outputs = self.results.outputs
        if all(f"e{k}_{body}" in outputs for k in range(4)) and all(f"{c}_{body}" in outputs for c in "xyz"):
            r = np.column_stack([np.asarray(outputs[f"{c}_{body}"], dtype=float) for c in "xyz"])
            e = np.column_stack([np.asarray(outputs[f"e{k}_{body}"], dtype=float) for k in range(4)])
            return r, _quaternion_matrices(e)
        try:
            x, y, z, yaw, pitch, roll = (np.asarray(self.results[f"{c}_{body}"], dtype=float) for c in _POSE)
        except KeyError:
            raise ModelError("results.npz", f"outputs {', '.join(f'{c}_{body}' for c in _POSE)} (or "
                             f"e0_{body} .. e3_{body} for the orientation)", "a run without them") from None
        return np.column_stack([x, y, z]), sequence_matrices("zyx", np.column_stack([yaw, pitch, roll]))

    def polylines(self) -> list[SpatialPolyline]:
        """Every beam's deflected centre line, every body's outline or centre line and its mass-centre
        marker, at every output row."""
        out = []
        for name, local in self.beams.items():
            r, C = self.pose(name)
            out.append(SpatialPolyline(name, r[:, None, :] + np.einsum("nij,nmj->nmi", C, local), "beam"))
        for name, shape in self.shapes.items():
            r, C = self.pose(name)
            if shape is not None:
                kind, local = shape
                out.append(SpatialPolyline(name, r[:, None, :] + np.einsum("nij,mj->nmi", C, local), kind))
            out.append(SpatialPolyline(f"{name} (mass centre)", r[:, None, :], "marker"))
        return out

    def trace_names(self) -> list[str]:
        """Points that can be traced: every body's mass centre, every beam's tip, ``cm``, ``none``."""
        return [*self.shapes, *self.beams, "cm", "none"]

    def default_trace(self) -> str:
        """The mass centre of the last body."""
        return list(self.shapes)[-1] if self.shapes else "none"

    def trace(self, point: str) -> np.ndarray | None:
        """Path of a body's mass centre, a beam's tip or the system's mass centre (``cm``), shape (N, 3) [m];
        None for ``none``."""
        if point == "none":
            return None
        if point == "cm":
            try:
                return np.column_stack([np.asarray(self.results[f"{c}_cm"], dtype=float) for c in "xyz"])
            except KeyError:
                raise ModelError("--trace", "a body name or 'none' (this run has no outputs x_cm, y_cm, z_cm)",
                                 point) from None
        if point in self.shapes:
            return self.pose(point)[0]
        if point in self.beams:
            r, C = self.pose(point)
            return r + np.einsum("nij,nj->ni", C, self.beams[point][:, -1])
        raise ModelError("--trace", "one of " + ", ".join(self.trace_names()), point)

    def trace_label(self, point: str) -> str:
        """Readable name of a traced point."""
        if point in self.beams:
            return f"tip of {point}"
        return "centre of mass of the system" if point == "cm" else f"mass centre of {point}"


def _magnification(magnify, shapes: dict) -> float:
    """The factor of ``magnify`` (checked by :func:`flexkane.animation.check_animation_options`):
    a number, or for ``"auto"`` a round one (1, 2 or 5 times a power of ten, at least 1) that draws
    the largest displacement at about a tenth of the longest beam, as the planar drawing does."""
    if not (isinstance(magnify, str) and magnify.strip().lower() == "auto"):
        return float(magnify)
    largest = max((float(np.max(np.linalg.norm(d, axis=-1), initial=0.0)) for _, d in shapes.values()), default=0.0)
    if largest <= 0 or not np.isfinite(largest):
        return 1.0
    target = 0.1 * max(line[-1, 0] for line, _ in shapes.values()) / largest
    if target <= 1:
        return 1.0
    exponent = np.floor(np.log10(target))
    return float(max(m for m in (1, 2, 5) if m * 10 ** exponent <= target) * 10 ** exponent)


def _quaternion_matrices(e: np.ndarray) -> np.ndarray:
    """Direction cosines of Euler parameters row by row, shape (N, 3, 3) from (N, 4); each row is
    normalized first (the integration keeps the norm only to its tolerance)."""
    norms = np.linalg.norm(e, axis=1)
    safe = np.where(norms > 0, norms, 1.0)[:, None]
    return quaternion_matrices(e / safe)
