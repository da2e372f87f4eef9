"""Anatomical landmarks that place the body model (Section 6) the same way on every skeleton family.

Skeleton families put some joints at different anatomical points: CMU's root sits 0.07 h above its hip
joints at the lower back, Bandai's at hip level; the hip joints are 0.061 h from the midline in CMU and
0.041 h in Bandai; the shoulder joints (the upper arm's start) are 0.12-0.13 h from the midline in CMU and
0.065 h in Bandai (h: standing height; medians over the shared files). Drawn on the raw joints, the same
person would get a different pelvis, hips and shoulders on every family, and a regressor trained on one
family would learn that family's body. The body model is therefore drawn on landmarks with fixed
anatomical definitions. The elbows, wrists, knees and ankles (hinge joints every family places alike),
the head top and the standing height come from the skeleton; where families disagree, the proportions
come from the anthropometric table of Drillis and Contini (D. A. Winter, *Biomechanics and Motor Control of
Human Movement*, 4th ed., 2009, Fig. 4.1), the table the generated skeleton is built from
(``voxpose.motion.generated_skeleton``):

* pelvis centre ``P``: the midpoint of the two hip joints (not the root joint).
* hip joint centres: ``P -+ k_hip (l_hip - r_hip) / 2``, with ``k_hip`` scaling the skeleton's rest hip
  half-width to 0.051 h (hip joint centres 0.102 h apart, about half the 0.191 h hip width).
* glenohumeral centres: ``S -+ k_sh (l_sh - r_sh) / 2`` about the shoulders' midpoint ``S``, ``k_sh``
  scaling the rest half-width to 0.1295 h (half the 0.259 h biacromial width).
* base of the neck ``N``: ``P + k_neck (neck - P)``, ``k_neck`` putting it in the rest pose at 0.288 / 0.470
  of the way from ``P`` to the head top (hip joint 0.530 h, neck base 0.818 h, head top 1.000 h).
* each arm (elbow, wrist, hand tip) and leg (knee, ankle, toe) moves rigidly with its shoulder or hip
  landmark: the limbs keep the skeleton's lengths and directions and hang from anatomical shoulders and hips.

The scale factors ``k`` are constants per motion, from medians over its frames (of the hip and shoulder
separations, the pelvis centre -> neck and pelvis centre -> head top distances), so they do not depend on a
rest pose the file may not have. A factor within 0.5 % of 1 is taken as 1: that is below the scatter of
those medians, and it keeps the bodies of the generated skeleton, which is built from the same table,
exactly on its joints (its factors come out 0.998-1.002), so the embedded default is unchanged. The test
retargets a motion onto a convention with a lower-back root, narrow hips and shoulders and a higher neck
joint and compares the two bodies' voxels.
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.motion import canon

HIP_HALF_WIDTH = 0.051
"""Hip joint centre from the midline, fraction of the standing height."""
SHOULDER_HALF_WIDTH = 0.1295
"""Glenohumeral centre from the midline, fraction of the standing height."""
NECK_FRACTION = (0.818 - 0.530) / (1.000 - 0.530)
"""Base of the neck along the pelvis centre -> head top, in the rest pose."""

_I = canon.INDEX
_HEAD_TOP = canon.ENDS.index("head_top")
_ARMS = {"l": ("lelbow", "lwrist"), "r": ("relbow", "rwrist")}
_LEGS = {"l": ("lknee", "lankle"), "r": ("rknee", "rankle")}
_LIMB_ENDS = {"lhand_tip": "lshoulder", "rhand_tip": "rshoulder", "ltoe": "lhip", "rtoe": "rhip"}


TOLERANCE = 0.005
"""Scale factors closer than this to 1 are taken as 1 (module docstring)."""


def _median_distance(a, b) -> float:
    return float(np.median(np.linalg.norm(a - b, axis=-1)))


def landmark_scales(positions, ends, height, label="motion") -> dict:
    """The per-motion constants ``k`` of the module docstring: ``{"hip", "shoulder", "neck"}``."""
    pelvis = 0.5 * (positions[:, _I["lhip"]] + positions[:, _I["rhip"]])
    measured = {
        "hip": (_median_distance(positions[:, _I["lhip"]], positions[:, _I["rhip"]]), 2 * HIP_HALF_WIDTH * height),
        "shoulder": (
            _median_distance(positions[:, _I["lshoulder"]], positions[:, _I["rshoulder"]]),
            2 * SHOULDER_HALF_WIDTH * height,
        ),
        "neck": (
            _median_distance(positions[:, _I["neck"]], pelvis),
            NECK_FRACTION * _median_distance(ends[:, _HEAD_TOP], pelvis),
        ),
    }
    scales = {}
    for name, (have, want) in measured.items():
        if have < 1e-6:
            raise VoxposeError(f"body model: {label}: the {name} landmarks coincide (distance {have:.2e} m)")
        scales[name] = 1.0 if abs(want / have - 1.0) < TOLERANCE else want / have
    return scales


def anatomical_points(positions, ends, height, label="motion"):
    """Landmark joints (F, 14, 3) and ends (F, 5, 3) for the body model (module docstring).

    ``root`` becomes the pelvis centre, ``neck`` the base of the neck, the shoulders and hips the
    glenohumeral and hip joint centres; the limbs and their ends move with them; the head top is kept.
    """
    k = landmark_scales(positions, ends, height, label)
    joints, tips = positions.copy(), ends.copy()
    pelvis = 0.5 * (positions[:, _I["lhip"]] + positions[:, _I["rhip"]])
    joints[:, _I["root"]] = pelvis
    joints[:, _I["neck"]] = pelvis + k["neck"] * (positions[:, _I["neck"]] - pelvis)
    for girdle, chains in (("shoulder", _ARMS), ("hip", _LEGS)):
        left, right = positions[:, _I["l" + girdle]], positions[:, _I["r" + girdle]]
        centre, half = 0.5 * (left + right), 0.5 * (left - right)
        for side, sign in (("l", 1.0), ("r", -1.0)):
            joint = _I[side + girdle]
            shift = centre + sign * k[girdle] * half - positions[:, joint]
            for name in (side + girdle, *chains[side]):
                joints[:, _I[name]] += shift
    for end, joint in _LIMB_ENDS.items():
        tips[:, canon.ENDS.index(end)] += joints[:, _I[joint]] - positions[:, _I[joint]]
    return joints, tips
