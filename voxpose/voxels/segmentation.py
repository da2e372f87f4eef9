"""Silhouettes from a recording and its empty scene: background subtraction with shadow suppression (Section 4:
"simple background subtraction in controlled environments").

Background: the per-pixel median (per colour channel) of the empty-scene frames (the first ``BACKGROUND_FRAMES``
of them, 25), ``B``.

Colour space: linear RGB as stored (0-255 per channel), compared by brightness and chromaticity (the
brightness/chromaticity split of Horprasert, Harwood & Davis, ICCV Frame-Rate Workshop 1999). For a pixel ``I``
of a frame, its brightness relative to the background is ``alpha = (I . B) / (B . B)`` and its colour
distortion the part of ``I`` not explained by a change of brightness, relative to the background's:
``cd = |I - alpha B| / |B|``. A pixel is foreground when

* its colour differs: ``cd > chroma`` (default 0.12; sensor noise of a few grey levels gives about 0.03), or
* it is much brighter than the background: ``alpha > 1 + brighter`` (default 0.3), or
* it is too dark for a shadow or a dimmer light: ``alpha < shadow`` (default 0.4).

So a shadow or a lighting change (the same colour, 40-100% of the brightness, up to 30% brighter) stays
background, at the price of a subject that wears the background's colour in a darker shade. The colour
distortion is taken relative to at least 10 grey levels per channel (``|B|`` >= 10 sqrt 3), so that sensor
noise on a near-black background does not count as colour.

Clean-up, in order: a morphological closing with a disc of radius ``close`` pixels (default 0: none; 1-2
fill cracks where clothes match the background, but also gaps between limbs, which the hull then keeps: in
``tests/apply/test_studio.py`` radius 1 lowers the hull's IoU with the exact one from 0.99 to 0.94), an
opening with radius ``open`` (default 0: none; it also erases limbs thinner than ``2 open + 1`` pixels), then
holes filled and only the largest 8-connected components kept: those of at least ``min_area`` times the
largest one's area (default 0.02: the subject, with a head or hand that a thin neck or wrist leaves apart in
a small image, but not specks of noise; 0 keeps all).
"""

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from voxpose.errors import VoxposeError

_DARK = 10.0 * np.sqrt(3.0)
BACKGROUND_FRAMES = 25


@dataclass(frozen=True)
class Segmentation:
    """The documented parameters (module docstring), checked when made."""

    chroma: float = 0.12
    brighter: float = 0.3
    shadow: float = 0.4
    close: int = 0
    open: int = 0
    min_area: float = 0.02

    def __post_init__(self):
        if not (np.isfinite(self.min_area) and 0 <= self.min_area <= 1):
            raise VoxposeError(f"--min-area must lie in [0, 1] (a fraction of the largest component), "
                               f"got {self.min_area!r}")  # fmt: skip
        for key in ("chroma", "brighter", "shadow"):
            value = getattr(self, key)
            if not (np.isfinite(value) and value > 0):
                raise VoxposeError(f"--{key} must be a positive number, got {value!r}")
        if self.shadow >= 1:
            raise VoxposeError(f"--shadow must lie in (0, 1): the darkest brightness taken as shadow, "
                               f"got {self.shadow}")  # fmt: skip
        for key in ("close", "open"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise VoxposeError(f"--{key} must be a non-negative integer, got {value!r}")

    def mask(self, image: np.ndarray, background: np.ndarray) -> np.ndarray:
        """(H, W) bool silhouette of one (H, W, 3) image against its (H, W, 3) background."""
        norm2 = (background * background).sum(axis=-1)
        alpha = (image * background).sum(axis=-1) / np.maximum(norm2, 1e-12)
        cd = np.linalg.norm(image - alpha[..., None] * background, axis=-1) / np.maximum(np.sqrt(norm2), _DARK)
        fore = (cd > self.chroma) | (alpha > 1 + self.brighter) | (alpha < self.shadow)
        if self.close:
            fore = ndimage.binary_closing(fore, _disc(self.close), border_value=0)
        if self.open:
            fore = ndimage.binary_opening(fore, _disc(self.open))
        fore = ndimage.binary_fill_holes(fore)
        if self.min_area > 0:
            labels, n = ndimage.label(fore, structure=np.ones((3, 3)))
            if n > 1:
                sizes = np.bincount(labels.reshape(-1))[1:]
                fore = np.isin(labels, np.flatnonzero(sizes >= self.min_area * sizes.max()) + 1)
        return fore


def _disc(radius: int) -> np.ndarray:
    r = np.arange(-radius, radius + 1)
    return r[:, None] ** 2 + r[None, :] ** 2 <= radius * radius


def median_background(frames) -> np.ndarray:
    """Per-pixel, per-channel median of the first ``BACKGROUND_FRAMES`` frames (an iterable of (C, H, W, 3)
    arrays, 0-255), stored as 8-bit while collected: (C, H, W, 3) float64."""
    kept = []
    for frame in frames:
        kept.append(np.clip(np.round(frame), 0, 255).astype(np.uint8))
        if len(kept) == BACKGROUND_FRAMES:
            break
    if not kept:
        raise VoxposeError("background: no frames of the empty scene")
    return np.median(np.stack(kept), axis=0)
