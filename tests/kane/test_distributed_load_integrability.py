"""A distributed load that cannot be integrated along its beam is refused naming the field (issue 25,
item 5): a pole inside the beam gave finite, arbitrary numbers through the Gauss-Legendre nodes.
Integrable singularities (``1/sqrt(|x - a|)``) are refused as unbounded: the rules of the derivation
missed their generalized forces by 3 to 10 %."""

import pytest

import flexkane
from flexkane.errors import ModelError

#: A 1 m cantilever with one distributed load ``fy`` (and, in 3D, a spatial beam bending in y and z).
CANTILEVER = """
name = "cantilever-load"
{dimensions}
[parameters]
a = 0.35
[beams.beam]
L = 1.0
rho = 0.5
{rigidity}
[joints.clamp]
type = "weld"
parent = "ground"
child = "beam"
[distributed_loads.w]
beam = "beam"
fy = "{fy}"
[simulation]
t_end = 2.0
"""
PLANAR = {"dimensions": "", "rigidity": "EI = 2.0\nn_modes = 3"}
SPATIAL = {"dimensions": "dimensions = 3", "rigidity": "EI_y = 2.0\nEI_z = 2.0\nn_modes_y = 2\nn_modes_z = 1"}


def _model(fy: str, kind: dict = PLANAR):
    return flexkane.loads_model(CANTILEVER.replace("{fy}", fy).replace("{dimensions}", kind["dimensions"])
                                .replace("{rigidity}", kind["rigidity"]))


#: Loads whose integral along [0, 1] m diverges, and what the message says of each.
NOT_INTEGRABLE = {
    "0.001/(x - 0.35)**2": "x = 0.35 m, a pole of order 2",     # the issue's reproducer
    "0.001/(x - a)**2": "x = 0.35 m, a pole of order 2",        # through a parameter
    "1/(x - 0.35)": "a pole of order 1",                        # a principal value is not an integral
    "1/abs(x - 0.35)": "a pole of order 1",
    "1/(x**2 - 0.7*x + 0.1225)": "a pole of order 2",           # a double root: no sign change
    "abs(x - 0.35)**-1.5": "a pole of order 1.5",
    "1/(0.999 - x)": "x = 0.999 m, a pole of order 1",          # near the tip
    "tan(2*x)": "x = 0.785398 m, a pole of order 1",            # tan = sin/cos: cos(2x) = 0 at pi/4
    "sin(3*t)/(x - 1.1 + 0.1*t)**2": "x = 0.9 m, a pole of order 2 of the load at t = 2 s",   # enters later
    "1/(x**2 + 1e-12)": "does not converge",                    # finite, too steep for any rule
    # integrable, unbounded
    "1/sqrt(abs(x - a))": "a pole of order 0.5 of the load at t = 0 s: integrable, but unbounded",
    "abs(x - a)**-0.9": "a pole of order 0.9",
    "log(abs(x - a))": "a logarithmic singularity",
}


@pytest.mark.parametrize("fy", sorted(NOT_INTEGRABLE))
def test_a_load_not_integrable_along_the_beam_is_refused_naming_the_field(fy):
    with pytest.raises(ModelError) as info:
        _model(fy)
    assert info.value.path == "distributed_loads.w.fy"
    message = str(info.value)
    assert "bounded and integrable along the beam" in message and NOT_INTEGRABLE[fy] in message, message


def test_a_pole_in_a_spatial_beams_load_is_refused():
    with pytest.raises(ModelError, match=r"distributed_loads\.w\.fy: .*a pole of order 2"):
        _model("0.001/(x - 0.35)**2", SPATIAL)


def test_check_of_the_issues_load_exits_2_naming_the_field(tmp_path, capsys):
    from flexkane.cli import main

    path = tmp_path / "pole.toml"
    path.write_text(CANTILEVER.replace("{fy}", "0.001/(x - 0.35)**2").replace("{dimensions}", "")
                    .replace("{rigidity}", PLANAR["rigidity"]), "utf-8")
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("flexkane: error: distributed_loads.w.fy: ") and "Traceback" not in err


@pytest.mark.parametrize("fy", ["-0.3", "-0.3*x", "sin(3*x - 2*t)*exp(x)", "1/(x + 0.01)", "1/(x**2 + 1e-3)",
                                "1/(x - 1.5)**2", "log(x + 1)", "tan(x)", "sqrt(abs(x - a))"])
def test_bounded_loads_are_accepted(fy):
    _model(fy)
