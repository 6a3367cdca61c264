"""The clamped spatial beam of the tests of spatial beams' modes, modal damping and convergence.

One uniform beam ``b`` (length :data:`L`, the numbers below) welded to the ground, bending in its two
principal planes and twisting; each test adds the keys it studies (mode counts, shape families,
principal angle, damping ratios) and may turn the weld's frame. Its clamped frequencies are eq. 8.7
with EI_y for the deflection along z and EI_z for the one along y, and (2k - 1) pi/(2L) sqrt(GJ/rho_Ip)
in torsion.
"""

from __future__ import annotations

#: Length [m], mass per length [kg/m], bending stiffnesses EI_y, EI_z [N m^2], torsional stiffness
#: GJ [N m^2] and polar mass moment per length rho_Ip [kg m] of the beam.
L, RHO, EI_Y, EI_Z, GJ, RHO_IP = 1.2, 0.7, 5.0, 9.0, 3.0, 0.01


def clamped_spatial_beam(name: str, beam_keys: str, orientation: tuple | None = None) -> str:
    """Return the TOML text of the clamped spatial beam.

    Parameters
    ----------
    name : str
        The model's name.
    beam_keys : str
        Further keys of ``[beams.b]``, one per line (TOML), after its numbers ``L`` to ``rho_Ip``.
    orientation : (axis, angle), optional
        Turn of the weld's frame: unit-free axis (3,) and angle [rad]; none when omitted.

    Returns
    -------
    str
        A model file's text (``dimensions = 3``), with the line ``rho_Ip = ...`` of its own.
    """
    weld = ""
    if orientation is not None:
        axis, angle = orientation
        weld = f"orientation = {{ axis = [{', '.join(str(a) for a in axis)}], angle = {angle} }}\n"
    return f"""
dimensions = 3
name = "{name}"

[beams.b]
L = {L}
rho = {RHO}
EI_y = {EI_Y}
EI_z = {EI_Z}
GJ = {GJ}
rho_Ip = {RHO_IP}
{beam_keys.strip()}

[joints.weld]
type = "weld"
parent = "ground"
child = "b"
{weld}"""
