"""Spiral and drunken walks derived from a real straight walk (Section 6, Tables 1 and 2).

Table 1 of the paper tests on spiral walking and Table 2 adds drunken walking, but the shared motion
capture has neither. These transforms bend a real, roughly straight walk into one, keeping the captured
body motion: every non-root channel is copied unchanged (``drunk`` also changes the torso lean joint),
so only the path and heading of the body (and, for ``drunk``, a trunk lean) are synthetic.

Derived, not captured. BVH has no comments, so the derived files say what they are by name
(``spiral_<stem>.bvh``, ``drunk_<stem>.bvh``: the type prefix the workflow reads) and ``derive_file``
returns a provenance dict (source file, transform, seed, parameters, unit) for the caller to store.

Method. The reference point is the canonical root (the pelvis, ``voxpose.motion.joint_map``: CMU's ``Hips``
root, Bandai's ``Hips`` below its static ``joint_Root``). Its horizontal path P(t) gives the walking
direction u = unit(P(end) - P(0)) and the forward progression s(t) = (P(t) - P(0)) . u, the distance
walked. Each frame gets a rigid world motion x -> A(t) x + b(t) with A = Ry(delta(t)) [L(t)], applied to
the whole body through the BVH root alone: R_root' = A R_root (converted back to the root's own Euler
order) and p_root' = A p_root + b (the root's position channels are its world position). The pelvis's
new horizontal path starts at P(0) and advances by the source's own per-frame displacement (forward
progress and natural sway) turned by the heading change delta (at mid-frame), plus, for ``drunk``, an
extra sideways sway. With ``lean``, L(t) tilts the body about its walking direction u through the
ground point below the pelvis (ground = the lowest joint or End Site over the sequence).

``spiral``: delta(t) = +-``motion.paths.spiral_heading`` of s(t): the radius of curvature shrinks
linearly with the distance walked from ``r_start`` to ``r_end`` (metres) over the whole walk, or, with
``turns`` given, over the distance that makes that many turns (a circle of ``r_end`` after it). The seed
picks the turning direction. The body leans into the turn by atan(v^2 / (g r)) (v the smoothed walking
speed) unless ``lean=False``.

``drunk``: delta(t) = ``motion.paths.random_walk_heading`` (diffusion ``wander`` degrees per
sqrt(second), smoothed over 0.5 s); a lateral sway of ``sway`` metres (a smooth unit-variance random
process over 0.6 s); and a torso lean: the lean joint's local rotation L_j becomes
W_p^T E(t) W_p L_j, with W_p its parent's world rotation and E a smooth random roll about u (standard
deviation ``torso_roll`` degrees, over 1.5 s) after a forward pitch of ``torso_pitch`` degrees, so the
upper body turns by E about that joint. The lean joint (``lean_joint``) is found by name on the chain
from the canonical root to the neck: the first of ``spine``, ``lowerback``, ``chest``, ``spine1`` (any
case); otherwise the first joint after the root on that chain.

Leading reference-pose frames of the source (CMU's frame 0, ``captured_frames``) are dropped first.

Units: the file's own. Lengths given in metres (radii, sway) are divided by ``unit`` (metres per file
unit), which is inferred like ``motion_loader`` does (standing height from bone lengths, then the first
known unit giving 1.4-2.1 m) unless given.
"""

import inspect
from pathlib import Path

import numpy as np
from scipy.ndimage import gaussian_filter1d

from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, joint_columns, read_bvh, rotation_order, write_bvh
from voxpose.motion import canon
from voxpose.motion.bvh_kinematics import forward_kinematics
from voxpose.motion.joint_map import resolve_joint_map, skeleton_points
from voxpose.motion.load import infer_unit, standing_height
from voxpose.motion.paths import random_walk_heading, smooth_noise, spiral_heading, spiral_radius, turn_lean
from voxpose.motion.reference_pose import leading_reference_frames
from voxpose.motion.rotations import (
    axis_angle_to_matrix,
    axis_rotation,
    euler_to_matrix,
    matrix_to_euler,
    unwrap_degrees,
)

KINDS = ("spiral", "drunk", "turn")
LEAN_JOINT_NAMES = ("spine", "lowerback", "chest", "spine1")
MIN_WALK_M = 1.0  # the source must travel at least this far (metres)


def infer_walk_unit(bvh: Bvh, source: str = "BVH", fk=None) -> float:
    """Metres per file unit of ``bvh``, inferred as ``motion_loader`` does (standing height)."""
    joints, ends = skeleton_points(bvh, resolve_joint_map(bvh, source=source), fk)
    return infer_unit(standing_height(joints, ends))[0]


def captured_frames(bvh: Bvh, source: str = "BVH") -> Bvh:
    """``bvh`` without its leading reference-pose frames (``reference_pose``; CMU's frame 0).

    The same rule as ``load_motion``'s ``drop_reference_frame="auto"``: the frames are not motion, and
    once moved by a transform they would no longer stand out from the motion's first frame.
    """
    first = leading_reference_frames(*skeleton_points(bvh, resolve_joint_map(bvh, source=source)))
    return bvh if first == 0 else Bvh(joints=bvh.joints, frame_time=bvh.frame_time, motion=bvh.motion[first:])


class _Walk:
    """What the transforms need to know about a source walk (file units, world axes)."""

    def __init__(self, bvh: Bvh, unit: float | None, source: str):
        bvh = captured_frames(bvh, source)
        if bvh.n_frames < 2:
            raise VoxposeError(f"{source}: a walk needs at least 2 frames, got {bvh.n_frames}")
        root = bvh.joints[0]
        pos_cols, rot_cols = joint_columns(bvh, 0)
        if pos_cols is None or rot_cols is None:
            raise VoxposeError(f"{source}: root joint {root.name!r} needs 3 position and 3 rotation channels")
        self.bvh, self.pos_cols, self.rot_cols = bvh, pos_cols, rot_cols
        self.fk = forward_kinematics(bvh)
        joints, _ = skeleton_points(bvh, resolve_joint_map(bvh, source=source), self.fk)
        if unit is None:
            unit = infer_walk_unit(bvh, source, self.fk)
        elif isinstance(unit, bool) or not (isinstance(unit, int | float) and np.isfinite(unit) and unit > 0):
            raise VoxposeError(f"{source}: unit must be a positive number of metres per file unit, got {unit!r}")
        self.unit = float(unit)
        self.pelvis = joints[:, canon.INDEX["root"]]
        travel = self.pelvis[-1] - self.pelvis[0]
        travel[1] = 0.0
        distance = float(np.linalg.norm(travel))
        if distance * self.unit < MIN_WALK_M:
            raise VoxposeError(
                f"{source}: not a walk: the pelvis travels {distance * self.unit:.2f} m "
                f"(at least {MIN_WALK_M} m needed)"
            )
        self.forward = travel / distance  # u, horizontal unit vector
        self.left = np.array([self.forward[2], 0.0, -self.forward[0]])  # Ry(90 deg) u
        self.progress = (self.pelvis - self.pelvis[0]) @ self.forward  # s(t), file units
        points = np.concatenate([self.fk[0], *[e[:, None] for e in self.fk[2].values()]], axis=1)
        self.ground = float(points[..., 1].min())


def _relay(walk: _Walk, delta: np.ndarray, sway: np.ndarray, lean: np.ndarray) -> np.ndarray:
    """New motion array: the whole body moved by A(t) = Ry(delta) L(t) through the root channels.

    ``delta`` (F,) heading change in radians; ``sway`` (F,) extra sideways offset of the path (file
    units, along the turned left axis); ``lean`` (F,) tilt in radians about the walking direction through
    the ground point below the pelvis (positive tilts the top towards the walker's right).
    """
    bvh = walk.bvh
    positions, rotations, _ = walk.fk
    yaw = axis_rotation("Y", np.rad2deg(delta))
    tilt = axis_angle_to_matrix(np.broadcast_to(walk.forward, (len(delta), 3)), lean)
    turn = yaw @ tilt
    ground = walk.pelvis.copy()
    ground[:, 1] = walk.ground
    mid = axis_rotation("Y", np.rad2deg((delta[1:] + delta[:-1]) / 2))
    step = np.diff(walk.pelvis * [1.0, 0.0, 1.0], axis=0)
    path = walk.pelvis[:1] * [1.0, 0.0, 1.0] + np.concatenate(
        [np.zeros((1, 3)), np.cumsum(np.einsum("fab,fb->fa", mid, step), 0)]
    )
    path += sway[:, None] * np.einsum("fab,b->fa", yaw, walk.left)
    # b = path - A G + (G - L G) turned: the ground point below the pelvis lands on the new path
    offset = path - np.einsum("fab,fb->fa", yaw, ground * [1.0, 0.0, 1.0])
    offset += np.einsum("fab,fb->fa", yaw, ground - np.einsum("fab,fb->fa", tilt, ground))
    motion = bvh.motion.copy()
    motion[:, walk.pos_cols] = np.einsum("fab,fb->fa", turn, positions[:, 0]) + offset
    order = rotation_order(bvh.joints[0])
    motion[:, walk.rot_cols] = unwrap_degrees(matrix_to_euler(turn @ rotations[:, 0], order), axis=0)
    return motion


def _speed(walk: _Walk) -> np.ndarray:
    """Smoothed forward walking speed (m/s) per frame."""
    dt = walk.bvh.frame_time
    return gaussian_filter1d(np.gradient(walk.progress * walk.unit, dt), 1.0 / dt, mode="nearest")


def spiral_from_walk(
    bvh: Bvh,
    *,
    seed,
    turns: float | None = None,
    r_start: float = 3.0,
    r_end: float = 1.2,
    lean: bool = True,
    unit: float | None = None,
    source: str = "BVH",
) -> Bvh:
    """The walk re-laid along a spiral of shrinking radius (module docstring); radii in metres.

    ``seed`` picks the turning direction; ``source`` names the walk in error messages.
    """
    for name, value in (("r_start", r_start), ("r_end", r_end)):
        if not (isinstance(value, int | float) and np.isfinite(value) and value > 0):
            raise VoxposeError(f"{source}: spiral {name} must be a positive number of metres, got {value!r}")
    if turns is not None and not (isinstance(turns, int | float) and np.isfinite(turns) and turns > 0):
        raise VoxposeError(f"{source}: spiral turns must be a positive number, got {turns!r}")
    rng, walk = np.random.default_rng(seed), _Walk(bvh, unit, source)
    direction = rng.choice([-1.0, 1.0])
    start, end = r_start / walk.unit, r_end / walk.unit
    if turns is None:
        length = float(walk.progress[-1])
    elif np.isclose(start, end):
        length = 2 * np.pi * turns * start
    else:
        length = 2 * np.pi * turns * (end - start) / np.log(end / start)
    geometry = dict(r_start=start, r_end=end, length=length)
    delta = direction * spiral_heading(walk.progress, **geometry)
    n = walk.bvh.n_frames
    tilt = np.zeros(n)
    if lean:
        radius = spiral_radius(walk.progress, **geometry) * walk.unit
        tilt = -direction * turn_lean(_speed(walk), radius)
    return Bvh(joints=bvh.joints, frame_time=bvh.frame_time, motion=_relay(walk, delta, np.zeros(n), tilt))


def lean_joint(bvh: Bvh, source: str = "BVH") -> int:
    """Index of the torso joint that ``drunk_from_walk`` leans (by name, with a fallback: module docstring)."""
    jmap = resolve_joint_map(bvh, source=source)
    index = {j.name: i for i, j in enumerate(bvh.joints)}
    root, j = index[jmap.joints[canon.INDEX["root"]]], index[jmap.joints[canon.INDEX["neck"]]]
    chain = []
    while j >= 0 and j != root:
        j = bvh.joints[j].parent
        if j >= 0 and j != root:
            chain.append(j)
    chain = [c for c in reversed(chain) if joint_columns(bvh, c)[1] is not None]
    if not chain:
        raise VoxposeError(f"{source}: no joint with rotation channels between the pelvis and the neck to lean")
    for name in LEAN_JOINT_NAMES:
        for c in chain:
            if bvh.joints[c].name.lower() == name:
                return c
    return chain[0]


def drunk_from_walk(
    bvh: Bvh,
    *,
    seed,
    wander: float = 18.0,
    sway: float = 0.08,
    torso_roll: float = 8.0,
    torso_pitch: float = 5.0,
    unit: float | None = None,
    source: str = "BVH",
) -> Bvh:
    """The walk with a wandering heading, a lateral sway and a swaying torso (module docstring).

    ``wander`` in degrees per sqrt(second), ``sway`` in metres, ``torso_roll`` and ``torso_pitch`` in degrees.
    """
    checks = (("wander", wander), ("sway", sway), ("torso_roll", torso_roll), ("torso_pitch", torso_pitch))
    for name, value in checks:
        if not (isinstance(value, int | float) and np.isfinite(value) and value >= 0):
            raise VoxposeError(f"{source}: drunk {name} must be a non-negative number, got {value!r}")
    rng, walk = np.random.default_rng(seed), _Walk(bvh, unit, source)
    source_motion = walk.bvh.motion
    n, dt = walk.bvh.n_frames, bvh.frame_time
    delta = np.deg2rad(random_walk_heading(rng, n, dt, rate=wander, smooth_s=0.5))
    offset = (sway / walk.unit) * smooth_noise(rng, n, 0.6 / dt)
    roll = np.deg2rad(torso_roll) * smooth_noise(rng, n, 1.5 / dt)
    motion = _relay(walk, delta, offset, np.zeros(n))

    j = lean_joint(bvh, source)
    parent_world = walk.fk[1][:, bvh.joints[j].parent]
    pitch = axis_angle_to_matrix(walk.left, np.deg2rad(torso_pitch))
    extra = axis_angle_to_matrix(np.broadcast_to(walk.forward, (n, 3)), roll) @ pitch
    _, cols = joint_columns(bvh, j)
    order = rotation_order(bvh.joints[j])
    local = euler_to_matrix(source_motion[:, cols], order)
    angles = matrix_to_euler(np.swapaxes(parent_world, -1, -2) @ extra @ parent_world @ local, order)
    motion[:, cols] = source_motion[:, cols] + (angles - source_motion[:, cols] + 180.0) % 360.0 - 180.0
    return Bvh(joints=bvh.joints, frame_time=bvh.frame_time, motion=motion)


def turned(bvh: Bvh, *, degrees: float, source: str = "BVH") -> Bvh:
    """The whole motion turned by ``degrees`` about the vertical axis through the origin (any motion).

    World-aligned descriptors (Section 4) make a regressor recognise only the headings its training
    frames cover, and captured walks mostly go one way; turned copies of training motions fill the
    circle. Like the other transforms it acts through the root channels alone (R_root' = Ry R_root,
    p_root' = Ry p_root), so the captured body motion is unchanged.
    """
    if isinstance(degrees, bool) or not (isinstance(degrees, int | float) and np.isfinite(degrees)):
        raise VoxposeError(f"{source}: turn degrees must be a number, got {degrees!r}")
    bvh = captured_frames(bvh, source)
    pos_cols, rot_cols = joint_columns(bvh, 0)
    if pos_cols is None or rot_cols is None:
        raise VoxposeError(f"{source}: root joint {bvh.joints[0].name!r} needs 3 position and 3 rotation channels")
    _, rotations, _ = forward_kinematics(bvh)
    yaw = axis_rotation("Y", float(degrees))
    motion = bvh.motion.copy()
    motion[:, pos_cols] = bvh.motion[:, pos_cols] @ yaw.T
    turned_root = np.einsum("ab,fbc->fac", yaw, rotations[:, 0])
    motion[:, rot_cols] = unwrap_degrees(matrix_to_euler(turned_root, rotation_order(bvh.joints[0])), axis=0)
    return Bvh(joints=bvh.joints, frame_time=bvh.frame_time, motion=motion)


def derived_name(kind: str, stem: str, params: dict | None = None) -> str:
    """File stem of a derived motion: ``spiral_<stem>``, ``drunk_<stem>`` (the type prefix the workflow
    reads) or ``<stem>_turnDDD`` (a turned copy keeps its source's type)."""
    if kind == "turn":
        return f"{stem}_turn{int(round((params or {}).get('degrees', 0))) % 360:03d}"
    return f"{kind}_{stem}"


def derive_file(src, kind: str, out_dir, seed, params: dict | None = None) -> tuple[Path, dict]:
    """Write ``{out_dir}/{derived_name}.bvh`` derived from ``src``; returns (path, provenance).

    ``kind`` is ``spiral`` or ``drunk`` (``src`` a walk) or ``turn`` (any motion; ``params`` must give
    ``degrees``); ``params`` are passed to the transform (its keyword arguments).
    """
    src = Path(src)
    if kind not in KINDS:
        raise VoxposeError(f"derive: unknown derived motion {kind!r} (known: {', '.join(KINDS)})")
    params = dict(params or {})
    transform = {"spiral": spiral_from_walk, "drunk": drunk_from_walk, "turn": turned}[kind]
    keywords = inspect.signature(transform).parameters.values()
    allowed = {p.name for p in keywords if p.kind is p.KEYWORD_ONLY} - {"seed", "source"}
    unknown = sorted(set(params) - allowed)
    if unknown:
        raise VoxposeError(f"derive {kind}: unknown parameter(s) {unknown} (known: {sorted(allowed)})")
    bvh = read_bvh(src)
    if kind == "turn":
        if "degrees" not in params:
            raise VoxposeError(f"derive turn of {src}: parameter 'degrees' is required")
        derived = turned(bvh, source=str(src), **params)
    else:
        params.setdefault("unit", infer_walk_unit(bvh, str(src)))
        derived = transform(bvh, seed=seed, source=str(src), **params)
    path = Path(out_dir) / f"{derived_name(kind, src.stem, params)}.bvh"
    write_bvh(derived, path)
    provenance = {
        "derived_from": str(src),
        "dropped_reference_frames": bvh.n_frames - derived.n_frames,
        "transform": f"voxpose.motion.derive.{transform.__name__}",
        "seed": seed if isinstance(seed, int) else repr(seed),
        "parameters": params,  # "unit": metres per file unit used for the lengths in metres
        "note": "synthetic path and heading on captured body motion (not captured as such)",
    }
    return path, provenance
