"""The chain: joints in tree order, generalized coordinates and speeds, kinematic equations.

Generalized coordinates q and speeds u are introduced joint by joint, from the ground outwards
(children of a link in the order of their joint names, so that the order in which a file lists its
parts does not matter), each beam's modal coordinates right after the joint that carries it:

* free joint (eqs. 8.10-8.14): q = (x, y, angle) of the child point in the parent attachment frame,
  u1, u2 = components of its velocity relative to that frame along the child frame's axes,
  u3 = angle rate; so ``x' = u1 cos(a) - u2 sin(a)``, ``y' = u1 sin(a) + u2 cos(a)``, ``a' = u3``;
* revolute and prismatic joints: one coordinate, u = q';
* beam shape functions (eq. 8.16): ``u_{i} = q_{i}'``; axial shape functions likewise;
* in a spatial chain (``dimensions = 3``) the kinematic equations of each joint type are those of
  :mod:`flexkane.kane.spatial_joints`: spherical and free joints have four Euler parameters and
  three angular speeds, so the chain has more coordinates than speeds (``Coordinate.u`` is None
  for e0; :attr:`Chain.u` lists the speeds).

A driven joint coordinate is not free: with a coordinate law q(t), q and u leave the state; with a
speed law, q stays in the state with q' = law(t) and u leaves it. A coordinate law may also read the
state (:mod:`flexkane.kane.driver_laws`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..model import Model
from ..model.coordinates import BEAM_ROLES, coordinate_names, tree_order
from ..model.parts import Joint
from ..model.values import TIME, FieldSymbols, GeneratedSymbol
from .driver_laws import reads_state
from .intermediates import NAME_ABOVE, Intermediates
from .spatial_joints import kinematic_equations

__all__ = ["BEAM_ROLES", "Chain", "Coordinate", "build_chain"]


@dataclass
class Coordinate:
    """One generalized coordinate and its speed.

    Attributes
    ----------
    q, u : sympy.Symbol
        Coordinate and speed; ``u`` is None for a coordinate without a speed of its own (the
        scalar Euler parameter e0 of a spherical or free joint in 3D).
    owner : str
        Joint or beam name.
    role : str
        ``x``, ``y``, ``angle``, ``slide``, ``mode``, ``axial``.
    index : int
        Mode index (1-based) for beam coordinates, else 0.
    driver : str or None
        ``coordinate`` or ``speed`` when prescribed.
    law : sympy.Expr or None
        The prescribed coordinate or speed as an expression of t (or of the state when
        ``state_law``: parsed once the signals are known, :mod:`flexkane.kane.driver_laws`).
    state_law : bool
        The law reads coordinates, sensors or controller states (a planar model's driver).
    """

    q: sp.Symbol
    u: sp.Symbol
    owner: str
    role: str
    index: int = 0
    driver: str | None = None
    law: sp.Expr | None = None
    state_law: bool = False


@dataclass
class Chain:
    """A model's tree of joints with its coordinates and kinematic equations.

    Attributes
    ----------
    model : Model
    symbols : FieldSymbols
        Symbols of parameters and field values.
    joints : list of Joint
        In tree order.
    coordinates : list of Coordinate
        All coordinates, in state order (driven ones included).
    qdot : dict of Symbol to Expr
        Kinematic differential equations ``q' = K(q, t) u + k(q, t)``, for every coordinate
        (before drivers are substituted).
    ud : dict of Symbol to Symbol
        Symbol standing for the time derivative of each speed.
    intermediates : Intermediates
        Named intermediate quantities of the kinematics, in evaluation order.
    controller_states : list of sympy.Symbol
        Controller states z, in state order (:mod:`flexkane.kane.controllers`).
    controller_rates : dict of Symbol to Expr
        ``z' = rate`` of each controller state.
    sensors : dict of str to Expr
        Every sensor by name (:mod:`flexkane.kane.sensors`).
    """

    model: Model
    symbols: FieldSymbols
    joints: list[Joint] = field(default_factory=list)
    coordinates: list[Coordinate] = field(default_factory=list)
    qdot: dict = field(default_factory=dict)
    ud: dict = field(default_factory=dict)
    t: sp.Symbol = TIME
    intermediates: Intermediates = None
    controller_states: list = field(default_factory=list)
    controller_rates: dict = field(default_factory=dict)
    sensors: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.intermediates is None:
            self.intermediates = Intermediates(self.qdot, self.t)

    # ------------------------------------------------------------------ lookups
    def of(self, owner: str, role: str | None = None) -> list[Coordinate]:
        """Coordinates of a joint or a beam (optionally of one role)."""
        return [c for c in self.coordinates if c.owner == owner and (role is None or c.role == role)]

    def joint_coordinates(self, joint: str) -> list[Coordinate]:
        """Coordinates of a joint, without those of a beam of the same name (a joint ``rod``
        carrying the beam ``rod``)."""
        return [c for c in self.of(joint) if c.role not in BEAM_ROLES]

    @property
    def q(self) -> list[sp.Symbol]:
        return [c.q for c in self.coordinates]

    @property
    def u(self) -> list[sp.Symbol]:
        return [c.u for c in self.coordinates if c.u is not None]

    @property
    def speed_coordinates(self) -> list[Coordinate]:
        """The coordinates that carry a speed, in the order of :attr:`u`."""
        return [c for c in self.coordinates if c.u is not None]

    @property
    def dimensions(self) -> int:
        """2 for a planar chain, 3 for a spatial one."""
        return getattr(self.model, "dimensions", 2)

    def joint_of(self, link: str) -> Joint:
        """The joint that carries a link."""
        return next(j for j in self.joints if j.child == link)

    def beam_modes(self, beam: str) -> list[sp.Symbol]:
        return [c.q for c in self.of(beam, "mode")]

    def beam_axial(self, beam: str) -> list[sp.Symbol]:
        return [c.q for c in self.of(beam, "axial")]

    # ------------------------------------------------------------------ calculus
    def dt(self, expr: sp.Expr, with_ud: bool = False) -> sp.Expr:
        """Total time derivative of an expression of q, u, t and intermediates, by the chain rule.

        Parameters
        ----------
        expr : sympy.Expr
        with_ud : bool
            Include the terms in u' (symbols ``ud``); otherwise they are left out, which gives the
            part of an acceleration that does not multiply u'.
        """
        return self.intermediates.rate(expr, self.ud if with_ud else None)

    def partial(self, expr: sp.Expr, u: sp.Symbol) -> sp.Expr:
        """Partial derivative with respect to a speed (a partial velocity, eq. 8.20), through the
        intermediates."""
        return self.intermediates.partial(expr, u)

    def name(self, expr: sp.Expr, label: str, above: int = NAME_ABOVE) -> sp.Expr:
        """``expr``, or an intermediate standing for it when it has more than ``above`` operations
        (see :mod:`.intermediates`)."""
        return self.intermediates.name(expr, label, above)


def _tree_order(model: Model) -> list[Joint]:
    return tree_order(model)


def build_chain(model: Model) -> Chain:
    """Order the joints, name the coordinates and write the kinematic equations.

    Parameters
    ----------
    model : Model
        A validated model.

    Returns
    -------
    Chain
    """
    chain = Chain(model=model, symbols=FieldSymbols(model))
    chain.joints = _tree_order(model)
    names = coordinate_names(model)   # names checked, initial conditions too
    for c in names:
        u = GeneratedSymbol(c.u, real=True) if c.u is not None else None
        chain.coordinates.append(Coordinate(GeneratedSymbol(c.q, real=True), u, c.owner, c.role, c.index))
    for coord in chain.speed_coordinates:
        chain.ud[coord.u] = GeneratedSymbol(f"{coord.u.name}'", real=True)
    for joint in chain.joints:
        coords = chain.joint_coordinates(joint.name) if chain.dimensions == 3 else chain.of(joint.name)
        if chain.dimensions == 3:
            chain.qdot.update(kinematic_equations(joint, coords))
        elif joint.type == "free":
            cx, cy, ca = coords
            angle = ca.q + chain.symbols.value(f"joints.{joint.name}.angle", joint.angle,
                                               f"theta_{joint.name}")
            c, s = sp.cos(angle), sp.sin(angle)
            chain.qdot[cx.q] = cx.u * c - cy.u * s
            chain.qdot[cy.q] = cx.u * s + cy.u * c
            chain.qdot[ca.q] = ca.u
        else:
            for coord in coords:
                chain.qdot[coord.q] = coord.u
        if joint.driver is not None:
            coord = coords[0]
            path = f"joints.{joint.name}.driver"
            if joint.driver.coordinate is not None:
                coord.driver = "coordinate"
                coord.state_law = reads_state(joint.driver.coordinate, model.parameters)
                if not coord.state_law:   # a law of the state is parsed with the signals (driver_laws)
                    coord.law = chain.symbols.time_function(f"{path}.coordinate", joint.driver.coordinate)
            else:
                coord.driver = "speed"
                coord.state_law = reads_state(joint.driver.speed, model.parameters)
                if not coord.state_law:
                    coord.law = chain.symbols.time_function(f"{path}.speed", joint.driver.speed)
        if joint.child in model.beams:
            for coord in chain.of(joint.child):
                chain.qdot[coord.q] = coord.u
    return chain
