"""Forward kinematics of y' against positions worked out by hand."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.motion import canon
from voxpose.motion.pose_kinematics import forward_kinematics

J = canon.INDEX


def skeleton():
    """A simple T-pose skeleton: offsets along the canonical T-pose directions."""
    offsets = np.zeros((14, 3))
    offsets[J["neck"]] = [0, 0.5, 0]
    offsets[J["lshoulder"]] = [0.2, 0, 0]
    offsets[J["lelbow"]] = [0.3, 0, 0]
    offsets[J["lwrist"]] = [0.25, 0, 0]
    offsets[J["rshoulder"]] = [-0.2, 0, 0]
    offsets[J["relbow"]] = [-0.3, 0, 0]
    offsets[J["rwrist"]] = [-0.25, 0, 0]
    offsets[J["lhip"]] = [0.1, -0.05, 0]
    offsets[J["lknee"]] = [0, -0.45, 0]
    offsets[J["lankle"]] = [0, -0.42, 0]
    offsets[J["rhip"]] = [-0.1, -0.05, 0]
    offsets[J["rknee"]] = [0, -0.45, 0]
    offsets[J["rankle"]] = [0, -0.42, 0]
    return offsets


def angles_with(**joint_angles):
    y = np.zeros((1, 42))
    for joint, triple in joint_angles.items():
        y[0, 3 * J[joint] : 3 * J[joint] + 3] = triple
    return y


def test_zero_angles_give_the_t_pose():
    pos, rot = forward_kinematics(angles_with(), skeleton())
    assert np.allclose(rot, np.eye(3))
    assert np.allclose(pos[0, J["lwrist"]], [0.75, 0.5, 0])  # neck + shoulder + upper arm + forearm
    assert np.allclose(pos[0, J["rankle"]], [-0.1, -0.92, 0])
    assert np.allclose(pos[0, J["root"]], 0)


def test_heading_turns_the_whole_body():
    # heading +90 degrees about Y: facing +Z becomes facing +X, the subject's left (+X) becomes -Z
    pos, _ = forward_kinematics(angles_with(root=(90, 0, 0)), skeleton())
    assert np.allclose(pos[0, J["neck"]], [0, 0.5, 0])
    assert np.allclose(pos[0, J["lwrist"]], [0, 0.5, -0.75])
    assert np.allclose(pos[0, J["rhip"]], [0, -0.05, 0.1])


def test_elbow_bend_moves_only_the_forearm():
    # left elbow rotated +90 about Z (third angle): the forearm (+X) turns to +Y, the wrist goes up
    pos, _ = forward_kinematics(angles_with(lelbow=(0, 0, 90)), skeleton())
    elbow = np.array([0.5, 0.5, 0])
    assert np.allclose(pos[0, J["lelbow"]], elbow)
    assert np.allclose(pos[0, J["lwrist"]], elbow + [0, 0.25, 0])
    assert np.allclose(pos[0, J["rwrist"]], [-0.75, 0.5, 0])


def test_knee_flexion_composes_with_the_hip():
    # hip flexed +90 about X: the thigh (-Y) swings to -Z ... Rx(90) @ (0, -1, 0) = (0, 0, -1)
    # knee flexed -90 about X relative to the thigh: the shin points down again (hips and knees are XYZ,
    # so flexion is their first angle)
    pos, _ = forward_kinematics(angles_with(lhip=(90, 0, 0), lknee=(-90, 0, 0)), skeleton())
    hip = np.array([0.1, -0.05, 0])
    knee = hip + [0, 0, -0.45]
    assert np.allclose(pos[0, J["lknee"]], knee)
    assert np.allclose(pos[0, J["lankle"]], knee + [0, -0.42, 0])


def test_bad_shapes_raise():
    with pytest.raises(VoxposeError, match="42 columns"):
        forward_kinematics(np.zeros((2, 41)), skeleton())
    with pytest.raises(VoxposeError, match="offsets"):
        forward_kinematics(np.zeros((2, 42)), np.zeros((13, 3)))
