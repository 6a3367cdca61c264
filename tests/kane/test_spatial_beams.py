"""Spatial beams (bending in two principal planes, torsion, axial stretch) on the spatial engine.

Oracles: the analytic frequencies of a clamped beam (eq. 8.7 with EI_y or EI_z; torsion
(2k - 1) pi / (2 L) sqrt(GJ / rho_Ip)), the conservation of energy (its rate along the motion is zero
at any state), and the planar engine (a planar beam chain run through the spatial engine).
"""

import numpy as np
import pytest

import flexkane
from flexkane.model import loads_model
from flexkane.model.as_spatial import as_spatial
from spatial_models import accelerations, compact_functions as _compact_functions, output_rates as _rates

LAMBDA = np.array([1.8751040687119611, 4.6940911329741745])   # clamped-free roots, eq. 8.4

CLAMPED = """
dimensions = 3
name = "clamped-spatial-beam"

[parameters]
L = 1.2
rho = 0.7
EI_y = 5.0
EI_z = 9.0
GJ = 3.0
rho_Ip = 0.01

[beams.b]
L = "L"
rho = "rho"
EI_y = "EI_y"
EI_z = "EI_z"
GJ = "GJ"
rho_Ip = "rho_Ip"
n_modes_y = 2
n_modes_z = 2
n_torsion = 2
principal_angle = {beta}

[joints.weld]
type = "weld"
parent = "ground"
child = "b"
{orientation}
"""


def _linear_frequencies(eom, h=1e-6):
    """Natural frequencies [rad/s] of the equations linearized about q = u = 0 (central differences
    of u'(q, u); the coordinates' rates are the speeds)."""
    acc = accelerations(eom)
    n = len(eom.q)
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    for k in range(2 * n):
        y = np.zeros(2 * n)
        y[k] = h
        A[n:, k] = (acc(y[:n], y[n:]) - acc(-y[:n], -y[n:])) / (2 * h)
    return np.sort(np.abs(np.linalg.eigvals(A).imag))[::2]


@pytest.mark.parametrize("beta, orientation", [(0.0, ""), (0.4, 'orientation = { axis = [1, 2, 0.5], angle = 0.7 }')])
def test_clamped_spatial_beam_frequencies_equal_the_analytic_values(beta, orientation):
    """A beam welded to the ground (in a turned frame, with turned principal axes): bending along z
    with EI_y, along y with EI_z (eq. 8.7), torsion (2k - 1) pi/(2L) sqrt(GJ/rho_Ip)."""
    eom = flexkane.derive(loads_model(CLAMPED.format(beta=beta, orientation=orientation)), cache=False)
    assert [q.name for q in eom.q] == ["q_b_y1", "q_b_y2", "q_b_z1", "q_b_z2", "q_b_t1", "q_b_t2"]
    L, rho, EI_y, EI_z, GJ, rho_Ip = 1.2, 0.7, 5.0, 9.0, 3.0, 0.01
    expected = np.sort(np.concatenate([
        LAMBDA ** 2 * np.sqrt(EI_y / (rho * L ** 4)), LAMBDA ** 2 * np.sqrt(EI_z / (rho * L ** 4)),
        np.array([1, 3]) * np.pi / (2 * L) * np.sqrt(GJ / rho_Ip)]))
    found = _linear_frequencies(eom)
    assert np.abs(found - expected).max() <= 1e-6 * expected.max()


ROTOR = """
dimensions = 3
name = "blade-on-a-pivot"

[bodies.hub]
mass = 2.0
inertia = [[0.3, 0.01, 0.0], [0.01, 0.2, 0.02], [0.0, 0.02, 0.25]]
points = { root = [0.1, 0.05, 0.0], C = [0.0, 0.0, -0.1] }

[beams.blade]
L = 1.5
rho = 0.8
EI_y = 20.0
EI_z = 35.0
GJ = 8.0
rho_Ip = 0.05
EA = 4000.0
n_modes_y = 2
n_modes_z = 2
n_torsion = 1
n_axial = 1
principal_angle = 0.3
geometric_stiffening = true

[joints.pivot]
type = "spherical"
parent = "ground"
child = "hub"
child_point = "C"

[joints.clamp]
type = "weld"
parent = "hub"
parent_point = "root"
child = "blade"
orientation = { sequence = "zyx", angles = [0.2, -0.3, 0.5] }

[bodies.tip]
mass = 0.3
inertia = [[0.004, 0.0005, 0.0], [0.0005, 0.002, 0.0001], [0.0, 0.0001, 0.003]]
points = { a = [-0.05, 0.01, 0.02] }

[joints.tip]
type = "weld"
parent = "blade"
station = 1.5
child = "tip"
child_point = "a"
orientation = { axis = [0, 1, 1], angle = 0.4 }

[bodies.sensor]
mass = 0.1
inertia = [0.0002, 0.0003, 0.0001]

[joints.flap]
type = "revolute"
parent = "blade"
station = 0.8
child = "sensor"
axis = [0, 1, 0]
stiffness = 2.0

[gravity]
g = 9.81
direction = [0, 0.3, -1]
"""


def _random_states(eom, euler_slice, count=4, seed=7):
    rng = np.random.default_rng(seed)
    states = []
    for _ in range(count):
        q = rng.uniform(-0.05, 0.05, len(eom.q))
        q[euler_slice] = rng.normal(size=4)
        q[euler_slice] /= np.linalg.norm(q[euler_slice])
        states.append((q, rng.uniform(-1.0, 1.0, len(eom.u))))
    return states


@pytest.mark.slow
def test_spatial_beam_on_a_spherical_joint_conserves_energy():
    """A hub on a spherical joint (Euler parameters) carrying a blade that bends in both planes,
    twists and stretches, with geometric stiffening and gravity, a tip body welded at its end and a
    body on a sprung revolute joint at a station (both follow the deflection, both slopes and the
    twist there); no load, no damping: the energy's rate along the equations of motion is zero at
    random states."""
    eom = flexkane.derive(loads_model(ROTOR), cache=False)
    rates = _rates(eom, ("energy", "kinetic"), _random_states(eom, slice(0, 4)))
    assert np.all(np.abs(rates[:, 0]) <= 1e-9 * np.abs(rates[:, 1])), rates
    assert _compact_functions(eom, [eom.compact.outputs["strain"]])(np.zeros(len(eom.q)), np.zeros(len(eom.u)))[0] == 0


@pytest.mark.slow
def test_free_floating_spatial_beam_conserves_momentum():
    """The same hub and blade floating free (free joint, no gravity): the linear momentum and the
    angular momentum about the mass centre are constant (their rates vanish at random states); the
    sections' polar inertia (rho_Ip, gyroscopic terms that do no work) enters the angular momentum."""
    text = ROTOR.replace('type = "spherical"', 'type = "free"').split("[gravity]")[0]
    eom = flexkane.derive(loads_model(text), cache=False)
    names = ("H_x", "H_y", "H_z", "p_x", "p_y", "p_z", "kinetic")
    states = _random_states(eom, slice(3, 7))
    rates = _rates(eom, names, states)
    H = _compact_functions(eom, [eom.compact.outputs[n] for n in names[:3]])
    for (q, u), row in zip(states, rates):
        scale = np.abs(H(q, u)).max()
        assert np.abs(row[:6]).max() <= 1e-9 * scale * max(1.0, np.abs(u).max()), row


@pytest.mark.parametrize("name", ["spin-up", "pendulum-beam", "flexible-arm", "two-link-flexible-arm"])
def test_planar_beam_chain_through_the_spatial_engine_equals_the_planar_engine(name):
    """A planar beam (driven hub with geometric stiffening; a pendulum with distributed gravity; a
    hub-driven arm with a payload at the tip; two flexible links, the second on the first's tip) as
    a spatial beam bending in its frame's x-y plane: the same accelerations and energies to 1e-10."""
    planar = flexkane.builtin_model(name)
    spatial = as_spatial(planar)
    eom2, eom3 = flexkane.derive(planar, cache=False), flexkane.derive(spatial, cache=False)
    assert [q.name.replace("_y", "_") for q in eom3.q] == [q.name for q in eom2.q]
    a2, a3 = accelerations(eom2), accelerations(eom3)
    values2, values3 = eom2.constant_values(), eom3.constant_values()
    rng = np.random.default_rng(11)
    for _ in range(3):
        q = rng.uniform(-0.3, 0.3, len(eom2.q))
        u = rng.uniform(-1.0, 1.0, len(eom2.u))
        t = rng.uniform(0.0, 3.0)
        ud2, ud3 = a2(q, u, t), a3(q, u, t)
        assert np.abs(ud2).max() > 1e-3
        assert np.abs(ud3 - ud2).max() <= 1e-10 * max(1.0, np.abs(ud2).max())
        for output in ("kinetic", "strain", "potential_gravity", "energy"):
            states = [dict(zip(e.q + e.u, np.concatenate([q, u]))) for e in (eom2, eom3)]
            o2, o3 = (float(e.outputs[output].xreplace({**v, **s, e.t: t}))
                      for e, v, s in zip((eom2, eom3), (values2, values3), states))
            assert abs(o3 - o2) <= 1e-10 * max(1.0, abs(o2)), output


SPINNING = """
dimensions = 3
name = "spinning-blade"

[parameters]
Omega = {Omega}

[beams.blade]
L = 2.0
rho = 1.5
EI_y = 30.0
EI_z = 30.0
n_modes_y = 2
n_modes_z = 2
geometric_stiffening = true

[joints.hub]
type = "revolute"
parent = "ground"
child = "blade"
axis = [0, 0, 1]
driver = {{ speed = "Omega" }}
"""


def _block_frequencies(eom, names, h=1e-6):
    """Frequencies [rad/s] of the equations linearized about q = u = 0 in the coordinates ``names``
    (their speeds are their rates; the other coordinates held at zero)."""
    acc = accelerations(eom)
    q_names = [q.name for q in eom.q]
    u_names = [u.name for u in eom.u]
    iq = [q_names.index(n) for n in names]
    iu = [u_names.index("u" + n[1:]) for n in names]
    m = len(names)
    A = np.zeros((2 * m, 2 * m))
    A[:m, m:] = np.eye(m)
    for k in range(2 * m):
        q, u = np.zeros(len(q_names)), np.zeros(len(u_names))
        if k < m:
            q[iq[k]] = h
        else:
            u[iu[k - m]] = h
        A[m:, k] = ((acc(q, u) - acc(-q, -u)) / (2 * h))[iu]
    return np.sort(np.abs(np.linalg.eigvals(A).imag))[::2]


def _southwell_coefficient(L):
    """``K_1 = int (L^2 - x^2)/2 Phi_1'^2 dx / int Phi_1^2 dx`` of the first clamped-free mode: the
    centrifugal tension's stiffness in the Rayleigh quotient, ``omega^2 = omega_0^2 + K_1 Omega^2``
    for a slow spin (an energy derivation, independent of the foreshortening kinematics)."""
    from flexkane.modes import get_family

    family = get_family("clamped-free")
    xi, w = np.polynomial.legendre.leggauss(60)
    xi, w = (xi + 1) / 2, w / 2
    x = xi * L
    slope = family.phi(xi, 1, 1)[0] / L
    return float(np.sum(w * L * (L ** 2 - x ** 2) / 2 * slope ** 2) / np.sum(w * L * family.phi(xi, 1)[0] ** 2))


def test_blade_spinning_about_an_axis_normal_to_it_obeys_southwell():
    """A uniform blade with EI_y = EI_z on a hub spun at a constant rate about an axis normal to it,
    with geometric stiffening: the flap (out of the plane of rotation, z) frequencies rise with the
    spin, for a slow spin as the Rayleigh quotient with the centrifugal tension predicts, and
    omega_lag^2 = omega_flap^2 - Omega^2 mode by mode (Southwell: the in-plane modes lose the
    centrifugal term)."""
    flap, lag = {}, {}
    for Omega in (0.0, 0.05, 6.0):
        eom = flexkane.derive(loads_model(SPINNING.format(Omega=Omega)), cache=False)
        flap[Omega] = _block_frequencies(eom, ["q_blade_z1", "q_blade_z2"])
        lag[Omega] = _block_frequencies(eom, ["q_blade_y1", "q_blade_y2"])
    np.testing.assert_allclose(flap[0.0], lag[0.0], rtol=1e-8)
    expected = LAMBDA[0] ** 2 * np.sqrt(30.0 / (1.5 * 2.0 ** 4))
    assert abs(flap[0.0][0] - expected) <= 1e-6 * expected
    for Omega in (0.05, 6.0):
        assert np.all(flap[Omega] > flap[0.0])
        np.testing.assert_allclose(lag[Omega] ** 2, flap[Omega] ** 2 - Omega ** 2, rtol=1e-7)
    assert np.all(flap[6.0] > flap[0.05])
    slow = (flap[0.05][0] ** 2 - flap[0.0][0] ** 2) / 0.05 ** 2
    assert abs(slow - _southwell_coefficient(2.0)) <= 1e-3 * slow, (slow, _southwell_coefficient(2.0))


@pytest.mark.slow
def test_free_vibration_of_a_spatial_blade_conserves_energy_when_simulated():
    """The pivoted hub, blade, tip and sprung body, compiled and integrated for 1 s from a spinning,
    bent and twisted state: the energy stays constant to solver tolerance while kinetic, strain and
    gravity energy exchange."""
    model = loads_model(ROTOR).with_values({"u_pivot_wz": 3.0, "u_pivot_wx": 0.5, "q_blade_z1": 0.02,
                                            "u_blade_t1": 1.0})
    run = flexkane.simulate(flexkane.compile_model(flexkane.derive(model, cache=False)), t_end=1.0, dt_out=0.01,
                            rtol=1e-10, atol=1e-12)
    energy, kinetic, strain = (run.outputs[n] for n in ("energy", "kinetic", "strain"))
    assert np.ptp(strain) > 1e-3 * np.abs(energy).max()        # the blade vibrates
    assert np.ptp(energy) <= 1e-9 * np.ptp(kinetic), (np.ptp(energy), np.ptp(kinetic))


TIP_LOAD = """
dimensions = 3
name = "tip-loaded-beam"

[beams.b]
static_corrections = false   # the oracle is the Ritz solution in the clamped-free modes
L = 1.2
rho = 0.7
EI_y = 5.0
EI_z = 9.0
n_modes_y = 4
n_modes_z = 4

[joints.weld]
type = "weld"
parent = "ground"
child = "b"

[loads.tip]
body = "b"
station = 1.2
force = [0, 0.02, -0.03]
frame = "local"

[springs.tether]
body_a = "ground"
position_a = [0.6, 0.0, 0.0]
body_b = "b"
station_b = 0.6
stiffness = 0.0
rest_length = 0.0
"""


def test_tip_force_on_a_spatial_beam_bends_it_as_a_cantilever():
    """A force at the tip station of a clamped beam: the static tip deflections are
    F L^3 / (3 EI) in each plane (EI_z for y, EI_y for z; four modes converge to 0.1 %), and a
    spring (of zero stiffness) may hang from a station."""
    eom = flexkane.derive(loads_model(TIP_LOAD), cache=False)
    acc = accelerations(eom)
    n = len(eom.q)
    zero = np.zeros(n)
    J = np.column_stack([(acc(np.eye(n)[k] * 1e-6, zero) - acc(-np.eye(n)[k] * 1e-6, zero)) / 2e-6
                         for k in range(n)])
    q = np.linalg.solve(J, -acc(zero, zero))              # where u' = 0 (linear equations)
    from flexkane.modes import get_family

    tip = get_family("clamped-free").phi(np.array([1.0]), 4)[:, 0]
    names = [c.name for c in eom.q]
    y = tip @ q[[names.index(f"q_b_y{i}") for i in range(1, 5)]]
    z = tip @ q[[names.index(f"q_b_z{i}") for i in range(1, 5)]]
    assert abs(y - 0.02 * 1.2 ** 3 / (3 * 9.0)) <= 1e-3 * abs(y)
    assert abs(z + 0.03 * 1.2 ** 3 / (3 * 5.0)) <= 1e-3 * abs(z)


def test_equations_report_of_a_spatial_beam_names_its_atoms_and_constants():
    """equations.md of a spatial beam with a body at a station: the station's constants (twist,
    slopes of both bending families) and the modal constants are written out."""
    from flexkane.report import equations_markdown

    text = CLAMPED.format(beta=0.0, orientation="") + """
[bodies.tip]
mass = 0.1
inertia = [0.001, 0.001, 0.001]

[joints.tip]
type = "weld"
parent = "b"
station = "L"
child = "tip"
"""
    eom = flexkane.derive(loads_model(text), cache=False)
    report = equations_markdown(eom, eom.constant_values())
    for piece in (r"\mathrm{Theta}_{1}(L)", r"\Phi'_{z1}(L)", "G_{y1,y1}", "Kt", "H_{y"):
        assert piece in report, piece
