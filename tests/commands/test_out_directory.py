"""Every command that writes handles --out alike: refuses a non-empty directory without --force,
checks the directory can be written before computing, and derives its default from the model's
name without ever leaving out/."""

import os
import subprocess
import sys

import pytest

from child_env import child_env

from flexkane.cli import main
from flexkane.commands._common import default_out, prepare_out, safe_folder_name
from flexkane.errors import ModelError

SMALL_RUN = ["--t-end", "0.01", "--dt-out", "0.005", "--quiet"]


def _model_named(tmp_path, name: str):
    import flexkane

    path = tmp_path / "named.toml"
    model = flexkane.builtin_model("falling-beam").with_values({"name": name})
    flexkane.save_model(model, path)
    return path


@pytest.mark.parametrize("name, folder", [
    ("../../ESCAPED", "ESCAPED"), ("/tmp/abs/ESCAPED", "tmp-abs-ESCAPED"), ("..", "model"),
    ("a/../../b", "a-..-..-b"), ("C:\\\\x\\\\y", "C-x-y"), ("~/home", "home"), ("arm v2", "arm-v2"),
    ("-rf", "rf"), ("", "model"), ("x" * 300, "x" * 100),
])
def test_a_model_name_becomes_a_single_folder_name_under_out(name, folder):
    assert safe_folder_name(name) == folder
    path = default_out(name, "-linearized")
    assert path.parent.name == "out" and len(path.parts) == 2 and not path.is_absolute()
    assert os.sep not in path.name and path.name not in (".", "..")


def test_a_malicious_model_name_cannot_make_run_write_outside_out(tmp_path, monkeypatch):
    work = tmp_path / "a" / "b"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    for name in ("../../ESCAPED", str(tmp_path / "ABSOLUTE")):
        model_file = _model_named(tmp_path, name)
        assert main(["run", str(model_file), *SMALL_RUN]) == 0
    assert not (tmp_path / "ESCAPED").exists() and not (tmp_path / "ABSOLUTE").exists()
    assert sorted(p.name for p in work.iterdir()) == ["out"]
    written = sorted(p.name for p in (work / "out").iterdir())
    assert written == sorted(["ESCAPED", safe_folder_name(str(tmp_path / "ABSOLUTE"))])
    assert (work / "out" / "ESCAPED" / "results.npz").is_file()


def test_a_non_empty_out_is_refused_without_force_and_nothing_is_lost(tmp_path, capsys):
    (tmp_path / "keep.txt").write_text("precious")
    assert main(["run", "falling-beam", "--out", str(tmp_path), *SMALL_RUN]) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "--force" in err and "keep.txt" in err and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.txt"]


def _read_only_directory(tmp_path):
    """A directory that cannot be written: chmod 555, or (as root, whom permissions do not stop) a
    path under a regular file."""
    directory = tmp_path / "read-only"
    directory.mkdir()
    directory.chmod(0o555)
    probe = directory / "probe"
    try:
        probe.write_text("x")
    except OSError:
        return directory
    probe.unlink()
    directory.chmod(0o755)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a directory")
    return blocker / "out"


def test_an_unwritable_out_is_refused_before_any_computing(tmp_path, capsys, monkeypatch):
    import flexkane.derivation_cache as derivation_cache

    def no_derivation(*args, **kwargs):
        raise AssertionError("derived although --out cannot be written")

    monkeypatch.setattr(derivation_cache, "cached_derive", no_derivation)
    directory = _read_only_directory(tmp_path)
    try:
        for argv in (["run", "falling-beam", *SMALL_RUN], ["linearize", "flexible-arm", "--quiet"],
                     ["modes", "--n", "2"],
                     ["vibrate", "--L", "1", "--EI", "35.3", "--rho", "0.22", "--n", "2", "--t-end", "0.1",
                      "--dt-out", "0.1", "--tip-load", "1"]):
            assert main([*argv, "--out", str(directory / "sub")]) == 2, argv
            captured = capsys.readouterr()
            assert "--out" in captured.err and str(directory) in captured.err, captured.err
            assert captured.out == "" and "Traceback" not in captured.err
    finally:
        if directory.name == "read-only":
            directory.chmod(0o755)


def test_prepare_out_checks_writability_of_an_existing_empty_directory(tmp_path, monkeypatch):
    import tempfile

    def full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(tempfile, "NamedTemporaryFile", full)
    with pytest.raises(ModelError) as info:
        prepare_out(tmp_path, force=False)
    assert info.value.path == "--out" and "no space left" in str(info.value)
    assert "nothing was computed" in str(info.value)


def test_prepare_out_accepts_an_empty_or_resumable_directory_and_creates_parents(tmp_path):
    assert prepare_out(tmp_path / "a" / "b", force=False) == tmp_path / "a" / "b"
    (tmp_path / "a" / "b" / "sweep.json").write_text("{}")
    with pytest.raises(ModelError):
        prepare_out(tmp_path / "a" / "b", force=False)
    assert prepare_out(tmp_path / "a" / "b", force=False, resumable=lambda d: (d / "sweep.json").exists())
    assert not [p for p in (tmp_path / "a" / "b").iterdir() if p.name.startswith(".flexkane-probe")]


def test_run_accepts_max_steps_and_a_too_small_budget_says_how_to_raise_it(tmp_path, capsys):
    code = main(["run", "falling-beam", "--out", str(tmp_path / "o"), "--max-steps", "3", "--t-end", "0.5",
                 "--quiet"])
    err = capsys.readouterr().err
    assert code == 3 and "max_steps" in err and "(3)" in err and "--max-steps" in err
    assert main(["run", "falling-beam", "--out", str(tmp_path / "p"), "--max-steps", "0", *SMALL_RUN]) == 2
    assert "--max-steps" in capsys.readouterr().err


def test_max_steps_in_the_simulation_table_of_a_model_file(tmp_path, capsys):
    import flexkane

    model = flexkane.builtin_model("falling-beam").with_values({"simulation.max_steps": 3})
    assert "max_steps = 3" in flexkane.dumps_model(model)
    path = tmp_path / "m.toml"
    flexkane.save_model(model, path)
    assert flexkane.load_model(path).simulation.max_steps == 3
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--t-end", "0.5", "--quiet"]) == 3
    assert "maximum number of steps (3)" in capsys.readouterr().err
    bad = flexkane.dumps_model(model).replace("max_steps = 3", "max_steps = -1")
    with pytest.raises(ModelError) as info:
        flexkane.loads_model(bad)
    assert info.value.path == "simulation.max_steps"


def test_cli_errors_name_options_and_the_library_names_parameters(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "flexkane", "run", "falling-beam", "--t-end", "-1",
                           "--out", str(tmp_path / "x")], capture_output=True, text=True,
                          env=child_env())
    assert proc.returncode == 2 and "--t-end" in proc.stderr and "Traceback" not in proc.stderr
    from flexkane.model.validate import validate_run_arguments
    from flexkane.simulation import output_grid

    for call, name in ((lambda: validate_run_arguments(t_end=-1, dt_out=1, rtol=1e-6, atol=1e-9), "t_end"),
                       (lambda: output_grid(1.0, -1.0), "dt_out"),
                       (lambda: validate_run_arguments(t_end=1, dt_out=1, rtol=1e-6, atol=1e-9, method="x"),
                        "method")):
        with pytest.raises(ModelError) as info:
            call()
        assert info.value.path == name and "--" not in str(info.value)


def test_sweep_library_errors_name_parameters_and_the_cli_names_options(tmp_path, capsys):
    from flexkane.sweep import SweepSpec, Vary

    with pytest.raises(ModelError) as info:
        Vary.parse("EI=1:2:0")
    assert info.value.path == "vary EI" and "--" not in str(info.value)
    with pytest.raises(ModelError) as info:
        SweepSpec(vary=("EI=1:2",), sampling="random", samples=5)
    assert info.value.path == "seed" and "--" not in str(info.value)
    assert main(["sweep", "falling-beam-exact", "--vary", "EI=1:2:0", "--out", str(tmp_path / "never")]) == 2
    assert "--vary EI" in capsys.readouterr().err
    assert not (tmp_path / "never").exists()
