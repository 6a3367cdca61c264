"""The parts of a chain: rigid bodies, flexible beams, joints, loads and drivers.

A planar model (``dimensions = 2``) has two-component vectors and scalar angles, inertias and
torques; a spatial model (``dimensions = 3``) has three-component vectors, inertia tensors, torque
vectors, joint axes as vectors and orientations (:class:`Orientation`).

Values of physical fields are kept as given (a number, or the text of an expression of the model's
parameters) so that a model can be saved back to the same file and so that the derivation can keep
every value as a symbol. They are checked and turned into SymPy expressions by
:mod:`flexkane.model.values`.

A chain is a tree rooted at the ground: every link (rigid body or beam) is the child of exactly one
joint. A beam clamped to a body (the chapter's Fig. 8.2) is the child of a ``weld`` joint.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

#: A field value as given: a number or the text of an expression of parameters (and t where allowed).
Value = Union[int, float, str]

JOINT_TYPES = ("free", "revolute", "prismatic", "weld")
#: Generalized coordinates that each joint type introduces, in order, by role (planar chains).
JOINT_DOFS = {"free": ("x", "y", "angle"), "revolute": ("angle",), "prismatic": ("slide",), "weld": ()}
#: Joint types of spatial chains (``dimensions = 3``).
SPATIAL_JOINT_TYPES = ("revolute", "prismatic", "cylindrical", "universal", "spherical", "planar", "free", "weld")
#: Generalized coordinates of each spatial joint type, in order, by role: ``angle`` about the axis,
#: ``slide`` along it, ``angle_1``/``angle_2`` about a universal joint's two axes, ``x``/``y``/``z``
#: translations, ``e0``..``e3`` Euler parameters (e0 has no speed of its own; see
#: :func:`flexkane.model.coordinates.coordinate_names`).
SPATIAL_JOINT_DOFS = {"revolute": ("angle",), "prismatic": ("slide",), "cylindrical": ("angle", "slide"),
                      "universal": ("angle_1", "angle_2"), "planar": ("x", "y", "angle"),
                      "spherical": ("e0", "e1", "e2", "e3"),
                      "free": ("x", "y", "z", "e0", "e1", "e2", "e3"), "weld": ()}
#: Joint types and their coordinates' roles by number of dimensions.
JOINT_TYPES_BY_DIMENSION = {2: JOINT_TYPES, 3: SPATIAL_JOINT_TYPES}
JOINT_DOFS_BY_DIMENSION = {2: JOINT_DOFS, 3: SPATIAL_JOINT_DOFS}
#: Numbers of dimensions a model may have (2: planar chains, 3: spatial chains).
DIMENSIONS = (2, 3)
#: ``joint``: coordinates named after their joint and beam (``q_shoulder``, ``q_arm_1``);
#: ``sequential``: q1, q2, ... and u1, u2, ... in tree order (the chapter's naming).
NAMING_STYLES = ("joint", "sequential")
#: Letters of the body-fixed axes in an orientation's ``sequence``.
SEQUENCE_AXES = "xyz"
GRAVITY_MODELS = ("distributed", "midpoint")
ELASTIC_MODELS = ("strain-energy", "shear-moment")
FRAMES = ("ground", "local")
#: Integration methods of a run (the one list: validation, the command line and the integrators use
#: it); ``auto`` chooses one of them by a stiffness estimate.
INTEGRATION_METHODS = ("dop853", "radau")
METHODS = ("auto", *INTEGRATION_METHODS)
#: Frames in which the components of a distributed load are given.
DISTRIBUTED_FRAMES = ("beam", "ground")
#: Kinds of sensors (named outputs usable in effort expressions, :class:`Sensor`).
SENSOR_TYPES = ("tip_deflection", "tip_slope", "bending_moment", "strain", "twist", "position", "velocity",
                "acceleration", "joint_angle", "joint_rate")
#: Components of a point sensor, along the axes of its frame.
COMPONENTS = ("x", "y")
#: Components of a point sensor of a spatial model (``dimensions = 3``).
SPATIAL_COMPONENTS = ("x", "y", "z")
#: Bending planes of a spatial beam's sensors: deflection along the section's principal axis y_p or z_p.
BEAM_COMPONENTS = ("y", "z")


@dataclass
class RigidBody:
    """A rigid body, in the plane or in space.

    Parameters
    ----------
    name : str
        Unique name among bodies and beams.
    mass : Value
        Mass [kg].
    inertia : Value, or 3 Values, or 3 x 3 Values
        Planar: moment of inertia about the mass centre, about an axis normal to the plane [kg m^2].
        Spatial: the inertia tensor about the mass centre in the body axes [kg m^2], as three
        principal values ``(Ixx, Iyy, Izz)`` or a symmetric 3 x 3 ``((Ixx, Ixy, Ixz), (Ixy, Iyy, Iyz),
        (Ixz, Iyz, Izz))`` of tensor components (``Ixy = -int x y dm``); see :meth:`inertia_tensor`.
    points : dict of str to tuple of Value
        Named points in the body frame, relative to the mass centre [m]: (x, y), or (x, y, z) in space.
    outline : list of tuple of Value
        Closed polygon drawn in animations, in the body frame [m], 2 or 3 components a vertex; may
        be empty.
    """

    name: str
    mass: Value
    inertia: Value | tuple
    points: dict[str, tuple] = field(default_factory=dict)
    outline: list[tuple] = field(default_factory=list)

    def inertia_tensor(self) -> tuple:
        """The inertia tensor about the mass centre in the body axes, 3 x 3 [kg m^2].

        Returns
        -------
        tuple of 3 tuples of 3 Value
            The components as given (a principal form ``(Ixx, Iyy, Izz)`` gives zeros off the
            diagonal), rows ``x, y, z``; symmetric when the model is valid.

        Raises
        ------
        ModelError
            If ``inertia`` is neither three values nor a 3 x 3 table (a planar body's scalar).
        """
        from ..errors import ModelError

        inertia = self.inertia
        if isinstance(inertia, (list, tuple)) and len(inertia) == 3:
            if all(isinstance(row, (list, tuple)) and len(row) == 3 for row in inertia):
                return tuple(tuple(row) for row in inertia)
            if not any(isinstance(row, (list, tuple, dict)) for row in inertia):
                return ((inertia[0], 0, 0), (0, inertia[1], 0), (0, 0, inertia[2]))
        raise ModelError(f"bodies.{self.name}.inertia", "three principal values [Ixx, Iyy, Izz] or a 3x3 "
                         "symmetric tensor [[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]] [kg m^2]",
                         inertia)


@dataclass
class Orientation:
    """A constant orientation of a frame B relative to a frame A (spatial models).

    Exactly one form is given: a turn by ``angle`` about ``axis`` (components in A and B alike), or
    successive body-fixed turns by ``angles`` about the axes named by ``sequence`` (``"zyx"``: about
    z, then about the new y, then about the newest x). Direction cosines and Euler parameters follow
    from :mod:`flexkane.model.orientation`.

    Parameters
    ----------
    axis : (Value, Value, Value), optional
        Axis of the turn (normalized when used; not zero) [-].
    angle : Value, optional
        Angle of the turn about ``axis`` [rad].
    sequence : str, optional
        One to three letters among x, y, z.
    angles : list of Value, optional
        One angle per letter of ``sequence`` [rad].
    """

    axis: tuple | None = None
    angle: Value | None = None
    sequence: str | None = None
    angles: list | None = None


@dataclass
class ShapeSpec:
    """Choice of shape functions Phi_i (eq. 8.15) for one beam.

    Parameters
    ----------
    family : str
        Family name (``clamped-free`` is the chapter's, eq. 8.4).
    roots : list of float, optional
        Eigenvalue parameters used instead of the exact roots (the chapter's notebook types
        ``lambda1 = 1.875``).
    options : dict
        Family options (tip-mass ratios, expressions, ...).
    """

    family: str = "clamped-free"
    roots: list[float] | None = None
    options: dict = field(default_factory=dict)


@dataclass
class Beam:
    """A uniform Euler-Bernoulli beam described by assumed modes (eqs. 8.15, 8.16).

    The beam frame has its origin at the root (x = 0, the point Q of Fig. 8.2) and its x axis along
    the undeformed beam. A point at distance x from the root is displaced by
    ``y(x, t) = sum_i Phi_i(x) q_i(t)`` along the beam frame's y axis. With ``rotary_inertia`` it is
    a Rayleigh beam: the section at x turns with the frame and the slope ``y'(x, t)``, and its
    rotation carries kinetic energy.

    Parameters
    ----------
    name : str
        Unique name among bodies and beams.
    L : Value
        Length [m].
    EI : Value
        Flexural rigidity [N m^2].
    rho : Value
        Mass per unit length [kg/m].
    n_modes : int
        Number of transverse shape functions n.
    shape : ShapeSpec
        Shape-function family.
    damping : list of Value
        Modal damping ratios zeta_i [-], empty for none.
    gravity : str
        ``distributed`` (the weight integrated along the beam) or ``midpoint`` (the whole weight at
        the deformed midpoint, eqs. 8.19, 8.33, 8.34, as the chapter's notebook does; in 3D the
        midpoint deflected in both planes).
    elastic_forces : str
        ``strain-energy`` (eqs. 8.31-8.32, -sum_j H_ij q_j) or ``shear-moment`` (eq. 8.28 as the
        notebook evaluates it, boundary terms kept; in 3D in each bending plane, torsion and stretch
        keeping their strain-energy forces: :mod:`flexkane.kane.spatial_beam_notebook`).
    geometric_stiffening : bool
        Keep the foreshortening of the beam axis in the kinematics.
    EA : Value, optional
        Axial stiffness [N], required when ``n_axial > 0``.
    n_axial : int
        Number of axial shape functions.
    axial_shape : ShapeSpec, optional
        Axial shape-function family.
    rotary_inertia : Value, optional
        Mass moment of inertia of the section about its neutral axis per unit length, ``rho I``
        [kg m] (Rayleigh beam); absent, the sections' rotation carries no kinetic energy
        (Euler-Bernoulli beam).
    EI_y, EI_z : Value, optional
        Spatial beams (``dimensions = 3``, where ``EI`` and ``n_modes`` are not used): flexural
        rigidities [N m^2] about the section's principal axes y_p and z_p. The deflection
        ``w(x) = sum_j Phi_j^z q_zj`` along z_p bends about y_p (``EI_y``); the deflection
        ``v(x) = sum_i Phi_i^y q_yi`` along y_p bends about z_p (``EI_z``, the planar beam's EI).
    n_modes_y, n_modes_z : int
        Numbers of shape functions of v (along y_p) and of w (along z_p).
    shape_y, shape_z : ShapeSpec, optional
        Their shape-function families.
    GJ : Value, optional
        Torsional rigidity [N m^2], required with ``n_torsion > 0``.
    rho_Ip : Value, optional
        Polar mass moment of inertia of the section per unit length [kg m]; with it the twist rate
        of the sections carries kinetic energy ``1/2 int rho_Ip (w_x + theta')^2 dx``.
    n_torsion : int
        Number of torsion shape functions ``Theta_k`` (twist ``theta(x) = sum_k Theta_k q_tk``).
    torsion_shape : ShapeSpec, optional
        Torsion shape-function family (``torsion-clamped-free`` ...).
    principal_angle : Value, optional
        Angle [rad] of the principal axes (y_p, z_p) from the beam frame's (y, z), about x.
    rho_Iy, rho_Iz : Value, optional
        Spatial Rayleigh beam: mass moments of inertia of the section per unit length about y_p and
        z_p [kg m]; the sections turn about z_p with the slope ``v'`` and about y_p with ``-w'``, and
        those turns carry kinetic energy ``1/2 int rho_Iz (w.z_p + v_t')^2 + rho_Iy (w.y_p - w_t')^2 dx``
        (``rho_Iz`` is the planar ``rotary_inertia``).
    damping_y, damping_z, torsion_damping, axial_damping : list of Value
        Spatial beams: modal damping ratios zeta [-] of the shape functions of v, w, the twist and
        the axial stretch (one value for all of a kind, or one per function), empty for none.
    static_corrections : bool
        Where the beam carries a joint, a load, a spring or a loop joint at its tip, the last
        functions of each basis (bending: two, torsion and axial: one; at most all but the first)
        are its static deflection, twist and stretch under a unit tip force, moment, torque and
        axial force
        (:mod:`flexkane.modes.static_correction`); ``False`` keeps the family's functions only.
    """

    name: str
    L: Value
    EI: Value
    rho: Value
    n_modes: int
    shape: ShapeSpec = field(default_factory=ShapeSpec)
    damping: list[Value] = field(default_factory=list)
    gravity: str = "distributed"
    elastic_forces: str = "strain-energy"
    geometric_stiffening: bool = False
    EA: Value | None = None
    n_axial: int = 0
    axial_shape: ShapeSpec | None = None
    rotary_inertia: Value | None = None
    EI_y: Value | None = None
    EI_z: Value | None = None
    n_modes_y: int = 0
    n_modes_z: int = 0
    shape_y: ShapeSpec | None = None
    shape_z: ShapeSpec | None = None
    GJ: Value | None = None
    rho_Ip: Value | None = None
    n_torsion: int = 0
    torsion_shape: ShapeSpec | None = None
    principal_angle: Value | None = None
    rho_Iy: Value | None = None
    rho_Iz: Value | None = None
    damping_y: list[Value] = field(default_factory=list)
    damping_z: list[Value] = field(default_factory=list)
    torsion_damping: list[Value] = field(default_factory=list)
    axial_damping: list[Value] = field(default_factory=list)
    static_corrections: bool = True

    def modes_text(self) -> str:
        """The beam's shape functions in words (``3 clamped-free + 1 axial, Rayleigh``; in 3D
        ``2 y clamped-free + 2 z clamped-free + 1 torsion, Rayleigh``, or ``Rayleigh in y`` when
        only the turns of one bending plane carry kinetic energy)."""
        if self.EI is None:    # a spatial beam (dimensions = 3)
            parts = [f"{n} {key} {shape.family}" for key, n, shape in (("y", self.n_modes_y, self.shape_y),
                                                                       ("z", self.n_modes_z, self.shape_z)) if n]
            parts += [f"{n} {what}" for n, what in ((self.n_torsion, "torsion"), (self.n_axial, "axial")) if n]
            planes = self.rayleigh_planes()
            rayleigh = "" if not planes else ", Rayleigh" if len(planes) == 2 else f", Rayleigh in {planes[0]}"
            return " + ".join(parts) + rayleigh
        return (f"{self.n_modes} {self.shape.family}" + (f" + {self.n_axial} axial" if self.n_axial else "")
                + (", Rayleigh" if self.rayleigh else ""))

    @property
    def rayleigh(self) -> bool:
        """Whether the sections' rotation enters the equations: ``rotary_inertia`` given and not a
        literal zero (a literal zero adds no terms, as every zero field does); for a spatial beam
        ``rho_Iz`` or ``rho_Iy`` so given (:meth:`rayleigh_planes`)."""
        return nonzero_field(self.rotary_inertia) or bool(self.rayleigh_planes())

    def rayleigh_planes(self) -> list[str]:
        """The bending planes of a spatial beam whose sections' turns carry kinetic energy: ``"y"``
        (v along y_p, the sections turn about z_p) with ``rho_Iz``, ``"z"`` (w along z_p, about
        y_p) with ``rho_Iy``, each given and not a literal zero; empty for a planar beam."""
        return [plane for plane, value in (("y", self.rho_Iz), ("z", self.rho_Iy)) if nonzero_field(value)]


def nonzero_field(value) -> bool:
    """Whether an optional field adds terms: given and not a literal zero."""
    return value is not None and not (isinstance(value, (int, float)) and not isinstance(value, bool)
                                      and value == 0)


@dataclass
class Driver:
    """A prescribed joint coordinate.

    Exactly one of ``coordinate`` and ``speed`` is given, as an expression of t [s].

    Parameters
    ----------
    coordinate : Value, optional
        The coordinate as a function of time [m or rad].
    speed : Value, optional
        Its time derivative [m/s or rad/s]; the coordinate is then integrated from its initial value.
    """

    coordinate: Value | None = None
    speed: Value | None = None


@dataclass
class Joint:
    """A joint between a parent attachment and a child link.

    Parameters
    ----------
    name : str
        Unique joint name; generalized coordinates are named after it.
    type : str
        ``free`` (3 DoF, eqs. 8.10-8.14), ``revolute``, ``prismatic`` or ``weld``.
    parent : str
        ``ground``, a body name or a beam name.
    child : str
        A body name or a beam name.
    parent_point : str, optional
        Name of a point of the parent body.
    parent_position : tuple of Value, optional
        Position on the ground [m] (parent ``ground`` only), 2 or 3 components.
    station : Value, optional
        Distance x from the root of the parent beam [m] (parent a beam only); the child follows the
        beam's deflected position and slope there.
    child_point : str, optional
        Point of the child body that sits at the joint; the mass centre when omitted.
        A beam child is always attached at its root.
    angle : Value
        Planar: constant angle of the child frame relative to the attachment frame [rad] (added to
        the joint angle of revolute and free joints).
    axis : Value or (Value, Value, Value)
        Planar: direction of a prismatic joint's slide, as an angle in the attachment frame [rad].
        Spatial: a vector in the joint frame J_p [-] (revolute: rotation axis; prismatic: slide
        direction; cylindrical: both; planar: the plane's normal), normalized when used.
    axes : list of two (Value, Value, Value), optional
        Spatial universal joint: the first axis fixed in J_p, the second fixed in J_c [-],
        perpendicular in the reference configuration.
    orientation : Orientation, optional
        Spatial: the orientation of the joint frame J_p relative to the parent link's frame
        (identity when omitted).
    child_orientation : Orientation, optional
        Spatial: the orientation of the joint frame J_c relative to the child link's frame
        (identity when omitted). With all joint coordinates zero, J_c coincides with J_p.
    coordinates, speeds : list of str, optional
        Names of the joint's generalized coordinates and speeds.
    stiffness, damping : Value, optional
        Linear spring [N m/rad or N/m] and damper [N m s/rad or N s/m] acting on the joint
        coordinate of a revolute or prismatic joint.
    rest : Value
        Coordinate at which the spring is relaxed [rad or m]; an expression of t, the state, sensors
        or controllers makes the spring an actuator (its power is counted in the work W).
    torque : Value, optional
        Actuator torque [N m] (revolute) or force [N] (prismatic) acting along the joint coordinate
        between parent and child, an expression of t, the coordinates and speeds, sensors and
        controllers (state feedback).
    driver : Driver, optional
        Prescribed motion of the (single) joint coordinate.
    """

    name: str
    type: str
    parent: str
    child: str
    parent_point: str | None = None
    parent_position: tuple | None = None
    station: Value | None = None
    child_point: str | None = None
    angle: Value = 0
    axis: Value | tuple = 0
    coordinates: list[str] | None = None
    speeds: list[str] | None = None
    stiffness: Value | None = None
    damping: Value | None = None
    rest: Value = 0
    torque: Value | None = None
    driver: Driver | None = None
    axes: list | None = None
    orientation: Orientation | None = None
    child_orientation: Orientation | None = None


@dataclass
class Gravity:
    """Uniform gravity.

    Parameters
    ----------
    g : Value
        Magnitude [m/s^2].
    direction : tuple of Value
        Direction in the ground frame (normalised when used), e.g. ``(0, -1)`` for -j0; three
        components in a spatial model.
    """

    g: Value
    direction: tuple


@dataclass
class Load:
    """A force and/or torque applied to a body point or a beam station.

    Parameters
    ----------
    name : str
        Unique load name.
    body : str
        Body or beam name.
    point : str, optional
        Point of a body; the mass centre when omitted.
    station : Value, optional
        Station x on a beam [m].
    force : tuple of Value, optional
        Force components [N] (3 in a spatial model): expressions of t, the coordinates and speeds,
        sensors and controllers.
    torque : Value or (Value, Value, Value), optional
        Torque about the normal to the plane [N m], an expression like the force components; a
        spatial model's is a vector of three components.
    frame : str
        ``ground`` or ``local`` (components along the body or beam-station frame).
    """

    name: str
    body: str
    point: str | None = None
    station: Value | None = None
    force: tuple | None = None
    torque: Value | tuple | None = None
    frame: str = "ground"


@dataclass
class DistributedLoad:
    """A force per unit length along a beam, an expression of x, t and the parameters.

    Its generalized active forces are ``F_r = int_0^L v_P,r . f(x, t) dx`` (the distributed
    analogue of eq. 8.24, as in eq. 8.28), with ``v_P,r`` the partial velocities of the beam point
    at x (eq. 8.18); see :mod:`flexkane.kane.distributed_loads` for how the integral over x is done.

    Parameters
    ----------
    name : str
        Unique name.
    beam : str
        Name of the loaded beam.
    fx, fy : Value
        Components of the force per unit length [N/m], expressions of ``x`` (distance from the
        beam's root [m]), ``t`` [s] and the parameters; an omitted component is zero.
    frame : str
        ``beam`` (components along the axes of the undeformed beam's frame, which turn with the
        beam's root) or ``ground`` (along i0, j0, and k0 in a spatial model).
    quadrature_nodes : int
        Gauss-Legendre nodes along the beam for the terms of the load that do not separate into a
        function of t times a function of x.
    """

    name: str
    beam: str
    fx: Value = 0
    fy: Value = 0
    frame: str = "beam"
    quadrature_nodes: int = 16
    #: Component along the beam frame's z axis (or k0) [N/m], spatial models only.
    fz: Value = 0


@dataclass
class PointSpring:
    """A linear spring and damper between two points.

    Parameters
    ----------
    name : str
        Unique name.
    body_a, body_b : str
        ``ground``, a body or a beam at each end.
    point_a, point_b : str, optional
        Points of bodies (the mass centre when omitted).
    station_a, station_b : Value, optional
        Stations x on beams [m]: the end follows the beam's deflected position there (eq. 8.18).
    position_a, position_b : tuple of Value, optional
        Positions on the ground [m] (3 components in a spatial model).
    stiffness : Value
        [N/m].
    damping : Value
        [N s/m].
    rest_length : Value
        [m].
    """

    name: str
    body_a: str
    body_b: str
    point_a: str | None = None
    point_b: str | None = None
    position_a: tuple | None = None
    position_b: tuple | None = None
    stiffness: Value = 0
    damping: Value = 0
    rest_length: Value = 0
    station_a: Value | None = None
    station_b: Value | None = None


@dataclass
class LoopConstraint:
    """A joint that closes a kinematic loop (its two sides already hang from the tree).

    A ``revolute`` loop joint keeps point a and point b together (two scalar constraints); a
    ``prismatic`` one keeps point b on the line through point a along ``axis`` (in frame a) and the
    angle of frame b relative to frame a equal to ``angle`` (two scalar constraints).

    In a spatial model (``dimensions = 3``, :mod:`flexkane.kane.spatial_constraints`) the types are
    ``spherical`` (point b at point a: three scalar constraints), ``point_on_line`` (point b on the
    line through point a along ``axis``, a 3-vector of numbers in frame a: two) and ``weld`` (frame b
    at frame a turned by ``orientation``: six).

    Parameters
    ----------
    name : str
        Unique name.
    type : str
        ``revolute`` or ``prismatic`` (planar); ``spherical``, ``point_on_line`` or ``weld`` (spatial).
    body_a, body_b : str
        ``ground``, a body or a beam.
    point_a, point_b : str, optional
        Points of bodies (the mass centre when omitted).
    station_a, station_b : Value, optional
        Stations on beams [m].
    position_a, position_b : tuple of Value, optional
        Positions on the ground [m].
    axis : Value
        Direction of the slide in frame a [rad] (prismatic); in a spatial model the line's
        direction ``[x, y, z]`` in frame a [-] (point_on_line).
    angle : Value
        Angle of frame b relative to frame a [rad] (prismatic).
    dependent : list of str, optional
        Names of the generalized speeds made dependent by this constraint (chosen automatically,
        by pivoting on the constraint matrix at the initial configuration, when omitted).
    stabilization : Value
        Rate [1/s] at which a drift of the constraint is driven back to zero (Baumgarte-type
        velocity stabilization, ``Phi' = -rate * Phi``); 0 keeps the exact velocity constraint.
    orientation : Orientation, optional
        Spatial ``weld``: the orientation of frame b relative to frame a that the loop keeps
        (identity when omitted).
    """

    name: str
    type: str
    body_a: str
    body_b: str
    point_a: str | None = None
    point_b: str | None = None
    station_a: Value | None = None
    station_b: Value | None = None
    position_a: tuple[Value, Value] | None = None
    position_b: tuple[Value, Value] | None = None
    axis: Value = 0
    angle: Value = 0
    dependent: list[str] | None = None
    stabilization: Value = 0.0
    orientation: Orientation | None = None


@dataclass
class Simulation:
    """Default settings of a run.

    Parameters
    ----------
    t_end : float, optional
        End time [s]; required by ``run`` when the command line does not give it.
    dt_out : float, optional
        Output interval [s]; t_end / 100 when omitted.
    rtol, atol : float
        Integrator tolerances [-].
    method : str
        ``auto`` or a method name.
    max_steps : int, optional
        Most integration steps of a run; 1,000,000 when omitted.
    deflection_warning : float
        A run warns when a beam's transverse deflection exceeds this fraction of its length [-]
        (the assumed modes of eq. 8.15 describe small deflections).
    spin_warning : float
        A run warns when a beam without ``geometric_stiffening`` turns faster than this fraction
        of its first bending frequency [-] (the linear modes then miss the centrifugal stiffening).
    """

    t_end: float | None = None
    dt_out: float | None = None
    rtol: float = 1e-8
    atol: float = 1e-10
    method: str = "auto"
    max_steps: int | None = None
    deflection_warning: float = 0.1
    spin_warning: float = 0.1


@dataclass
class Sensor:
    """A named output of the motion, usable in effort expressions (feedback) and written as the
    output column ``sensor_<name>``.

    Kinds (``type``) and their fields:

    * ``tip_deflection`` [m], ``tip_slope`` [rad]: ``y(L) = sum_i Phi_i(L) q_i`` and ``y'(L)`` of
      ``beam``, in the beam frame;
    * ``bending_moment`` [N m]: ``EI y''(x)`` of ``beam`` at ``station`` x;
      ``strain`` [-]: ``-distance * y''(x)`` there, ``distance`` [m] from the neutral axis along
      the beam frame's y axis (positive on the side y > 0, which a positive curvature compresses);
    * ``position`` [m], ``velocity`` [m/s], ``acceleration`` [m/s^2]: ``component`` (``x`` or
      ``y``) of the point ``point`` of body ``body`` (the mass centre when omitted), or of station
      ``station`` of beam ``body``, along the ground axes (``frame = "ground"``; the position from
      the ground origin) or along the axes of the body or beam-station frame (``frame = "local"``,
      a sensor mounted on the body). Acceleration sensors depend on u': they are outputs only and
      may not be used in efforts or controllers;
    * ``joint_angle`` [rad or m], ``joint_rate`` [rad/s or m/s]: the coordinate and speed of a
      revolute or prismatic ``joint``.

    In a spatial model (``dimensions = 3``) point sensors have a third ``component``, ``z``; the
    beam sensors of a spatial beam name their bending plane by ``component``: ``y`` for the
    deflection ``v = sum Phi^y_i q_yi`` along the section's principal axis y_p (slope v', bending
    moment ``EI_z v''``, strain ``-distance v''`` with distance along y_p), ``z`` for
    ``w = sum Phi^z_j q_zj`` along z_p (``EI_y w''``, distance along z_p); ``twist`` [rad] is the
    twist ``theta(x) = sum Theta_k q_tk`` of the section at ``station`` (spatial beams only).

    Parameters
    ----------
    name : str
        Unique name among sensors, controllers, their states, parameters and coordinates.
    type : str
        One of :data:`SENSOR_TYPES`.
    beam, body, point, joint : str, optional
        What is measured (see above).
    station : Value, optional
        Distance x from a beam's root [m].
    distance : Value, optional
        Distance from the neutral axis [m] (``strain``).
    frame : str
        ``ground`` or ``local`` (point sensors).
    component : str, optional
        ``x``, ``y`` (``z`` in 3D) for point sensors; ``y`` or ``z`` (the bending plane) for the
        beam sensors of a spatial beam.
    """

    name: str
    type: str
    beam: str | None = None
    body: str | None = None
    point: str | None = None
    joint: str | None = None
    station: Value | None = None
    distance: Value | None = None
    frame: str = "ground"
    component: str | None = None


@dataclass
class Controller:
    """First-order controller states and a controller output, integrated with the motion.

    Each state z has its rate ``z' = states[z]``, an expression of t, the parameters, the
    coordinates and speeds, sensors, controller states and controller outputs. The output (optional)
    is an expression of the same names, available under the controller's name in efforts and other
    controllers, saturated to ``[min, max]`` when they are given, and written as the output column
    ``controller_<name>``. The states extend the state vector after the speeds:
    ``y = [q, u, controller states]`` in the order of the controllers' names, then of each
    controller's states as listed.

    Parameters
    ----------
    name : str
        Unique name (the name of the output in expressions).
    states : dict of str to Value
        State name -> its rate [state unit / s].
    initial : dict of str to Value
        State name -> initial value [state unit]; 0 for a state not listed.
    output : Value, optional
        The controller's output [unit of the effort it feeds].
    min, max : Value, optional
        Saturation of the output (numbers or expressions of the parameters).
    """

    name: str
    states: dict[str, Value] = field(default_factory=dict)
    initial: dict[str, Value] = field(default_factory=dict)
    output: Value | None = None
    min: Value | None = None
    max: Value | None = None
