"""The skeleton of the generated motions (``voxpose.motion.generate``): joints, proportions and channels.

21 joints with CMU-like names (Hips root with 6 channels; Spine, Chest, Neck, Head; Left/Right Shoulder
(clavicle), Arm, ForeArm, Hand; Left/Right UpLeg, Leg, Foot, Toe; End Sites on Head, hands and toes),
in metres, rest pose a T-pose standing on y = 0, facing +Z, Y up, the subject's left along +X
(``voxpose.motion.canon``). Joint rotations use the channels ``Zrotation Xrotation Yrotation`` (R = Rz Rx Ry), on
purpose not CMU's order. Segment lengths are fractions of the standing height H from the
anthropometric table of Drillis and Contini as given by D. A. Winter, *Biomechanics and Motor Control of
Human Movement* (4th ed., 2009, Fig. 4.1): hip joint 0.530 H above the floor (thigh 0.245 H, shank
0.246 H, ankle 0.039 H), shoulder 0.818 H with a biacromial width of 0.259 H, chin 0.870 H, upper arm
0.186 H, forearm 0.146 H, hand 0.108 H, foot 0.152 H (ankle 0.038 H in front of the heel). The spine is
split at 0.630 H (Spine) and 0.750 H (Chest); the hip joint centres are 0.102 H apart (about half of the
0.191 H hip width). Legs hang straight down and the spine goes straight up, so the standing height
from the bone lengths (ankle height + shank + thigh + pelvis to neck + neck to head top) is exactly H.
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, BvhJoint
from voxpose.motion.rotations import matrix_to_euler, unwrap_degrees

ROOT_CHANNELS = ("Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation")
JOINT_CHANNELS = ("Zrotation", "Xrotation", "Yrotation")
EULER_ORDER = "ZXY"

# Left side and midline of the skeleton: name, parent, OFFSET / H, End Site OFFSET / H (see the module
# docstring for the sources). The right side mirrors the left (x -> -x).
_LEFT_AND_MID = (
    ("Hips", None, (0.0, 0.0, 0.0), None),
    ("Spine", "Hips", (0.0, 0.100, 0.0), None),
    ("Chest", "Spine", (0.0, 0.120, 0.0), None),
    ("Neck", "Chest", (0.0, 0.068, 0.0), None),
    ("Head", "Neck", (0.0, 0.052, 0.0), (0.0, 0.130, 0.0)),
    ("LeftShoulder", "Chest", (0.020, 0.050, 0.0), None),
    ("LeftArm", "LeftShoulder", (0.1095, 0.018, 0.0), None),
    ("LeftForeArm", "LeftArm", (0.186, 0.0, 0.0), None),
    ("LeftHand", "LeftForeArm", (0.146, 0.0, 0.0), (0.108, 0.0, 0.0)),
    ("LeftUpLeg", "Hips", (0.051, 0.0, 0.0), None),
    ("LeftLeg", "LeftUpLeg", (0.0, -0.245, 0.0), None),
    ("LeftFoot", "LeftLeg", (0.0, -0.246, 0.0), None),
    ("LeftToe", "LeftFoot", (0.0, -0.028, 0.070), (0.0, -0.011, 0.044)),
)
HEEL = np.array([0.0, -0.039, -0.038])  # heel in the foot's frame, fraction of H


def _mirror(v):
    return None if v is None else (-v[0], v[1], v[2])


def _skeleton_rows():
    """All rows in depth-first file order: torso and head, left arm, right arm, left leg, right leg."""
    rows = {}
    for name, parent, offset, end in _LEFT_AND_MID:
        rows[name] = (name, parent, offset, end)
        if name.startswith("Left"):
            right = name.replace("Left", "Right")
            rows[right] = (right, parent.replace("Left", "Right"), _mirror(offset), _mirror(end))
    order = ["Hips", "Spine", "Chest", "Neck", "Head"]
    order += [side + s for side in ("Left", "Right") for s in ("Shoulder", "Arm", "ForeArm", "Hand")]
    order += [side + s for side in ("Left", "Right") for s in ("UpLeg", "Leg", "Foot", "Toe")]
    return [rows[n] for n in order]


_ROWS = _skeleton_rows()
JOINT_NAMES = tuple(r[0] for r in _ROWS)
JOINT_INDEX = {name: i for i, name in enumerate(JOINT_NAMES)}


def default_skeleton(height_m: float) -> list[BvhJoint]:
    """The generated subject's joints (depth-first BVH order) for a standing height ``height_m`` (metres).

    Offsets are in metres; see the module docstring for the proportions and channels.
    """
    if isinstance(height_m, bool) or not isinstance(height_m, int | float | np.floating | np.integer):
        raise VoxposeError(f"default_skeleton: height must be a number of metres, got {height_m!r}")
    height = float(height_m)
    if not (np.isfinite(height) and 0.5 <= height <= 3.0):
        raise VoxposeError(f"default_skeleton: height must be in 0.5..3.0 m, got {height_m!r}")
    joints = []
    for name, parent, offset, end in _ROWS:
        joints.append(
            BvhJoint(
                name=name,
                parent=-1 if parent is None else JOINT_INDEX[parent],
                offset=height * np.array(offset, dtype=float),
                channels=ROOT_CHANNELS if parent is None else JOINT_CHANNELS,
                end_site=None if end is None else height * np.array(end, dtype=float),
            )
        )
    return joints


def bvh_from_rotations(joints, root_position: np.ndarray, local: np.ndarray, dt: float) -> Bvh:
    """A Bvh whose channels reproduce ``local`` (n, J, 3, 3) and root positions (n, 3)."""
    euler = unwrap_degrees(matrix_to_euler(local, EULER_ORDER), axis=0)
    motion = np.concatenate([root_position, euler.reshape(len(local), -1)], axis=1)
    return Bvh(joints=joints, frame_time=dt, motion=motion)
