"""Execute examples/chapter8.ipynb headless and save it with its outputs (``make notebook``).

Usage: ``python examples/run_notebook.py [--quiet] [OUT_DIR]`` (default ``out/notebook``). Writes
``OUT_DIR/chapter8.ipynb`` (the executed notebook: open it in Jupyter or on any notebook viewer)
and the files the notebook makes (plots, animation) to ``OUT_DIR/files``. Needs the ``notebook``
extra: ``pip install -e '.[notebook]'``. While the cells run, standard error shows which one and
for how long (:mod:`flexkane.progress`; ``--quiet``: nothing).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(argv: list[str]) -> int:
    quiet = "--quiet" in argv
    argv = [a for a in argv if a != "--quiet"]
    try:
        import nbclient
        import nbformat
    except ImportError as exc:
        print(f"run_notebook: {exc.name} is not installed: pip install -e '.[notebook]'", file=sys.stderr)
        return 2
    out = Path(argv[0] if argv else "out/notebook").resolve()
    out.mkdir(parents=True, exist_ok=True)
    notebook = nbformat.read(HERE / "chapter8.ipynb", as_version=4)
    env = dict(os.environ, FLEXKANE_NOTEBOOK_OUT=str(out / "files"), MPLBACKEND="Agg")
    from flexkane.progress import activity, reporting

    cells = sum(cell.cell_type == "code" for cell in notebook.cells)
    client = nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(out)}})
    try:
        with reporting(quiet), activity(f"executing {HERE.name}/chapter8.ipynb", delay=0) as running:
            started = []

            def on_cell_execute(cell, cell_index, **_):   # the kernel starts a code cell
                started.append(cell_index)
                running.update(len(started), cells, "cells")

            client.on_cell_execute = on_cell_execute
            client.execute(env=env)
    except nbclient.exceptions.CellExecutionError as exc:
        print(f"run_notebook: a cell failed:\n{exc}", file=sys.stderr)
        return 1
    finally:
        nbformat.write(notebook, out / "chapter8.ipynb")
    print(f"wrote {out / 'chapter8.ipynb'} (executed) and the notebook's files in {out / 'files'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
