"""Forward kinematics against positions worked out by hand."""

import numpy as np
import pytest

from tests.helpers import random_motion, tpose_bvh
from voxpose.io.bvh import Bvh, BvhJoint
from voxpose.motion.bvh_kinematics import forward_kinematics, local_transforms, rest_pose

ROT_ZYX = ("Zrotation", "Yrotation", "Xrotation")


def chain(root_channels, child_channels, grandchild_channels, motion):
    joints = [
        BvhJoint("root", -1, np.array([5.0, 5.0, 5.0]), root_channels),
        BvhJoint("child", 0, np.array([0.0, 1.0, 0.0]), child_channels),
        BvhJoint("tip", 1, np.array([1.0, 0.0, 0.0]), grandchild_channels, end_site=np.array([0.0, 0.0, 1.0])),
    ]
    return Bvh(joints, 0.1, np.atleast_2d(np.asarray(motion, dtype=float)))


def test_three_joint_chain_by_hand():
    # root at (1, 2, 3) turned +90 degrees about Y (x -> -z, z -> x); child turned +90 about Z (x -> y).
    b = chain(
        ("Xposition", "Yposition", "Zposition", "Zrotation", "Yrotation", "Xrotation"),
        ROT_ZYX,
        (),
        [1, 2, 3, 0, 90, 0, 90, 0, 0],
    )
    pos, rot, ends = forward_kinematics(b)
    assert np.allclose(pos[0, 0], [1, 2, 3])  # position channels replace the root OFFSET
    assert np.allclose(pos[0, 1], [1, 3, 3])  # child offset +y is unaffected by a turn about y
    # tip offset +x: child frame maps x -> y (Rz 90), then root frame leaves y alone
    assert np.allclose(pos[0, 2], [1, 4, 3])
    # end site +z: Rz(90) keeps z, Ry(90) maps z -> x
    assert np.allclose(ends[2][0], [2, 4, 3])
    assert set(ends) == {2}
    assert np.allclose(rot[0, 2] @ [1, 0, 0], [0, 1, 0])


def test_channel_order_is_the_euler_order():
    # child rotation channels X then Y: R = Rx(90) @ Ry(90); tip offset +x -> Ry: -z -> Rx: +y
    b = chain((), ("Xrotation", "Yrotation", "Zrotation"), (), [90, 90, 0])
    pos, _, _ = forward_kinematics(b)
    assert np.allclose(pos[0, 2], pos[0, 1] + [0, 1, 0])
    # the same numbers in Y-then-X order: R = Ry(90) @ Rx(90); +x -> Rx: +x -> Ry: -z
    b = chain((), ("Yrotation", "Xrotation", "Zrotation"), (), [90, 90, 0])
    pos, _, _ = forward_kinematics(b)
    assert np.allclose(pos[0, 2], pos[0, 1] + [0, 0, -1])
    assert np.allclose(pos[0, 0], [5, 5, 5])  # a root without position channels sits at its OFFSET


def test_position_channels_on_non_root_joints_replace_the_offset():
    # Bandai style: every joint has 6 channels; the child's position channels are used
    six = ("Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation")
    b = chain(six, six, (), [[0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0, 0]])
    pos, _, _ = forward_kinematics(b)
    assert np.allclose(pos[:, 1], [[0, 2, 0], [0, 3, 0]])
    assert np.allclose(pos[:, 2], [[1, 2, 0], [1, 3, 0]])


def test_rest_pose_sums_offsets_with_identity_rotations():
    b = random_motion(n_frames=3, seed=0)
    rest = rest_pose(b)
    assert rest.n_frames == 1
    pos, rot, ends = forward_kinematics(rest)
    assert np.allclose(rot, np.eye(3))
    for j, joint in enumerate(b.joints):
        expected = joint.offset + (pos[0, joint.parent] if joint.parent >= 0 else 0)
        assert np.allclose(pos[0, j], expected)
    left_hand = next(i for i, j in enumerate(b.joints) if j.name == "LeftHand")
    # T-pose: hand End Site at 0.03+0.15+0.28+0.25+0.09 along +x, 0.10+0.15+0.22 up
    assert np.allclose(ends[left_hand][0], [0.80, 0.47, 0.0])


def test_world_rotation_composes_locals_over_frames():
    b = random_motion(n_frames=6, seed=2)
    pos, rot, _ = forward_kinematics(b)
    trans, local = local_transforms(b)
    for j, joint in enumerate(b.joints):
        p = joint.parent
        if p >= 0:
            for f in range(b.n_frames):
                assert np.allclose(rot[f, j], rot[f, p] @ local[f, j])
                assert np.allclose(pos[f, j], pos[f, p] + rot[f, p] @ trans[f, j])


@pytest.mark.parametrize("n_frames", [0, 1])
def test_empty_and_single_frame(n_frames):
    b = tpose_bvh(n_frames=n_frames)
    pos, rot, ends = forward_kinematics(b)
    assert pos.shape == (n_frames, len(b.joints), 3) and rot.shape == (n_frames, len(b.joints), 3, 3)
