"""The Argyris L-frame (examples/argyris-frame.toml): its first two frequencies against a finite-element
model of the same Euler-Bernoulli beams.

The oracle is written here, independent of flexkane: a 3D frame of two-node elements, Hermite cubics
for the bending in the two principal planes, linear shape functions for the twist and the stretch,
consistent mass matrices, assembled in the ground frame and clamped at the first leg's root. Its
frequencies converge as h^4 with the element length: 16 and 32 elements per leg agree to 1.2e-7,
32 and 64 to 1e-8.

flexkane's frequencies come from its linearization about the equilibrium (the out-of-plane motion of
the frame: bending about the legs' weak axes and twist). With the static correction shapes at the
legs' tips (the default) 4 functions per leg and direction are within 0.01 % of the finite
elements; the clamped-free modes alone (``static_corrections = false``) converge as 1/n and are
0.3 % and 0.4 % off with 10, the most the 40 elastic coordinates of a model admit.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from flexkane.analysis import Linearization, modal_analysis
from flexkane.model import loads_model

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "argyris-frame.toml"

# the example's data, in SI units
LENGTH, WIDTH, THICKNESS = 0.24, 0.03, 0.003
E, NU, DENSITY = 71.24e9, 0.31, 5000.0
AREA = WIDTH * THICKNESS
I_WEAK, I_STRONG = WIDTH * THICKNESS ** 3 / 12, THICKNESS * WIDTH ** 3 / 12
TORSION_CONSTANT = WIDTH * THICKNESS ** 3 / 3 * (1 - 0.630 * THICKNESS / WIDTH)
SHEAR_MODULUS = E / (2 * (1 + NU))


def frame_element(length: float) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and consistent mass of a frame element in its own axes, shape (12, 12) each; the
    degrees of freedom of a node are u, v, w, rx, ry, rz (v' = rz, w' = -ry)."""
    stiffness, mass = np.zeros((12, 12)), np.zeros((12, 12))

    def add(dofs, k, m):
        stiffness[np.ix_(dofs, dofs)] += k
        mass[np.ix_(dofs, dofs)] += m

    bar_k = np.array([[1.0, -1.0], [-1.0, 1.0]]) / length
    bar_m = length / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])
    add([0, 6], E * AREA * bar_k, DENSITY * AREA * bar_m)
    add([3, 9], SHEAR_MODULUS * TORSION_CONSTANT * bar_k, DENSITY * (I_WEAK + I_STRONG) * bar_m)
    h = length
    hermite_k = np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                          [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]]) / h ** 3
    hermite_m = DENSITY * AREA * h / 420 * np.array(
        [[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
         [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    add([1, 5, 7, 11], E * I_STRONG * hermite_k, hermite_m)       # v in the frame's plane
    sign = np.diag([1.0, -1.0, 1.0, -1.0])                        # w' = -ry
    add([2, 4, 8, 10], E * I_WEAK * sign @ hermite_k @ sign, sign @ hermite_m @ sign)
    return stiffness, mass


def finite_element_frequencies(elements: int, count: int = 2) -> np.ndarray:
    """The lowest ``count`` natural frequencies [Hz] of the frame with ``elements`` per leg."""
    nodes = [np.array([LENGTH * i / elements, 0.0, 0.0]) for i in range(elements + 1)]
    nodes += [np.array([LENGTH, LENGTH * i / elements, 0.0]) for i in range(1, elements + 1)]
    size = 6 * len(nodes)
    stiffness, mass = np.zeros((size, size)), np.zeros((size, size))
    for a in range(2 * elements):
        chord = nodes[a + 1] - nodes[a]
        length = np.linalg.norm(chord)
        ex = chord / length
        ez = np.array([0.0, 0.0, 1.0])                 # the weak axis' normal: out of the plane
        rotation = np.kron(np.eye(4), np.vstack([ex, np.cross(ez, ex), ez]))
        k, m = frame_element(length)
        dofs = np.r_[6 * a:6 * a + 12]
        stiffness[np.ix_(dofs, dofs)] += rotation.T @ k @ rotation
        mass[np.ix_(dofs, dofs)] += rotation.T @ m @ rotation
    free = np.arange(6, size)                          # the first leg's root clamped
    k, m = stiffness[np.ix_(free, free)], mass[np.ix_(free, free)]
    # the largest 1/omega^2 of (M, K): accurate where the stiff axial terms would swamp omega^2 of (K, M)
    inverse = scipy.linalg.eigh(m, k, eigvals_only=True, subset_by_index=[len(free) - count, len(free) - 1])
    return np.sort(1.0 / np.sqrt(inverse)) / (2 * np.pi)


@pytest.fixture(scope="module")
def finite_elements() -> np.ndarray:
    coarse, fine = finite_element_frequencies(16), finite_element_frequencies(32)
    np.testing.assert_allclose(coarse, fine, rtol=1e-6)     # converged with the number of elements (h^4)
    return fine


def flexkane_frequencies(functions: int, corrections: bool = True) -> np.ndarray:
    """The first two frequencies [Hz] of the example with ``functions`` per leg and direction."""
    text = EXAMPLE.read_text()
    text = re.sub(r"^(n_modes_z|n_torsion) = \d+$", rf"\1 = {functions}", text, flags=re.MULTILINE)
    if not corrections:
        text = re.sub(r"^(\[beams\.leg\d\])$", r"\1\nstatic_corrections = false", text, flags=re.MULTILINE)
    modal = modal_analysis(Linearization(loads_model(text), about="equilibrium").at(outputs=False))
    omegas = sorted(m.omega for m in modal.modes if m.kind == "oscillatory")
    return np.array(omegas[:2]) / (2 * np.pi)


def test_finite_element_frame_has_the_textbook_cantilever_frequency_per_leg():
    """The oracle's elements, checked on one leg alone: a clamped 0.24 m leg bending about its weak
    axis has (1.8751^2 / L^2) sqrt(EI / rho A) (eq. 8.7)."""
    k, m = frame_element(LENGTH / 8)
    size = 6 * 9
    stiffness, mass = np.zeros((size, size)), np.zeros((size, size))
    for a in range(8):
        dofs = np.r_[6 * a:6 * a + 12]
        stiffness[np.ix_(dofs, dofs)] += k
        mass[np.ix_(dofs, dofs)] += m
    w = [2, 4]                                            # w and ry of every node but the root
    dofs = np.array([6 * n + d for n in range(1, 9) for d in w])
    omega2 = scipy.linalg.eigh(stiffness[np.ix_(dofs, dofs)], mass[np.ix_(dofs, dofs)], eigvals_only=True)[0]
    expected = 1.8751040687 ** 2 / LENGTH ** 2 * np.sqrt(E * I_WEAK / (DENSITY * AREA))
    assert np.sqrt(omega2) == pytest.approx(expected, rel=1e-5)   # 8 elements: 2e-6 (h^4)


def test_first_two_frequencies_within_a_thousandth_of_finite_elements(finite_elements):
    frequencies = flexkane_frequencies(4)                  # the example's 4 functions per leg and direction
    error = frequencies / finite_elements - 1.0
    assert np.all(np.abs(error) < 1e-4), (frequencies, finite_elements)
    assert np.all(error > 0)                               # a Ritz basis: upper bounds


@pytest.mark.slow
def test_static_corrections_converge_where_the_modes_alone_stop_at_four_thousandths(finite_elements):
    """Convergence with the number of functions per leg and direction (measured: with the
    corrections 2: +0.004 %, +0.061 %; 3: +0.003 %, +0.045 %; 4: +0.0003 %, +0.006 %; 10: +1e-6 %,
    +2e-5 %; modes alone 1: +3.8 %, +4.3 % (one function is the family's first with or without the
    corrections); 4: +0.81 %, +0.99 %; 10: +0.32 %, +0.39 %, the error falling as 1/n)."""
    corrected = {n: flexkane_frequencies(n) / finite_elements - 1 for n in (2, 3, 4, 6, 10)}
    alone = {n: flexkane_frequencies(n, corrections=False) / finite_elements - 1 for n in (5, 10)}
    for n in (2, 3, 4, 6, 10):
        assert np.all(0 < corrected[n]) and np.all(corrected[n] < 1e-3), (n, corrected[n])
    assert np.all(corrected[10] < 1e-6)
    assert np.all(np.diff([corrected[n] for n in sorted(corrected)], axis=0) <= 0)   # never worse with more
    assert np.all(alone[10] > 3e-3)
    # 1/n: doubling the functions halves the error of the modes alone
    np.testing.assert_allclose(alone[10] / alone[5], 0.5, rtol=0.2)
