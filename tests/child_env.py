"""The environment of a child Python process that runs this checkout's flexkane.

Tests that start ``python -m flexkane`` or a script in a new interpreter put the ``src`` folder of this
checkout first on ``PYTHONPATH`` (the installed package, if any, comes after it). Importable from any
test folder: ``tests/`` is on ``sys.path`` through ``tests/conftest.py``.
"""

import os
import pathlib

SRC = pathlib.Path(__file__).resolve().parents[1] / "src"


def child_env(**variables: str) -> dict:
    """A copy of ``os.environ`` with this checkout's ``src`` first on ``PYTHONPATH`` and ``variables`` set.

    Parameters
    ----------
    **variables : str
        Further environment variables of the child (``FLEXKANE_CACHE_DIR=...``).
    """
    path = os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")])
    return dict(os.environ, PYTHONPATH=path, **variables)
