"""Eigen-analysis of a linear model: natural frequencies, damping ratios, mode shapes of the chain.

The eigenvalues lambda of the state matrix A (:meth:`LinearModel.state_space`) are sorted into

* **rigid-body modes**: the directions dq with ``K dq = 0`` (null space of the stiffness, found
  by singular values below ``1e-9`` of the largest): the chain moves without deforming and nothing
  pulls it back. They give zero eigenvalues of A (``|lambda| <= 1e-6 max |lambda|``), reported
  with frequency 0;
* **oscillatory modes**: conjugate pairs, one per mode, with natural frequency
  ``omega_n = |lambda|`` [rad/s], ``f = omega_n / (2 pi)`` [Hz], damping ratio
  ``zeta = -Re(lambda) / |lambda|`` and damped frequency ``Im(lambda)`` (negative zeta: flutter;
  ``|zeta| < 1e-10`` is taken as the rounding error of an undamped mode and set to 0);
* **real modes**: real eigenvalues, ``lambda < 0`` overdamped (``zeta = 1``), ``lambda > 0``
  divergent, i.e. statically unstable (``zeta = -1``), as a rotating beam without geometric
  stiffening beyond its first bending frequency.

A mode shape is the dq part of the eigenvector (or the null vector), scaled so that its largest
component is 1 (real for undamped modes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from .linear_model import LinearModel

__all__ = ["Mode", "ModalAnalysis", "modal_analysis", "RIGID_TOLERANCE"]

#: Relative size of the singular values of K and of the eigenvalues of A taken as zero.
RIGID_TOLERANCE = (1e-9, 1e-6)
#: Damping ratios below this are rounding errors of undamped modes and are set to 0.
_UNDAMPED = 1e-10


@dataclass(frozen=True)
class Mode:
    """One mode of a linear model.

    Attributes
    ----------
    kind : str
        ``rigid``, ``oscillatory``, ``overdamped`` or ``divergent``.
    eigenvalue : complex
        lambda [1/s] (0 for rigid-body modes).
    shape : numpy.ndarray
        dq, shape (n,), largest component 1 (real part of ``shape_complex``).
    shape_complex : numpy.ndarray
        The complex dq of the eigenvector, shape (n,), same scaling.
    """

    kind: str
    eigenvalue: complex
    shape: np.ndarray
    shape_complex: np.ndarray

    @property
    def omega(self) -> float:
        """Natural frequency ``|lambda|`` [rad/s] (0 for rigid-body modes)."""
        return float(abs(self.eigenvalue))

    @property
    def frequency(self) -> float:
        """Natural frequency [Hz]."""
        return self.omega / (2.0 * math.pi)

    @property
    def damping_ratio(self) -> float:
        """``zeta = -Re(lambda) / |lambda|`` [-] (NaN for rigid-body modes)."""
        return float(-self.eigenvalue.real / abs(self.eigenvalue)) if self.eigenvalue != 0 else math.nan

    @property
    def damped_frequency(self) -> float:
        """``Im(lambda)`` [rad/s]."""
        return float(abs(self.eigenvalue.imag))

    @property
    def stable(self) -> bool:
        """Whether the mode does not grow (``Re(lambda) <= 0``, up to rounding)."""
        return self.kind != "divergent" and not (self.kind == "oscillatory" and self.damping_ratio < -1e-9)


def _normalise(vector: np.ndarray) -> np.ndarray:
    k = int(np.argmax(np.abs(vector)))
    if abs(vector[k]) == 0:
        return vector.astype(complex)
    return vector / vector[k]


def _null_space(K: np.ndarray) -> np.ndarray:
    """Orthonormal basis of the null space of K, shape (n, r)."""
    n = K.shape[0]
    if n == 0:
        return np.zeros((0, 0))
    _, s, vh = scipy.linalg.svd(K)
    largest = s[0] if s.size else 0.0
    rank = int(np.sum(s > RIGID_TOLERANCE[0] * largest)) if largest > 0 else 0
    return vh[rank:].conj().T


class ModalAnalysis:
    """Modes of a linear model (module docstring).

    Parameters
    ----------
    linear : LinearModel

    Attributes
    ----------
    linear : LinearModel
    eigenvalues : numpy.ndarray
        All eigenvalues of A, shape (2n,) [1/s].
    modes : list of Mode
        Rigid-body modes first, then the others by increasing natural frequency.
    """

    def __init__(self, linear: LinearModel):
        self.linear = linear
        n = linear.n
        A, _ = linear.state_space()
        if n == 0:
            self.eigenvalues = np.zeros(0, dtype=complex)
            self.modes = []
            return
        values, vectors = scipy.linalg.eig(A)
        self.eigenvalues = values
        modes: list[Mode] = []
        null = _null_space(linear.K)
        for k in range(null.shape[1]):
            shape = _normalise(null[:, k].astype(complex))
            modes.append(Mode("rigid", 0j, shape.real, shape))
        scale = float(np.max(np.abs(values), initial=0.0))
        zero = np.abs(values) <= RIGID_TOLERANCE[1] * max(scale, 1e-300)
        others = []
        for value, vector, is_zero in zip(values, vectors.T, zero):
            if is_zero:
                continue
            if abs(value.imag) > 1e-9 * abs(value):
                if value.imag < 0:
                    continue
                kind = "oscillatory"
                if abs(value.real) <= _UNDAMPED * abs(value):  # rounding of an undamped mode
                    value = complex(0.0, value.imag)
            else:
                value = complex(value.real, 0.0)
                kind = "divergent" if value.real > 0 else "overdamped"
            shape = _normalise(vector[:n])
            others.append(Mode(kind, complex(value), shape.real, shape))
        others.sort(key=lambda m: (m.omega, m.eigenvalue.real))
        self.modes = modes + others

    # ------------------------------------------------------------------ selections
    @property
    def rigid(self) -> list[Mode]:
        """Rigid-body modes."""
        return [m for m in self.modes if m.kind == "rigid"]

    @property
    def elastic(self) -> list[Mode]:
        """Every mode that is not a rigid-body mode, by increasing natural frequency."""
        return [m for m in self.modes if m.kind != "rigid"]

    @property
    def frequencies(self) -> np.ndarray:
        """Natural frequencies of the oscillatory modes [rad/s], ascending, shape (count,)."""
        return np.array([m.omega for m in self.modes if m.kind == "oscillatory"])

    @property
    def stable(self) -> bool:
        """Whether no mode grows."""
        return all(m.stable for m in self.modes)

    def max_growth_rate(self) -> float:
        """Largest real part of the eigenvalues other than the rigid-body zeros [1/s] (0 if none)."""
        rates = [m.eigenvalue.real for m in self.elastic]
        return float(max(rates, default=0.0))

    # ------------------------------------------------------------------ reports
    HEADER = ("mode", "kind", "omega_n [rad/s]", "f_n [Hz]", "zeta [-]", "Re(lambda) [1/s]",
              "Im(lambda) [rad/s]")

    def rows(self) -> list[tuple]:
        """One row per mode: (number, kind, omega_n, f_n, zeta, Re lambda, Im lambda)."""
        return [(k + 1, m.kind, m.omega, m.frequency, m.damping_ratio, m.eigenvalue.real,
                 m.damped_frequency) for k, m in enumerate(self.modes)]

    def table(self) -> str:
        """The modes as a text table, one line per mode."""
        widths = (4, 11, 16, 14, 11, 17, 18)
        lines = ["  ".join(f"{h:>{w}}" for h, w in zip(self.HEADER, widths))]
        for row in self.rows():
            cells = [f"{row[0]:>{widths[0]}}", f"{row[1]:>{widths[1]}}"]
            for value, w in zip(row[2:], widths[2:]):
                cells.append(f"{value + 0.0:>{w}.10g}" if not math.isnan(value) else f"{'-':>{w}}")
            lines.append("  ".join(cells))
        return "\n".join(lines)

    def csv_text(self) -> str:
        """The modes as CSV, with the mode shapes (one column per coordinate)."""
        names = self.linear.coordinates
        lines = [",".join(list(self.HEADER) + [f"shape {c}" for c in names])]
        for row, mode in zip(self.rows(), self.modes):
            cells = [str(row[0]), row[1]] + [repr(float(v) + 0.0) for v in row[2:]]
            cells += [repr(float(v)) for v in mode.shape]
            lines.append(",".join(cells))
        return "\n".join(lines) + "\n"


def modal_analysis(linear: LinearModel) -> ModalAnalysis:
    """Eigen-analysis of a linear model (module docstring).

    Parameters
    ----------
    linear : LinearModel

    Returns
    -------
    ModalAnalysis
    """
    return ModalAnalysis(linear)
