"""Leading reference poses found by geometry: planted T- and A-poses are dropped, motion is kept, on any rig."""

import numpy as np
import pytest

from tests.helpers import reorder_channels, set_rotation, tpose_bvh
from voxpose.io.bvh import Bvh, joint_columns, write_bvh
from voxpose.motion.generate import default_motion
from voxpose.motion.joint_map import resolve_joint_map, skeleton_points
from voxpose.motion.load import load_motion
from voxpose.motion.reference_pose import MIN_STEP, RATIO, leading_reference_frames, pose_steps, reference_poses


def points(bvh: Bvh):
    return skeleton_points(bvh, resolve_joint_map(bvh))


def arms(bvh: Bvh, frames, down_degrees) -> None:
    """Lower both arms of the generated rig (T-pose rest, channels Z X Y) by ``down_degrees`` in ``frames``."""
    for name, sign in (("LeftArm", -1.0), ("RightArm", 1.0)):
        j = next(i for i, joint in enumerate(bvh.joints) if joint.name == name)
        rot = joint_columns(bvh, j)[1]
        bvh.motion[frames, rot[0]] = sign * np.asarray(down_degrees)
        bvh.motion[frames, rot[1:]] = 0.0


def planted(walk: Bvh, down_degrees: float) -> Bvh:
    """``walk`` with frame 0 replaced by the rest T-pose (arms lowered by ``down_degrees``) at its root."""
    out = Bvh(walk.joints, walk.frame_time, walk.motion.copy())
    out.motion[0, 3:] = 0.0
    arms(out, [0], down_degrees)
    return out


@pytest.fixture(scope="module")
def walk() -> Bvh:
    return default_motion("walk", 0, n_frames=40, seed=3)  # the generated rig, 30 fps


@pytest.mark.parametrize("down", [0.0, 45.0])  # T-pose, A-pose
def test_a_planted_reference_pose_on_a_generated_walk_is_dropped(tmp_path, walk, down):
    bvh = planted(walk, down)
    joints, ends = points(bvh)
    assert reference_poses(joints)[0] and not reference_poses(joints)[1:].any()
    assert leading_reference_frames(joints, ends) == 1
    write_bvh(bvh, tmp_path / "walk_planted.bvh", precision=17)
    write_bvh(Bvh(walk.joints, walk.frame_time, walk.motion[1:]), tmp_path / "walk_rest.bvh", precision=17)
    loaded = load_motion(tmp_path / "walk_planted.bvh")
    assert loaded.source["dropped_frames"] == 1
    assert np.allclose(loaded.angles, load_motion(tmp_path / "walk_rest.bvh").angles, atol=1e-9)
    # the same file written by another rig (every joint in another Euler order): still found
    write_bvh(reorder_channels(bvh, seed=4), tmp_path / "walk_reordered.bvh", precision=17)
    assert load_motion(tmp_path / "walk_reordered.bvh").source["dropped_frames"] == 1


def test_an_ordinary_first_frame_is_kept(tmp_path, walk):
    joints, ends = points(walk)
    assert not reference_poses(joints).any()  # arms hang while walking
    write_bvh(walk, tmp_path / "walk_gen.bvh", precision=17)
    assert load_motion(tmp_path / "walk_gen.bvh").source["dropped_frames"] == 0


def standing(n_frames: int, lower_over: int, lowered_to: float = 80.0) -> Bvh:
    """Standing still with a slight sway, arms held out in an A-pose (45 degrees down) for 10 frames, then
    lowered to ``lowered_to`` degrees over ``lower_over`` frames (1: at once) and held."""
    bvh = tpose_bvh("generated", n_frames)
    t = np.arange(n_frames)
    down = np.interp(t, [9, 9 + lower_over], [45.0, lowered_to]) + 0.5 * np.sin(t / 3.0)
    arms(bvh, slice(None), down)
    set_rotation(bvh, "Spine", np.stack([np.sin(t / 5.0), 0.5 * np.sin(t / 4.0), 0 * t], axis=1))
    return bvh


def test_a_standing_pose_like_the_next_frames_is_kept_and_one_unlike_them_dropped():
    smooth = standing(40, lower_over=15)
    joints, ends = points(smooth)
    poses = reference_poses(joints)
    assert poses[:10].all() and not poses[-10:].any()  # held out in an A-pose, then lowered
    assert leading_reference_frames(joints, ends) == 0  # the arms come down like motion does
    assert pose_steps(joints, ends).max() < MIN_STEP
    abrupt = standing(40, lower_over=1)
    joints, ends = points(abrupt)
    assert reference_poses(joints)[:10].all()
    steps = pose_steps(joints, ends)
    assert steps[9] >= MIN_STEP and steps[9] >= RATIO * np.median(steps[10:15])  # arms down at once
    assert leading_reference_frames(joints, ends) == 10
    # a pose held for the whole take is the motion
    held = standing(40, lower_over=1, lowered_to=45.0)
    assert reference_poses(points(held)[0]).all() and leading_reference_frames(*points(held)) == 0


def test_bent_legs_or_elbows_or_arms_in_front_are_not_reference_poses(walk):
    bvh = planted(walk, 0.0)
    base = reference_poses(points(bvh)[0])[0]
    assert base
    for name, zxy in (("LeftLeg", [0.0, 30.0, 0.0]), ("RightForeArm", [0.0, 0.0, 40.0]), ("LeftArm", [0.0, 0.0, 80.0])):
        bent = Bvh(bvh.joints, bvh.frame_time, bvh.motion[:1].copy())
        set_rotation(bent, name, zxy)
        assert not reference_poses(points(bent)[0])[0], name
