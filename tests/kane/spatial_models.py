"""Rigid spatial chains shared by the tests of the spatial engine.

Each chain is described once in plain Python (see :mod:`kanes_method_reference`): the same
description builds the flexkane model (:func:`flexkane_model`) and the independent
``sympy.physics.mechanics`` derivation.
"""

from __future__ import annotations

from flexkane.model import Model
from flexkane.model.parts import Gravity, Joint, Load, Orientation, RigidBody

G = (0.0, 0.0, -9.81)

_I1 = [[0.1, 0.01, 0.0], [0.01, 0.2, 0.02], [0.0, 0.02, 0.15]]
_I2 = [[0.05, 0.0, 0.01], [0.0, 0.07, 0.0], [0.01, 0.0, 0.03]]

#: Two bodies on spherical joints, hanging from the ground, off-axis points, full inertia tensors.
SPHERICAL_DOUBLE_PENDULUM = (
    {"A": (2.0, _I1, {"top": (0.0, 0.0, 0.5), "bottom": (0.1, 0.0, -0.5)}),
     "B": (1.5, _I2, {"top": (0.0, 0.05, 0.4)})},
    [dict(name="j1", type="spherical", parent="ground", child="A", parent_point=(0.0, 0.0, 0.0), child_point="top"),
     dict(name="j2", type="spherical", parent="A", child="B", parent_point="bottom", child_point="top")])

#: A symmetric top on a spherical joint at its tip, mass centre above the pivot.
SPINNING_TOP = (
    {"top": (0.8, [[0.012, 0.0, 0.0], [0.0, 0.012, 0.0], [0.0, 0.0, 0.02]], {"tip": (0.0, 0.0, -0.07)})},
    [dict(name="pivot", type="spherical", parent="ground", child="top", parent_point=(0.0, 0.0, 0.0),
          child_point="tip")])

#: A robot arm: waist about the vertical, shoulder about a horizontal axis (its joint frame turned
#: about x), elbow about a skew axis; actuator torques on all three.
THREE_JOINT_ARM = (
    {"base": (3.0, _I1, {"top": (0.0, 0.0, 0.2), "bottom": (0.0, 0.0, -0.2)}),
     "upper": (2.0, _I2, {"a": (0.0, 0.0, -0.3), "b": (0.02, 0.0, 0.3)}),
     "fore": (1.0, _I1, {"a": (0.0, 0.0, -0.25)})},
    [dict(name="waist", type="revolute", parent="ground", child="base", parent_point=(0.0, 0.0, 0.1),
          child_point="bottom", axis=(0, 0, 1), torque=1.0),
     dict(name="shoulder", type="revolute", parent="base", child="upper", parent_point="top", child_point="a",
          axis=(0, 1, 0), orientation=((1, 0, 0), 0.3), torque=-2.0),
     dict(name="elbow", type="revolute", parent="upper", child="fore", parent_point="b", child_point="a",
          axis=(0, 1, 1), torque=0.5)])

#: A free body carrying a link on a universal joint (J_c turned in the link), which carries a slider
#: along a skew axis (J_p turned in the link).
FREE_UNIVERSAL_PRISMATIC = (
    {"hub": (5.0, _I1, {"U": (0.2, 0.1, 0.0), "C": (-0.05, 0.02, 0.03)}),
     "link": (1.0, _I2, {"a": (0.0, 0.0, -0.3), "b": (0.0, 0.02, 0.3)}),
     "slider": (0.4, _I1, {"s": (0.01, 0.0, 0.0)})},
    [dict(name="float", type="free", parent="ground", child="hub", parent_point=(0.1, 0.2, 0.3), child_point="C",
          orientation=((1, 1, 0), 0.5)),
     dict(name="cardan", type="universal", parent="hub", child="link", parent_point="U", child_point="a",
          axes=((1, 0, 0), (0, 1, 0)), child_orientation=((0, 0, 1), 0.4)),
     dict(name="slide", type="prismatic", parent="link", child="slider", parent_point="b", child_point="s",
          axis=(1, 1, 0), orientation=((0, 1, 0), 0.2))])

#: A cart on a planar joint (normal z), a rod on a cylindrical joint, a tip on a revolute joint with
#: a spring and a damper; loads in local and ground axes.
PLANAR_CYLINDRICAL_REVOLUTE = (
    {"cart": (3.0, _I2, {"top": (0.0, 0.0, 0.1), "C": (0.05, 0.0, -0.1)}),
     "rod": (1.0, _I1, {"a": (0.0, 0.0, -0.2), "b": (0.0, 0.0, 0.2)}),
     "tip": (0.5, _I2, {"a": (-0.1, 0.0, 0.0), "tool": (0.1, 0.02, 0.0)})},
    [dict(name="table", type="planar", parent="ground", child="cart", parent_point=(0.0, 0.0, 0.0), child_point="C",
          axis=(0, 0, 1)),
     dict(name="column", type="cylindrical", parent="cart", child="rod", parent_point="top", child_point="a",
          axis=(0, 1, 1)),
     dict(name="wrist", type="revolute", parent="rod", child="tip", parent_point="b", child_point="a",
          axis=(1, 0, 0), child_orientation=((0, 1, 0), 0.3), stiffness=4.0, rest=0.2, damping=0.3)])

APPLIED = [dict(body="tip", point="tool", force=(0.5, -1.0, 2.0), torque=(0.1, 0.0, -0.2), frame="local"),
           dict(body="rod", point="b", force=(1.0, 0.3, 0.0), torque=(0.0, 0.4, 0.0), frame="ground")]


def _orientation(pair):
    return None if pair is None else Orientation(axis=tuple(pair[0]), angle=pair[1])


def flexkane_model(description, gravity=G, name: str = "spatial", applied=()) -> Model:
    """The flexkane model (dimensions = 3) of a chain description."""
    bodies, joints = description
    model = Model(name=name, dimensions=3)
    for body, (mass, inertia, points) in bodies.items():
        model.bodies[body] = RigidBody(body, mass, [list(row) for row in inertia],
                                       {k: tuple(v) for k, v in points.items()})
    for j in joints:
        kw = {"child_point": j["child_point"]}
        if j["parent"] == "ground":
            kw["parent_position"] = tuple(j["parent_point"])
        else:
            kw["parent_point"] = j["parent_point"]
        if "axis" in j:
            kw["axis"] = tuple(j["axis"])
        if "axes" in j:
            kw["axes"] = [tuple(a) for a in j["axes"]]
        kw["orientation"] = _orientation(j.get("orientation"))
        kw["child_orientation"] = _orientation(j.get("child_orientation"))
        for key in ("torque", "stiffness", "rest", "damping"):
            if j.get(key) is not None:
                kw[key] = j[key]
        model.joints[j["name"]] = Joint(j["name"], j["type"], j["parent"], j["child"], **kw)
    for k, load in enumerate(applied):
        model.loads[f"load{k}"] = Load(f"load{k}", load["body"], point=load["point"], force=tuple(load["force"]),
                                       torque=tuple(load["torque"]), frame=load["frame"])
    if gravity is not None and any(gravity):
        norm = sum(c * c for c in gravity) ** 0.5
        model.gravity = Gravity(norm, tuple(c / norm for c in gravity))
    return model.validate()


def accelerations(eom):
    """``u'(q, u)`` of derived equations, evaluated numerically from their compact form (the named
    intermediates in order, then ``M u' = f``), with the constants of the derived model (controller
    states, if any, at zero)."""
    import numpy as np

    system = compact_system(eom)

    def rhs(q, u, t=0.0):
        M, f, _ = system(q, u, np.zeros(len(eom.z)), t)
        return np.linalg.solve(M, f)

    return rhs


def compact_functions(eom, expressions):
    """``f(q, u)`` evaluating expressions of the compact form (in terms of the named intermediates,
    evaluated in order first), with the constants of the derived model."""
    import numpy as np
    import sympy as sp

    values = eom.constant_values()
    constants = [values[c] for c in eom.constants]
    symbols = [s for s, _ in eom.intermediates]
    args = [eom.t, *eom.q, *eom.u, *eom.constants, *symbols]
    definitions = [sp.lambdify(args, e) for _, e in eom.intermediates]
    function = sp.lambdify(args, list(expressions))

    def evaluate(q, u, t=0.0):
        base = [t, *q, *u, *constants]
        known = [0.0] * len(definitions)
        for k, definition in enumerate(definitions):
            known[k] = definition(*base, *known)
        return np.array(function(*base, *known), dtype=float)

    return evaluate


def output_rates(eom, outputs, states):
    """d/dt of outputs along the equations of motion at states (Richardson-extrapolated central
    differences along (q', u')), one row per state."""
    import numpy as np

    acc = accelerations(eom)
    functions = compact_functions(eom, [eom.compact.outputs[name] for name in outputs])
    qdot = compact_functions(eom, list(eom.compact.qdot))
    rows = []
    for q, u in states:
        ud = acc(q, u)
        qd = qdot(q, u)

        def central(h):
            return (functions(q + h * qd, u + h * ud) - functions(q - h * qd, u - h * ud)) / (2 * h)

        rows.append((4 * central(5e-5) - central(1e-4)) / 3)
    return np.array(rows)


def compact_system(eom):
    """``(q, u, z, t) -> (M, f, z')`` of derived equations, evaluated numerically from their compact
    form (the named intermediates in order), with the constants of the derived model."""
    import numpy as np
    import sympy as sp

    values = eom.constant_values()
    constants = [values[c] for c in eom.constants]
    symbols = [s for s, _ in eom.intermediates]
    args = [eom.t, *eom.q, *eom.u, *eom.z, *eom.constants, *symbols]
    definitions = [sp.lambdify(args, e) for _, e in eom.intermediates]
    n = len(eom.u)
    mass = eom.compact.mass_matrix
    system = sp.lambdify(args, [sp.Matrix(n, n, lambda i, j: mass[i, j]), eom.compact.forcing, eom.compact.zdot])

    def evaluate(q, u, z, t):
        base = [t, *q, *u, *z, *constants]
        known = [0.0] * len(definitions)
        for k, definition in enumerate(definitions):
            known[k] = definition(*base, *known)
        return tuple(np.array(a, dtype=float).reshape(-1, n) if k == 0 else np.array(a, dtype=float).ravel()
                     for k, a in enumerate(system(*base, *known)))

    return evaluate
