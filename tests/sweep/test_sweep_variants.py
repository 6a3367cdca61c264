"""Variants: grid order, reproducible random draws, ids that identify a variant's settings."""

import pytest

import flexkane
from flexkane.errors import ModelError
from flexkane.sweep import RunSettings, SweepSpec, make_variants


@pytest.fixture(scope="module")
def model():
    return flexkane.builtin_model("falling-beam-exact").validate()


def variants(model, *vary, **options):
    spec = SweepSpec(vary=vary, **{"t_end": 0.2, **options})
    return make_variants(model, spec, RunSettings.resolve(spec, model))


def test_grid_is_the_cartesian_product_with_the_last_key_fastest(model):
    found = variants(model, "beams.B.EI=20,40", "initial.q3=0.5,1.0,1.5")
    assert [dict(v.assignments)["beams.B.EI"] for v in found] == [20, 20, 20, 40, 40, 40]
    assert [dict(v.assignments)["initial.q3"] for v in found] == [0.5, 1.0, 1.5] * 2
    assert [v.index for v in found] == list(range(6))


def test_assignments_reach_the_model_by_key_path(model):
    variant = variants(model, "beams.B.EI=20", "q3=0.25", "parameters.L=2.0")[0]
    assert variant.model.beams["B"].EI == 20
    assert variant.model.initial["q3"] == 0.25
    assert variant.model.parameters["L"] == 2.0
    assert model.beams["B"].EI == "EI"  # the base model is untouched


def test_random_draws_are_reproducible_with_the_seed_and_stay_in_range(model):
    first = variants(model, "beams.B.EI=20:80", "g=0,9.81", sampling="random", samples=20, seed=4)
    again = variants(model, "beams.B.EI=20:80", "g=0,9.81", sampling="random", samples=20, seed=4)
    other = variants(model, "beams.B.EI=20:80", "g=0,9.81", sampling="random", samples=20, seed=5)
    assert [v.id for v in first] == [v.id for v in again] != [v.id for v in other]
    assert all(20 <= dict(v.assignments)["beams.B.EI"] <= 80 for v in first)
    assert {dict(v.assignments)["g"] for v in first} == {0, 9.81}


def test_random_integer_keys_draw_whole_numbers(model):
    found = variants(model, "beams.B.n_modes=1:3", sampling="random", samples=10, seed=0)
    assert {dict(v.assignments)["beams.B.n_modes"] for v in found} <= {1, 2, 3}
    assert all(isinstance(v.model.beams["B"].n_modes, int) for v in found)


def test_variant_id_changes_with_the_values_and_the_run_settings_only(model):
    a = variants(model, "beams.B.EI=20,40")
    b = variants(model, "beams.B.EI=40,20")
    c = variants(model, "beams.B.EI=20,40", rtol=1e-6)
    assert [v.id for v in a] == [v.id for v in reversed(b)]  # position in the sweep does not matter
    assert not {v.id for v in a} & {v.id for v in c}
    assert len({v.id for v in a}) == 2 and all(len(v.id) == 16 for v in a)


def test_grid_listing_a_value_twice_is_rejected(model):
    with pytest.raises(ModelError, match="distinct variants"):
        variants(model, "beams.B.EI=20,20.0")


@pytest.mark.parametrize("key, path", [("beams.X.EI", "beams.X.EI"), ("parameters.nope", "vary parameters.nope"),
                                       ("status", "vary status")])
def test_unknown_or_reserved_keys_are_rejected_before_running(model, key, path):
    with pytest.raises(ModelError) as exc:
        variants(model, f"{key}=1,2")
    assert exc.value.path == path


def test_missing_end_time_names_the_option():
    bare = flexkane.builtin_model("falling-beam-exact")
    bare.simulation.t_end = None
    with pytest.raises(ModelError, match="end time") as exc:
        RunSettings.resolve(SweepSpec(vary=("EI=1,2",)), bare)
    assert exc.value.path == "t_end"     # the library names the parameter; the CLI maps it to --t-end


def test_adaptive_batches_aim_at_a_quarter_second_and_leave_work_for_every_worker():
    from flexkane.sweep.execute import MAX_BATCH, BatchSizer

    sizer = BatchSizer(threads=2)
    assert sizer.size(1000) == 1  # nothing measured yet
    sizer.observe([{"metrics": {"run_time": 0.01}}] * 3)
    assert sizer.size(1000) == 25  # 0.25 s / 0.01 s
    assert sizer.size(20) == 5  # 20 left for 2 workers: batches of 5 at most
    assert sizer.size(2) == 1
    fast = BatchSizer(threads=2)
    fast.observe([{"metrics": {"run_time": 1e-6}}])
    assert fast.size(10 ** 6) == MAX_BATCH
    assert BatchSizer(threads=2, fixed=3).size(1000) == 3
