"""Orientations: axis-angle turns, body-fixed sequences, direction cosines and Euler parameters agree
with each other and with matrices written out by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexkane.model import Model
from flexkane.model.field_values import FieldValues
from flexkane.model.orientation import (axis_angle_matrix, matrix_quaternion, normalized, orientation_matrix,
                                        orientation_quaternion, quaternion_matrix, sequence_matrix)


def Rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def Ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def Rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def test_turns_about_coordinate_axes_are_the_textbook_matrices():
    for axis, matrix in (((1, 0, 0), Rx), ((0, 1, 0), Ry), ((0, 0, 3.5), Rz)):
        for angle in (0.0, 0.3, -2.0, math.pi):
            assert np.allclose(axis_angle_matrix(axis, angle), matrix(angle), rtol=0, atol=1e-15)


def test_columns_are_the_turned_frame_axes():
    """v_A = C v_B: a quarter turn about z carries B's x axis onto A's y axis."""
    C = axis_angle_matrix((0, 0, 1), math.pi / 2)
    assert np.allclose(C @ [1, 0, 0], [0, 1, 0], atol=1e-15)


def test_body_fixed_sequence_is_the_product_in_order():
    a, b, c = 0.4, -0.7, 1.1
    assert np.allclose(sequence_matrix("zyx", (a, b, c)), Rz(a) @ Ry(b) @ Rx(c), rtol=0, atol=1e-15)
    assert np.allclose(sequence_matrix("xz", (a, b)), Rx(a) @ Rz(b), rtol=0, atol=1e-15)


def test_axis_angle_equals_a_sequence_about_the_same_axis_and_a_rotated_axis():
    """A turn about n equals the conjugation of a turn about z by a rotation that carries z onto n."""
    yaw, pitch = 0.6, 0.9
    R = Rz(yaw) @ Ry(pitch)                    # carries z onto n
    n = R @ [0, 0, 1]
    for angle in (0.2, 2.5):
        assert np.allclose(axis_angle_matrix(n, angle), R @ Rz(angle) @ R.T, rtol=0, atol=1e-14)
    assert np.allclose(axis_angle_matrix((0, 1, 0), 0.8), sequence_matrix("y", [0.8]), rtol=0, atol=1e-15)


def test_quaternion_of_a_turn_is_half_angle_and_axis():
    n = np.array([1.0, 2.0, -2.0]) / 3.0
    e = matrix_quaternion(axis_angle_matrix(n, 1.2))
    assert np.allclose(e, [math.cos(0.6), *(math.sin(0.6) * n)], rtol=0, atol=1e-15)


@pytest.mark.parametrize("seed", range(5))
def test_quaternion_and_direction_cosines_round_trip(seed):
    rng = np.random.default_rng(seed)
    for _ in range(200):
        e = rng.normal(size=4)
        e, _ = normalized(e)
        if e[0] < 0:
            e = -e
        C = quaternion_matrix(e)
        assert np.allclose(C @ C.T, np.eye(3), rtol=0, atol=1e-14)
        assert abs(np.linalg.det(C) - 1.0) < 1e-14
        back = matrix_quaternion(C)
        assert abs(np.linalg.norm(back) - 1.0) < 1e-15
        assert np.allclose(back, e, rtol=0, atol=1e-14)
        assert np.allclose(quaternion_matrix(back), C, rtol=0, atol=1e-14)


@pytest.mark.parametrize("angle", [math.pi, math.pi - 1e-9, 1e-12])
def test_half_turns_and_tiny_turns_are_stable(angle):
    for axis in ((1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)):
        C = axis_angle_matrix(axis, angle)
        e = matrix_quaternion(C)
        assert e[0] >= 0 and abs(np.linalg.norm(e) - 1) < 1e-15
        assert np.allclose(quaternion_matrix(e), C, rtol=0, atol=1e-14)


def test_orientation_fields_with_parameter_expressions():
    fields = FieldValues(Model(parameters={"tilt": 0.25, "k": 2}))
    C = orientation_matrix({"axis": [0, "k", 0], "angle": "2*tilt"}, "joints.j.orientation", fields)
    assert np.allclose(C, Ry(0.5), rtol=0, atol=1e-15)
    e = orientation_quaternion({"sequence": "zyx", "angles": ["tilt", 0, "-tilt"]}, "initial.q_s", fields)
    assert np.allclose(quaternion_matrix(e), Rz(0.25) @ Rx(-0.25), rtol=0, atol=1e-15)
    assert np.array_equal(orientation_matrix(None, "joints.j.orientation", fields), np.eye(3))


def test_many_orientations_at_once_equal_one_at_a_time():
    from flexkane.model.orientation import quaternion_matrices, sequence_matrices

    rng = np.random.default_rng(7)
    angles = rng.uniform(-4, 4, size=(50, 3))
    many = sequence_matrices("zyx", angles)
    assert many.shape == (50, 3, 3)
    for k in range(50):
        assert np.allclose(many[k], Rz(angles[k, 0]) @ Ry(angles[k, 1]) @ Rx(angles[k, 2]), rtol=0, atol=1e-14)
    e = rng.normal(size=(50, 4))
    e /= np.linalg.norm(e, axis=1)[:, None]
    assert np.array_equal(quaternion_matrices(e)[13], quaternion_matrix(e[13]))
    assert np.allclose(quaternion_matrices(e), [quaternion_matrix(row) for row in e], rtol=0, atol=0)
