"""Loading a BVH as a MotionData: reference frames, units, standing height, resampling, errors."""

import logging

import numpy as np
import pytest

from tests.helpers import random_motion, rescaled, tpose_bvh
from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, joint_columns, write_bvh
from voxpose.motion import canon
from voxpose.motion.joint_map import resolve_joint_map, skeleton_points
from voxpose.motion.load import (
    infer_unit,
    load_motion,
    resample,
    source_frame_rate,
    standing_height,
)

# the hand-made skeleton: leg 0.42 + 0.41, hips 0.08 below the root, root -> neck 0.50, neck -> head top 0.25
TPOSE_HEIGHT = (0.83 + 0.08 + 0.50 + 0.25) / 0.961


def test_resample_integer_ratio_takes_every_nth_frame():
    values = np.random.default_rng(0).normal(size=(41, 2, 3))
    out = resample(values, 120.0, 30.0)
    assert out.shape == (11, 2, 3) and np.array_equal(out, values[::4])
    assert resample(values[:40], 120.0, 30.0).shape[0] == 10  # 39 / 4 -> frames 0, 4, ..., 36


def test_resample_linear_matches_interpolation_by_time():
    rng = np.random.default_rng(1)
    values = rng.normal(size=(50, 3))
    out = resample(values, 50.0, 30.0)
    t_in, t_out = np.arange(50) / 50.0, np.arange(out.shape[0]) / 30.0
    assert out.shape[0] == int(np.floor(49 / 50 * 30)) + 1 and t_out[-1] <= t_in[-1]
    for k in range(3):
        assert np.allclose(out[:, k], np.interp(t_out, t_in, values[:, k]), atol=1e-12)
    up = resample(values, 25.0, 100.0)  # upsampling keeps the end points
    assert up.shape[0] == 49 * 4 + 1 and np.allclose(up[-1], values[-1]) and np.allclose(up[::4], values)


def test_frame_rate_snapping():
    assert source_frame_rate(0.0083333) == 120.0
    assert source_frame_rate(0.0333333) == 30.0
    assert source_frame_rate(0.04) == 25.0
    assert source_frame_rate(0.007) == pytest.approx(142.857142857)


def test_standing_height_by_hand():
    b = tpose_bvh()
    joints, ends = skeleton_points(b, resolve_joint_map(b))
    assert standing_height(joints, ends) == pytest.approx(TPOSE_HEIGHT, rel=1e-12)
    # the leg bones are rigid: a motion that moves only the limbs keeps the height
    moving = random_motion(n_frames=30, seed=5, rigid_trunk=True)
    joints, ends = skeleton_points(moving, resolve_joint_map(moving))
    assert standing_height(joints, ends) == pytest.approx(TPOSE_HEIGHT, rel=1e-9)


@pytest.mark.parametrize(
    ("factor", "unit"),
    [(1.0, 1.0), (100.0, 0.01), (1000.0, 0.001), (1 / 0.0254, 0.0254), (0.45 / 0.0254, 0.0254 / 0.45)],
)
def test_unit_inferred_from_standing_height(tmp_path, factor, unit):
    write_bvh(rescaled(tpose_bvh(n_frames=4), factor), tmp_path / "walk_x.bvh", precision=17)
    m = load_motion(tmp_path / "walk_x.bvh")
    assert m.source["unit_scale"] == pytest.approx(unit, rel=1e-12) and m.source["unit_from"] == "inferred"
    assert m.height == pytest.approx(TPOSE_HEIGHT, rel=1e-9)
    assert np.allclose(m.positions[0, canon.INDEX["neck"]], [0, 0.95 * factor * unit + 0.50, 0])


def test_unit_fallback_and_given(tmp_path, caplog):
    assert infer_unit(TPOSE_HEIGHT * 0.5) == (pytest.approx(1.75 / (TPOSE_HEIGHT * 0.5)), "fallback")
    write_bvh(rescaled(tpose_bvh(n_frames=2), 0.5), tmp_path / "small_x.bvh", precision=17)
    with caplog.at_level(logging.INFO, logger="voxpose.motion.load"):
        m = load_motion(tmp_path / "small_x.bvh")
    assert m.height == pytest.approx(1.75) and m.source["unit_from"] == "fallback"
    assert any(r.levelno == logging.WARNING and "small_x: unit" in r.getMessage() for r in caplog.records)
    given = load_motion(tmp_path / "small_x.bvh", unit_scale=3.0)
    assert given.source["unit_from"] == "given" and given.height == pytest.approx(3.0 * 0.5 * TPOSE_HEIGHT)


def test_inferred_unit_is_logged(tmp_path, caplog):
    write_bvh(rescaled(tpose_bvh(n_frames=2), 100.0), tmp_path / "walk_cm.bvh", precision=17)
    with caplog.at_level(logging.INFO, logger="voxpose.motion.load"):
        load_motion(tmp_path / "walk_cm.bvh")
    expected = f"walk_cm: unit 0.01 m inferred from a standing height of {100 * TPOSE_HEIGHT:.1f} units -> 1.73 m"
    assert expected in caplog.text


def cmu_style_motion(n_frames=41, blank_frames=0) -> Bvh:
    """CMU names at 120 fps: frame 0 a whole-number reference pose, then ``blank_frames`` zero frames."""
    b = random_motion("cmu", n_frames=n_frames, seed=9, fps=120.0)
    b.frame_time = 0.0083333
    b.motion[0] = 0.0
    b.motion[0, :3] = [0.1, 0.9, 0.0]
    _, rot = joint_columns(b, next(i for i, j in enumerate(b.joints) if j.name == "LeftShoulder"))
    b.motion[0, rot[0]] = -21.0
    b.motion[1 : 1 + blank_frames] = 0.0
    return b


def test_reference_frames(tmp_path):
    write_bvh(cmu_style_motion(), tmp_path / "walk_cmu.bvh", precision=17)
    auto = load_motion(tmp_path / "walk_cmu.bvh")
    assert auto.source["dropped_frames"] == 1 and auto.source["skeleton"] == "cmu"
    assert auto.n_frames == 10 and auto.source["source_fps"] == 120.0  # 40 frames at 120 fps -> 10 at 30
    # frame k of the output is source frame 1 + 4k; kept, the reference pose is frame 0
    b = cmu_style_motion()
    joints, _ = skeleton_points(b, resolve_joint_map(b))
    assert np.allclose(auto.positions, joints[1::4], atol=1e-12)
    kept = load_motion(tmp_path / "walk_cmu.bvh", drop_reference_frame=False)
    assert kept.n_frames == 11 and np.allclose(kept.positions, joints[::4], atol=1e-12)
    write_bvh(cmu_style_motion(blank_frames=1), tmp_path / "walk_blank.bvh", precision=17)
    assert load_motion(tmp_path / "walk_blank.bvh").source["dropped_frames"] == 2


def test_true_drops_frame_0_even_when_it_is_not_a_reference_pose(tmp_path):
    b = random_motion("generated", n_frames=12, seed=2)
    write_bvh(b, tmp_path / "jog_gen_00.bvh", precision=17)
    assert load_motion(tmp_path / "jog_gen_00.bvh").source["dropped_frames"] == 0
    forced = load_motion(tmp_path / "jog_gen_00.bvh", drop_reference_frame=True)
    assert forced.source["dropped_frames"] == 1


def test_motion_data_contents(tmp_path):
    b = random_motion(n_frames=61, seed=4)
    b.frame_time = 1 / 60
    write_bvh(b, tmp_path / "drunk_gen_03.bvh", precision=17)
    m = load_motion(tmp_path / "drunk_gen_03.bvh", fps=20.0)
    assert (m.name, m.kind, m.fps, m.n_frames) == ("drunk_gen_03", "drunk", 20.0, 21)
    assert m.positions.shape == (21, 14, 3) and m.rotations.shape == (21, 14, 3, 3)
    assert m.angles.shape == (21, 42) and m.ends.shape == (21, 5, 3) and m.offsets.shape == (14, 3)
    joints, ends = skeleton_points(b, resolve_joint_map(b))
    assert np.allclose(m.positions, joints[::3]) and np.allclose(m.ends, ends[::3])
    assert m.source == {
        "path": str(tmp_path / "drunk_gen_03.bvh"),
        "skeleton": "generated",
        "unit_scale": 1.0,
        "unit_from": "inferred",
        "dropped_frames": 0,
        "source_frames": 61,
        "source_fps": 60.0,
        "unmeasured": [],
    }


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"fps": 0}, "fps must be a positive number"),
        ({"fps": "30"}, "fps must be a positive number"),
        ({"unit_scale": -1.0}, "unit_scale must be a positive number"),
        ({"unit_scale": True}, "unit_scale must be a positive number"),
        ({"drop_reference_frame": "yes"}, "drop_reference_frame must be auto, true or false"),
    ],
)
def test_bad_arguments(tmp_path, kwargs, message):
    write_bvh(tpose_bvh(n_frames=2), tmp_path / "walk_a.bvh")
    with pytest.raises(VoxposeError, match=message):
        load_motion(tmp_path / "walk_a.bvh", **kwargs)


def test_only_reference_frames(tmp_path):
    # a T-pose with nothing after it is the motion (auto); dropping the only frame is an error
    write_bvh(tpose_bvh("cmu", n_frames=3), tmp_path / "walk_ref.bvh")
    assert load_motion(tmp_path / "walk_ref.bvh").source["dropped_frames"] == 0
    write_bvh(tpose_bvh("cmu", n_frames=1), tmp_path / "walk_one.bvh")
    with pytest.raises(VoxposeError, match="no motion frames left after dropping 1 reference frame"):
        load_motion(tmp_path / "walk_one.bvh", drop_reference_frame=True)


def test_position_channels_are_metres_after_scaling(tmp_path):
    b = rescaled(tpose_bvh(n_frames=2), 100.0)
    pos, _ = joint_columns(b, 0)
    assert pos == [0, 1, 2]
    write_bvh(b, tmp_path / "walk_cm.bvh")
    m = load_motion(tmp_path / "walk_cm.bvh")
    assert np.allclose(m.positions[:, 0], [0.0, 0.95, 0.0])
