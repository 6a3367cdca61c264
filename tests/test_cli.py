"""The command line: outputs of ``run``, printed equations, help of every subcommand, exit codes."""

import csv
import subprocess
import sys

import numpy as np
import pytest

import flexkane
from flexkane.cli import COMMAND_MODULES, main


def test_every_subcommand_has_help(capsys):
    for name in COMMAND_MODULES:
        with pytest.raises(SystemExit) as exc:
            main([name, "--help"])
        assert exc.value.code == 0
        assert "usage: flexkane " + name in capsys.readouterr().out


def test_run_falling_beam_writes_results_plots_and_equations(tmp_path, capsys):
    out = tmp_path / "fb"
    assert main(["run", "--out", str(out), "--quiet", "--dt-out", "0.01"]) == 0
    rows = list(csv.reader(open(out / "results.csv")))
    assert rows[0][:9] == ["t", "q1", "q2", "q3", "q4", "u1", "u2", "u3", "u4"]
    t = np.array([float(r[0]) for r in rows[1:]])
    np.testing.assert_allclose(t, np.arange(101) * 0.01, atol=1e-12)
    assert float(rows[1][3]) == 1.0 and float(rows[1][4]) == 0.0001
    for name in ("u1", "u2", "u3", "u4", "q3", "q4", "energy"):
        assert (out / f"{name}.png").stat().st_size > 5000
    text = (out / "equations.md").read_text()
    assert "F^*_{u_{3}}" in text and "G_{11}" in text
    res = flexkane.load_results(out)
    assert res.state_names[:4] == ["q1", "q2", "q3", "q4"] and not res.partial


def test_results_csv_is_byte_identical_when_run_twice(tmp_path):
    for k in (1, 2):
        assert main(["run", "falling-beam", "--out", str(tmp_path / str(k)), "--quiet", "--t-end", "0.2"]) == 0
    assert (tmp_path / "1" / "results.csv").read_bytes() == (tmp_path / "2" / "results.csv").read_bytes()


def test_existing_output_directory_is_kept_without_force(tmp_path, capsys):
    (tmp_path / "keep.txt").write_text("precious")
    assert main(["run", "--out", str(tmp_path), "--quiet", "--t-end", "0.1"]) == 2
    assert "--force" in capsys.readouterr().err
    assert (tmp_path / "keep.txt").read_text() == "precious"


def test_derive_prints_the_chapter_terms(capsys):
    assert main(["derive", "falling-beam-exact", "--n-modes", "2"]) == 0
    out = capsys.readouterr().out
    assert "F*[u3]" in out and "G_12" in out and "H_22" in out
    assert main(["derive", "falling-beam", "--latex"]) == 0
    assert r"\dot{u}_{1}" in capsys.readouterr().out


def test_set_overrides_parameters_and_initial_conditions(tmp_path):
    out = tmp_path / "o"
    assert main(["run", "falling-beam-exact", "--set", "g=0", "--set", "u3=2", "--out", str(out),
                 "--quiet", "--t-end", "0.1"]) == 0
    res = flexkane.load_results(out)
    assert res["u3"][0] == 2.0
    assert np.ptp(res["p_y"]) < 1e-9 and np.ptp(res["p_x"]) < 1e-9     # no external force without gravity


def test_bad_arguments_exit_2_without_traceback(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "flexkane", "run", "no-such-model", "--out", str(tmp_path / "x")],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and "no-such-model" in proc.stderr
    proc = subprocess.run([sys.executable, "-m", "flexkane", "run", "--set", "beams.B.EI=-1",
                           "--out", str(tmp_path / "y")], capture_output=True, text=True)
    assert proc.returncode == 2 and "beams.B.EI" in proc.stderr and "positive" in proc.stderr
