"""``voxpose render``: pictures through a rig camera are true photographs (a known pose's left hand on the side a
photograph shows it), the skeleton stands where the body was carved, and the outputs are PNG per frame or GIF."""

import numpy as np
import pytest

from tests.helpers import tpose
from voxpose.apply.animation import draw_frames, orbit_camera, placed_skeletons, write_pictures
from voxpose.apply.posed_body import posed_body
from voxpose.apply.predict import Prediction
from voxpose.motion import canon
from voxpose.motion.output_skeleton import OutputSkeleton
from voxpose.motion.pose_kinematics import forward_kinematics
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.render import render_silhouettes
from voxpose.voxels.voxelize import voxelize_silhouettes

RIG = circular_rig(n=6, focal_px=150.0, width=128, image_height=128)


@pytest.fixture(scope="module")
def one_arm_down():
    """The T-pose (facing +Z, its left at +X: ``motion.canon``) with the left arm lowered, carved by RIG."""
    motion = tpose()
    skeleton = OutputSkeleton.from_motions([motion])
    angles = np.zeros((1, canon.N_ANGLES))
    angles[0, 3 * canon.INDEX["lshoulder"] + 2] = 90.0  # YXZ order: the third angle turns about the body's Z
    joints = forward_kinematics(angles, skeleton.offsets)[0][0]
    lwrist, rwrist = joints[canon.INDEX["lwrist"]], joints[canon.INDEX["rwrist"]]
    assert abs(lwrist[0]) < 0.3 and rwrist[0] < -0.5  # left arm hanging, right arm out towards -X
    body = posed_body(angles, skeleton, motion.positions[:, 0])
    seq = voxelize_silhouettes([render_silhouettes(body.frame(0), RIG)], RIG, l_res_fraction=1 / 30, n_basis=20)
    prediction = Prediction(angles=angles, valid=np.array([True]), root=np.zeros((1, 3)), voxels=seq,
                            frames=np.array([7]), fps=30.0)  # fmt: skip
    return prediction, skeleton, motion.positions[0, 0]


def red_columns(picture, rows):
    r, g, b = (picture[rows, :, i].astype(int) for i in range(3))
    return np.flatnonzero(((r > 180) & (g < 90) & (b < 90)).any(axis=0))


@pytest.mark.parametrize("camera, outstretched_side", [(0, "left"), (3, "right")])
def test_a_known_pose_from_a_known_camera_shows_the_arm_on_the_photographs_side(one_arm_down, camera,
                                                                               outstretched_side):  # fmt: skip
    # camera 0 stands at +Z, in front of the subject: the subject's right arm (-X) is on the image's left, as in
    # a photograph of someone facing you; camera 3 stands behind
    prediction, skeleton, _ = one_arm_down
    cam = RIG[camera]
    (_, picture), = draw_frames(prediction, skeleton, cam)
    shoulders = placed_skeletons(prediction.angles, prediction.valid, skeleton, prediction.voxels)[0]
    row = int(round(cam.project(shoulders[canon.INDEX["rshoulder"]])[1]))
    columns = red_columns(picture, slice(row - 3, row + 4))
    centre = cam.project(shoulders[canon.INDEX["neck"]])[0]
    left, right = (columns < centre - 10).sum(), (columns > centre + 10).sum()
    assert (left > 5 and right == 0) if outstretched_side == "left" else (right > 5 and left == 0), (left, right)


def test_skeleton_stands_at_the_carved_root(one_arm_down):
    prediction, skeleton, root = one_arm_down
    seq = prediction.voxels
    joints = placed_skeletons(prediction.angles, prediction.valid, skeleton, seq)[0]
    assert np.linalg.norm(joints[0] - root) < seq.l_res  # the body was carved with its root at ``root``
    np.testing.assert_allclose(joints - joints[0], forward_kinematics(prediction.angles, skeleton.offsets)[0][0])
    nothing = placed_skeletons(prediction.angles, np.array([False]), skeleton, seq)
    assert np.isnan(nothing).all()


def test_png_per_frame_and_gif(one_arm_down, tmp_path):
    from PIL import Image

    prediction, skeleton, _ = one_arm_down
    view = orbit_camera([0.0, 1.0, 0.0], 2.0, azimuth=0.0, elevation=10.0)
    assert write_pictures(draw_frames(prediction, skeleton, view), tmp_path / "f{frame}.png", 30.0) == 1
    with Image.open(tmp_path / "f000007.png") as png:
        assert png.size == (view.width, view.height)
        columns = red_columns(np.asarray(png.convert("RGB")), slice(0, view.height))
    centre = (view.width - 1) / 2  # the virtual view from the front: the outstretched right arm on the left
    assert centre - columns.min() > 2 * (columns.max() - centre) > 0
    assert write_pictures(draw_frames(prediction, skeleton, view), tmp_path / "a.gif", 30.0) == 1


def test_mp4_with_the_video_extra(one_arm_down, tmp_path):
    iio = pytest.importorskip("imageio.v3")
    prediction, skeleton, _ = one_arm_down
    view = orbit_camera([0.0, 1.0, 0.0], 2.0, azimuth=0.0, elevation=10.0, size_px=160)
    assert write_pictures(draw_frames(prediction, skeleton, view), tmp_path / "a.mp4", 30.0) == 1
    assert iio.imread(tmp_path / "a.mp4", index=0).shape == (160, 160, 3)
