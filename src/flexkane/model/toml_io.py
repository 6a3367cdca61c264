"""Reading and writing model files (TOML).

The file has one table per kind of part, keyed by name::

    dimensions = 3          # a spatial model (2, the default, is planar)
    [parameters]            # name = number or "expression of other parameters"
    [bodies.NAME]           # mass, inertia, points = { P = [x, y] }, outline = [[x, y], ...]
    [beams.NAME]            # L, EI, rho, n_modes, shape = { family, roots, ... }, damping, ...
    [joints.NAME]           # type, parent, child, parent_point | parent_position | station, ...
    [gravity]               # g, direction
    [loads.NAME]            # body, point | station, force, torque, frame
    [distributed_loads.NAME]  # beam, fx, fy, fz (3D) (expressions of x, t), frame, quadrature_nodes
    [springs.NAME]          # body_a, point_a | station_a | position_a, body_b, ..., stiffness, damping, rest_length
    [constraints.NAME]      # loop-closure joints: type, body_a, point_a | station_a | position_a, ...
    [sensors.NAME]          # type, beam | body, point | station, joint, distance, frame, component
    [controllers.NAME]      # states = { z = "rate" }, initial = { z = value }, output, min, max
    [initial]               # coordinate or speed name = value
    [simulation]            # t_end, dt_out, rtol, atol, method, max_steps, deflection_warning, spin_warning
    [sweep]                 # read by flexkane.sweep, ignored here

In a spatial model vectors have three components, a body's ``inertia`` is three principal values or
a 3 x 3 tensor, a joint has ``axis = [ax, ay, az]`` (or ``axes`` for a universal joint) and
``orientation`` / ``child_orientation`` tables (:func:`flexkane.model.file_layout.orientation_from_table`),
a load's ``torque`` is a vector.

Reading checks the layout of the file: tables where tables belong, no unknown key (a typo is
reported with the nearest valid key), every required key present. Every part is read and written as
the model schema (:mod:`flexkane.model.schema`) declares its fields (:func:`read_part`,
:func:`write_part`). Values are kept as given (a
number or the text of an expression); :func:`flexkane.model.validate.validate_model` then checks
their types and ranges with the unit of each field, and every reference, so that a model built in
Python gets the same checks.
"""

from __future__ import annotations

import dataclasses
import difflib
import numbers
import tomllib
from pathlib import Path

import tomli_w

from ..errors import ModelError
from . import schema
from .file_layout import GRAVITY_KEYS, SHAPE_KEYS, SIM_KEYS, TOP_KEYS, orientation_from_table
from .model import Model
from .parts import Driver, ShapeSpec
from .schema import DRIVER

__all__ = ["load_model", "loads_model", "dumps_model", "save_model", "model_to_dict", "read_part", "write_part",
           "MAX_FILE_BYTES"]

#: Largest model file accepted [bytes].
MAX_FILE_BYTES = 1_000_000

_MISSING = object()


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _check_keys(table: dict, valid, path: str) -> None:
    for key in table:
        if key not in valid:
            close = difflib.get_close_matches(key, list(valid), n=1, cutoff=0.5)
            hint = f"did you mean {close[0]!r}?" if close else f"valid keys: {', '.join(valid)}"
            raise ModelError(_join(path, key), "a known key", key, hint)


def _table(parent: dict, key: str, path: str, what: str = "a table") -> dict:
    """A sub-table (empty when absent)."""
    value = parent.get(key, {})
    if not isinstance(value, dict):
        raise ModelError(_join(path, key), what, value)
    return value


def _parts(data: dict, kind: str, keys) -> dict[str, dict]:
    """The tables of one kind of part, ``[kind.NAME]``, each checked for unknown keys."""
    out = {}
    for name, table in _table(data, kind, "", f"a table of parts [{kind}.NAME]").items():
        if not isinstance(table, dict):
            raise ModelError(f"{kind}.{name}", f"a table [{kind}.{name}] of keys {', '.join(keys)}", table)
        _check_keys(table, keys, f"{kind}.{name}")
        out[name] = table
    return out


def _get(table: dict, key: str, path: str, expected: str | None = None, default=None):
    """A field as given; ``expected`` (what to write, with the unit) makes it required."""
    if key in table:
        return table[key]
    if expected is not None:
        raise ModelError(_join(path, key), expected, None, "missing", show_given=False)
    return default


def _pair(table: dict, key: str, path: str, expected: str | None = None):
    """A pair [x, y] as a tuple (other values are kept as given, for the validation to report)."""
    value = _get(table, key, path, expected)
    return tuple(value) if isinstance(value, list) else value


def _shape(spec, shape_path: str) -> ShapeSpec:
    """A shape family given as its name or as a table ``{ family = ..., roots = [...], options }``."""
    if isinstance(spec, str):
        return ShapeSpec(spec)
    if not isinstance(spec, dict):
        raise ModelError(shape_path, "a family name or a table { family = ..., options }", spec)
    family = _get(spec, "family", shape_path, "the name of a shape-function family")
    roots = spec.get("roots")
    if isinstance(roots, list) and all(isinstance(r, numbers.Real) and not isinstance(r, bool) for r in roots):
        roots = [float(r) for r in roots]
    options = {k: v for k, v in spec.items() if k not in SHAPE_KEYS}
    return ShapeSpec(family, roots, options)


def _vectors(value):
    """Lists (of lists) as tuples, to any depth (other values are kept for the validation)."""
    if isinstance(value, list):
        return tuple(_vectors(v) for v in value)
    return value


def _absent(field, table: dict, path: str, dimensions: int):
    """The value of a field the table does not give (:data:`_MISSING`: the part's default)."""
    if field.required:
        raise ModelError(_join(path, field.key), field.missing_message(dimensions), None, "missing",
                         show_given=False)
    if field.form == "shape" and field.shape_default and (field.default_with is None
                                                          or table.get(field.default_with, 0)):
        return ShapeSpec(field.shape_default)
    return {} if field.form == "table" else _MISSING


def _read_given(field, value, table: dict, path: str, dimensions: int):
    """A field the table gives, as the part keeps it (lists of numbers as tuples, shapes and
    orientations as their classes), by the field's declared form."""
    form = field.form
    if form == "pair":
        return tuple(value) if isinstance(value, list) else value
    if form == "vectors":
        return _vectors(value)
    if form == "axes":
        return [_vectors(a) for a in value] if isinstance(value, list) else value
    if form == "ratios":      # one value: a list of it
        return value if isinstance(value, list) else [value]
    if form == "float":
        return float(value) if isinstance(value, numbers.Real) and not isinstance(value, bool) else value
    where = _join(path, field.key)
    if form == "shape":
        return _shape(value, where)
    if form == "orientation":
        return orientation_from_table(value, where)
    if form == "table":
        return _table(table, field.key, path, f"a table of {field.doc}")
    if form == "driver":
        sub = _table(table, field.key, path, "a table { coordinate = ... } or { speed = ... }")
        _check_keys(sub, DRIVER.keys(dimensions), where)
        return Driver(sub.get("coordinate"), sub.get("speed"))
    if form == "points":
        points = _table(table, field.key, path, "a table of named points { P = [x, y] } [m]")
        return {name: _pair(points, name, where) for name in points}
    if form == "outline":
        return [tuple(v) if isinstance(v, list) else v for v in value] if isinstance(value, list) else value
    return value


def read_part(declared, table: dict, name: str | None, path: str, dimensions: int):
    """A part from its table of the model file, every field read as :mod:`flexkane.model.schema`
    declares it.

    Parameters
    ----------
    declared : flexkane.model.schema.Table
        The declaration of the table.
    table : dict
        The part's table, its keys checked (each a key of ``declared`` in ``dimensions``).
    name : str or None
        The part's name (None for a table of settings such as ``[gravity]``).
    path : str
        Key path of the table, for messages.
    dimensions : int
        The model's number of dimensions.
    """
    given = declared.outside(dimensions)
    if name is not None:
        given["name"] = name
    for field in declared.when_absent(dimensions):
        if field.key not in table:
            value = _absent(field, table, path, dimensions)
            if value is not _MISSING:
                given[field.key] = value
    for key, value in table.items():     # the keys were checked against the declaration
        field = declared.field(key)
        given[key] = value if field.form == "value" else _read_given(field, value, table, path, dimensions)
    return declared.part(**given)


def _model_from_dict(data: dict) -> Model:
    _check_keys(data, TOP_KEYS, "")
    model = Model(name=_get(data, "name", "", default="model"),
                  description=_get(data, "description", "", default=""),
                  naming=_get(data, "naming", "", default="joint"),
                  dimensions=_get(data, "dimensions", "", default=2))
    dimensions = model.dimensions if model.dimensions in (2, 3) else 2
    model.parameters.update(_table(data, "parameters", "", "a table of parameters { name = value }"))
    for kind in ("bodies", "beams", "joints", "loads", "distributed_loads", "springs", "constraints", "sensors",
                 "controllers"):
        declared = schema.table(kind)
        parts = getattr(model, kind)
        for name, table in _parts(data, kind, declared.keys(dimensions)).items():
            parts[name] = read_part(declared, table, name, f"{kind}.{name}", dimensions)
    if "gravity" in data:
        grav = _table(data, "gravity", "", "a table { g = ..., direction = [x, y] }")
        _check_keys(grav, GRAVITY_KEYS, "gravity")
        model.gravity = read_part(schema.GRAVITY, grav, None, "gravity", dimensions)
    model.initial.update(_table(data, "initial", "", "a table of initial values { q_name = value }"))
    sim = _table(data, "simulation", "", "a table of run settings")
    _check_keys(sim, SIM_KEYS, "simulation")
    model.simulation = read_part(schema.SIMULATION, sim, None, "simulation", dimensions)
    return model


def loads_model(text: str, *, source: str = "<string>") -> Model:
    """Parse and validate a model from TOML text.

    Parameters
    ----------
    text : str
        The file's content.
    source : str
        Where it came from, for messages.

    Returns
    -------
    Model
        The model, validated.
    """
    if not isinstance(text, str):
        raise ModelError(source if isinstance(source, str) else "text", "the text of a model file (str)",
                         type(text).__name__)
    if len(text.encode("utf-8", "replace")) > MAX_FILE_BYTES:
        raise ModelError(source, f"a model file of at most {MAX_FILE_BYTES} bytes", f"{len(text)} characters")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(source, "valid TOML", str(exc)) from None
    return _model_from_dict(data).validate()


def load_model(path: str | Path) -> Model:
    """Read and validate a model file.

    Parameters
    ----------
    path : str or Path
        Path of a TOML model file.
    """
    if not isinstance(path, (str, Path)):
        raise ModelError("MODEL", "the path of a model file", type(path).__name__)
    path = Path(path)
    try:
        if path.stat().st_size > MAX_FILE_BYTES:
            raise ModelError(str(path), f"a model file of at most {MAX_FILE_BYTES} bytes",
                             f"{path.stat().st_size} bytes")
        raw = path.read_bytes()
    except OSError as exc:
        raise ModelError("MODEL", "a readable model file", str(path), exc.strerror) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise ModelError(str(path), "a UTF-8 text file", "undecodable bytes") from None
    return loads_model(text, source=str(path))


def _shape_out(spec: ShapeSpec):
    if spec.roots is None and not spec.options:
        return spec.family
    out = {"family": spec.family}
    if spec.roots is not None:
        out["roots"] = list(spec.roots)
    out.update(spec.options)
    return out


def _drop_none(table: dict) -> dict:
    return {k: (list(v) if isinstance(v, tuple) else v) for k, v in table.items() if v is not None}


def _written(field, value):
    """A field's value as the model file writes it, by its declared form."""
    form = field.form
    if form == "shape":
        return _shape_out(value)
    if form == "ratios":
        return list(value)
    if form == "points":
        return {k: list(v) for k, v in value.items()}
    if form == "outline":
        return [list(p) for p in value]
    if form in ("orientation", "driver"):
        return _drop_none(dataclasses.asdict(value)) if dataclasses.is_dataclass(value) else value
    if form == "table":
        return dict(value)
    return list(value) if isinstance(value, tuple) else value


def write_part(declared, part, dimensions: int) -> dict:
    """A part as its table of the model file: the fields of ``dimensions`` in declaration order,
    each written when :mod:`flexkane.model.schema` says (given, changed from its default, not empty).

    Parameters
    ----------
    declared : flexkane.model.schema.Table
        The declaration of the part's table.
    part : dataclass instance
        The part (:mod:`flexkane.model.parts`), or the gravity or run settings.
    dimensions : int
        The model's number of dimensions.

    Returns
    -------
    dict
        Key -> value as the file writes it (lists for tuples, shape families as names or tables).
    """
    out = {}
    for field in declared.of(dimensions):
        value = getattr(part, field.key)
        if field.given_with is not None and not getattr(part, field.given_with):
            continue
        write = field.write
        if (write == "given" and value is None or write == "nonempty" and not value
                or write == "changed" and value == declared.default(field.key)):
            continue
        out[field.key] = value if field.form == "value" and not isinstance(value, tuple) else _written(field, value)
    return out


def model_to_dict(model: Model) -> dict:
    """The model as nested dictionaries in the model-file layout."""
    out: dict = {"name": model.name}
    if model.dimensions != 2:
        out["dimensions"] = model.dimensions
    if model.description:
        out["description"] = model.description
    if model.naming != "joint":
        out["naming"] = model.naming
    if model.parameters:
        out["parameters"] = dict(model.parameters)
    dimensions = model.dimensions
    for kind in ("bodies", "beams", "joints", "gravity", "loads", "distributed_loads", "springs", "constraints",
                 "sensors", "controllers"):
        declared = schema.table(kind)
        if not declared.named:
            if model.gravity is not None:
                out[kind] = write_part(declared, model.gravity, dimensions)
            continue
        parts = getattr(model, kind)
        if parts or kind in ("bodies", "joints"):
            out[kind] = {name: write_part(declared, part, dimensions) for name, part in parts.items()}
    if model.initial:
        out["initial"] = dict(model.initial)
    out["simulation"] = write_part(schema.SIMULATION, model.simulation, dimensions)
    return out


def _plain(value):
    """Tables, lists and numbers as TOML writes them (NumPy scalars and tuples converted)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, bool) or isinstance(value, str):
        return value
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    return value


def dumps_model(model: Model) -> str:
    """The model as TOML text; :func:`loads_model` of it gives an equivalent model."""
    return tomli_w.dumps(_plain(model_to_dict(model)))


def save_model(model: Model, path: str | Path) -> None:
    """Write the model file atomically."""
    from ..atomic import atomic_write_text

    if not isinstance(path, (str, Path)):
        raise ModelError("path", "the path of the model file to write", type(path).__name__)
    text = dumps_model(model)
    try:
        atomic_write_text(Path(path), text)
    except OSError as exc:
        raise ModelError("path", "a writable model file path", str(path), exc.strerror or str(exc)) from None
