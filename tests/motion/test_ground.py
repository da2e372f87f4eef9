"""Ground contact of the generated motions: the two-link leg IK and the toe rocker against their geometry."""

import numpy as np
import pytest

from voxpose.motion.ground import leg_ik, toe_rocker
from voxpose.motion.rotations import axis_angle_to_matrix, axis_rotation


def test_leg_ik_reaches_reachable_targets_and_straightens_towards_far_ones():
    rng = np.random.default_rng(2)
    lengths = (0.43, 0.42)
    hip = rng.normal(size=(200, 3))
    direction = rng.normal(size=(200, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    dist = rng.uniform(0.05, 0.84, size=200)
    ankle = hip + dist[:, None] * direction
    axis = rng.normal(size=(200, 3))
    frame, knee = leg_ik(hip, ankle, axis, lengths)
    np.testing.assert_allclose(frame @ np.swapaxes(frame, 1, 2), np.broadcast_to(np.eye(3), (200, 3, 3)), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(frame), 1.0)
    shank = frame @ axis_rotation("X", knee)
    reached = hip + lengths[0] * -frame[:, :, 1] + lengths[1] * -shank[:, :, 1]
    np.testing.assert_allclose(reached, ankle, atol=1e-9)
    # the hinge is the requested axis made perpendicular to the leg, and the knee bends forward (-Z)
    hinge = axis - np.sum(axis * direction, 1, keepdims=True) * direction
    np.testing.assert_allclose(frame[:, :, 0], hinge / np.linalg.norm(hinge, axis=1, keepdims=True), atol=1e-12)
    assert np.all((knee >= 0) & (knee <= 180))
    _, straight = leg_ik(np.zeros((1, 3)), [[0.0, -2.0, 0.0]], [[1.0, 0.0, 0.0]], lengths)
    assert straight[0] == pytest.approx(0.0, abs=1e-3)


def test_toe_rocker_lifts_the_heel_about_the_ball_just_enough():
    lengths = (0.4, 0.4)
    hip = np.array([[0.0, 0.85, 0.0], [0.0, 0.85, 0.0]])
    ball = np.array([[0.0, 0.02, -0.3], [0.0, 0.02, 0.12]])
    ankle = ball + [0.0, 0.05, -0.12]  # the foot points along +Z: the ankle is above and behind the ball
    foot = np.broadcast_to(np.eye(3), (2, 3, 3)).copy()
    new_ankle, new_foot = toe_rocker(hip, ankle, ball, foot, lengths, slack=1e-3)
    # far case: now exactly at reach, same distance from the ball, turned heel-up about +X through the ball
    assert np.linalg.norm(new_ankle[0] - hip[0]) == pytest.approx(0.8 * (1 - 1e-3))
    assert np.linalg.norm(new_ankle[0] - ball[0]) == pytest.approx(np.linalg.norm(ankle[0] - ball[0]))
    turn = new_foot[0]
    angle = np.arctan2(turn[2, 1], turn[1, 1])
    assert angle > 0  # Rx(+) turns the toes down, i.e. lifts the heel
    np.testing.assert_allclose(turn, axis_angle_to_matrix(np.array([1.0, 0, 0]), angle), atol=1e-12)
    np.testing.assert_allclose(new_ankle[0], ball[0] + turn @ (ankle[0] - ball[0]), atol=1e-12)
    # reachable case untouched
    np.testing.assert_array_equal(new_ankle[1], ankle[1])
    np.testing.assert_array_equal(new_foot[1], foot[1])
