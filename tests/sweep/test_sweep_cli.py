"""``flexkane sweep``: the command line, the [sweep] table of a model file, the CSV table and the plot."""

import csv
import math

import pytest

import flexkane
from flexkane.builtin import builtin_text
from flexkane.cli import main
from flexkane.sweep import plot_metric, read_table

SWEEP_TABLE = """
[sweep]
t_end = 0.1
dt_out = 0.01
metric = "max_abs_tip_B"

[sweep.vary]
"beams.B.EI" = "20:80:3"
"initial.q3" = [0.5, 1.0]
"""


@pytest.fixture
def model_file(tmp_path):
    path = tmp_path / "falling.toml"
    path.write_text(builtin_text("falling-beam-exact") + SWEEP_TABLE)
    return path


def test_sweep_table_of_the_model_file_drives_the_sweep_and_the_plot(model_file, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["sweep", str(model_file), "--workers", "1", "--out", str(out), "--plot"]) == 0
    printed = capsys.readouterr().out
    assert "6 variants: 6 computed" in printed and "max_abs_tip_B_vs_beams.B.EI_initial.q3.png" in printed
    rows = read_table(out, as_rows=True)
    assert [(r["beams.B.EI"], r["initial.q3"]) for r in rows] == [(e, q) for e in (20.0, 50.0, 80.0)
                                                                  for q in (0.5, 1.0)]
    assert all(r["status"] == "ok" and r["t_reached"] == pytest.approx(0.1) for r in rows)
    assert (out / "max_abs_tip_B_vs_beams.B.EI_initial.q3.png").stat().st_size > 5000


def test_a_short_sweep_without_workers_runs_in_this_process(tmp_path, capsys):
    assert main(["sweep", "falling-beam-exact", "--vary", "beams.B.EI=20:40:4", "--t-end", "0.05",
                 "--out", str(tmp_path / "out")]) == 0
    assert "4 variants: 4 computed in this process" in capsys.readouterr().out


def test_command_line_values_override_the_file_and_add_keys(model_file, tmp_path):
    out = tmp_path / "out"
    assert main(["sweep", str(model_file), "--vary", "beams.B.EI=30", "--vary", "g=0,9.81",
                 "--workers", "1", "--out", str(out), "--quiet"]) == 0
    rows = read_table(out, as_rows=True)
    assert {(r["beams.B.EI"], r["initial.q3"], r["g"]) for r in rows} == \
        {(30.0, q, g) for q in (0.5, 1.0) for g in (0.0, 9.81)}


def test_csv_table_holds_the_same_rows_as_the_parquet_table(model_file, tmp_path):
    out = tmp_path / "out"
    assert main(["sweep", str(model_file), "--workers", "1", "--out", str(out), "--quiet"]) == 0
    rows = read_table(out, as_rows=True)
    with open(out / "sweep.csv", newline="") as handle:
        lines = list(csv.DictReader(handle))
    assert len(lines) == len(rows)
    for line, row in zip(lines, rows):
        assert line["variant"] == row["variant"] and line["status"] == row["status"]
        for name in ("beams.B.EI", "max_abs_tip_B", "final_q4", "energy_error", "nsteps"):
            assert float(line[name]) == row[name]  # shortest round-trip text: exact


def test_random_sampling_from_the_command_line_is_reproducible(tmp_path):
    tables = []
    for name in ("a", "b"):
        assert main(["sweep", "falling-beam-exact", "--vary", "beams.B.EI=20:80", "--vary", "initial.q3=0.2:1.2",
                     "--random", "4", "--seed", "7", "--t-end", "0.05", "--workers", "1", "--quiet",
                     "--out", str(tmp_path / name)]) == 0
        tables.append([(r["beams.B.EI"], r["initial.q3"]) for r in read_table(tmp_path / name, as_rows=True)])
    assert tables[0] == tables[1] and len(set(tables[0])) == 4
    assert all(20 <= ei <= 80 and 0.2 <= q3 <= 1.2 for ei, q3 in tables[0])


@pytest.mark.parametrize("arguments, message", [
    (["--vary", "beams.B.EJ=1,2"], "beams.B.EJ"),
    (["--vary", "q9=1,2"], "--vary q9"),
    (["--vary", "EI=1:2:x"], "--vary EI"),
    (["--random", "3", "--vary", "EI=1:2"], "--seed"),
    ([], "--vary: expected at least one"),
])
def test_invalid_arguments_exit_2_naming_the_option_and_key(tmp_path, capsys, arguments, message):
    code = main(["sweep", "falling-beam-exact", *arguments, "--t-end", "0.05", "--workers", "1",
                 "--out", str(tmp_path / "out")])
    assert code == 2
    assert message in capsys.readouterr().err


def test_plot_of_a_metric_against_two_keys_is_written(model_file, tmp_path):
    out = tmp_path / "out"
    assert main(["sweep", str(model_file), "--workers", "1", "--out", str(out), "--quiet", "--plot",
                 "--metric", "energy_error"]) == 0
    assert (out / "energy_error_vs_beams.B.EI_initial.q3.png").stat().st_size > 5000


def test_saved_trajectories_reload_as_results(tmp_path):
    out = tmp_path / "out"
    assert main(["sweep", "falling-beam-exact", "--vary", "beams.B.EI=20,40", "--t-end", "0.05",
                 "--dt-out", "0.01", "--workers", "1", "--quiet", "--save-trajectories", "--out", str(out)]) == 0
    for row in read_table(out, as_rows=True):
        results = flexkane.load_results(out / "variants" / row["variant"])
        assert results["q4"][-1] == row["final_q4"]
        assert max(abs(results["tip_B"])) == row["max_abs_tip_B"]
        assert not math.isnan(row["energy_error"])


def test_plot_against_one_key_draws_one_line_per_value_of_the_other(model_file, tmp_path):
    out = tmp_path / "out"
    assert main(["sweep", str(model_file), "--workers", "1", "--out", str(out), "--quiet"]) == 0
    rows = read_table(out, as_rows=True)
    path = plot_metric(rows, "final_q3", ["beams.B.EI"], tmp_path / "q3.png")
    assert path.stat().st_size > 5000
    with pytest.raises(flexkane.errors.ModelError, match="metric"):
        plot_metric(rows, "no_such_column", ["beams.B.EI"], tmp_path / "x.png")
