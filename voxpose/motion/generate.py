"""Synthetic motions of the paper's five types, written as genuine BVH files (Section 6, Table 2).

Section 6 trains and tests on motion capture of five types: regular walking, drunken walking, spiral
walking, jogging and jumping (Table 2). When no capture is at hand the workflow runs on motions made
here (``walk``, ``drunk``, ``spiral``, ``jog``, ``jump``), written as BVH files that go through the same
reader, forward kinematics and joint mapping as real data. The paper prescribes none of this; it is a
stand-in for its MOCAP data, kept as plausible as a small kinematic model allows.

Skeleton (``default_skeleton``)
-------------------------------
21 joints with CMU-like names (Hips root with 6 channels; Spine, Chest, Neck, Head; Left/Right Shoulder
(clavicle), Arm, ForeArm, Hand; Left/Right UpLeg, Leg, Foot, Toe; End Sites on Head, hands and toes),
in metres, rest pose a T-pose standing on y = 0, facing +Z, Y up, the subject's left along +X
(``voxpose.motion.canon``). Joint rotations use the channels ``Zrotation Xrotation Yrotation`` (R = Rz Rx Ry), on
purpose not CMU's order. Segment lengths are fractions of the standing height H from the
anthropometric table of Drillis and Contini as given by D. A. Winter, *Biomechanics and Motor Control of
Human Movement* (4th ed., 2009, Fig. 4.1): hip joint 0.530 H above the floor (thigh 0.245 H, shank
0.246 H, ankle 0.039 H), shoulder 0.818 H with a biacromial width of 0.259 H, chin 0.870 H, upper arm
0.186 H, forearm 0.146 H, hand 0.108 H, foot 0.152 H (ankle 0.038 H in front of the heel). The spine is
split at 0.630 H (Spine) and 0.750 H (Chest); the hip joint centres are 0.102 H apart (about half of the
0.191 H hip width). Legs hang straight down and the spine goes straight up, so the standing height
from the bone lengths (ankle height + shank + thigh + pelvis to neck + neck to head top) is exactly H.

Gait model (``walk``, ``drunk``, ``spiral``, ``jog``)
-----------------------------------------------------
Pose. A stride phase p(t) = integral of the cadence (strides per second), left heel strike at p = 0,
the right leg half a stride later. Hip, knee, ankle and toe flexion are periodic shape-preserving
(PCHIP) interpolants through keyframes of normative curves in percent of the stride (``_WALK_CURVES``
after Winter's and Perry's walking data, ``_JOG_CURVES`` after Novacheck 1998); PCHIP does not
overshoot, so the curves stay inside their keyframes' range. The stance part of the hip curves was
solved once (planar, at the mean parameters) so that a planted foot moves back at a constant speed
under the pelvis, the swing part is normative. The stride scale widens the hip excursion about its mean.
Around the legs: pelvic rotation (yaw) and obliquity (roll) at the stride frequency and a small tilt at
the step frequency; a sideways sway (both legs tilted together in the frontal plane) that carries the
pelvis over the stance foot; the legs' frontal angle cancels the pelvic roll plus a constant stance
width; the thorax counter-rotates against the pelvis (split over Spine and Chest) and leans forward; the
neck keeps the head facing ahead; each shoulder swings in counter-phase with its own leg and the elbow
flexes more as the arm comes forward. Knee flexion stays below 90 degrees, so the middle (X) angle of
every ZXY triple stays inside (-90, 90) and the written angles are continuous.

Ground and root. Each foot has three contact points: the heel (0.039 H below and 0.038 H behind the
ankle, in the foot's frame), the ball (toe joint) and the toe tip (End Site). A foot is in stance for
the first ``duty`` of its stride (0.60 walking, 0.38 jogging, which leaves two flights per stride). With
the pose's forward kinematics in the heading frame (root at the origin, walking along +Z):
the root height is the one that puts the lowest contact point of the feet in stance on y = 0 (the
root height comes from the stance leg); in flight the root follows a ballistic parabola
(g = 9.81 m/s^2) between the take-off and landing heights. The root's horizontal step is, per stance,
the mean of the steps that keep that foot's lowest point fixed (``_steady_steps``: averaged over both
feet in double support, interpolated in flight), smoothed over 0.25 s forward and 0.1 s sideways, so the
pelvis advances steadily and sways; walking speed is therefore not drawn directly but follows from the
drawn cadence, stride scale and height. The steps are turned by the heading psi(t) into the world and
summed from the drawn start position.

Feet (``_place_feet``). What the smoothing leaves is removed by a two-link leg IK (``leg_ik``): a stance
foot is moved back by its lowest point's drift since heel strike, so it stays planted (the hold eases
out over 0.1 s after toe-off); a swing foot is lifted just enough to clear the ground by 1 cm; a foot
the stretched leg cannot reach rolls heel-up about its ball (``_toe_rocker``). Foot orientations are
kept, so contact heights do not change.

The types. ``walk``: a steady turn (15-30 degrees per second, left or right: a circle of 2.5-5 m
radius, a turning walk). ``jog``: running curves (more knee and elbow flexion, flight phases), faster cadence, more
forward lean, turning like ``walk``. Why every type turns: the 3D shape contexts are aligned with the world
(Section 4), so the regressor can only recognise a body heading that its training frames cover; the
paper's training set includes turning walks (Section 6), and a few straight sequences would cover a few
headings only; the default set also centres each sequence's arc on its own slot of the circle
(``default_heading``). ``spiral``: walking whose heading follows the tangent of a
spiral of shrinking radius (``spiral_heading``: the radius of curvature falls linearly with the
distance walked, from r_start (3-4.5 m) to r_end (1-1.6 m) over the sequence), turning left or right,
the trunk leaning into the turn by atan(v^2 / (g r)). ``drunk``: walking with a wandering heading
(``random_walk_heading``, 25-35 degrees per sqrt(s)), irregular cadence and step length, a large irregular
sideways sway, a wider stance, a smooth random torso lean and head roll, arms held away from the body.
``jump``: repeated jumps (``_jump_plan``): stand, crouch with the arms back, push-off with the arms
swinging over the head, a ballistic flight (0.12-0.35 m high, up to 0.5 m forward, a turn of 15-40
degrees, the same way for the whole sequence), landing and recovery; both feet stay planted on the
ground between flights.

Per-sequence variation comes from the seed: height (1.5-2.0 m), cadence, stride scale (hence speed and
stride length), arm swing amplitude, heading (unless given) and start position (within 1 m of the origin), and each
type's own parameters. Everything is vectorised over frames; 1.5 s are simulated before and after the
requested frames so that flights, smoothing and noise have context at both ends.
"""

import logging
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import PchipInterpolator
from scipy.ndimage import gaussian_filter1d

from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, BvhJoint
from voxpose.motion.bvh_kinematics import forward_kinematics
from voxpose.motion.rotations import axis_angle_to_matrix, axis_rotation, matrix_to_euler, unwrap_degrees

log = logging.getLogger(__name__)

KINDS = ("walk", "drunk", "spiral", "jog", "jump")
GRAVITY = 9.81  # m/s^2
HEIGHT_RANGE = (1.5, 2.0)  # metres, drawn uniformly when no height is given
ROOT_CHANNELS = ("Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation")
JOINT_CHANNELS = ("Zrotation", "Xrotation", "Yrotation")
EULER_ORDER = "ZXY"

# Left side and midline of the skeleton: name, parent, OFFSET / H, End Site OFFSET / H (see the module
# docstring for the sources). The right side mirrors the left (x -> -x).
_LEFT_AND_MID = (
    ("Hips", None, (0.0, 0.0, 0.0), None),
    ("Spine", "Hips", (0.0, 0.100, 0.0), None),
    ("Chest", "Spine", (0.0, 0.120, 0.0), None),
    ("Neck", "Chest", (0.0, 0.068, 0.0), None),
    ("Head", "Neck", (0.0, 0.052, 0.0), (0.0, 0.130, 0.0)),
    ("LeftShoulder", "Chest", (0.020, 0.050, 0.0), None),
    ("LeftArm", "LeftShoulder", (0.1095, 0.018, 0.0), None),
    ("LeftForeArm", "LeftArm", (0.186, 0.0, 0.0), None),
    ("LeftHand", "LeftForeArm", (0.146, 0.0, 0.0), (0.108, 0.0, 0.0)),
    ("LeftUpLeg", "Hips", (0.051, 0.0, 0.0), None),
    ("LeftLeg", "LeftUpLeg", (0.0, -0.245, 0.0), None),
    ("LeftFoot", "LeftLeg", (0.0, -0.246, 0.0), None),
    ("LeftToe", "LeftFoot", (0.0, -0.028, 0.070), (0.0, -0.011, 0.044)),
)
_HEEL = np.array([0.0, -0.039, -0.038])  # heel in the foot's frame, fraction of H
_STEADY_S = 0.25  # seconds: smoothing of the gaits' root steps (removes the step-frequency lurch)
_RAMP_S = 0.1  # seconds: a foot's hold eases out after toe-off; the swing clearance ramps in and out


def _mirror(v):
    return None if v is None else (-v[0], v[1], v[2])


def _skeleton_rows():
    """All rows in depth-first file order: torso and head, left arm, right arm, left leg, right leg."""
    rows = {}
    for name, parent, offset, end in _LEFT_AND_MID:
        rows[name] = (name, parent, offset, end)
        if name.startswith("Left"):
            right = name.replace("Left", "Right")
            rows[right] = (right, parent.replace("Left", "Right"), _mirror(offset), _mirror(end))
    order = ["Hips", "Spine", "Chest", "Neck", "Head"]
    order += [side + s for side in ("Left", "Right") for s in ("Shoulder", "Arm", "ForeArm", "Hand")]
    order += [side + s for side in ("Left", "Right") for s in ("UpLeg", "Leg", "Foot", "Toe")]
    return [rows[n] for n in order]


_ROWS = _skeleton_rows()
JOINT_NAMES = tuple(r[0] for r in _ROWS)
_J = {name: i for i, name in enumerate(JOINT_NAMES)}


def default_skeleton(height_m: float) -> list[BvhJoint]:
    """The generated subject's joints (depth-first BVH order) for a standing height ``height_m`` (metres).

    Offsets are in metres; see the module docstring for the proportions and channels.
    """
    if isinstance(height_m, bool) or not isinstance(height_m, int | float | np.floating | np.integer):
        raise VoxposeError(f"default_skeleton: height must be a number of metres, got {height_m!r}")
    height = float(height_m)
    if not (np.isfinite(height) and 0.5 <= height <= 3.0):
        raise VoxposeError(f"default_skeleton: height must be in 0.5..3.0 m, got {height_m!r}")
    joints = []
    for name, parent, offset, end in _ROWS:
        joints.append(
            BvhJoint(
                name=name,
                parent=-1 if parent is None else _J[parent],
                offset=height * np.array(offset, dtype=float),
                channels=ROOT_CHANNELS if parent is None else JOINT_CHANNELS,
                end_site=None if end is None else height * np.array(end, dtype=float),
            )
        )
    return joints


# ---------------------------------------------------------------------------------------------------
# Gait curves: (percent of the stride from the left heel strike, degrees), first and last value equal.
# Hip flexion: thigh forward; knee flexion; ankle dorsiflexion (toes up, negative = plantarflexion);
# toe extension at the ball of the foot (heel rise with the toes flat).
_WALK_CURVES = {
    "hip": (
        (0, 25),
        (6, 23.6),
        (12, 22.5),
        (16, 19.1),
        (20, 14),
        (24, 8.1),
        (28, 2),
        (32, -3.6),
        (36, -8.3),
        (40, -11.1),
        (44, -10.1),
        (50, -6.8),
        (56, -4.8),
        (60, -4),
        (70, 16),
        (85, 27),
        (100, 25),
    ),
    "knee": ((0, 4), (15, 18), (38, 6), (50, 29), (62, 46), (71, 64), (82, 45), (92, 12), (100, 4)),
    "ankle": ((0, 0), (8, -6), (30, 6), (44, 10), (50, 5), (60, -14), (67, -5), (75, 3), (88, 2), (100, 0)),
    "toe": ((0, 0), (40, 0), (52, 32), (62, 26), (72, 18), (85, 8), (95, 0), (100, 0)),
}
_JOG_CURVES = {
    "hip": (
        (0, 32),
        (6, 29.8),
        (12, 28.8),
        (16, 24.6),
        (20, 18.2),
        (24, 11.2),
        (28, 4.5),
        (32, -2),
        (36, -7.8),
        (38, -10),
        (55, 5),
        (85, 38),
        (100, 32),
    ),
    "knee": ((0, 18), (15, 40), (38, 20), (50, 62), (70, 88), (90, 30), (100, 18)),
    "ankle": ((0, 2), (15, 18), (38, -22), (48, -12), (80, 8), (100, 2)),
    "toe": ((0, 0), (28, 0), (38, 25), (48, 0), (100, 0)),
}


@dataclass(frozen=True)
class _Gait:
    """Parameters of one gait style; pairs are ranges drawn uniformly per sequence (degrees unless noted)."""

    curves: dict
    duty: float  # fraction of the stride each foot is on the ground
    cadence: tuple[float, float]  # strides per second
    stride: tuple[float, float]  # scale of the hip flexion excursion about its mean
    arm_swing: tuple[float, float]  # shoulder flexion amplitude
    arm_abduction: tuple[float, float]  # arm held away from the trunk
    elbow: float  # mean elbow flexion
    elbow_swing: float  # extra elbow flexion with the arm forward
    trunk_pitch: float  # forward lean of the thorax
    pelvis_yaw: float
    pelvis_roll: float
    pelvis_tilt: float  # step-frequency oscillation
    sway: tuple[float, float]  # frontal tilt of both legs moving the pelvis over the stance foot
    stance_width: float  # hip abduction of each leg


_WALK = dict(curves=_WALK_CURVES, duty=0.60, pelvis_yaw=4.0, pelvis_roll=4.0, pelvis_tilt=1.5)
_GAITS = {
    "walk": _Gait(
        **_WALK,
        cadence=(0.85, 1.05),
        stride=(0.85, 1.15),
        arm_swing=(12, 24),
        arm_abduction=(7, 10),
        elbow=18,
        elbow_swing=12,
        trunk_pitch=3,
        sway=(2, 3),
        stance_width=0,
    ),
    "drunk": _Gait(
        **_WALK,
        cadence=(0.70, 0.90),
        stride=(0.75, 1.0),
        arm_swing=(6, 16),
        arm_abduction=(16, 24),
        elbow=20,
        elbow_swing=8,
        trunk_pitch=6,
        sway=(5, 8),
        stance_width=3,
    ),
    "jog": _Gait(
        curves=_JOG_CURVES,
        duty=0.38,
        pelvis_yaw=6.0,
        pelvis_roll=5.0,
        pelvis_tilt=2.0,
        cadence=(1.30, 1.50),
        stride=(0.90, 1.10),
        arm_swing=(20, 32),
        arm_abduction=(12, 16),
        elbow=70,
        elbow_swing=15,
        trunk_pitch=9,
        sway=(1.5, 2.5),
        stance_width=0,
    ),
}
_GAITS["spiral"] = _GAITS["walk"]


def _periodic_curve(keys, phase: np.ndarray) -> np.ndarray:
    """PCHIP through ``(percent, value)`` keyframes repeated every 100 percent, at ``phase`` (strides)."""
    pct, val = np.asarray(keys, dtype=float).T
    x = np.concatenate([pct[:-1] - 100, pct, pct[1:] + 100])
    y = np.concatenate([val[:-1], val, val[1:]])
    return PchipInterpolator(x, y)(100.0 * np.mod(phase, 1.0))


def smooth_noise(rng: np.random.Generator, n: int, sigma_frames: float) -> np.ndarray:
    """(n,) stationary Gaussian process with unit variance: white noise smoothed by a Gaussian kernel.

    The normalisation is the analytic one (a unit-sum Gaussian kernel of width ``sigma_frames`` leaves a
    variance of 1 / (2 sqrt(pi) sigma)), so the scale does not depend on the length drawn.
    """
    sigma = max(float(sigma_frames), 1.0)
    return gaussian_filter1d(rng.standard_normal(n), sigma, mode="reflect") * np.sqrt(2 * np.sqrt(np.pi) * sigma)


def random_walk_heading(rng: np.random.Generator, n: int, dt: float, rate: float, smooth_s: float = 0.5) -> np.ndarray:
    """(n,) heading wander in degrees: a Gaussian-smoothed random walk starting at 0.

    ``rate`` is the random walk's diffusion in degrees per sqrt(second) (after T seconds its standard
    deviation is ``rate * sqrt(T)``); ``smooth_s`` (seconds) removes frame-to-frame jitter.
    """
    walk = np.cumsum(rng.standard_normal(n) * rate * np.sqrt(dt))
    walk = gaussian_filter1d(walk, max(smooth_s / dt, 1.0), mode="nearest")
    return walk - walk[0]


def spiral_heading(arc_length, *, r_start: float, r_end: float, length: float) -> np.ndarray:
    """Heading change (radians, turning one way) after walking ``arc_length`` along a shrinking spiral.

    The path's radius of curvature falls linearly with arc length s from ``r_start`` at s = 0 to
    ``r_end`` at s = ``length`` and stays ``r_end`` beyond (a circle), so the curvature 1/r grows along
    the path. The heading is the integral of the curvature:
    psi(s) = length / (r_end - r_start) * ln(r(s) / r_start), or s / r_start for a constant radius.
    Arc lengths and radii share one unit; negative arc lengths use the radius ``r_start``.
    """
    if not (r_start > 0 and r_end > 0 and length > 0):
        raise VoxposeError(f"spiral: r_start, r_end and length must be positive, got {r_start}, {r_end}, {length}")
    s = np.asarray(arc_length, dtype=float)
    inside = np.clip(s, 0.0, length)
    if np.isclose(r_start, r_end):
        psi = inside / r_start
    else:
        radius = r_start + (r_end - r_start) * inside / length
        psi = length / (r_end - r_start) * np.log(radius / r_start)
    return psi + (s - inside) / np.where(s > length, r_end, r_start)


def spiral_radius(arc_length, *, r_start: float, r_end: float, length: float) -> np.ndarray:
    """Radius of curvature of the ``spiral_heading`` path at ``arc_length``."""
    s = np.clip(np.asarray(arc_length, dtype=float), 0.0, length)
    return r_start + (r_end - r_start) * s / length


# ---------------------------------------------------------------------------------------------------
def _rot(axis: str, degrees) -> np.ndarray:
    return axis_rotation(axis, degrees)


def _local_rotations(a: dict, n: int) -> np.ndarray:
    """(n, J, 3, 3) local joint rotations from named anatomical angles (degrees, arrays of shape (n,)).

    Axes in the T-pose frame: flexion of hip, shoulder, toe and dorsiflexion are rotations about -X,
    knee flexion about +X, elbow flexion about -Y (left) / +Y (right), abduction about Z.
    """
    rot = np.broadcast_to(np.eye(3), (n, len(JOINT_NAMES), 3, 3)).copy()
    rot[:, _J["Hips"]] = _rot("Y", a["pelvis_yaw"]) @ _rot("X", a["pelvis_tilt"]) @ _rot("Z", a["pelvis_roll"])
    half = _rot("Y", a["torso_yaw"] / 2) @ _rot("X", a["torso_pitch"] / 2) @ _rot("Z", a["torso_roll"] / 2)
    rot[:, _J["Spine"]] = half
    rot[:, _J["Chest"]] = half
    rot[:, _J["Neck"]] = _rot("Y", a["neck_yaw"]) @ _rot("X", a["neck_pitch"]) @ _rot("Z", a["neck_roll"])
    for side, sign in (("Left", 1.0), ("Right", -1.0)):
        s = side[0].lower()
        rot[:, _J[side + "Shoulder"]] = _rot("Z", sign * a["clavicle"])
        rot[:, _J[side + "Arm"]] = _rot("X", -a[f"shoulder_{s}"]) @ _rot("Z", -sign * (90.0 - a["arm_abduction"]))
        rot[:, _J[side + "ForeArm"]] = _rot("Y", -sign * a[f"elbow_{s}"])
        rot[:, _J[side + "UpLeg"]] = _rot("Z", a[f"frontal_{s}"]) @ _rot("X", -a[f"hip_{s}"])
        rot[:, _J[side + "Leg"]] = _rot("X", a[f"knee_{s}"])
        rot[:, _J[side + "Foot"]] = _rot("X", -a[f"ankle_{s}"])
        rot[:, _J[side + "Toe"]] = _rot("X", -a[f"toe_{s}"])
    return rot


@dataclass
class _Plan:
    """The pose over the padded time grid, before the root trajectory is known."""

    angles: dict  # named anatomical angles, (n,) degrees each
    stance: np.ndarray  # (n, 2) True while the left / right foot may bear weight
    flight_speed: np.ndarray  # (n,) extra forward speed in flight (m/s)
    turn: np.ndarray  # (n,) heading change not tied to the path (degrees)
    smooth_s: float  # Gaussian width (seconds) smoothing the root's horizontal steps; 0 = none


def _gait_plan(kind: str, rng: np.random.Generator, t: np.ndarray, turn_rate: float | None = None) -> _Plan:
    """Angles of a walking or jogging gait (``walk``, ``drunk``, ``spiral``, ``jog``) at times ``t``."""
    g = _GAITS[kind]
    n, dt = len(t), t[1] - t[0]
    u = rng.uniform
    cadence, stride, swing = u(*g.cadence), u(*g.stride), u(*g.arm_swing)
    abduction, sway_amp = u(*g.arm_abduction), u(*g.sway)
    zeros = np.zeros(n)
    drunk = kind == "drunk"
    if drunk:  # irregular cadence and step length, staggering, torso lean, head roll, heading wander
        sec = 1.0 / dt
        rate = cadence * (1 + 0.12 * smooth_noise(rng, n, 1.0 * sec))
        stride_t = np.clip(stride * (1 + 0.2 * smooth_noise(rng, n, 0.8 * sec)), 0.5, 1.3)
        sway_mod = 1 + 0.35 * smooth_noise(rng, n, 1.0 * sec)
        stagger = 3.0 * smooth_noise(rng, n, 0.6 * sec)
        lean_roll = 8.0 * smooth_noise(rng, n, 1.5 * sec)
        lean_pitch = 3.0 * smooth_noise(rng, n, 1.5 * sec)
        head_roll = 6.0 * smooth_noise(rng, n, 1.0 * sec)
        arm_noise = 5.0 * smooth_noise(rng, n, 1.0 * sec)
        turn = random_walk_heading(rng, n, dt, rate=u(25.0, 35.0), smooth_s=0.5)
    else:
        rate, stride_t, sway_mod = np.full(n, cadence), np.full(n, stride), np.ones(n)
        stagger = lean_roll = lean_pitch = head_roll = arm_noise = zeros
        # steady turn (see the module docstring); the spiral replaces it by its own heading
        drawn = rng.choice([-1.0, 1.0]) * u(15.0, 30.0)
        turn = zeros if kind == "spiral" else (drawn if turn_rate is None else turn_rate) * (t - t[0])
    phase = rng.uniform() + np.concatenate([[0.0], np.cumsum((rate[1:] + rate[:-1]) / 2 * dt)])
    cos = np.cos

    a: dict[str, np.ndarray] = {}
    hip_mean = np.mean(np.asarray(g.curves["hip"], dtype=float)[:-1, 1])
    for s, p in (("l", phase), ("r", phase + 0.5)):
        a[f"hip_{s}"] = hip_mean + stride_t * (_periodic_curve(g.curves["hip"], p) - hip_mean)
        for c in ("knee", "ankle", "toe"):
            a[f"{c}_{s}"] = _periodic_curve(g.curves[c], p)
    w = 2 * np.pi
    a["pelvis_yaw"] = -g.pelvis_yaw * cos(w * phase)
    a["pelvis_roll"] = g.pelvis_roll * np.sin(w * phase)
    a["pelvis_tilt"] = g.pelvis_tilt * cos(2 * w * (phase - 0.1))
    sway = sway_amp * sway_mod * cos(w * (phase - 0.3)) + stagger
    a["frontal_l"] = g.stance_width - a["pelvis_roll"] - sway
    a["frontal_r"] = -g.stance_width - a["pelvis_roll"] - sway
    a["torso_yaw"] = 1.5 * g.pelvis_yaw * cos(w * phase)  # thorax turns against the pelvis
    a["torso_pitch"] = g.trunk_pitch + lean_pitch
    a["torso_roll"] = lean_roll
    a["neck_yaw"] = -0.5 * g.pelvis_yaw * cos(w * phase)
    a["neck_pitch"] = -0.5 * a["torso_pitch"]
    a["neck_roll"] = head_roll - 0.5 * lean_roll
    a["clavicle"] = zeros
    a["arm_abduction"] = abduction + arm_noise
    arm = swing * cos(w * (phase - 0.05))  # the left arm is back while the left leg is forward
    a["shoulder_l"], a["shoulder_r"] = -arm, arm
    for s in ("l", "r"):  # more flexion as the arm comes forward
        a[f"elbow_{s}"] = g.elbow + g.elbow_swing * (1 + a[f"shoulder_{s}"] / swing) / 2
    stance = np.stack([np.mod(phase, 1.0) < g.duty, np.mod(phase + 0.5, 1.0) < g.duty], axis=1)
    return _Plan(a, stance, zeros, turn, _STEADY_S)


# Jump keyframes: hip, knee, pelvis tilt, heel rise, toe extension, shoulder flexion, elbow, thorax pitch,
# clavicle elevation (degrees), at: stand, crouch bottom, take-off, apex, touchdown, landing absorption.
_JUMP_CHANNELS = ("hip", "knee", "tilt", "heel", "toe", "shoulder", "elbow", "spine", "clavicle")
_JUMP_KEYS = np.array(
    [
        [0, 3, 0, 0, 0, -5, 10, 0, 0],
        [72, 88, 20, 0, 0, -45, 20, 15, 0],
        [-2, 4, 0, 35, 35, 150, 10, -3, 15],
        [18, 30, 0, 25, 5, 155, 15, 0, 15],
        [10, 12, 0, 20, 20, 110, 15, 5, 10],
        [50, 65, 12, 0, 0, 20, 20, 12, 0],
    ],
    dtype=float,
)


def _jump_plan(rng: np.random.Generator, t: np.ndarray) -> _Plan:
    """Repeated jumps: stand, crouch (arms back), push-off (arms swing up), ballistic flight, landing.

    Each jump draws its phase durations, crouch depth, flight height h (0.12-0.35 m, flight time
    2 sqrt(2 h / g)), forward distance (0-0.5 m, covered in flight) and a heading turn (15-40 degrees, one
    way for the whole sequence, made in flight). Keyframes (``_JUMP_KEYS``) are joined by PCHIP over time. The
    ankle keeps the foot flat: dorsiflexion = knee - hip + pelvis tilt - heel rise.
    """
    times, values, flights, turns = [], [], [], []
    clock, heading = t[0] - rng.uniform(0.0, 0.8), 0.0
    direction = rng.choice([-1.0, 1.0])
    while clock <= t[-1] + 1.0:
        stand, crouch, push = rng.uniform(0.3, 0.7), rng.uniform(0.4, 0.55), rng.uniform(0.2, 0.28)
        absorb, recover = rng.uniform(0.22, 0.32), rng.uniform(0.35, 0.5)
        depth, height = rng.uniform(0.7, 1.0), rng.uniform(0.12, 0.35)
        distance, turn = rng.uniform(0.0, 0.5), direction * rng.uniform(15.0, 40.0)
        air = 2.0 * np.sqrt(2.0 * height / GRAVITY)
        keys = _JUMP_KEYS.copy()
        keys[1] *= depth
        steps = np.cumsum([0.0, stand, crouch, push, air / 2, air / 2, absorb])
        times.extend(clock + steps)
        values.extend([keys[0], keys[0], keys[1], keys[2], keys[3], keys[4], keys[5]])
        takeoff = clock + steps[3]
        flights.append((takeoff, takeoff + air, distance / air))
        turns.append((takeoff, takeoff + air, heading, heading + turn))
        heading += turn
        clock += steps[-1] + recover
    curves = PchipInterpolator(np.array(times), np.array(values), axis=0)(t)
    c = dict(zip(_JUMP_CHANNELS, curves.T, strict=True))
    flight, speed = np.zeros(len(t), dtype=bool), np.zeros(len(t))
    for start, end, v in flights:
        inside = (t >= start) & (t < end)
        flight |= inside
        speed[inside] = v
    turn_t = np.array([x for start, end, _, _ in turns for x in (start, end)])
    turn_v = np.array([x for _, _, h0, h1 in turns for x in (h0, h1)])
    zeros = np.zeros(len(t))
    a = {"pelvis_yaw": zeros, "pelvis_roll": zeros, "pelvis_tilt": c["tilt"]}
    ankle = c["knee"] - c["hip"] + c["tilt"] - c["heel"]
    for s, sign in (("l", 1.0), ("r", -1.0)):
        a |= {f"hip_{s}": c["hip"], f"knee_{s}": c["knee"], f"ankle_{s}": ankle, f"toe_{s}": c["toe"]}
        a |= {
            f"frontal_{s}": np.full(len(t), sign * 3.0),
            f"shoulder_{s}": c["shoulder"],
            f"elbow_{s}": c["elbow"],
        }
    a |= {"torso_yaw": zeros, "torso_pitch": c["spine"], "torso_roll": zeros, "neck_yaw": zeros}
    a |= {"neck_pitch": -0.6 * (c["tilt"] + c["spine"]), "neck_roll": zeros, "clavicle": c["clavicle"]}
    a["arm_abduction"] = np.full(len(t), 10.0)
    stance = np.stack([~flight, ~flight], axis=1)
    return _Plan(a, stance, speed, np.interp(t, turn_t, turn_v), 0.0)


# ---------------------------------------------------------------------------------------------------
def _bvh_from_rotations(joints, root_position: np.ndarray, local: np.ndarray, dt: float) -> Bvh:
    """A Bvh whose channels reproduce ``local`` (n, J, 3, 3) and root positions (n, 3)."""
    euler = unwrap_degrees(matrix_to_euler(local, EULER_ORDER), axis=0)
    motion = np.concatenate([root_position, euler.reshape(len(local), -1)], axis=1)
    return Bvh(joints=joints, frame_time=dt, motion=motion)


@dataclass
class _Support:
    """The pose's forward kinematics in the heading frame (root at the origin) and what it implies."""

    positions: np.ndarray  # (n, J, 3) joint positions
    rotations: np.ndarray  # (n, J, 3, 3) world joint rotations
    contacts: np.ndarray  # (n, 6, 3) left heel, ball, toe tip, right heel, ball, toe tip
    root_y: np.ndarray  # (n,) root height above the ground
    steps: np.ndarray  # (n - 1, 2) horizontal root steps (x, z)


def _support(joints, local: np.ndarray, plan: _Plan, t: np.ndarray, height: float) -> _Support:
    """Forward kinematics of the pose in the heading frame, root height and horizontal root steps.

    The lowest contact point (heel, ball, toe tip) of the feet in stance is on y = 0; flights (no foot
    in stance) follow a ballistic parabola. Jumps: step k keeps the lowest stance point of frame k fixed
    from frame k to k + 1. Gaits (``plan.smooth_s`` > 0): ``_steady_steps``, then smoothed; the feet are
    put back on their contacts by ``_place_feet``. Airborne steps are interpolated from the neighbouring
    supported ones, plus the plan's flight speed.
    """
    n, dt = len(t), t[1] - t[0]
    pos, rot, ends = forward_kinematics(_bvh_from_rotations(joints, np.zeros((n, 3)), local, dt))
    points = []
    for side in ("Left", "Right"):
        foot, toe = _J[side + "Foot"], _J[side + "Toe"]
        points += [pos[:, foot] + rot[:, foot] @ (height * _HEEL), pos[:, toe], ends[toe]]
    points = np.stack(points, axis=1)
    in_stance = np.repeat(plan.stance, 3, axis=1)
    lowest = np.argmin(np.where(in_stance, points[..., 1], np.inf), axis=1)
    flight = ~plan.stance.any(axis=1)
    clear = -points[..., 1].min(axis=1)  # root height at which the lowest point touches the ground
    root_y = np.where(flight, clear, -points[np.arange(n), lowest, 1])

    idx = np.arange(n)
    prev = np.maximum.accumulate(np.where(flight, -1, idx))
    nxt = np.minimum.accumulate(np.where(flight, n, idx)[::-1])[::-1]
    inner = flight & (prev >= 0) & (nxt < n)
    t0, t1, ti = t[prev[inner]], t[nxt[inner]], t[inner]
    y0, y1 = root_y[prev[inner]], root_y[nxt[inner]]
    arc = y0 + (y1 - y0) * (ti - t0) / (t1 - t0) + 0.5 * GRAVITY * (ti - t0) * (t1 - ti)
    root_y[inner] = arc

    k = idx[:-1]
    if plan.smooth_s > 0:
        steps, airborne = _steady_steps(points, plan.stance)
    else:
        steps = -(points[k + 1, lowest[:-1]] - points[k, lowest[:-1]])[:, [0, 2]]
        airborne = flight[:-1] | flight[1:]
    if airborne.any() and not airborne.all():
        for c in range(2):
            steps[airborne, c] = np.interp(k[airborne], k[~airborne], steps[~airborne, c])
    steps[:, 1] += plan.flight_speed[:-1] * dt
    if plan.smooth_s > 0:  # forward: over smooth_s; sideways: over 0.4 smooth_s, keeping the sway
        steps[:, 0] = gaussian_filter1d(steps[:, 0], 0.4 * plan.smooth_s / dt, mode="nearest")
        steps[:, 1] = gaussian_filter1d(steps[:, 1], plan.smooth_s / dt, mode="nearest")
    return _Support(pos, rot, points, root_y, steps)


def _steady_steps(points: np.ndarray, stance: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Root steps (n-1, 2) of a gait: per stance, the mean step that keeps that foot's pivot planted.

    For each foot and each of its stances, the steps that would keep its lowest contact point fixed are
    averaged over the stance, so that over a whole stance the root travels exactly as far as the planted
    foot allows and the foot needs no net correction at toe-off (``_place_feet`` removes the rest).
    Frames with both feet in stance average the two; the second result marks steps with no foot down.
    """
    n = len(points)
    k = np.arange(n - 1)
    total, weight = np.zeros((n - 1, 2)), np.zeros(n - 1)
    for f in range(2):
        own = points[:, 3 * f : 3 * f + 3]
        pivot = np.argmin(own[..., 1], axis=1)[:-1]
        step = -(own[k + 1, pivot] - own[k, pivot])[:, [0, 2]]
        down = stance[:-1, f] & stance[1:, f]
        run = np.cumsum(down & ~np.concatenate([[False], down[:-1]]))
        count = np.bincount(run[down], minlength=run.max() + 1)
        for c in range(2):
            mean = np.bincount(run[down], weights=step[down, c], minlength=run.max() + 1)
            total[down, c] += mean[run[down]] / count[run[down]]
        weight += down
    airborne = weight == 0
    return total / np.maximum(weight, 1)[:, None], airborne


def _yaw_apply(psi: np.ndarray, x: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotate horizontal vectors (x, z) by ``Ry(psi)`` (radians, broadcast)."""
    c, s = np.cos(psi), np.sin(psi)
    return c * x + s * z, -s * x + c * z


def leg_ik(hip, ankle, knee_axis, lengths: tuple[float, float]):
    """Two-link leg inverse kinematics: thigh world rotation and knee flexion reaching ``ankle``.

    ``hip``, ``ankle`` (..., 3) positions; ``knee_axis`` (..., 3) the desired knee hinge axis (it is made
    perpendicular to the hip-ankle line; the knee bends forward about it, i.e. the shank swings towards
    -Z of the thigh frame as for ``Rx(+k)``); ``lengths`` = (thigh, shank). Returns the thigh's world
    rotation (..., 3, 3) (columns: hinge axis, up the thigh, forward) and the knee flexion (...) in
    degrees, with the hip-ankle distance clipped to the reachable range.
    """
    l1, l2 = lengths
    d = np.asarray(ankle, dtype=float) - np.asarray(hip, dtype=float)
    dist = np.linalg.norm(d, axis=-1)
    unit = d / np.maximum(dist, 1e-12)[..., None]
    dist = np.clip(dist, abs(l1 - l2) + 1e-9, (l1 + l2) * (1 - 1e-12))
    hinge = knee_axis - np.sum(knee_axis * unit, axis=-1, keepdims=True) * unit
    hinge /= np.linalg.norm(hinge, axis=-1, keepdims=True)
    beta = np.arccos(np.clip((l1**2 + dist**2 - l2**2) / (2 * l1 * dist), -1.0, 1.0))
    thigh_dir = np.cos(beta)[..., None] * unit + np.sin(beta)[..., None] * np.cross(unit, hinge)
    knee = np.pi - np.arccos(np.clip((l1**2 + l2**2 - dist**2) / (2 * l1 * l2), -1.0, 1.0))
    frame = np.stack([hinge, -thigh_dir, np.cross(hinge, -thigh_dir)], axis=-1)
    return frame, np.rad2deg(knee)


def _toe_rocker(hip, ankle, ball, foot_rot, lengths, slack: float = 1e-3):
    """Raise the heel about the ball of the foot until the leg can reach the ankle (the toe rocker).

    ``hip``, ``ankle``, ``ball`` (m, 3) positions and ``foot_rot`` (m, 3, 3) the foot's world rotation.
    Where the ankle is farther from the hip than the stretched leg (thigh + shank, less ``slack``), the
    foot turns about its lateral axis through the ball by the smallest heel-up angle that brings the
    ankle onto the reachable sphere (closed form: ``w . R(theta) u = c`` with w = ball - hip,
    u = ankle - ball). Ball and toes stay where they are. Returns the ankle positions and foot rotations.
    """
    reach = (lengths[0] + lengths[1]) * (1 - slack)
    far = np.linalg.norm(ankle - hip, axis=-1) > reach
    if not far.any():
        return ankle, foot_rot
    axis = foot_rot[far, :, 0]
    u, w = ankle[far] - ball[far], ball[far] - hip[far]
    along = np.sum(axis * u, axis=-1, keepdims=True) * axis
    perp = u - along
    a_, b_, c_ = np.sum(w * along, -1), np.sum(w * perp, -1), np.sum(w * np.cross(axis, perp), -1)
    target = (reach**2 - np.sum(w * w, -1) - np.sum(u * u, -1)) / 2
    phase, amp = np.arctan2(c_, b_), np.hypot(b_, c_)
    spread = np.arccos(np.clip((target - a_) / np.maximum(amp, 1e-12), -1.0, 1.0))
    roots = np.angle(np.exp(1j * (phase[:, None] + np.array([-1.0, 1.0]) * spread[:, None])))
    roots = np.where(roots >= 0, roots, roots + 2 * np.pi)  # heel up is a positive turn about +X
    theta = roots.min(axis=1)
    turn = axis_angle_to_matrix(axis, theta)
    ankle, foot_rot = ankle.copy(), foot_rot.copy()
    ankle[far] = ball[far] + np.einsum("mab,mb->ma", turn, u)
    foot_rot[far] = turn @ foot_rot[far]
    return ankle, foot_rot


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def _place_feet(local, support: _Support, stance, xz, psi, t, lengths) -> np.ndarray:
    """Put the feet where the ground says, by a two-link leg IK (``leg_ik``) per foot and frame.

    Stance: the world drift of the foot's lowest contact point between consecutive frames (left by the
    smoothed root path) is summed from the start of its stance, and the foot is moved back by that sum,
    so it stays planted. The hold eases out over ``_RAMP_S`` after toe-off (the drift still summed, the
    correction weighted down by a smoothstep), so the foot leaves the ground without a jump in velocity.
    Swing and flight: the foot is lifted just enough for its lowest point to clear the ground by 1 cm
    (ramped in after toe-off and out before heel strike). A foot the stretched leg cannot reach rolls
    heel-up about its ball (``_toe_rocker``); otherwise the foot's world orientation is kept, so its
    contact heights change only by the lift. Thigh, knee and ankle (and toe, after a roll) rotations are
    re-solved (hinge axis from the original thigh). Returns the new local rotations.
    """
    n = len(t)
    idx = np.arange(n)
    world = np.stack(_yaw_apply(psi[:, None], support.contacts[..., 0], support.contacts[..., 2]), axis=-1)
    world += xz[:, None, :]
    out = local.copy()
    pelvis = support.rotations[:, 0]
    for f, side in enumerate(("Left", "Right")):
        pts = world[:, 3 * f : 3 * f + 3]
        heights = support.root_y + support.contacts[:, 3 * f : 3 * f + 3, 1].min(axis=1)
        pivot = np.argmin(support.contacts[:, 3 * f : 3 * f + 3, 1], axis=1)
        drift = pts[idx[1:], pivot[:-1]] - pts[idx[:-1], pivot[:-1]]  # (n - 1, 2)
        st = stance[:, f]
        begins = st & ~np.concatenate([[False], st[:-1]])
        ends = st & ~np.concatenate([st[1:], [False]])
        last_end = np.maximum.accumulate(np.where(ends, idx, -1))
        next_begin = np.minimum.accumulate(np.where(begins, idx, n)[::-1])[::-1]
        since = np.where(~st & (last_end >= 0), t - t[np.maximum(last_end, 0)], np.inf)
        until = np.where(~st & (next_begin < n), t[np.minimum(next_begin, n - 1)] - t, np.inf)
        w_out = np.where(st, 1.0, 1.0 - _smoothstep(since / _RAMP_S))
        held = np.where((w_out[:-1] > 0) & (w_out[1:] > 0), 1.0, 0.0)[:, None] * drift
        total = np.concatenate([np.zeros((1, 2)), np.cumsum(held, axis=0)])
        corr = -(total - total[np.maximum.accumulate(np.where(begins, idx, 0))]) * w_out[:, None]
        margin = 0.01 * _smoothstep(np.minimum(since, until) / _RAMP_S)
        lift = np.where(st, 0.0, np.maximum(margin - heights, 0.0))
        cx, cz = _yaw_apply(-psi, corr[:, 0], corr[:, 1])
        moved = (np.hypot(cx, cz) > 1e-9) | (lift > 0)
        if not moved.any():
            continue
        up, leg, foot, toe = (_J[side + s] for s in ("UpLeg", "Leg", "Foot", "Toe"))
        rot, pos = support.rotations[moved], support.positions[moved]
        shift = np.stack([cx, lift, cz], axis=1)[moved]
        ankle, foot_rot = _toe_rocker(pos[:, up], pos[:, foot] + shift, pos[:, toe] + shift, rot[:, foot], lengths)
        thigh, knee = leg_ik(pos[:, up], ankle, rot[:, up, :, 0], lengths)
        shank = thigh @ _rot("X", knee)
        out[moved, up] = np.swapaxes(pelvis[moved], -1, -2) @ thigh
        out[moved, leg] = _rot("X", knee)
        out[moved, foot] = np.swapaxes(shank, -1, -2) @ foot_rot
        out[moved, toe] = np.swapaxes(foot_rot, -1, -2) @ rot[:, toe]
    return out


def _draw_height(rng: np.random.Generator, height) -> float:
    drawn = rng.uniform(*HEIGHT_RANGE)
    if height is None:
        return float(drawn)
    number = isinstance(height, int | float | np.floating | np.integer) and not isinstance(height, bool)
    if not (number and np.isfinite(height) and HEIGHT_RANGE[0] - 0.5 <= height <= HEIGHT_RANGE[1] + 0.5):
        raise VoxposeError(f"generate_motion: height must be in 1.0..2.5 m, got {height!r}")
    return float(height)


def generate_motion(
    kind: str,
    *,
    seed,
    n_frames: int,
    fps: float = 30.0,
    height: float | None = None,
    turn_rate: float | None = None,
    mid_heading: float | None = None,
) -> Bvh:
    """One synthetic motion of ``kind`` (``KINDS``) as a ``Bvh`` in metres (see the module docstring).

    Parameters
    ----------
    kind : ``walk``, ``drunk``, ``spiral``, ``jog`` or ``jump``.
    seed : int or ``np.random.SeedSequence``; every random choice is drawn from it.
    n_frames : number of frames (>= 2); ``fps`` the frame rate.
    height : the subject's standing height in metres; drawn from 1.5-2.0 m when None.
    turn_rate : steady turn of ``walk`` and ``jog`` in degrees per second (positive: towards +X); drawn
        (15-30, either way) when None; 0 gives a straight walk.
    mid_heading : the body heading in degrees (about +Y, 0 facing +Z) at the middle frame, so that the turn
        sweeps an arc centred on it; drawn uniformly when None. The default set passes
        ``default_heading(kind, index)``.
    """
    if kind not in KINDS:
        raise VoxposeError(f"generate_motion: unknown motion kind {kind!r} (known: {', '.join(KINDS)})")
    if isinstance(n_frames, bool) or not (isinstance(n_frames, int | np.integer) and n_frames >= 2):
        raise VoxposeError(f"generate_motion: n_frames must be an integer >= 2, got {n_frames!r}")
    if not (isinstance(fps, int | float) and np.isfinite(fps) and 1.0 <= fps <= 1000.0):
        raise VoxposeError(f"generate_motion: fps must be in 1..1000, got {fps!r}")
    rng = np.random.default_rng(seed)
    height = _draw_height(rng, height)
    heading0 = rng.uniform(-180.0, 180.0)
    start = rng.uniform(-1.0, 1.0, size=2)
    joints = default_skeleton(height)
    lengths = (
        float(np.linalg.norm(joints[_J["LeftLeg"]].offset)),
        float(np.linalg.norm(joints[_J["LeftFoot"]].offset)),
    )

    dt = 1.0 / fps
    pad = int(np.ceil(1.5 * fps))  # simulated before and after, so flights and noise have context
    t = (np.arange(n_frames + 2 * pad) - pad) * dt
    plan = _jump_plan(rng, t) if kind == "jump" else _gait_plan(kind, rng, t, turn_rate)
    local = _local_rotations(plan.angles, len(t))
    support = _support(joints, local, plan, t, height)
    heading = heading0 + plan.turn
    if kind == "spiral":
        r_start, r_end, direction = rng.uniform(3.0, 4.5), rng.uniform(1.0, 1.6), rng.choice([-1.0, 1.0])
        forward = np.concatenate([[0.0], np.cumsum(support.steps[:, 1])])
        s = forward - forward[pad]
        geometry = dict(r_start=r_start, r_end=r_end, length=max(s[pad + n_frames - 1], 1e-3))
        heading = heading + direction * np.rad2deg(spiral_heading(s, **geometry))
        speed = np.gradient(forward, dt)
        lean = np.rad2deg(np.arctan(speed**2 / (GRAVITY * spiral_radius(s, **geometry))))
        for name in ("Spine", "Chest"):  # the trunk leans into the turn (the top towards the centre)
            local[:, _J[name]] = _rot("Z", -direction * lean / 2) @ local[:, _J[name]]
    if mid_heading is not None:
        heading = heading + (float(mid_heading) - heading[pad + n_frames // 2])
    psi = np.deg2rad(heading)
    mid = (psi[1:] + psi[:-1]) / 2
    world = np.stack(_yaw_apply(mid, support.steps[:, 0], support.steps[:, 1]), axis=1)
    xz = np.concatenate([np.zeros((1, 2)), np.cumsum(world, axis=0)])
    local = _place_feet(local, support, plan.stance, xz, psi, t, lengths)

    crop = slice(pad, pad + n_frames)
    xz = xz[crop] - xz[pad] + start
    root = np.stack([xz[:, 0], support.root_y[crop], xz[:, 1]], axis=1)
    local = local[crop]
    local[:, 0] = _rot("Y", heading[crop]) @ local[:, 0]
    log.debug("generated %s: %d frames, height %.3f m", kind, n_frames, height)
    return _bvh_from_rotations(joints, root, local, dt)


def default_heading(kind: str, index: int) -> float:
    """Mid-sequence heading (degrees) of sequence ``index`` of ``kind`` in the default set.

    World-aligned descriptors (Section 4) let the regressor recognise only headings its training frames
    cover, and a few sequences with random headings leave gaps (with seed 1, 12 of 36 ten-degree bins had
    no Table 1 training frame). Sequences 0 and 1 of the five kinds take ten slots 36 degrees apart
    (kind order, then index), each turning through an arc centred on its slot, so the training sequences
    of any experiment that takes two per kind tile the circle; later sequences sit half-way between.
    """
    if kind not in KINDS:
        raise VoxposeError(f"default motions: unknown kind {kind!r} (known: {', '.join(KINDS)})")
    slots = 2 * len(KINDS)
    n = KINDS.index(kind) + len(KINDS) * (int(index) % 2)
    return float(np.mod(360.0 * (n + 0.5 * (int(index) // 2)) / slots + 180.0, 360.0) - 180.0)


def sequence_seed(seed: int, kind: str, index: int) -> np.random.SeedSequence:
    """The seed of sequence ``index`` of ``kind`` in the default set: it depends only on (seed, kind, index)."""
    if kind not in KINDS:
        raise VoxposeError(f"default motions: unknown kind {kind!r} (known: {', '.join(KINDS)})")
    return np.random.SeedSequence(int(seed), spawn_key=(KINDS.index(kind), int(index)))


def default_motion(kind: str, index: int, *, n_frames: int, seed: int, fps: float = 30.0) -> Bvh:
    """Sequence ``index`` of ``kind`` in the default set: its own seed (``sequence_seed``) and heading
    (``default_heading``), so that it depends only on (seed, kind, index, n_frames, fps)."""
    seq_seed, heading = sequence_seed(seed, kind, index), default_heading(kind, index)
    return generate_motion(kind, seed=seq_seed, n_frames=n_frames, fps=fps, mid_heading=heading)

