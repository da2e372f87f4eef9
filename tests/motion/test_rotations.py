"""Rotations against explicit products of axis matrices and known geometry."""

import itertools

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.motion.rotations import axis_rotation, euler_to_matrix, matrix_to_euler, minimal_rotation, unwrap_degrees

ORDERS = ["".join(p) for p in itertools.permutations("XYZ")]


def test_axis_rotation_right_handed():
    # +90 degrees about Z takes +X to +Y; about X takes +Y to +Z; about Y takes +Z to +X
    assert np.allclose(axis_rotation("Z", 90) @ [1, 0, 0], [0, 1, 0])
    assert np.allclose(axis_rotation("X", 90) @ [0, 1, 0], [0, 0, 1])
    assert np.allclose(axis_rotation("Y", 90) @ [0, 0, 1], [1, 0, 0])


@pytest.mark.parametrize("order", ORDERS)
def test_euler_is_product_of_axis_rotations(order):
    a = np.array([30.0, -20.0, 75.0])
    expected = axis_rotation(order[0], a[0]) @ axis_rotation(order[1], a[1]) @ axis_rotation(order[2], a[2])
    assert np.allclose(euler_to_matrix(a, order), expected)


@pytest.mark.parametrize("order", ORDERS)
def test_euler_round_trip(order):
    rng = np.random.default_rng(0)
    angles = rng.uniform([-180, -89, -180], [180, 89, 180], size=(500, 3))
    back = matrix_to_euler(euler_to_matrix(angles, order), order)
    assert np.allclose(back, angles, atol=1e-8)


@pytest.mark.parametrize("order", ORDERS)
def test_gimbal_lock_reconstructs_matrix(order):
    m = euler_to_matrix([40.0, 90.0, 25.0], order)
    assert np.allclose(euler_to_matrix(matrix_to_euler(m, order), order), m, atol=1e-9)


def test_bad_order():
    with pytest.raises(VoxposeError):
        euler_to_matrix([0, 0, 0], "XXY")


def test_minimal_rotation():
    rng = np.random.default_rng(1)
    a = rng.normal(size=(100, 3))
    b = rng.normal(size=(100, 3))
    r = minimal_rotation(a, b)
    an = a / np.linalg.norm(a, axis=1, keepdims=True)
    bn = b / np.linalg.norm(b, axis=1, keepdims=True)
    assert np.allclose(np.einsum("nij,nj->ni", r, an), bn)
    assert np.allclose(np.linalg.det(r), 1.0)
    # the axis is perpendicular to both vectors: it leaves a x b fixed
    axis = np.cross(an, bn)
    assert np.allclose(np.einsum("nij,nj->ni", r, axis), axis)
    # opposite and identical vectors
    assert np.allclose(minimal_rotation([1, 0, 0], [-1, 0, 0]) @ [1, 0, 0], [-1, 0, 0])
    assert np.allclose(minimal_rotation([0, 1, 0], [0, 1, 0]), np.eye(3))


def test_unwrap():
    x = np.array([170.0, -175.0, -160.0, 179.0])
    assert np.allclose(unwrap_degrees(x), [170.0, 185.0, 200.0, 179.0])
