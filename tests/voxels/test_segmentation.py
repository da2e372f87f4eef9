"""Background subtraction: a planted subject on a noisy background with a shadow and a lighting change."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.voxels.segmentation import Segmentation, median_background


@pytest.fixture
def scene():
    rng = np.random.default_rng(3)
    back = 60.0 + 130.0 * rng.uniform(size=(1, 1, 3)) * np.ones((60, 80, 3))
    back[:, 40:] *= 0.7  # a darker wall
    subject = np.zeros((60, 80), dtype=bool)
    subject[10:50, 30:45] = True
    subject[20:24, 45:60] = True  # an arm, 4 px thick
    shadow = np.zeros_like(subject)
    shadow[48:56, 20:60] = True
    frame = back * 0.9  # dimmer light
    frame[shadow] *= 0.5
    frame[subject] = [190.0, 50.0, 40.0]
    frame += rng.normal(0, 3.0, frame.shape)
    frames = [back[None] + rng.normal(0, 3.0, (1,) + back.shape) for _ in range(7)]
    return frame, median_background(frames)[0], subject


def test_subject_found_shadow_and_lighting_change_ignored(scene):
    frame, background, subject = scene
    mask = Segmentation().mask(frame, background)
    assert np.array_equal(mask, subject)


def test_median_background_ignores_a_passer_by():
    frames = [np.full((1, 4, 4, 3), 100.0) for _ in range(5)]
    frames[2][0, 1, 1] = 250.0
    assert np.array_equal(median_background(frames), np.full((1, 4, 4, 3), 100.0))


def test_specks_are_dropped_and_limbs_kept_apart_from_the_body(scene):
    frame, background, subject = scene
    frame = frame.copy()
    frame[2, 2] = [0.0, 255.0, 0.0]  # a speck of noise
    assert np.array_equal(Segmentation().mask(frame, background), subject)
    assert Segmentation(min_area=0).mask(frame, background)[2, 2]
    assert not Segmentation(open=2).mask(frame, background)[20:24, 50:60].any()  # opening erases the thin arm


@pytest.mark.parametrize("kwargs, fragment", [({"chroma": -1.0}, "--chroma"), ({"shadow": 1.2}, "--shadow"),
                                              ({"close": -1}, "--close"), ({"min_area": 2.0}, "--min-area")])
def test_bad_parameters(kwargs, fragment):
    with pytest.raises(VoxposeError, match=fragment):
        Segmentation(**kwargs)


def test_videos_are_read_with_the_video_extra_or_refused_in_one_line_without(tmp_path):
    from voxpose.voxels.cameras import circular_rig
    from voxpose.voxels.recordings import recording

    rig = circular_rig(n=2, width=32, image_height=16)
    try:
        import imageio.v3 as iio
    except ImportError:
        for cam in rig:
            (tmp_path / f"{cam.name}.mp4").write_bytes(b"")
        with pytest.raises(VoxposeError, match=r"cam0.mp4: reading videos needs the optional extra: pip install"):
            next(recording(tmp_path, rig)[1])
        return
    for c, cam in enumerate(rig):
        video = np.stack([np.full((16, 32, 3), 40 * c + 20 * f + 30, np.uint8) for f in range(3)])
        iio.imwrite(tmp_path / f"{cam.name}.mp4", video, fps=10)
    frames = list(recording(tmp_path, rig)[1])
    assert [n for n, _ in frames] == [0, 1, 2] and frames[0][1].shape == (2, 16, 32, 3)
    means = np.array([[images[c].mean() for c in range(2)] for _, images in frames])
    assert np.abs(means - [[30, 70], [50, 90], [70, 110]]).max() < 4  # lossy, but the same grey levels


def test_image_folders_with_frame_numbers_in_their_names(tmp_path):
    from PIL import Image

    from voxpose.voxels.cameras import circular_rig
    from voxpose.voxels.recordings import recording

    rig = circular_rig(n=2, width=8, image_height=6)
    for c, cam in enumerate(rig):
        (tmp_path / cam.name).mkdir()
        for number in (12, 9, 10):
            Image.fromarray(np.full((6, 8, 3), c * 100 + number, np.uint8)).save(tmp_path / cam.name /
                                                                                  f"img_{number:04d}.jpg")
    numbers, frames = recording(tmp_path, rig)
    got = list(frames)
    assert numbers == [9, 10, 12] and [n for n, _ in got] == [9, 10, 12]
    assert got[2][1].shape == (2, 6, 8, 3) and abs(got[2][1][1].mean() - 112) < 2
