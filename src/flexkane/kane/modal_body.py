"""A beam as a modal body: its invariants as arrays, and the modal constants read from them.

:mod:`flexkane.modes.invariants` computes a beam's invariants (``m_B, e_B, I_B, E_i, F_i, G_ij,
H_ij`` and their spatial, Rayleigh, torsion, axial and stiffening counterparts) as numeric arrays from
any shape functions. Here a beam of a model gets its :class:`~flexkane.modes.invariants.ModalInvariants`
(:func:`spatial_invariants`, :func:`planar_invariants`), and each modal constant a derivation uses (a
symbol of :class:`~flexkane.kane.beam_constants.BeamConstants` with its specification) is an entry
of one of those arrays (:func:`constant_value`): the atoms of :mod:`flexkane.kane.modal_field` map to
groups of functions and their 1-based indices to the arrays' 0-based ones.
"""

from __future__ import annotations

from ..modes.invariants import ModalInvariants, ShapeBasis, modal_invariants
from .modal_field import Atom, direction

__all__ = ["spatial_invariants", "planar_invariants", "constant_value", "atom_group"]


def atom_group(atom: Atom) -> tuple[tuple, tuple]:
    """The group of functions of an atom (:meth:`ModalInvariants.integral`) and its 0-based index
    in the group (``()`` for ``1`` and ``x``; ``(i, j)`` for a foreshortening atom)."""
    kind = atom[0]
    if kind in ("1", "x"):
        return (kind,), ()
    if kind in ("phi", "dphi"):
        return (kind, direction(atom) or ""), (atom[1] - 1,)
    if kind == "d":
        return ("d", direction(atom) or ""), (atom[1] - 1, atom[2] - 1)
    if kind in ("theta", "psi"):
        return (kind,), (atom[1] - 1,)
    raise ValueError(f"unknown atom {atom!r}")


def _entry(inv: ModalInvariants, weight: str, atoms, deriv: int = 0) -> float:
    groups, index = [], ()
    for atom in atoms:
        group, at = atom_group(atom)
        groups.append(group)
        index += at
    return float(inv.integral(weight, *groups, deriv=deriv)[index])


def constant_value(inv: ModalInvariants, spec: tuple) -> float | None:
    """Value of the modal constant of specification ``spec`` (as recorded in ``BeamConstants.used``)
    from the beam's invariants, or None for the kinds that are no invariant of the beam (values at a
    station, integrals of a load's profile, the notebook's shear-moment constants).

    Parameters
    ----------
    inv : ModalInvariants
        The beam's invariants, with the section properties the constant needs.
    spec : tuple
        ``("pair", a, b)`` (weight rho), ``("polar", a, b)`` (rho_Ip), ``("section", axis, a, b)``
        (rho_I of the direction ``axis``), ``("rotary", a, b)`` (planar Rayleigh, rho_I),
        ``("H", i, j)`` / ``("Hs", label, i, j)`` (EI), ``("Kt", k, l)`` (GJ), ``("HA", k, l)`` (EA).

    Returns
    -------
    float or None
    """
    kind = spec[0]
    if kind == "pair":
        return _entry(inv, "rho", spec[1:3])
    if kind == "polar":
        return _entry(inv, "rho_Ip", spec[1:3])
    if kind == "section":
        if spec[1] == "t":
            return _entry(inv, "rho_Ip", spec[2:4])
        return _entry(inv, f"rho_I:{spec[1]}", spec[2:4])
    if kind == "rotary":
        return _entry(inv, "rho_I:", spec[1:3])
    if kind == "H":
        return _entry(inv, "EI:", (("phi", spec[1]), ("phi", spec[2])), 2)
    if kind == "Hs":
        label = spec[1]
        return _entry(inv, f"EI:{label}", (("phi", spec[2], label), ("phi", spec[3], label)), 2)
    if kind == "Kt":
        return _entry(inv, "GJ", (("theta", spec[1]), ("theta", spec[2])), 1)
    if kind == "HA":
        return _entry(inv, "EA", (("psi", spec[1]), ("psi", spec[2])), 1)
    return None


def spatial_invariants(beam, fields, parameters, model=None) -> ModalInvariants:
    """The invariants of a spatial beam of a model, with its uniform sections.

    Parameters
    ----------
    beam : flexkane.model.parts.Beam
        A spatial beam.
    fields : flexkane.model.field_values.FieldValues
        Values of the model's fields.
    parameters : dict
        The model's parameter values (numeric options of the shape families).
    model : flexkane.model.model.Model, optional
        The beam's model: with it, the bases get their static correction shapes where the beam
        carries something at its tip (:func:`flexkane.modes.from_spec.beam_shape_family`).

    Returns
    -------
    ModalInvariants
        Bending families ``y`` (deflection along y_p, ``"EI:y"`` = EI_z, ``"rho_I:y"`` = rho_Iz) and
        ``z`` (``EI_y``, ``rho_Iy``), torsion, axial; the section properties the beam gives.
    """
    from ..modes.from_spec import beam_shape_family, shape_family

    path = f"beams.{beam.name}"

    def basis(key: str, count: int) -> ShapeBasis | None:
        if not count:
            return None
        family = beam_shape_family(model, beam, key, parameters) if model is not None \
            else shape_family(getattr(beam, key), f"{path}.{key}", parameters)
        return ShapeBasis.of_family(family, count)

    bending = {label: basis(key, count) for label, key, count in
               (("y", "shape_y", beam.n_modes_y), ("z", "shape_z", beam.n_modes_z)) if count}
    sections = {}
    for name, key in (("rho", "rho"), ("EI:y", "EI_z"), ("EI:z", "EI_y"), ("rho_I:y", "rho_Iz"),
                      ("rho_I:z", "rho_Iy"), ("rho_Ip", "rho_Ip"), ("GJ", "GJ"), ("EA", "EA")):
        value = getattr(beam, key, None)
        if value is not None:
            sections[name] = fields.value(value, f"{path}.{key}")
    return modal_invariants(fields.value(beam.L, f"{path}.L"), bending,
                            torsion=basis("torsion_shape", beam.n_torsion),
                            axial=basis("axial_shape", beam.n_axial), **sections)


def planar_invariants(beam, fields, parameters) -> ModalInvariants:
    """The invariants of a planar beam of a model (bending family labelled ``""``).

    Parameters and result as :func:`spatial_invariants`; section properties ``rho``, ``"EI:"``,
    ``"rho_I:"`` (the Rayleigh beam's ``rotary_inertia``) and ``EA``.
    """
    from ..modes.from_spec import shape_family

    path = f"beams.{beam.name}"
    bending = {"": ShapeBasis.of_family(shape_family(beam.shape, f"{path}.shape", parameters), beam.n_modes)} \
        if beam.n_modes else {}
    axial = ShapeBasis.of_family(shape_family(beam.axial_shape, f"{path}.axial_shape", parameters),
                                 beam.n_axial) if beam.n_axial else None
    sections = {}
    for name, key in (("rho", "rho"), ("EI:", "EI"), ("rho_I:", "rotary_inertia"), ("EA", "EA")):
        value = getattr(beam, key, None)
        if value is not None:
            sections[name] = fields.value(value, f"{path}.{key}")
    return modal_invariants(fields.value(beam.L, f"{path}.L"), bending, axial=axial, **sections)
