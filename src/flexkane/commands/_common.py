"""Options shared by the commands that take a model: MODEL, --n-modes, --set."""

from __future__ import annotations

import argparse
import math
import re

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
                        help="number of shape functions of every beam (overrides the model)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="settings",
                        help="override a parameter, an initial condition or any value by key path "
                             "(e.g. --set g=0 --set u3=2 --set beams.B.EI=40); repeatable")


def parse_assignment(text: str) -> tuple[str, object]:
    """Split ``KEY=VALUE``; numbers become numbers, true/false booleans, anything else expression text."""
    if "=" not in text:
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
    return key, value


def apply_settings(model: Model, settings: list[str]) -> Model:
    """A copy of the model with ``KEY=VALUE`` overrides applied (validated afterwards)."""
    from ..model.paths import set_value

    if not settings:
        return model
    model = model.copy()
    for text in settings:
        key, value = parse_assignment(text)
        set_value(model, key, value)
    return model


def model_from_args(args) -> Model:
    """Load the model named on the command line, apply --set and --n-modes, and validate it."""
    from ..builtin import resolve_model

    model = resolve_model(args.model)
    model = apply_settings(model, getattr(args, "settings", []))
    if getattr(args, "n_modes", None) is not None:
        model = model.with_modes(args.n_modes)
    return model.validate()
