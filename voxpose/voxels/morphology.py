"""Binary dilation and erosion of silhouettes by small symmetric structuring elements, with numpy shifts.

The carver widens and narrows every view by the 3 x 3 square (its window bounds, ``voxels.carve``) and the
degradations study flips a boundary band and grows or shrinks silhouettes by a disc (``voxels.degrade``). These
are ``scipy.ndimage.binary_dilation`` and ``binary_erosion`` with pixels outside the image counting as background
(``border_value=0``), written as ORs and ANDs of shifted copies, one per pixel of the element: the same masks
(the tests compare them), without importing scipy.ndimage, which cost 0.2-0.3 s of start-up in every job that
carved or rendered a degraded view. Also faster (best of 30 runs, one core): six 480 x 480 views by the 3 x 3
square, dilation 1.00 ms and erosion 1.02 ms against scipy's 11.9 and 7.0; a 290 x 130 window by the disc of
radius 2, 0.10 and 0.11 ms against 0.18 and 0.51. Structuring elements are symmetric, so the reflection that
tells dilation from correlation does not arise.
"""

import numpy as np


def _offsets(element: np.ndarray) -> list[tuple[int, int]]:
    """(dy, dx) of the set pixels of a (2r + 1, 2s + 1) structuring element, relative to its centre."""
    element = np.asarray(element, dtype=bool)
    centre = np.array(element.shape) // 2
    return [(int(dy), int(dx)) for dy, dx in np.argwhere(element) - centre]


def _span(shift: int, size: int) -> tuple[slice, slice, slice]:
    """(destination, source, rest) slices along one axis: ``dst[i] = src[i + shift]`` where both exist, and the
    destination's indices with no source (all of them when the shift reaches past the image)."""
    if abs(shift) >= size:
        return slice(0, 0), slice(0, 0), slice(0, size)
    if shift >= 0:
        return slice(0, size - shift), slice(shift, size), slice(size - shift, size)
    return slice(-shift, size), slice(0, size + shift), slice(0, -shift)


def dilate(masks: np.ndarray, element: np.ndarray) -> np.ndarray:
    """Masks (..., H, W) dilated by ``element``: a pixel is set if any pixel under the element centred on it is."""
    masks = np.asarray(masks, dtype=bool)
    out = np.zeros_like(masks)
    height, width = masks.shape[-2:]
    for dy, dx in _offsets(element):
        (rows, rows_src, _), (cols, cols_src, _) = _span(dy, height), _span(dx, width)
        out[..., rows, cols] |= masks[..., rows_src, cols_src]
    return out


def erode(masks: np.ndarray, element: np.ndarray) -> np.ndarray:
    """Masks (..., H, W) eroded by ``element``: a pixel stays set only if every pixel under the element centred
    on it is set, pixels outside the image counting as unset."""
    masks = np.asarray(masks, dtype=bool)
    out = np.ones_like(masks)
    height, width = masks.shape[-2:]
    for dy, dx in _offsets(element):
        (rows, rows_src, rows_out), (cols, cols_src, cols_out) = _span(dy, height), _span(dx, width)
        out[..., rows, cols] &= masks[..., rows_src, cols_src]
        out[..., rows_out, :] = False  # the element reaches past the image there
        out[..., cols_out] = False
    return out
