"""Modal invariants as arrays (flexkane.modes.invariants) against the modal constants of today's
derivations, the closed-form integrals of flexkane.modes.integrals and integrals done by hand."""

import numpy as np
import pytest
import sympy

from flexkane.errors import ModelError
from flexkane.kane.equations import derive
from flexkane.kane.modal_body import constant_value, planar_invariants, spatial_invariants
from flexkane.kane.numeric import constant_values
from flexkane.kane.spatial_beam_constants import SpatialBeamConstants
from flexkane.model import as_spatial, loads_model
from flexkane.model.field_values import FieldValues
from flexkane.modes import get_family
from flexkane.modes.integrals import foreshortening, mass_integrals, stiffness_integrals
from flexkane.modes.invariants import ShapeBasis, modal_invariants

L, RHO, EI = 1.3, 0.21991, 35.3

#: Every analytic family with the options it needs.
FAMILIES = [("clamped-free", {}), ("pinned-free", {}), ("pinned-pinned", {}), ("clamped-pinned", {}),
            ("clamped-clamped", {}), ("free-free", {}), ("clamped-free-tip-mass",
                                                          {"mass_ratio": 0.7, "inertia_ratio": 0.05}),
            ("polynomial", {}), ("expression", "xi**2, xi**3 - xi**2/3"),
            ("axial-fixed-free", {}), ("axial-fixed-fixed", {}), ("torsion-clamped-free", {}),
            ("torsion-clamped-clamped", {}), ("torsion-free-free", {})]


def close(a, b, rtol=1e-12, scale=0.0):
    """Agreement relative to the largest entry or to ``scale`` (the size of the integrand's
    factors: ``E_i`` of a family orthogonal to the rigid motion is zero to rounding)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape
    scale = max(np.abs(b).max(initial=0.0), scale, 1e-300)
    assert np.abs(a - b).max(initial=0.0) <= rtol * scale, (a, b)


@pytest.mark.parametrize("name, options", FAMILIES, ids=[f[0] for f in FAMILIES])
def test_invariants_of_every_family_equal_the_closed_form_integrals(name, options):
    if name == "expression":    # two functions of xi, as SymPy expressions
        xi = sympy.Symbol("xi")
        options = {"expressions": [xi ** 2, xi ** 3 - xi ** 2 / 3]}
    family = get_family(name, **options)
    n = 2 if name == "expression" else 5
    basis = ShapeBasis.of_family(family, n)
    if family.kind == "transverse":
        inv = modal_invariants(L, {"y": basis}, rho=RHO, **{"EI:y": EI})
        closed = mass_integrals(family, n, L, RHO)
        close(inv.E("y"), closed.E, scale=RHO * L)
        close(inv.F("y"), closed.F, scale=RHO * L ** 2)
        close(inv.G("y"), closed.G)
        close(inv.H("y"), stiffness_integrals(family, n, L, EI))
        assert (inv.m, inv.e, inv.I) == pytest.approx((RHO * L, RHO * L ** 2 / 2, RHO * L ** 3 / 3), rel=1e-14)
        # the foreshortening functions at the nodes, as geometric stiffening computes them today
        xi = np.linspace(0.0, 1.0, 7)
        close(inv._foreshortening(basis, xi), foreshortening(family, n, L, xi * L))
    elif family.kind == "axial":
        inv = modal_invariants(L, {}, axial=basis, rho=RHO, EA=EI)
        close(inv.AA, mass_integrals(family, n, L, RHO).G)
        close(inv.A, mass_integrals(family, n, L, RHO).E, scale=RHO * L)
        close(inv.HA, stiffness_integrals(family, n, L, EI))
    else:
        inv = modal_invariants(L, {}, torsion=basis, rho_Ip=RHO, GJ=EI)
        close(inv.Gt, mass_integrals(family, n, L, RHO).G)
        close(inv.Et, mass_integrals(family, n, L, RHO).E, scale=RHO * L)
        close(inv.Kt, stiffness_integrals(family, n, L, EI))


def test_invariants_of_shape_functions_from_any_producer_equal_integrals_by_hand():
    # Phi_1 = xi^2 given as a plain function: d_11(x) = int_0^x (2 s/L^2)^2 ds = 4 x^3/(3 L^4)
    basis = ShapeBasis(1, lambda xi, k: np.array([xi ** 2, 2 * xi, 2 + 0 * xi, 0 * xi, 0 * xi])[k][None, :], 4)
    inv = modal_invariants(L, {"y": basis}, rho=RHO, **{"EI:y": EI, "rho_I:y": 0.01})
    assert inv.E("y")[0] == pytest.approx(RHO * L / 3, rel=1e-14)
    assert inv.F("y")[0] == pytest.approx(RHO * L ** 2 / 4, rel=1e-14)
    assert inv.G("y")[0, 0] == pytest.approx(RHO * L / 5, rel=1e-14)
    assert inv.H("y")[0, 0] == pytest.approx(4 * EI / L ** 3, rel=1e-14)
    assert inv.Gr("y")[0, 0] == pytest.approx(0.01 * 4 / (3 * L), rel=1e-14)
    assert inv.D("y")[0, 0] == pytest.approx(RHO / 3, rel=1e-14)
    assert inv.Dx("y")[0, 0] == pytest.approx(RHO * 4 * L / 15, rel=1e-14)
    assert inv.Dphi("y")[0, 0, 0] == pytest.approx(RHO * 4 / 18, rel=1e-14)
    assert inv.DD("y")[0, 0, 0, 0] == pytest.approx(16 * RHO / (63 * L), rel=1e-14)


def test_sections_that_vary_along_the_beam_are_weights_of_the_quadrature():
    # rho = rho0 (1 + x/L): m = 3/2 rho0 L, e = 5/6 rho0 L^2; pinned-pinned sqrt(2) sin(pi xi):
    # G_11 = rho0 L (1 + 1/2), the linear part integrating sin^2 symmetrically about L/2
    basis = ShapeBasis.of_family(get_family("pinned-pinned"), 1)
    inv = modal_invariants(L, {"y": basis}, rho=lambda x: RHO * (1 + x / L))
    assert inv.m == pytest.approx(1.5 * RHO * L, rel=1e-14)
    assert inv.e == pytest.approx(5 / 6 * RHO * L ** 2, rel=1e-14)
    assert inv.G("y")[0, 0] == pytest.approx(1.5 * RHO * L, rel=1e-13)


def test_an_invariant_whose_section_property_is_missing_names_it():
    inv = modal_invariants(L, {"y": ShapeBasis.of_family(get_family("clamped-free"), 2)}, rho=RHO)
    with pytest.raises(ModelError, match="EI:y"):
        inv.H("y")
    with pytest.raises(ModelError, match="rho"):
        modal_invariants(L, {}, rho=lambda x: np.nan * x).m


def test_array_shapes_of_a_spatial_beam():
    cf = get_family("clamped-free")
    inv = modal_invariants(L, {"y": ShapeBasis.of_family(cf, 3), "z": ShapeBasis.of_family(cf, 2)},
                           torsion=ShapeBasis.of_family(get_family("torsion-clamped-free"), 2),
                           axial=ShapeBasis.of_family(get_family("axial-fixed-free"), 1), rho=RHO)
    assert inv.G("y", "z").shape == (3, 2)
    assert inv.DD("y", "z").shape == (3, 3, 2, 2)
    assert inv.Dphi("y", of="z").shape == (2, 3, 3)
    assert inv.Dpsi("z").shape == (1, 2, 2)
    assert inv.C("y").shape == (3, 1)
    close(inv.DD("y", "z"), np.transpose(inv.DD("z", "y"), (2, 3, 0, 1)))


SPATIAL = """
dimensions = 3
name = "invariants"
[beams.b]
L = 1.7
rho = 2.5
EI_y = 900.0
EI_z = 1500.0
GJ = 300.0
EA = 2.0e5
rho_Ip = 0.008
rho_Iy = 0.002
rho_Iz = 0.003
n_modes_y = 3
n_modes_z = 2
n_torsion = 2
n_axial = 2
shape_z = "polynomial"
principal_angle = 0.3
geometric_stiffening = true
[joints.hub]
type = "revolute"
parent = "ground"
child = "b"
axis = [0, 0, 1]
"""


#: Kinds of constants that are invariants of a beam (the others: values at stations, loads' integrals).
INVARIANT_KINDS = {"pair", "polar", "section", "rotary", "H", "Hs", "Kt", "HA"}


def _per_constant_quadrature(consts, beam, fields) -> dict:
    """The values of a spatial beam's invariant constants as computed before the invariants, one
    quadrature per constant (:meth:`SpatialBeamConstants.model_values`)."""
    used = consts.used
    consts.used = {s: spec for s, spec in used.items() if spec[0] in INVARIANT_KINDS}
    try:
        return SpatialBeamConstants.model_values(consts, beam, fields, fields.parameters)
    finally:
        consts.used = used


def _compare_every_constant(eom, model, invariants_of):
    values = constant_values(eom)
    fields = FieldValues(model)
    compared = 0
    for name, consts in eom.kinematics.constants.items():
        if model.dimensions == 3:   # the engine's values come from the invariants: today's quadrature
            values.update(_per_constant_quadrature(consts, model.beams[name], fields))
        inv = invariants_of(model.beams[name], fields, fields.parameters)
        # entries zero to rounding (off-diagonal H of orthogonal modes) judged by their kind's largest
        largest = {}
        for symbol, spec in consts.used.items():
            largest[spec[0]] = max(largest.get(spec[0], 0.0), abs(values[symbol]))
        for symbol, spec in consts.used.items():
            value = constant_value(inv, spec)
            if value is None:
                continue
            assert value == pytest.approx(values[symbol], rel=1e-12, abs=1e-12 * largest[spec[0]]), symbol
            compared += 1
    return compared


def test_every_constant_of_a_spatial_derivation_is_an_entry_of_the_invariants():
    model = loads_model(SPATIAL)
    eom = derive(model)
    kinds = {spec[0] for consts in eom.kinematics.constants.values() for spec in consts.used.values()}
    assert {"pair", "polar", "section", "Hs", "Kt", "HA"} <= kinds
    assert _compare_every_constant(eom, model, spatial_invariants) > 100


PLANAR = """
name = "planar-invariants"
[beams.B]
L = 1.2
rho = 0.8
EI = 40.0
EA = 1.0e4
rotary_inertia = 0.001
n_modes = 3
n_axial = 1
geometric_stiffening = true
[joints.hub]
type = "revolute"
parent = "ground"
child = "B"
"""


def test_every_constant_of_a_planar_derivation_is_an_entry_of_the_invariants():
    model = loads_model(PLANAR)
    eom = derive(model)
    assert _compare_every_constant(eom, model, planar_invariants) > 30
    spatial = as_spatial(model)
    assert _compare_every_constant(derive(spatial), spatial, spatial_invariants) > 30
