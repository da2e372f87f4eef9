"""The 42 canonical angles: zero in the T-pose, known values for known rotations, and invariance to how a
rig writes the same motion (channel orders, rest-pose bone frames, length unit)."""

import numpy as np
import pytest

from tests.helpers import random_motion, rebase_frames, reorder_channels, rescaled, set_rotation, tpose_bvh
from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, read_bvh, write_bvh
from voxpose.motion import canon
from voxpose.motion.canonical_pose import canonical_pose
from voxpose.motion.joint_map import resolve_joint_map, skeleton_points
from voxpose.motion.load import load_motion
from voxpose.motion.pose_kinematics import forward_kinematics as pose_forward_kinematics
from voxpose.motion.rotations import axis_rotation, matrix_to_euler, minimal_rotation


def pose_of(bvh: Bvh):
    joints, ends = skeleton_points(bvh, resolve_joint_map(bvh))
    return canonical_pose(joints, ends), joints, ends


def angles_of(pose, joint: str) -> np.ndarray:
    i = canon.INDEX[joint]
    return pose.angles[:, 3 * i : 3 * i + 3]


def test_tpose_is_zero_and_identity():
    for style in ("generated", "cmu"):
        pose, _, _ = pose_of(tpose_bvh(style, n_frames=3))
        assert np.allclose(pose.angles, 0.0, atol=1e-9)
        assert np.allclose(pose.rotations, np.eye(3), atol=1e-12)
    # offsets of the hand-made skeleton in its own canonical frames
    off = dict(zip(canon.JOINTS, pose.offsets, strict=True))
    assert np.allclose(off["root"], 0) and np.allclose(off["neck"], [0, 0.50, 0])
    assert np.allclose(off["lshoulder"], [0.18, -0.03, 0]) and np.allclose(off["relbow"], [-0.28, 0, 0])
    assert np.allclose(off["lhip"], [0.09, -0.08, 0]) and np.allclose(off["rankle"], [0, -0.41, 0])


def test_known_rotations():
    b = tpose_bvh(n_frames=1)
    set_rotation(b, "Hips", [0.0, 0.0, 30.0])  # pelvis turned 30 degrees to its left (towards +X)
    set_rotation(b, "LeftArm", [-90.0, 0.0, 0.0])  # left arm lowered to the side
    set_rotation(b, "RightForeArm", [0.0, 0.0, 90.0])  # right forearm bent forward: -x -> +z
    set_rotation(b, "LeftLeg", [0.0, 40.0, 0.0])  # left knee flexed 40
    set_rotation(b, "RightFoot", [0.0, 20.0, 0.0])  # right foot pointed 20 degrees down
    pose, _, _ = pose_of(b)
    expected = np.zeros((canon.N_JOINTS, 3))
    expected[canon.INDEX["root"]] = [30, 0, 0]
    expected[canon.INDEX["lshoulder"]] = [0, 0, -90]
    expected[canon.INDEX["relbow"]] = [90, 0, 0]
    expected[canon.INDEX["lknee"]] = [40, 0, 0]  # XYZ order: flexion first
    expected[canon.INDEX["rankle"]] = [0, 20, 0]
    assert np.allclose(pose.angles[0], expected.ravel(), atol=1e-9)
    # world rotations: the arm points down in a body turned by 30 degrees
    assert np.allclose(pose.rotations[0, canon.INDEX["lwrist"]] @ [1, 0, 0], axis_rotation("Y", 30) @ [0, -1, 0])


def test_knee_and_hip_flexion_beyond_90_degrees_stay_continuous():
    flex = np.linspace(0.0, 150.0, 31)
    b = tpose_bvh(n_frames=flex.size)
    set_rotation(b, "LeftLeg", np.stack([0 * flex, flex, 0 * flex], axis=1))
    set_rotation(b, "RightUpLeg", np.stack([0 * flex, -flex, 0 * flex], axis=1))  # thigh raised forward
    pose, _, _ = pose_of(b)
    # hips and knees use XYZ: flexion is the first angle, continuous through 90 degrees
    assert canon.EULER_ORDERS[canon.INDEX["lknee"]] == "XYZ"
    assert np.allclose(angles_of(pose, "lknee"), np.stack([flex, 0 * flex, 0 * flex], axis=1), atol=1e-7)
    assert np.allclose(angles_of(pose, "rhip"), np.stack([-flex, 0 * flex, 0 * flex], axis=1), atol=1e-7)
    # under YXZ the same rotation would sit on the principal branch's jump: (180, 60, 180) at 120 degrees
    principal = matrix_to_euler(axis_rotation("X", 120.0), "YXZ")
    assert np.allclose(np.abs(principal), [180, 60, 180])


def test_heading_is_unwrapped_over_time():
    heading = np.linspace(0.0, 720.0, 73)
    b = tpose_bvh(n_frames=heading.size)
    set_rotation(b, "Hips", np.stack([0 * heading, 0 * heading, heading], axis=1))
    pose, _, _ = pose_of(b)
    assert np.allclose(angles_of(pose, "root")[:, 0], heading, atol=1e-7)


def test_limb_rotations_are_parallel_transport_of_the_parent():
    pose, joints, ends = pose_of(random_motion(n_frames=12, seed=7))
    rot = pose.rotations
    for j, p in enumerate(canon.PARENTS):
        if j in (canon.INDEX["root"], canon.INDEX["neck"]):
            continue
        # R_j maps the T-pose direction onto the segment, and differs from R_p by a rotation whose axis
        # is perpendicular to both (no twist)
        end = {"lwrist": 1, "rwrist": 2, "lankle": 3, "rankle": 4}.get(canon.JOINTS[j])
        child = joints[:, j + 1] if end is None else ends[:, end]
        seg = child - joints[:, j]
        seg /= np.linalg.norm(seg, axis=1, keepdims=True)
        assert np.allclose(rot[:, j] @ canon.TPOSE_DIRECTIONS[j], seg, atol=1e-12)
        expected = minimal_rotation(rot[:, p] @ canon.TPOSE_DIRECTIONS[j], seg) @ rot[:, p]
        assert np.allclose(rot[:, j], expected, atol=1e-12)


def test_forward_kinematics_is_exact_for_a_rigid_trunk():
    b = random_motion(n_frames=20, seed=3, rigid_trunk=True)
    pose, joints, _ = pose_of(b)
    positions, rotations = pose_forward_kinematics(pose.angles, pose.offsets)
    assert np.allclose(positions, joints - joints[:, :1], atol=1e-12)
    assert np.allclose(rotations, pose.rotations, atol=1e-12)


def test_forward_kinematics_error_comes_from_the_moving_trunk():
    b = random_motion(n_frames=20, seed=3)  # spine, neck and clavicles move
    pose, joints, _ = pose_of(b)
    positions, rotations = pose_forward_kinematics(pose.angles, pose.offsets)
    assert np.allclose(rotations, pose.rotations, atol=1e-12)
    err = np.linalg.norm(positions - (joints - joints[:, :1]), axis=-1)
    assert err[:, canon.INDEX["neck"]].max() > 1e-3  # the spine length between root and neck changes
    limb = [canon.INDEX[n] for n in ("lelbow", "lwrist", "lknee", "lankle")]
    parents = [canon.PARENTS[i] for i in limb]
    # limb offsets are exact: each limb joint sits at its parent plus a rigid segment
    assert np.allclose(
        np.linalg.norm(positions[:, limb] - positions[:, parents], axis=-1),
        np.linalg.norm(joints[:, limb] - joints[:, parents], axis=-1),
        atol=1e-12,
    )


def test_bad_input():
    _, joints, ends = pose_of(tpose_bvh(n_frames=2))
    with pytest.raises(VoxposeError, match="expected positions"):
        canonical_pose(joints[:, :13], ends)
    broken = joints.copy()
    broken[1, canon.INDEX["lelbow"]] = broken[1, canon.INDEX["lshoulder"]]
    with pytest.raises(VoxposeError, match="segment lshoulder->lelbow has zero length in frame 1"):
        canonical_pose(broken, ends)
    broken = joints.copy()
    broken[0, 0, 0] = np.nan
    with pytest.raises(VoxposeError, match="NaN"):
        canonical_pose(broken, ends)


# ---- invariance: the same motion written by differently built rigs ----


def bones_along_x(bvh: Bvh, seed: int) -> Bvh:
    """Bandai style: every joint frame turned so its bone (first child or End Site) lies along local +X,
    with a random twist about the bone; joints without a bone get a random frame."""
    rng = np.random.default_rng(seed)
    frames = {}
    for j, joint in enumerate(bvh.joints):
        child = next((c.offset for c in bvh.joints if c.parent == j), joint.end_site)
        twist = axis_rotation("X", rng.uniform(-180, 180))
        if child is not None and np.linalg.norm(child) > 1e-9:
            frames[joint.name] = minimal_rotation([1.0, 0.0, 0.0], child) @ twist
        else:
            frames[joint.name] = axis_rotation("Z", rng.uniform(-180, 180)) @ axis_rotation("Y", rng.uniform(-90, 90))
    return rebase_frames(bvh, frames)


def assert_same_motion(a, b):
    assert a.n_frames == b.n_frames
    assert np.abs(a.angles - b.angles).max() < 1e-6
    assert np.abs(a.positions - b.positions).max() < 1e-9
    assert np.abs(a.ends - b.ends).max() < 1e-9
    assert np.abs(a.offsets - b.offsets).max() < 1e-9
    assert a.height == pytest.approx(b.height, rel=1e-12)


def check_invariance(original: Bvh, stem: str, tmp_path, unit: float):
    write_bvh(original, tmp_path / f"{stem}.bvh", precision=17)
    # a rebased rig's reference frame is no longer whole numbers: drop frame 0 explicitly
    base = load_motion(tmp_path / f"{stem}.bvh", unit_scale=unit, drop_reference_frame=True)
    reordered = reorder_channels(original, seed=1)
    assert [j.channels for j in reordered.joints] != [j.channels for j in original.joints]
    rebased = bones_along_x(original, seed=2)
    assert not np.allclose([j.offset for j in rebased.joints], [j.offset for j in original.joints])
    variants = {"reordered": reordered, "rebased": rebased, "both": bones_along_x(reordered, seed=3)}
    for name, variant in variants.items():
        write_bvh(variant, tmp_path / name / f"{stem}.bvh", precision=17)
        assert_same_motion(
            load_motion(tmp_path / name / f"{stem}.bvh", unit_scale=unit, drop_reference_frame=True), base
        )
    write_bvh(rescaled(original, 100.0), tmp_path / "x100" / f"{stem}.bvh", precision=17)
    x100 = load_motion(tmp_path / "x100" / f"{stem}.bvh", unit_scale=unit / 100.0, drop_reference_frame=True)
    assert_same_motion(x100, base)
    return base


def test_invariance_on_the_hand_made_skeleton(tmp_path):
    base = check_invariance(random_motion(n_frames=30, seed=11), "walk_test", tmp_path, unit=1.0)
    assert np.abs(base.angles).max() > 10.0  # a real motion, not the T-pose


def test_invariance_on_a_real_cmu_file(tmp_path, shared_bvh_dir):
    original = read_bvh(shared_bvh_dir / "walk_cmu_07_01.bvh")
    base = check_invariance(original, "walk_cmu_07_01", tmp_path, unit=0.0254 / 0.45)
    assert base.n_frames == 79
