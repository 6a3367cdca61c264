"""``flexkane modes``: roots, natural frequencies and a plot of a family of shape functions.

Example::

    flexkane modes clamped-free --n 4 --L 1 --EI 35.3 --rho 0.21991

prints ``i, lambda_i`` and, when ``--L``, ``--EI`` (``--EA`` for an axial family) and ``--rho``
(``--GJ`` and ``--rhoIp`` for a torsion family) are all given, ``p_i`` [rad/s] (eq. 8.7) and
``f_i = p_i / (2 pi)`` [Hz]; it writes ``modes-<family>.png`` to ``--out DIR`` (default
``out/modes-<family>``; a non-empty directory needs ``--force``). For ``polynomial`` and
``expression`` families, which have no eigenvalues, the table shows the Rayleigh-Ritz values (``H v = p^2 G v``).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from ..atomic import atomic_writer
from ..errors import ModelError
from ._common import add_out_arguments, default_out, prepare_out

__all__ = ["register", "run", "family_from_args", "add_family_arguments", "output_directory",
           "parse_xi_expressions", "plot_family"]

#: Family options settable from the command line: option name -> flag.
_OPTION_FLAGS = {"mass_ratio": "--mass-ratio", "inertia_ratio": "--inertia-ratio",
                 "expressions": "--expression", "boundary": "--boundary"}


def output_directory(args: argparse.Namespace, command: str, family: str) -> Path:
    """The ``--out`` directory of ``modes`` and ``vibrate``, ``out/<command>-<family>`` by default,
    prepared by :func:`~flexkane.commands._common.prepare_out` (empty or ``--force``, writable)."""
    directory = Path(args.out) if args.out else default_out(f"{command}-{family}")
    return prepare_out(directory, force=args.force)


def parse_xi_expressions(texts: list[str], flag: str) -> list[Any]:
    """Parse expressions of ``xi`` with :func:`flexkane.expressions.parse_expression`."""
    try:
        from ..expressions import parse_expression
    except ImportError:
        raise ModelError(flag, "an expression of xi", texts[0] if texts else None,
                         hint="this installation has no expression parser (flexkane.expressions)") \
            from None
    from ..modes import XI
    if len(texts) == 1:
        return [parse_expression(texts[0], {"xi": XI}, path=flag)]
    return [parse_expression(text, {"xi": XI}, path=f"{flag}[{k}]") for k, text in enumerate(texts)]


#: Placeholder of the list of family names in the help of FAMILY, filled in when the help is shown.
_FAMILY_LIST = "{family names}"


class _FamilyHelpFormatter(argparse.HelpFormatter):
    """Help formatter that lists the shape-function families only when the help is printed.

    Listing them needs :mod:`flexkane.modes` (SciPy, SymPy), which building the parser must not import.
    """

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help
        if text and _FAMILY_LIST in text:
            from ..modes import family_names

            text = text.replace(_FAMILY_LIST, ", ".join(family_names()))
        return text


def add_family_arguments(parser: argparse.ArgumentParser, default: str | None,
                         options: bool = True) -> None:
    """Add ``FAMILY`` and, if ``options``, the family options (``--mass-ratio``,
    ``--inertia-ratio``, ``--expression``, ``--boundary``)."""
    parser.formatter_class = _FamilyHelpFormatter
    parser.add_argument("family", nargs="?", default=default, metavar="FAMILY",
                        help="family of shape functions: " + _FAMILY_LIST
                        + (f" (default {default})" if default else ""))
    if not options:
        return
    parser.add_argument("--mass-ratio", type=float, default=None, metavar="MU",
                        help="tip mass over beam mass M/(rho L) [-] (clamped-free-tip-mass)")
    parser.add_argument("--inertia-ratio", type=float, default=None, metavar="KAPPA",
                        help="tip moment of inertia over rho L^3 [-] (clamped-free-tip-mass)")
    parser.add_argument("--expression", action="append", default=None, metavar="EXPR",
                        help="a shape function of xi = x/L (family expression; repeat per function)")
    parser.add_argument("--boundary", default=None, metavar="ROOT-TIP",
                        help="boundary the expressions must be admissible for, e.g. clamped-free")


def family_from_args(args: argparse.Namespace):
    """Build the :class:`~flexkane.modes.ShapeFamily` named on the command line.

    Raises
    ------
    ModelError
        With the command-line flag as path for a missing or invalid option.
    """
    from ..modes import get_family

    options: dict[str, Any] = {}
    for option, flag in _OPTION_FLAGS.items():
        value = getattr(args, flag[2:].replace("-", "_"), None)
        if value is not None and value != []:
            options[option] = value
    if "expressions" in options:
        options["expressions"] = parse_xi_expressions(options["expressions"], "--expression")
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
            if exc.path == option or exc.path.startswith(f"{option}["):
                raise ModelError(flag + exc.path[len(option):], exc.expected, exc.given, exc.hint,
                                 show_given=exc.given is not None) from None
        raise


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``modes`` subcommand."""
    parser = subparsers.add_parser(
        "modes", help="roots, natural frequencies and plot of a family of shape functions",
        description="Print the roots lambda_i of a family of shape functions and, given --L, "
                    "--EI (--EA) and --rho, the natural frequencies (eq. 8.7); plot the functions "
                    "to modes-<family>.png.")
    add_family_arguments(parser, "clamped-free")
    parser.add_argument("--n", type=int, default=None,
                        help="number of modes (default 4, or the number of --expression)")
    parser.add_argument("--L", type=float, default=None, help="length of the beam [m]")
    parser.add_argument("--EI", type=float, default=None, help="flexural rigidity [N m^2]")
    parser.add_argument("--EA", type=float, default=None, help="axial rigidity [N] (axial families)")
    parser.add_argument("--rho", type=float, default=None, help="mass per unit length [kg/m]")
    parser.add_argument("--GJ", type=float, default=None, help="torsional rigidity [N m^2] (torsion families)")
    parser.add_argument("--rhoIp", type=float, default=None,
                        help="polar mass moment of inertia of the section per unit length [kg m] "
                             "(torsion families)")
    add_out_arguments(parser, "out/modes-FAMILY")
    parser.set_defaults(handler=run)


def _physical(args: argparse.Namespace, kind: str) -> tuple[float, float, float] | None:
    rigidity = {"axial": ("--EA", args.EA, "the axial rigidity [N]"),
                "torsion": ("--GJ", args.GJ, "the torsional rigidity [N m^2]")}.get(
        kind, ("--EI", args.EI, "the flexural rigidity [N m^2]"))
    inertia = ("--rhoIp", args.rhoIp, "the polar mass moment of inertia of the section per unit length"
               " [kg m]") if kind == "torsion" else ("--rho", args.rho, "the mass per unit length [kg/m]")
    given = [("--L", args.L, "the length of the beam [m]"), rigidity, inertia]
    if all(value is None for _, value, _ in given):
        return None
    for flag, value, what in given:
        if value is None:
            raise ModelError(flag, what, None, show_given=False,
                             hint=f"frequencies need --L, {rigidity[0]} and {inertia[0]} together")
        if not math.isfinite(value) or value <= 0.0:
            raise ModelError(flag, f"{what}, a positive number", value)
    return args.L, given[1][1], given[2][1]


def _table(family, n: int, physical: tuple[float, float, float] | None) -> list[str]:
    import numpy as np

    from ..modes.free_vibration import rayleigh_ritz_frequencies

    lam = family.roots(n)
    symbol = "beta_i" if family.kind in ("axial", "torsion") else "lambda_i"
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
        if family.kind in ("axial", "torsion"):
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
    import numpy as np

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
    with atomic_writer(path, "path") as temporary:
        figure.savefig(temporary, format="png", dpi=120)
    return path


def run(args: argparse.Namespace) -> int:
    """Print the table of roots and frequencies and write ``modes-<family>.png``."""
    if args.n is not None and args.n < 1:
        raise ModelError("--n", "a positive integer number of modes", args.n)
    family = family_from_args(args)
    n = args.n if args.n is not None else min(4, family.max_modes or 4)
    if family.max_modes is not None and n > family.max_modes:
        raise ModelError("--n", f"at most {family.max_modes} modes for this family", n)
    physical = _physical(args, family.kind)
    directory = output_directory(args, "modes", family.name)
    for line in _table(family, n, physical):
        print(line)
    path = plot_family(family, n, directory / f"modes-{family.name}.png")
    print(f"wrote {path}")
    return 0
