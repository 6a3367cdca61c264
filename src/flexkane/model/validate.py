"""Validation of a model, before anything is derived.

:func:`validate_model` checks a :class:`~flexkane.model.Model` however it was built (model file,
Python API, ``--set``, sweep), so it trusts no field's type. In order:

1. the model's own fields, the parameters (each resolved to a number);
2. every part: types, names (identifiers, unique), physical ranges with units (positive lengths,
   rigidities, densities and masses; non-negative inertias, stiffnesses and dampings; beam stations
   ``0 <= x <= L``), time laws (expressions of ``t`` finite at ``t = 0``);
3. references: every joint's parent and child, points, stations, load, spring and loop-constraint
   ends; the joints form a tree rooted at the ground (loops are closed by ``constraints``);
4. structure: the shape-function family of each beam with its options and mode count, the chain's
   generalized coordinates (names unique), initial conditions only for coordinates and speeds that
   exist, the dependent speeds of loop constraints.

Each problem is a :class:`~flexkane.errors.ModelError` naming the key path (``beams.arm.EI``), what
was expected with its unit, and what was given. The problems of independent parts are reported
together (:class:`~flexkane.errors.ModelErrors`, at most :data:`MAX_REPORTED`); a stage that relies on
an earlier one (parts on parameter values, joints on parts, the structure on everything) runs only
when the earlier one passed.
"""

from __future__ import annotations

import contextlib
import difflib
import keyword
import math
import numbers
import re

from ..errors import ModelError, ModelErrors
from .field_values import FieldValues
from . import schema
from .schema import BEAMS, BODIES, GRAVITY, JOINTS, SPRINGS
from .parts import (DIMENSIONS, DISTRIBUTED_FRAMES, ELASTIC_MODELS, FRAMES, GRAVITY_MODELS, JOINT_DOFS, JOINT_TYPES,
                    JOINT_TYPES_BY_DIMENSION, METHODS, NAMING_STYLES, SPATIAL_JOINT_TYPES, Beam, Controller,
                    DistributedLoad, Driver, Gravity, Joint, Load, LoopConstraint, PointSpring, RigidBody, Sensor,
                    ShapeSpec, Simulation)

__all__ = ["validate_model", "validate_run_arguments", "check_output_grid", "RUN_SETTINGS", "MAX_MODES",
           "MAX_ELASTIC_COORDINATES", "MAX_STIFFENED_MODES", "MAX_OUTPUT_ROWS", "METHODS", "is_name"]

#: Largest number of shape functions of one beam (transverse or axial), and of all the beams of a
#: model together (n_modes + n_axial summed) (measured in benchmarks/RESULTS.md; 200 modes exhausted
#: 24 GB).
MAX_MODES = 40
MAX_ELASTIC_COORDINATES = 40
#: Largest number of shape functions of a beam with geometric stiffening, whose derivation grows
#: fastest (spin-up: 10 modes derive in 32 s of CPU time, 20 did not in 270 s and 1.3 GB).
MAX_STIFFENED_MODES = 10
#: Largest number of rows of an output grid (t_end / dt_out).
MAX_OUTPUT_ROWS = 10_000_000
#: Most problems one validation reports together.
MAX_REPORTED = 20
#: Range of relative tolerances the integrators accept [-].
RTOL_RANGE = (1e-13, 1.0)

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_NAME_RULE = "of ASCII letters, digits and underscores, not starting with a digit"


def is_name(text) -> bool:
    """Whether ``text`` is a valid part, point, coordinate or speed name."""
    return isinstance(text, str) and _NAME.fullmatch(text) is not None


def _suggest(name, options) -> str | None:
    close = difflib.get_close_matches(str(name), [str(o) for o in options], n=1, cutoff=0.5)
    return f"did you mean {close[0]!r}?" if close else None


def _is_value(value) -> bool:
    return not isinstance(value, bool) and isinstance(value, (numbers.Real, str))


def _is_pair(value) -> bool:
    return isinstance(value, (tuple, list)) and len(value) == 2


class _Values(FieldValues):
    """Evaluates constant fields and time laws of one model, for range checks (the model's one
    evaluator, :class:`~flexkane.model.field_values.FieldValues`, with the messages of validation)."""

    #: Where to record the unit of every numeric field checked, by key path (None: nowhere).
    units: dict | None = None

    def __init__(self, model):
        super().__init__(model)
        #: (path, value) of laws that name something other than t and the parameters
        self.deferred: list = []
        #: key paths of the fields checked so far
        self.checked: set = set()

    def evaluate(self, path: str, value, extra: dict) -> float:
        """The value of an expression of the parameters and ``extra`` names (``t``, ``x``) [their units].

        Raises ModelError as :func:`~flexkane.expressions.parse_expression` and
        :func:`~flexkane.expressions.to_float` do (through them when the value needs SymPy).
        """
        return self.value(value, path, **extra)

    def number(self, path: str, value, what: str, unit: str, *, time: bool = False) -> float:
        """The value of a field (at t = 0 for a time law); checks its type and that it is finite."""
        kind = f"{what} [{unit}]" + (", a number or an expression of t" if time else "")
        self.checked.add(path)
        if self.units is not None:
            self.units[path] = unit
        if not _is_value(value):
            raise ModelError(path, f"a number or an expression string ({kind})", value)
        return self.value(value, path, what=kind, **({"t": 0.0} if time else {}))

    def law(self, path: str, value, what: str, unit: str) -> float | None:
        """:meth:`number` of an effort (at t = 0), or None when it names a signal (coordinates,
        speeds, sensors, controllers), which :mod:`flexkane.model.signals` checks once the chain's
        coordinates are known."""
        from ..expression_syntax import NeedsSymbolic, expression_names

        try:
            beyond = expression_names(value) - {*self.parameters, "t"}
        except NeedsSymbolic:
            beyond = set()      # not in the language: the evaluation below says why
        if beyond:
            self.deferred.append((path, value))
            if self.units is not None:
                self.units[path] = unit   # the field's unit all the same
            return None
        return self.number(path, value, what, unit, time=True)

    @staticmethod
    def shown(value, number: float):
        """What was given: the number, or the expression with its value."""
        return value if not isinstance(value, str) else f"{value} = {number:g}"

    def positive(self, path, value, what, unit) -> float:
        number = self.number(path, value, what, unit)
        if not number > 0:
            raise ModelError(path, f"a positive value [{unit}] ({what})", self.shown(value, number))
        return number

    def non_negative(self, path, value, what, unit) -> float:
        number = self.number(path, value, what, unit)
        if number < 0:
            raise ModelError(path, f"a non-negative value [{unit}] ({what})", self.shown(value, number))
        return number

    def declared(self, table, key: str, part, path: str, dimensions: int = 2) -> float:
        """Check the field ``key`` of ``part`` (key path ``path.key``) by the rule, the words and the
        unit that its declaration (:mod:`flexkane.model.schema`) gives; its value [its unit]."""
        field = table.field(key)
        return getattr(self, field.rule)(f"{path}.{key}", getattr(part, key), field.doc, field.unit_in(dimensions))

    def declared_rest(self, table, part, path: str, dimensions: int) -> None:
        """Check every field of ``part`` that has a rule in its declaration, is given, and that the
        part's own checks did not check (a field declared with a range and no relation to others)."""
        for field in table.of(dimensions):
            if field.rule is not None and getattr(part, field.key, None) is not None \
                    and f"{path}.{field.key}" not in self.checked:
                self.declared(table, field.key, part, path, dimensions)

    def station(self, path: str, value, beam: str, lengths: dict) -> None:
        """Check a station on ``beam``: 0 <= x <= L [m] (``lengths``: the beams' lengths by name)."""
        x = self.number(path, value, f"station on beam {beam!r}", "m")
        length = lengths[beam]
        if not 0 <= x <= length * (1 + 1e-12):
            raise ModelError(path, f"a station 0 <= x <= L = {length:g} [m] on beam {beam!r}",
                             self.shown(value, x))

    def pair(self, path, value, what, unit, *, time=False) -> tuple[float, float]:
        if not _is_pair(value):
            raise ModelError(path, f"a pair [x, y] of {what} [{unit}]", value)
        return (self.number(f"{path}[0]", value[0], what, unit, time=time),
                self.number(f"{path}[1]", value[1], what, unit, time=time))


def _name(path: str, name, what: str = f"a name {_NAME_RULE}") -> None:
    if not is_name(name):
        raise ModelError(path, what, name)


def _choice(path: str, value, choices) -> None:
    if not isinstance(value, str) or value not in choices:
        raise ModelError(path, "one of " + ", ".join(repr(c) for c in choices), value,
                         _suggest(value, choices) if isinstance(value, str) else None)


def _check_elastic_coordinates(beams: dict) -> None:
    """Refuse more than MAX_ELASTIC_COORDINATES shape functions over all the beams of a model, and
    more than MAX_STIFFENED_MODES on a beam with geometric stiffening."""
    counts = {name: beam.n_modes + (beam.n_axial or 0) + beam.n_modes_y + beam.n_modes_z + beam.n_torsion
              for name, beam in beams.items()}
    for name, beam in beams.items():
        if beam.geometric_stiffening is True and counts[name] > MAX_STIFFENED_MODES:
            raise ModelError(f"beams.{name}.n_modes", f"at most {MAX_STIFFENED_MODES} shape functions "
                             "(n_modes + n_axial) with geometric_stiffening (more do not derive within bounded "
                             "time and memory)", counts[name], "lower n_modes (or --n-modes)")
    if sum(counts.values()) > MAX_ELASTIC_COORDINATES:
        raise ModelError("beams", f"at most {MAX_ELASTIC_COORDINATES} shape functions over all beams "
                         "(n_modes + n_axial summed; more do not run within bounded time and memory)",
                         ", ".join(f"{name}: {n}" for name, n in counts.items()),
                         "lower n_modes (or --n-modes)")


def _integer(path: str, value, low: int, high: int, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not low <= value <= high:
        raise ModelError(path, f"an integer {what} from {low} to {high}", value)
    return int(value)


def _names_list(path: str, value, count: int, what: str) -> None:
    if value is None:
        return
    if not isinstance(value, (list, tuple)) or len(value) != count:
        raise ModelError(path, f"a list of {count} {what} names", value)
    from ..expression_syntax import RESERVED_NAMES

    for i, item in enumerate(value):
        _name(f"{path}[{i}]", item)
        if item in RESERVED_NAMES or item in ("t", "xi") or keyword.iskeyword(item):
            raise ModelError(f"{path}[{i}]", f"a {what} name that is not reserved (t, xi, pi, function names, "
                             "Python keywords)", item)


def _table(model, kind: str, cls) -> dict:
    table = getattr(model, kind)
    if not isinstance(table, dict):
        raise ModelError(kind, f"a table of {cls.__name__} parts by name", table)
    for key, part in table.items():
        if not isinstance(part, cls):
            raise ModelError(f"{kind}.{key}", f"a {cls.__name__}", type(part).__name__)
        _name(f"{kind}.{key}", key, f"a part name {_NAME_RULE}")
        if part.name != key:
            raise ModelError(f"{kind}.{key}.name", f"the name the part is stored under ({key!r})", part.name)
    return table


class _Problems:
    """The problems found so far in one model; each check of a part runs under :meth:`part`."""

    def __init__(self):
        self.errors: list[ModelError] = []
        self.later: list[ModelError] = []   # problems no other check depends on, listed last

    @contextlib.contextmanager
    def part(self, *, later: bool = False):
        """Record a ModelError raised in the block and go on (stop at :data:`MAX_REPORTED`)."""
        found = self.later if later else self.errors
        try:
            yield
        except ModelErrors as exc:
            found.extend(exc.errors)
        except ModelError as exc:
            found.append(exc)
        everything = self.errors + self.later
        if len(everything) >= MAX_REPORTED:
            raise ModelErrors(everything[:MAX_REPORTED], limit=MAX_REPORTED)

    def raise_found(self, *, final: bool = False) -> None:
        """Raise what was found when a check that others rely on failed (or at the end).

        The error itself if there is one, :class:`~flexkane.errors.ModelErrors` if several.
        """
        everything = self.errors + self.later
        if not (self.errors or final and self.later):
            return
        if len(everything) == 1:
            raise everything[0]
        raise ModelErrors(everything)


def validate_model(model, *, units: dict | None = None) -> None:
    """Check a model; raise :class:`~flexkane.errors.ModelError` naming every problem found.

    Checks whose parts are independent (each body, beam, joint, load, spring, constraint, the
    gravity, the run settings) all run, and their problems are reported together (up to
    :data:`MAX_REPORTED`, as :class:`~flexkane.errors.ModelErrors`); a stage whose checks rely on
    the previous ones (values on parameters, references on parts) runs only when those passed.

    Parameters
    ----------
    model : Model
        The model, from a file or built in Python. Called through :meth:`Model.validate
        <flexkane.model.Model.validate>` (this module does not import the class: the model imports
        its validation), or by a caller that checked the type.
    units : dict, optional
        Filled with the unit of every numeric field checked, by key path (``"bodies.crank.mass"``:
        ``"kg"``).
    """
    problems = _Problems()
    with problems.part():
        if not isinstance(model.name, str) or not model.name.strip():
            raise ModelError("name", "a non-empty model name", model.name)
    with problems.part():
        if not isinstance(model.description, str):
            raise ModelError("description", "a text", model.description)
    with problems.part():
        _choice("naming", model.naming, NAMING_STYLES)
    with problems.part():
        if isinstance(model.dimensions, bool) or model.dimensions not in DIMENSIONS:
            raise ModelError("dimensions", "2 (a planar chain) or 3 (a spatial chain)", model.dimensions)
    values = None
    with problems.part():
        values = _Values(model)
        values.units = units
    tables = {}
    for kind, cls in (("bodies", RigidBody), ("beams", Beam), ("joints", Joint), ("loads", Load),
                      ("distributed_loads", DistributedLoad),
                      ("springs", PointSpring), ("constraints", LoopConstraint), ("sensors", Sensor),
                      ("controllers", Controller)):
        with problems.part():
            tables[kind] = _table(model, kind, cls)
    with problems.part(later=True):
        _check_simulation(model.simulation)
    with problems.part(later=True):
        if not isinstance(model.initial, dict):
            raise ModelError("initial", "a table of initial values by coordinate or speed name", model.initial)
        from .coordinates import starts_at_equilibrium

        starts_at_equilibrium(model)     # initial.equilibrium: true or false
    problems.raise_found()   # values and parts are needed by every check below
    dimensions = model.dimensions
    with problems.part():
        _check_parameter_names(model)
    with problems.part():
        _check_gravity(model.gravity, values, dimensions)
    bodies, beams = tables["bodies"], tables["beams"]
    for name in beams:
        if name in bodies:
            with problems.part():
                raise ModelError(f"beams.{name}", "a name unique among bodies and beams", name)
    for name in list(bodies) + list(beams):
        if name == "ground":
            with problems.part():
                raise ModelError(f"{'bodies' if name in bodies else 'beams'}.{name}",
                                 "a name other than 'ground' (the fixed frame)", name)
    if not bodies and not beams:
        with problems.part():
            raise ModelError("bodies", "at least one body or beam", None, show_given=False)
    for body in bodies.values():
        with problems.part():
            _check_body(body, values, dimensions)
            values.declared_rest(BODIES, body, f"bodies.{body.name}", dimensions)
    lengths = {}
    for beam in beams.values():
        with problems.part():
            length = (_check_spatial_beam if dimensions == 3 else _check_beam)(beam, values)
            values.declared_rest(BEAMS, beam, f"beams.{beam.name}", dimensions)
            lengths[beam.name] = length
    with problems.part():   # over the beams that passed their own checks
        _check_elastic_coordinates({name: beams[name] for name in lengths})
    problems.raise_found()   # joints and ends refer to parts and beam lengths
    for joint in model.joints.values():
        with problems.part():
            _check_joint(model, joint, values, lengths)
            values.declared_rest(JOINTS, joint, f"joints.{joint.name}", dimensions)
    problems.raise_found()   # the tree is made of valid joints
    with problems.part():
        _check_tree(model)
    for kind, check in (("loads", _check_load), ("distributed_loads", _check_distributed_load),
                        ("springs", _check_spring), ("constraints", _check_constraint)):
        for part in getattr(model, kind).values():
            with problems.part():
                check(model, part, values, lengths)
                values.declared_rest(schema.table(kind), part, f"{kind}.{part.name}", dimensions)
    problems.raise_found(final=True)   # the structure needs a valid tree of valid parts
    coordinates = _check_structure(model, values)
    _check_signals(model, values, lengths, coordinates)
    from .columns import result_columns

    result_columns(model, coordinates)   # one name per column of the results


# ---------------------------------------------------------------------------------------- parts
def _check_body(body: RigidBody, values: _Values, dimensions: int) -> None:
    path = f"bodies.{body.name}"
    values.declared(BODIES, "mass", body, path, dimensions)
    if dimensions == 3:
        from . import validate_spatial as spatial

        spatial.check_body(body, values)
        return
    values.non_negative(f"{path}.inertia", body.inertia, "moment of inertia about the mass centre", "kg m^2")
    if not isinstance(body.points, dict):
        raise ModelError(f"{path}.points", "a table of named points { P = [x, y] } [m]", body.points)
    for pname, xy in body.points.items():
        _name(f"{path}.points.{pname}", pname, f"a point name {_NAME_RULE}")
        values.pair(f"{path}.points.{pname}", xy, "coordinates from the mass centre", "m")
    if not isinstance(body.outline, (list, tuple)):
        raise ModelError(f"{path}.outline", "a list of [x, y] vertices [m]", body.outline)
    for k, xy in enumerate(body.outline):
        values.pair(f"{path}.outline[{k}]", xy, "vertex coordinates from the mass centre", "m")


def _check_shape_spec(path: str, spec, values: _Values) -> None:
    if not isinstance(spec, ShapeSpec):
        raise ModelError(path, "a shape family name or a table { family = ... }", spec)
    if not isinstance(spec.family, str):
        raise ModelError(f"{path}.family", "the name of a shape-function family", spec.family)
    if spec.roots is not None:
        expected = "a non-empty list of positive finite values lambda_i [-] (numbers or expressions of the parameters)"
        if not isinstance(spec.roots, (list, tuple)) or not spec.roots:
            raise ModelError(f"{path}.roots", expected, spec.roots)
        for i, root in enumerate(spec.roots):
            number = values.number(f"{path}.roots[{i}]", root, "eigenvalue parameter lambda_i", "-")
            if not number > 0:
                raise ModelError(f"{path}.roots", expected, list(spec.roots),
                                 f"roots[{i}] = {values.shown(root, number)}")
    if not isinstance(spec.options, dict):
        raise ModelError(path, "family options as a table", spec.options)


def _check_beam(beam: Beam, values: _Values) -> float:
    path = f"beams.{beam.name}"
    length = values.declared(BEAMS, "L", beam, path)
    values.declared(BEAMS, "EI", beam, path)
    values.declared(BEAMS, "rho", beam, path)
    n = _integer(f"{path}.n_modes", beam.n_modes, 1, MAX_MODES, "number of shape functions")
    _check_shape_spec(f"{path}.shape", beam.shape, values)
    if beam.shape.roots is not None and len(beam.shape.roots) != n:
        raise ModelError(f"{path}.shape.roots", f"{n} roots lambda_i (one per mode, n_modes = {n})",
                         list(beam.shape.roots))
    if not isinstance(beam.damping, (list, tuple)):
        raise ModelError(f"{path}.damping", "a list of modal damping ratios [-]", beam.damping)
    if beam.damping and len(beam.damping) not in (1, n):
        raise ModelError(f"{path}.damping", f"1 or {n} modal damping ratios [-] (n_modes = {n})",
                         list(beam.damping))
    for i, zeta in enumerate(beam.damping):
        values.non_negative(f"{path}.damping[{i}]", zeta, "modal damping ratio", "-")
    _choice(f"{path}.gravity", beam.gravity, GRAVITY_MODELS)
    _choice(f"{path}.elastic_forces", beam.elastic_forces, ELASTIC_MODELS)
    if not isinstance(beam.geometric_stiffening, bool):
        raise ModelError(f"{path}.geometric_stiffening", "true or false", beam.geometric_stiffening)
    if not isinstance(beam.static_corrections, bool):
        raise ModelError(f"{path}.static_corrections", "true or false (static correction shapes at the tip)",
                         beam.static_corrections)
    n_axial = _integer(f"{path}.n_axial", beam.n_axial, 0, MAX_MODES, "number of axial shape functions")
    if beam.EA is not None:
        values.declared(BEAMS, "EA", beam, path)
    if n_axial:
        if beam.EA is None:
            raise ModelError(f"{path}.EA", "the axial stiffness [N] (required with n_axial > 0)", None,
                             show_given=False)
        if beam.axial_shape is None:
            raise ModelError(f"{path}.axial_shape", "an axial shape family (required with n_axial > 0)",
                             None, show_given=False)
        _check_shape_spec(f"{path}.axial_shape", beam.axial_shape, values)
    if beam.rotary_inertia is not None:
        values.non_negative(f"{path}.rotary_inertia", beam.rotary_inertia,
                            "mass moment of inertia of the section per unit length, rho I", "kg m")
    _check_shear_moment(path, beam, n_axial)
    return length


def _check_shear_moment(path: str, beam: Beam, n_axial: int) -> None:
    """The shear-moment form of the elastic forces (eq. 8.28, the notebook's) is that of a beam
    without geometric stiffening and axial modes (in 3D: in each bending plane)."""
    if beam.elastic_forces == "shear-moment" and (beam.geometric_stiffening or n_axial):
        raise ModelError(f"{path}.elastic_forces", "'strain-energy' with geometric_stiffening or axial modes",
                         beam.elastic_forces)


def _check_spatial_beam(beam: Beam, values: _Values) -> float:
    """A beam of a spatial model: two bending planes, torsion and axial stretch (Beam's docstring)."""
    path = f"beams.{beam.name}"
    length = values.declared(BEAMS, "L", beam, path, 3)
    for key in ("rho", "EI_y", "EI_z"):
        values.declared(BEAMS, key, beam, path, 3)
    counts = {}
    for key in ("n_modes_y", "n_modes_z", "n_torsion", "n_axial"):
        counts[key] = _integer(f"{path}.{key}", getattr(beam, key), 0, MAX_MODES, "number of shape functions")
    for key, shape in (("y", beam.shape_y), ("z", beam.shape_z)):
        _check_shape_spec(f"{path}.shape_{key}", shape, values)
        if shape.roots is not None and len(shape.roots) != counts[f"n_modes_{key}"]:
            raise ModelError(f"{path}.shape_{key}.roots", f"{counts[f'n_modes_{key}']} roots lambda_i (one per mode)",
                             list(shape.roots))
    for count, stiffness, shape in (("n_torsion", "GJ", "torsion_shape"), ("n_axial", "EA", "axial_shape")):
        if getattr(beam, stiffness) is not None:
            values.declared(BEAMS, stiffness, beam, path, 3)
        if counts[count]:
            if getattr(beam, stiffness) is None:
                field = BEAMS.field(stiffness)
                raise ModelError(f"{path}.{stiffness}", f"the {field.doc} [{field.unit_in(3)}] (required with "
                                 f"{count} > 0)", None, show_given=False)
            _check_shape_spec(f"{path}.{shape}", getattr(beam, shape), values)
    for key in ("rho_Ip", "principal_angle", "rho_Iy", "rho_Iz"):
        if getattr(beam, key) is not None:
            values.declared(BEAMS, key, beam, path, 3)
    if beam.rotary_inertia is not None:
        raise ModelError(f"{path}.rotary_inertia", "no rotary_inertia on a beam with dimensions = 3",
                         beam.rotary_inertia, "a spatial Rayleigh beam has rho_Iy and rho_Iz (about y_p and z_p)")
    if beam.damping:
        raise ModelError(f"{path}.damping", "no damping on a beam with dimensions = 3", list(beam.damping),
                         "a spatial beam has damping_y, damping_z, torsion_damping and axial_damping")
    for key, count in (("damping_y", "n_modes_y"), ("damping_z", "n_modes_z"), ("torsion_damping", "n_torsion"),
                       ("axial_damping", "n_axial")):
        ratios = getattr(beam, key)
        if not isinstance(ratios, (list, tuple)):
            raise ModelError(f"{path}.{key}", "a list of modal damping ratios [-]", ratios)
        if ratios and len(ratios) not in (1, counts[count]):
            raise ModelError(f"{path}.{key}", f"1 or {counts[count]} modal damping ratios [-] ({count} = "
                             f"{counts[count]})", list(ratios))
        for i, zeta in enumerate(ratios):
            values.non_negative(f"{path}.{key}[{i}]", zeta, "modal damping ratio", "-")
    if beam.torsion_damping and beam.rho_Ip is None:
        raise ModelError(f"{path}.rho_Ip", "the polar mass moment of inertia of the section per unit length [kg m] "
                         "(the torsion modes' mass, required with torsion_damping)", None, show_given=False)
    _choice(f"{path}.gravity", beam.gravity, GRAVITY_MODELS)
    _choice(f"{path}.elastic_forces", beam.elastic_forces, ELASTIC_MODELS)
    if not isinstance(beam.geometric_stiffening, bool):
        raise ModelError(f"{path}.geometric_stiffening", "true or false", beam.geometric_stiffening)
    _check_shear_moment(path, beam, counts["n_axial"])
    if not isinstance(beam.static_corrections, bool):
        raise ModelError(f"{path}.static_corrections", "true or false (static correction shapes at the tip)",
                         beam.static_corrections)
    if not any(counts.values()):
        raise ModelError(f"{path}.n_modes_y", "at least one shape function (n_modes_y, n_modes_z, n_torsion "
                         "or n_axial)", 0)
    return length


def _point(path: str, model, body: str, point) -> None:
    if point is None:
        return
    points = model.bodies[body].points
    if not isinstance(point, str) or point not in points:
        raise ModelError(path, f"a point of body {body!r} ({', '.join(points) or 'it has none'})", point,
                         _suggest(point, points))


def _link(path: str, model, name, *, ground: bool) -> None:
    links = model.link_names()
    if isinstance(name, str) and (name in links or (ground and name == "ground")):
        return
    options = (["ground"] if ground else []) + links
    expected = ("'ground' or " if ground else "") + "the name of a body or a beam"
    raise ModelError(path, f"{expected} ({', '.join(options)})", name,
                     _suggest(name, options) if isinstance(name, str) else None)


def _check_joint(model, joint: Joint, values: _Values, lengths: dict) -> None:
    path = f"joints.{joint.name}"
    dimensions = model.dimensions
    if dimensions == 2 and isinstance(joint.type, str) and joint.type in SPATIAL_JOINT_TYPES \
            and joint.type not in JOINT_TYPES:
        raise ModelError(f"{path}.type", "one of " + ", ".join(repr(c) for c in JOINT_TYPES), joint.type,
                         f"a {joint.type} joint needs a spatial model: dimensions = 3 at the top of the file")
    _choice(f"{path}.type", joint.type, JOINT_TYPES_BY_DIMENSION[dimensions])
    _link(f"{path}.parent", model, joint.parent, ground=True)
    _link(f"{path}.child", model, joint.child, ground=False)
    if joint.parent == joint.child:
        raise ModelError(f"{path}.parent", "a link other than the child", joint.parent)
    given = [key for key in ("parent_point", "station", "parent_position") if getattr(joint, key) is not None]
    allowed = ("parent_point" if joint.parent in model.bodies else
               "station" if joint.parent in model.beams else "parent_position")
    for key in given:
        if key != allowed:
            raise ModelError(f"{path}.{key}", f"{allowed} (not {key}) on parent {joint.parent!r}",
                             getattr(joint, key))
    if joint.parent in model.bodies:
        _point(f"{path}.parent_point", model, joint.parent, joint.parent_point)
    elif joint.parent in model.beams:
        if joint.station is None:
            raise ModelError(f"{path}.station", f"the station x on parent beam {joint.parent!r} [m]", None,
                             show_given=False)
        values.station(f"{path}.station", joint.station, joint.parent, lengths)
    elif joint.parent_position is not None and dimensions == 2:
        values.pair(f"{path}.parent_position", joint.parent_position, "ground coordinates", "m")
    if joint.child in model.bodies:
        _point(f"{path}.child_point", model, joint.child, joint.child_point)
    elif joint.child_point is not None:
        raise ModelError(f"{path}.child_point", "no child point for a beam (a beam hangs at its root)",
                         joint.child_point)
    unit = {"revolute": "rad", "prismatic": "m"}.get(joint.type, "")
    if dimensions == 3:
        from . import validate_spatial as spatial

        dofs, speeds = spatial.joint_counts(joint.type)
        spatial.check_joint_geometry(joint, values)
    else:
        dofs = speeds = len(JOINT_DOFS[joint.type])
        for key in ("axes", "orientation", "child_orientation"):
            if getattr(joint, key) is not None:
                raise ModelError(f"{path}.{key}", f"no {key} in a planar model (dimensions = 2; the child frame's "
                                 "angle is 'angle', a prismatic joint's slide direction 'axis', both [rad])",
                                 getattr(joint, key), "or set dimensions = 3 at the top of the file")
        values.number(f"{path}.angle", joint.angle, "angle of the child frame", "rad")
        axis = values.number(f"{path}.axis", joint.axis, "slide direction angle", "rad")
        if axis != 0 and joint.type != "prismatic":
            raise ModelError(f"{path}.axis", "no slide axis on a joint that is not prismatic", joint.axis)
    for key, what, count in (("coordinates", "coordinate", dofs), ("speeds", "speed", speeds)):
        names = getattr(joint, key)
        _names_list(f"{path}.{key}", names, count, f"{joint.type}-joint {what}")
        if names is not None and model.naming == "sequential":
            raise ModelError(f"{path}.{key}", "no names with naming = 'sequential' (q1, q2, ... are used)",
                             names)
    for key in ("stiffness", "damping", "torque", "driver"):
        if getattr(joint, key) is not None and dofs != 1:
            raise ModelError(f"{path}.{key}", f"a revolute or prismatic joint for a joint {key}", joint.type)
    if dofs != 1:
        values.number(f"{path}.rest", joint.rest, "rest position", "rad or m")
        return
    for key in ("stiffness", "damping"):     # N m/rad or N/m, ... by the joint's type (the declaration's)
        if getattr(joint, key) is not None:
            values.non_negative(f"{path}.{key}", getattr(joint, key), f"joint {key}",
                                JOINTS.field(key).unit_for(dimensions, joint.type))
    values.law(f"{path}.rest", joint.rest, "rest position of the joint spring", JOINTS.field("rest").unit_for(
        dimensions, joint.type))
    if joint.torque is not None:
        what = "actuator torque" if joint.type == "revolute" else "actuator force"
        values.law(f"{path}.torque", joint.torque, what, JOINTS.field("torque").unit_for(dimensions, joint.type))
        if joint.driver is not None:
            raise ModelError(f"{path}.torque", "no actuator torque on a driven joint (the driver supplies it)",
                             joint.torque)
    if joint.driver is not None:
        driver = joint.driver
        if not isinstance(driver, Driver):
            raise ModelError(f"{path}.driver", "a table { coordinate = ... } or { speed = ... }", driver)
        if (driver.coordinate is None) == (driver.speed is None):
            raise ModelError(f"{path}.driver", "exactly one of 'coordinate' and 'speed'",
                             "both" if driver.coordinate is not None else "neither")
        if driver.coordinate is not None:
            values.law(f"{path}.driver.coordinate", driver.coordinate, "prescribed coordinate", unit)
        else:
            values.law(f"{path}.driver.speed", driver.speed, "prescribed speed", f"{unit}/s")


def _check_tree(model) -> None:
    children: dict[str, str] = {}
    for joint in model.joints.values():
        if joint.child in children:
            raise ModelError(f"joints.{joint.name}.child", "a link that no other joint has as child "
                             f"(joint {children[joint.child]!r} already does)", joint.child)
        children[joint.child] = joint.name
    for link in model.link_names():
        if link not in children:
            kind = "bodies" if link in model.bodies else "beams"
            raise ModelError(f"{kind}.{link}", "a link that hangs from a joint (a joint with child "
                             f"{link!r})", None, show_given=False)
    parent_of = {j.child: j.parent for j in model.joints.values()}
    for link in parent_of:
        seen = [link]
        node = parent_of[link]
        while node != "ground":
            if node in seen:
                loop = seen[seen.index(node):] + [node]
                raise ModelError(f"joints.{children[link]}.parent",
                                 "joints forming a tree rooted at the ground (close loops with [constraints])",
                                 " -> ".join(loop))
            seen.append(node)
            node = parent_of[node]


def _check_load(model, load: Load, values: _Values, lengths: dict) -> None:
    path = f"loads.{load.name}"
    _link(f"{path}.body", model, load.body, ground=False)
    if load.body in model.bodies:
        if load.station is not None:
            raise ModelError(f"{path}.station", f"a point (not a station) on body {load.body!r}", load.station)
        _point(f"{path}.point", model, load.body, load.point)
    else:
        if load.point is not None:
            raise ModelError(f"{path}.point", f"a station (not a point) on beam {load.body!r}", load.point)
        if load.station is None:
            raise ModelError(f"{path}.station", f"the station x on beam {load.body!r} [m]", None, show_given=False)
        values.station(f"{path}.station", load.station, load.body, lengths)
    if load.force is None and load.torque is None:
        raise ModelError(path, "a force, a torque or both", None, show_given=False)
    if model.dimensions == 3:
        from . import validate_spatial as spatial

        spatial.check_load(load, values)
    else:
        if load.force is not None:
            if not _is_pair(load.force):
                raise ModelError(f"{path}.force", "a pair [x, y] of force components [N]", load.force)
            for k in range(2):
                values.law(f"{path}.force[{k}]", load.force[k], "force component", "N")
        if load.torque is not None:
            values.law(f"{path}.torque", load.torque, "torque", "N m")
    _choice(f"{path}.frame", load.frame, FRAMES)


def _run_times(simulation) -> tuple[float, ...]:
    """The start and, when it is a finite number, the end of the run [s]."""
    end = simulation.t_end
    return (0.0, float(end)) if _is_finite(end) and end > 0 else (0.0,)


def _check_distributed_load(model, load: DistributedLoad, values: _Values, lengths: dict) -> None:
    from .load_integrability import check_integrable

    path = f"distributed_loads.{load.name}"
    beams = list(model.beams)
    if not isinstance(load.beam, str) or load.beam not in model.beams:
        raise ModelError(f"{path}.beam", f"the name of a beam ({', '.join(beams) or 'the model has none'})",
                         load.beam, _suggest(load.beam, beams) if isinstance(load.beam, str) else None)
    _choice(f"{path}.frame", load.frame, DISTRIBUTED_FRAMES)
    _integer(f"{path}.quadrature_nodes", load.quadrature_nodes, 1, 200, "number of Gauss-Legendre nodes")
    if "x" in values.parameters:
        raise ModelError("parameters.x", "parameter names other than 'x' in a model with distributed loads "
                         "(x is the position along the beam)", "x")
    kind = "force per unit length [N/m], a number or an expression of x [m], t [s] and the parameters"
    length = lengths[load.beam]
    keys = ("fx", "fy", "fz") if model.dimensions == 3 else ("fx", "fy")
    if model.dimensions != 3 and not (isinstance(load.fz, (int, float)) and load.fz == 0):
        raise ModelError(f"{path}.fz", "no fz in a planar model (forces per length in the plane: fx, fy)", load.fz)
    for key in keys:
        value = getattr(load, key)
        if not _is_value(value):
            raise ModelError(f"{path}.{key}", kind, value)
        _parses(f"{path}.{key}", value, values, ("t", "x"))
        for x in (0.0, 0.5 * length, length):
            try:
                values.evaluate(f"{path}.{key}", value, {"t": 0.0, "x": x})
            except ModelError as exc:
                raise ModelError(f"{path}.{key}", f"{kind}, finite at t = 0 along the beam", value,
                                 f"at x = {x:g} m: {exc.hint or exc.expected}") from None
        check_integrable(f"{path}.{key}", value, values.parameters, length, _run_times(model.simulation))
    if all(isinstance(v, (int, float)) and v == 0 for v in (getattr(load, key) for key in keys)):
        raise ModelError(path, f"a non-zero component {' or '.join(keys)} [N/m]", None, show_given=False)


def _parses(path: str, value, values: _Values, names: tuple[str, ...]) -> None:
    """Check that an expression is in the language and uses only the parameters and ``names``."""
    from ..expression_syntax import NeedsSymbolic, simple_names

    try:
        simple_names(value, {**values.parameters, **dict.fromkeys(names, 0.0)})
        return
    except NeedsSymbolic:
        pass
    import sympy as sp

    from ..expressions import parse_expression

    parse_expression(value, {name: sp.Symbol(name, real=True) for name in [*values.parameters, *names]}, path=path)


def _check_end(model, path: str, part, end: str, values: _Values, lengths: dict) -> None:
    """One end of a spring or of a loop constraint."""
    body = getattr(part, f"body_{end}")
    given = {key: getattr(part, f"{key}_{end}", None) for key in ("point", "station", "position")}
    if body == "ground":
        allowed = "position"
    elif isinstance(body, str) and body in model.bodies:
        allowed = "point"
    elif isinstance(body, str) and body in model.beams:
        allowed = "station"
    else:
        options = ["ground"] + model.link_names()
        raise ModelError(f"{path}.body_{end}", f"'ground' or a body or a beam ({', '.join(options)})", body,
                         _suggest(body, options) if isinstance(body, str) else None)
    for key, value in given.items():
        if value is not None and key != allowed:
            raise ModelError(f"{path}.{key}_{end}", f"{allowed}_{end} (not {key}_{end}) on {body!r}", value)
    if allowed == "point":
        _point(f"{path}.point_{end}", model, body, given["point"])
    elif allowed == "station":
        if given["station"] is None:
            raise ModelError(f"{path}.station_{end}", f"the station x on beam {body!r} [m]", None,
                             show_given=False)
        values.station(f"{path}.station_{end}", given["station"], body, lengths)
    elif given["position"] is not None and model.dimensions == 3:
        from . import validate_spatial as spatial

        spatial.check_position(f"{path}.position_{end}", given["position"], values, "ground coordinates")
    elif given["position"] is not None:
        values.pair(f"{path}.position_{end}", given["position"], "ground coordinates", "m")


def _check_spring(model, spring: PointSpring, values: _Values, lengths: dict) -> None:
    path = f"springs.{spring.name}"
    for end in ("a", "b"):
        _check_end(model, path, spring, end, values, lengths)
    if spring.body_a == "ground" and spring.body_b == "ground":
        raise ModelError(f"{path}.body_b", "a body at one end at least", spring.body_b)
    values.declared_rest(SPRINGS, spring, path, model.dimensions)   # stiffness, damping, rest length


def _check_constraint(model, con: LoopConstraint, values: _Values, lengths: dict) -> None:
    path = f"constraints.{con.name}"
    if con.name in model.joints:
        raise ModelError(path, "a name different from every joint's", con.name)
    if model.dimensions == 3:
        from . import validate_spatial as spatial

        count = spatial.check_constraint_kind(con, values)
    else:
        _choice(f"{path}.type", con.type, ("revolute", "prismatic"))
    for end in ("a", "b"):
        _check_end(model, path, con, end, values, lengths)
    if con.body_a == con.body_b:
        raise ModelError(f"{path}.body_b", "a link other than body_a", con.body_b)
    if model.dimensions == 3:
        _names_list(f"{path}.dependent", con.dependent, count, "dependent speed")
        values.non_negative(f"{path}.stabilization", con.stabilization, "constraint stabilization rate", "1/s")
        return
    if con.orientation is not None:
        raise ModelError(f"{path}.orientation", "no orientation in a planar model (a prismatic loop joint has "
                         "angle)", con.orientation)
    values.number(f"{path}.axis", con.axis, "slide direction angle in frame a", "rad")
    values.number(f"{path}.angle", con.angle, "angle of frame b relative to frame a", "rad")
    _names_list(f"{path}.dependent", con.dependent, 2, "dependent speed")
    values.non_negative(f"{path}.stabilization", con.stabilization, "constraint stabilization rate", "1/s")


def _check_gravity(gravity, values: _Values, dimensions: int) -> None:
    if gravity is None:
        return
    if not isinstance(gravity, Gravity):
        raise ModelError("gravity", "a table { g = ..., direction = [x, y] }", gravity)
    values.declared(GRAVITY, "g", gravity, "gravity", dimensions)
    if dimensions == 3:
        from . import validate_spatial as spatial

        spatial.check_gravity(gravity, values)
        return
    direction = gravity.direction
    if not _is_pair(direction):
        raise ModelError("gravity.direction", "two finite values [x, y] (a direction in the ground frame)",
                         direction)
    components = values.pair("gravity.direction", direction, "direction components in the ground frame", "-")
    if components[0] == 0 and components[1] == 0:
        raise ModelError("gravity.direction", "a non-zero direction [x, y]", list(direction))


def _check_simulation(sim) -> None:
    if not isinstance(sim, Simulation):
        raise ModelError("simulation", "a table of run settings", sim)
    validate_run_arguments(t_end=sim.t_end, dt_out=sim.dt_out, rtol=sim.rtol, atol=sim.atol, method=sim.method,
                           max_steps=sim.max_steps, prefix="simulation.", optional=("t_end", "dt_out"))
    for key, what in (("deflection_warning", "fraction of a beam's length [-] above which a run warns"),
                      ("spin_warning", "fraction of a beam's first bending frequency [-] above which a run warns")):
        value = getattr(sim, key)
        if value is not None and not (_is_finite(value) and value > 0):
            raise ModelError(f"simulation.{key}", f"a positive finite {what}", value)


def _is_finite(value) -> bool:
    return not isinstance(value, bool) and isinstance(value, numbers.Real) and math.isfinite(value)


def _check_time(path: str, value) -> None:
    """An end time or output interval [s]: positive and finite."""
    if not (_is_finite(value) and value > 0):
        what = "output interval [s]" if path.endswith("dt_out") else "end time [s]"
        raise ModelError(path, f"a positive finite {what}", value)


def check_output_grid(t_end, dt_out, *, prefix: str = "") -> None:
    """Check an end time and output interval: positive, finite, at most :data:`MAX_OUTPUT_ROWS` rows.

    Parameters
    ----------
    t_end : float
        End time [s].
    dt_out : float
        Output interval [s].
    prefix : str
        Prefix of the key paths in messages (``simulation.``).

    Raises
    ------
    ModelError
        Naming ``t_end`` or ``dt_out``, what was expected and what was given.
    """
    for name, value in (("t_end", t_end), ("dt_out", dt_out)):
        _check_time(prefix + name, value)
    rows = t_end / dt_out
    if not rows <= MAX_OUTPUT_ROWS:
        raise ModelError(prefix + "dt_out", f"an output interval [s] giving at most {MAX_OUTPUT_ROWS:,} output "
                         f"rows up to t_end = {t_end:g} s (dt_out >= {t_end / MAX_OUTPUT_ROWS:g} s)", dt_out,
                         f"that is {rows:.3g} rows")


#: The settings of a run, as :func:`validate_run_arguments` names them.
RUN_SETTINGS = ("t_end", "dt_out", "rtol", "atol", "method", "max_steps")


def validate_run_arguments(*, t_end, dt_out, rtol, atol, method="auto", max_steps=None, progress=None,
                           prefix: str = "", optional=()) -> None:
    """Check the settings of a run before it starts: the one check of :func:`flexkane.simulate`,
    ``flexkane run``, a model's ``[simulation]`` table and a sweep's settings.

    Parameters
    ----------
    t_end : float
        End time [s], positive and finite.
    dt_out : float
        Output interval [s], positive and finite, at most :data:`MAX_OUTPUT_ROWS` rows up to ``t_end``.
    rtol : float
        Relative tolerance [-], from 1e-13 to below 1.
    atol : float
        Absolute tolerance [units of each state], positive and finite.
    method : str
        One of :data:`METHODS`.
    max_steps : int, optional
        Step budget, a positive integer.
    progress : callable, optional
        Called as ``progress(t_reached, t_end)``.
    prefix : str
        Prefix of the key paths in messages (``simulation.`` for a model's table).
    optional : sequence of str
        Settings among :data:`RUN_SETTINGS` that may be None (not given: another source supplies them).

    Raises
    ------
    ModelError
        Naming the argument (``t_end``, ``rtol``, ...), what was expected and what was given; the
        command line names its option instead (:func:`flexkane.commands._common.cli_path`).
    """
    given = {name: value is not None or name not in optional
             for name, value in (("t_end", t_end), ("dt_out", dt_out), ("rtol", rtol), ("atol", atol),
                                 ("method", method))}
    for name, value in (("t_end", t_end), ("dt_out", dt_out)):
        if given[name]:
            _check_time(prefix + name, value)
    if given["atol"] and not (_is_finite(atol) and atol > 0):
        raise ModelError(prefix + "atol", "a positive finite absolute tolerance [units of each state]", atol)
    if given["t_end"] and given["dt_out"]:
        check_output_grid(t_end, dt_out, prefix=prefix)
    low, high = RTOL_RANGE
    if given["rtol"] and not (_is_finite(rtol) and low <= rtol < high):
        raise ModelError(prefix + "rtol", f"a relative tolerance from {low:g} to below {high:g} [-]", rtol)
    if given["method"]:
        _choice(prefix + "method", method, METHODS)
    if max_steps is not None and (isinstance(max_steps, bool) or not isinstance(max_steps, numbers.Integral)
                                  or max_steps < 1):
        raise ModelError(prefix + "max_steps", "a positive integer number of steps", max_steps)
    if progress is not None and not callable(progress):
        raise ModelError("progress", "a function progress(t_reached, t_end), or None", progress)


# ------------------------------------------------------------------------------------ structure
def _check_parameter_names(model) -> None:
    """Refuse a parameter printed like a constant the derivation generates (E_1, H_11, m_<beam>).

    The symbols are distinct whatever the names (see :class:`~flexkane.model.values.GeneratedSymbol`);
    the refusal keeps printed equations readable.
    """
    from .constant_names import generated_constant

    label_beams = len(model.beams) > 1
    for name in model.parameters:
        for beam in model.beams:
            meaning = generated_constant(str(name), beam, beam if label_beams else "")
            if meaning is not None:
                raise ModelError(f"parameters.{name}", "a parameter name other than those of the "
                                 "constants flexkane generates", name,
                                 f"{name!r} is {meaning}; rename the parameter")


def _family(spec: ShapeSpec, path: str, n: int, kind: str, values: _Values) -> None:
    """Build the shape family, check that it is of ``kind`` and provides ``n`` functions."""
    from ..modes.from_spec import shape_family

    try:
        family = shape_family(spec, path, values.parameters)
    except ModelError as exc:
        hint = exc.hint
        option = exc.path.rsplit(".", 1)[-1]
        if hint is None and exc.path == f"{path}.family" and isinstance(spec.family, str):
            from ..modes import family_names

            hint = _suggest(spec.family, family_names())
        if hint is None and option in spec.options and exc.expected.startswith("options among"):
            words = exc.expected[len("options among "):].split(" for family")[0].split(", ")
            hint = _suggest(option, words)
        raise ModelError(exc.path, exc.expected, exc.given, hint) from None
    if family.kind != kind and spec.family != "expression":   # user expressions serve either use
        raise ModelError(f"{path}.family", f"the name of {'an axial' if kind == 'axial' else 'a ' + kind}"
                         " shape-function family", spec.family,
                         f"{spec.family!r} is a family of {family.kind} shape functions")
    if family.max_modes is not None and n > family.max_modes:
        count = path.rsplit(".", 1)[0] + (".n_axial" if kind == "axial" else ".n_modes")
        raise ModelError(count, f"at most {family.max_modes} shape function(s): as many as family "
                         f"{spec.family!r} provides as specified", n)


def _check_structure(model, values: _Values) -> list:
    """Shape families, the chain's coordinates, initial conditions and dependent speeds."""
    from .coordinates import coordinate_names, coordinate_unit, speed_unit

    for beam in model.beams.values():
        path = f"beams.{beam.name}"
        if model.dimensions == 3:
            for key in ("y", "z"):
                _family(getattr(beam, f"shape_{key}"), f"{path}.shape_{key}", getattr(beam, f"n_modes_{key}"),
                        "transverse", values)
            if beam.n_torsion:
                _family(beam.torsion_shape, f"{path}.torsion_shape", beam.n_torsion, "torsion", values)
        else:
            _family(beam.shape, f"{path}.shape", beam.n_modes, "transverse", values)
        if beam.n_axial:
            _family(beam.axial_shape, f"{path}.axial_shape", beam.n_axial, "axial", values)
    coordinates = coordinate_names(model)   # names unique; initial conditions name existing coordinates
    units = {}
    for coord in coordinates:
        units[coord.q] = coordinate_unit(coord.role)
        if coord.u is not None:
            units[coord.u] = speed_unit(coord.role)
    for key, value in model.initial.items():
        if key in units:
            values.number(f"initial.{key}", value, f"initial value of {key}", units[key])
    if model.dimensions == 3:
        from .initial import initial_values

        initial_values(model, values)   # orientations as tables, Euler parameters (all four, not zero)
    free = {c.u for c in coordinates if c.driver is None and c.u is not None}   # e0 of a 3D joint: no speed
    chosen: dict[str, str] = {}
    for con in model.constraints.values():
        for i, name in enumerate(con.dependent or []):
            path = f"constraints.{con.name}.dependent[{i}]"
            if name not in free:
                raise ModelError(path, f"the name of a free generalized speed ({', '.join(sorted(free))})", name,
                                 _suggest(name, free))
            if name in chosen:
                raise ModelError(path, f"a speed not already dependent through constraint {chosen[name]!r}", name)
            chosen[name] = con.name
    return coordinates


def _check_signals(model, values: _Values, lengths: dict, coordinates) -> None:
    """Sensors, controllers and every effort that uses them (:mod:`flexkane.model.signals`)."""
    from .signals import Signals, check_controller, check_sensor, effort_fields

    problems = _Problems()
    signals = None
    with problems.part():
        signals = Signals(model, coordinates, values)
    problems.raise_found()
    for sensor in model.sensors.values():
        with problems.part():
            check_sensor(model, sensor, values, lengths)
    uses = {}
    for ctrl in model.controllers.values():
        with problems.part():
            uses[ctrl.name] = check_controller(ctrl, signals, values)
    with problems.part():
        signals.check_outputs_acyclic(uses)
    deferred = dict(values.deferred)
    for path, value in effort_fields(model):
        deferred.pop(path, None)
        with problems.part():
            signals.used(path, value, "an effort [N, N m, or m, rad for a rest position]")
    for path, value in deferred.items():   # drivers' laws: of t and the parameters, or of the state
        with problems.part():
            if not signals.check_driver(path, value, uses):
                values.number(path, value, "prescribed motion", "m, rad or their rates", time=True)
    problems.raise_found(final=True)
