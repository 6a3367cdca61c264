"""The ranges of the analysis commands are bounded as sweeps are (flexkane.limits): a count beyond the
bound exits 2 naming the option, what it allows and what was given, before the model is even read."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import flexkane
from flexkane.analysis import campbell_diagram, convergence_study
from flexkane.analysis.campbell import parse_spin_range
from flexkane.analysis.convergence import parse_mode_counts
from flexkane.cli import main
from flexkane.errors import ModelError
from flexkane.limits import MAX_VARIANTS

MANY = ",".join(["1"] * (MAX_VARIANTS + 1))


@pytest.mark.parametrize("command, option, given, allowed", [
    ("campbell", "--spin", "0:10:1000000000", "at most 100,000 spin rates"),
    ("campbell", "--spin", MANY, "at most 100,000 spin rates"),
    ("converge", "--n-modes", "1..100000000", "each 1 to 40"),
    ("converge", "--n-modes", MANY, "each 1 to 40"),
])
def test_an_unbounded_range_exits_2_naming_the_option_before_the_model_is_read(tmp_path, capsys, command,
                                                                                option, given, allowed):
    missing = tmp_path / "no-such-model.toml"      # read only after the range is checked
    tracemalloc.start()
    code = main([command, str(missing), option, given, "--out", str(tmp_path / "o")])
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    err = capsys.readouterr().err
    assert code == 2 and err.startswith(f"flexkane: error: {option}: expected") and "Traceback" not in err
    assert allowed in err and (given if len(given) < 100 else given[:50]) in err
    assert peak < 20_000_000           # nothing of the size of the asked range was built
    assert not (tmp_path / "o").exists()


def test_the_largest_campbell_range_is_the_largest_sweep():
    assert parse_spin_range(f"0:1:{MAX_VARIANTS}").shape == (MAX_VARIANTS,)
    with pytest.raises(ModelError, match="at most 100,000 spin rates"):
        parse_spin_range(f"0:1:{MAX_VARIANTS + 1}")


def test_the_library_refuses_the_same_ranges_before_deriving():
    model = flexkane.builtin_model("spin-up")
    with pytest.raises(ModelError, match="--spin: expected at most 100,000 spin rates"):
        campbell_diagram(model, np.zeros(MAX_VARIANTS + 1))
    with pytest.raises(ModelError, match="--n-modes"):
        convergence_study(model, range(1, 10**8))
    with pytest.raises(ModelError, match="--n-modes"):
        convergence_study(model, (n for n in range(1, 10**12)))
    assert parse_mode_counts("1..40") == list(range(1, 41))
