"""The body model of Section 6 on the output skeleton, posed by angles y': what an estimate looks like in 3D.

The joints are the forward kinematics of y' on the model's output skeleton (``voxpose.motion.pose_kinematics``,
root at the origin, heading included); each end (head top, hand tips, toes) lies ``end_lengths`` from its
joint along that joint's T-pose direction, turned by the joint's rotation, exactly where the BVH written by
``OutputSkeleton.bvh`` puts it. The solids (``voxpose.voxels.body``, default proportions) scale with the
skeleton's standing height (``voxpose.motion.load.standing_height`` of its T-pose), so this is the body
that ``voxpose voxelize`` would carve for a subject with this skeleton in this pose.
"""

import numpy as np

from voxpose.motion import canon
from voxpose.motion.load import standing_height
from voxpose.motion.output_skeleton import OutputSkeleton
from voxpose.motion.pose_kinematics import forward_kinematics
from voxpose.voxels.body import Ellipsoids, body_ellipsoids

# the joint each end hangs from (the output skeleton's End Sites)
_ANCHORS = [canon.INDEX[j] for j in ("neck", "lwrist", "rwrist", "lankle", "rankle")]


def pose_arrays(angles, skeleton: OutputSkeleton, root=None) -> dict:
    """Positions (F, 14, 3), rotations (F, 14, 3, 3), ends (F, 5, 3) and height of y' (F, 42) degrees on
    ``skeleton`` with the root at ``root`` (F, 3) metres (default: the origin): ``body_ellipsoids``' input."""
    positions, rotations, ends = _joints_and_ends(angles, skeleton)
    if root is not None:
        shift = np.asarray(root, dtype=float)[:, None, :]
        positions, ends = positions + shift, ends + shift
    return {"positions": positions, "rotations": rotations, "ends": ends, "height": skeleton_height(skeleton)}


def skeleton_height(skeleton: OutputSkeleton) -> float:
    """Standing height (metres) of the skeleton's T-pose (all angles 0)."""
    positions, _, ends = _joints_and_ends(np.zeros((1, canon.N_ANGLES)), skeleton)
    return standing_height(positions, ends)


def subject_skeleton(skeleton: OutputSkeleton, height: float) -> OutputSkeleton:
    """``skeleton`` scaled to a subject ``height`` metres tall (``h_sub``, Section 4): the model's output
    skeleton has its training subjects' size, and a body of the wrong size fits the hull best at a root
    displaced by about half the difference in height."""
    return skeleton.scaled(height / skeleton_height(skeleton))


def posed_body(angles, skeleton: OutputSkeleton, root=None) -> Ellipsoids:
    """The solids (F, 16) of y' (F, 42) on ``skeleton`` (module docstring), root at ``root`` or the origin."""
    return body_ellipsoids(pose_arrays(angles, skeleton, root))


def _joints_and_ends(angles, skeleton: OutputSkeleton):
    """Joint positions, rotations and ends of y', root at the origin (module docstring)."""
    positions, rotations = forward_kinematics(angles, skeleton.offsets)
    bones = np.asarray(skeleton.end_lengths)[:, None] * canon.TPOSE_DIRECTIONS[_ANCHORS]  # (5, 3)
    ends = positions[:, _ANCHORS] + np.einsum("feij,ej->fei", rotations[:, _ANCHORS], bones)
    return positions, rotations, ends
