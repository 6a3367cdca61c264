"""The numeric linear model, its state-space form and its export (.npz, MATLAB .mat, python-control).

Second-order form (velocity coordinates), about the operating point ``(q0, u0 = 0, r0)``::

    M du' + C du + K dq = B dr,        dq' = W du + V dq.

State-space form, with the state ``x = (dq, du)`` of length 2n (named after the coordinates and
speeds), the inputs ``dr`` (the control inputs of :mod:`flexkane.kane.inputs`: ``input_effort_<joint>``,
``input_load_<name>_fx`` ...) and the outputs ``dy = y - y0`` (the model's outputs, named as in the
results files, :func:`linear_outputs`)::

    x' = A x + B_ss dr,     A = [[V, W], [-M^-1 K, -M^-1 C]],     B_ss = [[0], [M^-1 B]],
    dy = C_ss x + D_ss dr,  C_ss = C_out + C_acc [-M^-1 K, -M^-1 C],  D_ss = D_out + C_acc M^-1 B,

where ``C_out`` and ``D_out`` are the outputs' derivatives with respect to (dq, du) and dr and
``C_acc`` with respect to du' (outputs with accelerations, such as a driver's effort).

With controller states z (``[controllers]`` with ``states``), the state is ``x = (dq, du, dz)`` of
length 2n + nz, the forcing depends on dz through ``K_z = -df/dz`` and the states' rates are
``dz' = Z_x x + Z_r dr``::

    M du' + C du + K dq + K_z dz = B dr,
    A = [[V, W, 0], [-M^-1 K, -M^-1 C, -M^-1 K_z], Z_x],     B_ss = [[0], [M^-1 B], [Z_r]],

and ``C_out`` has the outputs' derivatives with respect to dz as its last nz columns.

When ``W`` is invertible and ``V = 0`` (every operating point of a chain at rest), ``du = W^-1 dq'``
and premultiplying by ``W^-T`` (which turns generalized forces along the speeds into forces along the
coordinates) give the form in the coordinates alone, with a symmetric mass matrix
(:meth:`LinearModel.second_order`)::

    W^-T M W^-1 dq'' + W^-T C W^-1 dq' + W^-T K dq = W^-T B dr.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import re

import numpy as np
import scipy.linalg

from ..kane.inputs import InputChannel

__all__ = ["LinearModel", "linear_outputs", "load_control"]

_SAFE_NAME = re.compile(r"[^0-9A-Za-z_]")
#: Descriptive text of a MAT-file's header (116 bytes), written instead of scipy's, which ends with the time.
_MAT_HEADER = b"MATLAB 5.0 MAT-file, written by flexkane".ljust(116, b" ")

#: Groups of outputs (:data:`flexkane.model.columns.GROUPS`) that are not outputs of a linear model:
#: energies and power are quadratic (their first-order change at an equilibrium says nothing),
#: momenta are integrals of the motion rather than measurements (and their Jacobians cost as much as
#: the rest of a large model's), the loop constraints' residuals and the dependent speeds of closed
#: loops are not outputs of the reduced linear model.
NONLINEAR_GROUPS = ("energy", "power", "momentum", "angular_momentum", "constraint", "dependent_speed")


def linear_outputs(eom) -> list[str]:
    """Names of the outputs of the linear model of ``eom``: its outputs in their order (positions,
    angles, tip deflections, drivers' efforts ...), but those of the groups :data:`NONLINEAR_GROUPS`
    (energies, power, momenta, the loop constraints and the dependent speeds of closed loops)."""
    return [d.name for d in eom.output_declarations if d.group not in NONLINEAR_GROUPS]


@dataclass
class LinearModel:
    """A chain's equations of motion linearized about an operating point (module docstring).

    Attributes
    ----------
    name : str
        Model name.
    about : str
        ``equilibrium``, ``rest`` or ``spin``.
    spin : float or None
        Spin rate Omega of the hub [rad/s] (``about = "spin"``).
    hub : str or None
        The spun joint.
    t0 : float
        Time of the operating point [s].
    coordinates, speeds : list of str
        Names of dq and du, n of each.
    inputs : list of InputChannel
        The inputs dr, m of them (actuator torques [N m] or forces [N], load components).
    output_names : list of str
        Names of the outputs y, k of them.
    q0 : numpy.ndarray
        Operating point, shape (n,) [m or rad].
    r0 : numpy.ndarray
        Nominal inputs, shape (m,).
    M, C, K : numpy.ndarray
        Mass, damping-and-gyroscopic, stiffness matrices, shape (n, n).
    B : numpy.ndarray
        Input matrix of the second-order form, shape (n, m).
    W, V : numpy.ndarray
        Linearized kinematic equations ``dq' = W du + V dq``, shape (n, n).
    C_out : numpy.ndarray
        Derivatives of the outputs with respect to the state x = (dq, du), shape (k, 2n).
    y0 : numpy.ndarray
        Outputs at the operating point, shape (k,).
    dropped : dict of str to str
        Coordinates left out of the linear model and why (``cyclic``, ``prescribed, frozen``,
        ``dependent (closed loop)``).
    fixed : dict of str to float
        Their values at the operating point [m or rad].
    dependent_map : numpy.ndarray
        ``dq_d = dependent_map dq`` for the dependent coordinates of closed loops (in the order they
        appear in ``dropped``), shape (n_d, n); (0, n) for open chains.
    notes : list of str
        Assumptions and changes, in words.
    residual : float
        Largest generalized acceleration left at the operating point [m/s^2 or rad/s^2].
    C_acc : numpy.ndarray
        Derivatives of the outputs with respect to du', shape (k, n) (zero unless an output has
        accelerations).
    D_out : numpy.ndarray
        Derivatives of the outputs with respect to dr, shape (k, m).
    output_units : dict of str to str
        Unit of each output (``m``, ``rad``, ``N m`` ...).
    controller_states : list of str
        Names of the controller states dz, nz of them (empty without controller states).
    z0 : numpy.ndarray
        The controller states at the operating point, shape (nz,).
    K_z : numpy.ndarray
        ``-df/dz``, shape (n, nz).
    Z_x, Z_r : numpy.ndarray
        Derivatives of the controller states' rates with respect to x = (dq, du, dz) and dr, shapes
        (nz, 2n + nz) and (nz, m).
    """

    name: str
    about: str
    spin: float | None
    hub: str | None
    t0: float
    coordinates: list[str]
    speeds: list[str]
    inputs: list[InputChannel]
    output_names: list[str]
    q0: np.ndarray
    r0: np.ndarray
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    B: np.ndarray
    W: np.ndarray
    V: np.ndarray
    C_out: np.ndarray
    y0: np.ndarray
    dropped: dict = field(default_factory=dict)
    fixed: dict = field(default_factory=dict)
    dependent_map: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    notes: list = field(default_factory=list)
    residual: float = 0.0
    linearization: object = field(default=None, repr=False, compare=False)
    C_acc: np.ndarray | None = None
    D_out: np.ndarray | None = None

    output_units: dict = field(default_factory=dict)
    controller_states: list = field(default_factory=list)
    z0: np.ndarray = field(default_factory=lambda: np.zeros(0))
    K_z: np.ndarray | None = None
    Z_x: np.ndarray | None = None
    Z_r: np.ndarray | None = None

    # ------------------------------------------------------------------ sizes and names
    @property
    def n(self) -> int:
        """Number of degrees of freedom of the linear model."""
        return len(self.coordinates)

    @property
    def input_names(self) -> list[str]:
        return [ch.name for ch in self.inputs]

    @property
    def nz(self) -> int:
        """Number of controller states."""
        return len(self.controller_states)

    @property
    def state_names(self) -> list[str]:
        """Names of the state x = (dq, du, dz)."""
        return list(self.coordinates) + list(self.speeds) + list(self.controller_states)

    # ------------------------------------------------------------------ forms
    def state_space(self) -> tuple[np.ndarray, np.ndarray]:
        """``(A, B_ss)`` of ``x' = A x + B_ss dr``, shapes (2n + nz, 2n + nz) and (2n + nz, m)."""
        n, m, nz = self.n, self.B.shape[1], self.nz
        if n == 0 and nz == 0:
            return np.zeros((0, 0)), np.zeros((0, m))
        if n == 0:
            return np.array(self.Z_x, dtype=float).reshape(nz, nz), np.array(self.Z_r, dtype=float).reshape(nz, m)
        lu = scipy.linalg.lu_factor(self.M)
        A = np.block([[self.V, self.W],
                      [-scipy.linalg.lu_solve(lu, self.K), -scipy.linalg.lu_solve(lu, self.C)]])
        Bss = np.vstack([np.zeros((n, m)), scipy.linalg.lu_solve(lu, self.B) if m else np.zeros((n, 0))])
        if nz:
            coupling = np.vstack([np.zeros((n, nz)), -scipy.linalg.lu_solve(lu, self.K_z)])
            A = np.vstack([np.hstack([A, coupling]), self.Z_x])
            Bss = np.vstack([Bss, np.array(self.Z_r, dtype=float).reshape(nz, m)])
        return A, Bss

    def output_matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """``(C_ss, D_ss)`` of ``y - y0 = C_ss x + D_ss dr``, shapes (k, 2n) and (k, m) (module docstring)."""
        k, n, m = len(self.output_names), self.n, self.B.shape[1]
        C = self.C_out.copy()
        D = np.zeros((k, m)) if self.D_out is None else np.array(self.D_out, dtype=float).reshape(k, m)
        if self.C_acc is not None and n and np.any(self.C_acc != 0):
            A, Bss = self.state_space()
            C = C + self.C_acc @ A[n:2 * n]
            D = D + self.C_acc @ Bss[n:2 * n]
        return C, D

    def to_control(self):
        """The state-space model as a python-control ``StateSpace`` with named states, inputs and outputs.

        Returns
        -------
        control.StateSpace
            ``(A, B_ss, C_ss, D_ss)`` (continuous time) with ``states=state_names``,
            ``inputs=input_names`` and ``outputs=output_names``; ``name`` is the model's name.

        Raises
        ------
        flexkane.extras.MissingExtraError
            If python-control is not installed (``pip install 'flexkane[control]'``).
        """
        from ..extras import require

        control = require("control")
        A, B = self.state_space()
        C, D = self.output_matrices()
        return control.ss(A, B, C, D, states=self.state_names, inputs=self.input_names,
                          outputs=list(self.output_names), name=_SAFE_NAME.sub("_", self.name) or "model")

    def second_order(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(M_q, C_q, K_q, B_q)`` of ``M_q dq'' + C_q dq' + K_q dq = B_q dr`` (module docstring).

        Returns
        -------
        tuple of numpy.ndarray
            Shapes (n, n), (n, n), (n, n), (n, m); ``M_q`` is symmetric.

        Raises
        ------
        ValueError
            If ``V`` is not zero (the form needs ``du = W^-1 dq'``) or the model has controller
            states (their first-order equations are not part of this form: use :meth:`state_space`).
        """
        if self.nz:
            raise ValueError("the coordinate form has no controller states: use state_space()")
        if np.any(self.V != 0):
            raise ValueError("the coordinate form needs V = 0 (dq' = W du)")
        if self.n == 0:
            return self.M.copy(), self.C.copy(), self.K.copy(), self.B.copy()
        Winv = np.linalg.inv(self.W)
        return Winv.T @ self.M @ Winv, Winv.T @ self.C @ Winv, Winv.T @ self.K, Winv.T @ self.B

    # ------------------------------------------------------------------ export
    def arrays(self) -> dict:
        """Every matrix and name, as the arrays written by :meth:`save_npz` and :meth:`save_mat`.

        Keys: ``M, C, K, B, W, V`` (second-order form), ``A, B_ss, C_ss, D_ss`` (state space),
        ``q0, r0, y0``, ``spin`` (NaN unless about a spin), ``t0``, and the names ``state_names``,
        ``coordinates``, ``speeds``, ``input_names``, ``input_units``, ``output_names``,
        ``output_units``, ``about``, ``name``; with controller states also ``K_z, Z_x, Z_r``, ``z0``
        and their names ``controller_states``.
        """
        A, Bss = self.state_space()
        Css, Dss = self.output_matrices()
        return {
            "M": self.M, "C": self.C, "K": self.K, "B": self.B, "W": self.W, "V": self.V,
            "A": A, "B_ss": Bss, "C_ss": Css, "D_ss": Dss,
            "q0": self.q0, "r0": self.r0, "y0": self.y0,
            "spin": np.array(np.nan if self.spin is None else self.spin), "t0": np.array(self.t0),
            "state_names": self.state_names, "coordinates": list(self.coordinates),
            "speeds": list(self.speeds), "input_names": self.input_names,
            "input_units": [ch.unit for ch in self.inputs], "output_names": list(self.output_names),
            "output_units": [self.output_units.get(k, "") for k in self.output_names],
            "about": self.about, "name": self.name,
        } | ({"K_z": self.K_z, "Z_x": self.Z_x, "Z_r": self.Z_r, "z0": self.z0,
              "controller_states": list(self.controller_states)} if self.nz else {})

    def save_npz(self, path) -> None:
        """Write :meth:`arrays` to a NumPy ``.npz`` file (names as Unicode arrays, no pickles)."""
        from ..atomic import atomic_writer

        data = {k: (np.array(v, dtype=str) if isinstance(v, (list, str)) else np.asarray(v, dtype=float))
                for k, v in self.arrays().items()}
        with atomic_writer(path, "path") as temporary:
            np.savez(temporary, **data)

    def save_mat(self, path) -> None:
        """Write :meth:`arrays` to a MATLAB ``.mat`` file (``scipy.io.savemat``; names as cell arrays;
        the 116 bytes of the header's text without the date, :data:`_MAT_HEADER`)."""
        import scipy.io

        from ..atomic import atomic_writer

        data = {}
        for k, v in self.arrays().items():
            if isinstance(v, list):
                cell = np.empty((len(v),), dtype=object)
                cell[:] = v
                data[k] = cell
            elif isinstance(v, str):
                data[k] = v
            else:
                data[k] = np.asarray(v, dtype=float)
        A, B, C, D = data["A"], data["B_ss"], data["C_ss"], data["D_ss"]
        # the state space as one struct: sys = ss(s.statespace.A, s.statespace.B, ..., 'StateName', ...)
        data["statespace"] = {"A": A, "B": B, "C": C, "D": D, "StateName": data["state_names"],
                              "InputName": data["input_names"], "OutputName": data["output_names"]}
        with atomic_writer(path, "path") as temporary:
            scipy.io.savemat(temporary, data, oned_as="column")
            with open(temporary, "r+b") as handle:     # the header's text without the time of writing:
                handle.write(_MAT_HEADER)               # the same model gives the same bytes

    def save_control(self, path) -> None:
        """Write the state space as python-control builds it, to a NumPy ``.npz`` file without pickles.

        Keys: ``A, B, C, D`` (:meth:`state_space`, :meth:`output_matrices`), ``states``, ``inputs``,
        ``outputs`` (names, Unicode arrays), ``name``, ``dt`` (0: continuous time), and ``x0``
        (the operating point's state), ``r0``, ``y0`` (nominal inputs and outputs), ``input_units``,
        ``output_units``. :func:`load_control` reads it back as a ``control.StateSpace``; without
        flexkane: ``control.ss(d["A"], d["B"], d["C"], d["D"], states=list(d["states"]),
        inputs=list(d["inputs"]), outputs=list(d["outputs"]))`` with ``d = numpy.load(path)``.
        """
        from ..atomic import atomic_writer

        A, B = self.state_space()
        C, D = self.output_matrices()
        names = lambda v: np.array(list(v), dtype=str).reshape(len(v))  # noqa: E731
        data = {"A": A, "B": B, "C": C, "D": D, "states": names(self.state_names),
                "inputs": names(self.input_names), "outputs": names(self.output_names),
                "name": np.array(self.name), "dt": np.array(0.0),
                "x0": np.concatenate([self.q0, np.zeros(self.n), self.z0]), "r0": np.asarray(self.r0, dtype=float),
                "y0": np.asarray(self.y0, dtype=float), "input_units": names([ch.unit for ch in self.inputs]),
                "output_units": names([self.output_units.get(k, "") for k in self.output_names])}
        with atomic_writer(path, "path") as temporary:
            np.savez(temporary, **data)


def load_control(path):
    """Read a file of :meth:`LinearModel.save_control` as a python-control ``StateSpace``.

    Parameters
    ----------
    path : path-like
        The ``.npz`` file (``flexkane linearize MODEL --export control`` writes ``statespace.npz``).

    Returns
    -------
    control.StateSpace
        With the names of its states, inputs and outputs.
    """
    from ..errors import ModelError
    from ..extras import require

    control = require("control")
    try:
        with np.load(path, allow_pickle=False) as d:
            parts = {k: d[k] for k in ("A", "B", "C", "D", "states", "inputs", "outputs", "name", "dt")}
    except (OSError, ValueError, KeyError) as exc:
        raise ModelError(str(path), "a state-space file written by flexkane linearize --export control",
                         f"{type(exc).__name__}: {exc}") from None
    return control.ss(parts["A"], parts["B"], parts["C"], parts["D"], float(parts["dt"]),
                      states=[str(s) for s in parts["states"]], inputs=[str(s) for s in parts["inputs"]],
                      outputs=[str(s) for s in parts["outputs"]], name=str(parts["name"]) or None)
