"""Anatomical landmarks (issue 18 item 1): one person on two skeleton conventions gets one body.

The second convention is a retarget built in the test: the generated motion's local rotations on a rig whose
root sits 0.07 h above the hip joints (a lower-back root, as CMU's), whose hip joints are 0.041 h and shoulder
joints 0.065 h from the midline (Bandai's widths) and whose neck joint is 0.03 h higher with a head bone as much
shorter; it is loaded through the normal loader with a config joint map. Truth: the generated motion's body,
which the anthropometric table it is built from places exactly on its joints.
"""

import numpy as np
import pytest

from tests.helpers import GENERATED_MAP, renamed
from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, BvhJoint, write_bvh
from voxpose.motion import canon
from voxpose.motion.bvh_kinematics import forward_kinematics
from voxpose.motion.generate import default_motion
from voxpose.motion.load import load_motion
from voxpose.voxels import body as body_module
from voxpose.voxels.body import body_ellipsoids
from voxpose.voxels.landmarks import HIP_HALF_WIDTH, SHOULDER_HALF_WIDTH, anatomical_points, landmark_scales
from voxpose.voxels.occupancy import occupied_voxels

ROOT_RAISE = 0.07
NECK_RAISE = 0.03
NEW_OFFSETS = {  # joint: new OFFSET / H (left side; the right mirrors it)
    "Spine": (0.0, 0.100 - ROOT_RAISE, 0.0),
    "LeftUpLeg": (0.041, -ROOT_RAISE, 0.0),
    "LeftArm": (0.045, 0.018, 0.0),
    "Neck": (0.0, 0.068 + NECK_RAISE, 0.0),
    "Head": (0.0, 0.052 - NECK_RAISE, 0.0),
}


def other_convention(bvh: Bvh) -> Bvh:
    """The retargeted rig of the module docstring; joint names get a ``_b`` suffix."""
    height = bvh.joints[[j.name for j in bvh.joints].index("Spine")].offset[1] / 0.100
    joints = []
    for joint in bvh.joints:
        name = joint.name.replace("Right", "Left")
        offset = joint.offset
        if name in NEW_OFFSETS:
            offset = height * np.array(NEW_OFFSETS[name])
            offset[0] *= -1.0 if joint.name.startswith("Right") else 1.0
        joints.append(BvhJoint(joint.name, joint.parent, offset, joint.channels, joint.end_site))
    _, rotations, _ = forward_kinematics(bvh)
    motion = bvh.motion.copy()
    motion[:, :3] += rotations[:, 0] @ np.array([0.0, ROOT_RAISE * height, 0.0])
    rig = Bvh(joints, bvh.frame_time, motion)
    return renamed(rig, {j.name: j.name + "_b" for j in rig.joints})


def frame_iou(a, b, l_res: float) -> np.ndarray:
    """Per frame, the intersection over union of the voxels of two bodies on one world grid."""
    out = []
    (fa, ia), (fb, ib) = occupied_voxels(a, l_res), occupied_voxels(b, l_res)
    for f in range(a.n_frames):
        sa, sb = set(map(tuple, ia[fa == f])), set(map(tuple, ib[fb == f]))
        out.append(len(sa & sb) / len(sa | sb))
    return np.array(out)


@pytest.fixture(scope="module", params=["walk", "jump"])
def two_conventions(request, tmp_path_factory):
    kind, folder = request.param, tmp_path_factory.mktemp(request.param)
    generated = default_motion(kind, 0, n_frames=30, seed=5)
    write_bvh(generated, folder / f"{kind}_a.bvh")
    write_bvh(other_convention(generated), folder / f"{kind}_b.bvh")
    a = load_motion(folder / f"{kind}_a.bvh", drop_reference_frame=False)
    joint_map = {k: v + "_b" for k, v in GENERATED_MAP.items()}
    b = load_motion(folder / f"{kind}_b.bvh", joint_map=joint_map, drop_reference_frame=False)
    return a, b


def test_the_retarget_moves_the_joints_as_the_families_do(two_conventions):
    a, b = two_conventions
    index, h = canon.INDEX, a.height
    pelvis = 0.5 * (b.positions[:, index["lhip"]] + b.positions[:, index["rhip"]])
    assert np.allclose(np.linalg.norm(b.positions[:, index["root"]] - pelvis, axis=-1), ROOT_RAISE * h, rtol=1e-3)
    hips = np.linalg.norm(b.positions[:, index["lhip"]] - b.positions[:, index["rhip"]], axis=-1)
    shoulders = np.linalg.norm(b.positions[:, index["lshoulder"]] - b.positions[:, index["rshoulder"]], axis=-1)
    assert np.allclose(hips, 0.082 * h, rtol=1e-3) and np.median(shoulders) == pytest.approx(0.130 * h, rel=1e-3)
    # the arms and legs of the retarget are elsewhere in the world: 6 and 1 cm nearer the midline
    assert np.linalg.norm(a.positions[:, index["lwrist"]] - b.positions[:, index["lwrist"]], axis=-1).min() > 0.05


def test_one_person_on_two_conventions_gets_one_body(two_conventions):
    a, b = two_conventions
    assert abs(b.height / a.height - 1.0) < 0.02  # the same h_sub within 2 %
    l_res = a.height / 60.0
    iou = frame_iou(body_ellipsoids(a), body_ellipsoids(b), l_res)
    assert iou.min() >= 0.9, iou


def test_without_the_landmarks_the_two_bodies_differ(two_conventions, monkeypatch):
    """The IoU test can fail: drawn on the raw joints, the retarget's body is another body."""
    a, b = two_conventions
    monkeypatch.setattr(body_module, "anatomical_points", lambda positions, ends, height, label: (positions, ends))
    iou = frame_iou(body_ellipsoids(a), body_ellipsoids(b), a.height / 60.0)
    assert iou.max() < 0.85, iou


def test_landmarks_of_the_generated_skeleton_are_its_joints(two_conventions):
    a, _ = two_conventions
    assert landmark_scales(a.positions, a.ends, a.height) == {"hip": 1.0, "shoulder": 1.0, "neck": 1.0}
    joints, ends = anatomical_points(a.positions, a.ends, a.height)
    assert np.abs(joints - a.positions).max() < 1e-12 and np.abs(ends - a.ends).max() < 1e-12


def test_landmarks_put_hips_and_shoulders_at_the_table_widths(two_conventions):
    _, b = two_conventions
    joints, ends = anatomical_points(b.positions, b.ends, b.height)
    index = canon.INDEX
    for girdle, half in (("hip", HIP_HALF_WIDTH), ("shoulder", SHOULDER_HALF_WIDTH)):
        width = np.linalg.norm(joints[:, index["l" + girdle]] - joints[:, index["r" + girdle]], axis=-1)
        assert np.median(width) == pytest.approx(2 * half * b.height, rel=1e-9)
    # a limb keeps its length and direction: it is moved rigidly with its girdle
    for upper, lower in (("lshoulder", "lelbow"), ("relbow", "rwrist"), ("lhip", "lknee"), ("rknee", "rankle")):
        moved = joints[:, index[lower]] - joints[:, index[upper]]
        assert np.allclose(moved, b.positions[:, index[lower]] - b.positions[:, index[upper]], atol=1e-12)
    toe = canon.ENDS.index("ltoe")
    assert np.allclose(ends[:, toe] - joints[:, index["lankle"]], b.ends[:, toe] - b.positions[:, index["lankle"]])
    # the root becomes the pelvis centre between the hip joints
    assert np.allclose(joints[:, index["root"]], 0.5 * (b.positions[:, index["lhip"]] + b.positions[:, index["rhip"]]))


def test_coinciding_hips_are_refused():
    positions = np.zeros((2, canon.N_JOINTS, 3))
    positions[:, canon.INDEX["lshoulder"], 0] = 0.2
    with pytest.raises(VoxposeError, match="body model: motion x: the hip landmarks coincide"):
        landmark_scales(positions, np.ones((2, len(canon.ENDS), 3)), 1.75, "motion x")
