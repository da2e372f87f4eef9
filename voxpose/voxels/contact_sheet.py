"""A contact sheet to check silhouette thresholds by eye: frames (rows) x cameras (columns), each image with its
mask tinted red and outlined in yellow."""

import numpy as np
from PIL import Image
from scipy import ndimage

from voxpose.io.atomic import atomic_path

MAX_ROWS = 6


def contact_sheet(rows, path, tile: int = 240) -> None:
    """Write ``rows`` (list of (frame number, (C, H, W, 3) images, (C, H, W) masks)) as one PNG, atomically;
    each image scaled to ``tile`` pixels high."""
    tiles = []
    for _, images, masks in rows:
        row = []
        for image, mask in zip(images, masks, strict=True):
            out = np.clip(image, 0, 255).astype(float)
            out[mask] = 0.55 * out[mask] + 0.45 * np.array([255.0, 0.0, 0.0])
            edge = mask & ~ndimage.binary_erosion(mask)
            out[edge] = [255.0, 230.0, 0.0]
            picture = Image.fromarray(out.astype(np.uint8))
            width = max(1, round(picture.width * tile / picture.height))
            row.append(np.asarray(picture.resize((width, tile), Image.Resampling.NEAREST)))
        tiles.append(np.concatenate(row, axis=1))
    with atomic_path(path) as tmp:
        Image.fromarray(np.concatenate(tiles, axis=0)).save(tmp, format="PNG")
