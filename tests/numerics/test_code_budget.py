"""The size budget of code generation (flexkane.numerics.code_budget): a right-hand side with more
straight-line operations than Numba compiles in bounded time is refused before the compile, with
exit 2 naming its size, the budget and what to do; the measure is a count, not a timer."""

import pytest

import flexkane
from flexkane.cli import main
from flexkane.errors import ModelError
from flexkane.kane.equations import derive
from flexkane.numerics.code_budget import DEFAULT_COMPILED_OPERATIONS, compiled_operations
from flexkane.numerics.codegen import generate_rhs_source


def test_compiled_operations_count_code_lines_and_skip_tables_and_comments():
    lines = ["RHS_TABLE_COEF = np.array([1.0, -2.0, 3e-5], dtype=np.float64)",
             "RHS_TABLE_INDEX = np.array([1, 2], dtype=np.int64).reshape(1, 2)",
             "RHS_COPY_DY = np.array([0, 3], dtype=np.int64).reshape(1, 2)",
             "# Kinematic equations q' = qdot(q, u, t); M(q, t) u' = f(q, u, t)",
             "    a = b*c + d - e/f",           # 4 operators
             "    g = math.sin(a)*2.0"]          # 1 operator and one math call (20)
    assert compiled_operations(lines) == 4 + 1 + 20


def test_the_size_measure_is_deterministic_and_ignores_term_tables(monkeypatch):
    monkeypatch.delenv("FLEXKANE_COMPILE_OPERATIONS", raising=False)
    beam = generate_rhs_source(derive(flexkane.builtin_model("falling-beam-exact").with_modes(20)))
    arm = generate_rhs_source(derive(flexkane.builtin_model("flexible-arm").with_modes(20)))
    again = generate_rhs_source(derive(flexkane.builtin_model("flexible-arm").with_modes(20)))
    size = {name: compiled_operations(src.splitlines()) for name, src in
            (("beam", beam), ("arm", arm), ("again", again))}
    # the free beam's long modal sums are term tables: few straight-line operations although its
    # right-hand side is as long as the arm's, whose payload puts the tip slope into rotations
    assert size["arm"] == size["again"]
    assert size["beam"] < size["arm"] < DEFAULT_COMPILED_OPERATIONS


def test_a_model_above_the_size_budget_is_refused_before_compiling(monkeypatch):
    monkeypatch.setenv("FLEXKANE_COMPILE_OPERATIONS", "500")
    eom = derive(flexkane.builtin_model("flexible-arm").with_modes(5))
    with pytest.raises(ModelError) as info:
        flexkane.compile_model(eom)
    text = str(info.value)
    assert info.value.path == "model size"
    assert "at most 500 operations" in text and "FLEXKANE_COMPILE_OPERATIONS" in text
    assert "fewer shape functions" in text


def test_the_size_budget_exits_2_from_run_naming_the_size_and_the_limit(monkeypatch, capsys, tmp_path):
    monkeypatch.setenv("FLEXKANE_COMPILE_OPERATIONS", "500")
    code = main(["run", "flexible-arm", "--n-modes", "5", "--t-end", "0.01", "--dt-out", "0.005",
                 "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2
    assert "flexkane: error: model size: expected a right-hand side of at most 500" in err
    assert "fewer shape functions" in err and "Traceback" not in err


def test_a_bad_budget_setting_is_refused(monkeypatch):
    monkeypatch.setenv("FLEXKANE_COMPILE_OPERATIONS", "many")
    with pytest.raises(ModelError) as info:
        generate_rhs_source(derive(flexkane.builtin_model("pendulum-beam")))
    assert info.value.path == "FLEXKANE_COMPILE_OPERATIONS"


@pytest.mark.slow
def test_falling_beam_exact_with_40_modes_derives_and_its_rhs_compiles(monkeypatch, tmp_path):
    monkeypatch.delenv("FLEXKANE_COMPILE_OPERATIONS", raising=False)
    compiled = flexkane.compile_model(derive(flexkane.builtin_model("falling-beam-exact").with_modes(40)),
                                      cache_dir=tmp_path)
    results = flexkane.simulate(compiled, t_end=0.01, dt_out=0.005)
    assert results.success and len(compiled.eom.u) == 40 + 3


@pytest.mark.slow
def test_spin_up_with_10_stiffened_modes_is_refused_by_its_size_not_a_timer(monkeypatch, capsys, tmp_path):
    """27,544 straight-line operations (benchmarks/RESULTS.md): above the default budget."""
    monkeypatch.delenv("FLEXKANE_COMPILE_OPERATIONS", raising=False)
    code = main(["run", "spin-up", "--n-modes", "10", "--t-end", "0.01", "--dt-out", "0.005",
                 "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2
    assert f"at most {DEFAULT_COMPILED_OPERATIONS} operations" in err and "Traceback" not in err
