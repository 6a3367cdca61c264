"""Spatial (dimensions = 3) models of the control tests, and a numeric evaluation of derived equations
that needs no compiled module (SymPy's lambdify of the compact form: fast for small models).

* :data:`HINGE`: a body on a revolute joint about a skew axis under gravity; its joint effort is a PD
  law, a PID controller with an integral state, or a spring and damper (``{effort}``).
* :data:`ATTITUDE`: a free rigid body (free joint, no gravity) with a torque in body axes written with
  its Euler parameters and angular speeds, ``T = -Kp e_vec - Kd w`` (``{torque}``).
* :data:`STRAIN_FEEDBACK`: a hub turning about z with a spatial beam bending in both planes and
  twisting, its torque a PD law plus feedback of the root bending moment (a sensor) and of a filter.
* :data:`SENSED_BEAM`: a clamped spatial beam with exact shape functions for a static tip load
  (cubic polynomials in both bending planes, a linear twist) and sensors of every beam kind.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

import flexkane

#: PD gains of the hinge [N m/rad, N m s/rad], its set-point [rad] and the integral gain [N m/(rad s)].
KP, KD, Q_REF, KI = 6.0, 0.4, 0.3, 2.0
#: Unit axis of the hinge (J_p = ground axes) and the body's points [m].
AXIS = np.array([1.0, 0.5, 0.2]) / np.linalg.norm([1.0, 0.5, 0.2])
TOP, TOOL = np.array([0.0, 0.05, 0.3]), np.array([0.1, 0.0, -0.3])
MASS, G = 1.5, 9.81

HINGE = f"""
name = "hinge-3d"
dimensions = 3
[parameters]
Kp = {KP}
Kd = {KD}
Ki = {KI}
q_ref = {Q_REF}
[bodies.arm]
mass = {MASS}
inertia = [[0.02, 0.001, 0.0], [0.001, 0.03, 0.002], [0.0, 0.002, 0.04]]
points = {{ top = [{TOP[0]}, {TOP[1]}, {TOP[2]}], tool = [{TOOL[0]}, {TOOL[1]}, {TOOL[2]}] }}
[joints.hinge]
type = "revolute"
parent = "ground"
parent_position = [0, 0, 0]
child = "arm"
child_point = "top"
axis = [1, 0.5, 0.2]
{{effort}}
[gravity]
g = {G}
direction = [0, 0, -1]
[initial]
q_hinge = 0.1
u_hinge = 0.5
"""

#: The hinge's effort fields: a PD law, the spring and damper it equals, and a PID with saturation and a
#: first-order filter of the tool's height (a sensor).
PD_LAW = 'torque = "-Kp*(q_hinge - q_ref) - Kd*u_hinge"'
SPRING = 'stiffness = "Kp"\nrest = "q_ref"\ndamping = "Kd"'
PID = '''torque = "pid"
[controllers.pid]
states = { zi = "q_ref - q_hinge" }
output = "Kp*(q_ref - q_hinge) - Kd*u_hinge + Ki*zi"
min = -40
max = 40
[controllers.filter]
states = { zf = "10*(tool_z - zf)" }
[sensors.tool_z]
type = "position"
body = "arm"
point = "tool"
component = "z"'''

#: A spring whose rest position moves with the speed: the same force as PD_LAW (an actuator).
MOVING_REST = 'stiffness = "Kp"\nrest = "q_ref - Kd/Kp*u_hinge"'

#: Point and joint sensors of the hinge's tool (appended to a HINGE model).
HINGE_SENSORS = "".join(f"""
[sensors.{kind}_{frame}_{c}]
type = "{kind}"
body = "arm"
point = "tool"
component = "{c}"
frame = "{frame}"
""" for kind in ("position", "velocity", "acceleration") for frame in ("ground", "local") for c in "xyz") + """
[sensors.angle]
type = "joint_angle"
joint = "hinge"
[sensors.rate]
type = "joint_rate"
joint = "hinge"
"""

#: Principal moments of the free body [kg m^2] and the attitude gains [N m, N m s/rad].
INERTIA, KP_ATT, KD_ATT = (1.0, 2.0, 2.5), 8.0, 1.5

ATTITUDE = f"""
name = "attitude-3d"
dimensions = 3
[parameters]
Kp = {KP_ATT}
Kd = {KD_ATT}
[bodies.bus]
mass = 20.0
inertia = [{INERTIA[0]}, {INERTIA[1]}, {INERTIA[2]}]
[joints.float]
type = "free"
parent = "ground"
parent_position = [0, 0, 0]
child = "bus"
[loads.attitude]
body = "bus"
torque = {{torque}}
frame = "local"
"""
#: The attitude law ``T = -Kp e_vec - Kd w`` in body axes, and no torque (the open loop).
ATTITUDE_LAW = '["-Kp*q_float_e1 - Kd*u_float_wx", "-Kp*q_float_e2 - Kd*u_float_wy", ' \
               '"-Kp*q_float_e3 - Kd*u_float_wz"]'
NO_TORQUE = "[0, 0, 0]"
#: The attitude law with integral states of the attitude error (more q than u, and z after them).
ATTITUDE_PI = '["-Kp*q_float_e1 - Kd*u_float_wx - 0.5*zx", "-Kp*q_float_e2 - Kd*u_float_wy - 0.5*zy", ' \
              '"-Kp*q_float_e3 - Kd*u_float_wz - 0.5*zz"]'
INTEGRAL = '[controllers.integral]\nstates = { zx = "q_float_e1", zy = "q_float_e2", zz = "q_float_e3" }\n' \
           'initial = { zx = 0.1 }\n'

#: The clamped beam: length [m], rigidities [N m^2] and its sensors' station and distance [m].
BEAM_L, EI_Y, EI_Z, GJ, STATION, DISTANCE = 1.2, 5.0, 9.0, 3.0, 0.5, 0.01

SENSED_BEAM = f"""
name = "sensed-beam"
dimensions = 3
[beams.b]
L = {BEAM_L}
rho = 0.7
EI_y = {EI_Y}
EI_z = {EI_Z}
GJ = {GJ}
rho_Ip = 0.01
n_modes_y = 2
n_modes_z = 2
n_torsion = 1
shape_y = "polynomial"
shape_z = "polynomial"
torsion_shape = {{ family = "expression", expressions = ["xi"] }}
[joints.weld]
type = "weld"
parent = "ground"
child = "b"
[loads.tip]
body = "b"
station = {BEAM_L}
force = [0, 0, 0]
torque = [0, 0, 0]
frame = "ground"
[sensors.tip_v]
type = "tip_deflection"
beam = "b"
component = "y"
[sensors.tip_w]
type = "tip_deflection"
beam = "b"
component = "z"
[sensors.slope_v]
type = "tip_slope"
beam = "b"
component = "y"
[sensors.slope_w]
type = "tip_slope"
beam = "b"
component = "z"
[sensors.moment_z]
type = "bending_moment"
beam = "b"
station = 0.0
component = "y"
[sensors.moment_y]
type = "bending_moment"
beam = "b"
station = {STATION}
component = "z"
[sensors.strain_v]
type = "strain"
beam = "b"
station = {STATION}
distance = {DISTANCE}
component = "y"
[sensors.twist_tip]
type = "twist"
beam = "b"
station = {BEAM_L}
[sensors.tip_y]
type = "position"
body = "b"
station = {BEAM_L}
component = "y"
"""


def hinge(effort: str, sensors: bool = False) -> flexkane.Model:
    """The hinge model with an effort field (:data:`PD_LAW`, :data:`SPRING`, :data:`PID`)."""
    return flexkane.loads_model(HINGE.replace("{effort}", effort) + (HINGE_SENSORS if sensors else ""))


def attitude(torque: str, extra: str = "") -> flexkane.Model:
    """The free body with a torque field (:data:`ATTITUDE_LAW`, :data:`NO_TORQUE`, :data:`ATTITUDE_PI`
    with ``extra`` = :data:`INTEGRAL`)."""
    return flexkane.loads_model(ATTITUDE.replace("{torque}", torque) + extra)


class Evaluated:
    """Derived equations evaluated numerically through their compact form (no compiled module).

    Parameters
    ----------
    eom : EquationsOfMotion
    inputs : dict of str to float, optional
        Values of input channels (a model derived with its control inputs).
    prefixes : tuple of str, optional
        Evaluate only the outputs whose names start so (all by default).
    """

    def __init__(self, eom, inputs: dict | None = None, prefixes: tuple | None = None):
        self.eom = eom
        values = eom.constant_values()
        for name, value in (inputs or {}).items():
            values[next(c for c in eom.constants if c.name == name)] = value
        self.constants = [values[c] for c in eom.constants]
        compact = eom.compact
        self.nq, self.nu, self.nz = len(eom.q), len(eom.u), len(eom.z)
        args = [eom.t, *eom.q, *eom.u, *eom.z, *eom.ud, *eom.constants]
        definitions = list(compact.intermediates)     # evaluated in order, before the expressions

        def named(exprs):
            return definitions, exprs

        self._system = sp.lambdify(args, [compact.mass_matrix, compact.forcing, compact.qdot, compact.zdot],
                                   cse=named)
        self.output_names = [k for k in compact.outputs if prefixes is None or k.startswith(prefixes)]
        self._outputs = sp.lambdify(args, [compact.outputs[k] for k in self.output_names], cse=named)

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        """``y' = [q', u', z']`` at (t, y), shape (nq + nu + nz,)."""
        M, f, qdot, zdot = self._system(t, *y, *np.zeros(self.nu), *self.constants)
        ud = np.linalg.solve(np.array(M, dtype=float), np.array(f, dtype=float).ravel())
        return np.concatenate([np.array(qdot, dtype=float).ravel(), ud, np.array(zdot, dtype=float).ravel()])

    def outputs(self, t: float, y: np.ndarray) -> dict:
        """Every output at (t, y) (accelerations with the u' of :meth:`rhs`), by name."""
        ud = self.rhs(t, y)[self.nq:self.nq + self.nu]
        return dict(zip(self.output_names, (float(v) for v in self._outputs(t, *y, *ud, *self.constants))))


def random_states(eom, count: int, seed: int = 18) -> list:
    """``count`` states about the model's initial state (Euler parameters kept on the unit sphere)."""
    rng = np.random.default_rng(seed)
    y0 = eom.initial_state()
    nq, nu, nz = len(eom.q), len(eom.u), len(eom.z)
    states = []
    for _ in range(count):
        y = y0.copy()
        y[:nq] += 0.3 * rng.standard_normal(nq)
        y[nq:] += rng.standard_normal(nu + nz)
        for joint in {c.owner for c in eom.chain.coordinates if c.role == "e0"}:
            rows = [eom.q.index(c.q) for c in eom.chain.of(joint) if c.role in ("e0", "e1", "e2", "e3")]
            y[rows] /= np.linalg.norm(y[rows])
        states.append(y)
    return states


STRAIN_FEEDBACK = """
name = "hub-beam-3d"
dimensions = 3
[parameters]
Kp = 5.0
Kd = 0.8
Ks = 0.3
[bodies.hub]
mass = 2.0
inertia = [0.05, 0.05, 0.08]
points = { clamp = [0.1, 0, 0] }
[beams.blade]
L = 1.0
rho = 0.6
EI_y = 8.0
EI_z = 12.0
GJ = 4.0
rho_Ip = 0.02
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
[joints.hub]
type = "revolute"
parent = "ground"
parent_position = [0, 0, 0]
child = "hub"
axis = [0, 0, 1]
torque = "-Kp*q_hub - Kd*u_hub - Ks*root - filtered"
[joints.clamp]
type = "weld"
parent = "hub"
parent_point = "clamp"
child = "blade"
orientation = { axis = [1, 0, 0], angle = 0.3 }
[sensors.root]
type = "bending_moment"
beam = "blade"
station = 0.0
component = "y"
[controllers.filtered]
states = { zf = "5*(0.1*tip_twist - zf)" }
output = "zf"
[sensors.tip_twist]
type = "twist"
beam = "blade"
station = 1.0
[gravity]
g = 9.81
direction = [0, 1, -1]
[initial]
q_hub = 0.2
u_hub = 1.0
q_blade_y1 = 0.02
q_blade_z1 = -0.01
u_blade_t1 = 0.5
"""
