"""The output skeleton: a BVH of y' that the project's readers give back, channel for channel and by positions."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.evaluation import metrics
from voxpose.io.bvh import read_bvh, write_bvh
from voxpose.motion import canon
from voxpose.motion.generate import generate_motion
from voxpose.motion.load import load_motion
from voxpose.motion.output_skeleton import OutputSkeleton, angles_from_bvh
from voxpose.motion.pose_kinematics import forward_kinematics


@pytest.fixture(scope="module")
def motions(tmp_path_factory):
    d = tmp_path_factory.mktemp("skeleton")
    out = []
    for kind, height in (("jump", 1.6), ("spiral", 1.9)):
        write_bvh(generate_motion(kind, seed=2, n_frames=20, height=height), d / f"{kind}_gen_00.bvh")
        out.append(load_motion(d / f"{kind}_gen_00.bvh"))
    return out


def test_canonical_angles_survive_the_position_based_reader(motions, tmp_path):
    """Canonical angles have no limb twist, so load_motion finds exactly the angles written."""
    skeleton = OutputSkeleton.from_motions(motions)
    for m in motions:
        write_bvh(skeleton.bvh(m.angles, m.positions[:, 0], 1 / 30), tmp_path / "out.bvh", precision=9)
        reread = load_motion(tmp_path / "out.bvh")
        assert reread.source["skeleton"] == "generated" and reread.source["unit_scale"] == 1.0
        assert metrics.angle_differences(m.angles, reread.angles).max() < 1e-5
        # joint positions are the forward kinematics of y' on the skeleton, at the written root
        expected = forward_kinematics(m.angles, skeleton.offsets)[0] + m.positions[:, :1]
        np.testing.assert_allclose(reread.positions, expected, atol=1e-6)
        np.testing.assert_allclose(reread.offsets, skeleton.offsets, atol=1e-6)


def test_channels_are_the_angles_and_any_angles_read_back(motions, tmp_path):
    skeleton = OutputSkeleton.from_motions(motions)
    rng = np.random.default_rng(0)
    angles = rng.uniform(-170, 170, (5, canon.N_ANGLES))
    root = rng.normal(size=(5, 3))
    write_bvh(skeleton.bvh(angles, root, 1 / 25), tmp_path / "any.bvh", precision=9)
    bvh = read_bvh(tmp_path / "any.bvh")
    got, got_root = angles_from_bvh(bvh)
    np.testing.assert_allclose(got, angles, atol=1e-6)
    np.testing.assert_allclose(got_root, root, atol=1e-8)
    assert bvh.frame_time == pytest.approx(0.04)


def test_skeleton_is_symmetric_with_limbs_along_the_t_pose(motions):
    skeleton = OutputSkeleton.from_motions(motions)
    off = skeleton.offsets
    for j in ("shoulder", "elbow", "wrist", "hip", "knee", "ankle"):
        np.testing.assert_allclose(off[canon.INDEX["r" + j]], off[canon.INDEX["l" + j]] * [-1, 1, 1])
    for j in ("lelbow", "lwrist", "lknee", "lankle"):
        parent = canon.PARENTS[canon.INDEX[j]]
        direction = off[canon.INDEX[j]] / np.linalg.norm(off[canon.INDEX[j]])
        np.testing.assert_allclose(direction, canon.TPOSE_DIRECTIONS[parent], atol=1e-12)
    # the median of two subjects lies between their bone lengths
    thigh = [np.linalg.norm(m.offsets[canon.INDEX["lknee"]]) for m in motions]
    assert min(thigh) <= np.linalg.norm(off[canon.INDEX["lknee"]]) <= max(thigh)


def test_a_bvh_of_another_skeleton_is_refused(tmp_path):
    write_bvh(generate_motion("walk", seed=1, n_frames=3), tmp_path / "walk.bvh")
    with pytest.raises(VoxposeError, match="joint Hips has channels"):
        angles_from_bvh(read_bvh(tmp_path / "walk.bvh"))
