"""Subcommands of the ``flexkane`` command line, one module each."""
