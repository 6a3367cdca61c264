"""The model schema: every field declared once, and reading, writing, validation, the derivation
cache's value fields, units and constant names walking the declaration."""

import dataclasses
import re
import tomllib

import pytest
import tomli_w

from flexkane.builtin import builtin_model, builtin_names
from flexkane.errors import ModelError
from flexkane.model import schema
from flexkane.model.constant_names import MODAL_STEMS, generated_constant
from flexkane.model.parameter_units import field_values, inferred_units
from flexkane.model.parts import Beam, Driver, Orientation, ShapeSpec
from flexkane.model.toml_io import _plain, read_part, write_part
from flexkane.sweep.plot import column_units


def _sample(field, dimensions):
    """A value of a field unlike its default, in the form the part keeps it."""
    return {"value": "p_" + field.key, "pair": (1.5, -2.0), "vectors": tuple([0.5] * dimensions),
            "axes": [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0)], "ratios": ["zeta", 0.25], "float": 0.5,
            "shape": ShapeSpec("some-family", [1.5, 4.5], {"mass_ratio": 0.5}),
            "orientation": Orientation(axis=(0.0, 0.0, 1.0), angle="a"), "driver": Driver(speed="w"),
            "points": {"P": (1.0, 2.0)}, "outline": [(1.0, 2.0), (3.0, 4.0)],
            "table": {"z": "1 - z"}}[field.form]


def _every_table():
    return [(t, d) for t in (*schema.TABLES.values(), schema.DRIVER) for d in (2, 3) if t.of(d)]


@pytest.mark.parametrize("declared,dimensions", _every_table(),
                         ids=[f"{t.name}-{d}" for t, d in _every_table()])
def test_every_declared_field_is_written_to_toml_and_read_back(declared, dimensions):
    given = {f.key: _sample(f, dimensions) for f in declared.of(dimensions)}
    given.update({f.key: f.outside for f in declared.fields
                  if dimensions not in f.dimensions and f.outside is not schema.ABSENT})
    if declared.named:
        given["name"] = "part"
    part = declared.part(**given)
    written = write_part(declared, part, dimensions)
    assert list(written) == list(declared.keys(dimensions))     # every field, in declaration order
    data = tomllib.loads(tomli_w.dumps({"t": _plain(written)}))["t"]
    assert read_part(declared, data, "part" if declared.named else None, "t", dimensions) == part


@pytest.mark.parametrize("declared", [*schema.TABLES.values(), schema.DRIVER], ids=lambda t: t.name)
def test_every_attribute_of_a_part_is_declared_once(declared):
    keys = [f.key for f in declared.fields]
    assert len(keys) == len(set(keys))
    attributes = {f.name for f in dataclasses.fields(declared.part)} - {"name"}
    assert set(keys) == attributes
    for field in declared.fields:
        assert field.kind in schema.KINDS and field.write in schema.WRITES
        assert field.rule in (None, *schema.RULES) and set(field.dimensions) <= {2, 3}
        if field.rule is not None:
            assert all(field.unit_in(d) for d in field.dimensions), field.key
        assert field.unit is None or field.unit_by_type is None, field.key


def test_a_key_no_table_declares_is_refused_with_the_nearest_declared_one():
    import flexkane

    data = tomllib.loads(flexkane.dumps_model(builtin_model("rotor-blade")))
    data["beams"]["blade"]["rho_Ipp"] = data["beams"]["blade"].pop("rho_Ip")
    with pytest.raises(ModelError) as err:
        flexkane.loads_model(tomli_w.dumps(data))
    assert err.value.path == "beams.blade.rho_Ipp" and "did you mean 'rho_Ip'?" in str(err.value)


# The key paths whose change only changes numbers, as the derivation cache decided before the
# schema declared them (kept here as the behaviour to keep).
_VALUE_PATHS_BEFORE = [re.compile(p) for p in (
    r"gravity\.g", r"bodies\.[^.]+\.(mass|inertia)", r"bodies\.[^.]+\.inertia(\[[012]\]){1,2}",
    r"bodies\.[^.]+\.points\.[^.]+\[[012]\]", r"beams\.[^.]+\.(EI|rho|EA|rotary_inertia)",
    r"beams\.[^.]+\.damping\[\d+\]", r"beams\.[^.]+\.(EI_y|EI_z|GJ|rho_Ip|rho_Iy|rho_Iz|principal_angle)",
    r"beams\.[^.]+\.(damping_y|damping_z|torsion_damping|axial_damping)\[\d+\]",
    r"joints\.[^.]+\.(angle|axis|stiffness|damping|rest)", r"joints\.[^.]+\.parent_position\[[012]\]",
    r"joints\.[^.]+\.(orientation|child_orientation)\.(angle|angles\[[012]\])",
    r"springs\.[^.]+\.(stiffness|damping|rest_length)", r"springs\.[^.]+\.position_[ab]\[[012]\]",
    r"constraints\.[^.]+\.(axis|angle)", r"constraints\.[^.]+\.position_[ab]\[[01]\]",
    r"sensors\.[^.]+\.(station|distance)", r"controllers\.[^.]+\.(min|max)")]


def _key_paths(value, path=""):
    """Every key path of a model's fields, as the derivation cache walks them."""
    yield path
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            yield from _key_paths(getattr(value, f.name), f"{path}.{f.name}".lstrip("."))
    elif isinstance(value, dict):
        for k, v in value.items():
            yield from _key_paths(v, f"{path}.{k}")
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            yield from _key_paths(v, f"{path}[{i}]")


def test_the_cache_tells_value_changes_from_structure_changes_as_before():
    from flexkane.derivation_cache import VALUE_FIELDS

    paths = {p for name in builtin_names() for p in _key_paths(builtin_model(name))}
    paths |= {"joints.j.axis[0]", "constraints.c.position_a[2]", "bodies.b.inertia[1][2]", "beams.b.damping_y[3]",
              "joints.j.orientation.axis[0]", "beams.b.n_modes", "beams.b.L", "sensors.s.component"}
    assert len(paths) > 500
    for path in sorted(paths):
        before = any(p.fullmatch(path) for p in _VALUE_PATHS_BEFORE)
        assert any(p.fullmatch(path) for p in VALUE_FIELDS) == before, path


def test_validation_records_the_declared_unit_of_every_field_it_checks():
    checked = 0
    for name in builtin_names():
        model = builtin_model(name)
        for path, (_, unit) in field_values(model).items():
            declared = schema.unit_of_path(path, model.dimensions, model)
            if declared is not None:
                assert unit == declared, (name, path)
                checked += 1
    assert checked > 200


def test_a_declared_unit_is_the_unit_of_the_field_and_of_the_parameter_it_names(monkeypatch):
    from flexkane.model import validate

    model = builtin_model("flexible-arm")   # beams.link.EI = "EI"
    assert model.beams["link"].EI == "EI"
    other = dataclasses.replace(schema.BEAMS, fields=tuple(
        dataclasses.replace(f, unit="N m^3") if f.key == "EI" else f for f in schema.BEAMS.fields))
    assert field_values(model)["beams.link.EI"][1] == "N m^2"
    monkeypatch.setattr(validate, "BEAMS", other)
    monkeypatch.setitem(schema.TABLES, "beams", other)
    assert field_values(model)["beams.link.EI"][1] == "N m^3"
    assert inferred_units(field_values(model), model.parameters)["EI"] == "N m^3"
    units = column_units(model, ["beams.link.EI", "EI"])
    assert (units["beams.link.EI"], units["EI"]) == ("N m^3", "N m^3")


def test_generated_constant_names_are_those_the_beam_fields_declare():
    stems = [stem for f in schema.BEAMS.fields for _, stem, _ in f.constants]
    assert len(stems) == len(set(stems))
    assert MODAL_STEMS == schema.constant_stems("modal")
    assert generated_constant("Kt_tw_12", "tw", "tw").startswith("the modal constant Kt_tw_12 = int GJ")
    assert generated_constant("Ip_tw", "tw", "tw").startswith("the mass constant Ip_tw = int rho_Ip dx")
    assert generated_constant("Kx_tw_12", "tw", "tw") is None


@dataclasses.dataclass
class _BeamWithSkin(Beam):
    """A beam with one more attribute, the part of a field declared only in a copy of the schema."""

    rho_skin: object = None


def test_a_field_declared_once_is_read_written_validated_and_classified(monkeypatch):
    import flexkane
    from flexkane.model import validate

    skin = schema.Field("rho_skin", "mass of the skin per unit length", "kg/m", (2,), kind="value",
                        rule="non_negative")
    beams = schema.BEAMS.with_field(skin, _BeamWithSkin)
    monkeypatch.setitem(schema.TABLES, "beams", beams)
    monkeypatch.setattr(validate, "BEAMS", beams)
    data = tomllib.loads(flexkane.dumps_model(builtin_model("pendulum-beam")))
    beam = next(iter(data["beams"]))
    data["beams"][beam]["rho_skin"] = "m_skin"
    data["parameters"] = {**data.get("parameters", {}), "m_skin": 0.25}
    model = flexkane.loads_model(tomli_w.dumps(data))
    assert model.beams[beam].rho_skin == "m_skin"
    assert tomllib.loads(flexkane.dumps_model(model))["beams"][beam]["rho_skin"] == "m_skin"
    assert field_values(model)[f"beams.{beam}.rho_skin"] == ("m_skin", "kg/m")
    assert inferred_units(field_values(model), model.parameters)["m_skin"] == "kg/m"
    value = schema.one_pattern(schema.value_path_patterns([beams]))
    assert value.fullmatch(f"beams.{beam}.rho_skin") and not value.fullmatch(f"beams.{beam}.n_modes")
    data["parameters"]["m_skin"] = -0.25
    with pytest.raises(ModelError) as err:
        flexkane.loads_model(tomli_w.dumps(data))
    assert err.value.path == f"beams.{beam}.rho_skin"
    assert "a non-negative value [kg/m] (mass of the skin per unit length)" in str(err.value)
    assert "rho_skin" in beams.keys(2) and "rho_skin" not in beams.keys(3)   # a planar field


def test_the_report_gives_a_value_field_the_unit_its_declaration_gives(monkeypatch):
    import flexkane
    from flexkane.report import constant_columns

    eom = flexkane.derive(builtin_model("slider-crank"))
    defined = {row[4]: row[6] for row in constant_columns(eom) if row[2] == "defined"}
    assert defined == {"`bodies.crank.points.pin[0]`": "m", "`bodies.crank.points.pivot[0]`": "m"}
    other = dataclasses.replace(schema.BODIES, fields=tuple(
        dataclasses.replace(f, unit="km") if f.key == "points" else f for f in schema.BODIES.fields))
    monkeypatch.setitem(schema.TABLES, "bodies", other)
    assert {row[6] for row in constant_columns(eom) if row[2] == "defined"} == {"km"}
