"""Load a BVH file as a ``MotionData``: the 14 canonical joints and 42 angles of Section 2, in metres.

Steps: ``io.bvh.read_bvh`` -> joint map (``joint_map``) -> forward kinematics of the whole skeleton
(``kinematics``) -> the 14 joints and 5 ends -> drop leading reference frames -> metres -> resample to
``fps`` -> canonical rotations, y' and offsets (``canonical_pose``).

Reference frames. A leading T- or A-pose unlike the frame after it (CMU's cgspeed conversions have one, and
``walk_cmu_07_12`` a second) is found by geometry on any rig (``reference_pose.leading_reference_frames``).
``drop_reference_frame="auto"`` drops those frames; ``True`` drops them and at least frame 0; ``False`` keeps
every frame.

Units. ``unit_scale`` (metres per file unit) when given; otherwise inferred from the standing height in
file units (``standing_height``): the first of 1 (metres), 0.01 (cm), 0.001 (mm), 0.0254 (inches) and
0.0254/0.45 (CMU's ASF unit, about 0.0564 m) that gives 1.4-2.1 m; if none does, the scale that makes the
subject 1.75 m, with a warning. The ranges of neighbouring units do not overlap, so at most one fits.

Standing height (file units, from bone lengths): ankle height + leg (hip -> knee -> ankle, mean of both
sides) + hip-to-pelvis drop (the hip joints' mid-point below the root along the root -> neck direction)
+ root -> neck + neck -> head top, with the ankle height taken as 0.039 of the height (Winter,
Biomechanics and Motor Control of Human Movement, 4th ed., Fig. 4.1), i.e. the sum of the measured
lengths divided by 0.961. Each length is the median over the frames of a distance between the mapped
joints and ends (a bone length for the rigid leg bones), not a distance in the rest pose: a rest pose
need not be a standing pose (Bandai's is not), and measured this way the height is the same for every
rig that writes the same motion; the price is that a bent trunk shortens root -> neck a little, so one
subject's height varies by up to 1% between motions. The shared CMU skeletons, whose trunks are short,
come out at 1.45-1.54 m; the Bandai skeletons at 1.56-1.58 m.

Resampling. Joint and end positions are resampled in time to ``fps`` by linear interpolation, from the
first frame over the whole duration; an integer ratio of frame rates (CMU 120 -> 30) takes every n-th
frame exactly. A frame time printed with few digits (0.0083333) is read as the whole frame rate it rounds
to (120) when within 0.01%. Canonical rotations and angles are then computed from the resampled positions.

Unmeasured wrists. A file whose hand tips lie on the forearms' axes in every frame records no hand rotation;
its wrists are logged with a warning and listed in ``source["unmeasured"]`` (``neutral_ends.unmeasured_wrists``).

World frame. Both shared families are Y up (and so is the generated set); a source with another up
axis would need a rotation from the config, which is not supported yet.
"""

import logging
import numbers
from pathlib import Path

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.io.bvh import read_bvh
from voxpose.motion import canon
from voxpose.motion.bvh_kinematics import forward_kinematics
from voxpose.motion.canonical_pose import canonical_pose
from voxpose.motion.data import MotionData, kind_of
from voxpose.motion.joint_map import resolve_joint_map, skeleton_points
from voxpose.motion.neutral_ends import unmeasured_wrists
from voxpose.motion.reference_pose import leading_reference_frames

log = logging.getLogger(__name__)

KNOWN_UNITS = (1.0, 0.01, 0.001, 0.0254, 0.0254 / 0.45)
HEIGHT_RANGE = (1.4, 2.1)
FALLBACK_HEIGHT = 1.75
ANKLE_HEIGHT_FRACTION = 0.039


def standing_height(joints: np.ndarray, ends: np.ndarray) -> float:
    """Standing height from world joints (F, 14, 3) and ends (F, 5, 3), in their unit (module docstring)."""
    p = {name: joints[:, i] for name, i in canon.INDEX.items()}
    dist = lambda a, b: float(np.median(np.linalg.norm(a - b, axis=-1)))  # noqa: E731
    leg = 0.5 * sum(dist(p[f"{s}hip"], p[f"{s}knee"]) + dist(p[f"{s}knee"], p[f"{s}ankle"]) for s in "lr")
    spine = p["neck"] - p["root"]
    length = np.linalg.norm(spine, axis=-1)
    if np.any(length <= 0.0):
        raise VoxposeError("standing height: the root and neck joints coincide")
    below = np.sum((p["root"] - 0.5 * (p["lhip"] + p["rhip"])) * spine, axis=-1) / length
    head = dist(ends[:, canon.ENDS.index("head_top")], p["neck"])
    total = leg + max(float(np.median(below)), 0.0) + float(np.median(length)) + head
    return total / (1.0 - ANKLE_HEIGHT_FRACTION)


def infer_unit(height_units: float) -> tuple[float, str]:
    """Metres per file unit for a subject ``height_units`` tall, and how it was chosen."""
    for unit in KNOWN_UNITS:
        if HEIGHT_RANGE[0] <= height_units * unit <= HEIGHT_RANGE[1]:
            return unit, "inferred"
    return FALLBACK_HEIGHT / height_units, "fallback"


def source_frame_rate(frame_time: float) -> float:
    """Frames per second of a file, snapped to a whole number when within 0.01% of one."""
    rate = 1.0 / frame_time
    return float(round(rate)) if round(rate) > 0 and abs(rate - round(rate)) <= 1e-4 * rate else rate


def resample(values: np.ndarray, source_fps: float, fps: float) -> np.ndarray:
    """Linear resampling along axis 0 from ``source_fps`` to ``fps``, starting at the first frame.

    The output covers the input's duration: ``floor((F - 1) * fps / source_fps) + 1`` frames. An integer
    ratio of rates takes every n-th frame exactly.
    """
    n_in = values.shape[0]
    step = source_fps / fps
    n_out = int(np.floor((n_in - 1) / step + 1e-9)) + 1
    if abs(step - round(step)) < 1e-9:
        return values[:: int(round(step))][:n_out].copy()
    s = np.arange(n_out) * step
    i0 = np.minimum(np.floor(s).astype(int), max(n_in - 2, 0))
    w = (s - i0).reshape((-1,) + (1,) * (values.ndim - 1))
    i1 = np.minimum(i0 + 1, n_in - 1)
    return (1.0 - w) * values[i0] + w * values[i1]


def _positive(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and 0 < value < np.inf


def _frames_to_drop(joints: np.ndarray, ends: np.ndarray, option, path: Path) -> int:
    if option == "auto":
        return leading_reference_frames(joints, ends)
    if option is True:
        return max(leading_reference_frames(joints, ends), 1)
    if option is False:
        return 0
    raise VoxposeError(f"{path}: drop_reference_frame must be auto, true or false, got {option!r}")


def load_motion(path, *, fps=30.0, unit_scale=None, joint_map=None, drop_reference_frame="auto") -> MotionData:
    """Read a BVH file and map it onto the canonical body (Section 2), resampled to ``fps``.

    Parameters
    ----------
    path : BVH file; its stem is the motion's name and the stem's part before the first ``_`` its kind.
    fps : output frame rate (frames per second).
    unit_scale : metres per file unit, or None to infer it from the standing height.
    joint_map : ``{canonical name: source joint}`` for skeletons without a preset (``joint_map``).
    drop_reference_frame : ``"auto"``, True or False (see the module docstring).
    """
    path = Path(path)
    if not _positive(fps):
        raise VoxposeError(f"{path}: fps must be a positive number, got {fps!r}")
    if unit_scale is not None and not _positive(unit_scale):
        raise VoxposeError(f"{path}: unit_scale must be a positive number of metres per unit, got {unit_scale!r}")
    bvh = read_bvh(path)
    jmap = resolve_joint_map(bvh, joint_map, source=str(path))
    joints, ends = skeleton_points(bvh, jmap, forward_kinematics(bvh))
    dropped = _frames_to_drop(joints, ends, drop_reference_frame, path)
    if dropped >= bvh.n_frames:
        raise VoxposeError(f"{path}: no motion frames left after dropping {dropped} reference frame(s)")
    joints, ends = joints[dropped:], ends[dropped:]

    height_units = standing_height(joints, ends)
    if unit_scale is not None:
        scale, how = float(unit_scale), "given"
    else:
        scale, how = infer_unit(height_units)
        message = "%s: unit %.5g m %s from a standing height of %.1f units -> %.2f m"
        level = logging.WARNING if how == "fallback" else logging.INFO
        log.log(level, message, path.stem, scale, how, height_units, height_units * scale)

    source_fps = source_frame_rate(bvh.frame_time)
    joints = resample(joints * scale, source_fps, float(fps))
    ends = resample(ends * scale, source_fps, float(fps))
    pose = canonical_pose(joints, ends)
    unmeasured = unmeasured_wrists(joints, ends)
    if unmeasured:
        log.warning(
            "%s: the hand tips lie on the forearms' axes in every frame (%s): the file records no hand rotation, "
            "so these wrist angles are a straight hand, not a measurement",
            path.stem,
            ", ".join(unmeasured),
        )
    return MotionData(
        name=path.stem,
        kind=kind_of(path.stem),
        fps=float(fps),
        positions=joints,
        rotations=pose.rotations,
        angles=pose.angles,
        ends=ends,
        offsets=pose.offsets,
        height=height_units * scale,
        source={
            "path": str(path),
            "skeleton": jmap.preset,
            "unit_scale": scale,
            "unit_from": how,
            "dropped_frames": dropped,
            "source_frames": bvh.n_frames,
            "source_fps": source_fps,
            "unmeasured": unmeasured,
        },
    )
