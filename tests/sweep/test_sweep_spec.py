"""Sweep specifications: --vary syntax, the [sweep] table of a model file, and their errors."""

import pytest

from flexkane.errors import ModelError
from flexkane.sweep import SweepSpec, Vary, sweep_spec_from_toml


def test_range_gives_count_values_including_both_ends():
    vary = Vary.parse("beams.B.EI=20:80:4")
    assert vary.key == "beams.B.EI" and vary.is_range
    assert vary.grid_values() == [20.0, 40.0, 60.0, 80.0]


def test_log_range_is_geometric():
    assert Vary.parse("EI=1:100:3:log").grid_values() == pytest.approx([1.0, 10.0, 100.0], rel=1e-15)


def test_list_keeps_numbers_booleans_and_expressions_with_commas():
    vary = Vary.parse("g=0, 9.81, 2*g0, min(a, b), true")
    assert vary.values == (0, 9.81, "2*g0", "min(a, b)", True)


def test_integer_range_of_a_count_gives_integers_and_rejects_fractions():
    assert Vary.parse("beams.B.n_modes=1:3:3").grid_values(integer=True) == [1, 2, 3]
    with pytest.raises(ModelError, match="whole numbers"):
        Vary.parse("beams.B.n_modes=1:2:3").grid_values(integer=True)


@pytest.mark.parametrize("text, message", [
    ("EI", "KEY=START:STOP:COUNT"),
    ("EI=1:2:0", "COUNT >= 1"),
    ("EI=a:2:3", "START:STOP:COUNT"),
    ("EI=-1:10:3:log", "positive START and STOP"),
])
def test_malformed_vary_names_the_option_and_key(text, message):
    with pytest.raises(ModelError, match=message) as exc:
        Vary.parse(text)
    assert exc.value.path.startswith("vary")    # the library names the parameter; the CLI says --vary


def test_grid_of_a_range_without_count_asks_for_count():
    with pytest.raises(ModelError, match="needs COUNT"):
        Vary.parse("EI=1:2").grid_values()


def test_random_sampling_requires_a_seed_so_that_a_rerun_regenerates_the_variants():
    with pytest.raises(ModelError, match="seed") as exc:
        SweepSpec(vary=("EI=1:2",), sampling="random", samples=5)
    assert exc.value.path == "seed"


def test_a_key_varied_twice_is_rejected():
    with pytest.raises(ModelError, match="each key varied once"):
        SweepSpec(vary=("EI=1,2", "EI=3,4"))


def test_sweep_table_of_a_model_file_is_parsed_in_order():
    spec = sweep_spec_from_toml("""
name = "m"
[sweep]
sampling = "random"
samples = 7
seed = 3
t_end = 0.5
metric = "energy_error"
[sweep.vary]
"beams.B.EI" = "20:80:4"
g = [0.0, 9.81]
"initial.q3" = { start = 0.5, stop = 1.5, count = 3, scale = "log" }
""")
    assert [v.key for v in spec.vary] == ["beams.B.EI", "g", "initial.q3"]
    assert spec.vary[1].values == (0.0, 9.81)
    assert spec.vary[2].scale == "log" and spec.vary[2].count == 3
    assert (spec.sampling, spec.samples, spec.seed, spec.t_end, spec.metric) == ("random", 7, 3, 0.5, "energy_error")


def test_model_file_without_sweep_table_gives_none():
    assert sweep_spec_from_toml('name = "m"\n') is None


@pytest.mark.parametrize("table, path", [
    ('[sweep]\nsampels = 3\n', "sweep.sampels"),
    ('[sweep]\nsampling = "random"\nseed = 1\n', "sweep.samples"),
    ('[sweep.vary]\nEI = { start = 1, stop = 2, cuont = 3 }\n', "sweep.vary.EI.cuont"),
    ('[sweep.vary]\nEI = "1:x:3"\n', "sweep.vary.EI"),
    ('[sweep]\nt_end = -1.0\n', "sweep.t_end"),
])
def test_errors_in_the_sweep_table_name_the_field(table, path):
    with pytest.raises(ModelError) as exc:
        sweep_spec_from_toml(table)
    assert exc.value.path == path


def test_command_line_replaces_and_extends_the_file_spec():
    file_spec = SweepSpec(vary=("EI=1,2", "g=0,9.81"), t_end=1.0, dt_out=0.1)
    cli = SweepSpec(vary=("g=1.62", "u3=0,1"), t_end=0.5)
    merged = file_spec.merged(cli)
    assert [v.describe() for v in merged.vary] == ["EI=1,2", "g=1.62", "u3=0,1"]
    assert (merged.t_end, merged.dt_out) == (0.5, 0.1)
