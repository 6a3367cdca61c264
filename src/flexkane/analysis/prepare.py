"""The model a linearization is derived from: control inputs as symbols, a hub spun at a constant rate.

Two changes turn a model into one whose Kane's equations give the linear model directly:

* **Inputs.** The copy is derived with its control inputs (:mod:`flexkane.kane.inputs`): one symbol
  per actuator effort (``input_effort_<joint>`` of every revolute or prismatic joint not driven) and per
  load component (``input_load_<name>_fx``, ``_fy``, ``_torque``), added to the
  generalized active forces, so that the input matrix ``B`` is the Jacobian of the forcing with
  respect to them. The inputs r are these channels, in their order (joints in the order of the
  model, then loads); a model with none has no inputs (``B`` with zero columns). The nominal input
  r0 of a channel is the value of the model's own field at the time ``t0`` of the operating point
  (the joint's torque, the load's component; 0 when the field is not given), which the linear
  model's equations contain already: ``dr`` is what is added to it.
  An effort that uses the state (feedback: coordinates, speeds, sensors, controllers,
  :mod:`flexkane.model.signals`) stays in the equations with its law; its channel adds to it, of
  nominal value 0, so that ``B`` is then the input matrix of the closed loop.
  Spatial models (``dimensions = 3``) have the same channels, load components in three directions
  (``_fx, _fy, _fz, _tx, _ty, _tz``); their inputs and outputs go through the same reduction of Euler
  parameters as the state (:mod:`flexkane.analysis.rotation_reduction`).
* **Steady spin.** For ``about = "spin"`` the hub joint (a revolute joint) is given the driver
  ``speed = Omega``, a new parameter whose value is the spin rate [rad/s]; its actuator torque, if
  any, is removed (the driver supplies the effort, the joint has no input), and so are initial
  values of its speed.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from ..errors import ModelError
from ..model import Model
from ..kane.inputs import InputChannel, input_channels
from ..model.parts import Driver

__all__ = ["ABOUT", "InputChannel", "PreparedModel", "prepare_model", "spin_hub"]

#: Operating points a linearization can be taken about.
ABOUT = ("equilibrium", "rest", "spin")
_SAFE = re.compile(r"[^0-9A-Za-z_]")


@dataclass
class PreparedModel:
    """A model rewritten for linearization (see the module docstring).

    Attributes
    ----------
    model : Model
        The rewritten copy.
    inputs : list of InputChannel
    nominal : list of float
        Nominal value r0 of each input at t0 [N m or N].
    about : str
        One of :data:`ABOUT`.
    hub : str or None
        Name of the spun joint (``about = "spin"``).
    spin_parameter : str or None
        Name of the parameter holding the spin rate Omega [rad/s] (a revolute hub).
    spin_axis : tuple of 3 float or None
        Unit vector along J_c's axes about which a spherical or free hub spins freely (3D), its
        steady angular velocity ``w0 = Omega spin_axis`` [rad/s]; None for a revolute hub.
    spin : float or None
        Omega of a spherical or free hub [rad/s].
    notes : list of str
        What was changed, in words.
    """

    model: Model
    inputs: list[InputChannel] = field(default_factory=list)
    nominal: list[float] = field(default_factory=list)
    about: str = "equilibrium"
    hub: str | None = None
    spin_parameter: str | None = None
    spin_axis: tuple | None = None
    spin: float | None = None
    notes: list[str] = field(default_factory=list)


def _fresh(model: Model, base: str, taken: set[str]) -> str:
    name = _SAFE.sub("_", base)
    candidate, k = name, 1
    while candidate in model.parameters or candidate in taken or candidate in ("t", "pi"):
        k += 1
        candidate = f"{name}_{k}"
    taken.add(candidate)
    return candidate


def _value_at(model: Model, text, t0: float, path: str) -> float:
    """Numeric value of a field that may depend on t, at t = t0."""
    from ..model.field_values import FieldValues

    return FieldValues(model).value(text, path, t=float(t0))


def _field(model: Model, path: str):
    """The text or number of the field a channel adds to, or None when the model does not give it."""
    from ..model.paths import get_value

    owner = path.split(".")[1]
    if path.startswith("joints.") and model.joints[owner].torque is None:
        return None
    return get_value(model, path)


def _feedback(model: Model, text, t0: float, path: str) -> bool:
    """Whether an effort uses the state (coordinates, speeds, sensors, controllers): it then stays in
    the equations, and its input is an additive parameter of nominal value 0."""
    try:
        _value_at(model, text, t0, path)
        return False
    except ModelError as exc:
        if isinstance(text, str) and "unknown name" in f"{exc.expected} {exc.hint}":
            return True     # the model is valid: the name is a signal (flexkane.model.signals)
        raise


def spin_hub(model: Model, hub: str | None, spin_axis=None) -> str:
    """The revolute joint to spin: ``hub`` if given, else the only driven revolute joint, else the
    only revolute joint on the ground. With ``spin_axis`` (3D models), the spherical or free joint
    that spins freely: ``hub`` if given, else the only one on the ground.

    Raises
    ------
    ModelError
        If ``hub`` is not a revolute joint, or no single joint qualifies.
    """
    if spin_axis is not None:
        return _free_spin_hub(model, hub)
    revolute = sorted(name for name, j in model.joints.items() if j.type == "revolute")
    if hub is not None:
        if hub not in revolute:
            raise ModelError("--hub", f"a revolute joint of the model ({', '.join(revolute) or 'none'})", hub)
        return hub
    driven = [name for name in revolute if model.joints[name].driver is not None]
    if len(driven) == 1:
        return driven[0]
    grounded = [name for name in revolute if model.joints[name].parent == "ground"]
    if len(grounded) == 1 and not driven:
        return grounded[0]
    raise ModelError("--hub", "the name of the revolute joint to spin "
                     f"({', '.join(revolute) or 'the model has none'})", None, show_given=False)


def _free_spin_hub(model: Model, hub: str | None) -> str:
    """The spherical or free joint named by ``hub``, else the only one on the ground (``--spin-axis``)."""
    if model.dimensions != 3:
        raise ModelError("--spin-axis", "no spin axis for a planar model (its hub is a revolute joint)",
                         "a spin axis")
    rotating = sorted(name for name, j in model.joints.items() if j.type in ("spherical", "free"))
    if hub is not None:
        if hub not in rotating:
            raise ModelError("--hub", "a spherical or free joint of the model with --spin-axis "
                             f"({', '.join(rotating) or 'none'})", hub)
        return hub
    grounded = [name for name in rotating if model.joints[name].parent == "ground"]
    if len(grounded) == 1:
        return grounded[0]
    raise ModelError("--hub", "the name of the spherical or free joint that spins about --spin-axis "
                     f"({', '.join(rotating) or 'the model has none'})", None, show_given=False)


def _unit_axis(spin_axis) -> tuple:
    """``spin_axis`` as a unit 3-vector of floats, or a ModelError naming --spin-axis."""
    try:
        axis = [float(c) for c in spin_axis]
    except (TypeError, ValueError):
        raise ModelError("--spin-axis", "three numbers (components along J_c's axes)", spin_axis) from None
    norm = sum(c * c for c in axis) ** 0.5
    if len(axis) != 3 or not norm > 0 or norm == float("inf"):
        raise ModelError("--spin-axis", "a finite non-zero vector of three components along J_c's axes", spin_axis)
    return tuple(c / norm for c in axis)


def prepare_model(model: Model, *, about: str, spin: float | None = None, hub: str | None = None,
                  t0: float = 0.0, spin_axis=None) -> PreparedModel:
    """Rewrite a model for linearization.

    Parameters
    ----------
    model : Model
        A valid model (not modified).
    about : str
        One of :data:`ABOUT`.
    spin : float, optional
        Spin rate Omega of the hub [rad/s]; required for ``about = "spin"``, refused otherwise.
    hub : str, optional
        Revolute joint to spin (see :func:`spin_hub`).
    t0 : float
        Time of the operating point [s]: loads are replaced by their values at t0.
    spin_axis : sequence of 3 float, optional
        For a 3D model spinning freely on a spherical or free joint (a torque-free body, a top): the
        axis of the steady angular velocity along J_c's axes [-]; the joint is not driven, its steady
        angular speeds are ``Omega * axis`` (:mod:`flexkane.analysis.rotation_reduction`).

    Returns
    -------
    PreparedModel
    """
    from ..model.coordinates import coordinate_names

    if about not in ABOUT:
        raise ModelError("--about", "one of " + ", ".join(ABOUT), about)
    if about == "spin":
        if spin is None:
            raise ModelError("--spin", "a spin rate Omega [rad/s] with --about spin", None, show_given=False)
    elif spin is not None:
        raise ModelError("--spin", f"no spin rate unless --about spin (--about is {about})", spin)
    if spin_axis is not None and about != "spin":
        raise ModelError("--spin-axis", f"no spin axis unless --about spin (--about is {about})", spin_axis)
    model.validate()
    new = model.copy()
    prepared = PreparedModel(new, about=about)
    coordinates = coordinate_names(model)
    taken: set[str] = {c.q for c in coordinates} | {c.u for c in coordinates}
    if about == "spin":
        spin = float(spin)
        if not spin == spin or abs(spin) == float("inf"):
            raise ModelError("--spin", "a finite spin rate [rad/s]", spin)
        name = spin_hub(model, hub, spin_axis)
        if spin_axis is not None:
            prepared.hub, prepared.spin, prepared.spin_axis = name, spin, _unit_axis(spin_axis)
            prepared.notes.append(f"joint {name} spins freely at Omega = {spin:g} rad/s about "
                                  f"({', '.join(f'{c:g}' for c in prepared.spin_axis)}) of its child frame: "
                                  "the linear model is written in the rotation of that frame (rx, ry, rz)")
    if about == "spin" and spin_axis is None:
        coord = next(c for c in coordinates if c.owner == name)
        joint = new.joints[name]
        parameter = _fresh(new, "Omega", taken)
        new.parameters[parameter] = spin
        if joint.torque is not None:
            prepared.notes.append(f"the actuator torque of joint {name} is not an input: the spin is prescribed")
        joint.torque = None
        joint.driver = Driver(speed=parameter)
        new.initial.pop(coord.u, None)
        prepared.hub = name
        prepared.spin_parameter = parameter
        prepared.notes.append(f"joint {name} spins at the constant rate {parameter} = {spin:g} rad/s")
    new.control_inputs = True           # derived with its input channels (flexkane.kane.inputs)
    for channel in input_channels(new):
        field_value = _field(new, channel.path)
        prepared.inputs.append(channel)
        if field_value is None or _feedback(model, field_value, t0, channel.path):
            prepared.nominal.append(0.0)
        else:
            prepared.nominal.append(_value_at(model, field_value, t0, channel.path))
    new.validate()
    return prepared
