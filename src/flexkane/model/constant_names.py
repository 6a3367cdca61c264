"""Names of the constants the derivation generates for a beam (``m_B``, ``E_1``, ``H_11``), without SymPy.

Model validation refuses parameters named like them (printed equations stay readable);
:class:`flexkane.kane.beam_constants.BeamConstants` makes the symbols.
"""

from __future__ import annotations

__all__ = ["MODAL_STEMS", "generated_constant"]

#: Stems of the modal constants' names (``E_1``, ``G_12``, ``H_11``, ...), with what they are.
MODAL_STEMS = {
    "E": "int rho Phi_i dx", "F": "int rho x Phi_i dx", "G": "int rho Phi_i Phi_j dx",
    "H": "int EI Phi_i'' Phi_j'' dx", "HA": "int EA Psi_k' Psi_l' dx", "A": "int rho Psi_k dx",
    "Ax": "int rho x Psi_k dx", "C": "int rho Phi_i Psi_k dx", "AA": "int rho Psi_k Psi_l dx",
    "D": "int rho d dx", "Dx": "int rho x d dx", "Dphi": "int rho Phi_i d dx",
    "Dpsi": "int rho Psi_k d dx", "DD": "int rho d d dx", "J": "int Phi_i'''' dx",
    "Jx": "int x Phi_i'''' dx", "JPhi": "int Phi_j Phi_i'''' dx",
    "Er": "int rho_I Phi_i' dx", "Gr": "int rho_I Phi_i' Phi_j' dx",
}
_MASS_NAMES = {"m": "int rho dx", "e": "int rho x dx", "I": "int rho x^2 dx", "Ir": "int rho_I dx"}


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
        if rest and all(part.isdigit() and part.isascii() for part in rest.split("_")):
            return f"the modal constant {name} = {meaning} of beam {beam!r}"
    return None
