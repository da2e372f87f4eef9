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
