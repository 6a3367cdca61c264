"""The LQR example, examples/flexible-arm-lqr.ipynb, runs from top to bottom and damps the arm.

Executed as tests/test_notebook.py executes the chapter's notebook (nbclient, a python3 kernel, the
test session's FLEXKANE_CACHE_DIR, a temporary directory).
"""

import json
import os
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
NOTEBOOK = ROOT / "examples" / "flexible-arm-lqr.ipynb"


def test_committed_lqr_notebook_has_no_outputs():
    cells = json.loads(NOTEBOOK.read_text())["cells"]
    code = [c for c in cells if c["cell_type"] == "code"]
    assert code and all(c["outputs"] == [] and c["execution_count"] is None for c in code)


def test_lqr_notebook_slews_the_hub_and_damps_the_tip_vibration_the_open_loop_leaves(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    pytest.importorskip("control")
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    env = dict(os.environ, FLEXKANE_NOTEBOOK_OUT=str(tmp_path / "out"), MPLBACKEND="Agg")
    client = nbclient.NotebookClient(notebook, timeout=240, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute(env=env)
    text = []
    for cell in notebook.cells:
        for output in cell.get("outputs", []):
            if output["output_type"] == "error":
                pytest.fail(f"{output['ename']}: {output['evalue']}")
            text.append(output.get("text", ""))
    text = "".join(text)
    assert "inputs: ['input_effort_shoulder']" in text and "'tip_link'" in text
    opened = re.search(r"open loop: hub at ([\d.]+) rad, residual tip vibration ([\d.]+) mm", text)
    closed = re.search(r"closed loop: hub at ([\d.]+) rad, residual tip vibration ([\d.]+) mm", text)
    assert abs(float(closed.group(1)) - float(opened.group(1))) < 2e-3           # the same slew
    assert float(closed.group(2)) < 0.02 * float(opened.group(2))                # its vibration damped
    assert (tmp_path / "out" / "flexible-arm-lqr.png").stat().st_size > 10_000
