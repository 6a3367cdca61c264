"""Eigen-analysis of a linear model: natural frequencies, damping ratios, mode shapes of the chain.

The eigenvalues lambda of the state matrix A (:meth:`LinearModel.state_space`) are sorted into

* **rigid-body modes**: the states that stay put, ``A x = 0`` (the null space of the state matrix,
  i.e. of ``[[V, W, 0], [K, C, K_z], [Z_q, Z_u, Z_z]]`` with each block row scaled to its largest
  entry, found by singular values below ``1e-9`` of the largest): the chain moves without
  deforming and nothing pulls it back. Without a steady spin (``V = 0``, W invertible) these are
  the directions ``K dq = 0`` (the null space of the stiffness); about a steady spin they are fewer:
  a body spinning freely keeps its turn about the spin axis (and its shift along it) as rigid-body
  modes, while its turns about the other axes, seen from the spinning frame, are oscillations at
  the spin rate. Rigid-body modes give zero eigenvalues of A (``|lambda| <= 1e-6 max |lambda|``),
  reported with frequency 0;
* **oscillatory modes**: conjugate pairs, one per mode, with natural frequency
  ``omega_n = |lambda|`` [rad/s], ``f = omega_n / (2 pi)`` [Hz], damping ratio
  ``zeta = -Re(lambda) / |lambda|`` and damped frequency ``Im(lambda)`` (negative zeta: flutter;
  ``|zeta| < 1e-10`` is taken as the rounding error of an undamped mode and set to 0);
* **real modes**: real eigenvalues, ``lambda < 0`` overdamped (``zeta = 1``), ``lambda > 0``
  divergent, i.e. statically unstable (``zeta = -1``), as a rotating beam without geometric
  stiffening beyond its first bending frequency.

A mode shape is the dq part of the eigenvector (or the null vector), scaled so that its largest
component is 1 (real for undamped modes). Each mode is labelled by its dominant motion (``flap``,
``lag``, ``torsion``, ``bending``, ``axial``, ``rotation about x of bus``, ``joint <name>``,
:mod:`flexkane.analysis.participation`) and its rank among the modes of that motion (``flap 1``,
``flap 2``; the two real eigenvalues of a statically unstable or overdamped mode share one label),
with the share of that motion in the mode's kinetic energy (the participations of its families
summed, as written in ``modes.csv``). A rigid-body mode, which does not move, is weighed by the
speeds ``du = W^-1 dq`` that move the chain along its shape (by dq itself when W is singular), and
the rigid-body modes are the basis of their null space whose members each move one speed alone
(a free body's translations along, and turns about, its own axes), chosen by the speeds they move
most independently.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

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
    label : str
        Dominant motion and rank among the modes of that motion (``flap 1``, ``torsion 1``,
        ``joint hub 1``; :mod:`flexkane.analysis.participation`); '' when the linear model does not
        know its chain.
    participation : dict of str to float
        Share of each family of motion in the mode's kinetic energy (summing to 1).
    share : float
        Share of the labelled motion in the mode's kinetic energy [-]: the participation of its
        family, or of all the families of its kind (``bending z`` of two beams); 0 when unlabelled.
    """

    kind: str
    eigenvalue: complex
    shape: np.ndarray
    shape_complex: np.ndarray
    label: str = ""
    participation: dict = field(default_factory=dict)
    share: float = 0.0

    @property
    def motion(self) -> str:
        """The dominant motion (the label without its rank)."""
        return self.label.rsplit(" ", 1)[0] if self.label else ""

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
    """Orthonormal basis of the null space of K, shape (columns, r)."""
    n = K.shape[1]
    if n == 0:
        return np.zeros((0, 0))
    _, s, vh = scipy.linalg.svd(K)
    largest = s[0] if s.size else 0.0
    rank = int(np.sum(s > RIGID_TOLERANCE[0] * largest)) if largest > 0 else 0
    return vh[rank:].conj().T


def _rest_states(linear: LinearModel) -> np.ndarray:
    """The states that stay put (module docstring): basis of the null space of the state matrix,
    shape (2n + nz, r), from its block rows ``[V, W, 0]``, ``[K, C, K_z]`` (M times A's second
    block row) and ``[Z_q, Z_u, Z_z]``, each scaled by its largest entry."""
    n, nz = linear.n, linear.nz
    K_z = np.asarray(linear.K_z if nz else np.zeros((n, 0)), dtype=float).reshape(n, nz)
    blocks = [np.hstack([linear.V, linear.W, np.zeros((n, nz))]), np.hstack([linear.K, linear.C, K_z])]
    if nz:
        blocks.append(np.asarray(linear.Z_x, dtype=float).reshape(nz, 2 * n + nz))
    scaled = [b / max(float(np.max(np.abs(b), initial=0.0)), 1e-300) for b in blocks]
    return _null_space(np.vstack(scaled))


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
        modes: list[tuple] = []       # (mode, speed part of its eigenvector or None)
        null = _rest_states(linear)[:n]
        if null.shape[1]:       # the dq parts, orthonormal
            u, s, _ = scipy.linalg.svd(null, full_matrices=False)
            null = u[:, :int(np.sum(s > RIGID_TOLERANCE[0] * s[0]))] if s[0] > 0 else null[:, :0]
            null = _one_speed_each(linear, null)
        for k in range(null.shape[1]):
            shape = _normalise(null[:, k].astype(complex))
            modes.append((Mode("rigid", 0j, shape.real, shape), None))
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
            others.append((Mode(kind, complex(value), shape.real, shape), vector[n:2 * n]))
        others.sort(key=lambda pair: (pair[0].omega, pair[0].eigenvalue.real))
        self.modes = _labelled(linear, modes + others)

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

    @property
    def families(self) -> list[str]:
        """The families of motion of the chain, in the order of first appearance in the modes."""
        names: list[str] = []
        for mode in self.modes:
            names += [k for k in mode.participation if k not in names]
        return names

    def rows(self) -> list[tuple]:
        """One row per mode: (number, kind, omega_n, f_n, zeta, Re lambda, Im lambda)."""
        return [(k + 1, m.kind, m.omega, m.frequency, m.damping_ratio, m.eigenvalue.real,
                 m.damped_frequency) for k, m in enumerate(self.modes)]

    def table(self) -> str:
        """The modes as a text table, one line per mode."""
        widths = (4, 11, 16, 14, 11, 17, 18)
        labelled = any(m.label for m in self.modes)
        lines = ["  ".join(f"{h:>{w}}" for h, w in zip(self.HEADER, widths)) + ("  motion" if labelled else "")]
        for row, mode in zip(self.rows(), self.modes):
            cells = [f"{row[0]:>{widths[0]}}", f"{row[1]:>{widths[1]}}"]
            for value, w in zip(row[2:], widths[2:]):
                cells.append(f"{value + 0.0:>{w}.10g}" if not math.isnan(value) else f"{'-':>{w}}")
            if labelled:
                cells.append(f"{mode.label} ({100 * mode.share:.0f} %)")
            lines.append("  ".join(cells))
        return "\n".join(lines)

    def csv_text(self) -> str:
        """The modes as CSV: the table, the label (dominant motion and rank), the share of that
        motion [-], the participation of each family of motion [-] and the mode shapes (one column
        per coordinate)."""
        names = self.linear.coordinates
        families = self.families
        lines = [",".join(list(self.HEADER) + ["motion", "motion share [-]"]
                          + [f"participation {f}" for f in families] + [f"shape {c}" for c in names])]
        for row, mode in zip(self.rows(), self.modes):
            cells = [str(row[0]), row[1]] + [repr(float(v) + 0.0) for v in row[2:]] + [mode.label]
            cells.append(repr(float(mode.share)))
            cells += [repr(float(mode.participation.get(f, 0.0))) for f in families]
            cells += [repr(float(v)) for v in mode.shape]
            lines.append(",".join(cells))
        return "\n".join(lines) + "\n"


def _one_speed_each(linear: LinearModel, null: np.ndarray) -> np.ndarray:
    """The basis of the rigid-body shapes ``null`` (n, r) whose members each move one speed alone
    (module docstring): the r speeds that the shapes move most independently (QR with column
    pivoting of their speeds ``W^-1 null``), in the speeds' order."""
    speeds = _speeds_along(linear, null)
    _, _, pivots = scipy.linalg.qr(speeds.T, pivoting=True, mode="economic")
    chosen = np.sort(pivots[:null.shape[1]])
    return null @ np.linalg.inv(speeds[chosen, :])


def _speeds_along(linear: LinearModel, shape: np.ndarray) -> np.ndarray:
    """The speeds ``du = W^-1 dq`` that move the chain along shapes dq (n,) or (n, r) (module
    docstring); dq itself when W is singular."""
    W = np.asarray(linear.W, dtype=float)
    if W.shape != (linear.n, linear.n) or not np.all(np.isfinite(W)) or np.linalg.cond(W) > 1e12:
        return shape
    return scipy.linalg.solve(W, shape)


def _labelled(linear: LinearModel, modes: list) -> list:
    """The modes of ``(mode, du)`` pairs with their participations, labels and shares (module
    docstring), ``du`` the speed part of the eigenvector (``W^-1 dq`` of the shape when it is None or
    zero)."""
    from .participation import motion_families

    families = motion_families(linear)
    ranks: dict = {}
    pending: dict = {}       # the motion of a real mode whose partner may follow
    out = []
    for mode, speeds in modes:
        if families is None:
            out.append(mode)
            continue
        moving = speeds is not None and np.any(np.abs(speeds) > 0)
        vector = speeds if moving else _speeds_along(linear, mode.shape_complex)
        share = families.participation(linear.M, vector)
        motion = families.dominant(share)
        if mode.kind in ("overdamped", "divergent") and motion in pending:
            rank = pending.pop(motion)
        else:
            rank = ranks[motion] = ranks.get(motion, 0) + 1
            if mode.kind in ("overdamped", "divergent"):
                pending[motion] = rank
        out.append(replace(mode, label=f"{motion} {rank}" if motion else "", participation=share,
                           share=families.share(share, motion)))
    return out


def modal_analysis(linear: LinearModel) -> ModalAnalysis:
    """Eigen-analysis of a linear model (module docstring).

    Parameters
    ----------
    linear : LinearModel

    Returns
    -------
    ModalAnalysis
    """
    from ..progress import activity

    with activity(f"eigenvalues and mode shapes of {linear.name}"):   # on stderr when long (flexkane.progress)
        return ModalAnalysis(linear)
