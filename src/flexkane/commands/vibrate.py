"""``flexkane vibrate``: free vibration of a beam on a fixed base (eqs. 8.3, 8.5).

Example::

    flexkane vibrate clamped-free --L 1 --EI 35.3 --rho 0.21991 --n 8 --tip-load 2 \\
        --t-end 0.5 --dt-out 0.001 --out out/vibrate

releases the cantilever from its static shape under a tip load of 2 N. ``--initial EXPR`` gives
instead the initial deflection [m] as an expression of ``xi = x/L`` (and ``--initial-velocity``
the initial velocity [m/s]; at rest if omitted). Writes ``results.csv`` (columns ``t`` [s],
``tip`` = y(L, t) [m], ``mid`` = y(L/2, t) [m]) and ``vibration.png`` to ``--out DIR`` (default
``out/vibrate-<family>``; a non-empty directory needs ``--force``).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..atomic import atomic_writer
from ..errors import ModelError
from ._common import add_out_arguments
from .modes import add_family_arguments, family_from_args, output_directory, parse_xi_expressions

__all__ = ["register", "run"]

#: Largest number of output times accepted.
MAX_OUTPUT_POINTS = 2_000_000


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``vibrate`` subcommand."""
    parser = subparsers.add_parser(
        "vibrate", help="free vibration of a beam on a fixed base (modal superposition)",
        description="Free vibration of a beam on a fixed base by eqs. 8.3 and 8.5, released from "
                    "a tip load or an initial shape; writes results.csv (t [s], tip [m], mid [m]) "
                    "and vibration.png.")
    add_family_arguments(parser, "clamped-free", options=False)
    parser.add_argument("--L", type=float, required=True, help="length of the beam [m]")
    parser.add_argument("--EI", type=float, required=True, help="flexural rigidity [N m^2]")
    parser.add_argument("--rho", type=float, required=True, help="mass per unit length [kg/m]")
    parser.add_argument("--n", type=int, required=True, help="number of elastic modes")
    start = parser.add_mutually_exclusive_group(required=True)
    start.add_argument("--tip-load", type=float, metavar="P",
                       help="release from the static shape under a tip load P [N] (clamped-free)")
    start.add_argument("--initial", metavar="EXPR",
                       help="initial deflection [m] as an expression of xi = x/L")
    parser.add_argument("--initial-velocity", metavar="EXPR", default=None,
                        help="initial velocity [m/s] as an expression of xi (default: at rest)")
    parser.add_argument("--t-end", type=float, required=True, help="end time [s]")
    parser.add_argument("--dt-out", type=float, required=True, help="output interval [s]")
    add_out_arguments(parser, "out/vibrate-FAMILY")
    parser.set_defaults(handler=run)


def _positive(value: float, flag: str, what: str) -> float:
    if not math.isfinite(value) or value <= 0.0:
        raise ModelError(flag, f"{what}, a positive number", value)
    return value


def _function_of_xi(text: str, flag: str):
    import numpy as np
    import sympy

    from ..modes import XI

    expr = parse_xi_expressions([text], flag)[0]
    function = sympy.lambdify(XI, expr, modules="numpy")
    return lambda xi: np.broadcast_to(np.asarray(function(xi), dtype=float), np.shape(xi))


def output_times(t_end: float, dt_out: float) -> np.ndarray:
    """Output times ``0, dt, 2 dt, ...`` up to ``t_end`` (included when a multiple of ``dt``)."""
    import numpy as np

    count = int(math.floor(t_end / dt_out * (1.0 + 1e-12))) + 1
    if count > MAX_OUTPUT_POINTS:
        raise ModelError("--dt-out", f"at most {MAX_OUTPUT_POINTS} output times up to --t-end",
                         dt_out, hint=f"that would be {count} times")
    return dt_out * np.arange(count)


def _write_csv(path: Path, t: np.ndarray, tip: np.ndarray, mid: np.ndarray) -> None:
    import numpy as np

    table = np.column_stack([t, tip, mid])
    np.savetxt(path, table, delimiter=",", header="t,tip,mid", comments="", fmt="%.12g")


def _plot(path: Path, t: np.ndarray, tip: np.ndarray, mid: np.ndarray, title: str) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(6.4, 4.0), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    axes.plot(t, tip, label="tip, y(L, t)")
    axes.plot(t, mid, label="mid, y(L/2, t)")
    axes.set_xlabel("t [s]")
    axes.set_ylabel("y [m]")
    axes.set_title(title)
    axes.legend(fontsize="small")
    figure.savefig(path, format="png", dpi=120)


def run(args: argparse.Namespace) -> int:
    """Compute the modal coefficients, evaluate tip and mid deflections and write the files."""
    import numpy as np

    from ..modes.free_vibration import FreeVibration

    L = _positive(args.L, "--L", "the length of the beam [m]")
    EI = _positive(args.EI, "--EI", "the flexural rigidity [N m^2]")
    rho = _positive(args.rho, "--rho", "the mass per unit length [kg/m]")
    if args.n < 1:
        raise ModelError("--n", "a positive integer number of modes", args.n)
    t_end = _positive(args.t_end, "--t-end", "the end time [s]")
    dt_out = _positive(args.dt_out, "--dt-out", "the output interval [s]")
    times = output_times(t_end, dt_out)
    family = family_from_args(args)
    if family.roots(1) is None or family.kind != "transverse" \
            or family.name == "clamped-free-tip-mass":
        raise ModelError("FAMILY", "a transverse eigenfunction family without tip body",
                         family.name)
    if args.tip_load is not None:
        if family.name != "clamped-free":
            raise ModelError("--tip-load", "family clamped-free (the static tip-load shape is "
                             "that of a cantilever)", family.name, hint="use --initial")
        if not math.isfinite(args.tip_load):
            raise ModelError("--tip-load", "a finite tip load [N]", args.tip_load)
        directory = output_directory(args, "vibrate", family.name)
        vibration = FreeVibration.from_tip_load(family, args.n, L, EI, rho, args.tip_load)
        start = f"tip load {args.tip_load:g} N released"
    else:
        deflection = _function_of_xi(args.initial, "--initial")
        velocity = None if args.initial_velocity is None else \
            _function_of_xi(args.initial_velocity, "--initial-velocity")
        directory = output_directory(args, "vibrate", family.name)
        vibration = FreeVibration(family, args.n, L, EI, rho, deflection, velocity)
        start = f"y0 = {args.initial}"

    fields = vibration.deflection(np.array([L, 0.5 * L]), times)
    tip, mid = fields[:, 0], fields[:, 1]
    csv_path, png_path = directory / "results.csv", directory / "vibration.png"
    with atomic_writer(csv_path, "path") as temporary:
        _write_csv(temporary, times, tip, mid)
    with atomic_writer(png_path, "path") as temporary:
        _plot(temporary, times, tip, mid, f"{family.name}, {start}")
    p1 = vibration.frequencies[0]
    print(f"{family.name}, {args.n} modes, {start}; p_1 = {p1:.10g} rad/s "
          f"(f_1 = {p1 / (2.0 * math.pi):.10g} Hz)")
    print(f"y(L, 0) = {tip[0]:.10g} m, y(L/2, 0) = {mid[0]:.10g} m")
    print(f"wrote {csv_path}")
    print(f"wrote {png_path}")
    return 0
