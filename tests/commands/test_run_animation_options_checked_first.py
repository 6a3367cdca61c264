"""``flexkane run --animate`` refuses a --magnify or --trace the animation could not use before it
derives or integrates anything (found by the fuzzing of the command line: the refusal used to come
after the whole run)."""

import pytest

from flexkane.cli import main


@pytest.mark.parametrize("options, message", [
    (["--trace", "nowhere"], "--trace: expected one of rod, cm, none, got 'nowhere'"),
    (["--magnify", "nan"], "--magnify: expected a positive number or 'auto', got nan"),
    (["--magnify", "-1"], "--magnify: expected a positive number or 'auto', got -1.0"),
])
def test_bad_animation_options_are_refused_before_the_run(tmp_path, capsys, monkeypatch, options, message):
    import flexkane.derivation_cache

    def no_derivation(*args, **kwargs):
        raise AssertionError("derived before the options were checked")
    monkeypatch.setattr(flexkane.derivation_cache, "cached_derive", no_derivation)
    out = tmp_path / "run"
    code = main(["run", "pendulum-beam", "--t-end", "0.01", "--animate", "--out", str(out), *options])
    err = capsys.readouterr().err
    assert code == 2 and message in err and "Traceback" not in err, err
    assert not out.exists()


def test_good_animation_options_pass_the_check():
    from flexkane import builtin_model
    from flexkane.animation import check_animation_options

    model = builtin_model("pendulum-beam")
    for magnify, trace in (("auto", None), ("1000", "rod"), (2.0, "tip_rod"), ("1", "cm"), ("1", "none")):
        check_animation_options(model, magnify, trace)
