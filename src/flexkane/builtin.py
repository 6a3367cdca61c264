"""Built-in example models, shipped as model files (also in the repository's examples/ folder)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from .errors import ModelError
from .model import Model, load_model, loads_model

__all__ = ["builtin_names", "builtin_model", "builtin_text", "resolve_model"]


def builtin_names() -> list[str]:
    """Names of the built-in models."""
    folder = resources.files("flexkane") / "builtin_models"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def builtin_text(name: str) -> str:
    """Model-file text of a built-in model."""
    if name not in builtin_names():
        raise ModelError("MODEL", f"a built-in model ({', '.join(builtin_names())}) or a model file path",
                         name)
    return (resources.files("flexkane") / "builtin_models" / f"{name}.toml").read_text("utf-8")


def builtin_model(name: str) -> Model:
    """A built-in model by name (e.g. ``falling-beam``)."""
    return loads_model(builtin_text(name), source=name)


def resolve_model(spec: str) -> Model:
    """A model from a built-in name or a model-file path."""
    if spec in builtin_names():
        return builtin_model(spec)
    path = Path(spec)
    if path.suffix == ".toml" or path.exists():
        return load_model(path)
    raise ModelError("MODEL", f"a built-in model ({', '.join(builtin_names())}) or a model file path", spec)
