"""Warnings where a run leaves the validity of its model.

Two assumptions of the chapter's formulation can fail silently during a run:

* **small deflections.** The assumed modes (eq. 8.15) and the linear strain energy (eq. 8.32)
  describe a beam whose deflection is small against its length; a run warns when the largest
  transverse deflection of a beam, ``max_x,t |sum_i Phi_i(x/L) q_i(t)|`` (in space the length of
  the deflection vector ``(v, w)`` along the section's principal axes, each summed over the modes of
  its bending plane), exceeds ``simulation.deflection_warning`` (default 10 %) of its length.
* **slow spin without geometric stiffening.** Without the foreshortening of the beam axis
  (``geometric_stiffening = true``) the linear modes miss the centrifugal stiffening of a spinning
  beam; the error grows like the square of the spin over the first bending frequency (Kane, Ryan and
  Banerjee 1987; at 11 % of it the chapter's beam is off by 9 % of its tip deflection). A run warns
  when the angular velocity of a beam's root frame about the axes normal to the beam (planar: about
  z; in space: ``sqrt(w_y^2 + w_z^2)`` in the root frame's axes, a spin about the beam's own axis
  stretches nothing) exceeds ``simulation.spin_warning`` (default 10 %) of the beam's first bending
  frequency (in space the lower of its two bending planes').

Both checks read the bending planes of a beam from one table, :data:`BENDING_PLANES` (one plane in
the plane, two in space), so planar and spatial beams are checked by the same code.

And one of the integration: the Euler parameters of a spherical or free joint keep unit norm only to
the solver's tolerance (their kinematic equations preserve it exactly); a run warns when
``|e0^2 + e1^2 + e2^2 + e3^2 - 1|`` exceeds :data:`QUATERNION_NORM_WARNING`.

The first bending frequency is that of the beam's shape family on its own boundary conditions
(eq. 8.7, with the tip body of ``clamped-free-tip-mass``), or, for families without eigenvalues,
the lowest Rayleigh-Ritz frequency ``sqrt(eig(H, G))`` of its modal constants (eqs. 8.22, 8.32).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["BENDING_PLANES", "QUATERNION_NORM_WARNING", "beam_checks", "first_bending_frequency", "run_warnings", "spin_expressions",
           "validity_warnings"]

#: Largest departure of a joint's Euler parameters from unit norm before a run warns [-].
QUATERNION_NORM_WARNING = 1e-6
#: Stations per beam at which the deflection is sampled, as fractions of its length.
_STATIONS = np.linspace(0.0, 1.0, 41)
#: The bending planes of a beam by the chain's dimensions: (coordinate role, shape field, rigidity
#: field). A spatial beam's deflection along y_p (``shape_y``) bends it about z_p (``EI_z``).
BENDING_PLANES = {2: (("mode", "shape", "EI"),),
                  3: (("mode_y", "shape_y", "EI_z"), ("mode_z", "shape_z", "EI_y"))}


def first_bending_frequency(family, n: int, L: float, EI: float, rho: float) -> float:
    """First bending frequency of a beam [rad/s].

    Parameters
    ----------
    family : ShapeFamily
        The beam's transverse shape functions.
    n : int
        Number of shape functions used.
    L, EI, rho : float
        Length [m], flexural rigidity [N m^2], mass per unit length [kg/m].
    """
    frequencies = family.frequencies(1, L, EI, rho)
    if frequencies is not None:
        return float(frequencies[0])
    from .kane.beam_quadrature import AtomEvaluator

    ev = AtomEvaluator(L=L, family=family, n=n)
    atoms = [("phi", i + 1) for i in range(n)]
    H = np.array([[EI * ev.derivative_integral(a, b, 2) for b in atoms] for a in atoms])
    G = np.array([[rho * ev.integral(a, b) for b in atoms] for a in atoms])
    from scipy.linalg import eigh

    return float(math.sqrt(max(eigh(H, G, eigvals_only=True)[0], 0.0)))


def spin_expressions(eom) -> dict:
    """Angular velocity [rad/s] of the root frame of every beam checked for its spin.

    Parameters
    ----------
    eom : EquationsOfMotion

    Returns
    -------
    dict of str to sympy.Expr
        Beam name to the angular velocity of its root frame as an expression of ``t``, ``q``, ``u``
        and the constants (driven and dependent speeds written in terms of the state), for every
        beam with modes, without ``geometric_stiffening``, whose root frame turns. The run
        evaluates them with its outputs, in compiled code (:mod:`flexkane.simulation`).
    """
    import sympy as sp

    out = {}
    known = {eom.t, *eom.q, *eom.u, *eom.constants, *(s for s, _ in getattr(eom, "intermediates", ()))}
    roles = [role for role, _, _ in BENDING_PLANES[eom.chain.dimensions]]
    for name, beam in eom.model.beams.items():
        if beam.geometric_stiffening or not any(eom.chain.of(name, role) for role in roles):
            continue
        omega = _transverse_spin(eom.kinematics.beams[name].frame.omega)
        omega = omega.xreplace(eom.substitutions or {}).xreplace(eom.dependent_speeds)
        if omega != 0 and omega.free_symbols <= known:
            out[name] = omega
    return out


def _transverse_spin(omega):
    """The angular velocity of a beam's root frame about the axes normal to the beam's axis x
    [rad/s]: planar frames turn about z only (``omega`` is that scalar); a spatial frame's
    ``(w_x, w_y, w_z)`` along its own axes gives ``sqrt(w_y^2 + w_z^2)``."""
    import sympy as sp

    if isinstance(omega, (tuple, list)):
        transverse = [sp.sympify(c) for c in omega[1:]]
        nonzero = [c for c in transverse if c != 0]
        if len(nonzero) == 1:
            return nonzero[0]
        return sp.sqrt(sp.Add(*[c ** 2 for c in transverse]))
    return sp.sympify(omega)


def beam_checks(eom, model, spins) -> list[dict]:
    """The numbers the validity checks of a run need, one entry per beam with modes (and one per
    spherical or free joint, ``{"euler": joint, "indices": state indices of e0 .. e3}``).

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model
        The model that gives the numbers of the run.
    spins : collection of str
        The beams whose spin is checked (the keys of :func:`spin_expressions`).

    Returns
    -------
    list of dict
        JSON-able entries ``{"beam", "L" [m], "planes", "p1" [rad/s] or None}``, ``planes`` one
        ``{"modes" (state indices), "phi" (modes x stations, the shape functions at
        :data:`_STATIONS` of the length)}`` per bending plane with modes (:data:`BENDING_PLANES`);
        ``p1``, the lowest first bending frequency of the planes, only for the beams in ``spins``.
    """
    from .model.field_values import FieldValues
    from .modes.from_spec import beam_shape_family

    names = eom.state_names
    fields = FieldValues(model)
    params = fields.parameters
    checks = []
    for name, beam in model.beams.items():
        path = f"beams.{name}"
        planes, frequencies = [], []
        for role, shape_key, rigidity_key in BENDING_PLANES[eom.chain.dimensions]:
            modes = [c.q.name for c in eom.chain.of(name, role)]
            if not modes:
                continue
            family = beam_shape_family(model, beam, shape_key, params)
            planes.append({"modes": [names.index(m) for m in modes],
                           "phi": np.asarray(family.phi(_STATIONS, len(modes)), dtype=float).tolist()})
            if name in spins:
                L, EI, rho = (fields.value(beam.L, f"{path}.L"), fields.value(getattr(beam, rigidity_key),
                              f"{path}.{rigidity_key}"), fields.value(beam.rho, f"{path}.rho"))
                frequencies.append(first_bending_frequency(family, len(modes), L, EI, rho))
        if planes:
            checks.append({"beam": name, "L": fields.value(beam.L, f"{path}.L"), "planes": planes,
                           "p1": min(frequencies) if frequencies else None})
    for joint in eom.chain.joints:
        euler = [c.q.name for c in eom.chain.of(joint.name) if c.role in ("e0", "e1", "e2", "e3")]
        if euler:
            checks.append({"euler": joint.name, "indices": [names.index(e) for e in euler]})
    return checks


def run_warnings(checks: list[dict], simulation, t: np.ndarray, state: np.ndarray, spins: dict) -> list[str]:
    """Warnings of a run whose model left its range of validity (module docstring).

    Parameters
    ----------
    checks : list of dict
        :func:`beam_checks` of the run's model.
    simulation : Simulation
        The model's run settings (``deflection_warning``, ``spin_warning``).
    t : ndarray, shape (N,)
        Output times [s].
    state : ndarray, shape (N, n)
        Coordinates then speeds at the output times.
    spins : dict of str to ndarray, shape (N,)
        Angular velocity [rad/s] of the root frame of each beam of :func:`spin_expressions`.

    Returns
    -------
    list of str
        One sentence per warning, naming the beam, the measured value and the limit.
    """
    if len(t) == 0:
        return []
    warnings = []
    for check in checks:
        if "euler" in check:
            with np.errstate(all="ignore"):
                drift = np.abs(np.sum(state[:, check["indices"]] ** 2, axis=1) - 1.0)
            over = np.flatnonzero(~(drift <= QUATERNION_NORM_WARNING))
            if over.size:
                warnings.append(
                    f"joint {check['euler']!r}: the norm of its Euler parameters departed from 1 by "
                    f"{float(np.nanmax(np.where(np.isfinite(drift), drift, np.inf))):.3g} (first at t = "
                    f"{t[over[0]]:.4g} s), more than {QUATERNION_NORM_WARNING:g}: the orientation is no longer "
                    "accurate; tighten rtol and atol")
            continue
        name, L = check["beam"], check["L"]
        with np.errstate(all="ignore"):   # the deflection vector's length over the bending planes
            y = np.sqrt(sum((state[:, plane["modes"]] @ np.array(plane["phi"], dtype=float)) ** 2
                            for plane in check["planes"]))                         # (N, stations)
        peak = np.max(np.where(np.isfinite(y), y, np.inf), axis=1)                # (N,)
        over = np.flatnonzero(peak > simulation.deflection_warning * L)
        if over.size:
            worst = float(np.max(peak))
            warnings.append(
                f"beam {name!r}: its deflection reached {worst:.3g} m, more than {simulation.deflection_warning:.3g} "
                f"of its length L = {L:.3g} m (first at t = {t[over[0]]:.4g} s): the small-deflection assumption "
                "of the assumed modes no longer holds, and the results from there on are not physical "
                "(simulation.deflection_warning sets this limit)")
        if name not in spins or check["p1"] is None:
            continue
        with np.errstate(all="ignore"):
            spin = np.abs(np.broadcast_to(np.asarray(spins[name], dtype=float), t.shape))
        p1 = check["p1"]
        fast = np.flatnonzero(spin > simulation.spin_warning * p1)
        if fast.size:
            top = float(np.nanmax(np.where(np.isfinite(spin), spin, np.inf)))
            warnings.append(
                f"beam {name!r}: it spins at up to {top:.3g} rad/s, more than {simulation.spin_warning:.3g} of its "
                f"first bending frequency p1 = {p1:.3g} rad/s (first at t = {t[fast[0]]:.4g} s), without "
                f"geometric_stiffening: the linear modes miss the centrifugal stiffening; set "
                f"geometric_stiffening = true in [beams.{name}] (simulation.spin_warning sets this limit)")
    return warnings


def validity_warnings(eom, model, t: np.ndarray, state: np.ndarray, values: dict) -> list[str]:
    """Warnings of a run from its equations: :func:`run_warnings` with the spins evaluated here.

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model
        The model that gave the numbers of the run.
    t : ndarray, shape (N,)
        Output times [s].
    state : ndarray, shape (N, n)
        Coordinates then speeds at the output times.
    values : dict of sympy.Symbol to float
        Values of the constants (``eom.constant_values(model)``).

    Returns
    -------
    list of str
    """
    import sympy as sp

    if len(t) == 0:
        return []
    expressions = spin_expressions(eom)
    args = [eom.t] + list(eom.q) + list(eom.u)
    spins = {}
    for name, omega in expressions.items():
        rate = sp.lambdify(args, eom.expand(omega).xreplace(values), modules="numpy")
        with np.errstate(all="ignore"):
            spins[name] = np.asarray(rate(t, *state.T), dtype=float)
    return run_warnings(beam_checks(eom, model, expressions), model.simulation, t, state, spins)
