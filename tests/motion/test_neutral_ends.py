"""The 42 angles of one motion on two skeleton conventions (issue 18 item 2), and the ends at rest on real data.

The second convention is built in the test from the generated skeleton's world trajectories: other bone-local
axes (each bone along its local +X with a random twist, Bandai style), other Euler orders, an extra spine joint
with its own twist, and a hand End Site placed like CMU's index knuckle, off the hand's axis; it is loaded through
the normal loader with a config joint map. Truth: the generated motion's own angles.
"""

import logging
from pathlib import Path

import numpy as np
import pytest
import yaml

from tests.helpers import GENERATED_MAP, rebase_frames, renamed, reorder_channels
from voxpose.io.bvh import Bvh, BvhJoint, joint_columns, read_bvh, write_bvh
from voxpose.motion import canon
from voxpose.motion.bvh_kinematics import forward_kinematics, local_transforms, rest_pose
from voxpose.motion.canonical_pose import canonical_pose, local_rotations
from voxpose.motion.generate import default_motion
from voxpose.motion.joint_map import resolve_joint_map, skeleton_points
from voxpose.motion.load import load_motion
from voxpose.motion.rotations import axis_angle_to_matrix, axis_rotation, matrix_to_euler, minimal_rotation
from voxpose.workflow_config import motion_settings

ROTATION = ("Zrotation", "Xrotation", "Yrotation")
CONFIG = Path(__file__).resolve().parents[2] / "config" / "config.yaml"
KNUCKLE = np.array([0.0, -0.30, 0.20])  # off the hand axis, per unit hand length, in the hand's frame (~20 deg)


def with_extra_spine_joint(bvh: Bvh) -> Bvh:
    """``bvh`` with a joint ``Spine2`` halfway between ``Spine`` and ``Chest``, twisting about that bone over
    time while ``Chest`` untwists: the same world positions and rotations of every other joint."""
    _, local = local_transforms(bvh)
    chest = next(i for i, j in enumerate(bvh.joints) if j.name == "Chest")
    half = 0.5 * bvh.joints[chest].offset
    t = np.arange(bvh.n_frames) / bvh.n_frames
    twist = axis_angle_to_matrix(half / np.linalg.norm(half), np.radians(10.0 + 20.0 * np.sin(2 * np.pi * t)))
    rows, rotations = [], []
    for i, joint in enumerate(bvh.joints):
        parent = -1 if joint.parent < 0 else joint.parent + (joint.parent >= chest)
        if i == chest:
            rows.append(BvhJoint("Spine2", parent, half, ROTATION, None))
            rotations.append(twist)
            joint, parent = BvhJoint(joint.name, chest, half, joint.channels, joint.end_site), chest
            rotations.append(np.swapaxes(twist, -1, -2) @ local[:, i])
        else:
            rotations.append(local[:, i])
        rows.append(BvhJoint(joint.name, parent, joint.offset, joint.channels, joint.end_site))
    blocks = [bvh.motion[:, :3]]  # the root's position channels (the generated root writes them first)
    for row, rot in zip(rows, rotations, strict=True):
        order = "".join(c[0] for c in row.channels if c.endswith("rotation"))
        blocks.append(matrix_to_euler(rot, order))
    return Bvh(rows, bvh.frame_time, np.concatenate(blocks, axis=1))


def knuckle_rig(bvh: Bvh) -> Bvh:
    """The second convention (module docstring); joint names get a ``_b`` suffix."""
    axes = {}  # each hand's anatomical axis (the generated End Site) before the End Site moves to the knuckle
    joints = []
    for joint in bvh.joints:
        site = joint.end_site
        if joint.name.endswith("Hand"):
            axes[joint.name] = site.copy()
            site = site + np.linalg.norm(site) * KNUCKLE
        joints.append(BvhJoint(joint.name, joint.parent, joint.offset, joint.channels, site))
    spine = with_extra_spine_joint(Bvh(joints, bvh.frame_time, bvh.motion))
    rng = np.random.default_rng(7)
    frames = {}
    for j, joint in enumerate(spine.joints):
        bone = axes.get(joint.name, next((c.offset for c in spine.joints if c.parent == j), joint.end_site))
        frames[joint.name] = minimal_rotation([1.0, 0.0, 0.0], bone) @ axis_rotation("X", rng.uniform(-180, 180))
    rig = reorder_channels(rebase_frames(spine, frames), seed=4)
    return renamed(rig, {j.name: j.name + "_b" for j in rig.joints})


KNUCKLE_MAP = {k: v + "_b" for k, v in GENERATED_MAP.items()}


@pytest.mark.parametrize("kind", ["walk", "jump"])
def test_one_motion_on_two_conventions_gives_the_same_42_angles(tmp_path, kind):
    generated = default_motion(kind, 0, n_frames=45, seed=5)
    other = knuckle_rig(generated)
    assert [j.channels for j in other.joints[1:]] != [j.channels for j in generated.joints[1:]]
    write_bvh(generated, tmp_path / "a" / f"{kind}_a.bvh")
    write_bvh(other, tmp_path / "b" / f"{kind}_b.bvh")
    a = load_motion(tmp_path / "a" / f"{kind}_a.bvh", drop_reference_frame=False)
    b = load_motion(tmp_path / "b" / f"{kind}_b.bvh", joint_map=KNUCKLE_MAP, drop_reference_frame=False)
    assert a.source["skeleton"] == "generated" and b.source["skeleton"] == "config"
    assert np.abs(a.positions - b.positions).max() < 1e-4  # the same world landmarks (metres)
    # the knuckle lies off the forearm: measured towards it, the wrists would be ~20 degrees off
    rest = rest_pose(other)
    joints, _ = skeleton_points(rest, resolve_joint_map(rest, KNUCKLE_MAP))
    _, _, sites = forward_kinematics(rest)
    left = [j.name for j in other.joints].index("LeftHand_b")
    forearm = joints[0, canon.INDEX["lwrist"]] - joints[0, canon.INDEX["lelbow"]]
    knuckle = sites[left][0] - joints[0, canon.INDEX["lwrist"]]
    cos = forearm @ knuckle / np.linalg.norm(forearm) / np.linalg.norm(knuckle)
    assert np.degrees(np.arccos(cos)) > 15.0
    assert np.abs(a.angles - b.angles).max() < 1.0
    assert np.abs(a.angles).max() > 20.0  # a real motion


def rest_bends(path) -> dict[str, float]:
    """Degrees between each end segment and its parent's T-pose direction in the rest pose (all channels zero)."""
    rest = rest_pose(read_bvh(path))
    joints, ends = skeleton_points(rest, resolve_joint_map(rest))
    local = local_rotations(canonical_pose(joints, ends).rotations)[0]
    out = {}
    for name in ("lwrist", "rwrist", "neck"):
        t = canon.TPOSE_DIRECTIONS[canon.INDEX[name]]
        out[name] = float(np.degrees(np.arccos(np.clip(t @ local[canon.INDEX[name]] @ t, -1.0, 1.0))))
    return out


def test_real_rest_ends_of_cmu_and_bandai(shared_bvh_dir):
    """At rest (benchmarks/end_angles.py, documented in canonical_pose): CMU's and Bandai's hands are straight
    (within 0.1 degrees); their heads lean off the root -> neck line by 1.2-7.0 (CMU) and 0.6 (Bandai) degrees,
    means 2.8 and 0.6, i.e. they differ by less than 3 degrees (the head is not normalised)."""
    bends = {
        family: [rest_bends(p) for p in sorted(shared_bvh_dir.glob(f"*_{family}*.bvh"))] for family in ("cmu", "bandai")
    }
    for family, rows in bends.items():
        assert max(max(r["lwrist"], r["rwrist"]) for r in rows) < 0.1, family
        assert max(r["neck"] for r in rows) < 7.5, family
    means = {family: np.mean([r["neck"] for r in rows]) for family, rows in bends.items()}
    assert abs(means["cmu"] - means["bandai"]) < 3.0


def test_a_rig_without_hand_rotation_has_straight_unmeasured_wrists(tmp_path, caplog):
    generated = default_motion("walk", 1, n_frames=30, seed=6)
    still = Bvh(generated.joints, generated.frame_time, generated.motion.copy())
    for j, joint in enumerate(still.joints):
        if joint.name.endswith("Hand"):
            still.motion[:, joint_columns(still, j)[1]] = 0.0
    write_bvh(generated, tmp_path / "walk_hands.bvh")
    write_bvh(knuckle_rig(still), tmp_path / "walk_still.bvh")  # its knuckle End Sites lie ~20 degrees off axis
    with caplog.at_level(logging.WARNING, logger="voxpose.motion.load"):
        still_motion = load_motion(tmp_path / "walk_still.bvh", joint_map=KNUCKLE_MAP, drop_reference_frame=False)
    assert still_motion.source["unmeasured"] == ["lwrist", "rwrist"]
    assert "walk_still: the hand tips lie on the forearms' axes in every frame (lwrist, rwrist)" in caplog.text
    wrists = [3 * canon.INDEX[w] + k for w in ("lwrist", "rwrist") for k in range(3)]
    assert np.abs(still_motion.angles[:, wrists]).max() < 0.05
    moving = load_motion(tmp_path / "walk_hands.bvh", drop_reference_frame=False)
    assert moving.source["unmeasured"] == [] and np.abs(moving.angles[:, wrists]).max() > 5.0


def test_shared_files_without_hands_are_flagged(shared_bvh_dir, shared_library_dir):
    cmu = load_motion(shared_bvh_dir / "walk_cmu_07_01.bvh")
    bandai = load_motion(shared_bvh_dir / "walk_bandai2_walk_normal_001.bvh")
    assert cmu.source["unmeasured"] == [] and bandai.source["unmeasured"] == []
    settings = motion_settings("idle_reactidle_000_genuine", yaml.safe_load(CONFIG.read_text())["motions"])
    idle = load_motion(shared_library_dir / "idle_reactidle_000_genuine.bvh", **settings)
    assert idle.source["unmeasured"] == ["lwrist", "rwrist"]
