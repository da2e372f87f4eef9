"""The body of y' on the output skeleton is the body of the BVH that ``voxpose predict`` writes, as the motion
reader sees it: the same joints, ends, standing height and solids."""

import numpy as np
import pytest

from voxpose.apply.posed_body import pose_arrays, posed_body, skeleton_height
from voxpose.io.bvh import write_bvh
from voxpose.motion.generate import generate_motion
from voxpose.motion.load import load_motion
from voxpose.motion.output_skeleton import OutputSkeleton
from voxpose.voxels.body import body_ellipsoids


def test_posed_body_is_the_written_bvh_read_back(tmp_path):
    write_bvh(generate_motion("spiral", seed=4, n_frames=12, height=1.8), tmp_path / "spiral_gen_00.bvh")
    motion = load_motion(tmp_path / "spiral_gen_00.bvh")
    skeleton = OutputSkeleton.from_motions([motion])
    root = motion.positions[:, 0] + [0.3, 0.0, -0.2]
    write_bvh(skeleton.bvh(motion.angles, root, 1 / 30), tmp_path / "out.bvh", precision=9)
    reread = load_motion(tmp_path / "out.bvh")  # joint map, End Sites and standing height of the reader
    arrays = pose_arrays(motion.angles, skeleton, root)
    np.testing.assert_allclose(arrays["positions"], reread.positions, atol=1e-6)
    np.testing.assert_allclose(arrays["ends"], reread.ends, atol=1e-6)
    assert skeleton_height(skeleton) == pytest.approx(reread.height, rel=1e-6)
    assert skeleton_height(skeleton) == pytest.approx(motion.height, rel=1e-3)  # the generated subject's
    body, expected = posed_body(motion.angles, skeleton, root), body_ellipsoids(reread)
    np.testing.assert_allclose(body.centres, expected.centres, atol=1e-5)
    np.testing.assert_allclose(body.radii, expected.radii, atol=1e-5)
    # without a root, the root joint sits at the origin
    np.testing.assert_allclose(posed_body(motion.angles, skeleton).centres, body.centres - root[:, None], atol=1e-12)
