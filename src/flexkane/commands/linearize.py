"""``flexkane linearize``: linear model, natural frequencies and mode shapes of a chain.

Example::

    flexkane linearize flexible-arm --n-modes 4
    flexkane linearize falling-beam-exact --set g=0 --about rest
    flexkane linearize spin-up --about spin --spin 6

prints the operating point and the table of modes (natural frequency [rad/s] and [Hz], damping
ratio, eigenvalue; rigid-body modes first) and writes to DIR: ``linear_model.npz`` and
``linear_model.mat`` (M, C, K, B, W, V and the state-space A, B_ss, C_ss, D_ss with the names of
states, inputs and outputs; in the .mat also the struct ``statespace`` with A, B, C, D, StateName,
InputName, OutputName), ``modes.csv`` (the table with the mode shapes) and ``mode_shapes.png``.
``--export control`` also writes ``statespace.npz``: the state space as python-control builds it
(A, B, C, D, the names of states, inputs and outputs, dt = 0; no pickles), read back by
``flexkane.analysis.load_control`` as a ``control.StateSpace``. A model without equilibrium (free
fall) exits with code 2 and says so.
"""

from __future__ import annotations

from pathlib import Path

from ._common import add_model_arguments, add_out_arguments, model_from_args

__all__ = ["register", "add_operating_point_arguments", "add_no_result_cache_argument", "answer_and_print", "EXPORTS"]

#: Formats of ``--export``, with the file each writes.
EXPORTS = {"control": "statespace.npz"}


def add_operating_point_arguments(parser, *, spin: bool = True, spin_axis: bool = False) -> None:
    """--about, --spin (unless ``spin`` is false), --hub, --spin-axis (if ``spin_axis``)."""
    # no argparse choices: they would import flexkane.analysis (SciPy) to build the parser; the
    # library checks the value against flexkane.analysis.ABOUT and names --about when it is not one
    parser.add_argument("--about", default=None, metavar="POINT",
                        help="operating point: equilibrium (searched from the initial coordinates), "
                             "rest (undeformed, speeds zero) or spin (a hub at the constant rate --spin) "
                             "[default: equilibrium, or spin when --spin is given]")
    if spin:
        parser.add_argument("--spin", type=float, default=None, metavar="OMEGA",
                            help="spin rate of the hub [rad/s] (--about spin)")
    parser.add_argument("--hub", default=None, metavar="JOINT",
                        help="revolute joint that spins [default: the driven one, else the one on the ground]; "
                             "with --spin-axis, the spherical or free joint that spins freely")
    if spin_axis:
        parser.add_argument("--spin-axis", default=None, metavar="X,Y,Z", type=spin_axis_argument,
                            help="3D models: spin freely about this axis of the child frame of a spherical or "
                                 "free joint (--hub; a torque-free body, a top) instead of driving a revolute hub")


def add_no_result_cache_argument(parser) -> None:
    """``--no-cache``: compute the analysis afresh instead of answering from the cache of results."""
    parser.add_argument("--no-cache", action="store_true",
                        help="compute afresh instead of answering from the cache of analysis results (a repeated "
                             "analysis with the same model, values and options), and store nothing there")


def spin_axis_argument(text: str) -> tuple:
    """``X,Y,Z`` as three floats (argparse reports anything else as an error of --spin-axis, exit 2)."""
    import argparse

    try:
        axis = tuple(float(c) for c in text.split(","))
    except ValueError:
        axis = ()
    if len(axis) != 3:
        raise argparse.ArgumentTypeError(f"expected three numbers X,Y,Z (components along the child frame's axes), "
                                         f"got {text!r}")
    return axis


def operating_point(args) -> tuple[str, float | None]:
    """``(about, spin)`` from the command line."""
    spin = getattr(args, "spin", None)
    about = args.about or ("spin" if spin is not None else "equilibrium")
    return about, spin


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "linearize", help="linearize a model: natural frequencies, mode shapes, state-space matrices",
        description="Linearize Kane's equations of a model about an equilibrium, the state at rest or a "
                    "steady spin: M du' + C du + K dq = B dr. Print the natural frequencies [rad/s, Hz], "
                    "damping ratios and rigid-body modes; write the matrices (.npz, .mat), modes.csv and "
                    "mode_shapes.png to DIR.")
    add_model_arguments(p, default=None)
    add_operating_point_arguments(p, spin_axis=True)
    p.add_argument("--t0", type=float, default=0.0, metavar="T",
                   help="time of the operating point [s]: loads and drivers are taken there [default: 0]")
    p.add_argument("--plot-modes", type=int, default=4, metavar="K", help="number of mode shapes drawn [default: 4]")
    p.add_argument("--export", action="append", default=[], metavar="FORMAT",
                   help="also write the state space for another tool (repeatable): control = statespace.npz "
                        "for python-control (flexkane.analysis.load_control reads it)")
    add_out_arguments(p, "out/MODEL_NAME-linearized")
    p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    add_no_result_cache_argument(p)
    p.set_defaults(handler=_handle)


def describe(linear) -> list[str]:
    """Lines describing the operating point of a linear model."""
    if linear.about == "spin":
        about = f"a steady spin of joint {linear.hub} at Omega = {linear.spin:g} rad/s"
        if linear.linearization is not None and linear.linearization.prepared.spin_axis is not None:
            axis = ", ".join(f"{c:g}" for c in linear.linearization.prepared.spin_axis)
            about += f" about ({axis}) of its child frame"
    else:
        about = "an equilibrium" if linear.about == "equilibrium" else "rest"
    n, m = linear.n, len(linear.inputs)
    lines = [f"{linear.name}: linearized about {about}, {n} degree{'s' if n != 1 else ''} of freedom, "
             f"{m} input{'s' if m != 1 else ''} ({', '.join(linear.input_names) or 'none'})"]
    if linear.n:
        lines.append("operating point: " + ", ".join(f"{c} = {v:.6g}" for c, v in zip(linear.coordinates, linear.q0)))
    if linear.nz:
        lines.append("controller states: " + ", ".join(f"{c} = {v:.6g}"
                                                      for c, v in zip(linear.controller_states, linear.z0)))
    lines += [f"note: {note}" for note in linear.notes]
    return lines


def _handle(args) -> int:
    from ..errors import ModelError
    from ._common import default_out, prepare_out

    model = model_from_args(args)
    if args.plot_modes < 1:
        raise ModelError("--plot-modes", "a positive number of modes", args.plot_modes)
    for export in args.export:
        if export not in EXPORTS:
            raise ModelError("--export", "one of " + ", ".join(EXPORTS), export)
    out = prepare_out(Path(args.out) if args.out else default_out(model.name, "-linearized"), force=args.force)
    return answer_and_print(args, "linearize", model, out, lambda out: _linearize(args, model, out))


def answer_and_print(args, analysis: str, model, out: Path, compute) -> int:
    """The result from the cache of analysis results, else ``compute(out)``
    (:func:`flexkane.result_cache.answer`); its lines printed unless --quiet. Exit code 0."""
    from ..result_cache import analysis_options, answer

    result = answer(analysis, model, analysis_options(args), out, compute, cache=not args.no_cache)
    if not args.quiet:
        for line in result.lines:
            print(line)
        count = len(result.files)
        print(f"wrote {count} file{'s' if count != 1 else ''} to {out}")
    return 0


def _linearize(args, model, out: Path) -> tuple[list[str], list[str]]:
    """Linearize, write the files to ``out``; the lines to print and the names of the files."""
    from ..atomic import atomic_write_text
    from ..analysis import Linearization, modal_analysis, plot_mode_shapes

    about, spin = operating_point(args)
    linear = Linearization(model, about=about, spin=spin, hub=args.hub, t0=args.t0, spin_axis=args.spin_axis).at()
    modal = modal_analysis(linear)
    names = ["linear_model.npz", "linear_model.mat", "modes.csv"]
    linear.save_npz(out / "linear_model.npz")
    linear.save_mat(out / "linear_model.mat")
    atomic_write_text(out / "modes.csv", modal.csv_text())
    spatial = model.dimensions == 3 and not model.beams     # rigid 3D chains: shapes in modes.csv only
    if not spatial:
        plot_mode_shapes(modal, out / "mode_shapes.png", count=args.plot_modes)
        names.append("mode_shapes.png")
    exports = sorted(set(args.export))
    if "control" in exports:
        linear.save_control(out / EXPORTS["control"])
        names.append(EXPORTS["control"])
    lines = describe(linear)
    rigid = len(modal.rigid)
    if rigid:
        lines.append(f"{rigid} rigid-body mode{'s' if rigid > 1 else ''} (zero frequency)")
    if not modal.stable:
        lines.append("the operating point is unstable (a mode grows)")
    lines.append(modal.table())
    if spatial:
        lines.append("note: mode_shapes.png is drawn for planar models and spatial models with beams only "
                     "(the shapes are in modes.csv)")
    return lines, names
