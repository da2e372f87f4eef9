"""The heading encoding round-trips and removes the 360-degree ambiguity."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.regression import pose_encoding


def test_round_trip_and_wrap():
    rng = np.random.default_rng(0)
    angles = rng.uniform(-60, 60, size=(50, 42))
    angles[:, pose_encoding.HEADING] = rng.uniform(-720, 720, size=50)
    for heading in ("vector", "angle"):
        back = pose_encoding.decode(pose_encoding.encode(angles, heading), heading)
        d = np.mod(back - angles, 360.0)
        assert np.allclose(np.minimum(d, 360.0 - d), 0.0, atol=1e-9)


def test_same_orientation_same_target():
    a = np.zeros((2, 42))
    a[:, pose_encoding.HEADING] = [170.0, 170.0 - 360.0]
    enc = pose_encoding.encode(a, "vector")
    assert enc.shape == (2, 43)
    assert np.allclose(enc[0], enc[1])
    # a small heading change moves the encoded point by the same number of units (degrees)
    b = a[:1].copy()
    b[0, pose_encoding.HEADING] += 0.01
    assert np.linalg.norm(pose_encoding.encode(b)[0] - enc[0]) == pytest.approx(0.01, rel=1e-4)


def test_averaging_across_the_wrap_stays_on_the_circle():
    a = np.zeros((2, 42))
    a[:, pose_encoding.HEADING] = [179.0, -179.0]
    mean = pose_encoding.decode(pose_encoding.encode(a).mean(axis=0, keepdims=True))
    assert abs(abs(mean[0, pose_encoding.HEADING]) - 180.0) < 1e-9  # the raw angles would average to 0


def test_unknown_encoding():
    with pytest.raises(VoxposeError, match="regression.heading"):
        pose_encoding.encode(np.zeros((1, 42)), "quaternion")


def test_turn_heading_is_the_root_turned_about_the_vertical():
    """Independent truth: the root's world rotation premultiplied by Ry(d), read back as Y-X-Z Euler angles."""
    from voxpose.motion import canon
    from voxpose.motion.rotations import axis_rotation, euler_to_matrix, matrix_to_euler

    rng = np.random.default_rng(1)
    angles = rng.uniform(-60, 60, size=(20, 42))
    turn = rng.uniform(-400, 400, size=20)
    turned = pose_encoding.turn_heading(angles, turn)
    root = euler_to_matrix(angles[:, :3], canon.EULER_ORDERS[0])
    expected = matrix_to_euler(axis_rotation("Y", turn) @ root, canon.EULER_ORDERS[0])
    d = np.mod(turned[:, :3] - expected + 180.0, 360.0) - 180.0
    np.testing.assert_allclose(d, 0.0, atol=1e-9)
    np.testing.assert_array_equal(turned[:, 3:], angles[:, 3:])
