"""Names of the constants the derivation generates for a beam (``m_B``, ``E_1``, ``H_11``), without SymPy.

A spatial beam's modal constants carry the direction of the bending family in their indices
(``E_y1``, ``G_y1_z2``, ``H_z11``, ``Er_y1``, ``DD_y11_z22``) and add the torsion constants
(``Et_1``, ``Gt_12``, ``Kt_11``) and the sections' inertia (``Ip_B``, ``Iry_B``, ``Irz_B``); see
:class:`flexkane.kane.spatial_beam_constants.SpatialBeamConstants`.

Model validation refuses parameters named like them (printed equations stay readable);
:class:`flexkane.kane.beam_constants.BeamConstants` makes the symbols.
"""

from __future__ import annotations

from .schema import constant_stems

__all__ = ["MODAL_STEMS", "generated_constant"]

#: Stems of the modal constants' names (``E_1``, ``G_12``, ``H_11``, ...), with what they are: each
#: declared with the beam field that brings it (:mod:`flexkane.model.schema`).
MODAL_STEMS = constant_stems("modal")
_MASS_NAMES = constant_stems("mass")


def _index(part: str) -> bool:
    """Whether ``part`` is an index of a modal constant: digits (``12``), after a spatial beam's
    direction letter (``y12``, ``z1``)."""
    digits = part[1:] if part[:1] in ("y", "z") else part
    return bool(digits) and digits.isdigit() and digits.isascii()


def generated_constant(name: str, beam: str, label: str) -> str | None:
    """What ``name`` stands for among the constants of a beam, or None if it is not theirs.

    Parameters
    ----------
    name : str
        A candidate name (e.g. a parameter's).
    beam : str
        The beam's name (``m_<beam>``, ``e_<beam>``, ``I_<beam>``).
    label : str
        The label of its modal constants (see :class:`BeamConstants`).

    Returns
    -------
    str or None
        E.g. ``"the modal constant H_11 = int EI Phi_i'' Phi_j'' dx of beam 'link'"``.
    """
    for stem, meaning in _MASS_NAMES.items():
        if name == f"{stem}_{beam}":
            return f"the mass constant {name} = {meaning} of beam {beam!r}"
    prefix = f"_{label}_" if label else "_"
    for stem, meaning in MODAL_STEMS.items():
        rest = name[len(stem) + len(prefix):] if name.startswith(stem + prefix) else ""
        if rest and all(_index(part) for part in rest.split("_")):
            return f"the modal constant {name} = {meaning} of beam {beam!r}"
    return None
