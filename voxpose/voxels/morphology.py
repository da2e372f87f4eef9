"""Binary dilation and erosion of silhouettes by small symmetric structuring elements, with numpy shifts.

The carver widens and narrows every view by the 3 x 3 square (its window bounds, ``voxels.carve``) and the
degradations study flips a boundary band and grows or shrinks silhouettes by a disc (``voxels.degrade``). These
are ``scipy.ndimage.binary_dilation`` and ``binary_erosion`` with pixels outside the image counting as background
(``border_value=0``), written as ORs and ANDs of shifted copies: the same masks (the tests compare them), without
importing scipy.ndimage, which cost 0.2-0.3 s of start-up in every job that carved or rendered a degraded view,
and faster on the small windows the degradations use. Structuring elements are symmetric, so the reflection that
tells dilation from correlation does not arise.
"""

import numpy as np


def _offsets(element: np.ndarray) -> list[tuple[int, int]]:
    """(dy, dx) of the set pixels of a (2r + 1, 2s + 1) structuring element, relative to its centre."""
    element = np.asarray(element, dtype=bool)
    centre = np.array(element.shape) // 2
    return [(int(dy), int(dx)) for dy, dx in np.argwhere(element) - centre]


def _span(shift: int, size: int) -> tuple[slice, slice]:
    """(destination, source) slices along one axis so that ``dst[i] = src[i + shift]`` where both exist
    (none when the shift reaches past the image)."""
    if abs(shift) >= size:
        return slice(0, 0), slice(0, 0)
    if shift >= 0:
        return slice(0, size - shift), slice(shift, size)
    return slice(-shift, size), slice(0, size + shift)


def dilate(masks: np.ndarray, element: np.ndarray) -> np.ndarray:
    """Masks (..., H, W) dilated by ``element``: a pixel is set if any pixel under the element centred on it is."""
    masks = np.asarray(masks, dtype=bool)
    out = np.zeros_like(masks)
    height, width = masks.shape[-2:]
    for dy, dx in _offsets(element):
        (rows, rows_src), (cols, cols_src) = _span(dy, height), _span(dx, width)
        out[..., rows, cols] |= masks[..., rows_src, cols_src]
    return out


def erode(masks: np.ndarray, element: np.ndarray) -> np.ndarray:
    """Masks (..., H, W) eroded by ``element``: a pixel stays set only if every pixel under the element centred
    on it is set, pixels outside the image counting as unset."""
    masks = np.asarray(masks, dtype=bool)
    out = np.ones_like(masks)
    height, width = masks.shape[-2:]
    for dy, dx in _offsets(element):
        (rows, rows_src), (cols, cols_src) = _span(dy, height), _span(dx, width)
        inside = np.zeros_like(masks)
        inside[..., rows, cols] = masks[..., rows_src, cols_src]
        out &= inside
    return out


def dilate_square(masks: np.ndarray) -> np.ndarray:
    """``dilate`` by the 3 x 3 square, in two passes (rows, then columns: the square is separable)."""
    masks = np.asarray(masks, dtype=bool)
    rows = masks.copy()
    rows[..., 1:, :] |= masks[..., :-1, :]
    rows[..., :-1, :] |= masks[..., 1:, :]
    out = rows.copy()
    out[..., 1:] |= rows[..., :-1]
    out[..., :-1] |= rows[..., 1:]
    return out


def erode_square(masks: np.ndarray) -> np.ndarray:
    """``erode`` by the 3 x 3 square, in two passes like ``dilate_square``."""
    masks = np.asarray(masks, dtype=bool)
    rows = masks.copy()
    rows[..., 1:, :] &= masks[..., :-1, :]
    rows[..., :-1, :] &= masks[..., 1:, :]
    rows[..., [0, -1], :] = False
    out = rows.copy()
    out[..., 1:] &= rows[..., :-1]
    out[..., :-1] &= rows[..., 1:]
    out[..., [0, -1]] = False
    return out
