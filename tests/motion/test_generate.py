"""The synthetic motions: determinism, heights, the five types' statistics, feet, limits, I/O, headings."""

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter1d

from tests.helpers import standing_height_from_bones
from voxpose.errors import VoxposeError
from voxpose.io.bvh import read_bvh, write_bvh
from voxpose.motion import canon
from voxpose.motion.bvh_kinematics import forward_kinematics
from voxpose.motion.generate import KINDS, default_motion, generate_motion
from voxpose.motion.generated_skeleton import JOINT_NAMES
from voxpose.motion.load import load_motion

FPS = 30
SEEDS = (0, 1, 2)
GAITS = ("walk", "drunk", "spiral", "jog")
J = {name: i for i, name in enumerate(JOINT_NAMES)}


@pytest.fixture(scope="module")
def motions():
    """{kind: [(bvh, (positions, rotations, end sites))]} for three seeds, 150 frames each."""
    out = {}
    for kind in KINDS:
        out[kind] = []
        for seed in SEEDS:
            bvh = generate_motion(kind, seed=seed, n_frames=150, fps=FPS)
            out[kind].append((bvh, forward_kinematics(bvh)))
    return out


def root_speed(fk) -> float:
    root = fk[0][:, 0]
    return float(np.mean(np.linalg.norm(np.diff(root[:, [0, 2]], axis=0), axis=1)) * FPS)


def heading(fk) -> np.ndarray:
    """Body heading (radians) from the root's forward axis, smoothed over 1 s (removes pelvic yaw)."""
    forward = fk[1][:, 0, :, 2]
    return gaussian_filter1d(np.unwrap(np.arctan2(forward[:, 0], forward[:, 2])), FPS, mode="nearest")


def heading_rate(fk) -> float:
    return float(np.degrees(np.mean(np.abs(np.gradient(heading(fk)) * FPS))))


def foot_points(fk) -> np.ndarray:
    """(F, 2, 3, 3): per foot (left, right), the ankle, toe joint and toe End Site."""
    pos, _, ends = fk
    return np.stack(
        [np.stack([pos[:, J[s + "Foot"]], pos[:, J[s + "Toe"]], ends[J[s + "Toe"]]], 1) for s in ("Left", "Right")],
        1,
    )


def segment_distance(a0, a1, b0, b1, samples: int = 21) -> np.ndarray:
    """(F,) smallest distance between segments a0-a1 and b0-b1 (each (F, 3)), by dense sampling."""
    s = np.linspace(0.0, 1.0, samples)[None, :, None]
    a = a0[:, None] + s * (a1 - a0)[:, None]
    b = b0[:, None] + s * (b1 - b0)[:, None]
    return np.linalg.norm(a[:, :, None] - b[:, None, :], axis=-1).min(axis=(1, 2))


def in_pelvis_frame(fk, points: np.ndarray) -> np.ndarray:
    """(F, 3) world points in the root's local frame (x: the subject's left, y: up, z: forward)."""
    pos, rot, _ = fk
    return np.einsum("fba,fb->fa", rot[:, 0], points - pos[:, 0])


def knee_flexion(fk, side: str) -> np.ndarray:
    """Signed knee flexion (degrees) from joint positions: positive when the shank folds backwards."""
    pos, rot, _ = fk
    thigh = pos[:, J[side + "Leg"]] - pos[:, J[side + "UpLeg"]]
    shank = pos[:, J[side + "Foot"]] - pos[:, J[side + "Leg"]]
    cos = np.sum(thigh * shank, 1) / np.linalg.norm(thigh, axis=1) / np.linalg.norm(shank, axis=1)
    sign = np.sign(np.sum(np.cross(thigh, shank) * rot[:, J[side + "UpLeg"], :, 0], 1))
    return np.degrees(np.arccos(np.clip(cos, -1, 1))) * np.where(sign == 0, 1, sign)


def test_bad_arguments_are_voxpose_errors():
    with pytest.raises(VoxposeError, match="unknown motion kind 'dance'"):
        generate_motion("dance", seed=0, n_frames=10)
    with pytest.raises(VoxposeError, match="n_frames"):
        generate_motion("walk", seed=0, n_frames=1)
    with pytest.raises(VoxposeError, match="height"):
        generate_motion("walk", seed=0, n_frames=10, height=3.5)
    with pytest.raises(VoxposeError, match="fps"):
        generate_motion("walk", seed=0, n_frames=10, fps=0)


# --- determinism and heights ------------------------------------------------------------------------
@pytest.mark.parametrize("kind", KINDS)
def test_same_seed_same_motion_other_seed_other_motion(kind):
    a = generate_motion(kind, seed=7, n_frames=40)
    b = generate_motion(kind, seed=7, n_frames=40)
    c = generate_motion(kind, seed=8, n_frames=40)
    np.testing.assert_array_equal(a.motion, b.motion)
    assert not np.allclose(a.motion, c.motion)


def test_heights_drawn_in_range_and_given_height_is_the_skeletons(motions):
    heights = [standing_height_from_bones(bvh.joints) for kind in KINDS for bvh, _ in motions[kind]]
    assert all(1.5 <= h <= 2.0 for h in heights)
    assert len({round(h, 6) for h in heights}) == len(SEEDS)  # drawn from the seed
    bvh = generate_motion("walk", seed=3, n_frames=20, height=1.83)
    assert standing_height_from_bones(bvh.joints) == pytest.approx(1.83, abs=1e-12)


def test_loader_measures_the_drawn_height(tmp_path):
    """The motion loader's height from bone lengths (in motion) agrees with the generator's skeleton."""
    path = tmp_path / "walk_gen_00.bvh"
    write_bvh(generate_motion("walk", seed=4, n_frames=60, height=1.62), path)
    motion = load_motion(path)
    assert motion.source["unit_scale"] == 1.0
    assert motion.height == pytest.approx(1.62, rel=0.01)


# --- the five types are distinct --------------------------------------------------------------------
def test_speeds(motions):
    speed = {kind: [root_speed(fk) for _, fk in motions[kind]] for kind in KINDS}
    assert all(0.8 <= s <= 1.9 for kind in ("walk", "spiral", "drunk") for s in speed[kind])
    assert min(speed["jog"]) > 1.3 * max(speed["walk"])
    assert min(speed["jog"]) > 2.2
    assert max(speed["jump"]) < 0.5 * min(speed["walk"])


def test_pelvis_advances_steadily(motions):
    """Walking and jogging: the root's speed varies little within a sequence (no lurching)."""
    for kind in ("walk", "jog"):
        for _, fk in motions[kind]:
            speed = np.linalg.norm(np.diff(fk[0][:, 0, [0, 2]], axis=0), axis=1) * FPS
            assert np.ptp(speed) < 0.1 * speed.mean()


def test_vertical_root_range(motions):
    ranges = {kind: [float(np.ptp(fk[0][:, 0, 1])) for _, fk in motions[kind]] for kind in KINDS}
    assert max(ranges["walk"]) < 0.08
    assert min(ranges["jog"]) > max(ranges["walk"])
    assert min(ranges["jump"]) > 5 * max(ranges["walk"])


def test_heading_rates(motions):
    rate = {kind: [heading_rate(fk) for _, fk in motions[kind]] for kind in KINDS}
    # walk and jog turn steadily at 15-30 degrees per second
    assert 13.0 < min(rate["walk"] + rate["jog"]) and max(rate["walk"] + rate["jog"]) < 32.0

    # the drunk heading wanders: it strays far more from a steady turn (a straight line in time) than the walk's
    def wander(fk):
        psi = np.degrees(heading(fk))[FPS:-FPS]  # without the ends, where the 1 s smoothing bends the line
        t = np.arange(len(psi))
        return float(np.std(psi - np.polyval(np.polyfit(t, psi, 1), t)))

    strays = {kind: [wander(fk) for _, fk in motions[kind]] for kind in ("walk", "drunk")}
    assert np.mean(strays["drunk"]) > 5 * np.mean(strays["walk"])


def test_spiral_turns_one_way_with_growing_curvature(motions):
    for _, fk in motions["spiral"]:
        psi = heading(fk)
        root = fk[0][:, 0, [0, 2]]
        arc = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(root, axis=0), axis=1))])
        thirds = np.array_split(np.arange(len(psi)), 3)
        curvature = [(psi[i[-1]] - psi[i[0]]) / (arc[i[-1]] - arc[i[0]]) for i in thirds]
        assert np.all(np.sign(curvature) == np.sign(curvature[0]))
        assert abs(curvature[2]) > abs(curvature[0]) * 1.1
        assert 1 / 5.0 < abs(curvature[0]) and abs(curvature[2]) < 1 / 0.8  # radii of 0.8 .. 5 m


def test_knee_flexion_ranges(motions):
    def peak(kind):
        return [max(knee_flexion(fk, "Left").max(), knee_flexion(fk, "Right").max()) for _, fk in motions[kind]]

    assert min(peak("jog")) > max(peak("walk")) + 15
    assert min(peak("jump")) > max(peak("walk"))
    stance_jog = [np.percentile(knee_flexion(fk, "Left"), 5) for _, fk in motions["jog"]]
    stance_walk = [np.percentile(knee_flexion(fk, "Left"), 5) for _, fk in motions["walk"]]
    assert min(stance_jog) > max(stance_walk)  # running never straightens the knee as walking does


def test_flight_phases(motions):
    """Walking always has a foot on the ground; jogging and jumping have flights."""
    for kind, airborne in (("walk", False), ("drunk", False), ("spiral", False), ("jog", True), ("jump", True)):
        for _, fk in motions[kind]:
            lowest = foot_points(fk)[..., 1].min(axis=(1, 2))
            if airborne:
                assert lowest.max() > (0.15 if kind == "jump" else 0.02)
            else:
                assert lowest.max() < 0.03


def test_jump_arms_swing_over_the_head(motions):
    for _, fk in motions["jump"]:
        pos, _, ends = fk
        hands = np.maximum(ends[J["LeftHand"]][:, 1], ends[J["RightHand"]][:, 1])
        assert np.any(hands > ends[J["Head"]][:, 1])


def test_wrists_bend_in_every_kind(tmp_path, motions):
    """The hand bends against the forearm (angle between the two segments from the joint positions), and the six
    canonical wrist angles of Eq. 6 all move, so none is a free zero in the full-body error (issue 20)."""
    wrist = [i for i, name in enumerate(canon.ANGLE_NAMES) if "wrist" in name]
    for kind in KINDS:
        bvh, (pos, _, ends) = motions[kind][0]
        for side in ("Left", "Right"):
            forearm = pos[:, J[side + "Hand"]] - pos[:, J[side + "ForeArm"]]
            hand = ends[J[side + "Hand"]] - pos[:, J[side + "Hand"]]
            cos = np.sum(forearm * hand, axis=1) / np.linalg.norm(forearm, axis=1) / np.linalg.norm(hand, axis=1)
            bend = np.degrees(np.arccos(np.clip(cos, -1, 1)))
            assert np.ptp(bend) > 5.0, (kind, side)
        path = tmp_path / f"{kind}_gen_00.bvh"
        write_bvh(bvh, path)
        assert np.all(load_motion(path).angles[:, wrist].std(axis=0) > 0.1), kind


# --- feet and limits --------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", GAITS)
def test_feet_touch_the_ground_every_stride_and_never_sink(motions, kind):
    for bvh, fk in motions[kind]:
        feet = foot_points(fk)[..., 1]
        assert feet.min() > -1e-6
        stride = int(FPS / 0.7)  # longer than any stride (cadence >= 0.7 strides/s)
        for start in range(0, bvh.n_frames - stride, stride // 2):
            window = feet[start : start + stride]
            assert window[:, 0].min() < 0.01 and window[:, 1].min() < 0.01  # each foot lands


@pytest.mark.parametrize("kind", GAITS + ("jump",))
def test_planted_toes_do_not_slide(motions, kind):
    for _, fk in motions[kind]:
        toes = foot_points(fk)[:, :, 1:]  # toe joints and tips, (F, 2, 2, 3)
        down = (toes[1:, ..., 1] < 0.002) & (toes[:-1, ..., 1] < 0.002)
        slide = np.linalg.norm(np.diff(toes[..., [0, 2]], axis=0), axis=-1)[down]
        # under 14 mm per frame: the turn (up to 30 deg/s) pivots a planted foot a little about its contact
        assert slide.size > 0 and slide.max() < 0.014


@pytest.mark.parametrize("kind", KINDS)
def test_joint_limits_and_no_limb_through_the_body(motions, kind):
    for bvh, fk in motions[kind]:
        pos, rot, ends = fk
        height = standing_height_from_bones(bvh.joints)
        for side, sign in (("Left", 1.0), ("Right", -1.0)):
            knee = knee_flexion(fk, side)
            assert knee.min() > -0.5 and knee.max() < 90.0
            upper = pos[:, J[side + "ForeArm"]] - pos[:, J[side + "Arm"]]
            fore = pos[:, J[side + "Hand"]] - pos[:, J[side + "ForeArm"]]
            elbow = np.degrees(
                np.arccos(np.sum(upper * fore, 1) / np.linalg.norm(upper, axis=1) / np.linalg.norm(fore, axis=1))
            )
            assert elbow.max() < 150.0
            # in the pelvis frame the hands stay outside the hips
            for point in (pos[:, J[side + "Hand"]], ends[J[side + "Hand"]]):
                p = in_pelvis_frame(fk, point)
                low = p[:, 1] < 0.0  # below the pelvis, beside the thighs
                assert np.all(sign * p[low, 0] > 0.08 * height)
        # the legs never pass through each other: thigh, shank and foot axes stay 0.05 H apart
        for a, b in (("UpLeg", "Leg"), ("Leg", "Foot")):
            gap = segment_distance(*(pos[:, J[s + n]] for s in ("Left", "Right") for n in (a, b)))
            assert gap.min() > 0.05 * height
        feet = segment_distance(*(p for s in ("Left", "Right") for p in (pos[:, J[s + "Foot"]], ends[J[s + "Toe"]])))
        assert feet.min() > 0.05 * height


# --- files ------------------------------------------------------------------------------------------
def test_written_files_read_back_the_same(tmp_path, motions):
    bvh = motions["spiral"][0][0]
    path = tmp_path / "spiral_gen_00.bvh"
    write_bvh(bvh, path)
    back = read_bvh(path)
    assert [(j.name, j.parent, j.channels) for j in back.joints] == [(j.name, j.parent, j.channels) for j in bvh.joints]
    np.testing.assert_allclose(back.motion, bvh.motion, rtol=1e-5, atol=1e-4)
    np.testing.assert_allclose(forward_kinematics(back)[0], motions["spiral"][0][1][0], atol=2e-4)
    assert back.frame_time == pytest.approx(1 / FPS)


def test_default_motions_depend_only_on_seed_kind_and_index(tmp_path):
    def written(kind, index, seed):
        write_bvh(default_motion(kind, index, n_frames=12, seed=seed), tmp_path / "m.bvh")
        return (tmp_path / "m.bvh").read_bytes()

    walk = written("walk", 0, seed=11)
    others = [written("walk", 0, seed=12), written("walk", 1, seed=11), written("jog", 0, seed=11)]
    assert written("walk", 0, seed=11) == walk  # the same bytes again, after other sequences were drawn
    assert len({walk, *others}) == 4
    write_bvh(default_motion("jump", 0, n_frames=15, seed=11, fps=25.0), tmp_path / "jump.bvh")
    jump = read_bvh(tmp_path / "jump.bvh")
    assert jump.n_frames == 15 and jump.frame_time == pytest.approx(1 / 25)


# --- headings ---------------------------------------------------------------------------------------
def test_mid_heading_is_the_heading_at_the_middle_frame():
    for kind in ("walk", "jump", "spiral"):
        for target in (-150.0, 40.0):
            fk = forward_kinematics(generate_motion(kind, seed=2, n_frames=120, mid_heading=target))
            forward = fk[1][60, 0, :, 2]  # the root's forward axis at the middle frame
            got = np.degrees(np.arctan2(forward[0], forward[2]))
            assert abs((got - target + 180) % 360 - 180) < 12.0  # pelvic yaw swings a few degrees about it


def test_default_training_sequences_cover_every_heading(tmp_path):
    """Sequences 0 and 1 of walk, drunk, jog and jump (the default Table 1 training set) leave no 10-degree
    heading bin empty, for several master seeds (Section 4: world-aligned descriptors)."""
    for seed in (0, 1, 2):
        headings = []
        for kind in ("walk", "drunk", "jog", "jump"):
            for index in (0, 1):
                path = tmp_path / f"{kind}_gen_{index:02d}.bvh"
                write_bvh(default_motion(kind, index, n_frames=175, seed=seed), path)
                headings.append(load_motion(path).angles[:, 0])
        counts = np.histogram(np.mod(np.concatenate(headings), 360), bins=36, range=(0, 360))[0]
        assert counts.min() > 0, (seed, counts)
