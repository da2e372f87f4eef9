"""The canonical 14-joint body of Section 2: names, tree, T-pose and the Euler convention of y'.

Every source skeleton (CMU, Bandai Namco, generated, a lab's own) is mapped onto these joints, so
everything downstream (body model, descriptors, regression, error metric) sees one body.

World frame: metres, Y up. Canonical rest ("T-pose"): the subject stands at the origin facing +Z,
arms stretched sideways, so the subject's left is +X. In that pose every canonical world rotation is
the identity.

The pose vector y' (m' = 42) holds, for each joint in ``JOINTS`` order, three Euler angles in degrees
of the joint's rotation relative to its parent in ``PARENTS`` (the root: relative to the world), both
expressed in the canonical T-pose frame. Euler orders are intrinsic and chosen per joint (``EULER_ORDERS``)
so that the middle angle, the one that locks at +-90 degrees, is one that stays small in human motion:
Y-X-Z (``R = Ry(a0) @ Rx(a1) @ Rz(a2)``, stored as ``(a0, a1, a2)``) for the root, neck, arms and ankles,
whose X rotation (pitch of the trunk, twist of an arm, ankle flexion) stays well inside +-90; X-Y-Z for
hips and knees, which flex about X far beyond 90 degrees (crouching, jumping, running) while their Y
(twist) stays small. For the root, ``a0`` is the body heading (rotation about the vertical axis, 0 when
facing +Z, positive turning towards +X).
"""

import numpy as np

JOINTS = (
    "root",  # torso centre (pelvis)
    "neck",
    "lshoulder",
    "lelbow",
    "lwrist",
    "rshoulder",
    "relbow",
    "rwrist",
    "lhip",
    "lknee",
    "lankle",
    "rhip",
    "rknee",
    "rankle",
)
N_JOINTS = len(JOINTS)
N_ANGLES = 3 * N_JOINTS  # m' = 42
INDEX = {name: i for i, name in enumerate(JOINTS)}

# Parent of each joint in the canonical tree (-1 for the root).
PARENTS = tuple(
    INDEX[p] if p else -1
    for p in (
        None,
        "root",
        "neck",
        "lshoulder",
        "lelbow",
        "neck",
        "rshoulder",
        "relbow",
        "root",
        "lhip",
        "lknee",
        "root",
        "rhip",
        "rknee",
    )
)

# End points beyond the 14 joints, needed by the body model (head sphere, hands, feet).
ENDS = ("head_top", "lhand_tip", "rhand_tip", "ltoe", "rtoe")

# Direction of the segment that each joint rotates, in the T-pose (unit vectors, world axes).
# root: pelvis -> neck; neck: neck -> head top; shoulders/elbows/wrists: along the arm;
# hips/knees: down the leg; ankles: along the foot, forward.
TPOSE_DIRECTIONS = np.array(
    [
        [0, 1, 0],
        [0, 1, 0],
        [1, 0, 0],
        [1, 0, 0],
        [1, 0, 0],
        [-1, 0, 0],
        [-1, 0, 0],
        [-1, 0, 0],
        [0, -1, 0],
        [0, -1, 0],
        [0, 0, 1],
        [0, -1, 0],
        [0, -1, 0],
        [0, 0, 1],
    ],
    dtype=float,
)

EULER_ORDERS = tuple("XYZ" if j in ("lhip", "lknee", "rhip", "rknee") else "YXZ" for j in JOINTS)

ANGLE_NAMES = tuple(f"{j}_{axis.lower()}" for j, order in zip(JOINTS, EULER_ORDERS, strict=True) for axis in order)
