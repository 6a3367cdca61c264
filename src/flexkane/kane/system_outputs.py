"""Outputs that planar and spatial chains declare alike: energies, power, efforts and signals.

* ``kinetic``, ``potential_gravity``, ``strain``, ``potential_springs`` and their sum ``energy`` [J];
* ``power_nonconservative`` [W];
* ``effort_<joint>`` [N m on an angle, else N]: the generalized force of each driver;
* the columns of the actuators' efforts, loads, sensors and controllers
  (:func:`flexkane.kane.controllers.signal_outputs`).

:mod:`flexkane.kane.outputs` and :mod:`flexkane.kane.spatial_outputs` compute the values; each is
declared here with its unit and group (:class:`~flexkane.model.columns.Outputs`).
"""

from __future__ import annotations

import sympy as sp

from ..model.columns import ENERGIES, Outputs
from .controllers import effort_unit, signal_outputs

__all__ = ["energy_outputs", "power_and_efforts"]


def energy_outputs(out: Outputs, **parts) -> None:
    """The energies :data:`flexkane.model.columns.ENERGIES` [J] (given by name in ``parts``) and their
    sum ``energy``."""
    for name, what in ENERGIES.items():
        out.add(name, parts[name], "J", "energy", what)
    out.add("energy", sp.Add(*[parts[name] for name in ENERGIES]), "J", "energy", "the total energy")


def power_and_efforts(out: Outputs, eom, power) -> None:
    """``power_nonconservative`` [W], the drivers' efforts ``effort_<joint>`` [N m or N] and the
    columns of efforts, loads, sensors and controllers (:func:`flexkane.kane.controllers.signal_outputs`)."""
    out.add("power_nonconservative", power, "W", "power", "the power of the non-conservative forces")
    for owner, effort in eom.driver_efforts.items():
        out.add(f"effort_{owner}", effort, effort_unit(eom.chain, owner), "effort",
                f"the generalized force of the driver of joint {owner!r}")
    for output in signal_outputs(eom):    # efforts, loads, sensors, controllers (flexkane.kane.controllers)
        out.put(output)
