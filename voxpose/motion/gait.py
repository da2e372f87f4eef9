"""Pose plans of the generated motions: joint-angle curves over time for the gaits and for jumps.

A plan (``Plan``) is the body's pose on a time grid before the root's path is known: named anatomical
angles, which feet may bear weight, and the heading turn not tied to the path. ``voxpose.motion.ground``
then puts the feet on the ground and ``voxpose.motion.generate`` assembles the motion.

Gaits (``gait_plan``: ``walk``, ``drunk``, ``spiral``, ``jog``). A stride phase p(t) = integral of the cadence
(strides per second), left heel strike at p = 0, the right leg half a stride later. Hip, knee, ankle and toe
flexion are periodic shape-preserving (PCHIP) interpolants through keyframes of normative curves in percent of
the stride (``_WALK_CURVES`` after Winter's and Perry's walking data, ``_JOG_CURVES`` after Novacheck 1998);
PCHIP does not overshoot, so the curves stay inside their keyframes' range. The stance part of the hip curves
was solved once (planar, at the mean parameters) so that a planted foot moves back at a constant speed under
the pelvis, the swing part is normative. The stride scale widens the hip excursion about its mean. Around the
legs: pelvic rotation (yaw) and obliquity (roll) at the stride frequency and a small tilt at the step
frequency; a sideways sway (both legs tilted together in the frontal plane) that carries the pelvis over the
stance foot; the legs' frontal angle cancels the pelvic roll plus a constant stance width; the thorax
counter-rotates against the pelvis (split over Spine and Chest) and leans forward; the neck keeps the head
facing ahead; each shoulder swings in counter-phase with its own leg and the elbow flexes more as the arm
comes forward; the hand lags the arm's swing at the wrist (flexion about a drawn mean, 5-15 degrees, swinging
by 5-10 degrees, and a drawn ulnar deviation, 3-10 degrees, wobbling by 3), so the canonical wrist angles move
as captured wrists do and Eq. 6 averages over 42 angles that all vary (with still wrists 6 of them would be
predicted exactly, free zeros that lower the full-body error). Knee flexion stays below 90 degrees, so the
middle (X) angle of every ZXY triple stays inside (-90, 90) and the written angles are continuous. A foot is
in stance for the first ``duty`` of its stride (0.60 walking, 0.38 jogging, which leaves two flights per stride).

Jumps (``jump_plan``): stand, crouch with the arms back, push-off with the arms swinging over the head, a
ballistic flight, landing and recovery, joined by PCHIP over time through keyframes (``_JUMP_KEYS``); the
wrists extend with the arms back and flex as they swing up.

The wrists' parameters are drawn after every other random choice, so adding them left every other angle of
the default motions as it was.
"""

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import PchipInterpolator

from voxpose.motion.generated_skeleton import JOINT_INDEX, JOINT_NAMES
from voxpose.motion.paths import GRAVITY, random_walk_heading, smooth_noise
from voxpose.motion.rotations import axis_rotation

_STEADY_S = 0.25  # seconds: smoothing of the gaits' root steps (removes the step-frequency lurch)


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


def _rot(axis: str, degrees) -> np.ndarray:
    return axis_rotation(axis, degrees)


def local_rotations(a: dict, n: int) -> np.ndarray:
    """(n, J, 3, 3) local joint rotations from named anatomical angles (degrees, arrays of shape (n,)).

    Axes in the T-pose frame: flexion of hip, shoulder, toe and dorsiflexion are rotations about -X,
    knee flexion about +X, elbow flexion about -Y (left) / +Y (right), abduction about Z.
    """
    joint = JOINT_INDEX
    rot = np.broadcast_to(np.eye(3), (n, len(JOINT_NAMES), 3, 3)).copy()
    rot[:, joint["Hips"]] = _rot("Y", a["pelvis_yaw"]) @ _rot("X", a["pelvis_tilt"]) @ _rot("Z", a["pelvis_roll"])
    half = _rot("Y", a["torso_yaw"] / 2) @ _rot("X", a["torso_pitch"] / 2) @ _rot("Z", a["torso_roll"] / 2)
    rot[:, joint["Spine"]] = half
    rot[:, joint["Chest"]] = half
    rot[:, joint["Neck"]] = _rot("Y", a["neck_yaw"]) @ _rot("X", a["neck_pitch"]) @ _rot("Z", a["neck_roll"])
    for side, sign in (("Left", 1.0), ("Right", -1.0)):
        s = side[0].lower()
        rot[:, joint[side + "Shoulder"]] = _rot("Z", sign * a["clavicle"])
        rot[:, joint[side + "Arm"]] = _rot("X", -a[f"shoulder_{s}"]) @ _rot("Z", -sign * (90.0 - a["arm_abduction"]))
        rot[:, joint[side + "ForeArm"]] = _rot("Y", -sign * a[f"elbow_{s}"])
        # wrist flexion bends the hand towards the palm (-Y in the T-pose), ulnar deviation towards the back (-Z)
        rot[:, joint[side + "Hand"]] = _rot("Z", -sign * a[f"wrist_{s}"]) @ _rot("Y", sign * a[f"deviation_{s}"])
        rot[:, joint[side + "UpLeg"]] = _rot("Z", a[f"frontal_{s}"]) @ _rot("X", -a[f"hip_{s}"])
        rot[:, joint[side + "Leg"]] = _rot("X", a[f"knee_{s}"])
        rot[:, joint[side + "Foot"]] = _rot("X", -a[f"ankle_{s}"])
        rot[:, joint[side + "Toe"]] = _rot("X", -a[f"toe_{s}"])
    return rot


@dataclass
class Plan:
    """The pose over the padded time grid, before the root trajectory is known."""

    angles: dict  # named anatomical angles, (n,) degrees each
    stance: np.ndarray  # (n, 2) True while the left / right foot may bear weight
    flight_speed: np.ndarray  # (n,) extra forward speed in flight (m/s)
    turn: np.ndarray  # (n,) heading change not tied to the path (degrees)
    smooth_s: float  # Gaussian width (seconds) smoothing the root's horizontal steps; 0 = none


def gait_plan(kind: str, rng: np.random.Generator, t: np.ndarray, turn_rate: float | None = None) -> Plan:
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
        # steady turn (see ``motion.generate``); the spiral replaces it by its own heading
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
    flex, flex_swing, deviation = u(5.0, 15.0), u(5.0, 10.0), u(3.0, 10.0)
    for s, sign in (("l", -1.0), ("r", 1.0)):  # the hand lags the arm: most flexed just after the arm's back turn
        lag = sign * cos(w * (phase - 0.15))
        a[f"wrist_{s}"] = flex + flex_swing * lag + 0.5 * arm_noise
        a[f"deviation_{s}"] = deviation + 3.0 * np.sin(w * (phase - 0.15) + (s == "r") * np.pi)
    stance = np.stack([np.mod(phase, 1.0) < g.duty, np.mod(phase + 0.5, 1.0) < g.duty], axis=1)
    return Plan(a, stance, zeros, turn, _STEADY_S)


# Jump keyframes: hip, knee, pelvis tilt, heel rise, toe extension, shoulder flexion, elbow, thorax pitch,
# clavicle elevation, wrist flexion (degrees), at: stand, crouch bottom, take-off, apex, touchdown, landing absorption.
_JUMP_CHANNELS = ("hip", "knee", "tilt", "heel", "toe", "shoulder", "elbow", "spine", "clavicle", "wrist")
_JUMP_KEYS = np.array(
    [
        [0, 3, 0, 0, 0, -5, 10, 0, 0, 10],
        [72, 88, 20, 0, 0, -45, 20, 15, 0, -25],
        [-2, 4, 0, 35, 35, 150, 10, -3, 15, 20],
        [18, 30, 0, 25, 5, 155, 15, 0, 15, 10],
        [10, 12, 0, 20, 20, 110, 15, 5, 10, 0],
        [50, 65, 12, 0, 0, 20, 20, 12, 0, 15],
    ],
    dtype=float,
)


def jump_plan(rng: np.random.Generator, t: np.ndarray) -> Plan:
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
    deviation = rng.uniform(3.0, 10.0)
    for s in ("l", "r"):
        a[f"wrist_{s}"], a[f"deviation_{s}"] = c["wrist"], deviation + 0.1 * c["shoulder"]
    stance = np.stack([~flight, ~flight], axis=1)
    return Plan(a, stance, speed, np.interp(t, turn_t, turn_v), 0.0)
