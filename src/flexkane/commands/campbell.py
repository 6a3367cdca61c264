"""``flexkane campbell``: frequencies of a chain against the spin rate of its hub.

Example::

    flexkane campbell spin-up --spin 0:8:33
    flexkane campbell spin-up-linear --spin 0:8:33 --n-modes 6

writes ``campbell.csv`` (Omega [rad/s], the frequencies in the rotating frame [rad/s] in ascending
order, the largest growth rate [1/s]), ``campbell_modes.csv`` (one row per spin rate and mode: its
label by dominant motion, ``flap 1``, ``lag 1``, ``torsion 1``..., its frequency and the participation
of each family of motion), ``campbell.json`` (the labelled curves and modes) and ``campbell.png``
(the curves, labelled in the legend) to DIR and prints the curves.
"""

from __future__ import annotations

from pathlib import Path

from ._common import add_model_arguments, add_out_arguments, model_from_args
from .linearize import add_no_result_cache_argument, answer_and_print, spin_axis_argument

__all__ = ["register"]


def register(subparsers) -> None:
    from ..limits import MAX_VARIANTS

    p = subparsers.add_parser(
        "campbell", help="Campbell diagram: frequencies against the spin rate of a hub",
        description="Linearize a model about steady spins of a hub (revolute joint) and tabulate and plot "
                    "its frequencies in the rotating frame against the spin rate, each mode labelled by its dominant "
                    "motion (flap, lag, torsion, axial, a joint); write campbell.csv, campbell_modes.csv, "
                    "campbell.json and campbell.png to DIR.")
    add_model_arguments(p, default=None)
    p.add_argument("--spin", required=True, metavar="START:STOP:COUNT",
                   help="spin rates [rad/s]: COUNT values from START to STOP (e.g. 0:8:33), or a list A,B,C; "
                        f"at most {MAX_VARIANTS:,} (as a sweep's variants)")
    p.add_argument("--hub", default=None, metavar="JOINT",
                   help="revolute joint that spins [default: the driven one, else the one on the ground]; "
                        "with --spin-axis, the spherical or free joint that spins freely")
    p.add_argument("--spin-axis", default=None, metavar="X,Y,Z", type=spin_axis_argument,
                   help="3D models: spin freely about this axis of the child frame of a spherical or free joint")
    add_out_arguments(p, "out/MODEL_NAME-campbell")
    p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    add_no_result_cache_argument(p)
    p.set_defaults(handler=_handle)


def _handle(args) -> int:
    from ._common import default_out, prepare_out
    from ..model.study_ranges import parse_spin_range

    spins = parse_spin_range(args.spin)
    model = model_from_args(args)
    out = prepare_out(Path(args.out) if args.out else default_out(model.name, "-campbell"), force=args.force)
    return answer_and_print(args, "campbell", model, out, lambda out: _campbell(args, model, spins, out))


def _campbell(args, model, spins, out: Path) -> tuple[list[str], list[str]]:
    """The diagram, its files written to ``out``; the lines to print and the names of the files."""
    from ..atomic import atomic_write_text
    from ..analysis import campbell_diagram

    diagram = campbell_diagram(model, spins, hub=args.hub, spin_axis=args.spin_axis)
    atomic_write_text(out / "campbell.csv", diagram.csv_text())
    atomic_write_text(out / "campbell_modes.csv", diagram.modes_csv_text())
    atomic_write_text(out / "campbell.json", diagram.json_text())
    diagram.plot(out / "campbell.png")
    lines = [f"{model.name}: Campbell diagram, joint {diagram.hub} spinning at {spins.size} rates "
             f"from {spins[0]:g} to {spins[-1]:g} rad/s"]
    lines += [f"note: {note}" for note in diagram.notes]
    if diagram.unstable.any():
        unstable = diagram.spins[diagram.unstable]
        lines.append(f"unstable (a mode grows) from Omega = {unstable.min():g} rad/s "
                     f"({int(diagram.unstable.sum())} of {spins.size} rates)")
    lines.append(diagram.table())
    return lines, ["campbell.csv", "campbell_modes.csv", "campbell.json", "campbell.png"]
