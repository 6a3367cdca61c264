"""Every command on a spatial (dimensions = 3) model exits 0 with its files, or 2 with a clear message
naming what is refused: never a traceback (exit 1), never a wrong answer.

The spatial built-ins ``robot-arm-3d`` and ``spacecraft-slew`` are derived and compiled once per
module (the cached run of ``ran``); the other commands reuse that cache.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest

import flexkane
from flexkane.cli import main


@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    """Run directories of short runs of the two spatial built-ins (with their animations)."""
    out = {}
    for name in ("robot-arm-3d", "spacecraft-slew"):
        directory = tmp_path_factory.mktemp("runs") / name
        assert main(["run", name, "--out", str(directory), "--quiet", "--t-end", "0.2", "--dt-out", "0.02",
                     "--animate", "--view", "30,-50"]) == 0
        out[name] = directory
    return out


def test_run_writes_the_spatial_outputs(ran):
    header = next(csv.reader(open(ran["spacecraft-slew"] / "results.csv")))
    for column in ("q_float_e0", "u_float_wz", "yaw_bus", "pitch_bus", "roll_bus", "quaternion_norm_float",
                   "H_x", "H_y", "H_z", "energy_balance"):
        assert column in header
    files = {p.name for p in ran["spacecraft-slew"].iterdir()}
    assert {"angular_momentum.png", "quaternion_norm.png", "animation.gif", "equations.md", "equations.tex",
            "energy.png", "q_float_e0.png"} <= files
    results = flexkane.load_results(ran["spacecraft-slew"] / "results.npz")
    assert np.max(np.abs(results["quaternion_norm_float"])) < 1e-9     # |e| - 1
    arm = next(csv.reader(open(ran["robot-arm-3d"] / "results.csv")))
    assert "quaternion_norm_waist" not in arm and "yaw_payload" in arm and "H_z" in arm


def test_equations_name_the_spatial_speeds(ran):
    text = (ran["spacecraft-slew"] / "equations.md").read_text()
    assert "u_{float,wx}" in text or "u_{float wx}" in text or "float_wx" in text


def test_animate_a_finished_spatial_run(ran, tmp_path):
    assert main(["animate", str(ran["robot-arm-3d"]), "--view", "90,-90", "--frames", "5", "--no-mp4",
                 "--out", str(tmp_path / "top.gif")]) == 0
    assert (tmp_path / "top.gif").stat().st_size > 1000


def test_derive_prints_spatial_equations(ran, capsys):
    assert main(["derive", "robot-arm-3d", "--markdown"]) == 0
    assert "u_{waist}" in capsys.readouterr().out
    assert main(["derive", "spacecraft-slew", "--latex"]) == 0
    assert "\\begin" in capsys.readouterr().out


def _refused(capsys, argv, *words):
    code = main(argv)
    err = capsys.readouterr().err
    assert "Traceback" not in err
    if code == 0:
        return
    assert code == 2, err
    assert any(word in err for word in words), err     # one of the expected explanations


@pytest.mark.parametrize("argv, words", [
    (["linearize", "robot-arm-3d"], ("dimensions",)),
    (["linearize", "spacecraft-slew", "--about", "rest"], ("dimensions",)),
    (["campbell", "robot-arm-3d", "--spin", "0:1:3", "--hub", "waist"], ("dimensions",)),
    (["campbell", "spacecraft-slew", "--spin", "0:1:3"], ("dimensions", "--hub")),
    (["converge", "robot-arm-3d", "--n-modes", "1..3"], ("beam",)),
])
def test_commands_on_spatial_models_work_or_refuse_clearly(ran, capsys, tmp_path, argv, words):
    _refused(capsys, [*argv, "--out", str(tmp_path / "out")], *words)


def test_linearize_refusal_names_the_dimensions(ran, capsys, tmp_path):
    code = main(["linearize", "robot-arm-3d", "--out", str(tmp_path / "lin")])
    err = capsys.readouterr().err
    assert code in (0, 2) and "Traceback" not in err
    if code == 2:
        assert "dimensions" in err and "spatial" in err


def test_sweep_over_an_inertia_and_a_point_derives_once(ran, capsys, tmp_path):
    pytest.importorskip("dask")
    pytest.importorskip("pyarrow")
    out = tmp_path / "sweep"
    assert main(["sweep", "robot-arm-3d", "--vary", "bodies.payload.inertia[2]=0.0006:0.0012:2",
                 "--vary", "bodies.fore.points.end[0]=0.15,0.25", "--t-end", "0.1", "--dt-out", "0.05",
                 "--workers", "1", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "4 variants" in text and "1 structure(s)" in text and "0 failed" in text
    rows = list(csv.DictReader(open(out / "sweep.csv")))
    assert [r["status"] for r in rows] == ["ok"] * 4
    finals = {r["final_q_shoulder"] for r in rows}
    assert len(finals) == 4          # each variant's numbers reach the equations


def test_sweep_table_in_a_spatial_model_file(ran, capsys, tmp_path):
    pytest.importorskip("dask")
    pytest.importorskip("pyarrow")
    text = flexkane.builtin.builtin_text("spacecraft-slew") + (
        '\n[sweep]\nt_end = 0.1\ndt_out = 0.05\n\n[sweep.vary]\n"bodies.bus.inertia[2]" = [36.0, 40.0]\n'
        '"bodies.bus.points.left[1]" = [-0.5, -0.6]\n')
    path = tmp_path / "slew-sweep.toml"
    path.write_text(text)
    assert main(["check", str(path)]) == 0
    out = tmp_path / "sweep"
    assert main(["sweep", str(path), "--workers", "1", "--out", str(out)]) == 0
    assert "1 structure(s)" in capsys.readouterr().out
    assert [r["status"] for r in csv.DictReader(open(out / "sweep.csv"))] == ["ok"] * 4


def test_export_c_counts_euler_parameters(ran, tmp_path):
    assert main(["export", "spacecraft-slew", "--c", str(tmp_path / "c"), "--quiet"]) == 0
    header = (tmp_path / "c" / "spacecraft_slew.h").read_text()
    assert "#define SPACECRAFT_SLEW_NQ 7" in header and "#define SPACECRAFT_SLEW_NU 6" in header
    assert "#define SPACECRAFT_SLEW_NY 13" in header


def test_python_api_on_a_spatial_model(ran):
    eom = flexkane.derive(flexkane.builtin_model("spacecraft-slew"))
    results = flexkane.simulate(flexkane.compile_model(eom), t_end=0.1, dt_out=0.05)
    assert results.state_names[3:7] == ["q_float_e0", "q_float_e1", "q_float_e2", "q_float_e3"]
    assert results.state.shape == (3, 13)
    assert results["q_float_e0"][0] == 1.0 and "H_x" in results.outputs
    with pytest.raises(KeyError, match="neither a state variable"):
        results["u_float_e0"]
