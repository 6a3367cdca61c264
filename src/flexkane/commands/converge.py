"""``flexkane converge``: frequencies and an output against the number of modes.

Example::

    flexkane converge flexible-arm --n-modes 1..6
    flexkane converge flexible-arm --n-modes 1..4 --output tip_link --at 0.8

prints a table (one row per number of modes, with the relative change from the previous row) and a
verdict per frequency and output: converged when the last relative change is within ``--tolerance``
(default 1e-3; "converged to 2.1e-04 relative at n = 3", "not converged: last change 3.4e-02 >
0.001"), and writes ``convergence.csv`` and ``convergence_verdicts.csv`` to DIR. With ``--output NAME
--at T`` each model is also integrated from its initial state to T [s] (compiling one right-hand side
per number of modes). Initial values of modes beyond a count under study are dropped with a note.
"""

from __future__ import annotations

from pathlib import Path

from .linearize import add_no_result_cache_argument, add_operating_point_arguments, answer_and_print, \
    operating_point
from ._common import add_out_arguments

__all__ = ["register"]


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "converge", help="convergence study: frequencies and an output as modes are added",
        description="Linearize a model with 1, 2, ... N shape functions per beam (a spatial beam: per bending "
                    "plane and of torsion) and tabulate its first "
                    "natural frequencies and, with --output and --at, an output at a time, and say whether "
                    "each converged (--tolerance); write convergence.csv and convergence_verdicts.csv to DIR.")
    p.add_argument("model", metavar="MODEL", help="built-in model name or model file (.toml)")
    p.add_argument("--n-modes", required=True, metavar="1..N", dest="n_modes_range",
                   help="numbers of shape functions per beam: 1..N, a list A,B,C, or N")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="settings",
                   help="override a parameter, an initial condition or any value by key path; repeatable")
    add_operating_point_arguments(p)
    p.add_argument("--count", type=int, default=4, metavar="K", help="number of frequencies tabulated [default: 4]")
    p.add_argument("--output", default=None, metavar="NAME", help="output to follow, e.g. tip_link (with --at)")
    p.add_argument("--at", type=float, default=None, metavar="T", help="time of the output [s]")
    p.add_argument("--tolerance", type=float, default=None, metavar="TOL",
                   help="relative change per added count of modes under which a frequency or the output has "
                        "converged [default: 1e-3]")
    add_out_arguments(p, "out/MODEL_NAME-converge")
    p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    add_no_result_cache_argument(p)
    p.set_defaults(handler=_handle)


def _handle(args) -> int:
    from ..errors import ModelError
    from ..model.study_ranges import DEFAULT_TOLERANCE, check_tolerance, parse_mode_counts
    from ._common import default_out, model_from_args, prepare_out

    counts = parse_mode_counts(args.n_modes_range)
    tolerance = check_tolerance(DEFAULT_TOLERANCE if args.tolerance is None else args.tolerance)
    if args.count < 1:
        raise ModelError("--count", "a positive number of frequencies", args.count)
    model = model_from_args(args)          # MODEL and --set (--n-modes is the range here)
    out = prepare_out(Path(args.out) if args.out else default_out(model.name, "-converge"), force=args.force)
    return answer_and_print(args, "converge", model, out, lambda out: _converge(args, model, counts, tolerance, out))


def _converge(args, model, counts, tolerance: float, out: Path) -> tuple[list[str], list[str]]:
    """The study with its verdicts at relative ``tolerance``, its files written to ``out``; the lines to
    print and the names of the files."""
    from ..atomic import atomic_write_text
    from ..analysis import convergence_study

    about, spin = operating_point(args)
    study = convergence_study(model, counts, about=about, spin=spin, hub=args.hub, count=args.count,
                              output=args.output, at=args.at, tolerance=tolerance)
    atomic_write_text(out / "convergence.csv", study.csv_text())
    atomic_write_text(out / "convergence_verdicts.csv", study.verdicts_csv_text())
    lines = [f"{model.name}: convergence with the number of modes per beam, linearized about {about}"]
    lines += [f"note: {note}" for note in study.notes]
    lines += [study.table(), study.verdicts_text()]
    return lines, ["convergence.csv", "convergence_verdicts.csv"]
