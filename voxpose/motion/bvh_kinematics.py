"""Forward kinematics of a BVH skeleton: world positions and rotations of every joint in every frame.

BVH semantics (as written by CMU's, Bandai Namco's and most other exporters): joint ``j``'s local
transform is a translation followed by a rotation,

    T_j = translate(t_j) @ rotate(L_j),

where ``t_j`` is the joint's position channels (X, Y, Z) when it has them and its ``OFFSET`` otherwise
(the root's OFFSET is then ignored; in the shared data it is zero, and Bandai's non-root position channels
repeat the OFFSET), and ``L_j`` is the Euler rotation of its rotation channels in CHANNELS order
(``voxpose.motion.rotations.euler_to_matrix``). World transforms compose from the root: ``W_j = W_parent @ L_j``
and ``p_j = p_parent + W_parent @ t_j``. An End Site sits at ``p_j + W_j @ end_site``.

The loop runs over joints; every step is vectorised over frames.
"""

import numpy as np

from voxpose.io.bvh import Bvh, joint_columns, rotation_order
from voxpose.motion.rotations import euler_to_matrix


def local_transforms(bvh: Bvh) -> tuple[np.ndarray, np.ndarray]:
    """Per-frame local translations (F, J, 3) and rotations (F, J, 3, 3) of every joint, file units."""
    n_frames, n_joints = bvh.n_frames, len(bvh.joints)
    translations = np.empty((n_frames, n_joints, 3))
    rotations = np.broadcast_to(np.eye(3), (n_frames, n_joints, 3, 3)).copy()
    for j, joint in enumerate(bvh.joints):
        pos_cols, rot_cols = joint_columns(bvh, j)
        translations[:, j] = joint.offset if pos_cols is None else bvh.motion[:, pos_cols]
        if rot_cols is not None:
            rotations[:, j] = euler_to_matrix(bvh.motion[:, rot_cols], rotation_order(joint))
    return translations, rotations


def forward_kinematics(bvh: Bvh) -> tuple[np.ndarray, np.ndarray, dict[int, np.ndarray]]:
    """World positions and rotations of all joints in all frames.

    Returns
    -------
    positions : (F, J, 3) joint origins in world coordinates, file units.
    rotations : (F, J, 3, 3) world rotation of each joint's frame (columns: its local axes in world).
    end_sites : {joint index: (F, 3)} world positions of the End Sites, for joints that have one.
    """
    translations, local = local_transforms(bvh)
    positions = np.empty_like(translations)
    rotations = np.empty_like(local)
    for j, joint in enumerate(bvh.joints):
        p = joint.parent
        if p < 0:
            positions[:, j] = translations[:, j]
            rotations[:, j] = local[:, j]
        else:
            positions[:, j] = positions[:, p] + np.einsum("fab,fb->fa", rotations[:, p], translations[:, j])
            rotations[:, j] = rotations[:, p] @ local[:, j]
    end_sites = {
        j: positions[:, j] + rotations[:, j] @ joint.end_site
        for j, joint in enumerate(bvh.joints)
        if joint.end_site is not None
    }
    return positions, rotations, end_sites


def rest_pose(bvh: Bvh) -> Bvh:
    """A one-frame copy of ``bvh`` in its rest pose: position channels = OFFSETs, rotations zero.

    In the rest pose every world rotation is the identity, so world positions are sums of OFFSETs.
    """
    row = np.zeros(sum(len(j.channels) for j in bvh.joints))
    for j, joint in enumerate(bvh.joints):
        pos_cols, _ = joint_columns(bvh, j)
        if pos_cols is not None:
            row[pos_cols] = joint.offset
    return Bvh(joints=bvh.joints, frame_time=bvh.frame_time, motion=row[None, :])
