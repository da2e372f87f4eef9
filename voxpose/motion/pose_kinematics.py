"""Forward kinematics of the pose vector y' on a subject's canonical skeleton.

Used to express pose errors as joint-position errors (millimetres), which weigh an angle error by the
length of the limb it moves. With ``Euler`` the rotation of a joint's three angles in its
``motion.canon.EULER_ORDERS`` order (``voxpose.motion.rotations.euler_to_matrix_per_joint``):

    R_root = Euler(root angles),  pos_root = 0,
    R_j = R_p @ Euler(angles of j),  pos_j = pos_p + R_p @ offsets[j]   (p = canon.PARENTS[j]),

so the root sits at the origin and its rotation (heading included) turns the whole body.
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.motion import canon
from voxpose.motion.rotations import euler_to_matrix_per_joint
from voxpose.validation import as_rows


def forward_kinematics(angles, offsets) -> tuple[np.ndarray, np.ndarray]:
    """Joint positions and world rotations of y'.

    Parameters
    ----------
    angles : (F, 42) y' in degrees, ``motion.canon.JOINTS`` order, three angles each (``motion.canon.EULER_ORDERS``).
    offsets : (14, 3) each joint's offset from its canonical parent in the parent's frame (metres,
        ``MotionData.offsets``; the root row is ignored).

    Returns
    -------
    positions : (F, 14, 3) joint positions relative to the root, metres.
    rotations : (F, 14, 3, 3) world rotation of each joint.
    """
    angles = as_rows(angles, "forward kinematics: angles", canon.N_ANGLES)
    offsets = np.asarray(offsets, dtype=np.float64)
    if offsets.shape != (canon.N_JOINTS, 3) or not np.all(np.isfinite(offsets)):
        raise VoxposeError(f"forward kinematics: offsets must be finite with shape (14, 3), got {offsets.shape}")
    local = euler_to_matrix_per_joint(angles.reshape(-1, canon.N_JOINTS, 3), canon.EULER_ORDERS)
    rotations = np.empty_like(local)
    positions = np.zeros(local.shape[:2] + (3,))
    # canon.JOINTS lists every parent before its children
    for j, p in enumerate(canon.PARENTS):
        if p < 0:
            rotations[:, j] = local[:, j]
        else:
            rotations[:, j] = rotations[:, p] @ local[:, j]
            positions[:, j] = positions[:, p] + rotations[:, p] @ offsets[j]
    return positions, rotations
