"""What a run needs of its equations, as names and numbers: the run manifest.

A run integrates the compiled module of its equations and evaluates its outputs there
(:mod:`flexkane.simulation`); around that it needs only names and numbers. They are computed from
the symbolic :class:`~flexkane.kane.EquationsOfMotion` once and stored by
:mod:`flexkane.derivation_cache` beside them, so that a run whose equations are cached loads
neither them nor SymPy:

* the manifest of the structure (:func:`manifest_of`): the names of the chain's coordinates, of
  the state and of the constants vector p, the unit of every column (for the plots) and the beams
  whose spin is checked;
* the numbers of one model of that structure (:func:`numbers_of`): the constants vector p, the
  initial state and the numbers of the validity checks (:func:`flexkane.validity.beam_checks`).

The printed equations of the structure (:func:`flexkane.report.printed_structure`) are stored beside
the manifest too; ``equations.md`` and ``equations.tex`` of a model are assembled from them and its p
(:mod:`flexkane.equations_document`).

Everything here is plain JSON data (lists, dicts, str, float): loading it imports nothing.
"""

from __future__ import annotations

import contextlib

__all__ = ["MANIFEST_FORMAT", "NUMBER_FIELDS", "manifest_of", "numbers_of", "units"]

#: Layout of the stored manifests and numbers (a change invalidates the stored files).
MANIFEST_FORMAT = 1

#: The fields of the numbers of a model, each computed on demand by :func:`numbers_of`.
NUMBER_FIELDS = ("p", "y0", "checks")


def manifest_of(eom) -> dict:
    """The manifest of a structure, from its equations.

    Parameters
    ----------
    eom : EquationsOfMotion

    Returns
    -------
    dict
        ``coordinates`` (names of every coordinate of the chain, driven ones too, in state order),
        ``state_names`` (coordinates then speeds of the state), ``nq``, ``constant_names`` (the
        order of p), ``units`` (column name to unit, :func:`units`) and ``spins``
        (beams whose spin is checked, :func:`flexkane.validity.spin_expressions`).
    """
    from .validity import spin_expressions

    return {"format": MANIFEST_FORMAT,
            "coordinates": [c.q.name for c in eom.chain.coordinates],
            "state_names": list(eom.state_names), "nq": len(eom.q),
            "constant_names": [s.name for s in eom.constants],
            "units": units(eom), "spins": list(spin_expressions(eom))}


def numbers_of(eom, model, fields, spins) -> dict:
    """Numbers of ``model`` for a run of the equations ``eom`` of its structure.

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model
        A model of the structure of ``eom`` (its numbers may differ from those of ``eom.model``).
    fields : collection of str
        Which of :data:`NUMBER_FIELDS` to compute.
    spins : list of str
        The beams whose spin is checked (the manifest's ``spins``).

    Returns
    -------
    dict
        ``p`` (list of float, the constants vector), ``y0`` (list of float, the initial state
        from the model's ``[initial]`` table, loop constraints closed), ``checks``
        (:func:`flexkane.validity.beam_checks`), as asked.

    Raises
    ------
    ModelError
        For numbers the model cannot give (a non-finite modal constant, an unclosable loop ...).
    """
    out = {}
    values = eom.constant_values(model)
    if "p" in fields:
        out["p"] = [float(values[s]) for s in eom.constants]
    if "y0" in fields:
        out["y0"] = [float(v) for v in eom.initial_state(model)]
    if "checks" in fields:
        from .validity import beam_checks

        out["checks"] = beam_checks(eom, model, spins)
    return out


def _sensor_unit(eom, name: str) -> str:
    """Unit of a sensor (:data:`flexkane.model.signals.SENSOR_UNITS`; m and m/s on a prismatic joint)."""
    from .model.signals import SENSOR_UNITS

    sensor = eom.model.sensors[name]
    if sensor.type in ("joint_angle", "joint_rate") and eom.model.joints[sensor.joint].type == "prismatic":
        return "m" if sensor.type == "joint_angle" else "m/s"
    return SENSOR_UNITS[sensor.type]


def _controller_units(eom, known: dict) -> dict[str, str]:
    """Units of the controller states and outputs (by name), where the model fixes them.

    A controller state has the unit of its rate times s, an output the unit of its expression and
    of the efforts it feeds (:func:`flexkane.model.parameter_units.inferred_units`,
    from the units of the coordinates, speeds and sensors in ``known``): the integral of an angle
    error [rad] is in rad s. A state or output whose unit no expression fixes is left out.
    """
    from .expression_syntax import NeedsSymbolic, expression_names
    from .model.parameter_units import field_values, inferred_units
    from .model.signals import effort_fields

    model = eom.model
    equal, names = [], set(model.parameters)
    for ctrl in model.controllers.values():
        names.update(ctrl.states)
        equal += [(state, rate, True) for state, rate in ctrl.states.items()]
        if ctrl.output is not None:
            names.add(ctrl.name)
            equal.append((ctrl.name, ctrl.output, False))   # not its bounds: numbers of one model, not structure
    if not equal:
        return {}
    # the efforts that use signals: their texts are structure, as are the controllers' (a manifest
    # serves every model of a structure, so no number of one model may decide a unit)
    efforts = set()
    for path, value in effort_fields(model):
        with contextlib.suppress(NeedsSymbolic):
            if isinstance(value, str) and expression_names(value) - set(model.parameters) - {"t"}:
                efforts.add(path)
    fields = {path: field for path, field in field_values(model).items() if path in efforts}
    found = inferred_units(fields, names, known=known, equal=equal)
    out = {}
    for ctrl in model.controllers.values():
        out.update({state: found[state] for state in ctrl.states if state in found})
        if ctrl.output is not None and ctrl.name in found:
            out[f"controller_{ctrl.name}"] = found[ctrl.name]
    return out


def units(eom) -> dict[str, str]:
    """Unit of every state variable and output, by name (a controller's state or output only where
    the model fixes it, :func:`_controller_units`)."""
    from .model.coordinates import coordinate_unit, speed_unit

    out = {}
    for c in eom.chain.coordinates:
        out[c.q.name] = coordinate_unit(c.role)
        if c.u is not None:
            out[c.u.name] = speed_unit(c.role)
    for name in eom.output_names:
        if name.startswith(("x_", "y_", "z_", "tip_")):
            out[name] = "m"
        elif name.startswith(("theta_", "yaw_", "pitch_", "roll_", "twist_", "slope_")):
            out[name] = "rad"
        elif name.startswith(("e0_", "e1_", "e2_", "e3_", "quaternion_norm_")):
            out[name] = "-"
        elif name in ("H_x", "H_y", "H_z"):
            out[name] = "kg m^2/s"
        elif name in ("kinetic", "potential_gravity", "strain", "potential_springs", "energy"):
            out[name] = "J"
        elif name.startswith("effort_"):
            joint = name[len("effort_"):]
            role = eom.chain.of(joint)[0].role
            out[name] = "N m" if role == "angle" else "N"
        elif name == "power_nonconservative":
            out[name] = "W"
        elif name.startswith("load_"):
            out[name] = "N m" if name.endswith(("_torque", "_tx", "_ty", "_tz")) else "N"   # 3D: _tx .. _tz
        elif name.startswith("sensor_"):
            out[name] = _sensor_unit(eom, name[len("sensor_"):])
        elif name in ("p_x", "p_y", "p_z"):
            out[name] = "kg m/s"
        elif name in ("h_o", "h_cm"):
            out[name] = "kg m^2/s"
    out["work"] = out["energy_balance"] = "J"
    if eom.model.controllers:
        known = {name: unit for name, unit in out.items() if not name.startswith("sensor_")}
        known.update({name[len("sensor_"):]: unit for name, unit in out.items() if name.startswith("sensor_")})
        out.update(_controller_units(eom, known))
    return out
