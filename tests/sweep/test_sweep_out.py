"""A sweep's --out: resumed or extended when it holds the same sweep, refused (exit 2, nothing
replaced) when it holds another sweep or other files, unless --force; --max-steps reaches each
variant; the sweep extra is named when pyarrow is missing."""

import sys

import pytest

from flexkane.cli import main

MODEL = "falling-beam-exact"
BASE = [MODEL, "--t-end", "0.05", "--dt-out", "0.01", "--workers", "1", "--quiet"]


def sweep(out, *vary, extra=()):
    argv = ["sweep", *BASE, "--out", str(out), *extra]
    for v in vary:
        argv += ["--vary", v]
    return main(argv)


def test_a_sweep_with_other_values_refuses_to_replace_the_table(tmp_path, capsys):
    assert sweep(tmp_path, "beams.B.EI=20,40") == 0
    table = (tmp_path / "sweep.csv").read_bytes()
    capsys.readouterr()
    assert sweep(tmp_path, "beams.B.EI=30,50") == 2
    err = capsys.readouterr().err
    assert "--out" in err and "--force" in err and "beams.B.EI=20,40 there" in err and "Traceback" not in err
    assert (tmp_path / "sweep.csv").read_bytes() == table
    assert sweep(tmp_path, "beams.B.EI=20,40") == 0                      # the same sweep resumes
    assert sweep(tmp_path, "beams.B.EI=20,40,60") == 0                   # more values extend it
    assert sweep(tmp_path, "beams.B.EI=30,50", extra=["--force"]) == 0   # --force replaces the table
    assert (tmp_path / "sweep.csv").read_text().count("\n") == 3


def test_a_sweep_into_a_directory_of_other_files_needs_force(tmp_path, capsys):
    (tmp_path / "notes.txt").write_text("mine")
    assert sweep(tmp_path, "beams.B.EI=20,40") == 2
    err = capsys.readouterr().err
    assert "--force" in err and "notes.txt" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_max_steps_reaches_every_variant(tmp_path):
    assert sweep(tmp_path, "beams.B.EI=20,40", extra=["--max-steps", "2"]) == 0
    text = (tmp_path / "sweep.csv").read_text()
    assert text.count("failed") == 2 and "maximum number of steps (2)" in text


def test_a_sweep_without_pyarrow_names_the_extra_before_computing(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    monkeypatch.setitem(sys.modules, "pyarrow.parquet", None)
    assert sweep(tmp_path / "s", "beams.B.EI=20,40") == 2
    err = capsys.readouterr().err
    assert "'pyarrow'" in err and "flexkane[sweep]" in err and "Traceback" not in err
    assert not (tmp_path / "s" / "sweep-log.jsonl").exists()


def test_the_extras_are_declared_and_the_base_install_is_light():
    import tomllib
    from pathlib import Path

    project = tomllib.loads((Path(__file__).resolve().parents[2] / "pyproject.toml").read_text())["project"]
    base = " ".join(project["dependencies"])
    assert "dask" not in base and "pyarrow" not in base and "imageio" not in base
    extras = project["optional-dependencies"]
    assert any(d.startswith("dask[distributed]") for d in extras["sweep"])
    assert any(d.startswith("pyarrow") for d in extras["sweep"])
    assert any(d.startswith("imageio-ffmpeg") for d in extras["video"])
    assert "flexkane[sweep,video,dataframe,control]" in extras["all"]
    assert "flexkane[sweep,video,dataframe,control]" in extras["test"]
    assert any(d.startswith("control>=") for d in extras["control"])
    assert {"nbclient", "ipykernel"} <= {d.split(">")[0] for d in extras["notebook"]}


@pytest.mark.parametrize("module", ["distributed", "imageio_ffmpeg", "pandas", "control"])
def test_each_optional_module_has_an_extra_named_in_its_message(module, monkeypatch):
    from flexkane.extras import EXTRAS, MissingExtraError, require

    monkeypatch.setitem(sys.modules, module, None)
    with pytest.raises(MissingExtraError) as info:
        require(module)
    assert f"flexkane[{EXTRAS[module][0]}]" in str(info.value)
