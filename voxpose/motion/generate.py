"""Synthetic motions of the paper's five types, written as genuine BVH files (Section 6, Table 2).

Section 6 trains and tests on motion capture of five types: regular walking, drunken walking, spiral
walking, jogging and jumping (Table 2). When no capture is at hand the workflow runs on motions made
here (``walk``, ``drunk``, ``spiral``, ``jog``, ``jump``), written as BVH files that go through the same
reader, forward kinematics and joint mapping as real data. The paper prescribes none of this; it is a
stand-in for its MOCAP data, kept as plausible as a small kinematic model allows.

A motion is made in four steps, one module each: the subject's skeleton
(``voxpose.motion.generated_skeleton``), a plan of joint angles over time (``voxpose.motion.gait``: gait curves
or jumps), ground contact (``voxpose.motion.ground``: root height and horizontal steps from the feet in
stance), and here the heading: the steps are turned by the heading psi(t) into the world and summed from the
drawn start position; the feet are then planted by leg IK.

The types. ``walk``: a steady turn (15-30 degrees per second, left or right: a circle of 2.5-5 m
radius, a turning walk). ``jog``: running curves (more knee and elbow flexion, flight phases), faster cadence, more
forward lean, turning like ``walk``. Why every type turns: the 3D shape contexts are aligned with the world
(Section 4), so the regressor can only recognise a body heading that its training frames cover; the
paper's training set includes turning walks (Section 6), and a few straight sequences would cover a few
headings only; the default set also centres each sequence's arc on its own slot of the circle
(``default_heading``). ``spiral``: walking whose heading follows the tangent of a
spiral of shrinking radius (``motion.paths.spiral_heading``: the radius of curvature falls linearly with the
distance walked, from r_start (3-4.5 m) to r_end (1-1.6 m) over the sequence), turning left or right,
the trunk leaning into the turn by atan(v^2 / (g r)). ``drunk``: walking with a wandering heading
(``motion.paths.random_walk_heading``, 25-35 degrees per sqrt(s)), irregular cadence and step length, a large
irregular sideways sway, a wider stance, a smooth random torso lean and head roll, arms held away from the body.
``jump``: repeated jumps (``motion.gait.jump_plan``): stand, crouch with the arms back, push-off with the arms
swinging over the head, a ballistic flight (0.12-0.35 m high, up to 0.5 m forward, a turn of 15-40
degrees, the same way for the whole sequence), landing and recovery; both feet stay planted on the
ground between flights.

Per-sequence variation comes from the seed: height (1.5-2.0 m), cadence, stride scale (hence speed and
stride length), arm swing amplitude, heading (unless given) and start position (within 1 m of the origin), and each
type's own parameters. Everything is vectorised over frames; 1.5 s are simulated before and after the
requested frames so that flights, smoothing and noise have context at both ends.
"""

import logging

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh
from voxpose.motion.gait import gait_plan, jump_plan, local_rotations
from voxpose.motion.generated_skeleton import JOINT_INDEX, bvh_from_rotations, default_skeleton
from voxpose.motion.ground import find_support, place_feet, yaw_apply
from voxpose.motion.paths import spiral_heading, spiral_radius, turn_lean
from voxpose.motion.rotations import axis_rotation

log = logging.getLogger(__name__)

KINDS = ("walk", "drunk", "spiral", "jog", "jump")
HEIGHT_RANGE = (1.5, 2.0)  # metres, drawn uniformly when no height is given


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
        float(np.linalg.norm(joints[JOINT_INDEX["LeftLeg"]].offset)),
        float(np.linalg.norm(joints[JOINT_INDEX["LeftFoot"]].offset)),
    )

    dt = 1.0 / fps
    pad = int(np.ceil(1.5 * fps))  # simulated before and after, so flights and noise have context
    t = (np.arange(n_frames + 2 * pad) - pad) * dt
    plan = jump_plan(rng, t) if kind == "jump" else gait_plan(kind, rng, t, turn_rate)
    local = local_rotations(plan.angles, len(t))
    support = find_support(joints, local, plan, t, height)
    heading = heading0 + plan.turn
    if kind == "spiral":
        r_start, r_end, direction = rng.uniform(3.0, 4.5), rng.uniform(1.0, 1.6), rng.choice([-1.0, 1.0])
        forward = np.concatenate([[0.0], np.cumsum(support.steps[:, 1])])
        s = forward - forward[pad]
        geometry = dict(r_start=r_start, r_end=r_end, length=max(s[pad + n_frames - 1], 1e-3))
        heading = heading + direction * np.rad2deg(spiral_heading(s, **geometry))
        speed = np.gradient(forward, dt)
        lean = np.rad2deg(turn_lean(speed, spiral_radius(s, **geometry)))
        for name in ("Spine", "Chest"):  # the trunk leans into the turn (the top towards the centre)
            local[:, JOINT_INDEX[name]] = axis_rotation("Z", -direction * lean / 2) @ local[:, JOINT_INDEX[name]]
    if mid_heading is not None:
        heading = heading + (float(mid_heading) - heading[pad + n_frames // 2])
    psi = np.deg2rad(heading)
    mid = (psi[1:] + psi[:-1]) / 2
    world = np.stack(yaw_apply(mid, support.steps[:, 0], support.steps[:, 1]), axis=1)
    xz = np.concatenate([np.zeros((1, 2)), np.cumsum(world, axis=0)])
    local = place_feet(local, support, plan.stance, xz, psi, t, lengths)

    crop = slice(pad, pad + n_frames)
    xz = xz[crop] - xz[pad] + start
    root = np.stack([xz[:, 0], support.root_y[crop], xz[:, 1]], axis=1)
    local = local[crop]
    local[:, 0] = axis_rotation("Y", heading[crop]) @ local[:, 0]
    log.debug("generated %s: %d frames, height %.3f m", kind, n_frames, height)
    return bvh_from_rotations(joints, root, local, dt)


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
