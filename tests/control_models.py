"""Models shared by the tests of control inputs, controllers in the loop and linear models for control."""

from flexkane import Model
from flexkane.model.parts import Beam, Joint, RigidBody

#: Gain of the P controller, stiffness of the equivalent torsional spring [N m/rad], and its set-point [rad].
KP, Q_REF = 30.0, 0.2


def hub_beam(spring: bool, n_modes: int = 3) -> Model:
    """A hub on a revolute joint (``hub``) with a beam clamped to it, no gravity.

    With ``spring`` the joint has a torsional spring of stiffness KP relaxed at Q_REF; without,
    the hub is free (a P controller on ``effort_hub`` can stand for the spring). The hub starts
    spinning at 1 rad/s.
    """
    model = Model(name="hub-beam", parameters={"J": 0.05, "L": 1.0, "EI": 12.0, "rho": 0.6,
                                               "Kp": KP, "q_ref": Q_REF})
    model.bodies["hub"] = RigidBody(name="hub", mass=1.0, inertia="J", points={"clamp": (0.05, 0)})
    model.beams["link"] = Beam(name="link", L="L", EI="EI", rho="rho", n_modes=n_modes)
    model.joints["hub"] = Joint(name="hub", type="revolute", parent="ground", child="hub",
                                **({"stiffness": "Kp", "rest": "q_ref"} if spring else {}))
    model.joints["clamp"] = Joint(name="clamp", type="weld", parent="hub", parent_point="clamp", child="link")
    model.initial["u_hub"] = 1.0
    return model.validate()
