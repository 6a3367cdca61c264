"""Command-line interface: ``flexkane SUBCOMMAND ...`` (also ``python -m flexkane``).

Each subcommand lives in its own module of :mod:`flexkane.commands` and provides
``register(subparsers)``; the module's handler returns the process exit code. Errors a user can
cause exit with code 2 (:class:`~flexkane.errors.ModelError`), solver failures with code 3
(:class:`~flexkane.errors.SolverFailure`), and neither prints a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from .errors import FlexkaneError, ModelError, SolverFailure

#: Subcommand modules, in the order ``flexkane --help`` lists them.
COMMAND_MODULES = ("run", "derive", "check", "modes", "vibrate", "animate", "sweep", "linearize", "campbell", "converge",
                   "export")

EXIT_OK = 0
EXIT_USAGE = 2
EXIT_SOLVER = 3


class _Parser(argparse.ArgumentParser):
    """Argument parser whose usage errors exit with code 2 and a one-line message."""

    def error(self, message: str):  # noqa: D401 - argparse API
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """Build the top-level parser with every available subcommand."""
    from ._version import __version__

    parser = _Parser(prog="flexkane",
                     description="Dynamics of planar and spatial chains with flexible links, by Kane's method.")
    parser.add_argument("--version", action="version", version=f"flexkane {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(f"flexkane.commands.{name}")
        except ModuleNotFoundError as exc:  # a command whose module is not there yet
            if exc.name != f"flexkane.commands.{name}":
                raise
            continue
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line and return its exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "handler", None):
        parser.print_help()
        return EXIT_USAGE
    from .garbage_collection import long_lived_objects
    from .interruption import StopRequest
    from .progress import reporting

    try:   # SIGTERM as Ctrl-C in every phase of every command (exit 130); the long phases report on stderr
        with StopRequest(), long_lived_objects(), reporting(quiet=getattr(args, "quiet", False)):
            try:
                return int(args.handler(args) or EXIT_OK)
            except BaseException:
                from .commands._common import remove_unused_out

                remove_unused_out()   # a directory made for the outputs of a command that failed before writing
                raise
    except ModelError as exc:
        from .commands._common import cli_path

        print(f"flexkane: error: {cli_path(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except SolverFailure as exc:
        text = str(exc).replace("`max_steps`", "`max_steps` (--max-steps N, or max_steps in the model's [simulation])")
        print(f"flexkane: solver failure: {text}", file=sys.stderr)
        return EXIT_SOLVER
    except FlexkaneError as exc:
        print(f"flexkane: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("flexkane: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
