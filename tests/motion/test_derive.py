"""Spiral and drunken walks derived from straight walks: geometry against closed forms, untouched channels."""

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter1d

from tests.helpers import rescaled
from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, BvhJoint, joint_columns, read_bvh, write_bvh
from voxpose.motion.bvh_kinematics import forward_kinematics
from voxpose.motion.derive import derive_file, drunk_from_walk, lean_joint, spiral_from_walk
from voxpose.motion.generate import generate_motion
from voxpose.motion.load import load_motion

REAL_WALKS = ("walk_cmu_02_01.bvh", "walk_bandai1_walk_normal_001.bvh")


@pytest.fixture(scope="module")
def generated_walk() -> Bvh:
    return generate_motion("walk", seed=5, n_frames=180, turn_rate=0.0)  # a straight walk, like the real ones


def hips(bvh: Bvh) -> int:
    """The pelvis joint (named Hips in all three families here)."""
    return next(i for i, j in enumerate(bvh.joints) if j.name == "Hips")


def walk_geometry(bvh: Bvh):
    """Pelvis path, walking direction u and forward progression s(t), from the source's own FK."""
    pelvis = forward_kinematics(bvh)[0][:, hips(bvh)]
    travel = (pelvis[-1] - pelvis[0]) * [1, 0, 1]
    u = travel / np.linalg.norm(travel)
    return pelvis, u, (pelvis - pelvis[0]) @ u


def yaw_of_change(source: Bvh, derived: Bvh, u: np.ndarray) -> np.ndarray:
    """Heading turn (radians, unwrapped) of the rigid change R_root' R_root^T, read on the direction u."""
    before, after = forward_kinematics(source)[1][:, 0], forward_kinematics(derived)[1][:, 0]
    turned = (after @ np.swapaxes(before, 1, 2)) @ u
    return np.unwrap(np.arctan2(turned[:, 0], turned[:, 2]) - np.arctan2(u[0], u[2]))


def closed_form_spiral(s, r_start, r_end, length):
    """psi(s) = integral of 1 / r(s'), r linear in s from r_start to r_end over ``length`` (then r_end)."""
    inside = np.clip(s, 0, length)
    k = (r_end - r_start) / length
    return np.log1p(k * inside / r_start) / k + np.maximum(s - length, 0) / r_end


def path_heading(points: np.ndarray, frame_time: float) -> np.ndarray:
    """Direction of travel (radians, unwrapped) of a path, its velocity smoothed over 0.5 s."""
    velocity = gaussian_filter1d(np.gradient(points, axis=0), 0.5 / frame_time, axis=0, mode="nearest")
    return np.unwrap(np.arctan2(velocity[:, 0], velocity[:, 2]))


def non_root_columns(bvh: Bvh, skip=()) -> np.ndarray:
    start = len(bvh.joints[0].channels)
    cols = np.arange(start, bvh.motion.shape[1])
    for j in skip:
        pos, rot = joint_columns(bvh, j)
        cols = np.setdiff1d(cols, (pos or []) + (rot or []))
    return cols


def motion_frames(bvh: Bvh, reference: int) -> Bvh:
    """The source without its ``reference`` leading reference-pose frames."""
    return Bvh(bvh.joints, bvh.frame_time, bvh.motion[reference:])


def check_spiral(source: Bvh, seed: int, reference: int = 0, **params) -> None:
    derived = spiral_from_walk(source, seed=seed, **params)
    source = motion_frames(source, reference)
    assert derived.n_frames == source.n_frames
    cols = non_root_columns(source)
    np.testing.assert_array_equal(derived.motion[:, cols], source.motion[:, cols])  # body-local motion kept
    pelvis, u, s = walk_geometry(source)
    unit = params["unit"]
    expected = closed_form_spiral(s * unit, params["r_start"], params["r_end"], s[-1] * unit)
    turn = yaw_of_change(source, derived, u)
    turn -= turn[0]  # zero at s = 0 (the reference frame)
    direction = np.sign(turn[-1])
    np.testing.assert_allclose(turn, direction * expected, atol=1e-6)
    # the new pelvis path turns the same way with growing curvature close to 1/r
    path = forward_kinematics(derived)[0][:, hips(source)] * [1, 0, 1]
    arc = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))]) * unit
    psi = path_heading(path, source.frame_time)
    inner = np.arange(len(psi))[int(0.1 * len(psi)) : int(0.9 * len(psi))]
    thirds = np.array_split(inner, 3)
    curvature = [(psi[i[-1]] - psi[i[0]]) / (arc[i[-1]] - arc[i[0]]) for i in thirds]
    assert np.all(np.sign(curvature) == direction)
    assert abs(curvature[2]) > abs(curvature[0])
    mid = thirds[1][len(thirds[1]) // 2]
    radius = params["r_start"] + (params["r_end"] - params["r_start"]) * s[mid] / s[-1]
    assert abs(curvature[1]) == pytest.approx(1 / radius, rel=0.25)
    # every frame is moved rigidly: distances between joints are kept
    before, after = forward_kinematics(source)[0], forward_kinematics(derived)[0]
    for a, b in ((0, -1), (hips(source), len(source.joints) // 2)):
        np.testing.assert_allclose(
            np.linalg.norm(after[:, a] - after[:, b], axis=1),
            np.linalg.norm(before[:, a] - before[:, b], axis=1),
            atol=1e-9,
        )


def test_spiral_of_a_generated_walk(generated_walk):
    check_spiral(generated_walk, seed=0, r_start=3.0, r_end=1.2, unit=1.0, lean=False)


@pytest.mark.parametrize("name", REAL_WALKS)
def test_spiral_of_real_walks(shared_bvh_dir, name):
    source = read_bvh(shared_bvh_dir / name)
    unit = 0.0254 / 0.45 if "cmu" in name else 0.01
    reference = 1 if "cmu" in name else 0  # CMU's frame 0 is a reference T-pose (whole-degree rotations)
    assert np.all(source.motion[:reference, 3:] == np.round(source.motion[:reference, 3:]))
    check_spiral(source, seed=1, reference=reference, r_start=2.5, r_end=1.0, unit=unit, lean=False)


def test_spiral_unit_is_inferred_from_the_skeleton(generated_walk):
    metres = spiral_from_walk(generated_walk, seed=2)
    centimetres = spiral_from_walk(rescaled(generated_walk, 100.0), seed=2)
    np.testing.assert_allclose(centimetres.motion[:, :3], 100 * metres.motion[:, :3], rtol=1e-9, atol=1e-7)
    np.testing.assert_allclose(centimetres.motion[:, 3:6], metres.motion[:, 3:6], atol=1e-7)


def test_spiral_lean_tilts_the_body_into_the_turn_about_the_ground(generated_walk):
    flat = spiral_from_walk(generated_walk, seed=3, lean=False)
    leaning = spiral_from_walk(generated_walk, seed=3, lean=True)
    pos_flat, rot_flat, _ = forward_kinematics(flat)
    pos_lean, rot_lean, _ = forward_kinematics(leaning)
    # the tilt angle: atan(v^2 / (g r)) with the walking speed and the radius at that distance
    up_flat, up_lean = rot_flat[:, 1, :, 1], rot_lean[:, 1, :, 1]  # the Spine's up axis
    tilt = np.degrees(np.arccos(np.clip(np.sum(up_flat * up_lean, 1), -1, 1)))
    assert 2.0 < tilt[len(tilt) // 2] < 15.0
    assert tilt[-20] > tilt[20]  # the radius shrinks, the lean grows
    # towards the centre: the head moves to the side the path turns to
    turn = np.sign(yaw_of_change(generated_walk, flat, walk_geometry(generated_walk)[1])[-1])
    heading = rot_flat[:, 0, :, 2]
    left = np.stack([heading[:, 2], np.zeros(len(heading)), -heading[:, 0]], 1)
    head = forward_kinematics(leaning)[0][:, 4] - pos_flat[:, 4]
    assert np.all(turn * np.sum(head * left, 1)[30:] > 0)
    # the pivot is the ground below the pelvis: the feet move far less than the head
    feet = [i for i, j in enumerate(generated_walk.joints) if j.name.endswith("Foot")]
    assert np.abs(pos_lean[:, feet] - pos_flat[:, feet]).max() < 0.3 * np.abs(head).max()


def test_spiral_turns_parameter_and_direction_from_the_seed(generated_walk):
    _, u, s = walk_geometry(generated_walk)
    derived = spiral_from_walk(generated_walk, seed=4, turns=0.25, r_start=3.0, r_end=2.0, lean=False, unit=1.0)
    length = 2 * np.pi * 0.25 * (2.0 - 3.0) / np.log(2.0 / 3.0)  # the distance of a quarter turn
    turn = yaw_of_change(generated_walk, derived, u)
    expected = closed_form_spiral(s, 3.0, 2.0, length)
    np.testing.assert_allclose(np.abs(turn - turn[0]), expected, atol=1e-6)
    assert s[-1] > length  # so the end is on the circle of r_end
    directions = {
        np.sign(yaw_of_change(generated_walk, spiral_from_walk(generated_walk, seed=k, lean=False), u)[-1])
        for k in range(8)
    }
    assert directions == {-1.0, 1.0}
    again = spiral_from_walk(generated_walk, seed=4, turns=0.25, r_start=3.0, r_end=2.0, lean=False, unit=1.0)
    np.testing.assert_array_equal(again.motion, derived.motion)


def check_drunk(source: Bvh, seed: int, reference: int = 0) -> None:
    derived = drunk_from_walk(source, seed=seed)
    source = motion_frames(source, reference)
    assert derived.n_frames == source.n_frames
    leaned = lean_joint(source)
    assert source.joints[leaned].name == "Spine"
    cols = non_root_columns(source, skip=[leaned])
    np.testing.assert_array_equal(derived.motion[:, cols], source.motion[:, cols])
    _, rot_cols = joint_columns(source, leaned)
    assert not np.allclose(derived.motion[:, rot_cols], source.motion[:, rot_cols])
    # the heading wanders: the direction of travel varies more than the straight source's
    h = hips(source)
    spread = []
    for bvh in (source, derived):
        psi = path_heading(forward_kinematics(bvh)[0][:, h] * [1, 0, 1], source.frame_time)
        spread.append(np.std(psi))
    assert spread[1] > 2 * spread[0]
    # below the lean joint the body moves rigidly; above it, rigidly about the lean joint
    before, after = forward_kinematics(source)[0], forward_kinematics(derived)[0]
    above = [i for i, j in enumerate(source.joints) if j.name in ("Neck", "Head")]
    for group in ([0, h], [leaned] + above):
        a, b = group[0], group[-1]
        np.testing.assert_allclose(
            np.linalg.norm(after[:, a] - after[:, b], axis=1),
            np.linalg.norm(before[:, a] - before[:, b], axis=1),
            atol=1e-6,
        )


def test_drunk_of_a_generated_walk(generated_walk):
    check_drunk(generated_walk, seed=0)
    np.testing.assert_array_equal(
        drunk_from_walk(generated_walk, seed=0).motion, drunk_from_walk(generated_walk, seed=0).motion
    )
    assert not np.allclose(
        drunk_from_walk(generated_walk, seed=1).motion, drunk_from_walk(generated_walk, seed=0).motion
    )


@pytest.mark.parametrize("name", REAL_WALKS)
def test_drunk_of_real_walks(shared_bvh_dir, name):
    check_drunk(read_bvh(shared_bvh_dir / name), seed=2, reference=1 if "cmu" in name else 0)


def test_drunk_torso_lean_rotates_the_upper_body_by_the_planned_angle(generated_walk):
    quiet = drunk_from_walk(generated_walk, seed=6, torso_roll=0.0, torso_pitch=0.0)
    pitched = drunk_from_walk(generated_walk, seed=6, torso_roll=0.0, torso_pitch=10.0)
    spine = lean_joint(generated_walk)
    _, rot_q, _ = forward_kinematics(quiet)
    _, rot_p, _ = forward_kinematics(pitched)
    change = rot_p[:, spine] @ np.swapaxes(rot_q[:, spine], 1, 2)  # A E A^T: E turned with the body
    angle = np.degrees(np.arccos(np.clip((np.trace(change, axis1=1, axis2=2) - 1) / 2, -1, 1)))
    np.testing.assert_allclose(angle, 10.0, atol=1e-6)
    axis = np.stack(
        [change[:, 2, 1] - change[:, 1, 2], change[:, 0, 2] - change[:, 2, 0], change[:, 1, 0] - change[:, 0, 1]], 1
    )
    np.testing.assert_allclose(axis[:, 1], 0.0, atol=1e-9)  # a pitch about the horizontal left axis
    np.testing.assert_allclose(quiet.motion[:, 6:], generated_walk.motion[:, 6:], atol=1e-9)


def test_lean_joint_fallback_is_the_first_torso_joint():
    bvh = generate_motion("walk", seed=0, n_frames=3)
    renamed = [
        BvhJoint({"Spine": "Lumbar", "Chest": "Thorax"}.get(j.name, j.name), j.parent, j.offset, j.channels, j.end_site)
        for j in bvh.joints
    ]
    other = Bvh(renamed, bvh.frame_time, bvh.motion)
    assert other.joints[lean_joint(other)].name == "Lumbar"  # no name matches: first joint above the root
    assert bvh.joints[lean_joint(bvh)].name == "Spine"


def test_derive_file_names_provenance_and_errors(tmp_path, generated_walk):
    src = tmp_path / "walk_gen_07.bvh"
    write_bvh(generated_walk, src)
    path, provenance = derive_file(src, "spiral", tmp_path / "out", seed=3, params={"r_end": 1.5})
    assert path == tmp_path / "out" / "spiral_walk_gen_07.bvh"
    assert path.name.split("_", 1)[0] == "spiral"
    derived = read_bvh(path)
    expected = spiral_from_walk(read_bvh(src), seed=3, r_end=1.5).motion
    np.testing.assert_allclose(derived.motion, expected, rtol=6e-6, atol=1e-12)  # 6 printed digits
    assert provenance["derived_from"] == str(src)
    assert provenance["parameters"] == {"r_end": 1.5, "unit": 1.0}
    assert provenance["transform"].endswith("spiral_from_walk") and provenance["seed"] == 3
    assert provenance["dropped_reference_frames"] == 0
    path, provenance = derive_file(src, "drunk", tmp_path / "out", seed=3)
    assert path.name == "drunk_walk_gen_07.bvh" and provenance["transform"].endswith("drunk_from_walk")
    with pytest.raises(VoxposeError, match="unknown derived motion 'moonwalk'"):
        derive_file(src, "moonwalk", tmp_path, seed=0)
    with pytest.raises(VoxposeError, match=r"unknown parameter\(s\) \['radius'\]"):
        derive_file(src, "spiral", tmp_path, seed=0, params={"radius": 2})


def test_bad_walks_and_parameters_are_voxpose_errors(generated_walk):
    standing = Bvh(generated_walk.joints, generated_walk.frame_time, np.repeat(generated_walk.motion[:1], 30, axis=0))
    with pytest.raises(VoxposeError, match="not a walk: the pelvis travels 0.00 m"):
        spiral_from_walk(standing, seed=0, source="still.bvh")
    with pytest.raises(VoxposeError, match="r_end"):
        spiral_from_walk(generated_walk, seed=0, r_end=-1.0)
    with pytest.raises(VoxposeError, match="turns"):
        spiral_from_walk(generated_walk, seed=0, turns=0)
    with pytest.raises(VoxposeError, match="sway"):
        drunk_from_walk(generated_walk, seed=0, sway=float("nan"))
    with pytest.raises(VoxposeError, match="unit"):
        spiral_from_walk(generated_walk, seed=0, unit=0.0)
    no_position = [
        BvhJoint(j.name, j.parent, j.offset, j.channels[3:] if i == 0 else j.channels, j.end_site)
        for i, j in enumerate(generated_walk.joints)
    ]
    with pytest.raises(VoxposeError, match="root joint 'Hips' needs 3 position and 3 rotation channels"):
        spiral_from_walk(Bvh(no_position, generated_walk.frame_time, generated_walk.motion[:, 3:]), seed=0)


def test_derived_cmu_file_has_no_reference_frame_left(shared_bvh_dir, tmp_path):
    src = shared_bvh_dir / "walk_cmu_02_01.bvh"
    path, provenance = derive_file(src, "spiral", tmp_path, seed=0)
    assert provenance["dropped_reference_frames"] == 1
    motion = load_motion(path)  # the loader drops nothing more: every frame is captured motion
    assert motion.source["dropped_frames"] == 0
    assert motion.source["source_frames"] == read_bvh(src).n_frames - 1


def test_turned_copy_rotates_every_joint_about_the_vertical_and_shifts_only_the_heading(tmp_path, generated_walk):
    from voxpose.motion.derive import turned

    source = tmp_path / "walk_src.bvh"
    write_bvh(generated_walk, source)
    path, provenance = derive_file(source, "turn", tmp_path, seed=0, params={"degrees": 90})
    assert path.name == "walk_src_turn090.bvh" and provenance["parameters"] == {"degrees": 90}
    before, after = forward_kinematics(read_bvh(source))[0], forward_kinematics(read_bvh(path))[0]
    yaw = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # Ry(90): x -> -z, z -> x
    np.testing.assert_allclose(after, before @ yaw.T, atol=2e-5)  # BVH text keeps limited digits
    a, b = load_motion(source), load_motion(path)
    heading = (b.angles[:, 0] - a.angles[:, 0] + 180) % 360 - 180
    np.testing.assert_allclose(heading, 90.0, atol=1e-3)
    np.testing.assert_allclose(b.angles[:, 1:], a.angles[:, 1:], atol=1e-3)
    with pytest.raises(VoxposeError, match="degrees"):
        turned(generated_walk, degrees=float("nan"))
    with pytest.raises(VoxposeError, match="'degrees' is required"):
        derive_file(source, "turn", tmp_path, seed=0)
