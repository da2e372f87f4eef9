"""Silhouettes on disk: one folder of PNG masks per camera, for real multi-camera sequences (Section 6).

Layout: ``{directory}/{camera name}/{frame:06d}.png``, one folder per camera of the rig (named exactly
like the cameras in the rig file) and one image per frame, of the camera's image size. Frame numbers
need not start at 0 but every camera must have the same ones; frames are read in increasing number.
Files and folders whose names start with ``.`` are ignored; any other file in a camera folder must be a
``<digits>.png`` frame.

Masks: images in mode ``1``, ``L``, ``I`` or ``I;16`` are read as they are, any other mode (RGB, RGBA,
palette) is converted to 8-bit grey first. A mask has at most two grey levels: the higher of two levels
is the silhouette and the lower the background; an image of one level is all background if that level
is 0 and all silhouette otherwise. An image with more than two levels (anti-aliased, JPEG-damaged or
soft masks) is an error naming the file: threshold it first, deliberately. ``write_silhouette_folder``
writes 1-bit PNGs (black background, white silhouette), atomically.
"""

import re
from pathlib import Path

import numpy as np
from PIL import Image, UnidentifiedImageError

from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path
from voxpose.voxels.cameras import Rig

_FRAME_FILE = re.compile(r"^(\d+)\.png$", re.IGNORECASE)
_RAW_MODES = ("1", "L", "I", "I;16")


def write_silhouette_folder(frames, rig: Rig, directory, first_frame: int = 0) -> int:
    """Write frames of silhouettes (an iterable of (C, H, W) bool, or an (F, C, H, W) array).

    Frame ``f`` of the iterable becomes ``{directory}/{camera}/{first_frame + f:06d}.png``. Returns the
    number of frames written.
    """
    directory = Path(directory)
    expected = (len(rig),) + rig.image_size
    n = 0
    for n, sil in enumerate(frames, start=1):
        sil = np.asarray(sil)
        if sil.shape != expected or sil.dtype != bool:
            raise VoxposeError(
                f"write silhouettes: frame {n - 1} is {sil.dtype} {sil.shape}, rig {rig.name} needs bool {expected}"
            )
        for cam, mask in zip(rig.cameras, sil, strict=True):
            with atomic_path(directory / cam.name / f"{first_frame + n - 1:06d}.png") as tmp:
                Image.fromarray(mask).save(tmp, format="PNG")
    return n


def _frame_numbers(folder: Path) -> dict:
    """Frame number -> path of every frame file in one camera folder."""
    frames = {}
    for path in sorted(folder.iterdir()):
        if path.name.startswith("."):
            continue
        match = _FRAME_FILE.match(path.name)
        if not match or not path.is_file():
            raise VoxposeError(f"{path}: not a silhouette frame (expected files named <frame number>.png)")
        number = int(match.group(1))
        if number in frames:
            raise VoxposeError(f"{path}: frame {number} also stored as {frames[number].name}")
        frames[number] = path
    return frames


def _layout(directory, rig: Rig):
    """Validate the folder layout; return the sorted frame numbers and each camera's frame files."""
    directory = Path(directory)
    if not directory.is_dir():
        raise VoxposeError(f"{directory}: silhouette folder not found")
    folders = {p.name for p in directory.iterdir() if p.is_dir() and not p.name.startswith(".")}
    missing = [name for name in rig.names if name not in folders]
    if missing:
        raise VoxposeError(
            f"{directory}: no folder for camera(s) {', '.join(missing)} of rig {rig.name} "
            f"(found {len(folders)} folders, the rig has {len(rig)} cameras: {', '.join(rig.names)})"
        )
    extra = sorted(folders - set(rig.names))
    if extra:
        raise VoxposeError(
            f"{directory}: folder(s) {', '.join(extra)} match no camera of rig {rig.name} ({', '.join(rig.names)})"
        )
    files = {name: _frame_numbers(directory / name) for name in rig.names}
    reference = rig.names[0]
    numbers = sorted(files[reference])
    if not numbers:
        raise VoxposeError(f"{directory / reference}: no silhouette frames")
    for name in rig.names[1:]:
        if set(files[name]) != set(numbers):
            differ = sorted(set(files[name]) ^ set(numbers))[0]
            raise VoxposeError(
                f"{directory / name}: {len(files[name])} frames, {directory / reference} has {len(numbers)} "
                f"(frame {differ} is in one folder only)"
            )
    return numbers, files


def read_mask(path, width: int, height: int) -> np.ndarray:
    """One silhouette image as an (H, W) bool mask (rules in the module docstring)."""
    try:
        with Image.open(path) as image:
            if image.size != (width, height):
                raise VoxposeError(
                    f"{path}: image is {image.size[0]}x{image.size[1]}, the camera's is {width}x{height}"
                )
            if image.mode not in _RAW_MODES:
                image = image.convert("L")
            pixels = np.asarray(image)
    except (OSError, UnidentifiedImageError) as err:
        raise VoxposeError(f"{path}: cannot read image ({err})") from None
    if pixels.dtype == bool:
        return pixels.copy()
    if pixels.dtype == np.uint8:
        levels = np.flatnonzero(np.bincount(pixels.reshape(-1), minlength=256))
    else:
        levels = np.unique(pixels)
    if len(levels) > 2:
        raise VoxposeError(f"{path}: not a binary mask ({len(levels)} grey levels; expected at most 2)")
    if len(levels) == 1:
        return np.full(pixels.shape, levels[0] != 0)
    return pixels == levels[1]


def iter_silhouette_folder(directory, rig: Rig):
    """Frames (C, H, W) bool of a silhouette folder, one at a time; the layout is checked first."""
    numbers, files = _layout(directory, rig)
    height, width = rig.image_size

    def frames():
        for number in numbers:
            yield np.stack([read_mask(files[name][number], width, height) for name in rig.names])

    return frames()


def silhouette_frame_numbers(directory, rig: Rig) -> list:
    """The frame numbers (sorted) of a silhouette folder, after checking its layout."""
    return _layout(directory, rig)[0]
