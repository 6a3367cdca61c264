"""``flexkane modes`` and ``flexkane vibrate`` from the command line."""

import csv

import numpy as np
import pytest

from flexkane.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_modes_prints_roots_and_frequencies_and_writes_the_plot(tmp_path, capsys):
    code, out, _ = run(capsys, "modes", "--n", "4", "--L", "1", "--EI", "35.3", "--rho", "0.21991",
                       "--out", str(tmp_path))
    assert code == 0
    rows = np.array([line.split() for line in out.splitlines() if line.strip()[:1].isdigit()],
                    dtype=float)
    lam = np.array([1.8751040687, 4.6940911330, 7.8547574382, 10.995540735])
    np.testing.assert_allclose(rows[:, 1], lam, rtol=1e-10)
    p = lam ** 2 * np.sqrt(35.3 / 0.21991)
    np.testing.assert_allclose(rows[:, 2], p, rtol=1e-10)
    np.testing.assert_allclose(rows[:, 3], p / (2 * np.pi), rtol=1e-10)
    assert "p_i [rad/s]" in out and "f_i [Hz]" in out
    png = tmp_path / "modes-clamped-free.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_modes_defaults_to_four_cantilever_modes_in_out_and_never_overwrites_silently(tmp_path, capsys,
                                                                                    monkeypatch):
    # changed by the --out rules: the default folder is out/modes-<family>, not the current directory
    monkeypatch.chdir(tmp_path)
    code, out, _ = run(capsys, "modes")
    assert code == 0
    rows = [line.split() for line in out.splitlines() if line.strip()[:1].isdigit()]
    assert [row[0] for row in rows] == ["1", "2", "3", "4"]
    assert "p_i" not in out
    png = tmp_path / "out" / "modes-clamped-free" / "modes-clamped-free.png"
    assert png.exists() and [p.name for p in tmp_path.iterdir()] == ["out"]
    before = png.read_bytes()
    code, _, err = run(capsys, "modes", "--n", "2")
    assert code == 2 and "--force" in err and "modes-clamped-free" in err
    assert png.read_bytes() == before
    assert run(capsys, "modes", "--n", "2", "--force")[0] == 0
    assert png.read_bytes() != before


def test_vibrate_refuses_a_non_empty_directory_before_computing(tmp_path, capsys):
    (tmp_path / "keep.txt").write_text("precious")
    code, out, err = run(capsys, *VIBRATE, "--tip-load", "2", "--out", str(tmp_path))
    assert code == 2 and "--out" in err and "--force" in err and "keep.txt" in err
    assert out == "" and sorted(p.name for p in tmp_path.iterdir()) == ["keep.txt"]
    assert run(capsys, *VIBRATE, "--tip-load", "2", "--out", str(tmp_path), "--force")[0] == 0
    assert (tmp_path / "keep.txt").read_text() == "precious" and (tmp_path / "results.csv").exists()


@pytest.mark.parametrize("argv, expected", [
    (["pinned-free", "--n", "2"], ["3.92660231204792", "7.06858274562873"]),
    (["clamped-free-tip-mass", "--mass-ratio", "1", "--inertia-ratio", "0", "--n", "2"],
     ["1.2479174096"]),
    (["polynomial", "--n", "3"], ["Rayleigh-Ritz", "1.875386"]),
    (["axial-fixed-free", "--n", "2", "--L", "2", "--EA", "1e6", "--rho", "4"], ["392.699081"]),
])
def test_modes_for_other_families(tmp_path, capsys, argv, expected):
    code, out, _ = run(capsys, "modes", *argv, "--out", str(tmp_path))
    assert code == 0
    for text in expected:
        assert text in out


@pytest.mark.parametrize("argv, flag", [
    (["nope"], "family"),
    (["--n", "0"], "--n"),
    (["--L", "1", "--rho", "2"], "--EI"),
    (["--L", "-1", "--EI", "1", "--rho", "2"], "--L"),
    (["clamped-free-tip-mass", "--mass-ratio", "1"], "--inertia-ratio"),
    (["clamped-free-tip-mass", "--mass-ratio", "-1", "--inertia-ratio", "0"], "--mass-ratio"),
    (["clamped-clamped", "--mass-ratio", "1"], "--mass-ratio"),
])
def test_modes_reports_bad_input_with_exit_code_2(tmp_path, capsys, argv, flag):
    code, _, err = run(capsys, "modes", *argv, "--out", str(tmp_path))
    assert code == 2
    assert flag in err
    assert "Traceback" not in err


def test_modes_of_user_expressions_shows_ritz_roots(tmp_path, capsys):
    pytest.importorskip("flexkane.expressions")
    code, out, _ = run(capsys, "modes", "expression", "--expression", "xi**2",
                       "--expression", "xi**3", "--out", str(tmp_path))
    assert code == 0
    assert "2 modes (Rayleigh-Ritz)" in out
    assert (tmp_path / "modes-expression.png").exists()


def test_modes_reports_an_unparsable_expression(tmp_path, capsys):
    pytest.importorskip("flexkane.expressions")
    code, _, err = run(capsys, "modes", "expression", "--expression", "xi**2",
                       "--expression", "import os", "--out", str(tmp_path))
    assert code == 2 and "--expression[1]" in err


def test_modes_checks_expressions_against_a_boundary(tmp_path, capsys):
    pytest.importorskip("flexkane.expressions")
    code, _, err = run(capsys, "modes", "expression", "--expression", "xi**2",
                       "--expression", "sin(xi)", "--boundary", "clamped-free",
                       "--out", str(tmp_path))
    assert code == 2
    assert "--expression[1]" in err and "Phi'(0) = 0" in err


VIBRATE = ["vibrate", "--L", "1", "--EI", "35.3", "--rho", "0.21991", "--n", "8",
           "--t-end", "0.2", "--dt-out", "0.01"]


def read_results(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array(rows[1:], dtype=float)


def test_vibrate_after_a_tip_load_writes_tip_and_mid_histories(tmp_path, capsys):
    code, out, _ = run(capsys, *VIBRATE, "--tip-load", "2", "--out", str(tmp_path))
    assert code == 0
    header, data = read_results(tmp_path / "results.csv")
    assert header == ["t", "tip", "mid"]
    np.testing.assert_allclose(data[:, 0], 0.01 * np.arange(21), atol=1e-12)
    assert data[0, 1] == pytest.approx(2 / (3 * 35.3), rel=1e-4)
    assert data[0, 2] == pytest.approx(2 * 0.5 ** 2 * 2.5 / (6 * 35.3), rel=1e-3)
    assert np.abs(data[:, 1]).max() <= data[0, 1] * 1.01   # released from rest: no growth
    assert (tmp_path / "vibration.png").read_bytes()[:4] == b"\x89PNG"


def test_vibrate_needs_an_initial_condition(tmp_path, capsys):
    with pytest.raises(SystemExit) as info:
        main([*VIBRATE, "--out", str(tmp_path)])
    assert info.value.code == 2


def test_vibrate_with_a_tip_load_needs_a_cantilever(tmp_path, capsys):
    code, _, err = run(capsys, "vibrate", "pinned-pinned", *VIBRATE[1:], "--tip-load", "1",
                       "--out", str(tmp_path))
    assert code == 2 and "--tip-load" in err


def test_vibrate_rejects_a_non_positive_output_interval(tmp_path, capsys):
    argv = [a if a != "0.01" else "0" for a in VIBRATE]
    code, _, err = run(capsys, *argv, "--tip-load", "1", "--out", str(tmp_path))
    assert code == 2 and "--dt-out" in err


def test_vibrate_from_an_initial_expression(tmp_path, capsys):
    pytest.importorskip("flexkane.expressions")
    code, _, _ = run(capsys, "vibrate", "pinned-pinned", *VIBRATE[1:],
                     "--initial", "0.01*sin(pi*xi)", "--out", str(tmp_path))
    assert code == 0
    _, data = read_results(tmp_path / "results.csv")
    p1 = np.pi ** 2 * np.sqrt(35.3 / 0.21991)
    np.testing.assert_allclose(data[:, 2], 0.01 * np.cos(p1 * data[:, 0]), atol=1e-12)
    np.testing.assert_allclose(data[:, 1], 0.0, atol=1e-15)


def test_vibrate_reports_a_bad_initial_expression(tmp_path, capsys):
    pytest.importorskip("flexkane.expressions")
    code, _, err = run(capsys, *VIBRATE, "--initial", "xi +* 2", "--out", str(tmp_path))
    assert code == 2 and "--initial" in err
