"""The hand-written recursive right-hand side of chain_model(k) (benchmarks/recursive_yardstick.py)
against flexkane's generated one, and against physics on its own.

The yardstick computes its modal constants, kinematics and Kane's sums independently of flexkane
(body by body, composite bodies), so agreement to 1e-10 is an independent derivation of the same
equations: an oracle for any rebuild of the engine.
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp

BENCHMARKS = pathlib.Path(__file__).resolve().parents[2] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

import recursive_yardstick as ry  # noqa: E402
from scaling import chain_model  # noqa: E402



@pytest.fixture(scope="module")
def flexkane_chains():
    """flexkane's derived and compiled chain_model(k) for k = 1, 2."""
    return {k: ry.FlexkaneChain(chain_model(k)) for k in (1, 2)}


def test_cantilever_constants_satisfy_orthogonality_and_published_roots():
    """Eqs. 8.6, 8.8, 8.9: roots 1.8751, 4.6941, 7.8548; G = m delta_ij, H = p_i^2 m delta_ij."""
    L, rho, EI, n = 0.6, 0.5, 8.0, 3
    roots = ry.cantilever_roots(n)
    np.testing.assert_allclose(roots, [1.8751040687, 4.6940911330, 7.8547574382], rtol=1e-10)
    c = ry.beam_constants(L, rho, EI, n)
    m = rho * L
    np.testing.assert_allclose(c["G"], m * np.eye(n), atol=1e-13 * m)
    p2 = (roots / L) ** 4 * EI / rho          # eq. 8.7 squared
    np.testing.assert_allclose(c["H"], np.diag(p2 * m), atol=1e-11 * p2[-1] * m)
    # a cantilever's tip value is 2 (-1)^(i+1) with the normalization of eq. 8.8
    np.testing.assert_allclose(c["PhiL"], 2.0 * (-1.0) ** np.arange(n), rtol=1e-12)


def test_modal_constants_equal_flexkanes(flexkane_chains):
    """Every modal constant the derivation uses has the value the yardstick computes on its own."""
    fk = flexkane_chains[1]
    values = {s.name: v for s, v in fk.eom.constant_values(chain_model(1)).items()}
    c = ry.chain_data(chain_model(1), 1).constants
    mine = {"m_link_1": c["mB"], "e_link_1": c["eB"], "I_link_1": c["IB"]}
    for i in range(2):
        mine[f"E_{i + 1}"] = c["E"][i]
        mine[f"F_{i + 1}"] = c["F"][i]
        mine[f"Phi_{i + 1}(L)"] = c["PhiL"][i]
        mine[f"Phi'_{i + 1}(L)"] = c["dPhiL"][i]
        for j in range(i, 2):
            mine[f"G_{i + 1}{j + 1}"] = c["G"][i, j]
            mine[f"H_{i + 1}{j + 1}"] = c["H"][i, j]
    assert set(mine) <= set(values)
    for name, value in mine.items():
        scale = max(abs(values[name]), c["G"][0, 0] if name.startswith("G") else c["H"][1, 1]
                    if name.startswith("H") else abs(values[name]))
        assert abs(value - values[name]) <= 1e-12 * scale, (name, value, values[name])


def test_state_layout_is_flexkanes(flexkane_chains):
    """Joint angle, then the link's modal coordinates, link after link."""
    names = [s.name for s in flexkane_chains[2].eom.q]
    assert names == ["q_joint_1", "q_link_1_1", "q_link_1_2", "q_joint_2", "q_link_2_1", "q_link_2_2"]


@pytest.mark.parametrize("links", [1, 2])
def test_recursive_rhs_agrees_with_flexkane(flexkane_chains, links):
    """dy/dt at 20 random states (during and after the torque pulse) agree to 1e-10 relative."""
    fk = flexkane_chains[links]
    data = ry.chain_data(chain_model(links), links)
    times, states = ry.random_states(links, 2, 20, seed=100 + links)
    assert times.min() < 0.5 < times.max()
    for t, y in zip(times, states):
        ref = fk.rhs(t, y)
        got = ry.yardstick_rhs(data, t, y)
        assert np.all(np.isfinite(got))
        assert np.max(np.abs(got - ref)) <= 1e-10 * np.max(np.abs(ref)), (t, y)
    assert ry.agreement(fk, data, count=5, seed=7) < 1e-10


def test_recursive_rhs_agrees_with_flexkane_three_modes():
    """Any number of modes: one link with 3 modes (the third mode's modal stiffness is about 300
    times the first's, eq. 8.9) agrees to 1e-10 as well."""
    model = chain_model(1, modes=3)
    fk = ry.FlexkaneChain(model)
    assert [s.name for s in fk.eom.q] == ["q_joint_1", "q_link_1_1", "q_link_1_2", "q_link_1_3"]
    assert ry.agreement(fk, ry.chain_data(model, 1, 3), count=20, seed=13) < 1e-10


def test_a_wrong_constant_is_detected(flexkane_chains):
    """The comparison is sharp: the payload's inertia 1 % off shows far above the tolerance."""
    fk = flexkane_chains[2]
    data = ry.chain_data(chain_model(2), 2)
    data.tip[1] *= 1.01
    assert ry.agreement(fk, data, count=5, seed=3) > 1e-6


def _energy(data: ry.ChainData, y: np.ndarray) -> float:
    """Kinetic energy 1/2 u.M.u plus strain energy 1/2 q.H.q [J]; M is left by rhs in ``work``."""
    ry.yardstick_rhs(data, 1.0, y)
    N = data.links * (1 + data.n)
    upper = np.triu(data.work[:N, :N])
    M = upper + np.triu(upper, 1).T
    u = y[N:]
    strain = 0.0
    for k in range(data.links):
        q = y[k * (1 + data.n) + 1:(k + 1) * (1 + data.n)]
        strain += 0.5 * q @ data.H[k] @ q
    return 0.5 * u @ M @ u + strain


@pytest.mark.parametrize("links", [1, 3])
def test_energy_is_conserved_without_torques(links):
    """After the torque pulse (t > t1) the chain is conservative: the yardstick alone keeps
    kinetic plus strain energy to 1e-8 over 0.05 s (physics, independent of flexkane)."""
    data = ry.chain_data(chain_model(links), links)
    _, states = ry.random_states(links, 2, 1, seed=5)
    y0 = states[0]
    sol = solve_ivp(lambda t, y: ry.yardstick_rhs(data, t, y), (0.6, 0.65), y0, method="DOP853",
                    rtol=1e-12, atol=1e-12, dense_output=False)
    assert sol.success
    e0, e1 = _energy(data, y0), _energy(data, sol.y[:, -1])
    assert abs(e1 - e0) <= 1e-8 * e0
    assert np.max(np.abs(sol.y[:, -1] - y0)) > 1e-3   # it did move


@pytest.mark.slow
def test_recursive_rhs_agrees_with_flexkane_three_links():
    """The same for three links (flexkane derives and compiles it in about 5-35 s)."""
    fk = ry.FlexkaneChain(chain_model(3))
    assert ry.agreement(fk, ry.chain_data(chain_model(3), 3), count=20, seed=11) < 1e-10

