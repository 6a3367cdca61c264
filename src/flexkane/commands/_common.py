"""Options shared by the commands that take a model: MODEL, --n-modes, --set."""

from __future__ import annotations

import argparse
import difflib
import math
import re
import tomllib

from ..errors import ModelError
from ..model import Model

__all__ = ["add_model_arguments", "model_from_args", "parse_assignment", "apply_settings"]

_NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")
_INT = re.compile(r"^[+-]?\d+$")


def add_model_arguments(parser: argparse.ArgumentParser, default: str | None = "falling-beam") -> None:
    """MODEL, --n-modes and --set."""
    parser.add_argument("model", nargs="?" if default else None, default=default, metavar="MODEL",
                        help=f"built-in model name or model file (.toml){' [default: ' + default + ']' if default else ''}")
    parser.add_argument("--n-modes", type=int, default=None, metavar="N",
                        help="number of shape functions of every beam, 1 to 20, at most 20 over all beams "
                             "(overrides the model)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="settings",
                        help="override a parameter, an initial condition or any value by key path "
                             "(e.g. --set g=0 --set u3=2 --set beams.B.EI=40 --set 'bodies.RB.points.Q=[0.1, 0]'); "
                             "repeatable")


def _finite(key: str, value, text: str):
    """Refuse inf and nan anywhere in a value read from TOML."""
    items = value if isinstance(value, list) else list(value.values()) if isinstance(value, dict) else [value]
    for item in items:
        if isinstance(item, (list, dict)):
            _finite(key, item, text)
        elif isinstance(item, float) and not math.isfinite(item):
            raise ModelError(f"--set {key}", "finite numbers", text)
    return value


def parse_assignment(text: str) -> tuple[str, object]:
    """Split ``KEY=VALUE`` and read the value.

    Integers and decimal numbers become numbers, ``true``/``false`` booleans; a value starting with
    ``[``, ``{`` or a quote is read as a TOML value (``[0.1, 0]``, ``{ family = "pinned-free" }``,
    ``"text"``); anything else is kept as the text of an expression.
    """
    if not isinstance(text, str) or "=" not in text:
        raise ModelError("--set", "KEY=VALUE", text)
    key, value = text.split("=", 1)
    key, value = key.strip(), value.strip()
    if not key or not value:
        raise ModelError("--set", "KEY=VALUE with a non-empty key and value", text)
    if _INT.match(value):
        return key, int(value)
    if _NUMBER.match(value):
        number = float(value)
        if not math.isfinite(number):
            raise ModelError(f"--set {key}", "a finite number", value)
        return key, number
    if value in ("true", "false"):
        return key, value == "true"
    if value[0] in "[{\"'":
        try:
            parsed = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError as exc:
            raise ModelError(f"--set {key}", "a TOML value such as [0.1, 0] or { family = \"pinned-free\" }",
                             value, str(exc)) from None
        return key, _finite(key, parsed, value)
    return key, value


def apply_settings(model: Model, settings: list[str]) -> Model:
    """A copy of the model with ``KEY=VALUE`` overrides applied (validated afterwards)."""
    from ..model.paths import set_value

    if not settings:
        return model
    model = model.copy()
    for text in settings:
        key, value = parse_assignment(text)
        try:
            set_value(model, key, value)
        except ModelError as exc:
            raise ModelError(f"--set {exc.path}", exc.expected, exc.given, exc.hint) from None
    return model


def _bare_names(model: Model, settings: list[str]) -> set[str]:
    """Keys of ``--set`` without a dot that are not parameters (taken as initial conditions)."""
    import dataclasses

    fields = {f.name for f in dataclasses.fields(model)}
    names = set()
    for text in settings:
        key = text.split("=", 1)[0].strip()
        if "." not in key and "[" not in key and key not in model.parameters and key not in fields:
            names.add(key)
    return names


def model_from_args(args) -> Model:
    """Load the model named on the command line, apply --set and --n-modes, and validate it.

    The validation covers every field, reference and the chain's coordinates (see
    :func:`flexkane.model.validate.validate_model`); a ``--set NAME=...`` whose bare name is neither
    a parameter nor a coordinate or speed is reported as such.
    """
    from ..builtin import resolve_model

    model = resolve_model(args.model)
    settings = list(getattr(args, "settings", None) or [])
    model = apply_settings(model, settings)
    n_modes = getattr(args, "n_modes", None)
    if n_modes is not None:
        if not model.beams:
            raise ModelError("--n-modes", "a model with beams", n_modes, f"{model.name!r} has no beam")
        model = model.with_modes(n_modes)
    _check_bare_names(model, _bare_names(model, settings))
    return model.validate()


def _check_bare_names(model: Model, bare: set[str]) -> None:
    """Report a ``--set NAME=...`` whose name is neither a parameter nor a coordinate or speed."""
    from ..kane.chain import build_chain

    if not bare:
        return
    probe = model.copy()
    for name in bare:
        probe.initial.pop(name, None)
    chain = build_chain(probe.validate())
    names = [c.q.name for c in chain.coordinates] + [c.u.name for c in chain.coordinates]
    for name in sorted(bare):
        if name not in names:
            options = list(model.parameters) + names
            close = difflib.get_close_matches(name, options, n=1, cutoff=0.5)
            raise ModelError(f"--set {name}", f"a parameter ({', '.join(model.parameters) or 'none'}) or a "
                             f"generalized coordinate or speed ({', '.join(names)})", name,
                             f"did you mean {close[0]!r}?" if close else None)
