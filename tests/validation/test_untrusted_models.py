"""The corpus of untrusted model files in ``untrusted_models/``: each is refused by ``flexkane
check`` with exit 2 and the message of ``expected.toml``, or is valid and (where marked) derives,
prints and generates code without unbounded work and without impulses."""

import math
import pathlib
import tomllib

import pytest
import sympy as sp

import flexkane
from flexkane.cli import main
from flexkane.errors import ModelError, ModelErrors
from flexkane.kane.equations import derive
from flexkane.numerics.codegen import generate_rhs_source
from flexkane.report import format_equations

HERE = pathlib.Path(__file__).parent / "untrusted_models"
EXPECTED = tomllib.loads((HERE / "expected.toml").read_text("utf-8"))["files"]


def test_every_file_of_the_corpus_has_an_expected_outcome():
    assert sorted(p.name for p in HERE.glob("*.toml") if p.name != "expected.toml") == sorted(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_check_gives_the_expected_outcome(name, capsys):
    case = EXPECTED[name]
    code = main(["check", str(HERE / name)])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    if case["outcome"] == "refused":
        assert code == 2 and out == "" and err.startswith(f"flexkane: error: {case['path']}: expected ")
    else:
        assert code == 0 and err == "", err
    missing = [text for text in case.get("says", []) if text not in out + err]
    assert not missing, f"{missing} not in {out + err}"


_IMPULSES = (sp.DiracDelta, sp.Heaviside, sp.Derivative, sp.Subs)


@pytest.mark.parametrize("name", sorted(n for n, case in EXPECTED.items() if case.get("derive")))
def test_a_valid_file_derives_prints_and_generates_code_without_impulses(name):
    eom = derive(flexkane.load_model(HERE / name))
    exprs = [*eom.mass_matrix, *eom.forcing, *eom.qdot, *eom.outputs.values()]
    assert not any(e.has(*_IMPULSES) for e in exprs)
    text = format_equations(eom)
    source = generate_rhs_source(eom)
    assert "Dirac" not in source and "Heaviside" not in source
    if name == "torque_power_100.toml":    # the user's power is printed as written, not expanded
        assert "**100" in text and len(text) < 50_000


def test_several_problems_are_one_error_listing_each():
    with pytest.raises(ModelErrors) as info:
        flexkane.load_model(HERE / "several_errors.toml")
    paths = [error.path for error in info.value.errors]
    assert paths == ["bodies.hub.mass", "beams.link.rho", "simulation.t_end"]
    assert isinstance(info.value, ModelError) and info.value.path == "bodies.hub.mass"


def test_the_number_of_problems_reported_together_is_capped():
    from flexkane.model import validate

    text = (HERE / "several_errors.toml").read_text("utf-8")
    bodies = "".join(f"\n[bodies.extra{k}]\nmass = -1\ninertia = 0\n" for k in range(30))
    with pytest.raises(ModelErrors) as info:
        flexkane.model.toml_io.loads_model(text + bodies)
    assert len(info.value.errors) == validate.MAX_REPORTED
    assert f"(the first {validate.MAX_REPORTED};" in str(info.value)


@pytest.mark.parametrize("name, law, expected", [
    # law and its time derivatives at t = 0.001 (before the kink), 0.03 (after) [rad, rad/s, rad/s^2]
    ("driver_abs.toml", "coordinate", {0.001: (0.004, -1.0, 0.0), 0.03: (0.025, 1.0, 0.0)}),
    ("driver_max.toml", "coordinate", {0.001: (0.01, 0.0, 0.0), 0.03: (0.03, 1.0, 0.0)}),
    ("driver_where.toml", "coordinate", {0.001: (5e-5, 0.1, 100.0), 0.03: (0.04, 2.0, 0.0)}),
])
def test_kinked_drivers_are_differentiated_branch_by_branch(name, law, expected):
    eom = derive(flexkane.load_model(HERE / name))
    coord = eom.chain.of("j")[0]
    u, ud = eom.substitutions[coord.u], eom.substitutions[eom.chain.ud[coord.u]]
    for t, values in expected.items():
        got = [float(e.subs(eom.t, t)) for e in (coord.law, u, ud)]
        assert all(math.isclose(g, v, rel_tol=1e-12, abs_tol=1e-15) for g, v in zip(got, values)), got
