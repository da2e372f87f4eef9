"""Rest-pose normalisation of the hand tips, so a wrist angle means the same on every rig (issue 18 item 2).

The wrist angles of y' (Section 2, ``voxpose.motion.canonical_pose``) point the wrist frames at the hand tips,
and skeleton families put those ends at different points: CMU's hand tip is the index finger's End Site
(knuckles), Bandai's is estimated beyond the hand joint, a rig without hands continues the forearm, another rig
may end its hand at a knuckle off the hand's axis. Such an end would read as a constant wrist bend on that rig
only (about 20 degrees for a knuckle 0.36 hand lengths off the axis, tests/motion/test_neutral_ends.py).

So each hand tip is turned, rigidly with the joint that carries it, onto the forearm's direction in the rig's
rest pose (all BVH channels zero, where every joint's world rotation is the identity): a straight hand. With
``C = minimal_rotation(tip_rest - wrist_rest, wrist_rest - elbow_rest)`` (a fixed rotation in the carrying
joint's frame, since that frame is the world's at rest) and ``W_N(t)`` the carrying joint's world rotation (the
joint whose End Site is the end, or from which it is estimated; ``joint_map``),

    tip'(t) = wrist(t) + W_N(t) C W_N(t)^T (tip(t) - wrist(t)),

i.e. the tip keeps its distance from the wrist and all the rotation it gets from its joint since the rest pose,
and loses only its rest offset from the forearm's axis. ``C`` is the identity, and nothing changes, wherever the
rest hand is straight: on every shared family (CMU, Bandai, ReActIdle, generated: wrist bend 0.0 degrees at
rest, ``benchmarks/end_angles.py``) and on any rig that lays each bone along a local axis (Bandai style).

A file whose hand tips lie on the forearms' axes in every frame records no hand rotation (``unmeasured_wrists``);
``load`` warns and lists those wrists in the motion's ``source["unmeasured"]``, so that an evaluation can leave
them out. The head top and the toes are not normalised; ``canonical_pose`` gives the numbers and the reasons.
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.motion import canon
from voxpose.motion.rotations import minimal_rotation

ANCHORS = {"lhand_tip": "lwrist", "rhand_tip": "rwrist"}
NEUTRAL = {"lhand_tip": ("lelbow", "lwrist"), "rhand_tip": ("relbow", "rwrist")}
_ZERO = 1e-9
STRAIGHT = 0.1  # degrees: a hand tip this close to the forearm's axis in every frame was not measured


def _rest_vector(vector: np.ndarray, what: str) -> np.ndarray:
    norm = np.linalg.norm(vector)
    if norm <= _ZERO:
        raise VoxposeError(f"neutral ends: {what} has zero length in the rest pose (all channels zero)")
    return vector / norm


def rest_corrections(rest_joints: np.ndarray, rest_ends: np.ndarray) -> dict[str, np.ndarray]:
    """``{end: C}`` turning each normalised end's rest direction onto its neutral one (module docstring).

    ``rest_joints`` (14, 3) and ``rest_ends`` (5, 3) are the canonical points of the rest pose.
    """
    out = {}
    for end, anchor in ANCHORS.items():
        tail, head = NEUTRAL[end]
        neutral = _rest_vector(rest_joints[canon.INDEX[head]] - rest_joints[canon.INDEX[tail]], f"{tail} -> {head}")
        measured = rest_ends[canon.ENDS.index(end)] - rest_joints[canon.INDEX[anchor]]
        out[end] = minimal_rotation(_rest_vector(measured, f"{anchor} -> {end}"), neutral)
    return out


def neutral_ends(joints: np.ndarray, ends: np.ndarray, carriers: np.ndarray, corrections: dict) -> np.ndarray:
    """The ends (F, 5, 3) with the hand tips normalised (module docstring).

    ``joints`` (F, 14, 3) and ``ends`` (F, 5, 3) are the mapped points, ``carriers`` (F, 5, 3, 3) the world
    rotations of the joints that carry the ends, ``corrections`` from ``rest_corrections``.
    """
    out = ends.copy()
    for end, c in corrections.items():
        e = canon.ENDS.index(end)
        anchor = joints[:, canon.INDEX[ANCHORS[end]]]
        w = carriers[:, e]
        turn = w @ c @ np.swapaxes(w, -1, -2)
        out[:, e] = anchor + np.einsum("fab,fb->fa", turn, ends[:, e] - anchor)
    return out


def unmeasured_wrists(joints: np.ndarray, ends: np.ndarray) -> list[str]:
    """The wrists whose hand tip lies on the forearm's axis (within ``STRAIGHT`` degrees) in every frame.

    Such a file records no hand rotation (ReActIdle has no hand joints; the lab family of issue 18 writes its
    hand channels as zeros), so its wrist angles are a straight hand, not a measurement: where other families
    record their hands, they differ by what the hands did (CMU's wrists bend 28-29 degrees on average), not by
    the definition of the angle. ``joints`` (F, 14, 3) and ``ends`` (F, 5, 3) are the normalised points.
    """
    out = []
    for end, wrist in ANCHORS.items():
        elbow = NEUTRAL[end][0]
        forearm = joints[:, canon.INDEX[wrist]] - joints[:, canon.INDEX[elbow]]
        hand = ends[:, canon.ENDS.index(end)] - joints[:, canon.INDEX[wrist]]
        cos = np.sum(forearm * hand, axis=-1) / (np.linalg.norm(forearm, axis=-1) * np.linalg.norm(hand, axis=-1))
        if joints.shape[0] and np.all(cos >= np.cos(np.radians(STRAIGHT))):
            out.append(wrist)
    return out
