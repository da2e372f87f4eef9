"""Pose errors of Section 6: Eq. 6 and the aggregates reported in Tables 1 and 2.

Eq. 6 compares a true and an estimated angle vector (degrees) angle by angle, with the wrapped absolute
difference ``min(|d|, |360 - |d||)``. We first reduce ``d`` modulo 360 (to [0, 360)), so unwrapped angles
(e.g. 710 against 10) compare correctly; every difference then lies in [0, 180].

Aggregates (``over_time`` selects how frames are combined, for each angle separately):

* ``"rms"``: root mean square over frames of the wrapped difference;
* ``"mean"``: mean over frames.

The tables report "mean (over m' = 42 angles) RMS (over time) absolute difference errors"; our reading,
and the default here, is the mean over angles of the per-angle RMS over frames: ``full_body_error``.
Per joint, the error is the mean of its three angles' per-angle errors (Table 1's left shoulder and
right hip). The body heading error is the per-angle error of the root's first Euler angle (rotation
about the vertical axis, see ``voxpose.motion.canon``). With ``over_time="mean"``, ``full_body_error`` equals
the mean over frames of Eq. 6's per-frame ``D`` (``frame_errors``).

Joint-position errors (millimetres) complement the angles: forward kinematics (``voxpose.motion.pose_kinematics``) of
both angle vectors on the subject's skeleton, root at the origin, mean Euclidean distance over the 13
joints other than the root (the root is at the origin in both, so it carries no error).
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.motion import canon
from voxpose.motion.pose_kinematics import forward_kinematics
from voxpose.validation import as_rows

_AGGREGATES = ("rms", "mean")


def _pair(y_true, y_pred, n_cols=None) -> tuple[np.ndarray, np.ndarray]:
    a = as_rows(y_true, "pose error: true angles", n_cols)
    b = as_rows(y_pred, "pose error: estimated angles", n_cols)
    if a.shape != b.shape:
        raise VoxposeError(f"pose error: true angles {a.shape} and estimated angles {b.shape} differ in shape")
    return a, b


def _over_time(diff: np.ndarray, over_time: str) -> np.ndarray:
    if over_time == "rms":
        return np.sqrt(np.mean(diff * diff, axis=0))
    if over_time == "mean":
        return np.mean(diff, axis=0)
    raise VoxposeError(f"pose error: over_time must be one of {_AGGREGATES}, got {over_time!r}")


def angle_differences(y_true, y_pred) -> np.ndarray:
    """Wrapped absolute differences (F, m') in [0, 180] degrees, the terms of Eq. 6."""
    a, b = _pair(y_true, y_pred)
    d = np.mod(a - b, 360.0)
    return np.minimum(d, 360.0 - d)


def frame_errors(y_true, y_pred) -> np.ndarray:
    """Eq. 6 per frame: ``D(y', y'_hat)``, the mean over angles of the wrapped difference, (F,) degrees."""
    return angle_differences(y_true, y_pred).mean(axis=1)


def per_angle_error(y_true, y_pred, over_time: str = "rms") -> np.ndarray:
    """Each angle's wrapped difference combined over frames (``"rms"`` or ``"mean"``), (m',) degrees."""
    return _over_time(angle_differences(y_true, y_pred), over_time)


def full_body_error(y_true, y_pred, over_time: str = "rms") -> float:
    """The tables' full-body error: mean over the m' angles of ``per_angle_error``, degrees."""
    return float(per_angle_error(y_true, y_pred, over_time).mean())


def per_joint_error(y_true, y_pred, over_time: str = "rms") -> np.ndarray:
    """Mean of each joint's three per-angle errors, (14,) degrees in ``motion.canon.JOINTS`` order."""
    a, b = _pair(y_true, y_pred, canon.N_ANGLES)
    return per_angle_error(a, b, over_time).reshape(canon.N_JOINTS, 3).mean(axis=1)


def joint_error(y_true, y_pred, joint: str, over_time: str = "rms") -> float:
    """``per_joint_error`` of one named joint (``motion.canon.JOINTS``, e.g. ``"lshoulder"``), degrees."""
    if joint not in canon.INDEX:
        raise VoxposeError(f"pose error: unknown joint {joint!r}; expected one of {', '.join(canon.JOINTS)}")
    return float(per_joint_error(y_true, y_pred, over_time)[canon.INDEX[joint]])


def heading_error(y_true, y_pred, over_time: str = "rms") -> float:
    """Body heading error: ``per_angle_error`` of the root's first Euler angle (about Y), degrees."""
    a, b = _pair(y_true, y_pred, canon.N_ANGLES)
    heading = canon.ANGLE_NAMES.index("root_y")
    return float(per_angle_error(a[:, [heading]], b[:, [heading]], over_time)[0])


def position_errors_mm(y_true, y_pred, offsets) -> np.ndarray:
    """Per frame, mean distance (mm) between the 13 non-root joints of both poses posed on ``offsets``.

    ``offsets`` (14, 3) in metres (``MotionData.offsets`` of the subject); returns (F,).
    """
    a, b = _pair(y_true, y_pred, canon.N_ANGLES)
    pos_a, _ = forward_kinematics(a, offsets)
    pos_b, _ = forward_kinematics(b, offsets)
    return 1000.0 * np.linalg.norm(pos_a[:, 1:] - pos_b[:, 1:], axis=-1).mean(axis=1)


def table_errors(y_true, y_pred, offsets=None) -> dict:
    """The columns of Table 1 with both time aggregates, plus the position error when ``offsets`` is given.

    Keys: ``full_body``, ``heading``, ``lshoulder``, ``rhip`` (RMS over frames, the tables' convention),
    the same with a ``_mean`` suffix (mean over frames), and ``position_mm`` (mean over frames).
    """
    out = {}
    for over_time, suffix in (("rms", ""), ("mean", "_mean")):
        out[f"full_body{suffix}"] = full_body_error(y_true, y_pred, over_time)
        out[f"heading{suffix}"] = heading_error(y_true, y_pred, over_time)
        for joint in ("lshoulder", "rhip"):
            out[f"{joint}{suffix}"] = joint_error(y_true, y_pred, joint, over_time)
    if offsets is not None:
        out["position_mm"] = float(position_errors_mm(y_true, y_pred, offsets).mean())
    return out


FLIP_DEGREES = 135.0


def heading_by_bin(y_true, y_pred, width: float = 30.0) -> list[dict]:
    """The heading error per bin of the true heading: [{"from", "to", "frames", "rms", "flips"}], bins of
    ``width`` degrees from 0; ``flips`` is the fraction of the bin's frames whose wrapped heading error exceeds
    ``FLIP_DEGREES`` (a front/back confusion). Bins without frames are left out."""
    a, b = _pair(y_true, y_pred, canon.N_ANGLES)
    heading = canon.ANGLE_NAMES.index("root_y")
    error = angle_differences(a[:, [heading]], b[:, [heading]])[:, 0]
    bins = np.floor(np.mod(a[:, heading], 360.0) / width).astype(int)
    rows = []
    for k in np.unique(bins):
        e = error[bins == k]
        rows.append({"from": float(k * width), "to": float((k + 1) * width), "frames": int(e.size),
                     "rms": float(np.sqrt(np.mean(e**2))), "flips": float(np.mean(e > FLIP_DEGREES))})  # fmt: skip
    return rows
