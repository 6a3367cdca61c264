"""Orientations in space, numerically: direction cosines and Euler parameters (NumPy).

The orientation of a frame B relative to a frame A is described by

* its direction-cosine matrix ``C`` (3 x 3), whose columns are B's unit vectors in A's axes, so that
  ``v_A = C v_B`` (Kane and Levinson's ``A C B``);
* its Euler parameters ``e = (e0, e1, e2, e3)``, a unit quaternion: a turn by ``a`` about the unit
  vector ``n`` has ``e0 = cos(a/2)`` and ``(e1, e2, e3) = sin(a/2) n``.

A model gives a constant orientation (:class:`~flexkane.model.parts.Orientation`) as a turn about an
axis, ``{ axis = [ax, ay, az], angle = a }`` (Rodrigues' formula), or as successive body-fixed turns,
``{ sequence = "zyx", angles = [a1, a2, a3] }`` (about z, then about the new y, then about the newest
x: ``C = Cz(a1) Cy(a2) Cx(a3)``). The same conventions hold in the derivation's symbolic rotations
(:mod:`flexkane.kane.rotation`); this module serves what needs numbers (validation, initial
conditions, drawings).
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import ModelError
from .file_layout import ORIENTATION_FORMS, orientation_from_table
from .parts import SEQUENCE_AXES

__all__ = ["unit_vector", "axis_angle_matrix", "sequence_matrix", "sequence_matrices", "quaternion_matrix",
           "quaternion_matrices", "matrix_quaternion",
           "normalized", "orientation_matrix", "orientation_quaternion", "vector3"]

_UNIT = {"x": 0, "y": 1, "z": 2}


def axis_angle_matrix(axis, angle: float) -> np.ndarray:
    """Direction cosines of a turn by ``angle`` [rad] about ``axis`` (normalized here) [-].

    Parameters
    ----------
    axis : array_like, shape (3,)
        The axis, components in A and B alike; not zero.
    angle : float
        [rad]

    Returns
    -------
    ndarray, shape (3, 3)
        ``C = cos(a) 1 + (1 - cos(a)) n n^T + sin(a) [n x]``.
    """
    return _turns(unit_vector(axis), np.array([float(angle)]))[0]


def _turns(n: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """Rodrigues' formula for a unit axis ``n`` and N angles [rad]: shape (N, 3, 3)."""
    c, s = np.cos(angles)[:, None, None], np.sin(angles)[:, None, None]
    cross = np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])
    return c * np.eye(3) + (1.0 - c) * np.outer(n, n) + s * cross


def unit_vector(v) -> np.ndarray:
    """``v / |v|`` for a finite 3-vector, without overflow or underflow whatever its size [-].

    Raises
    ------
    ValueError
        If ``v`` is zero.
    """
    v = np.asarray(v, dtype=float)
    largest = float(np.max(np.abs(v)))
    if not largest > 0:
        raise ValueError("a zero vector has no direction")
    v = v / largest
    return v / np.linalg.norm(v)


def sequence_matrix(sequence: str, angles) -> np.ndarray:
    """Direction cosines of successive body-fixed turns (``"zyx"``: z, then new y, then newest x).

    Parameters
    ----------
    sequence : str
        1 to 3 letters among x, y, z.
    angles : array_like, shape (len(sequence),)
        [rad]

    Returns
    -------
    ndarray, shape (3, 3)
    """
    return sequence_matrices(sequence, np.asarray(angles, dtype=float)[None, :])[0]


def sequence_matrices(sequence: str, angles) -> np.ndarray:
    """:func:`sequence_matrix` for N sets of angles at once.

    Parameters
    ----------
    sequence : str
        1 to 3 letters among x, y, z.
    angles : array_like, shape (N, len(sequence))
        [rad]

    Returns
    -------
    ndarray, shape (N, 3, 3)
    """
    angles = np.asarray(angles, dtype=float)
    if angles.ndim != 2 or angles.shape[1] != len(sequence):
        raise ValueError(f"angles of shape (N, {len(sequence)}) for sequence {sequence!r}, got {angles.shape}")
    out = np.broadcast_to(np.eye(3), (len(angles), 3, 3))
    for k, letter in enumerate(sequence):
        axis = np.zeros(3)
        axis[_UNIT[letter]] = 1.0
        out = out @ _turns(axis, angles[:, k])
    return out


def quaternion_matrix(e) -> np.ndarray:
    """Direction cosines of a rotation with Euler parameters ``e = (e0, e1, e2, e3)`` (unit) [-].

    Returns
    -------
    ndarray, shape (3, 3)
    """
    return quaternion_matrices(np.asarray(e, dtype=float)[None, :])[0]


def quaternion_matrices(e) -> np.ndarray:
    """:func:`quaternion_matrix` for N sets of Euler parameters at once.

    Parameters
    ----------
    e : array_like, shape (N, 4)
        Unit quaternions ``(e0, e1, e2, e3)``, one per row.

    Returns
    -------
    ndarray, shape (N, 3, 3)
    """
    e = np.asarray(e, dtype=float)
    e0, e1, e2, e3 = e[:, 0], e[:, 1], e[:, 2], e[:, 3]
    out = np.empty((len(e), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 0, 2] = (e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3, 2 * (e1 * e2 - e0 * e3),
                                                2 * (e1 * e3 + e0 * e2))
    out[:, 1, 0], out[:, 1, 1], out[:, 1, 2] = (2 * (e1 * e2 + e0 * e3), e0 * e0 - e1 * e1 + e2 * e2 - e3 * e3,
                                                2 * (e2 * e3 - e0 * e1))
    out[:, 2, 0], out[:, 2, 1], out[:, 2, 2] = (2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1),
                                                e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3)
    return out


def matrix_quaternion(C) -> np.ndarray:
    """Euler parameters of a direction-cosine matrix, with ``e0 >= 0`` (Shepperd's method, stable
    for every rotation).

    Parameters
    ----------
    C : array_like, shape (3, 3)
        A proper orthogonal matrix.

    Returns
    -------
    ndarray, shape (4,)
        ``(e0, e1, e2, e3)``, unit norm.
    """
    C = np.asarray(C, dtype=float)
    trace = C[0, 0] + C[1, 1] + C[2, 2]
    candidates = (trace, C[0, 0], C[1, 1], C[2, 2])
    k = int(np.argmax(candidates))
    if k == 0:
        e0 = 0.5 * math.sqrt(max(1.0 + trace, 0.0))
        e = np.array([e0, (C[2, 1] - C[1, 2]) / (4 * e0), (C[0, 2] - C[2, 0]) / (4 * e0),
                      (C[1, 0] - C[0, 1]) / (4 * e0)])
    else:
        i = k - 1
        j, m = (i + 1) % 3, (i + 2) % 3
        ei = 0.5 * math.sqrt(max(1.0 + 2 * C[i, i] - trace, 0.0))
        e = np.empty(4)
        e[0] = (C[m, j] - C[j, m]) / (4 * ei)
        e[1 + i] = ei
        e[1 + j] = (C[j, i] + C[i, j]) / (4 * ei)
        e[1 + m] = (C[m, i] + C[i, m]) / (4 * ei)
    if e[0] < 0:
        e = -e
    return e / np.linalg.norm(e)


def normalized(e) -> tuple[np.ndarray, float]:
    """Euler parameters scaled to unit norm, and the norm they had.

    Raises
    ------
    ValueError
        If all four are zero (no rotation has them).
    """
    e = np.asarray(e, dtype=float)
    largest = float(np.max(np.abs(e)))
    if not largest > 0:
        raise ValueError("four zero Euler parameters")
    norm = largest * float(np.linalg.norm(e / largest))
    return e / norm if math.isfinite(norm) else (e / largest) / np.linalg.norm(e / largest), norm


def _is_value(value) -> bool:
    return not isinstance(value, bool) and isinstance(value, (numbers.Real, str))


def orientation_matrix(spec, path: str, fields) -> np.ndarray:
    """The direction cosines of an orientation with numbers from the model's parameters; checks it.

    Parameters
    ----------
    spec : Orientation, dict or None
        The orientation (None: the identity).
    path : str
        Its key path (``joints.shoulder.orientation``), named by every message.
    fields : FieldValues
        The model's evaluator of field values (:class:`~flexkane.model.field_values.FieldValues`).

    Returns
    -------
    ndarray, shape (3, 3)

    Raises
    ------
    ModelError
        Naming the key: both forms or neither, an axis that is not three values or is zero, a
        sequence that is not 1 to 3 letters among x, y, z, a count of angles that does not match it,
        a value that is not a finite number or expression of the parameters.
    """
    if spec is None:
        return np.eye(3)
    spec = orientation_from_table(spec, path)
    by_axis = spec.axis is not None or spec.angle is not None
    by_sequence = spec.sequence is not None or spec.angles is not None
    if by_axis == by_sequence:
        raise ModelError(path, ORIENTATION_FORMS, "both forms" if by_axis else "an empty table")
    if by_axis:
        if spec.axis is None or spec.angle is None:
            missing = "axis" if spec.axis is None else "angle"
            raise ModelError(f"{path}.{missing}", "the axis [ax, ay, az] and the angle [rad] of the turn", None,
                             "missing", show_given=False)
        axis = vector3(spec.axis, f"{path}.axis", fields, "axis components", "-")
        if not np.any(axis != 0):
            raise ModelError(f"{path}.axis", "a non-zero axis [ax, ay, az]", list(spec.axis))
        angle = _number(spec.angle, f"{path}.angle", fields, "angle of the turn", "rad")
        return axis_angle_matrix(axis, angle)
    sequence, angles = spec.sequence, spec.angles
    if not (isinstance(sequence, str) and 1 <= len(sequence) <= 3 and all(c in SEQUENCE_AXES for c in sequence)):
        raise ModelError(f"{path}.sequence", "1 to 3 letters among x, y, z naming body-fixed axes (e.g. \"zyx\")",
                         sequence)
    if not isinstance(angles, (list, tuple)) or len(angles) != len(sequence):
        raise ModelError(f"{path}.angles", f"a list of {len(sequence)} angle(s) [rad], one per letter of "
                         f"sequence {sequence!r}", angles)
    values = [_number(a, f"{path}.angles[{k}]", fields, "angle", "rad") for k, a in enumerate(angles)]
    return sequence_matrix(sequence, values)


def orientation_quaternion(spec, path: str, fields) -> np.ndarray:
    """The Euler parameters (e0 >= 0, unit norm) of an orientation; see :func:`orientation_matrix`.

    Returns
    -------
    ndarray, shape (4,)
    """
    return matrix_quaternion(orientation_matrix(spec, path, fields))


def _number(value, path: str, fields, what: str, unit: str) -> float:
    if not _is_value(value):
        raise ModelError(path, f"a number or an expression string ({what} [{unit}])", value)
    return fields.value(value, path, what=f"{what} [{unit}]")


def vector3(value, path: str, fields, what: str, unit: str, **names: float) -> np.ndarray:
    """A three-component field as numbers [its unit].

    Raises
    ------
    ModelError
        If it is not a list of three numbers or expressions (``path[k]`` names a bad component).
    """
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise ModelError(path, f"three values [x, y, z] ({what} [{unit}])", value)
    out = np.empty(3)
    for k, component in enumerate(value):
        if not _is_value(component):
            raise ModelError(f"{path}[{k}]", f"a number or an expression string ({what} [{unit}])", component)
        out[k] = fields.value(component, f"{path}[{k}]", what=f"{what} [{unit}]", **names)
    return out
