"""Key paths into a model: ``beams.arm.EI``, ``bodies.RB.points.Q[0]``, ``initial.q3``, ``L``.

Used by ``--set KEY=VALUE``, by sweeps, and to find the numeric value of a field symbol in a model
that differs from the one that was derived only by its numbers.
"""

from __future__ import annotations

import dataclasses
import re

from ..errors import ModelError
from .model import Model

__all__ = ["get_value", "set_value", "parse_path"]

_TOKEN = re.compile(r"([^.\[\]]+)|\[(\d+)\]")


def parse_path(path: str) -> list:
    """Split ``a.b[0].c`` into ``['a', 'b', 0, 'c']``."""
    parts: list = []
    pos = 0
    for match in _TOKEN.finditer(path):
        if match.start() != pos and path[pos] != ".":
            raise ModelError(path, "a key path such as beams.arm.EI or bodies.hub.points.P[0]", path)
        parts.append(match.group(1) if match.group(1) is not None else int(match.group(2)))
        pos = match.end()
        if pos < len(path) and path[pos] == ".":
            pos += 1
    if not parts or pos != len(path):
        raise ModelError(path, "a key path such as beams.arm.EI or bodies.hub.points.P[0]", path)
    return parts


def _child(obj, key, path):
    if isinstance(key, int):
        if isinstance(obj, (list, tuple)) and 0 <= key < len(obj):
            return obj[key]
        raise ModelError(path, "an index within the list", key)
    if isinstance(obj, dict):
        if key in obj:
            return obj[key]
        raise ModelError(path, f"one of {', '.join(map(str, obj)) or '(none)'}", key)
    if dataclasses.is_dataclass(obj) and key in {f.name for f in dataclasses.fields(obj)}:
        return getattr(obj, key)
    raise ModelError(path, "an existing key", key)


def get_value(model: Model, path: str):
    """The value at a key path."""
    obj = model
    for key in parse_path(path):
        obj = _child(obj, key, path)
    return obj


def set_value(model: Model, path: str, value) -> None:
    """Set the value at a key path (in place).

    A bare name sets a parameter if the model has one of that name, otherwise an initial condition
    (the caller checks that the coordinate exists).
    """
    parts = parse_path(path)
    if len(parts) == 1:
        name = parts[0]
        if name in model.parameters:
            model.parameters[name] = value
        else:
            model.initial[name] = value
        return
    if parts[0] in ("parameters", "initial") and len(parts) == 2:
        getattr(model, parts[0])[parts[1]] = value
        return
    obj = model
    for key in parts[:-1]:
        obj = _child(obj, key, path)
    last = parts[-1]
    if isinstance(last, int):
        if not isinstance(obj, (list, tuple)) or not 0 <= last < len(obj):
            raise ModelError(path, "an index within the list", last)
        if isinstance(obj, tuple):
            # tuples are rebuilt by the parent
            raise ModelError(path, "a settable value (set the whole pair instead)", path)
        obj[last] = value
    elif isinstance(obj, dict):
        if last not in obj:
            raise ModelError(path, f"one of {', '.join(map(str, obj)) or '(none)'}", last)
        obj[last] = value
    elif dataclasses.is_dataclass(obj) and last in {f.name for f in dataclasses.fields(obj)}:
        setattr(obj, last, value)
    else:
        raise ModelError(path, "an existing key", last)
