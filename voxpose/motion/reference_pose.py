"""Leading reference-pose frames (a T- or A-pose before the motion starts), found by geometry on any rig.

Motion capture often starts with a calibration pose that is not part of the motion: CMU's cgspeed conversions
put a T-pose in frame 0 (``walk_cmu_07_12`` a second, all-zero one in frame 1), other exporters a T- or A-pose.
Such frames must not become training or test poses. They are found from the 14 canonical joints and 5 ends
(``voxpose.motion.canon``) of each frame, so the rule is the same for every skeleton family and Euler order.

A frame is a *reference pose* when, in its pelvis frame (y from the root to the neck, x from the right to the
left hip; ``canonical_pose``):

* both upper arms (shoulder -> elbow) are abducted, at least ``ARM_ABDUCTION`` (40) degrees away from the
  trunk's down direction (T-pose 90, A-pose about 45; hanging arms about 10, e.g. 10-13 in the first frames
  of the ReActIdle files), and point sideways: their outward component exceeds their forward one (arms held
  out in front are not a calibration pose);
* both elbows are straight within ``STRAIGHT_ELBOW`` (30) degrees and both knees within ``STRAIGHT_KNEE`` (20).

The *leading reference frames* are the leading run of reference poses, provided the run ends in a jump. A
step is the RMS distance between two consecutive frames' 19 points (relative to the root, each in its own
pelvis frame, so a turn of the whole body does not count), in trunk lengths (the file's median root -> neck
distance). The step out of the run is a jump when it is at least ``JUMP`` (0.5) trunk lengths, or at least
``MIN_STEP`` (0.15) and ``RATIO`` (5) times the median of the ``FOLLOWING`` (5) steps after it: captured
motion changes smoothly, so its steps are like the ones that follow them, while a reference pose is a jump to
another pose. Otherwise (no run, a run that covers the whole file, or one that blends into the motion, e.g. a
standing idle with the arms held out that come down over a few frames) there are no reference frames.

Measured on the 85 shared files (CMU at 120 fps, Bandai at 30, ReActIdle at 24): the step out of CMU's
reference frames was 0.71-1.63 trunk lengths and 25-275 times the following steps; in the motion itself no
step reached 0.34, or was at least 0.15 and more than 3.8 times the following ones, except two one-frame
capture glitches in the middle of ``irregularwalk_cmu_03_02`` (frames 24 and 50: 0.31 and 1.44 trunk lengths,
11 and 46 times the following steps). The pose test alone passes in 29 of the dance's 1901 frames (arms out,
legs straight), none of them leading. The rule drops exactly what the earlier one (leading frames whose
rotation channels are all whole numbers, CMU files only) dropped: 1 frame of every CMU file, 2 of
``walk_cmu_07_12``, none of the Bandai and ReActIdle files (tests/motion/test_shared_bvh.py); unlike it, it
still finds a reference frame after a re-export with other joint frames or Euler orders.
"""

import numpy as np

from voxpose.motion import canon

ARM_ABDUCTION = 40.0  # degrees between an upper arm and the trunk's down direction
STRAIGHT_ELBOW = 30.0  # degrees of elbow flexion
STRAIGHT_KNEE = 20.0  # degrees of knee flexion
JUMP = 0.5  # trunk lengths (RMS over the 19 points) from the last reference frame to the next frame, or
MIN_STEP = 0.15  # at least this many
RATIO = 5.0  # and this many times the median of the following steps
FOLLOWING = 5  # steps after it that the step out of the run is compared with

_J = canon.INDEX


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle in degrees between vectors (..., 3)."""
    return np.degrees(np.arccos(np.clip(np.sum(_unit(a) * _unit(b), axis=-1), -1.0, 1.0)))


def _pelvis_frames(joints: np.ndarray) -> np.ndarray:
    """(F, 3, 3) pelvis frames, columns x (to the left), y (up the trunk), z (forward)."""
    y = _unit(joints[:, _J["neck"]] - joints[:, _J["root"]])
    x = joints[:, _J["lhip"]] - joints[:, _J["rhip"]]
    x = _unit(x - np.sum(x * y, axis=-1, keepdims=True) * y)
    return np.stack([x, y, np.cross(x, y)], axis=-1)


def reference_poses(joints: np.ndarray) -> np.ndarray:
    """(F,) bool: which frames of joints (F, 14, 3) are reference (T- or A-) poses (module docstring)."""
    frames = _pelvis_frames(joints)
    ok = np.ones(joints.shape[0], dtype=bool)
    for side, outward in (("l", 1.0), ("r", -1.0)):
        shoulder, elbow, wrist = (joints[:, _J[f"{side}{j}"]] for j in ("shoulder", "elbow", "wrist"))
        hip, knee, ankle = (joints[:, _J[f"{side}{j}"]] for j in ("hip", "knee", "ankle"))
        arm = np.einsum("fba,fb->fa", frames, elbow - shoulder)  # in the pelvis frame
        ok &= _angle(arm, np.array([0.0, -1.0, 0.0])) >= ARM_ABDUCTION
        ok &= outward * arm[:, 0] > np.abs(arm[:, 2])
        ok &= _angle(elbow - shoulder, wrist - elbow) <= STRAIGHT_ELBOW
        ok &= _angle(knee - hip, ankle - knee) <= STRAIGHT_KNEE
    return ok


def pose_steps(joints: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """(F - 1,) RMS distances in trunk lengths between consecutive frames of the 19 points, each relative
    to its root in its own pelvis frame."""
    points = np.concatenate([joints, ends], axis=1) - joints[:, :1]
    local = np.einsum("fba,fpb->fpa", _pelvis_frames(joints), points)
    trunk = float(np.median(np.linalg.norm(joints[:, _J["neck"]] - joints[:, _J["root"]], axis=-1)))
    return np.sqrt(np.mean(np.sum(np.diff(local, axis=0) ** 2, axis=-1), axis=-1)) / trunk


def leading_reference_frames(joints: np.ndarray, ends: np.ndarray) -> int:
    """Number of leading reference-pose frames of a motion, joints (F, 14, 3) and ends (F, 5, 3) in any unit:
    the leading run of reference poses when it ends in a jump (module docstring)."""
    poses = reference_poses(joints)
    run = int(np.argmin(poses)) if not np.all(poses) else poses.size
    if run == 0 or run == poses.size:
        return 0
    steps = pose_steps(joints, ends)
    out, after = steps[run - 1], steps[run : run + FOLLOWING]
    jump = out >= JUMP or (out >= MIN_STEP and (after.size == 0 or out >= RATIO * float(np.median(after))))
    return run if jump else 0
