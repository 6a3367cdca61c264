"""``flexkane modes``: roots, natural frequencies and a plot of a family of shape functions.

Example::

    flexkane modes clamped-free --n 4 --L 1 --EI 35.3 --rho 0.21991

prints ``i, lambda_i`` and, when ``--L``, ``--EI`` (``--EA`` for an axial family) and ``--rho``
are all given, ``p_i`` [rad/s] (eq. 8.7) and ``f_i = p_i / (2 pi)`` [Hz]; it writes
``modes-<family>.png``. For ``polynomial`` and ``expression`` families, which have no
eigenvalues, the table shows the Rayleigh-Ritz values (``H v = p^2 G v``).
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..errors import ModelError

__all__ = ["register", "run", "family_from_args", "write_atomically", "add_family_arguments"]

#: Family options settable from the command line: option name -> flag.
_OPTION_FLAGS = {"mass_ratio": "--mass-ratio", "inertia_ratio": "--inertia-ratio",
                 "expressions": "--expression"}


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_atomically(path: Path, write: Callable[[Path], None]) -> Path:
    """Write a file through a temporary sibling and ``os.replace``, so readers never see half.

    Parameters
    ----------
    path : pathlib.Path
        Final path.
    write : callable
        ``write(temporary_path)`` creates the content.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}-", suffix=path.suffix)
    os.close(fd)
    try:
        write(Path(tmp))
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def output_directory(value: str | None) -> Path:
    """The ``--out`` directory (created if missing), the current directory by default."""
    directory = Path(value) if value else Path.cwd()
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError("--out", "a writable directory", str(directory), hint=exc.strerror) from None
    return directory


def parse_xi_expressions(texts: list[str], flag: str) -> list[Any]:
    """Parse expressions of ``xi`` with :func:`flexkane.expressions.parse_expression`."""
    try:
        from ..expressions import parse_expression
    except ImportError:
        raise ModelError(flag, "an expression of xi", texts[0] if texts else None,
                         hint="this installation has no expression parser (flexkane.expressions)") \
            from None
    from ..modes import XI
    return [parse_expression(text, {"xi": XI}, path=f"{flag}[{k}]") for k, text in enumerate(texts)]


def add_family_arguments(parser: argparse.ArgumentParser, default: str | None) -> None:
    """Add ``FAMILY`` and the family options ``--mass-ratio``, ``--inertia-ratio``, ``--expression``."""
    parser.add_argument("family", nargs="?", default=default, metavar="FAMILY",
                        help="family of shape functions" + (f" (default {default})" if default else ""))
    parser.add_argument("--mass-ratio", type=float, default=None, metavar="MU",
                        help="tip mass over beam mass M/(rho L) [-] (clamped-free-tip-mass)")
    parser.add_argument("--inertia-ratio", type=float, default=None, metavar="KAPPA",
                        help="tip moment of inertia over rho L^3 [-] (clamped-free-tip-mass)")
    parser.add_argument("--expression", action="append", default=None, metavar="EXPR",
                        help="a shape function of xi = x/L (family expression; repeat per function)")


def family_from_args(args: argparse.Namespace):
    """Build the :class:`~flexkane.modes.ShapeFamily` named on the command line.

    Raises
    ------
    ModelError
        With the command-line flag as path for a missing or invalid option.
    """
    from ..modes import get_family

    options: dict[str, Any] = {}
    if args.mass_ratio is not None:
        options["mass_ratio"] = args.mass_ratio
    if args.inertia_ratio is not None:
        options["inertia_ratio"] = args.inertia_ratio
    if args.expression:
        options["expressions"] = parse_xi_expressions(args.expression, "--expression")
    if args.family == "clamped-free-tip-mass":
        for option, what in (("mass_ratio", "M_tip / (rho L) [-], a number >= 0"),
                             ("inertia_ratio", "J_tip / (rho L^3) [-], a number >= 0")):
            if option not in options:
                raise ModelError(_OPTION_FLAGS[option], what, None, hint="required for this family",
                                 show_given=False)
    try:
        return get_family(args.family, **options)
    except ModelError as exc:
        for option, flag in _OPTION_FLAGS.items():
            if exc.path.startswith(f"{args.family}.{option}") or exc.path.startswith(f"expression.{option}"):
                raise ModelError(flag, exc.expected, exc.given, exc.hint,
                                 show_given=exc.given is not None) from None
        raise


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``modes`` subcommand."""
    parser = subparsers.add_parser(
        "modes", help="roots, natural frequencies and plot of a family of shape functions",
        description=__doc__.split("\n\n")[0])
    add_family_arguments(parser, "clamped-free")
    parser.add_argument("--n", type=int, default=4, help="number of modes (default 4)")
    parser.add_argument("--L", type=float, default=None, help="length of the beam [m]")
    parser.add_argument("--EI", type=float, default=None, help="flexural rigidity [N m^2]")
    parser.add_argument("--EA", type=float, default=None, help="axial rigidity [N] (axial families)")
    parser.add_argument("--rho", type=float, default=None, help="mass per unit length [kg/m]")
    parser.add_argument("--out", default=None, metavar="DIR",
                        help="directory of modes-<family>.png (default: current directory)")
    parser.set_defaults(handler=run)


def _physical(args: argparse.Namespace, axial: bool) -> tuple[float, float, float] | None:
    rigidity = ("--EA", args.EA, "the axial rigidity [N]") if axial else \
        ("--EI", args.EI, "the flexural rigidity [N m^2]")
    given = [("--L", args.L, "the length of the beam [m]"), rigidity,
             ("--rho", args.rho, "the mass per unit length [kg/m]")]
    if all(value is None for _, value, _ in given):
        return None
    for flag, value, what in given:
        if value is None:
            raise ModelError(flag, what, None, show_given=False,
                             hint=f"frequencies need --L, {rigidity[0]} and --rho together")
        if not math.isfinite(value) or value <= 0.0:
            raise ModelError(flag, f"{what}, a positive number", value)
    return args.L, given[1][1], args.rho


def _table(family, n: int, physical: tuple[float, float, float] | None) -> list[str]:
    from ..modes.free_vibration import rayleigh_ritz_frequencies

    lam = family.roots(n)
    symbol = "beta_i" if family.kind == "axial" else "lambda_i"
    note = ""
    if lam is None:
        # Ritz values of the dimensionless problem: p L^2 sqrt(rho/EI) = lambda^2
        lam = np.sqrt(rayleigh_ritz_frequencies(family, n, 1.0, 1.0, 1.0))
        note = " (Rayleigh-Ritz)"
    lines = [f"family {family.name} (boundary {family.boundary}), {n} modes{note}"]
    if family.rigid_modes:
        lines.append("rigid-body modes (not counted): "
                     + ", ".join(m.name for m in family.rigid_modes))
    header = f"{'i':>4}  {symbol:>20}"
    if physical is not None:
        L, stiffness, rho = physical
        if family.kind == "axial":
            p = family.frequencies(n, L, stiffness, rho)
        else:
            p = (lam / L) ** 2 * math.sqrt(stiffness / rho)
        header += f"  {'p_i [rad/s]':>20}  {'f_i [Hz]':>20}"
    lines.append(header)
    for i in range(n):
        row = f"{i + 1:>4}  {lam[i]:>20.15g}"
        if physical is not None:
            row += f"  {p[i]:>20.12g}  {p[i] / (2.0 * math.pi):>20.12g}"
        lines.append(row)
    return lines


def plot_family(family, n: int, path: Path) -> Path:
    """Plot ``Phi_i(xi)``, ``i = 1..n``, to a PNG file (Agg canvas, no global backend change)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    xi = np.linspace(0.0, 1.0, 401)
    values = family.phi(xi, n)
    figure = Figure(figsize=(6.4, 4.0), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    for i in range(n):
        axes.plot(xi, values[i], label=f"i = {i + 1}")
    axes.axhline(0.0, color="0.6", linewidth=0.6)
    axes.set_xlabel("x/L")
    axes.set_ylabel("Phi_i")
    axes.set_title(f"{family.name} shape functions")
    if n <= 10:
        axes.legend(fontsize="small")
    return write_atomically(path, lambda tmp: figure.savefig(tmp, format="png", dpi=120))


def run(args: argparse.Namespace) -> int:
    """Print the table of roots and frequencies and write ``modes-<family>.png``."""
    if isinstance(args.n, bool) or args.n < 1:
        raise ModelError("--n", "a positive integer number of modes", args.n)
    family = family_from_args(args)
    if family.max_modes is not None and args.n > family.max_modes:
        raise ModelError("--n", f"at most {family.max_modes} modes for this family", args.n)
    physical = _physical(args, family.kind == "axial")
    for line in _table(family, args.n, physical):
        print(line)
    path = plot_family(family, args.n, output_directory(args.out) / f"modes-{family.name}.png")
    print(f"wrote {path}")
    return 0
