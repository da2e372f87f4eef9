"""Preset detection, config maps and their errors, and the ends (End Sites or estimates) in known geometry."""

import numpy as np
import pytest

from tests.helpers import random_motion, rebase_frames, renamed, set_rotation, tpose_bvh
from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, BvhJoint
from voxpose.motion import canon
from voxpose.motion.canonical_pose import canonical_pose
from voxpose.motion.joint_map import PRESETS, resolve_joint_map, skeleton_points
from voxpose.motion.rotations import axis_rotation

GENERATED = dict(zip(canon.JOINTS, PRESETS[1].joints, strict=True))


def bandai_names(bvh: Bvh) -> Bvh:
    table = {
        "LeftArm": "UpperArm_L",
        "LeftForeArm": "LowerArm_L",
        "LeftHand": "Hand_L",
        "LeftUpLeg": "UpperLeg_L",
    }
    table |= {
        "LeftLeg": "LowerLeg_L",
        "LeftFoot": "Foot_L",
        "LeftToe": "Toes_L",
        "LeftShoulder": "Shoulder_L",
    }
    table |= {k.replace("Left", "Right"): v[:-1] + "R" for k, v in table.items()}
    return renamed(bvh, table)


def test_presets_detected_from_names():
    assert resolve_joint_map(tpose_bvh("generated")).preset == "generated"
    cmu = resolve_joint_map(tpose_bvh("cmu"))
    assert cmu.preset == "cmu"
    assert dict(zip(canon.JOINTS, cmu.joints, strict=True))["neck"] == "Neck"
    assert cmu.ends == ("Head", "LeftHandIndex1", "RightHandIndex1", "LeftToeBase", "RightToeBase")
    bandai = resolve_joint_map(bandai_names(tpose_bvh()))
    assert bandai.preset == "bandai"
    assert bandai.joints[canon.INDEX["rknee"]] == "LowerLeg_R" and bandai.ends[4] == "Toes_R"


def test_unknown_skeleton_names_the_missing_joints():
    b = renamed(tpose_bvh(), {"LeftArm": "l_upperarm", "RightLeg": "r_shin"})
    with pytest.raises(VoxposeError) as err:
        resolve_joint_map(b, source="x.bvh")
    text = str(err.value)
    assert text.startswith("x.bvh: unknown skeleton")
    assert "lshoulder (LeftArm)" in text and "rknee (RightLeg)" in text and "lelbow (" not in text
    assert "closest: generated" in text
    assert "add joint_map: {root: <name>, neck: <name>, lshoulder: <name>" in text
    assert "\n" not in text


def test_config_map_is_used_as_given():
    b = renamed(tpose_bvh(), {"LeftArm": "l_upperarm", "RightLeg": "r_shin"})
    given = GENERATED | {"lshoulder": "l_upperarm", "rknee": "r_shin", "head_top": "Head"}
    jmap = resolve_joint_map(b, given)
    assert jmap.preset == "config"
    assert jmap.joints[canon.INDEX["lshoulder"]] == "l_upperarm"
    assert jmap.ends == ("Head", None, None, None, None)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"elbow": "LeftForeArm"}, "unknown keys ['elbow']"),
        ({"lknee": None}, "joint_map lacks lknee"),
        ({"lknee": "Knee_L"}, "names joints not in the skeleton: {'lknee': 'Knee_L'}"),
        ({"rknee": "LeftLeg"}, "maps several canonical joints to ['LeftLeg']"),
    ],
)
def test_config_map_errors(change, message):
    given = {k: v for k, v in (GENERATED | change).items() if v is not None}
    with pytest.raises(VoxposeError, match=message.replace("[", r"\[").replace("{", r"\{")):
        resolve_joint_map(tpose_bvh(), given, source="x.bvh")
    with pytest.raises(VoxposeError, match="joint_map must be a mapping"):
        resolve_joint_map(tpose_bvh(), ["Hips"], source="x.bvh")


def test_end_sites_give_the_ends():
    b = tpose_bvh("generated", root=(0.0, 1.0, 0.0))
    joints, ends = skeleton_points(b, resolve_joint_map(b))
    head_top = [0.0, 1.0 + 0.10 + 0.15 + 0.25 + 0.08 + 0.17, 0.0]
    assert np.allclose(ends[0], [head_top, [0.80, 1.47, 0], [-0.80, 1.47, 0], [0.09, 0.09, 0.17], [-0.09, 0.09, 0.17]])
    assert np.allclose(joints[0, canon.INDEX["lwrist"]], [0.71, 1.47, 0.0])
    # CMU layout: the hand tip is the index finger's End Site (wrist + 0.05 + 0.04)
    c = tpose_bvh("cmu", root=(0.0, 1.0, 0.0))
    _, ends = skeleton_points(c, resolve_joint_map(c))
    assert np.allclose(ends[0, 1], [0.80, 1.47, 0.0])


def test_missing_ends_are_estimated_in_proportion():
    names = ("Head", "LeftHand", "RightHand", "LeftToe", "RightToe")
    b = renamed(tpose_bvh(root=(0.0, 1.0, 0.0)), {}, drop_sites=names)
    jmap = resolve_joint_map(b, GENERATED)  # no ends named: estimated from the anchors
    joints, ends = skeleton_points(b, jmap)
    p = {n: joints[0, i] for n, i in canon.INDEX.items()}
    leg = 0.42 + 0.41
    assert np.allclose(ends[0, 0], p["neck"] + [0, 0.35 * leg, 0])  # along the spine, up
    assert np.allclose(ends[0, 1], p["lwrist"] + [0.36 * 0.25, 0, 0])  # continues the forearm
    assert np.allclose(ends[0, 2], p["rwrist"] - [0.36 * 0.25, 0, 0])
    assert np.allclose(ends[0, 3], p["lankle"] + [0, 0, 0.42 * 0.41])  # rest pose forward
    # ends named but without End Sites (or zero-length ones): continue beyond the named joint
    zero = renamed(tpose_bvh(root=(0.0, 1.0, 0.0)), {}, drop_sites=("LeftHand", "LeftToe"))
    zero.joints[4].end_site = np.zeros(3)  # Head: zero-length End Site counts as missing
    assert zero.joints[4].name == "Head"
    _, ends = skeleton_points(zero, resolve_joint_map(zero))
    head = joints[0, canon.INDEX["neck"]] + [0, 0.08, 0]
    assert np.allclose(ends[0, 0], head + [0, 0.35 * leg - 0.08, 0])
    toe = p["lankle"] + [0, 0, 0.12]
    assert np.allclose(ends[0, 3], toe + [0, 0, 0.42 * 0.41 - 0.12])
    assert np.allclose(ends[0, 1], p["lwrist"] + [0.36 * 0.25, 0, 0])


def test_estimated_ends_follow_the_joint_rotation():
    b = renamed(tpose_bvh(root=(0.0, 1.0, 0.0)), {}, drop_sites=("LeftHand",))
    set_rotation(b, "LeftHand", [90.0, 0.0, 0.0])  # wrist bent +90 about z: the hand points up
    joints, ends = skeleton_points(b, resolve_joint_map(b))
    assert np.allclose(ends[0, 1], joints[0, canon.INDEX["lwrist"]] + [0, 0.36 * 0.25, 0])


def test_estimated_hand_tip_with_turned_bone_frames():
    # Bandai-like rig: forearm and hand frames both turned about the bone (their x stays on the bone);
    # the same motion gives the same estimated hand tip.
    b = renamed(random_motion(n_frames=8, seed=5), {}, drop_sites=("LeftHand",))
    turned = rebase_frames(b, {"LeftForeArm": axis_rotation("X", 50.0), "LeftHand": axis_rotation("X", 50.0)})
    assert not np.allclose(turned.motion, b.motion)
    jmap = resolve_joint_map(b)
    joints, ends = skeleton_points(b, jmap)
    joints2, ends2 = skeleton_points(turned, jmap)
    assert np.allclose(joints2, joints, atol=1e-12) and np.allclose(ends2, ends, atol=1e-12)


def without_hands(bvh: Bvh) -> Bvh:
    """``bvh`` with its hand joints removed: each forearm ends in an End Site where its hand joint was."""
    hands = {"LeftHand", "RightHand"}
    keep = [i for i, j in enumerate(bvh.joints) if j.name not in hands]
    new_index = {old: new for new, old in enumerate(keep)}
    joints, columns = [], []
    for old in keep:
        j = bvh.joints[old]
        hand = next((h for h in bvh.joints if h.name in hands and bvh.joints[h.parent] is j), None)
        site = j.end_site if hand is None else hand.offset
        joints.append(BvhJoint(j.name, new_index.get(j.parent, -1), j.offset, j.channels, site))
        start = sum(len(bvh.joints[k].channels) for k in range(old))
        columns += range(start, start + len(j.channels))
    return Bvh(joints, bvh.frame_time, bvh.motion[:, columns])


def test_a_wrist_at_the_forearms_end_site():
    full = random_motion(n_frames=12, seed=7)
    handless = without_hands(full)
    assert {"LeftHand", "RightHand"}.isdisjoint(j.name for j in handless.joints)
    given = GENERATED | {"lwrist": "LeftForeArm/end", "rwrist": "RightForeArm/end"}
    given |= {"head_top": "Head", "ltoe": "LeftToe", "rtoe": "RightToe"}  # the preset's other ends
    joints, ends = skeleton_points(handless, resolve_joint_map(handless, given))
    truth, truth_ends = skeleton_points(full, resolve_joint_map(full))
    assert np.allclose(joints, truth, atol=1e-12)  # the End Sites are where the hand joints were
    # no hand: the hand tip continues the forearm by 0.36 of its length, so the wrist angles are zero
    for side, e in (("l", 1), ("r", 2)):
        forearm = joints[:, canon.INDEX[f"{side}wrist"]] - joints[:, canon.INDEX[f"{side}elbow"]]
        assert np.allclose(ends[:, e], joints[:, canon.INDEX[f"{side}wrist"]] + 0.36 * forearm, atol=1e-12)
    wrists = [canon.INDEX["lwrist"], canon.INDEX["rwrist"]]
    angles = canonical_pose(joints, ends).angles.reshape(-1, canon.N_JOINTS, 3)
    assert np.abs(angles[:, wrists]).max() < 1e-6
    with_hands = canonical_pose(truth, truth_ends).angles.reshape(-1, canon.N_JOINTS, 3)
    assert np.abs(with_hands[:, wrists]).max() > 5.0  # the hand joints bent the wrists
    others = [i for i in range(canon.N_JOINTS) if i not in wrists]
    assert np.allclose(angles[:, others], with_hands[:, others], atol=1e-9)


def test_an_end_site_point_must_exist():
    handless = without_hands(tpose_bvh())
    given = GENERATED | {"lwrist": "LeftArm/end", "rwrist": "RightForeArm/end"}  # LeftArm has no End Site
    with pytest.raises(VoxposeError, match=r"names joints not in the skeleton: \{'lwrist': 'LeftArm/end'\}; "
                       r"skeleton joints and End Site points \(<joint>/end\): .*LeftForeArm/end"):  # fmt: skip
        resolve_joint_map(handless, given, source="x.bvh")
