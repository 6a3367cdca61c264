"""Geometry of a finished run of a spatial model, frame by frame, as polylines in the ground frame.

From the run's outputs (``x_<b>, y_<b>, z_<b>``: a body's mass centre in N [m]; ``e0_<b> .. e3_<b>``:
the Euler parameters of its frame in N, or else ``yaw_<b>, pitch_<b>, roll_<b>``: its 3-2-1 body-fixed
angles [rad], ``C = Cz(yaw) Cy(pitch) Cx(roll)``) and the model file text stored with them, every body
becomes

* its outline (``outline``, a closed polyline in the body frame), if it has one;
* else a centre line from each of its named points to its mass centre (a link between its joints;
  from its one point to its mass centre if it has one);
* a marker at its mass centre.

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


class SpatialScene:
    """A spatial chain at the output rows of a run, as :class:`SpatialPolyline` s.

    Parameters
    ----------
    results : Results
        A finished (or partial) run of a model with ``dimensions = 3``.
    model : Model
        The run's model (validated), read from ``results.model_text``.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Output times [s].
    name : str
        Model name.
    partial : bool
    """

    def __init__(self, results: Results, model):
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
        """Every body's outline or centre line and its mass-centre marker, at every output row."""
        out = []
        for name, shape in self.shapes.items():
            r, C = self.pose(name)
            if shape is not None:
                kind, local = shape
                out.append(SpatialPolyline(name, r[:, None, :] + np.einsum("nij,mj->nmi", C, local), kind))
            out.append(SpatialPolyline(f"{name} (mass centre)", r[:, None, :], "marker"))
        return out

    def trace_names(self) -> list[str]:
        """Points that can be traced: every body's mass centre, ``cm``, ``none``."""
        return [*self.shapes, "cm", "none"]

    def default_trace(self) -> str:
        """The mass centre of the last body."""
        return list(self.shapes)[-1] if self.shapes else "none"

    def trace(self, point: str) -> np.ndarray | None:
        """Path of a body's mass centre, or of the system's (``cm``), shape (N, 3) [m]; None for ``none``."""
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
        raise ModelError("--trace", "one of " + ", ".join(self.trace_names()), point)

    def trace_label(self, point: str) -> str:
        """Readable name of a traced point."""
        return "centre of mass of the system" if point == "cm" else f"mass centre of {point}"


def _quaternion_matrices(e: np.ndarray) -> np.ndarray:
    """Direction cosines of Euler parameters row by row, shape (N, 3, 3) from (N, 4); each row is
    normalized first (the integration keeps the norm only to its tolerance)."""
    norms = np.linalg.norm(e, axis=1)
    safe = np.where(norms > 0, norms, 1.0)[:, None]
    return quaternion_matrices(e / safe)
