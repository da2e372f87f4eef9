"""Binary dilation and erosion by shifts (``voxels.morphology``) against scipy.ndimage's, pixels outside the
image counting as background, on random masks of every density and shape, one-pixel-wide images included."""

import numpy as np
import pytest
from scipy import ndimage

from voxpose.voxels.degrade import disc
from voxpose.voxels.morphology import dilate, erode

SHAPES = [(6, 40, 50), (2, 1, 1), (1, 2, 5), (3, 3, 3), (1, 9, 1), (2, 4, 30)]


def _masks(shape, density, seed):
    return np.random.default_rng(seed).random(shape) < density


@pytest.mark.parametrize("shape", SHAPES)
def test_the_3x3_square_equals_ndimage(shape):
    square = np.ones((1, 3, 3), dtype=bool)
    for k, density in enumerate((0.0, 0.1, 0.5, 0.9, 1.0)):
        masks = _masks(shape, density, k + sum(shape))
        np.testing.assert_array_equal(dilate(masks, square[0]), ndimage.binary_dilation(masks, square))
        np.testing.assert_array_equal(erode(masks, square[0]), ndimage.binary_erosion(masks, square, border_value=0))


@pytest.mark.parametrize("radius", [1, 2, 3])
@pytest.mark.parametrize("shape", SHAPES)
def test_discs_equal_ndimage_view_by_view(shape, radius):
    element = disc(radius)
    for k, density in enumerate((0.1, 0.5, 0.9, 1.0)):
        masks = _masks(shape, density, 7 * k + radius + sum(shape))
        for got, mask in zip(dilate(masks, element), masks, strict=True):
            np.testing.assert_array_equal(got, ndimage.binary_dilation(mask, element))
        for got, mask in zip(erode(masks, element), masks, strict=True):
            np.testing.assert_array_equal(got, ndimage.binary_erosion(mask, element, border_value=0))


def test_an_element_without_its_centre_does_not_require_the_pixel_itself():
    ring = np.ones((3, 3), dtype=bool)
    ring[1, 1] = False
    masks = _masks((2, 12, 15), 0.8, 0)
    np.testing.assert_array_equal(erode(masks, ring)[0], ndimage.binary_erosion(masks[0], ring, border_value=0))
    np.testing.assert_array_equal(dilate(masks, ring)[1], ndimage.binary_dilation(masks[1], ring))
