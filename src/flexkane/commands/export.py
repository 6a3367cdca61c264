"""``flexkane export``: a model's equations as standalone C for controllers and other integrators.

Example::

    flexkane export flexible-arm --c out/arm-c
    cc -O2 -c out/arm-c/flexible_arm.c

writes ``<prefix>.h`` and ``<prefix>.c`` (C99, math.h only): ``<prefix>_rhs``, ``_mass_matrix``,
``_forcing``, ``_kinematics``, ``_outputs`` and ``_solve``, the state, constants and outputs
documented in the header, the model's constants and initial state as default arrays
(:func:`flexkane.c_export.export_c`).
"""

from __future__ import annotations

from ._common import add_equilibrium_argument, add_model_arguments, model_from_args

__all__ = ["register"]


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "export", help="write a model's equations as standalone C (right-hand side, mass matrix, outputs)",
        description="Write the right-hand side, mass matrix, forcing and outputs of a model as one C99 header "
                    "and one source file that need only math.h, with the state, constants and outputs "
                    "documented in the header and the model's constants as a default array.")
    add_model_arguments(p, default=None)
    add_equilibrium_argument(p)
    p.add_argument("--c", metavar="DIR", default=None, dest="c_dir",
                   help="directory to write <prefix>.h and <prefix>.c to (required)")
    p.add_argument("--prefix", default=None, metavar="NAME",
                   help="prefix of the C names and files [default: the model's name as a C identifier]")
    p.add_argument("--force", action="store_true",
                   help="write into an existing non-empty directory (files of the same name are replaced)")
    p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    p.set_defaults(handler=_handle)


def _handle(args) -> int:
    from pathlib import Path

    from ..c_export import export_c
    from ..errors import ModelError
    from ._common import prepare_out

    if args.c_dir is None:
        raise ModelError("--c", "the directory to write the C files to (flexkane export MODEL --c DIR)", None,
                         show_given=False)
    model = model_from_args(args)
    if args.prefix is not None:
        from ..numerics.c_source import check_prefix

        try:
            check_prefix(args.prefix)
        except ValueError as exc:
            raise ModelError("--prefix", str(exc), args.prefix) from None
    out = prepare_out(Path(args.c_dir), force=args.force, flag="--c")
    files = export_c(model, out, prefix=args.prefix, force=True, flag="--c")
    if not args.quiet:
        print(f"wrote {', '.join(f.name for f in files)} to {out}")
    return 0
