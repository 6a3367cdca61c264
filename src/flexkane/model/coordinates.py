"""The generalized coordinates of a model's chain, by name, without SymPy.

:func:`coordinate_names` orders the joints from the ground, names every coordinate and speed (joint
coordinates, then the modal coordinates of the beam a joint carries) and checks the names and the
initial conditions. :func:`flexkane.kane.chain.build_chain` makes the symbols of the derivation from
it; ``flexkane check`` needs only the names.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass

from ..errors import ModelError
from .model import Model
from .parts import JOINT_DOFS, Joint

__all__ = ["CoordinateName", "coordinate_names", "tree_order"]


@dataclass(frozen=True)
class CoordinateName:
    """Names of one generalized coordinate and its speed.

    Attributes
    ----------
    q, u : str
        Names of the coordinate and of the speed.
    owner : str
        Joint or beam name.
    role : str
        ``x``, ``y``, ``angle``, ``slide``, ``mode``, ``axial``.
    index : int
        Mode index (1-based) for beam coordinates, else 0.
    driver : str or None
        ``coordinate`` or ``speed`` when a driver prescribes it.
    """

    q: str
    u: str
    owner: str
    role: str
    index: int = 0
    driver: str | None = None


def tree_order(model: Model) -> list[Joint]:
    """The joints from the ground outwards (breadth first, siblings by name)."""
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


def coordinate_names(model: Model) -> list[CoordinateName]:
    """Name the coordinates of a model's chain, in state order; check names and initial conditions.

    Parameters
    ----------
    model : Model
        A model whose parts and joint tree are valid.

    Returns
    -------
    list of CoordinateName

    Raises
    ------
    ModelError
        For a name used twice (or also by a parameter, ``t`` or ``pi``), an initial value of an unknown
        coordinate or speed, or one of a coordinate or speed a driver prescribes.
    """
    raw: list[tuple[str, str, int, str, str, str | None]] = []  # (owner, role, index, q, u, driver)
    for joint in tree_order(model):
        roles = JOINT_DOFS[joint.type]
        driver = None if joint.driver is None else ("coordinate" if joint.driver.coordinate is not None
                                                    else "speed")
        for k, role in enumerate(roles):
            suffix = "" if len(roles) == 1 else f"_{role}"
            qn = joint.coordinates[k] if joint.coordinates else f"q_{joint.name}{suffix}"
            un = joint.speeds[k] if joint.speeds else f"u_{joint.name}{suffix}"
            raw.append((joint.name, role, 0, qn, un, driver if k == 0 else None))
        if joint.child in model.beams:
            beam = model.beams[joint.child]
            for i in range(1, beam.n_modes + 1):
                raw.append((beam.name, "mode", i, f"q_{beam.name}_{i}", f"u_{beam.name}_{i}", None))
            for k in range(1, beam.n_axial + 1):
                raw.append((beam.name, "axial", k, f"s_{beam.name}_{k}", f"v_{beam.name}_{k}", None))
    if model.naming == "sequential":
        raw = [(o, r, i, f"q{n + 1}", f"u{n + 1}", d) for n, (o, r, i, _, _, d) in enumerate(raw)]
    seen: dict[str, str] = {}
    coordinates = []
    for owner, role, index, qn, un, driver in raw:
        for name in (qn, un):
            if name in seen or name in model.parameters or name in ("t", "pi"):
                raise ModelError(f"joints.{owner}" if role not in ("mode", "axial") else f"beams.{owner}",
                                 "coordinate and speed names unique and distinct from parameters", name)
            seen[name] = owner
        coordinates.append(CoordinateName(qn, un, owner, role, index, driver))
    names = {c.q for c in coordinates} | {c.u for c in coordinates}
    for key in model.initial:
        if key not in names:
            close = difflib.get_close_matches(key, sorted(names), n=1, cutoff=0.5)
            raise ModelError(f"initial.{key}", "the name of a generalized coordinate or speed of this model"
                             f" ({', '.join(sorted(names))})", key,
                             f"did you mean {close[0]!r}?" if close else None)
    for coord in coordinates:
        if coord.driver == "coordinate" and coord.q in model.initial:
            raise ModelError(f"initial.{coord.q}", "no initial value for a coordinate prescribed by a driver",
                             model.initial[coord.q])
        if coord.driver is not None and coord.u in model.initial:
            raise ModelError(f"initial.{coord.u}", "no initial value for a speed prescribed by a driver",
                             model.initial[coord.u])
    return coordinates
