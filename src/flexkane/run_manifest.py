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

from .model.columns import Output

__all__ = ["MANIFEST_FORMAT", "NUMBER_FIELDS", "RUN_OUTPUTS", "manifest_of", "numbers_of", "units"]

#: Layout of the stored manifests and numbers (a change invalidates the stored files).
MANIFEST_FORMAT = 2

#: The outputs a run adds to those of its equations (:func:`flexkane.simulate`), declared.
RUN_OUTPUTS = (Output("work", None, "J", "energy", "the work of the non-conservative forces"),
               Output("energy_balance", None, "J", "energy", "the energy balance E - E0 - work"))

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
        order of p), ``units`` (column name to unit, :func:`units`), ``outputs`` (the declaration of
        every output, :meth:`flexkane.model.columns.Output.to_json`) and ``spins``
        (beams whose spin is checked, :func:`flexkane.validity.spin_expressions`).
    """
    from .validity import spin_expressions

    return {"format": MANIFEST_FORMAT,
            "coordinates": [c.q.name for c in eom.chain.coordinates],
            "state_names": list(eom.state_names), "nq": len(eom.q),
            "constant_names": [s.name for s in eom.constants],
            "units": units(eom), "outputs": [o.to_json() for o in eom.output_declarations],
            "spins": list(spin_expressions(eom))}


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


def units(eom) -> dict[str, str]:
    """Unit of every state variable and output, by name: the coordinates' and speeds' by their roles,
    the controller states' where the model fixes them (:func:`flexkane.model.signal_units.controller_units`),
    the outputs' as declared where they are made (:attr:`EquationsOfMotion.output_declarations`; a
    controller's output only where the model fixes it), and ``work`` and ``energy_balance`` of a run [J]."""
    from .model.coordinates import coordinate_unit, speed_unit
    from .model.signal_units import controller_units, sensor_unit

    out = {}
    for c in eom.chain.coordinates:
        out[c.q.name] = coordinate_unit(c.role)
        if c.u is not None:
            out[c.u.name] = speed_unit(c.role)
    known = dict(out)
    out.update((o.name, o.unit) for o in eom.output_declarations if o.unit is not None)
    out.update((o.name, o.unit) for o in RUN_OUTPUTS)
    if any(ctrl.states for ctrl in eom.model.controllers.values()):
        known.update((name, sensor_unit(eom.model, name)) for name in eom.model.sensors)
        states = {state for ctrl in eom.model.controllers.values() for state in ctrl.states}
        out.update((name, unit) for name, unit in controller_units(eom.model, known).items() if name in states)
    return out
