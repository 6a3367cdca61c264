"""Units of parameters read from the expressions that use them (time laws of drivers and loads)."""

from flexkane.builtin import builtin_model
from flexkane.model.parameter_units import format_unit, inferred_units, parse_unit
from flexkane.model.paths import get_value
from flexkane.model.validate import validate_model


def test_unit_texts_read_and_write_back():
    for text in ("N m", "rad/s", "kg m^2", "N m s/rad", "1/s", "-", "m/s^2"):
        assert format_unit(parse_unit(text)) == text
    assert parse_unit("rad or m") is None and parse_unit("its unit") is None


def test_time_laws_fix_the_units_of_their_parameters():
    fields = {"joints.shoulder.torque": ("where(t < t1, T0*sin(2*pi*t/t1), 0)", "N m"),
              "joints.crank.driver.coordinate": ("Omega*t", "rad"),
              "joints.hub.driver.speed": ("where(t < T, Os/T*(t - T/(2*pi)*sin(2*pi*t/T)), Os)", "rad/s"),
              "loads.wind.fx": ("q0*min(t/T2, 1) + A*sqrt(x/L)", "N/m"),
              "bodies.arm.mass": ("m", "kg"), "beams.mast.L": ("L", "m")}
    units = inferred_units(fields, ["t1", "T0", "Omega", "Os", "T", "q0", "T2", "A", "L", "m", "free"])
    assert units == {"A": "N/m", "L": "m", "Omega": "rad/s", "Os": "rad/s", "T": "s", "T0": "N m", "T2": "s",
                     "m": "kg", "q0": "N/m", "t1": "s"}


def test_uses_that_disagree_or_leave_it_free_fix_no_unit():
    fields = {"bodies.a.mass": ("k", "kg"), "bodies.b.points.p[0]": ("k", "m"),   # k: kg and m
              "joints.j.torque": ("a*b*sin(t)", "N m")}                       # a*b: neither alone
    assert inferred_units(fields, ["k", "a", "b"]) == {}


def test_a_built_in_models_time_law_parameters_get_their_units():
    model = builtin_model("flexible-arm")   # torque = "where(t < t1, T0*sin(2*pi*t/t1), 0)" [N m]
    field_units = {}
    validate_model(model, units=field_units)
    fields = {path: (get_value(model, path), unit) for path, unit in field_units.items()}
    units = inferred_units(fields, model.parameters)
    assert (units["T0"], units["t1"], units["m_tip"]) == ("N m", "s", "kg")
