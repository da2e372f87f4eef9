"""Ground contact of the generated motions: root height and path from the feet, feet planted by leg IK.

Root. Each foot has three contact points: the heel (0.039 H below and 0.038 H behind the ankle, in the
foot's frame), the ball (toe joint) and the toe tip (End Site). With the pose's forward kinematics in the
heading frame (root at the origin, walking along +Z): the root height is the one that puts the lowest contact
point of the feet in stance on y = 0 (the root height comes from the stance leg); in flight the root follows a
ballistic parabola (g = 9.81 m/s^2) between the take-off and landing heights. The root's horizontal step is, per
stance, the mean of the steps that keep that foot's lowest point fixed (``_steady_steps``: averaged over both
feet in double support, interpolated in flight), smoothed over 0.25 s forward and 0.1 s sideways, so the
pelvis advances steadily and sways; walking speed is therefore not drawn directly but follows from the drawn
cadence, stride scale and height (``find_support``).

Feet (``place_feet``). What the smoothing leaves is removed by a two-link leg IK (``leg_ik``): a stance foot is
moved back by its lowest point's drift since heel strike, so it stays planted (the hold eases out over 0.1 s
after toe-off); a swing foot is lifted just enough to clear the ground by 1 cm; a foot the stretched leg
cannot reach rolls heel-up about its ball (``toe_rocker``). Foot orientations are kept, so contact heights do
not change.
"""

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d

from voxpose.motion.bvh_kinematics import forward_kinematics
from voxpose.motion.gait import Plan
from voxpose.motion.generated_skeleton import HEEL, JOINT_INDEX, bvh_from_rotations
from voxpose.motion.paths import GRAVITY
from voxpose.motion.rotations import axis_angle_to_matrix, axis_rotation

_RAMP_S = 0.1  # seconds: a foot's hold eases out after toe-off; the swing clearance ramps in and out


@dataclass
class Support:
    """The pose's forward kinematics in the heading frame (root at the origin) and what it implies."""

    positions: np.ndarray  # (n, J, 3) joint positions
    rotations: np.ndarray  # (n, J, 3, 3) world joint rotations
    contacts: np.ndarray  # (n, 6, 3) left heel, ball, toe tip, right heel, ball, toe tip
    root_y: np.ndarray  # (n,) root height above the ground
    steps: np.ndarray  # (n - 1, 2) horizontal root steps (x, z)


def find_support(joints, local: np.ndarray, plan: Plan, t: np.ndarray, height: float) -> Support:
    """Forward kinematics of the pose in the heading frame, root height and horizontal root steps.

    The lowest contact point (heel, ball, toe tip) of the feet in stance is on y = 0; flights (no foot
    in stance) follow a ballistic parabola. Jumps: step k keeps the lowest stance point of frame k fixed
    from frame k to k + 1. Gaits (``plan.smooth_s`` > 0): ``_steady_steps``, then smoothed; the feet are
    put back on their contacts by ``place_feet``. Airborne steps are interpolated from the neighbouring
    supported ones, plus the plan's flight speed.
    """
    n, dt = len(t), t[1] - t[0]
    pos, rot, ends = forward_kinematics(bvh_from_rotations(joints, np.zeros((n, 3)), local, dt))
    points = []
    for side in ("Left", "Right"):
        foot, toe = JOINT_INDEX[side + "Foot"], JOINT_INDEX[side + "Toe"]
        points += [pos[:, foot] + rot[:, foot] @ (height * HEEL), pos[:, toe], ends[toe]]
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
    return Support(pos, rot, points, root_y, steps)


def _steady_steps(points: np.ndarray, stance: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Root steps (n-1, 2) of a gait: per stance, the mean step that keeps that foot's pivot planted.

    For each foot and each of its stances, the steps that would keep its lowest contact point fixed are
    averaged over the stance, so that over a whole stance the root travels exactly as far as the planted
    foot allows and the foot needs no net correction at toe-off (``place_feet`` removes the rest).
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


def yaw_apply(psi: np.ndarray, x: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def toe_rocker(hip, ankle, ball, foot_rot, lengths, slack: float = 1e-3):
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


def place_feet(local, support: Support, stance, xz, psi, t, lengths) -> np.ndarray:
    """Put the feet where the ground says, by a two-link leg IK (``leg_ik``) per foot and frame.

    Stance: the world drift of the foot's lowest contact point between consecutive frames (left by the
    smoothed root path) is summed from the start of its stance, and the foot is moved back by that sum,
    so it stays planted. The hold eases out over ``_RAMP_S`` after toe-off (the drift still summed, the
    correction weighted down by a smoothstep), so the foot leaves the ground without a jump in velocity.
    Swing and flight: the foot is lifted just enough for its lowest point to clear the ground by 1 cm
    (ramped in after toe-off and out before heel strike). A foot the stretched leg cannot reach rolls
    heel-up about its ball (``toe_rocker``); otherwise the foot's world orientation is kept, so its
    contact heights change only by the lift. Thigh, knee and ankle (and toe, after a roll) rotations are
    re-solved (hinge axis from the original thigh). Returns the new local rotations.
    """
    n = len(t)
    idx = np.arange(n)
    world = np.stack(yaw_apply(psi[:, None], support.contacts[..., 0], support.contacts[..., 2]), axis=-1)
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
        cx, cz = yaw_apply(-psi, corr[:, 0], corr[:, 1])
        moved = (np.hypot(cx, cz) > 1e-9) | (lift > 0)
        if not moved.any():
            continue
        up, leg, foot, toe = (JOINT_INDEX[side + s] for s in ("UpLeg", "Leg", "Foot", "Toe"))
        rot, pos = support.rotations[moved], support.positions[moved]
        shift = np.stack([cx, lift, cz], axis=1)[moved]
        ankle, foot_rot = toe_rocker(pos[:, up], pos[:, foot] + shift, pos[:, toe] + shift, rot[:, foot], lengths)
        thigh, knee = leg_ik(pos[:, up], ankle, rot[:, up, :, 0], lengths)
        shank = thigh @ axis_rotation("X", knee)
        out[moved, up] = np.swapaxes(pelvis[moved], -1, -2) @ thigh
        out[moved, leg] = axis_rotation("X", knee)
        out[moved, foot] = np.swapaxes(shank, -1, -2) @ foot_rot
        out[moved, toe] = np.swapaxes(foot_rot, -1, -2) @ rot[:, toe]
    return out
