"""Options shared by the commands: MODEL, --n-modes, --set, --from-equilibrium, --max-steps, and the --out
directory.

Every command that writes files takes its directory through :func:`prepare_out` (refuses a non-empty
directory without ``--force``, checks that it can be written before anything is computed) and derives
its default from the model's name with :func:`default_out` (a name is a label, never a path).
"""

from __future__ import annotations

import argparse
import difflib
import errno
import math
import os
import re
import sys
import tempfile
import tomllib
from pathlib import Path

from ..errors import ModelError
from ..model import Model
from ..model.coordinates import EQUILIBRIUM_KEY

__all__ = ["add_model_arguments", "add_equilibrium_argument", "model_from_args", "parse_assignment", "apply_settings", "parse_settings",
           "add_out_arguments", "add_max_steps_argument", "prepare_out", "default_out", "safe_folder_name",
           "OUT_ROOT", "cli_path", "remove_unused_out"]

#: Folder under which the default output directories go (``out/<model name>``).
OUT_ROOT = Path("out")
#: Longest folder name derived from a model's name [characters].
_MAX_FOLDER_NAME = 100
_UNSAFE_CHARACTERS = re.compile(r"[^A-Za-z0-9._+-]+")

_NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")
_INT = re.compile(r"^[+-]?\d+$")


def add_model_arguments(parser: argparse.ArgumentParser, default: str | None = "falling-beam") -> None:
    """MODEL, --n-modes and --set."""
    parser.add_argument("model", nargs="?" if default else None, default=default, metavar="MODEL",
                        help=f"built-in model name or model file (.toml){' [default: ' + default + ']' if default else ''}")
    parser.add_argument("--n-modes", type=int, default=None, metavar="N",
                        help="number of shape functions of every beam, 1 to 40, at most 40 over all beams "
                             "(overrides the model)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="settings",
                        help="override a parameter, an initial condition or any value by key path "
                             "(e.g. --set g=0 --set u3=2 --set beams.B.EI=40 --set 'bodies.RB.points.Q=[0.1, 0]'); "
                             "repeatable")


def add_equilibrium_argument(parser: argparse.ArgumentParser) -> None:
    """``--from-equilibrium``: start from the static equilibrium (``[initial] equilibrium = true``)."""
    parser.add_argument("--from-equilibrium", action="store_true",
                        help="start at rest in the static equilibrium under gravity, loads and drivers at t0 "
                             "(as [initial] equilibrium = true; the [initial] values are where its search starts)")


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


def parse_settings(settings: list[str]) -> dict:
    """``KEY=VALUE`` texts of ``--set`` as a dict of key paths to values (:func:`parse_assignment`)."""
    return dict(parse_assignment(text) for text in settings)


def apply_settings(model: Model, settings: list[str]) -> Model:
    """A copy of the model with ``KEY=VALUE`` overrides applied (validated afterwards).

    The values go through :meth:`flexkane.Model.with_values`, the Python form of ``--set``; errors
    name the option (``--set beams.B.EI``).
    """
    if not settings:
        return model
    values = parse_settings(settings)
    try:
        return model.with_values(values, validate=False)
    except ModelError as exc:
        raise ModelError(f"--set {exc.path}", exc.expected, exc.given, exc.hint) from None


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
    if getattr(args, "from_equilibrium", False):
        model = model.with_values({f"initial.{EQUILIBRIUM_KEY}": True}, validate=False)
    n_modes = getattr(args, "n_modes", None)
    if n_modes is not None:
        if not model.beams:
            raise ModelError("--n-modes", "a model with beams", n_modes, f"{model.name!r} has no beam")
        try:
            dropped = model.initial_beyond_modes(n_modes)
            model = model.with_modes(n_modes)
        except ModelError as exc:
            if exc.path == "n_modes":
                raise cli_path(exc) from None
            raise ModelError("--n-modes", f"a mode count this model can have ({exc})", n_modes) from None
        if dropped and not getattr(args, "quiet", False):
            print(f"note: --n-modes {n_modes} drops the initial values of {', '.join(dropped)} (modes beyond "
                  "the count)", file=sys.stderr)
    _check_bare_names(model, _bare_names(model, settings))
    return model.validate()


def _check_bare_names(model: Model, bare: set[str]) -> None:
    """Report a ``--set NAME=...`` whose name is neither a parameter nor a coordinate or speed."""
    from ..model.coordinates import coordinate_names, initial_keys

    if not bare:
        return
    probe = model.copy()
    for name in bare:
        probe.initial.pop(name, None)
    coordinates = coordinate_names(probe.validate())
    names = [key for key in initial_keys(coordinates) if key != EQUILIBRIUM_KEY]
    for name in sorted(bare):
        if name not in names and name != EQUILIBRIUM_KEY:
            options = list(model.parameters) + names
            close = difflib.get_close_matches(name, options, n=1, cutoff=0.5)
            raise ModelError(f"--set {name}", f"a parameter ({', '.join(model.parameters) or 'none'}) or a "
                             f"generalized coordinate or speed ({', '.join(names)})", name,
                             f"did you mean {close[0]!r}?" if close else None)


# ------------------------------------------------------------------------------- --max-steps
def add_max_steps_argument(parser: argparse.ArgumentParser) -> None:
    """``--max-steps N``: the integrator's step budget (overrides ``[simulation] max_steps``)."""
    parser.add_argument("--max-steps", type=int, default=None, metavar="N",
                        help="most integration steps of a run [default: the model's simulation.max_steps, "
                             "else 1000000]")


#: Library parameter names and the command-line options that set them (for messages).
_CLI_OPTIONS = {"t_end": "--t-end", "dt_out": "--dt-out", "rtol": "--rtol", "atol": "--atol",
                "method": "--method", "max_steps": "--max-steps", "n_modes": "--n-modes",
                # parameters of flexkane.sweep
                "vary": "--vary", "samples": "--random", "seed": "--seed", "workers": "--workers",
                "batch_size": "--batch-size", "scheduler": "--scheduler", "keys": "--plot-against",
                "metric": "--metric", "out": "--out"}


def cli_path(error: ModelError) -> ModelError:
    """The same error with an argument named by its command-line option (``t_end`` -> ``--t-end``,
    ``vary beams.B.EI`` -> ``--vary beams.B.EI``).

    The library names parameters (``t_end``); the command line speaks of the option the user typed.
    """
    head, _, rest = error.path.partition(" ")
    option = _CLI_OPTIONS.get(head)
    if option is None:
        return error
    if rest:
        option = f"{option} {rest}"
    return ModelError(option, error.expected, error.given, error.hint, show_given=error.given is not None)


# ------------------------------------------------------------------------------- --out
def add_out_arguments(parser: argparse.ArgumentParser, default: str, *, required: bool = False) -> None:
    """``--out DIR`` and ``--force`` of a command that writes files into a directory."""
    parser.add_argument("--out", metavar="DIR", default=None, required=required,
                        help="output directory" + ("" if required else f" [default: {default}]"))
    parser.add_argument("--force", action="store_true",
                        help="write into an existing non-empty directory (files of the same name are replaced)")


def safe_folder_name(name: str, fallback: str = "model") -> str:
    """A folder name derived from a label: no separators, no ``..``, never absolute.

    Characters other than letters, digits, ``.``, ``_``, ``+`` and ``-`` become ``-``; leading dots
    and dashes are dropped (no hidden folders, no ``..``, no option-like names); at most
    :data:`_MAX_FOLDER_NAME` characters. An empty result gives ``fallback``.

    Examples
    --------
    >>> safe_folder_name("../../ESCAPED")
    'ESCAPED'
    >>> safe_folder_name("/etc/passwd")
    'etc-passwd'
    """
    text = _UNSAFE_CHARACTERS.sub("-", str(name)).lstrip(".-")[:_MAX_FOLDER_NAME].rstrip(".-")
    return text or fallback


def default_out(name: str, suffix: str = "") -> Path:
    """The default output directory ``out/<name><suffix>`` of a model (or family) name."""
    return OUT_ROOT / (safe_folder_name(name) + suffix)


def _listing(directory: Path, limit: int = 3) -> str:
    names = sorted(p.name for p in directory.iterdir())
    shown = ", ".join(names[:limit]) + (", ..." if len(names) > limit else "")
    return f"it holds {len(names)} file{'s' if len(names) != 1 else ''}: {shown}"


def _check_writable(directory: Path, flag: str) -> None:
    """Write, sync and remove a small probe file in ``directory``; a read-only, full or otherwise
    unwritable directory is reported now, before any computing."""
    try:
        with tempfile.NamedTemporaryFile(dir=directory, prefix=".flexkane-probe-", suffix=".tmp") as probe:
            probe.write(b"\0" * 65536)
            probe.flush()
            os.fsync(probe.fileno())
    except OSError as exc:
        reason = {errno.ENOSPC: "no space left on the device", errno.EDQUOT: "disk quota exceeded",
                  errno.EROFS: "read-only file system", errno.EACCES: "permission denied"}.get(
                      exc.errno, exc.strerror or str(exc))
        raise ModelError(flag, "a directory flexkane can write to", str(directory),
                         f"{reason}; nothing was computed") from None


def prepare_out(directory, *, force: bool, flag: str = "--out", resumable=None) -> Path:
    """Create or accept the output directory of a command; check it can be written; return it.

    The one place where commands handle ``--out``: called before any computing, so that a refused,
    read-only or full directory costs nothing and loses nothing.

    Parameters
    ----------
    directory : str or os.PathLike
        The directory (``--out``, or the command's default); missing parents are created.
    force : bool
        Accept a non-empty directory (its other files are kept; files of the same name are replaced).
    flag : str
        Option named in messages.
    resumable : callable, optional
        ``resumable(directory) -> bool``: a non-empty directory this command may continue in without
        ``force`` (a sweep resumes its own directory).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ModelError
        A non-empty directory without ``force``, a file of that name, a directory that cannot be
        created or written (read-only, full, no permission).
    """
    from ..atomic import prepare_output_dir

    directory = Path(directory)
    missing = [d for d in (directory, *directory.parents) if not d.exists()]
    if directory.is_dir() and not force and any(directory.iterdir()) and not (resumable and resumable(directory)):
        raise ModelError(flag, "a new or empty directory (or --force to write into it; files of the same "
                         "name are replaced, others kept)", str(directory), _listing(directory))
    try:
        directory = prepare_output_dir(directory, force=True)   # creates it (and its parents)
    except ModelError as exc:
        raise ModelError(flag, exc.expected, exc.given, exc.hint) from None
    if missing:
        _CREATED.append((directory, missing[-1]))
    _check_writable(directory, flag)
    return directory


#: Directories created by :func:`prepare_out` in this process, with the top-most one created.
_CREATED: list[tuple[Path, Path]] = []


def remove_unused_out() -> None:
    """Remove the directories :func:`prepare_out` created that are still empty (the command failed
    before writing anything: bad input found after the directory was checked)."""
    while _CREATED:
        directory, top = _CREATED.pop()
        for folder in (directory, *directory.parents):
            try:
                folder.rmdir()     # only an empty directory
            except OSError:
                break
            if folder == top:
                break
