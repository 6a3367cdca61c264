"""A failing variant is recorded with its message and does not stop the sweep."""

import pytest

from flexkane.sweep import SweepSpec, read_table, run_sweep


# EI = -10 is rejected by validation; u3 = 1e200 rad/s overflows the state at once
SPEC = SweepSpec(vary=("beams.B.EI=-10,35.3", "u3=0,1e200"), t_end=0.2, dt_out=0.01)


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    out = tmp_path_factory.mktemp("failures")
    outcome = run_sweep("falling-beam-exact", SPEC, out=out, workers=1)
    assert outcome.computed == 4 and outcome.failed == 3
    return out


@pytest.fixture(scope="module")
def rows(out):
    return {(r["beams.B.EI"], r["u3"]): r for r in read_table(out, as_rows=True)}


def test_the_valid_variant_completes(rows):
    ok = rows[(35.3, 0.0)]
    assert ok["status"] == "ok" and ok["error"] == "" and ok["t_reached"] == pytest.approx(0.2)


def test_an_invalid_value_is_recorded_with_the_message_naming_the_field(rows):
    for u3 in (0.0, 1e200):
        row = rows[(-10.0, u3)]
        assert row["status"] == "failed"
        assert row["error"].startswith("beams.B.EI: expected a positive") and "[N m^2]" in row["error"]
        assert row["t_reached"] is None  # never ran: no metrics


def test_a_diverging_variant_is_recorded_with_the_solver_message(rows):
    row = rows[(35.3, 1e200)]
    assert row["status"] == "failed" and "non-finite" in row["error"]
    assert row["t_reached"] == 0.0 and row["final_u3"] == 1e200


def test_failed_variants_are_not_run_again_unless_asked(out, rows):
    again = run_sweep("falling-beam-exact", SPEC, out=out, workers=1)
    assert (again.computed, again.reused, again.failed) == (0, 4, 3)
    retried = run_sweep("falling-beam-exact", SPEC, out=out, workers=1, retry_failed=True)
    assert (retried.computed, retried.reused, retried.failed) == (3, 1, 3)
