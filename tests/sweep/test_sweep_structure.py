"""Derive once per structure: variants grouped together really share their generated equations."""

import pytest

import flexkane
from flexkane.numerics.codegen import generate_rhs_source
from flexkane.numerics.jit_module import structure_key
from flexkane.sweep import RunSettings, SweepSpec, make_variants
from flexkane.sweep.structure import group_by_structure


def generated_key(eom):
    return structure_key(flexkane.__version__, generate_rhs_source(eom))


def check_groups(name, vary, n_groups):
    """Group the variants; each group must share generated code and numbers with its members' own."""
    model = flexkane.builtin_model(name).validate()
    spec = SweepSpec(vary=vary, t_end=0.1)
    groups = group_by_structure(make_variants(model, spec, RunSettings.resolve(spec, model)))
    assert len(groups) == n_groups
    keys_of_groups = []
    for group in groups:
        shared = flexkane.derive(group.variants[0].model)
        keys = set()
        for variant in group.variants:
            own = flexkane.derive(variant.model)
            keys.add(generated_key(own))
            # the numbers of each variant, from the group's one derivation, equal those from its own
            ours = dict(zip((s.name for s in shared.constants), shared.parameter_vector(variant.model)))
            theirs = dict(zip((s.name for s in own.constants), own.parameter_vector(variant.model)))
            assert ours == theirs
            assert list(shared.initial_state(variant.model)) == list(own.initial_state(variant.model))
        assert len(keys) == 1, [v.assignments for v in group.variants]
        keys_of_groups.append(keys.pop())
    assert len(set(keys_of_groups)) == n_groups
    return groups


def test_numbers_share_a_structure_while_zeros_and_mode_counts_do_not():
    # EI (modal constants), g (a parameter) and q3 (an initial condition) are numbers; a weld angle of
    # 0 is a literal zero (structure), unlike 0.1; n_modes changes the coordinates
    check_groups("falling-beam-exact", ("beams.B.EI=20,40", "g=0,9.81", "initial.q3=1.0",
                                        "joints.clamp.angle=0,0.1", "beams.B.n_modes=1,2"), 4)


def test_a_field_naming_a_parameter_and_its_numeric_values_are_two_structures():
    groups = check_groups("falling-beam-exact", ("bodies.RB.mass=mR,2.0,3.0",), 2)
    assert [[dict(v.assignments)["bodies.RB.mass"] for v in g.variants] for g in groups] == [["mR"], [2.0, 3.0]]


@pytest.mark.parametrize("vary", ["beams.link.L=1.0,1.2", "joints.tip.station=0.8,0.9"])
def test_beam_lengths_and_stations_given_as_numbers_are_structure(vary):
    # the constants at a station are named after its text (Phi_1(0.8)): one structure per value
    check_groups("flexible-arm", (vary, "T0=1.0,2.0"), 2)
