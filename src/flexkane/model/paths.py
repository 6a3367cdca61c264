"""Key paths into a model: ``beams.arm.EI``, ``bodies.RB.points.Q[0]``, ``initial.q3``, ``L``.

Used by ``--set KEY=VALUE``, by sweeps, and to find the numeric value of a field symbol in a model
that differs from the one that was derived only by its numbers. A path is a dot-separated list of
keys, each optionally followed by list indices ``[k]``; the options of a beam's shape family are
reached through its shape (``beams.B.shape.mass_ratio``).
"""

from __future__ import annotations

import dataclasses
import difflib
import re

from ..errors import ModelError
from .file_layout import BEAM_KEYS, SPATIAL_BEAM_KEYS
from .parts import Beam, ShapeSpec

__all__ = ["get_value", "set_value", "parse_path"]

_KEY = r"[^.\[\]\s=]+"
_PATH = re.compile(rf"{_KEY}(\[\d+\])*(\.{_KEY}(\[\d+\])*)*")
_TOKEN = re.compile(rf"({_KEY})|\[(\d+)\]")
_EXAMPLE = "a key path such as beams.arm.EI, bodies.hub.points.P[0] or a parameter name"


def parse_path(path: str) -> list:
    """Split ``a.b[0].c`` into ``['a', 'b', 0, 'c']``."""
    if not isinstance(path, str) or not _PATH.fullmatch(path):
        raise ModelError(str(path) if isinstance(path, str) and path else "KEY", _EXAMPLE, path)
    return [m.group(1) if m.group(1) is not None else int(m.group(2)) for m in _TOKEN.finditer(path)]


def _keys(obj) -> list[str]:
    if isinstance(obj, dict):
        return [str(k) for k in obj]
    keys = [f.name for f in dataclasses.fields(obj)]
    if isinstance(obj, Beam):     # the keys of a planar or of a spatial beam, not both
        own, other = (SPATIAL_BEAM_KEYS, BEAM_KEYS) if obj.EI_y is not None or obj.EI_z is not None \
            else (BEAM_KEYS, SPATIAL_BEAM_KEYS)
        other = set(other) - set(own)
        keys = [k for k in keys if k not in other]
    if isinstance(obj, ShapeSpec):
        keys += [str(k) for k in obj.options]
    return keys


def _missing(path: str, obj, key) -> ModelError:
    """The error for a key that ``obj`` does not have."""
    if isinstance(key, int) or not (isinstance(obj, dict) or dataclasses.is_dataclass(obj)):
        what = "a list" if isinstance(obj, (list, tuple)) else "a value with sub-keys"
        size = f" of {len(obj)} items" if isinstance(obj, (list, tuple)) else ""
        return ModelError(path, f"an index within {what}{size}" if isinstance(key, int)
                          else f"no key {key!r} below a plain value (the path is too long)",
                          key, None)
    keys = _keys(obj)
    close = difflib.get_close_matches(str(key), keys, n=1, cutoff=0.5)
    hint = f"did you mean {close[0]!r}?" if close else None
    return ModelError(path, f"one of {', '.join(keys) or '(none)'} at {key!r}", key, hint)


def _child(obj, key, path):
    if isinstance(key, int):
        if isinstance(obj, (list, tuple)) and 0 <= key < len(obj):
            return obj[key]
        raise _missing(path, obj, key)
    if isinstance(obj, dict):
        if key in obj:
            return obj[key]
        raise _missing(path, obj, key)
    if dataclasses.is_dataclass(obj) and key in {f.name for f in dataclasses.fields(obj)}:
        return getattr(obj, key)
    if isinstance(obj, ShapeSpec) and key in obj.options:
        return obj.options[key]
    raise _missing(path, obj, key)


def get_value(model, path: str):
    """The value at a key path.

    Parameters
    ----------
    model : Model
    path : str
        E.g. ``"beams.arm.EI"`` or ``"bodies.hub.points.P[0]"``.
    """
    obj = model
    for key in parse_path(path):
        obj = _child(obj, key, path)
    return obj


def _assign(container, key, value, path: str):
    """``container[key] = value`` (or the attribute); returns the container, rebuilt if a tuple."""
    if isinstance(key, int):
        if not isinstance(container, (list, tuple)) or not 0 <= key < len(container):
            raise _missing(path, container, key)
        items = list(container)
        items[key] = value
        if isinstance(container, tuple):
            return tuple(items)
        container[key] = value
        return container
    if isinstance(container, dict):
        if key not in container:
            raise _missing(path, container, key)
        container[key] = value
    elif dataclasses.is_dataclass(container) and key in {f.name for f in dataclasses.fields(container)}:
        setattr(container, key, value)
    elif isinstance(container, ShapeSpec):
        container.options[key] = value   # a family option; the family checks its name and value
    else:
        raise _missing(path, container, key)
    return container


def set_value(model, path: str, value) -> None:
    """Set the value at a key path (in place).

    A bare name sets a parameter if the model has one of that name, else the model's ``name``,
    ``description`` or ``naming``, else an initial condition (the validation then checks that such a
    coordinate or speed exists). ``parameters.NAME`` and
    ``initial.NAME`` (and ``controllers.NAME.initial.STATE``) may add entries; every other path must
    exist. A path to a whole table (a part,
    a list of parts) cannot be replaced by a value.

    Parameters
    ----------
    model : Model
    path : str
    value : int, float, str, bool, list or dict
        The new value, as a model file would give it; checked by :meth:`Model.validate`.
    """
    parts = parse_path(path)
    fields = {f.name for f in dataclasses.fields(model)}
    if len(parts) == 1 and (parts[0] in model.parameters or parts[0] not in fields):
        table = model.parameters if parts[0] in model.parameters else model.initial
        table[parts[0]] = value
        return
    if parts[0] in ("parameters", "initial") and len(parts) == 2 and isinstance(parts[1], str):
        getattr(model, parts[0])[parts[1]] = value
        return
    if parts[0] == "controllers" and len(parts) == 4 and parts[2] == "initial" and parts[1] in model.controllers \
            and isinstance(model.controllers[parts[1]].initial, dict):
        model.controllers[parts[1]].initial[parts[3]] = value   # a controller state's initial value
        return
    chain = [model]
    for key in parts[:-1]:
        chain.append(_child(chain[-1], key, path))
    current = None
    try:
        current = _child(chain[-1], parts[-1], path)
    except ModelError:
        pass
    if dataclasses.is_dataclass(current) or isinstance(current, dict) or (
            isinstance(current, list) and current and dataclasses.is_dataclass(current[0])):
        raise ModelError(path, "a key path to a value (e.g. beams.arm.EI), not to a whole table", value)
    # assign, rebuilding tuples (pairs [x, y]) upwards until a mutable container holds them
    new = value
    for depth in range(len(parts) - 1, -1, -1):
        container = chain[depth]
        rebuilt = _assign(container, parts[depth], new, path)
        if rebuilt is container:
            return
        new = rebuilt
