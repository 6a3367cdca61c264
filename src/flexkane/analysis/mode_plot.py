"""Drawings of a chain's mode shapes: beams deformed with their shape functions, bodies by outline.

A configuration is drawn from the outputs of the equations of motion (the position ``x_<link>``,
``y_<link>`` and angle ``theta_<link>`` of every body's mass centre and every beam's root) and, along
each beam, the deflection ``Y(x) = sum_i Phi_i(x/L) q_i`` of eq. 8.15 (and the axial displacement
``sum_k Psi_k(x/L) s_k`` of beams with axial modes) evaluated with the beam's shape family; the
foreshortening of geometric stiffening, second order in q, is not drawn. A mode is drawn at
``q0 + a dq`` with the amplitude a chosen so that the largest displacement is 15 % of the chain's size.

Spatial models (``dimensions = 3``) with beams are drawn along each beam instead
(:class:`SpatialBeamShapes`): the deflections ``v(x) = sum_i Phi^y_i(x/L) dq_yi`` along the section's
principal axis y_p and ``w(x) = sum_j Phi^z_j(x/L) dq_zj`` along z_p [m], the axial displacement
``u(x)`` [m] and the twist ``theta(x) = sum_k Theta_k(x/L) dq_tk`` [rad] (on a second axis) of the
mode shape dq (largest coordinate 1), each panel titled with the mode's label (``flap 1``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import sympy as sp

from .eigen import ModalAnalysis, Mode

__all__ = ["ChainDrawing", "SpatialBeamShapes", "plot_mode_shapes"]

#: Largest displacement of a drawn mode, as a fraction of the size of the chain.
DRAWN_AMPLITUDE = 0.15


class ChainDrawing:
    """Polylines of every link of a linearized chain for any configuration.

    Parameters
    ----------
    linear : LinearModel
        A linear model made by :class:`~flexkane.analysis.linearization.Linearization` (which gives
        the equations, the model and the constants).
    points : int
        Points drawn along each beam.
    """

    def __init__(self, linear, points: int = 61):
        from ..model.field_values import FieldValues
        from ..modes.from_spec import beam_shape_family

        lin = linear.linearization
        self.linear = linear
        eom = lin.eom
        model = lin.model
        if model.dimensions == 3:
            from ..errors import ModelError

            raise ModelError("mode shapes", "a planar model to draw (the shapes of a 3D model are in modes.csv)",
                             f"{model.name} (dimensions = 3)")
        self.linearization = lin
        values = eom.constant_values(model)
        values[eom.t] = lin.t0
        self._state = list(eom.q)
        names = [*model.bodies, *model.beams]
        exprs = [[eom.outputs[f"x_{k}"], eom.outputs[f"y_{k}"], eom.outputs[f"theta_{k}"]] for k in names]
        exprs = [[sp.sympify(e).xreplace(values) for e in row] for row in exprs]
        self._frames = sp.lambdify(self._state, exprs, modules="numpy")
        self._names = names
        fields = FieldValues(model)
        self._outlines = {}
        for name, body in model.bodies.items():
            if body.outline:
                pts = [[fields.value(c, f"bodies.{name}.outline") for c in point] for point in body.outline]
                pts.append(pts[0])
                self._outlines[name] = np.array(pts, dtype=float)
            else:
                self._outlines[name] = None
        self._beams = {}
        params = fields.parameters
        index = {q: k for k, q in enumerate(self._state)}
        for name, beam in model.beams.items():
            path = f"beams.{name}"
            L = fields.value(beam.L, f"{path}.L")
            xi = np.linspace(0.0, 1.0, points)
            modes = [index[q] for q in eom.chain.beam_modes(name)]
            phi = (beam_shape_family(model, beam, "shape", params).phi(xi, beam.n_modes) if modes
                   else np.zeros((0, points)))
            axial = [index[s] for s in eom.chain.beam_axial(name)]
            psi = (beam_shape_family(model, beam, "axial_shape", params).phi(xi, beam.n_axial)
                   if axial else np.zeros((0, points)))
            self._beams[name] = (L * xi, modes, phi, axial, psi)

    def full_state(self, q: np.ndarray) -> np.ndarray:
        """Every coordinate of the equations for the linear model's coordinates ``q`` (n,)."""
        values = self.linearization.configuration(self.linear, q)
        return np.array([values[s] for s in self._state], dtype=float)

    def lines(self, q: np.ndarray) -> list[tuple[str, np.ndarray]]:
        """``(kind, points)`` for every link: kind ``beam``, ``body`` or ``point``; points (N, 2) [m]."""
        state = self.full_state(q)
        frames = self._frames(*state)
        out = []
        for name, (x, y, theta) in zip(self._names, frames):
            c, s = np.cos(float(theta)), np.sin(float(theta))
            if name in self._beams:
                xs, modes, phi, axial, psi = self._beams[name]
                X = xs + (state[axial] @ psi if axial else 0.0)
                Y = state[modes] @ phi if modes else np.zeros_like(xs)
                local = np.column_stack([X, Y])
                kind = "beam"
            elif self._outlines[name] is not None:
                local, kind = self._outlines[name], "body"
            else:
                local, kind = np.zeros((1, 2)), "point"
            points = np.column_stack([float(x) + c * local[:, 0] - s * local[:, 1],
                                      float(y) + s * local[:, 0] + c * local[:, 1]])
            out.append((kind, points))
        return out

    def amplitude(self, q0: np.ndarray, shape: np.ndarray) -> float:
        """Amplitude a of ``q0 + a shape`` whose largest displacement is :data:`DRAWN_AMPLITUDE` of
        the size of the chain."""
        base = np.vstack([p for _, p in self.lines(q0)])
        size = float(np.max(np.ptp(base, axis=0))) if base.shape[0] > 1 else 0.0
        size = size if size > 0 else 1.0
        eps = 1e-6 / max(float(np.max(np.abs(shape))), 1e-300)
        moved = np.vstack([p for _, p in self.lines(q0 + eps * shape)])
        per_unit = float(np.max(np.linalg.norm(moved - base, axis=1))) / eps
        return DRAWN_AMPLITUDE * size / per_unit if per_unit > 0 else 0.0


class SpatialBeamShapes:
    """The fields along each spatial beam of a mode shape (module docstring).

    Parameters
    ----------
    linear : LinearModel
        Of a spatial model with beams, made by :class:`~flexkane.analysis.linearization.Linearization`.
    points : int
        Points along each beam.

    Attributes
    ----------
    beams : dict of str to (numpy.ndarray, dict)
        Per beam: the stations x [m], shape (points,), and per field (``v``, ``w``, ``theta``, ``u``)
        the positions of its coordinates in the linear model's coordinates and the values of their
        shape functions at the stations, shape (count, points).
    """

    #: Field of each spatial beam role, and the family key of its shape functions.
    FIELDS = {"mode_y": ("v", "shape_y"), "mode_z": ("w", "shape_z"), "axial": ("u", "axial_shape"),
              "torsion": ("theta", "torsion_shape")}

    def __init__(self, linear, points: int = 61):
        from ..model.field_values import FieldValues
        from ..modes.from_spec import beam_shape_family

        lin = linear.linearization
        model = lin.model
        fields = FieldValues(model)
        index = {name: k for k, name in enumerate(linear.coordinates)}
        xi = np.linspace(0.0, 1.0, points)
        self.beams = {}
        for name, beam in model.beams.items():
            path = f"beams.{name}"
            per_field = {}
            for role, (field_name, key) in self.FIELDS.items():
                coordinates = [c for c in lin.eom.chain.of(name, role) if c.q.name in index]
                if not coordinates:
                    continue
                family = beam_shape_family(model, beam, key, fields.parameters)
                count = max(c.index for c in coordinates)
                phi = family.phi(xi, count)
                per_field[field_name] = ([index[c.q.name] for c in coordinates],
                                         np.array([phi[c.index - 1] for c in coordinates]))
            self.beams[name] = (fields.value(beam.L, f"{path}.L") * xi, per_field)

    def fields(self, shape: np.ndarray) -> dict:
        """Per beam: field name -> its values at the stations for the mode shape ``shape`` (n,)."""
        shape = np.asarray(shape, dtype=float)
        return {name: {f: shape[rows] @ phi for f, (rows, phi) in per_field.items()}
                for name, (_, per_field) in self.beams.items()}


#: Smallest half-range of a field's axis in a drawing of a mode shape whose largest coordinate is 1.
_NOISE_FLOOR = 1e-6
#: How each field of a spatial beam is drawn: label and line style.
_SPATIAL_STYLE = {"v": ("v (along y_p)", "-"), "w": ("w (along z_p)", "--"), "u": ("u (axial)", ":"),
                  "theta": ("twist theta", "-.")}


def _plot_spatial(modal: ModalAnalysis, chosen: list, figure, rows: int, columns: int) -> None:
    """One panel per chosen mode: the fields along every beam (deflections left, twist right)."""
    shapes = SpatialBeamShapes(modal.linear)
    several = len(shapes.beams) > 1
    for panel, (number, mode) in enumerate(chosen):
        axes = figure.add_subplot(rows, columns, panel + 1)
        twist = None
        values = shapes.fields(mode.shape)
        for colour, (name, per_field) in enumerate(values.items()):
            xs = shapes.beams[name][0]
            for field_name, line in per_field.items():
                text, style = _SPATIAL_STYLE[field_name]
                label = f"{text} {name}" if several else text
                if field_name == "theta":
                    twist = twist or axes.twinx()
                    twist.plot(xs, line, style, color="C3" if not several else f"C{colour}", label=label)
                else:
                    axes.plot(xs, line, style, color=f"C{colour}" if several else
                              {"v": "C0", "w": "C1", "u": "C2"}[field_name], label=label)
        for side, lines in ((axes, [v for f in values.values() for k, v in f.items() if k != "theta"]),
                            (twist, [f["theta"] for f in values.values() if "theta" in f])):
            if side is not None:    # symmetric, so that rounding noise of a field absent from the mode shows as 0
                top = max([float(np.max(np.abs(v), initial=0.0)) for v in lines] + [_NOISE_FLOOR])
                side.set_ylim(-1.1 * top, 1.1 * top)
        axes.axhline(0.0, color="0.7", linewidth=0.8)
        axes.set_title(_title(number, mode), fontsize="medium")
        axes.set_xlabel("x along the beam [m]")
        axes.set_ylabel("deflection [m]")
        handles, labels = axes.get_legend_handles_labels()
        if twist is not None:
            twist.set_ylabel("twist [rad]")
            more = twist.get_legend_handles_labels()
            handles, labels = handles + more[0], labels + more[1]
        if handles:
            axes.legend(handles, labels, fontsize="small")


def _draw(axes, lines, **style) -> None:
    for kind, points in lines:
        if kind == "point":
            axes.plot(points[:, 0], points[:, 1], "o", markersize=4, **style)
        else:
            axes.plot(points[:, 0], points[:, 1], "-", **style)


def _title(number: int, mode: Mode) -> str:
    name = f"mode {number} ({mode.label})" if mode.label else f"mode {number}"
    if mode.kind == "rigid":
        return f"{name}: rigid-body"
    if mode.kind == "oscillatory":
        return f"{name}: {mode.omega:.4g} rad/s, {mode.frequency:.4g} Hz"
    return f"{name}: {mode.kind}, {mode.eigenvalue.real:.4g} 1/s"


def plot_mode_shapes(modal: ModalAnalysis, path, count: int = 4) -> Path:
    """Draw the first ``count`` modes that are not rigid-body modes (or the rigid-body modes of a
    chain that has no other) to a PNG file.

    Parameters
    ----------
    modal : ModalAnalysis
        Of a linear model made by :class:`~flexkane.analysis.linearization.Linearization`.
    path : str or pathlib.Path
        The PNG file (written atomically).
    count : int
        Number of modes drawn.

    Returns
    -------
    pathlib.Path
    """
    from ..progress import activity

    with activity(f"drawing the mode shapes of {modal.linear.name}"):   # on stderr when long (flexkane.progress)
        return _plot_mode_shapes(modal, path, count)


def _plot_mode_shapes(modal: ModalAnalysis, path, count: int) -> Path:
    """:func:`plot_mode_shapes`."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from ..atomic import atomic_writer

    linear = modal.linear
    spatial = linear.linearization.model.dimensions == 3
    if spatial and not linear.linearization.model.beams:
        from ..errors import ModelError

        raise ModelError("mode shapes", "a planar model or a spatial model with beams to draw (the shapes of "
                         "a rigid 3D chain are in modes.csv)", f"{linear.name} (dimensions = 3, no beams)")
    drawing = None if spatial else ChainDrawing(linear)
    numbered = list(enumerate(modal.modes, start=1))
    chosen = [(k, m) for k, m in numbered if m.kind != "rigid"][:count] or \
        [(k, m) for k, m in numbered if m.kind == "rigid"][:count]
    panels = max(len(chosen), 1)
    columns = min(panels, 2)
    rows = (panels + columns - 1) // columns
    figure = Figure(figsize=(5.2 * columns, 3.6 * rows), layout="constrained")
    FigureCanvasAgg(figure)
    about = (f"a steady spin, Omega = {linear.spin:g} rad/s (rotating frame)" if linear.spin is not None
             else linear.about)
    figure.suptitle(f"{linear.name}: mode shapes about {about}"
                    + (" (largest coordinate 1)" if spatial else ""))
    if spatial:
        _plot_spatial(modal, chosen, figure, rows, columns)
    base = drawing.lines(linear.q0) if not spatial else []
    for panel, (number, mode) in enumerate([] if spatial else chosen):
        axes = figure.add_subplot(rows, columns, panel + 1)
        _draw(axes, base, color="0.7", linewidth=1.0)
        a = drawing.amplitude(linear.q0, mode.shape)
        _draw(axes, drawing.lines(linear.q0 + a * mode.shape), color="C0", linewidth=1.8)
        _draw(axes, drawing.lines(linear.q0 - a * mode.shape), color="C0", linewidth=0.8, alpha=0.4)
        axes.set_title(_title(number, mode), fontsize="medium")
        axes.set_aspect("equal", adjustable="datalim")
        axes.set_xlabel("x [m]")
        axes.set_ylabel("y [m]")
    if not chosen:
        axes = figure.add_subplot(1, 1, 1)
        _draw(axes, base, color="0.3")
        axes.set_title("no modes (every coordinate is prescribed)")
    with atomic_writer(path, "path") as temporary:
        figure.savefig(temporary, format="png", dpi=110)
    return Path(path)
