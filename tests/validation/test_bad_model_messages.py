"""Every bad model file in ``bad_models/`` and every bad command line of ``bad_models/expected.toml``
gives the message it must give: from the Python API a ModelError naming the key path, from
``flexkane check`` exit code 2 and that message on one line, without a traceback."""

import pathlib
import subprocess
import sys
import tomllib

import pytest

import flexkane
from flexkane.cli import main
from flexkane.errors import ModelError

BAD = pathlib.Path(__file__).parent / "bad_models"
EXPECTED = tomllib.loads((BAD / "expected.toml").read_text("utf-8"))
FILES = sorted(EXPECTED["files"])
ARGUMENTS = sorted(EXPECTED["arguments"])


def _says(message: str, case: dict) -> None:
    missing = [text for text in case["says"] if text not in message]
    assert not missing, f"{missing} not in message: {message}"


def test_the_corpus_has_at_least_thirty_cases_each_with_its_message():
    files = sorted(p.name for p in BAD.glob("*.toml") if p.name != "expected.toml")
    assert files == FILES
    assert len(FILES) >= 30 and len(ARGUMENTS) >= 10


@pytest.mark.parametrize("name", FILES)
def test_loading_a_bad_file_raises_a_model_error_naming_the_key_path(name):
    case = EXPECTED["files"][name]
    with pytest.raises(ModelError) as info:
        flexkane.load_model(BAD / name)
    message = str(info.value)
    if "path" in case:
        assert info.value.path == case["path"]
        assert message.startswith(f"{case['path']}: expected ")
    _says(message, case)


@pytest.mark.parametrize("name", FILES)
def test_check_of_a_bad_file_exits_2_with_the_message_and_no_traceback(name, capsys):
    assert main(["check", str(BAD / name)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.startswith("flexkane: error: ") and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    _says(err, EXPECTED["files"][name])


@pytest.mark.parametrize("name", ARGUMENTS)
def test_a_bad_command_line_exits_2_with_the_message(name, capsys):
    case = EXPECTED["arguments"][name]
    argv = [arg.replace("{bad_models}", str(BAD)) for arg in case["argv"]]
    try:
        code = main(argv)
    except SystemExit as exc:   # argparse's own usage errors
        code = exc.code
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and "Traceback" not in err
    _says(err, case)


def test_every_built_in_model_passes_check(capsys):
    for name in flexkane.builtin_names():
        assert main(["check", name]) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    assert out.count(": valid (") == len(flexkane.builtin_names())


def test_check_in_its_own_process_prints_one_line_without_traceback():
    names = ["beam_key_typo.toml", "joint_graph_cycle.toml", "beam_expression_shape_unsafe.toml"]
    procs = [subprocess.Popen([sys.executable, "-m", "flexkane", "check", str(BAD / name)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for name in names]
    for name, proc in zip(names, procs):
        out, err = proc.communicate(timeout=300)
        assert proc.returncode == 2 and out == ""
        assert "Traceback" not in err and len(err.strip().splitlines()) == 1
        _says(err, EXPECTED["files"][name])
