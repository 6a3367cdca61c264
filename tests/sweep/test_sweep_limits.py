"""Sweeps are bounded: at most MAX_VARIANTS variants, refused up front (exit 2) before anything is
allocated; variants are generated one at a time; output grids are bounded in check, run and sweep."""

import itertools
import tracemalloc

import pytest

import flexkane
from flexkane.cli import main
from flexkane.errors import ModelError
from flexkane.simulation import output_grid
from flexkane.sweep.spec import MAX_VARIANTS, SweepSpec, Vary
from flexkane.sweep.variants import make_assignments


@pytest.mark.parametrize("arguments, message", [
    (["--vary", "beams.B.EI=20:80:100000000"], "a COUNT of at most 100,000 values"),
    (["--vary", "beams.B.EI=20:80:1000", "--vary", "g=0:9.81:1000"], "at most 100,000 variants"),
    (["--random", "1000000000000", "--seed", "1", "--vary", "beams.B.EI=20:80"], "at most 100,000 variants"),
    (["--dt-out", "1e-320", "--vary", "beams.B.EI=20:80:2"], "at most 10,000,000 output rows"),
])
def test_an_unbounded_sweep_exits_2_before_any_work(tmp_path, capsys, arguments, message):
    tracemalloc.start()
    code = main(["sweep", "falling-beam", "--out", str(tmp_path / "s"), "--quiet", *arguments])
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    err = capsys.readouterr().err
    assert code == 2 and message in err and "Traceback" not in err
    assert peak < 50_000_000     # nothing of the size of the asked grid was built
    assert not (tmp_path / "s" / "table.csv").exists()


def test_the_largest_grid_is_accepted_and_its_variants_are_generated_lazily():
    spec = SweepSpec(vary=(Vary("a", start=0, stop=1, count=1000), Vary("b", start=0, stop=1, count=100)))
    assert spec.variant_count == MAX_VARIANTS
    assignments = make_assignments(spec)
    assert not isinstance(assignments, list)
    first = list(itertools.islice(assignments, 3))
    assert first[0] == (("a", 0.0), ("b", 0.0)) and first[1][1] == ("b", 1 / 99)


def test_one_more_variant_than_the_maximum_is_refused():
    with pytest.raises(ModelError) as info:
        SweepSpec(vary=(Vary("a", values=(1, 2)), Vary("b", start=0, stop=1, count=MAX_VARIANTS // 2 + 1)))
    assert "at most 100,000 variants" in str(info.value)


def test_an_output_grid_finer_than_the_float_range_allows_is_a_model_error():
    with pytest.raises(ModelError) as info:
        output_grid(1.0, 1e-320)
    assert "output rows" in str(info.value)


def test_run_refuses_a_tiny_output_interval_before_deriving(capsys, tmp_path):
    assert main(["run", "falling-beam", "--dt-out", "1e-320", "--out", str(tmp_path / "r")]) == 2
    assert "at most 10,000,000 output rows" in capsys.readouterr().err


def test_a_model_with_a_tiny_output_interval_is_refused_by_validation():
    model = flexkane.builtin_model("falling-beam")
    model.simulation.dt_out = 1e-320
    with pytest.raises(ModelError) as info:
        model.validate()
    assert info.value.path == "simulation.dt_out"
