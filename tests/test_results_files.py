"""Damaged results files: load_results and `flexkane animate` give a ResultsError naming the file and
what is wrong (exit 2, no traceback), never a raw NumPy or zipfile exception; intact files read back."""

import io
import zipfile

import numpy as np
import pytest

from flexkane.cli import main
from flexkane.errors import FlexkaneError, ResultsError
from flexkane.results import NPZ_ARRAYS, Results, load_results


@pytest.fixture
def saved(tmp_path):
    """A small results.npz (3 output times, 2 states, 2 outputs) and its bytes."""
    t = np.array([0.0, 0.1, 0.2])
    results = Results(t=t, state=np.column_stack([np.sin(t), np.cos(t)]), state_names=["q1", "u1"],
                      outputs={"energy": 1.0 + 0 * t, "kinetic": t ** 2},
                      model_text='name = "x"\n', parameters={"g": 9.81}, solver={"method": "dop853"})
    results.write(tmp_path)
    path = tmp_path / "results.npz"
    return path, path.read_bytes()


def _arrays(data: bytes) -> dict:
    with np.load(io.BytesIO(data), allow_pickle=False) as archive:
        return {name: archive[name] for name in archive.files}


def test_an_intact_file_reads_back(saved):
    path, _ = saved
    back = load_results(path.parent)
    assert back.state_names == ["q1", "u1"] and back.parameters == {"g": 9.81}
    np.testing.assert_array_equal(back["kinetic"], np.array([0.0, 0.1, 0.2]) ** 2)


def test_a_run_without_outputs_is_written_and_read_back(tmp_path):
    Results(t=np.array([0.0, 1.0]), state=np.zeros((2, 1)), state_names=["q"]).write(tmp_path)
    assert load_results(tmp_path).outputs == {}


def _check_refused(path, capsys=None):
    """load_results raises ResultsError naming the file (a FlexkaneError, so the CLI exits 2)."""
    with pytest.raises(ResultsError) as caught:
        load_results(path)
    assert str(path) in str(caught.value) and isinstance(caught.value, FlexkaneError)
    return str(caught.value)


def test_truncated_files_are_refused_at_every_offset(saved, tmp_path):
    path, data = saved
    damaged = tmp_path / "damaged.npz"
    offsets = sorted(set(range(0, len(data), 97)) | {1, 3, 4, 30, len(data) // 2, len(data) - 22, len(data) - 1})
    for offset in offsets:
        damaged.write_bytes(data[:offset])
        message = _check_refused(damaged)
        assert ("truncated or damaged" in message or "not an NPZ" in message), (offset, message)


def test_flipped_bytes_are_refused_or_read_intact(saved, tmp_path):
    """A flipped byte in the arrays fails their CRC; a flip in the ZIP bookkeeping that leaves the
    arrays intact may read back, and then gives exactly the original arrays."""
    path, data = saved
    original = load_results(path)
    damaged = tmp_path / "flipped.npz"
    refused = 0
    for offset in range(0, len(data), 13):
        damaged.write_bytes(data[:offset] + bytes([data[offset] ^ 0xFF]) + data[offset + 1:])
        try:
            back = load_results(damaged)
        except ResultsError as exc:
            assert str(damaged) in str(exc)
            refused += 1
            continue
        np.testing.assert_array_equal(back.state, original.state)
        np.testing.assert_array_equal(back.t, original.t)
        assert back.outputs.keys() == original.outputs.keys() and back.model_text == original.model_text
        assert back.parameters == original.parameters and back.solver == original.solver
    assert refused > len(range(0, len(data), 13)) // 2


def test_a_text_file_and_an_npy_file_are_not_results(tmp_path):
    text = tmp_path / "notes.npz"
    text.write_text("t,q1\n0.0,1.0\n")
    assert "not an NPZ (ZIP) archive" in _check_refused(text)
    empty = tmp_path / "empty.npz"
    empty.write_bytes(b"")
    assert "empty" in _check_refused(empty)
    single = tmp_path / "single.npz"
    with open(single, "wb") as handle:
        np.save(handle, np.zeros(3))
    assert "single NumPy array" in _check_refused(single)


def test_a_zip_that_is_not_an_npz_is_refused(tmp_path):
    path = tmp_path / "results.npz"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("readme.txt", "hello")
    assert "missing" in _check_refused(path)


@pytest.mark.parametrize("name", list(NPZ_ARRAYS))
def test_a_missing_array_is_named(saved, tmp_path, name):
    _, data = saved
    arrays = _arrays(data)
    del arrays[name]
    path = tmp_path / "incomplete.npz"
    np.savez(path, **arrays)
    assert repr(name) in _check_refused(path)


@pytest.mark.parametrize("name, value, words", [
    ("state", np.zeros((2, 2)), "array 'state' has shape (2, 2), expected (3, 2)"),
    ("state", np.zeros(6), "array 'state' should hold floating-point numbers with 2 dimension(s)"),
    ("t", np.array(["a", "b", "c"]), "array 't' should hold floating-point numbers"),
    ("outputs", np.zeros((2, 4)), "array 'outputs' has shape (2, 4), expected (2, 3)"),
    ("state_names", np.array(["q1"]), "expected (3, 1)"),
    ("parameters", np.array("{not json"), "array 'parameters' is not JSON"),
    ("solver", np.array("[1, 2]"), "array 'solver' should be a JSON object"),
    ("partial", np.array(1.5), "array 'partial' should hold a boolean"),
])
def test_inconsistent_arrays_are_named(saved, tmp_path, name, value, words):
    _, data = saved
    arrays = _arrays(data)
    arrays[name] = value
    path = tmp_path / "inconsistent.npz"
    np.savez(path, **arrays)
    assert words in _check_refused(path)


def test_a_pickled_array_is_refused_not_loaded(saved, tmp_path):
    _, data = saved
    arrays = _arrays(data)
    arrays["model_text"] = np.array([{"x": 1}], dtype=object)
    path = tmp_path / "pickled.npz"
    np.savez(path, **arrays)
    assert "truncated or damaged" in _check_refused(path)


def test_animate_of_a_truncated_run_exits_2_naming_the_file(saved, capsys):
    path, data = saved
    path.write_bytes(data[: len(data) // 2])
    assert main(["animate", str(path.parent), "--quiet", "--no-mp4"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and str(path) in err and "truncated or damaged" in err
