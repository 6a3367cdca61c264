"""The model schema: every field of a model file, declared once.

Each table of a model file (``[beams.NAME]``, ``[joints.NAME]``, ``[gravity]``, ...) is a
:class:`Table` of :class:`Field` declarations, in the order the file is written. A field says:

* its key, what it is (``doc``, the words of validation's messages) and its unit (by number of
  dimensions where the two differ; None where the part's type decides it, e.g. a joint's stiffness
  in N m/rad or N/m);
* the dimensions it belongs to (2: planar models, 3: spatial ones, or both);
* its ``kind`` for the derivation cache: ``"structure"`` (a change derives the equations again),
  ``"value"`` (a constant the equations keep as a symbol: a change only changes numbers; the key
  paths below it that are value fields are ``value_paths``), ``"number"`` (read for the numbers
  only: parameters, initial values, the roots of a shape family) or ``"ignored"`` (never enters the
  equations: an outline, the run settings);
* how it is read and written (``form``: ``"value"`` kept as given, ``"pair"``, ``"vectors"``,
  ``"ratios"``, ``"shape"``, ``"float"``, ``"table"``, ``"orientation"``, ``"driver"``,
  ``"points"``, ``"outline"``, ``"axes"``), whether it is required (the message when it is missing)
  and when it is written (``write``: ``"always"``, ``"given"`` (not None), ``"changed"`` (not its
  default), ``"nonempty"``);
* the range validation checks it in (``rule``: ``"positive"``, ``"non_negative"``, ``"number"``;
  None where the part's own checks decide, with other fields);
* for a beam, the constants of the equations that it brings (``constants``: name stem -> integral),
  whose names no parameter may take (:mod:`flexkane.model.constant_names`).

Reading and writing (:mod:`flexkane.model.toml_io`), the keys a table accepts
(:mod:`flexkane.model.file_layout`), validation's ranges, units and messages
(:mod:`flexkane.model.validate`), the derivation cache's value fields
(:mod:`flexkane.derivation_cache`) and the names of generated constants walk these declarations. A
new field of an existing part is one :class:`Field` here and its attribute in
:mod:`flexkane.model.parts` (see docs/design.md, "The model schema").
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass, field

from .parts import (SENSOR_TYPES, Beam, Controller, DistributedLoad, Driver, Gravity, Joint, Load, LoopConstraint,
                    PointSpring, RigidBody, Sensor, ShapeSpec, Simulation)

__all__ = ["ABSENT", "Field", "Table", "TABLES", "TOP", "DRIVER", "SHAPE", "KINDS", "table", "value_path_patterns",
           "path_patterns", "one_pattern", "constant_stems", "unit_of_path"]

#: Kinds of fields, for the derivation cache (see the module's docstring).
KINDS = ("structure", "value", "number", "ignored")
#: How a field is written (see the module's docstring).
WRITES = ("always", "given", "changed", "nonempty")
#: Rules of the ranges validation checks a field in.
RULES = ("positive", "non_negative", "number")



class _Absent:
    """The ``outside`` of a field that every model's part may leave to its default."""

    def __repr__(self):
        return "ABSENT"


#: See :attr:`Field.outside`.
ABSENT = _Absent()

#: Index suffixes of key paths (regular expressions): a list of numbers, a point's components.
LIST = r"\[\d+\]"
COMPONENTS = r"\[[012]\]"


@dataclass
class Field:
    """One field of a table of a model file (a declaration: not changed once made; a variant is a
    copy, :func:`dataclasses.replace`).

    Parameters
    ----------
    key : str
        Its key in the file, and the attribute of the part (:mod:`flexkane.model.parts`).
    doc : str
        What it is, as messages say it (``"flexural rigidity"``).
    unit : str, dict of int to str, or None
        Its unit (``"N m^2"``), by number of dimensions where they differ; None where the part's
        type decides it (``unit_by_type``) or it has none.
    unit_by_type : dict of str to str, optional
        Its unit by the part's ``type`` where that decides it (a joint's stiffness: ``"N m/rad"``
        for a revolute joint, ``"N/m"`` for a prismatic one); a type not listed has none.
    dimensions : tuple of int
        The numbers of dimensions of the models that have it.
    kind : str
        One of :data:`KINDS`.
    value_paths : tuple of str
        For a ``"value"`` field, the suffixes (regular expressions) of the key paths below the key
        that are value fields: ``("",)`` the field itself, ``(LIST,)`` each item of a list.
    form : str
        How it is read and written (see the module's docstring).
    required : bool, str or dict of int to str
        Whether it must be given: True (the message is ``the <doc> [<unit>]``), the message, or the
        message by number of dimensions.
    write : str
        When :func:`flexkane.model.dumps_model` writes it, one of :data:`WRITES`.
    rule : str or None
        The range validation checks it in, one of :data:`RULES`; None where the part's checks do.
    outside : object
        The attribute's value in a model whose dimensions do not have the field (a constructor
        argument without default).
    shape_default : str or None
        For a shape: the family when none is given.
    default_with : str or None
        For a shape: the count field without which it has no default (``n_axial``: no axial shape
        without axial modes).
    given_with : str or None
        The count field without which it is not written (``n_modes_y`` for ``shape_y``).
    constants : tuple of (str, str, str)
        For a beam: the constants it brings, ``(kind, stem, integral)``, kind ``"mass"``
        (``<stem>_<beam>``) or ``"modal"`` (``<stem>_<indices>``).
    """

    key: str
    doc: str
    unit: str | dict | None = None
    dimensions: tuple = (2, 3)
    kind: str = "structure"
    value_paths: tuple = ("",)
    form: str = "value"
    required: bool | str | dict = False
    write: str = "given"
    rule: str | None = None
    outside: object = ABSENT
    shape_default: str | None = None
    default_with: str | None = None
    given_with: str | None = None
    constants: tuple = ()
    unit_by_type: dict | None = None

    def unit_in(self, dimensions: int) -> str | None:
        """The unit in a model of ``dimensions`` dimensions."""
        return self.unit.get(dimensions) if isinstance(self.unit, dict) else self.unit

    def unit_for(self, dimensions: int, kind: str | None = None) -> str | None:
        """The unit in a model of ``dimensions`` dimensions, of a part of type ``kind`` where the type
        decides it."""
        if self.unit_by_type is not None:
            return self.unit_by_type.get(kind)
        return self.unit_in(dimensions)

    def missing_message(self, dimensions: int) -> str | None:
        """What a missing required field's message expects, or None if it is optional."""
        if isinstance(self.required, dict):
            return self.required.get(dimensions)
        if self.required is True:
            return f"the {self.doc} [{self.unit_in(dimensions)}]"
        return self.required or None


@dataclass
class Table:
    """A table of a model file: its fields, in the order they are written (a declaration, as
    :class:`Field`).

    Parameters
    ----------
    name : str
        Its key at the top of the file (``beams``).
    part : type
        The class of :mod:`flexkane.model.parts` it is read into.
    fields : tuple of Field
        Its fields.
    named : bool
        Whether the file has one such table per part, ``[beams.NAME]`` (else one, ``[gravity]``).
    """

    name: str
    part: type
    fields: tuple
    named: bool = True
    _by_key: dict = field(default=None, init=False, repr=False, compare=False)
    _of: dict = field(default=None, init=False, repr=False, compare=False)
    _outside: dict = field(default=None, init=False, repr=False, compare=False)
    _keys: dict = field(default=None, init=False, repr=False, compare=False)
    _absent: dict = field(default=None, init=False, repr=False, compare=False)
    _defaults: dict = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self):
        self._by_key = {f.key: f for f in self.fields}
        self._of = {d: tuple(f for f in self.fields if d in f.dimensions) for d in (2, 3)}
        self._outside = {d: {f.key: f.outside for f in self.fields if d not in f.dimensions and f.outside is not ABSENT}
                         for d in (2, 3)}
        self._keys = {d: tuple(f.key for f in fields) for d, fields in self._of.items()}
        self._absent = {d: tuple(f for f in fields if f.required or f.form in ("shape", "table"))
                        for d, fields in self._of.items()}
        parts = dataclasses.fields(self.part) if dataclasses.is_dataclass(self.part) else ()
        self._defaults = {f.name: f.default for f in parts if f.default is not dataclasses.MISSING}

    def keys(self, dimensions: int) -> tuple[str, ...]:
        """The keys the table accepts in a model of ``dimensions`` dimensions, in declaration order."""
        return self._keys[dimensions] if dimensions in self._keys else ()

    def of(self, dimensions: int) -> tuple[Field, ...]:
        """The fields of a model of ``dimensions`` dimensions."""
        return self._of[dimensions] if dimensions in self._of else ()

    def default(self, key: str):
        """The part's default of the field ``key`` (None for a field whose default is made anew,
        a list or a table: it is written when it is not empty)."""
        return self._defaults.get(key)

    def when_absent(self, dimensions: int) -> tuple[Field, ...]:
        """The fields of ``dimensions`` whose absence means something: required ones, and those
        whose absence gives a value other than the part's default (a shape family, an empty table)."""
        return self._absent[dimensions]

    def outside(self, dimensions: int) -> dict:
        """The attributes of the fields that a model of ``dimensions`` dimensions does not have but
        that its part needs (:attr:`Field.outside`)."""
        return dict(self._outside.get(dimensions, ()))

    def field(self, key: str) -> Field:
        """The field of ``key`` (KeyError for an undeclared key)."""
        return self._by_key[key]

    def with_field(self, new: Field, part: type | None = None) -> Table:
        """A copy of the table with one more field (and another part class), e.g. for a test."""
        return dataclasses.replace(self, fields=self.fields + (new,), part=part or self.part)


_BOTH, _PLANAR, _SPATIAL = (2, 3), (2,), (3,)
_RATIO = "modal damping ratio"

BODIES = Table("bodies", RigidBody, (
    Field("mass", "mass", "kg", kind="value", required=True, rule="positive"),
    Field("inertia", "moment of inertia about the mass centre", {2: "kg m^2", 3: "kg m^2"}, kind="value",
          value_paths=("", r"(\[[012]\]){1,2}"), form="vectors",
          required={2: "the moment of inertia about the mass centre [kg m^2]",
                    3: "the inertia tensor about the mass centre, [Ixx, Iyy, Izz] or "
                       "[[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]] [kg m^2]"}),
    Field("points", "named points, coordinates from the mass centre", "m", kind="value",
          value_paths=(r"\.[^.]+" + COMPONENTS,), form="points", write="nonempty"),
    Field("outline", "outline vertices from the mass centre", "m", kind="ignored", form="outline", write="nonempty"),
))

BEAMS = Table("beams", Beam, (
    Field("L", "length", "m", required=True, rule="positive"),
    Field("EI", "flexural rigidity", "N m^2", _PLANAR, "value", required=True, rule="positive", write="always",
          outside=None, constants=(("modal", "H", "int EI Phi_i'' Phi_j'' dx"),)),
    Field("rho", "mass per unit length", "kg/m", kind="value", required=True, rule="positive",
          constants=(("mass", "m", "int rho dx"), ("mass", "e", "int rho x dx"), ("mass", "I", "int rho x^2 dx"),
                     ("modal", "E", "int rho Phi_i dx"), ("modal", "F", "int rho x Phi_i dx"),
                     ("modal", "G", "int rho Phi_i Phi_j dx"), ("modal", "A", "int rho Psi_k dx"),
                     ("modal", "Ax", "int rho x Psi_k dx"), ("modal", "C", "int rho Phi_i Psi_k dx"),
                     ("modal", "AA", "int rho Psi_k Psi_l dx"))),
    Field("EI_y", "flexural rigidity about the section's y axis", "N m^2", _SPATIAL, "value", required=True,
          rule="positive"),
    Field("EI_z", "flexural rigidity about the section's z axis", "N m^2", _SPATIAL, "value", required=True,
          rule="positive"),
    Field("GJ", "torsional rigidity", "N m^2", _SPATIAL, "value", rule="positive",
          constants=(("modal", "Kt", "int GJ Theta_k' Theta_l' dx"),)),
    Field("rho_Ip", "polar mass moment of inertia of the section per unit length", "kg m", _SPATIAL, "value",
          rule="non_negative", constants=(("mass", "Ip", "int rho_Ip dx"), ("modal", "Et", "int rho_Ip Theta_k dx"),
                                          ("modal", "Gt", "int rho_Ip Theta_k Theta_l dx"))),
    Field("n_modes", "number of shape functions", "-", _PLANAR,
          required="the number of shape functions, a positive integer", write="always", outside=0),
    Field("shape", "bending shape-function family", None, _PLANAR, form="shape", write="always",
          shape_default="clamped-free"),
    Field("damping", _RATIO + "s", "-", kind="value", value_paths=(LIST,), form="ratios", write="nonempty"),
    Field("gravity", "gravity model", None, write="changed"),
    Field("elastic_forces", "elastic force model", None, write="changed",
          constants=(("modal", "J", "int Phi_i'''' dx"), ("modal", "Jx", "int x Phi_i'''' dx"),
                     ("modal", "JPhi", "int Phi_j Phi_i'''' dx"))),
    Field("EA", "axial stiffness", "N", kind="value", rule="positive",
          constants=(("modal", "HA", "int EA Psi_k' Psi_l' dx"),)),
    Field("principal_angle", "angle of the section's principal axes from the beam frame's", "rad", _SPATIAL,
          "value", rule="number"),
    Field("rho_Iy", "mass moment of inertia of the section per unit length about its y axis", "kg m", _SPATIAL,
          "value", rule="non_negative", constants=(("mass", "Iry", "int rho_Iy dx"),)),
    Field("rho_Iz", "mass moment of inertia of the section per unit length about its z axis", "kg m", _SPATIAL,
          "value", rule="non_negative", constants=(("mass", "Irz", "int rho_Iz dx"),)),
    Field("n_modes_y", "number of shape functions", "-", _SPATIAL, write="changed"),
    Field("shape_y", "shape-function family of the bending along y", None, _SPATIAL, form="shape",
          shape_default="clamped-free", given_with="n_modes_y"),
    Field("n_modes_z", "number of shape functions", "-", _SPATIAL, write="changed"),
    Field("shape_z", "shape-function family of the bending along z", None, _SPATIAL, form="shape",
          shape_default="clamped-free", given_with="n_modes_z"),
    Field("n_torsion", "number of shape functions", "-", _SPATIAL, write="changed"),
    Field("torsion_shape", "torsion shape-function family", None, _SPATIAL, form="shape",
          shape_default="torsion-clamped-free", default_with="n_torsion",
          given_with="n_torsion"),
    Field("n_axial", "number of axial shape functions", "-", write="changed"),
    Field("axial_shape", "axial shape-function family", None, form="shape", shape_default="axial-fixed-free",
          default_with="n_axial", given_with="n_axial"),
    Field("rotary_inertia", "mass moment of inertia of the section per unit length, rho I", "kg m", kind="value",
          rule="non_negative", constants=(("mass", "Ir", "int rho_I dx"), ("modal", "Er", "int rho_I Phi_i' dx"),
                                          ("modal", "Gr", "int rho_I Phi_i' Phi_j' dx"))),
    Field("damping_y", _RATIO + "s of the bending along y", "-", _SPATIAL, "value", (LIST,), "ratios",
          write="nonempty"),
    Field("damping_z", _RATIO + "s of the bending along z", "-", _SPATIAL, "value", (LIST,), "ratios",
          write="nonempty"),
    Field("torsion_damping", _RATIO + "s of the torsion", "-", _SPATIAL, "value", (LIST,), "ratios",
          write="nonempty"),
    Field("axial_damping", _RATIO + "s of the axial stretch", "-", _SPATIAL, "value", (LIST,), "ratios",
          write="nonempty"),
    Field("geometric_stiffening", "geometric stiffening", None, write="changed",
          constants=(("modal", "D", "int rho d dx"), ("modal", "Dx", "int rho x d dx"),
                     ("modal", "Dphi", "int rho Phi_i d dx"), ("modal", "Dpsi", "int rho Psi_k d dx"),
                     ("modal", "DD", "int rho d d dx"))),
    Field("static_corrections", "static correction shapes at the tip (true) or the family's functions alone",
          None, write="changed"),
))

#: A beam's shape-function family, ``shape = { family = ..., roots = [...], options }`` (the options
#: are the family's, checked by the family).
SHAPE = Table("shape", ShapeSpec, (
    Field("family", "shape-function family"),
    Field("roots", "eigenvalue parameters lambda_i", "-", kind="number"),
))
#: Options of shape families that give numbers only (a tip body's mass and inertia ratios).
SHAPE_NUMBER_OPTIONS = ("mass_ratio", "inertia_ratio")

DRIVER = Table("driver", Driver, (
    Field("coordinate", "prescribed coordinate"),
    Field("speed", "prescribed speed"),
), named=False)

JOINTS = Table("joints", Joint, (
    Field("type", "joint type", required="the joint type (free, revolute, prismatic or weld)"),
    Field("parent", "parent link", required="the parent: 'ground', a body or a beam"),
    Field("child", "child link", required="the child: a body or a beam"),
    Field("parent_point", "point of the parent body"),
    Field("parent_position", "ground coordinates", "m", kind="value", value_paths=(COMPONENTS,), form="pair"),
    Field("station", "station on the parent beam", "m"),
    Field("child_point", "point of the child body"),
    Field("coordinates", "coordinate names"),
    Field("speeds", "speed names"),
    Field("stiffness", "joint stiffness", kind="value", unit_by_type={"revolute": "N m/rad", "prismatic": "N/m"}),
    Field("damping", "joint damping", kind="value", unit_by_type={"revolute": "N m s/rad", "prismatic": "N s/m"}),
    Field("torque", "actuator torque or force", unit_by_type={"revolute": "N m", "prismatic": "N"}),
    Field("angle", "angle of the child frame", "rad", _BOTH, kind="value", write="changed"),
    Field("axis", "slide direction angle (planar) or joint axis (spatial)", {2: "rad", 3: "-"}, kind="value",
          form="vectors", write="changed"),
    Field("axes", "axes of a universal joint", "-", form="axes"),
    Field("orientation", "orientation of the joint frame", kind="value",
          value_paths=(r"\.(angle|angles\[[012]\])",), form="orientation"),     # not its axes: structure
    Field("child_orientation", "orientation of the child frame", kind="value",
          value_paths=(r"\.(angle|angles\[[012]\])",), form="orientation"),
    Field("rest", "rest position of the joint spring", kind="value", write="changed",
          unit_by_type={"revolute": "rad", "prismatic": "m"}),
    Field("driver", "prescribed motion", form="driver"),
))

GRAVITY = Table("gravity", Gravity, (
    Field("g", "gravitational acceleration", "m/s^2", kind="value", required="the gravitational acceleration [m/s^2]",
          rule="non_negative", write="always"),
    Field("direction", "direction in the ground frame", "-", form="pair", write="always",
          required="a direction [x, y] in the ground frame"),
), named=False)

LOADS = Table("loads", Load, (
    Field("body", "loaded body or beam", required="the name of a body or a beam"),
    Field("point", "point of the body"),
    Field("station", "station on the beam", "m"),
    Field("force", "force", "N", form="pair"),
    Field("torque", "torque", "N m", form="vectors"),
    Field("frame", "frame of the components"),
))

DISTRIBUTED_LOADS = Table("distributed_loads", DistributedLoad, (
    Field("beam", "loaded beam", required="the name of the loaded beam"),
    Field("fx", "force per unit length along x", "N/m", write="changed"),
    Field("fy", "force per unit length along y", "N/m", write="changed"),
    Field("fz", "force per unit length along z", "N/m", _SPATIAL, write="changed"),
    Field("frame", "frame of the components", write="always"),
    Field("quadrature_nodes", "number of Gauss-Legendre nodes", "-", write="changed"),
))

_END = "'ground', a body or a beam"
SPRINGS = Table("springs", PointSpring, (
    Field("body_a", "first end's link", required=_END),
    Field("point_a", "first end's point"),
    Field("station_a", "first end's station", "m"),
    Field("position_a", "first end's ground coordinates", "m", kind="value", value_paths=(COMPONENTS,), form="pair"),
    Field("body_b", "second end's link", required=_END),
    Field("point_b", "second end's point"),
    Field("station_b", "second end's station", "m"),
    Field("position_b", "second end's ground coordinates", "m", kind="value", value_paths=(COMPONENTS,), form="pair"),
    Field("stiffness", "spring stiffness", "N/m", kind="value", rule="non_negative"),
    Field("damping", "damping coefficient", "N s/m", kind="value", rule="non_negative"),
    Field("rest_length", "rest length", "m", kind="value", rule="non_negative"),
))

CONSTRAINTS = Table("constraints", LoopConstraint, (
    Field("type", "loop joint type", required="the loop joint type (revolute or prismatic)"),
    Field("body_a", "frame a's link", required=_END),
    Field("point_a", "frame a's point"),
    Field("station_a", "frame a's station", "m"),
    Field("position_a", "frame a's ground coordinates", "m", kind="value", value_paths=(r"\[[01]\]",), form="pair"),
    Field("body_b", "frame b's link", required=_END),
    Field("point_b", "frame b's point"),
    Field("station_b", "frame b's station", "m"),
    Field("position_b", "frame b's ground coordinates", "m", kind="value", value_paths=(r"\[[01]\]",), form="pair"),
    Field("dependent", "dependent speeds"),
    Field("axis", "slide direction angle in frame a (planar) or axis (spatial)", kind="value", form="vectors",
          write="changed"),
    Field("angle", "angle of frame b relative to frame a", "rad", kind="value", write="changed"),
    Field("stabilization", "constraint stabilization rate", "1/s", form="float", write="nonempty"),
    Field("orientation", "orientation of frame b", form="orientation"),
))

SENSORS = Table("sensors", Sensor, (
    Field("type", "kind of sensor", required="the kind of sensor (" + ", ".join(SENSOR_TYPES) + ")"),
    Field("beam", "beam"),
    Field("body", "body"),
    Field("point", "point of the body"),
    Field("joint", "joint"),
    Field("station", "station on the beam", "m", kind="value"),
    Field("distance", "distance across the section", "m", kind="value"),
    Field("frame", "frame of the components", write="changed"),
    Field("component", "component"),
))

CONTROLLERS = Table("controllers", Controller, (
    Field("states", "state rates { z = \"expression\" }", form="table", write="nonempty"),
    Field("initial", "initial values { z = value }", kind="number", form="table", write="nonempty"),
    Field("output", "output"),
    Field("min", "lower saturation of the output", kind="value"),
    Field("max", "upper saturation of the output", kind="value"),
))

SIMULATION = Table("simulation", Simulation, (
    Field("t_end", "end time", "s", kind="ignored", form="float"),
    Field("dt_out", "output interval", "s", kind="ignored", form="float"),
    Field("rtol", "relative tolerance", "-", kind="ignored", form="float"),
    Field("atol", "absolute tolerance", kind="ignored", form="float"),
    Field("method", "integration method", kind="ignored"),
    Field("max_steps", "most integration steps", "-", kind="ignored"),
    Field("deflection_warning", "fraction of a beam's length above which a run warns", "-", kind="ignored",
          form="float", write="changed"),
    Field("spin_warning", "fraction of a beam's first bending frequency above which a run warns", "-",
          kind="ignored", form="float", write="changed"),
), named=False)

#: The tables of parts and settings, by their key at the top of a model file.
TABLES = {t.name: t for t in (BODIES, BEAMS, JOINTS, GRAVITY, LOADS, DISTRIBUTED_LOADS, SPRINGS, CONSTRAINTS,
                              SENSORS, CONTROLLERS, SIMULATION)}

#: The top level of a model file; the tables of :data:`TABLES` are structure field by field.
TOP = Table("", object, (
    Field("name", "model name", kind="ignored"),
    Field("dimensions", "number of dimensions"),
    Field("description", "description", kind="ignored"),
    Field("naming", "naming of coordinates"),
    Field("parameters", "parameters", kind="number"),
    *(Field(name, name) for name in ("bodies", "beams", "joints", "gravity", "loads", "distributed_loads",
                                     "springs", "constraints", "sensors", "controllers")),
    Field("initial", "initial values", kind="number"),
    Field("simulation", "run settings", kind="ignored"),
    Field("sweep", "sweep (read by flexkane.sweep)", kind="ignored"),
), named=False)


def table(name: str) -> Table:
    """The declared table of ``name`` (``beams``)."""
    return TABLES[name]


def _prefix(t: Table) -> str:
    return rf"{t.name}\.[^.]+\." if t.named else rf"{t.name}\."


def value_path_patterns(tables=None) -> tuple[str, ...]:
    """Regular expressions of the key paths of value fields, over every dimension (a path is one
    when its whole text matches).

    Parameters
    ----------
    tables : iterable of Table, optional
        The tables (default: :data:`TABLES` and the driver's).
    """
    out = []
    for t in (tables if tables is not None else TABLES.values()):
        for f in t.fields:
            if f.kind == "value":
                out += [_prefix(t) + f.key + suffix for suffix in f.value_paths]
    return tuple(out)


def path_patterns(kind: str, tables=None) -> tuple[str, ...]:
    """Regular expressions of the key paths (and all below them) of the fields of ``kind``
    (``"number"`` or ``"ignored"``), top level included."""
    out = [f.key for f in TOP.fields if f.kind == kind]
    for t in (tables if tables is not None else TABLES.values()):
        if t.name in out:
            continue
        out += [_prefix(t) + f.key for f in t.fields if f.kind == kind]
    shapes = [f.key for f in BEAMS.fields if f.form == "shape"]
    group = "(" + "|".join(shapes) + ")"
    if kind == "number":
        out += [rf"beams\.[^.]+\.{group}\.{f.key}" for f in SHAPE.fields if f.kind == "number"]
        out.append(rf"beams\.[^.]+\.{group}\.options\.({'|'.join(SHAPE_NUMBER_OPTIONS)})")
    return tuple(out)


def one_pattern(patterns) -> re.Pattern:
    """One compiled regular expression that matches where any of ``patterns`` does."""
    return re.compile("|".join(f"(?:{p})" for p in patterns))


def constant_stems(kind: str) -> dict[str, str]:
    """The stems of a beam's generated constants of ``kind`` (``"mass"``: ``m``, ``e``, ``I``, ...;
    ``"modal"``: ``E``, ``G``, ``H``, ...) -> the integral each stands for."""
    return {stem: meaning for f in BEAMS.fields for k, stem, meaning in f.constants if k == kind}


def unit_of_path(path: str, dimensions: int, model=None) -> str | None:
    """The declared unit of the field at a key path (``beams.arm.EI``, ``bodies.hub.points.P[0]``),
    None when the field has none, or the part's type decides it and no ``model`` tells the type.

    Parameters
    ----------
    path : str
        The key path.
    dimensions : int
        The model's number of dimensions.
    model : Model, optional
        The model, whose parts' types decide some units (a joint's stiffness).
    """
    parts = path.split(".")
    t = TABLES.get(parts[0])
    if t is None or len(parts) < (3 if t.named else 2):
        return None
    key = (parts[2] if t.named else parts[1]).split("[")[0]
    if key not in t._by_key or dimensions not in t.field(key).dimensions:
        return None
    field = t.field(key)
    if field.unit_by_type is None:
        return field.unit_in(dimensions)
    part = getattr(model, t.name, {}).get(parts[1].split("[")[0]) if model is not None and t.named else None
    return field.unit_for(dimensions, getattr(part, "type", None))
