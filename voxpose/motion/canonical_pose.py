"""The pose vector y' of Section 2 (m' = 42 joint angles) from the positions of the 14 joints and 5 ends.

Section 2 parameterises a pose by 3 joint angles for each of 14 major joints (torso centre, neck,
shoulders, elbows, wrists, hips, knees, ankles) of the motion-capture skeleton. The paper uses one
skeleton; we take motion from several (CMU, Bandai Namco, generated, a lab's own), whose Euler channel
orders, rest-pose bone frames (CMU: world-aligned T-pose; Bandai: every bone along its local X, so its
zero pose is not a T-pose) and units all differ. Copying channels across rigs would give different
numbers for the same movement, so y' is defined from what all rigs share, the world positions of the 14
canonical joints and 5 ends (``voxpose.motion.canon``), and is therefore the same for the same physical motion
whatever the source rig:

* root (pelvis) frame: ``y = unit(neck - root)``; ``x = unit(lhip - rhip)`` made orthogonal to ``y``;
  ``z = x cross y`` (forward).
* neck (upper torso and head) frame: ``y = unit(head_top - neck)``; ``x = unit(lshoulder - rshoulder)``
  made orthogonal to ``y``; ``z = x cross y``.
* each limb joint ``j`` (shoulders, elbows, wrists, hips, knees, ankles) with canonical parent ``p`` and
  segment direction ``a_j`` (shoulder->elbow, elbow->wrist, wrist->hand tip, hip->knee, knee->ankle,
  ankle->toe): ``R_j = minimal_rotation(R_p @ t_j, a_j) @ R_p`` with ``t_j = canon.TPOSE_DIRECTIONS[j]``,
  i.e. the parent frame parallel-transported onto the segment (no twist relative to the parent).

In the canonical T-pose (facing +Z, left = +X, Y up) every ``R_j`` is the identity. The joint angles are
the Euler angles (per-joint orders ``motion.canon.EULER_ORDERS``: YXZ for the root, so its first angle is the body
heading; XYZ for hips and knees, so flexion beyond 90 degrees never meets gimbal lock) of the local
rotations ``Q_j = R_p^T R_j`` (root: ``Q = R_root``), in degrees, unwrapped over time.

What is lost: the twist of a limb about its own axis (e.g. forearm pronation, thigh rotation). It does
not show in joint positions and each rig's local frames define it differently, so it cannot be made
consistent across rigs; here it is zero by construction, and each limb angle triple describes only the
direction of its segment. The spine's bending between pelvis and neck is likewise summarised by the two
frames.

Ends (issue 18 item 2). The wrist, ankle and neck angles point at the hand tips, toes and head top, the points
where skeleton families differ most (``joint_map``). Measured with ``benchmarks/end_angles.py`` (bend = degrees
between the end's segment and its parent's T-pose direction; Euler X of the ankle = flexion, of the neck = pitch):

======================  ======================  =======================  =======================
family (files)          wrist bend, all frames  ankle X, all frames      neck bend, all frames
                        mean (sd) / at rest     mean (sd) / at rest      mean (sd) / at rest
======================  ======================  =======================  =======================
CMU (17)                27.7 (8.5) / 0.0        -3.5 (13.6) / 9.0        8.6 (6.9) / 2.8
Bandai (64)             21.8 (15.4) / 0.0       24.8 (15.0) / 90 *       13.5 (10.9) / 0.6
ReActIdle (4)           0.0 (0.0) / 0.0         17.5 (4.3) / 22.9        29.7 (4.2) / 8.9
generated (10)          15.2 (5.1) / 0.0        15.3 (9.2) / 18.9        2.6 (3.3) / 0.0
======================  ======================  =======================  =======================

(left side; * Bandai's zero pose lays every bone along its local X, the foot in line with the shin). Every
family's rest hand is straight: CMU's index-finger End Site lies on the forearm's axis at rest (and in its
reference frame), so CMU's 28-29 degree wrist bends are recorded hand rotation (its ``LeftFingerBase`` channels,
mean Z 15.5, Y -23.1 degrees in ``walk_cmu_07_01``), not rest geometry; Bandai records its hands too. A family
that records no hand rotation (ReActIdle has no hand joints; the lab family of issue 18 has hand joints whose
channels are all zero) has straight wrists in every frame: that difference is missing data, which no definition
of the angles can restore; ``load`` flags such wrists (``source["unmeasured"]``, ``neutral_ends.unmeasured_wrists``).
What a definition must handle is a hand end at another point of the hand, e.g. a knuckle off the hand's axis:
the hand tips are therefore normalised to the rest pose's straight hand (``voxpose.motion.neutral_ends``), which
changes no shared family (their rest hands are straight) and makes a knuckle-ended rig agree with the generated
one within 1 degree instead of 19-20 (tests/motion/test_neutral_ends.py).

The head top and the toes keep their mapped points. A rest correction needs a rest pose whose end is neutral,
and is not invariant to how a rig lays its bone frames: correcting the head to the trunk's rest direction turned
``walk_cmu_07_01``'s neck angles by up to 1.2 degrees once its bones were re-laid along their local X
(tests/motion/test_canonical_pose.py), because CMU's rest head leans 2.8 degrees (1.2-7.0 over the files) off
its root -> neck line and the re-laid rest does not. For the feet, Bandai's zero pose has no neutral foot at all,
and correcting CMU's (9-10 degrees at rest) would move its ankle mean to about -12.5, further from Bandai's 24.8.
Nor is the ankle gap in where the toe end lies: towards the ball of the foot (the toe joint, which CMU, Bandai and
the generated rig place at the same anatomical point) the walking ankle flexion averages 3.7 (CMU), 33.4 (Bandai)
and 21.5 (generated) degrees, towards the mapped toe -3.2, 26.6 and 15.1: the ~30 degree CMU-Bandai difference is
in the recorded feet. The rest knees are straight (0.0 degrees) on all four families measured; the lab family of
issue 18 (6-10 degree rest knees) is not among the shared files, and a rest correction of its knees would depend
on its bone frames as the head's does (re-laid along local axes, any rest knee is straight).

Offsets: the subject's skeleton in its own canonical frames, the median over frames of
``R_p^T (pos_j - pos_p)`` (root row zero), so that forward kinematics of y' (``voxpose.motion.pose_kinematics``)
gives back the joint positions relative to the root. Limb offsets are exact (rigid segments along
``t_j``); the neck, shoulder and hip offsets absorb the spine and clavicle motion of the source, which is
where the reconstruction differs from the source positions.
"""

from dataclasses import dataclass

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.motion import canon
from voxpose.motion.rotations import matrix_to_euler_per_joint, minimal_rotation, unwrap_degrees

_J = canon.INDEX
_E = {name: i for i, name in enumerate(canon.ENDS)}
# Limb joints in parent-before-child order, with the point their segment points to: (joint, "j"/"e", name).
_LIMBS = (
    ("lshoulder", "j", "lelbow"),
    ("lelbow", "j", "lwrist"),
    ("lwrist", "e", "lhand_tip"),
    ("rshoulder", "j", "relbow"),
    ("relbow", "j", "rwrist"),
    ("rwrist", "e", "rhand_tip"),
    ("lhip", "j", "lknee"),
    ("lknee", "j", "lankle"),
    ("lankle", "e", "ltoe"),
    ("rhip", "j", "rknee"),
    ("rknee", "j", "rankle"),
    ("rankle", "e", "rtoe"),
)
# Joints whose flexion (about X) exceeds 90 degrees: Euler branch chosen for small outer angles.
_EPS = 1e-9


@dataclass
class CanonicalPose:
    """Canonical rotations, the 42 angles and the skeleton offsets of a motion.

    Attributes
    ----------
    rotations : (F, 14, 3, 3) canonical world rotation of each joint (identity in the T-pose).
    angles : (F, 42) y' in degrees: 3 Euler angles (``canon.EULER_ORDER``) per joint, ``canon.JOINTS`` order.
    offsets : (14, 3) each joint's offset from its canonical parent in the parent's canonical frame (same
        unit as the positions; root row zero).
    """

    rotations: np.ndarray
    angles: np.ndarray
    offsets: np.ndarray


def _unit(v: np.ndarray, what: str) -> np.ndarray:
    norm = np.linalg.norm(v, axis=-1, keepdims=True)
    bad = np.flatnonzero(norm[..., 0] <= _EPS)
    if bad.size:
        raise VoxposeError(f"canonical pose: {what} has zero length in frame {bad[0]}")
    return v / norm


def _frame(y_vec: np.ndarray, x_vec: np.ndarray, what: str) -> np.ndarray:
    """Rotation with columns x, y, z from an up vector and a roughly lateral vector, (F, 3) -> (F, 3, 3)."""
    y = _unit(y_vec, f"the {what} up axis")
    x = x_vec - np.sum(x_vec * y, axis=-1, keepdims=True) * y
    x = _unit(x, f"the {what} left-right axis (parallel to its up axis)")
    return np.stack([x, y, np.cross(x, y)], axis=-1)


def canonical_rotations(positions: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Canonical world rotations (F, 14, 3, 3) from joint positions (F, 14, 3) and ends (F, 5, 3)."""
    positions = np.asarray(positions, dtype=np.float64)
    ends = np.asarray(ends, dtype=np.float64)
    n = positions.shape[0]
    if positions.shape != (n, canon.N_JOINTS, 3) or ends.shape != (n, len(canon.ENDS), 3):
        raise VoxposeError(
            f"canonical pose: expected positions (F, 14, 3) and ends (F, 5, 3), got {positions.shape} and {ends.shape}"
        )
    if not (np.all(np.isfinite(positions)) and np.all(np.isfinite(ends))):
        raise VoxposeError("canonical pose: positions or ends hold NaN or infinite values")
    pos = {name: positions[:, i] for name, i in _J.items()}
    end = {name: ends[:, i] for name, i in _E.items()}
    rot = np.empty((n, canon.N_JOINTS, 3, 3))
    rot[:, _J["root"]] = _frame(pos["neck"] - pos["root"], pos["lhip"] - pos["rhip"], "pelvis")
    rot[:, _J["neck"]] = _frame(end["head_top"] - pos["neck"], pos["lshoulder"] - pos["rshoulder"], "neck")
    for joint, kind, target in _LIMBS:
        j = _J[joint]
        r_parent = rot[:, canon.PARENTS[j]]
        segment = (pos if kind == "j" else end)[target] - pos[joint]
        direction = _unit(segment, f"segment {joint}->{target}")
        rot[:, j] = minimal_rotation(r_parent @ canon.TPOSE_DIRECTIONS[j], direction) @ r_parent
    return rot


def local_rotations(rotations: np.ndarray) -> np.ndarray:
    """Each joint's rotation relative to its canonical parent, ``Q_j = R_p^T R_j`` (root: ``R_root``)."""
    parents = np.array(canon.PARENTS)
    parent_rot = rotations[:, np.maximum(parents, 0)]
    parent_rot[:, parents < 0] = np.eye(3)
    return np.swapaxes(parent_rot, -1, -2) @ rotations


def rotations_to_angles(local: np.ndarray) -> np.ndarray:
    """Local rotations (F, 14, 3, 3) -> y' (F, 42) in degrees, unwrapped over time."""
    euler = matrix_to_euler_per_joint(local, canon.EULER_ORDERS)
    return unwrap_degrees(euler.reshape(euler.shape[0], canon.N_ANGLES), axis=0)


def canonical_pose(positions: np.ndarray, ends: np.ndarray) -> CanonicalPose:
    """Rotations, 42 angles and offsets from world joint positions (F, 14, 3) and ends (F, 5, 3)."""
    rotations = canonical_rotations(positions, ends)
    angles = rotations_to_angles(local_rotations(rotations))
    parents = np.array(canon.PARENTS)
    rel = positions[:, 1:] - positions[:, parents[1:]]
    local_rel = np.einsum("fjba,fjb->fja", rotations[:, parents[1:]], rel)
    offsets = np.zeros((canon.N_JOINTS, 3))
    offsets[1:] = np.median(local_rel, axis=0)
    return CanonicalPose(rotations=rotations, angles=angles, offsets=offsets)
