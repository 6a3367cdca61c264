"""The chapter's notebook, examples/chapter8.ipynb, runs from top to bottom and shows its results.

It is executed with nbclient in a python3 kernel (ipykernel) that inherits the test session's
FLEXKANE_CACHE_DIR, in a temporary directory, so it never goes stale and never writes into the tree.
"""

import json
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
NOTEBOOK = ROOT / "examples" / "chapter8.ipynb"


def test_committed_notebook_has_no_outputs():
    cells = json.loads(NOTEBOOK.read_text())["cells"]
    code = [c for c in cells if c["cell_type"] == "code"]
    assert code and all(c["outputs"] == [] and c["execution_count"] is None for c in code)


def test_chapter8_notebook_executes_and_shows_the_modes_the_equations_the_six_plots_and_the_animation(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    env = dict(os.environ, FLEXKANE_NOTEBOOK_OUT=str(tmp_path / "out"), MPLBACKEND="Agg")
    client = nbclient.NotebookClient(notebook, timeout=240, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute(env=env)
    text, images = [], []
    for cell in notebook.cells:
        for output in cell.get("outputs", []):
            if output["output_type"] == "error":
                pytest.fail(f"{output['ename']}: {output['evalue']}")
            text.append(output.get("text", "") + output.get("data", {}).get("text/markdown", ""))
            images += [k for k in output.get("data", {}) if k.startswith("image/")]
    text = "".join(text)
    assert "lambda_1 = 1.8751040687" in text                             # eq. 8.6
    for r in range(1, 5):
        assert f"F*_{r} - eq. 8.23: 0" in text                           # the chapter's eq. 8.23
    assert "(F_4)_elastic - eq. 8.31: 0" in text
    assert "## Partial velocities" in text and "## Constants" in text    # the report
    assert "falling-beam-exact" in text and "q2(1) = -4.9050 m" in text  # both variants simulated
    assert images.count("image/png") >= 4 and "image/gif" in images     # modes, six plots, animation, 3D
    for name in ("robot-arm-3d-flexible", "rotor-blade", "spacecraft-flexible-slew"):    # section 6
        assert f"{name}: t = 0 ..." in text
    assert "largest tip deflection of the forearm" in text and "slewed 30.0 degrees" in text
    out = tmp_path / "out"
    for name in ("modes.png", "six-plots.png", "falling-beam.gif", "falling-beam/results.npz",
                 "falling-beam-exact/results.npz", "spatial-tips.png", "robot-arm-3d-flexible.png"):
        assert (out / name).stat().st_size > 1000, name
