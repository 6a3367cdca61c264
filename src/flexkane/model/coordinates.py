"""The generalized coordinates of a model's chain, by name, without SymPy.

:func:`coordinate_names` orders the joints from the ground, names every coordinate and speed (joint
coordinates, then the modal coordinates of the beam a joint carries) and checks the names and the
initial conditions. :func:`flexkane.kane.chain.build_chain` makes the symbols of the derivation from
it; ``flexkane check`` needs only the names.

Spatial joints (``dimensions = 3``) name their coordinates by role: ``q_<j>`` for a one-coordinate
joint, else ``q_<j>_<suffix>`` (cylindrical ``_angle``, ``_slide``; universal ``_1``, ``_2``; planar
``_x``, ``_y``, ``_angle``). A spherical joint has the Euler parameters ``q_<j>_e0 .. q_<j>_e3`` of
J_c in J_p and the angular velocity of J_c in J_p along J_c's axes as speeds ``u_<j>_wx, _wy, _wz``:
e0 has no speed of its own (``CoordinateName.u`` is None), so a spatial chain can have more
coordinates than speeds. A free joint has first the position of J_c's origin in J_p
(``q_<j>_x, _y, _z``, with speeds ``u_<j>_vx, _vy, _vz``: the velocity of that origin relative to J_p
along J_c's axes), then the Euler parameters and angular speeds of a spherical joint.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass

from ..errors import ModelError
from .parts import JOINT_DOFS_BY_DIMENSION, Joint

__all__ = ["CoordinateName", "coordinate_names", "tree_order", "coordinate_unit", "speed_unit",
           "orientation_key", "initial_keys", "EULER_ROLES", "EQUILIBRIUM_KEY",
           "starts_at_equilibrium"]

#: Roles of the Euler parameters of a spherical or free joint, scalar part first.
EULER_ROLES = ("e0", "e1", "e2", "e3")
#: Unit of a coordinate, by role.
_COORDINATE_UNIT = {"x": "m", "y": "m", "z": "m", "angle": "rad", "angle_1": "rad", "angle_2": "rad",
                    "slide": "m", "mode": "m", "mode_y": "m", "mode_z": "m", "torsion": "rad", "axial": "m",
                    "e0": "-", "e1": "-", "e2": "-", "e3": "-"}
#: Name suffix of a spatial joint's coordinate and speed, by role, where it differs from the role.
_Q_SUFFIX = {"angle_1": "1", "angle_2": "2"}
_U_SUFFIX = {"e0": None, "e1": "wx", "e2": "wy", "e3": "wz"}
#: The speeds of a spatial free joint's translations: velocity components along J_c's axes.
_FREE_U_SUFFIX = {"x": "vx", "y": "vy", "z": "vz"}


def coordinate_unit(role: str) -> str:
    """Unit of a coordinate of this role (``m``, ``rad``, ``-`` for Euler parameters)."""
    return _COORDINATE_UNIT[role]


def speed_unit(role: str) -> str:
    """Unit of the speed that goes with a coordinate of this role (an Euler parameter's is the
    angular velocity component, ``rad/s``)."""
    return "rad/s" if role in EULER_ROLES else f"{_COORDINATE_UNIT[role]}/s"


#: The ``[initial]`` key that asks for a start from the static equilibrium (true or false; no coordinate
#: or speed has this name: theirs begin with q or u). See :mod:`flexkane.analysis.equilibrium_start`.
EQUILIBRIUM_KEY = "equilibrium"


def starts_at_equilibrium(model) -> bool:
    """Whether the model's ``[initial]`` table asks for a start from the static equilibrium
    (``equilibrium = true``).

    Raises
    ------
    ModelError
        Naming ``initial.equilibrium`` when its value is not true or false.
    """
    value = model.initial.get(EQUILIBRIUM_KEY, False)
    if not isinstance(value, bool):
        raise ModelError(f"initial.{EQUILIBRIUM_KEY}", "true or false (true: start from the static equilibrium "
                         "under gravity, loads and drivers at t0, the other initial values being where its "
                         "search starts)", value)
    return value


def orientation_key(joint_name: str) -> str:
    """The ``[initial]`` key that gives a spherical or free joint's orientation as a table
    (``q_<joint>``, whatever the naming of the coordinates)."""
    return f"q_{joint_name}"


def initial_keys(coordinates: list[CoordinateName]) -> list[str]:
    """Every key ``[initial]`` may hold: the coordinates, the speeds (e0 has none), the orientation
    table ``q_<joint>`` of each spatial spherical or free joint (unless a coordinate has that name),
    and :data:`EQUILIBRIUM_KEY`."""
    names = [c.q for c in coordinates] + [c.u for c in coordinates if c.u is not None]
    taken = set(names)
    oriented = [orientation_key(c.owner) for c in coordinates if c.role == "e0"]
    return names + [key for key in oriented if key not in taken] + [EQUILIBRIUM_KEY]


def _joint_names(joint: Joint, roles: tuple, dimensions: int) -> list[tuple[str, str | None]]:
    """(coordinate, speed) names of a joint's coordinates, by role (speed None for e0)."""
    pairs = []
    for role in roles:
        if len(roles) == 1:
            pairs.append((f"q_{joint.name}", f"u_{joint.name}"))
            continue
        q_suffix = _Q_SUFFIX.get(role, role) if dimensions == 3 else role
        if dimensions == 3 and role in _U_SUFFIX:
            u_suffix = _U_SUFFIX[role]
        elif dimensions == 3 and joint.type == "free":
            u_suffix = _FREE_U_SUFFIX[role]
        else:
            u_suffix = q_suffix
        pairs.append((f"q_{joint.name}_{q_suffix}", None if u_suffix is None else f"u_{joint.name}_{u_suffix}"))
    if joint.coordinates:
        pairs = [(name, u) for name, (_, u) in zip(joint.coordinates, pairs)]
    if joint.speeds:
        speeds = iter(joint.speeds)
        pairs = [(q, None if u is None else next(speeds)) for q, u in pairs]
    return pairs


@dataclass(frozen=True)
class CoordinateName:
    """Names of one generalized coordinate and its speed.

    Attributes
    ----------
    q : str
        Name of the coordinate.
    u : str or None
        Name of its speed; None for the scalar Euler parameter e0 of a spatial spherical or free
        joint, which has no speed of its own.
    owner : str
        Joint or beam name.
    role : str
        ``x``, ``y``, ``angle``, ``slide``, ``mode``, ``axial``; in space also ``z``, ``angle_1``,
        ``angle_2`` (universal joints) and ``e0`` .. ``e3`` (Euler parameters).
    index : int
        Mode index (1-based) for beam coordinates, else 0.
    driver : str or None
        ``coordinate`` or ``speed`` when a driver prescribes it.
    """

    q: str
    u: str | None
    owner: str
    role: str
    index: int = 0
    driver: str | None = None


#: Roles of the coordinates of a beam: planar bending, bending along the section's y and z axes
#: (spatial beams), torsion and axial stretch.
BEAM_ROLES = ("mode", "mode_y", "mode_z", "torsion", "axial")


def _spatial_beam_names(beam) -> list[tuple]:
    """(owner, role, index, q, u, driver) of a spatial beam's coordinates: ``q_<b>_y<i>`` (deflection
    along y), ``q_<b>_z<i>`` (along z), ``q_<b>_t<k>`` (twist), ``s_<b>_<k>`` (axial stretch)."""
    out = []
    for role, key, count in (("mode_y", "y", beam.n_modes_y), ("mode_z", "z", beam.n_modes_z),
                             ("torsion", "t", beam.n_torsion)):
        for i in range(1, count + 1):
            out.append((beam.name, role, i, f"q_{beam.name}_{key}{i}", f"u_{beam.name}_{key}{i}", None))
    for k in range(1, beam.n_axial + 1):
        out.append((beam.name, "axial", k, f"s_{beam.name}_{k}", f"v_{beam.name}_{k}", None))
    return out


def tree_order(model) -> list[Joint]:
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


def coordinate_names(model) -> list[CoordinateName]:
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
    raw: list[tuple[str, str, int, str, str | None, str | None]] = []  # (owner, role, index, q, u, driver)
    dimensions = model.dimensions
    for joint in tree_order(model):
        roles = JOINT_DOFS_BY_DIMENSION[dimensions][joint.type]
        driver = None if joint.driver is None else ("coordinate" if joint.driver.coordinate is not None
                                                    else "speed")
        for k, (role, (qn, un)) in enumerate(zip(roles, _joint_names(joint, roles, dimensions))):
            raw.append((joint.name, role, 0, qn, un, driver if k == 0 else None))
        if joint.child in model.beams and dimensions == 3:
            raw.extend(_spatial_beam_names(model.beams[joint.child]))
        elif joint.child in model.beams:
            beam = model.beams[joint.child]
            for i in range(1, beam.n_modes + 1):
                raw.append((beam.name, "mode", i, f"q_{beam.name}_{i}", f"u_{beam.name}_{i}", None))
            for k in range(1, beam.n_axial + 1):
                raw.append((beam.name, "axial", k, f"s_{beam.name}_{k}", f"v_{beam.name}_{k}", None))
    if model.naming == "sequential":   # q1, q2, ... and u1, u2, ... numbered separately
        numbered, speeds = [], 0
        for n, (o, r, i, _, un, d) in enumerate(raw):
            speeds += un is not None
            numbered.append((o, r, i, f"q{n + 1}", None if un is None else f"u{speeds}", d))
        raw = numbered
    seen: dict[str, str] = {}
    coordinates = []
    for owner, role, index, qn, un, driver in raw:
        for name in (qn, un):
            if name is None:
                continue
            if name in seen or name in model.parameters or name in ("t", "pi"):
                raise ModelError(f"beams.{owner}" if role in BEAM_ROLES else f"joints.{owner}",
                                 "coordinate and speed names unique and distinct from parameters", name)
            seen[name] = owner
        coordinates.append(CoordinateName(qn, un, owner, role, index, driver))
    keys = set(initial_keys(coordinates))   # with the orientation tables (flexkane.model.initial)
    for key in model.initial:
        if key not in keys:
            close = difflib.get_close_matches(key, sorted(keys), n=1, cutoff=0.5)
            raise ModelError(f"initial.{key}", "the name of a generalized coordinate or speed of this model"
                             f" ({', '.join(sorted(keys - {EQUILIBRIUM_KEY}))}) or {EQUILIBRIUM_KEY} (true or false)",
                             key,
                             f"did you mean {close[0]!r}?" if close else None)
    for coord in coordinates:
        if coord.driver == "coordinate" and coord.q in model.initial:
            raise ModelError(f"initial.{coord.q}", "no initial value for a coordinate prescribed by a driver",
                             model.initial[coord.q])
        if coord.driver is not None and coord.u in model.initial:
            raise ModelError(f"initial.{coord.u}", "no initial value for a speed prescribed by a driver",
                             model.initial[coord.u])
    return coordinates
