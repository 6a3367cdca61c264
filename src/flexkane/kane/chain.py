"""The chain: joints in tree order, generalized coordinates and speeds, kinematic equations.

Generalized coordinates q and speeds u are introduced joint by joint, from the ground outwards
(children of a link in the order of their joint names, so that the order in which a file lists its
parts does not matter), each beam's modal coordinates right after the joint that carries it:

* free joint (eqs. 8.10-8.14): q = (x, y, angle) of the child point in the parent attachment frame,
  u1, u2 = components of its velocity relative to that frame along the child frame's axes,
  u3 = angle rate; so ``x' = u1 cos(a) - u2 sin(a)``, ``y' = u1 sin(a) + u2 cos(a)``, ``a' = u3``;
* revolute and prismatic joints: one coordinate, u = q';
* beam shape functions (eq. 8.16): ``u_{i} = q_{i}'``; axial shape functions likewise.

A driven joint coordinate is not free: with a coordinate law q(t), q and u leave the state; with a
speed law, q stays in the state with q' = law(t) and u leaves it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..errors import ModelError
from ..model import Model
from ..model.parts import JOINT_DOFS, Joint
from ..model.values import TIME, FieldSymbols, GeneratedSymbol

__all__ = ["Chain", "Coordinate", "build_chain"]


@dataclass
class Coordinate:
    """One generalized coordinate and its speed.

    Attributes
    ----------
    q, u : sympy.Symbol
        Coordinate and speed.
    owner : str
        Joint or beam name.
    role : str
        ``x``, ``y``, ``angle``, ``slide``, ``mode``, ``axial``.
    index : int
        Mode index (1-based) for beam coordinates, else 0.
    driver : str or None
        ``coordinate`` or ``speed`` when prescribed.
    law : sympy.Expr or None
        The prescribed coordinate or speed as an expression of t.
    """

    q: sp.Symbol
    u: sp.Symbol
    owner: str
    role: str
    index: int = 0
    driver: str | None = None
    law: sp.Expr | None = None


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
    """

    model: Model
    symbols: FieldSymbols
    joints: list[Joint] = field(default_factory=list)
    coordinates: list[Coordinate] = field(default_factory=list)
    qdot: dict = field(default_factory=dict)
    ud: dict = field(default_factory=dict)
    t: sp.Symbol = TIME

    # ------------------------------------------------------------------ lookups
    def of(self, owner: str, role: str | None = None) -> list[Coordinate]:
        """Coordinates of a joint or a beam (optionally of one role)."""
        return [c for c in self.coordinates if c.owner == owner and (role is None or c.role == role)]

    @property
    def q(self) -> list[sp.Symbol]:
        return [c.q for c in self.coordinates]

    @property
    def u(self) -> list[sp.Symbol]:
        return [c.u for c in self.coordinates]

    def beam_modes(self, beam: str) -> list[sp.Symbol]:
        return [c.q for c in self.of(beam, "mode")]

    def beam_axial(self, beam: str) -> list[sp.Symbol]:
        return [c.q for c in self.of(beam, "axial")]

    # ------------------------------------------------------------------ calculus
    def dt(self, expr: sp.Expr, with_ud: bool = False) -> sp.Expr:
        """Total time derivative of an expression of q, u and t, by the chain rule.

        Parameters
        ----------
        expr : sympy.Expr
        with_ud : bool
            Include the terms in u' (symbols ``ud``); otherwise they are left out, which gives the
            part of an acceleration that does not multiply u'.
        """
        expr = sp.sympify(expr)
        free = expr.free_symbols
        terms = []
        for q, qd in self.qdot.items():
            if q in free:
                terms.append(sp.diff(expr, q) * qd)
        if with_ud:
            for u, ud in self.ud.items():
                if u in free:
                    terms.append(sp.diff(expr, u) * ud)
        if self.t in free:
            terms.append(sp.diff(expr, self.t))
        return sp.Add(*terms)


def _tree_order(model: Model) -> list[Joint]:
    by_parent: dict[str, list[Joint]] = {}
    for joint in model.joints.values():
        by_parent.setdefault(joint.parent, []).append(joint)
    order: list[Joint] = []
    stack = ["ground"]
    while stack:
        parent = stack.pop(0)
        for joint in sorted(by_parent.get(parent, []), key=lambda j: j.name):
            order.append(joint)
            stack.append(joint.child)
    return order


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
    raw: list[tuple[str, str, int, str, str]] = []  # (owner, role, index, q name, u name)
    for joint in chain.joints:
        roles = JOINT_DOFS[joint.type]
        for k, role in enumerate(roles):
            suffix = "" if len(roles) == 1 else f"_{role}"
            qn = joint.coordinates[k] if joint.coordinates else f"q_{joint.name}{suffix}"
            un = joint.speeds[k] if joint.speeds else f"u_{joint.name}{suffix}"
            raw.append((joint.name, role, 0, qn, un))
        if joint.child in model.beams:
            beam = model.beams[joint.child]
            for i in range(1, beam.n_modes + 1):
                raw.append((beam.name, "mode", i, f"q_{beam.name}_{i}", f"u_{beam.name}_{i}"))
            for k in range(1, beam.n_axial + 1):
                raw.append((beam.name, "axial", k, f"s_{beam.name}_{k}", f"v_{beam.name}_{k}"))
    if model.naming == "sequential":
        raw = [(o, r, i, f"q{n + 1}", f"u{n + 1}") for n, (o, r, i, _, _) in enumerate(raw)]
    seen: dict[str, str] = {}
    for owner, role, index, qn, un in raw:
        for name in (qn, un):
            if name in seen or name in model.parameters or name in ("t", "pi"):
                raise ModelError(f"joints.{owner}" if role not in ("mode", "axial") else f"beams.{owner}",
                                 "coordinate and speed names unique and distinct from parameters", name)
            seen[name] = owner
        chain.coordinates.append(Coordinate(GeneratedSymbol(qn, real=True), GeneratedSymbol(un, real=True),
                                            owner, role, index))
    for coord in chain.coordinates:
        chain.ud[coord.u] = GeneratedSymbol(f"{coord.u.name}'", real=True)
    for joint in chain.joints:
        coords = chain.of(joint.name)
        if joint.type == "free":
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
                coord.law = chain.symbols.time_function(f"{path}.coordinate", joint.driver.coordinate)
            else:
                coord.driver = "speed"
                coord.law = chain.symbols.time_function(f"{path}.speed", joint.driver.speed)
        if joint.child in model.beams:
            for coord in chain.of(joint.child):
                chain.qdot[coord.q] = coord.u
    names = {c.q.name for c in chain.coordinates} | {c.u.name for c in chain.coordinates}
    for key in model.initial:
        if key not in names:
            import difflib

            close = difflib.get_close_matches(key, sorted(names), n=1, cutoff=0.5)
            raise ModelError(f"initial.{key}", "the name of a generalized coordinate or speed of this model"
                             f" ({', '.join(sorted(names))})", key,
                             f"did you mean {close[0]!r}?" if close else None)
    for coord in chain.coordinates:
        if coord.driver == "coordinate" and coord.q.name in model.initial:
            raise ModelError(f"initial.{coord.q.name}", "no initial value for a coordinate prescribed by a driver",
                             model.initial[coord.q.name])
        if coord.driver is not None and coord.u.name in model.initial:
            raise ModelError(f"initial.{coord.u.name}", "no initial value for a speed prescribed by a driver",
                             model.initial[coord.u.name])
    return chain
