"""Body variation (issue 18 item 3): planted distribution, exact segment geometry, seeded per motion name."""

import numpy as np
import pytest

from tests.helpers import tpose, walk_motion
from voxpose.errors import VoxposeError
from voxpose.motion import canon
from voxpose.voxels.body import SEGMENTS, body_ellipsoids
from voxpose.voxels.body_variation import GIRTH_GROUPS, LENGTHS, BodyVariation, vary_lengths
from voxpose.voxels.landmarks import anatomical_points
from voxpose.voxels.settings import VoxelSettings

INDEX = canon.INDEX


def test_off_by_default_draws_no_factors():
    assert BodyVariation().draw("walk_x", 0) is None
    assert VoxelSettings.from_config({}).body_variation("walk_x", 0) is None


def test_draws_are_seeded_by_name_and_follow_the_planted_distribution():
    variation = BodyVariation(girth_sd=0.1, length_sd=0.04)
    assert variation.draw("walk_cmu_07_01", 3) == variation.draw("walk_cmu_07_01", 3)
    assert variation.draw("walk_cmu_07_01", 3) != variation.draw("walk_cmu_07_02", 3)
    assert variation.draw("walk_cmu_07_01", 3) != variation.draw("walk_cmu_07_01", 4)
    draws = [variation.draw(f"walk_{i:05d}", 0) for i in range(4000)]
    girth = np.log([[d["girth"][g] for g in GIRTH_GROUPS] for d in draws])
    length = np.log([[d["length"][s] for s in LENGTHS] for d in draws])
    assert np.allclose(girth.std(axis=0), 0.1, rtol=0.06) and np.abs(girth.mean(axis=0)).max() < 0.01
    assert np.allclose(length.std(axis=0), 0.04, rtol=0.06) and np.abs(length.mean(axis=0)).max() < 0.004
    assert np.abs(np.corrcoef(girth.T) - np.eye(3)).max() < 0.06  # independent groups


def test_lengths_scale_each_segment_and_carry_what_lies_beyond():
    motion = walk_motion(4)
    joints, ends = anatomical_points(motion.positions, motion.ends, motion.height)
    factors = {"trunk": 1.1, "upperarm": 0.9, "forearm": 1.2, "thigh": 1.05, "shin": 0.95}
    varied, varied_ends = vary_lengths(joints, ends, factors)

    def vec(points, a, b):
        return points[:, INDEX[b]] - points[:, INDEX[a]]

    for segment, (a, b) in {"trunk": ("root", "neck"), "upperarm": ("lshoulder", "lelbow"),
                            "forearm": ("relbow", "rwrist"), "thigh": ("rhip", "rknee"),
                            "shin": ("lknee", "lankle")}.items():  # fmt: skip
        assert np.allclose(vec(varied, a, b), factors[segment] * vec(joints, a, b), atol=1e-12)
    # unscaled relations are rigid: hips apart, shoulders from the neck, the hand and foot ends from their joints
    assert np.allclose(vec(varied, "lhip", "rhip"), vec(joints, "lhip", "rhip"), atol=1e-12)
    assert np.allclose(vec(varied, "neck", "lshoulder"), vec(joints, "neck", "lshoulder"), atol=1e-12)
    for end, joint in (("lhand_tip", "lwrist"), ("rtoe", "rankle"), ("head_top", "neck")):
        e, j = canon.ENDS.index(end), INDEX[joint]
        assert np.allclose(varied_ends[:, e] - varied[:, j], ends[:, e] - joints[:, j], atol=1e-12)


def test_the_feet_stay_on_the_floor_of_a_standing_body():
    motion = tpose()
    joints, ends = anatomical_points(motion.positions, motion.ends, motion.height)
    factors = {"trunk": 1.0, "upperarm": 1.0, "forearm": 1.0, "thigh": 1.1, "shin": 0.9}
    varied, varied_ends = vary_lengths(joints, ends, factors)
    for ankle in ("lankle", "rankle"):
        assert varied[0, INDEX[ankle], 1] == pytest.approx(joints[0, INDEX[ankle], 1], abs=1e-12)
    thigh, shin = 0.44, 0.40  # tests.helpers' skeleton, straight legs
    rise = 0.1 * thigh - 0.1 * shin
    assert varied[0, INDEX["root"], 1] - joints[0, INDEX["root"], 1] == pytest.approx(rise, abs=1e-12)


def test_girths_scale_each_group_and_keep_the_head():
    motion = walk_motion(2)
    factors = {"girth": {"trunk": 1.2, "arms": 0.8, "legs": 1.1}, "length": dict.fromkeys(LENGTHS, 1.0)}
    base, varied = body_ellipsoids(motion), body_ellipsoids(motion, variation=factors)
    for group, names in GIRTH_GROUPS.items():
        for name in names:
            e = SEGMENTS.index(name)
            assert np.allclose(varied.radii[:, e, 1:], factors["girth"][group] * base.radii[:, e, 1:])
            assert np.allclose(varied.radii[:, e, 0], base.radii[:, e, 0])
    head = SEGMENTS.index("head")
    assert np.allclose(varied.radii[:, head], base.radii[:, head])


@pytest.mark.parametrize(
    ("cfg", "message"),
    [
        ({"variation": {"girth": 0.1}}, "voxels.variation: unknown key 'girth' (known: girth_sd, length_sd)"),
        ({"variation": {"length_sd": -0.1}}, "voxels.variation.length_sd must be a number in [0, 0.5], got -0.1"),
        ({"variation": {"girth_sd": True}}, "voxels.variation.girth_sd must be a number in [0, 0.5], got True"),
    ],
)
def test_bad_variation_settings_are_one_line_errors(cfg, message):
    with pytest.raises(VoxposeError) as err:
        VoxelSettings.from_config(cfg)
    assert str(err.value) == message
