"""Control inputs: named actuator efforts that enter F_r additively through the partial velocities.

A model derived with ``control_inputs = True`` (:func:`with_control_inputs`) has one input symbol per
*input channel*, added to the generalized active forces (eq. 8.35) of the loads:

* ``input_effort_<joint>`` for every revolute joint (a torque [N m] about the joint axis, between
  parent and child) and every prismatic joint (a force [N] along the slide) whose coordinate is not
  prescribed by a driver (a driven joint's effort is the driver's, an output ``effort_<joint>``):
  ``F_r += (d u_joint / d u_r) effort``, which is ``effort`` on the joint's own speed;
* ``input_load_<name>_fx``, ``input_load_<name>_fy`` [N] for every load that declares a force, in
  the load's frame (``ground`` or ``local``, as its ``frame`` says), ``F_r += v_P,r . (fx, fy)``;
* ``input_load_<name>_torque`` [N m] for every load that declares a torque, ``F_r += w_r . torque``.

Spatial models (``dimensions = 3``) have the same channels with three components: the efforts of
their revolute and prismatic joints (the joints with one coordinate), ``input_load_<name>_fx``,
``_fy``, ``_fz`` [N] and ``input_load_<name>_tx``, ``_ty``, ``_tz`` [N m] (in the load's frame, as its
``frame`` says), added through the partial velocities and partial angular velocities of the load's
point, ``F_r += v_P,r . F + w_r . T``.

**Names.** A channel's name is the name of the input signal everywhere: the controller's dict keys,
the results column of its values (``simulate(..., controller=f)``), the inputs of a linear model
and of its python-control ``StateSpace``. The ``input_`` prefix keeps it apart from the output
columns of the model's own efforts (``effort_<joint>``, ``load_<name>_fx`` ..., the values of the
fields the inputs add to), which are outputs of the same linear model: python-control connects
signals by name, so an input and an output must never share one.

The order of the channels is: joints in the order of the model, then loads in the order of the model
(fx, fy, torque; in 3D fx, fy, fz, tx, ty, tz).
Each input adds to what the model's own field gives (a joint's ``torque``, a
load's ``force`` and ``torque``), so with every input zero the equations are the model's. An input
symbol is a constant of the equations (an entry of the constants vector p, value 0 by default):
``flexkane.simulate(..., controller=f)`` sets it at every evaluation of the right-hand side, and
:mod:`flexkane.analysis` differentiates with respect to it for the input matrix B.

A model derived without ``control_inputs`` (every model file, every run without a controller) has
none, and its equations and printed report are unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import ModelError

__all__ = ["INPUT_PREFIX", "InputChannel", "input_channels", "input_forces", "input_symbols", "with_control_inputs"]

#: Prefix of the input channels' names before the name of the output column of the field they add to.
INPUT_PREFIX = "input_"


@dataclass(frozen=True)
class InputChannel:
    """One control input of a model.

    Attributes
    ----------
    name : str
        ``input_effort_<joint>``, ``input_load_<name>_fx``, ``input_load_<name>_fy`` or
        ``input_load_<name>_torque`` (:data:`INPUT_PREFIX` and the name of the field's output column).
    path : str
        Key path of the model field it adds to (``joints.shoulder.torque``, ``loads.push.force[0]``).
    unit : str
        ``N m`` or ``N``.
    """

    name: str
    path: str
    unit: str


def with_control_inputs(model):
    """A copy of ``model`` whose derivation has the input channels as symbols (module docstring).

    Parameters
    ----------
    model : Model

    Returns
    -------
    Model
        ``model`` itself when it has them already.
    """
    if getattr(model, "control_inputs", False) is True:
        return model
    new = model.copy()
    new.control_inputs = True
    return new


def input_channels(model) -> list[InputChannel]:
    """The input channels of a model, in their order (module docstring), whether or not it derives them.

    Parameters
    ----------
    model : Model
        A valid model.

    Returns
    -------
    list of InputChannel

    Raises
    ------
    ModelError
        If a parameter has the name of an input channel.
    """
    channels = []
    for name, joint in model.joints.items():
        if joint.type in ("revolute", "prismatic") and joint.driver is None:
            channels.append(InputChannel(f"{INPUT_PREFIX}effort_{name}", f"joints.{name}.torque",
                                         "N m" if joint.type == "revolute" else "N"))
    spatial = getattr(model, "dimensions", 2) == 3
    axes = "xyz" if spatial else "xy"
    for name, load in model.loads.items():
        if load.force is not None:
            channels += [InputChannel(f"{INPUT_PREFIX}load_{name}_f{axis}", f"loads.{name}.force[{k}]", "N")
                         for k, axis in enumerate(axes)]
        if load.torque is not None and spatial:
            channels += [InputChannel(f"{INPUT_PREFIX}load_{name}_t{axis}", f"loads.{name}.torque[{k}]", "N m")
                         for k, axis in enumerate(axes)]
        elif load.torque is not None:
            channels.append(InputChannel(f"{INPUT_PREFIX}load_{name}_torque", f"loads.{name}.torque", "N m"))
    for channel in channels:
        if channel.name in model.parameters:
            raise ModelError(f"parameters.{channel.name}", "a parameter name other than those of the input "
                             "channels", channel.name, f"{channel.name!r} is the input of {channel.path}; "
                             "rename the parameter")
    return channels


def input_symbols(chain) -> dict:
    """The input symbols of a chain derived with ``control_inputs``, by channel name (else empty).

    Parameters
    ----------
    chain : Chain

    Returns
    -------
    dict of str to sympy.Symbol
        In the order of :func:`input_channels`; the same symbols on every call.
    """
    symbols = getattr(chain, "_input_symbols", None)   # kept with the chain (and its pickle)
    if symbols is None:
        if getattr(chain.model, "control_inputs", False) is not True:
            return {}
        from ..model.values import GeneratedSymbol

        symbols = {ch.name: GeneratedSymbol(ch.name, real=True) for ch in input_channels(chain.model)}
        chain._input_symbols = symbols
    return symbols


def input_forces(kin) -> list:
    """Generalized active forces of the inputs, one expression per speed of the chain.

    Parameters
    ----------
    kin : Kinematics or SpatialKinematics

    Returns
    -------
    list of sympy.Expr
        ``sum_k (partial velocity of channel k along u_r) . input_k`` for every speed u_r; all zero
        for a model derived without ``control_inputs``.
    """
    import sympy as sp

    from .kinematics import Kinematics, rot

    chain = kin.chain
    speeds = chain.u
    forces = [sp.Integer(0)] * len(speeds)
    symbols = input_symbols(chain)
    if not symbols:
        return forces
    for name, joint in chain.model.joints.items():
        symbol = symbols.get(f"{INPUT_PREFIX}effort_{name}")
        if symbol is not None:
            coord = chain.of(name)[0]
            forces[speeds.index(coord.u)] += symbol
    if not isinstance(kin, Kinematics):    # the spatial engine (a planar chain's too)
        _spatial_load_forces(kin, symbols, forces)
        return forces
    for name, load in chain.model.loads.items():
        frame = kin.load_frame(load)
        if load.force is not None:
            fx, fy = symbols[f"{INPUT_PREFIX}load_{name}_fx"], symbols[f"{INPUT_PREFIX}load_{name}_fy"]
            force = (fx, fy) if load.frame == "local" else rot(-frame.theta, (fx, fy))
            for r, u in enumerate(speeds):
                forces[r] += chain.partial(frame.v[0], u) * force[0] + chain.partial(frame.v[1], u) * force[1]
        if load.torque is not None:
            torque = symbols[f"{INPUT_PREFIX}load_{name}_torque"]
            for r, u in enumerate(speeds):
                forces[r] += chain.partial(frame.omega, u) * torque
    return forces


def _spatial_load_forces(kin, symbols: dict, forces: list) -> None:
    """Add the load channels of a chain derived by the spatial engine to ``forces``:
    ``v_P,r . F + w_r . T`` with F and T along the axes of the frame at the load's point (turned from
    N for ``frame = "ground"``); a planar chain's force in the x-y plane, its torque about z."""
    import sympy as sp

    from .spatial_frame import dot

    chain = kin.chain
    zero = sp.Integer(0)
    for name, load in chain.model.loads.items():
        frame = kin.load_frame(load)

        def vector(letter):
            if chain.dimensions == 2 and letter == "t":
                return (zero, zero, symbols[f"{INPUT_PREFIX}load_{name}_torque"])
            axes = "xyz" if chain.dimensions == 3 else "xy"
            value = tuple(symbols[f"{INPUT_PREFIX}load_{name}_{letter}{axis}"] for axis in axes)
            value = value + (zero,) * (3 - len(value))
            return value if load.frame == "local" else frame.rotation.inverse_apply(value)

        force = vector("f") if load.force is not None else None
        torque = vector("t") if load.torque is not None else None
        for r, u in enumerate(chain.u):
            if force is not None:
                forces[r] += dot(tuple(chain.partial(c, u) for c in frame.v), force)
            if torque is not None:
                forces[r] += dot(tuple(chain.partial(c, u) for c in frame.omega), torque)
