"""Silhouettes on disk: one folder of PNG masks per camera, for real multi-camera sequences (Section 6).

Layout: a ``pattern`` relative to the silhouette folder with the fields ``{camera}`` (a camera name of the rig)
and ``{frame}`` (digits: the frame number, kept through ``carve`` and ``predict``), and optionally the wildcards
``*`` and ``?`` within one path component; the default ``{camera}/{frame}.png`` is one folder per camera with
files such as ``000042.png``. Another layout: ``--pattern '{camera}/img_{frame}.png'`` or
``--pattern 'view_{camera}_{frame}.pgm'``. The rig chooses the cameras: files of cameras that are not in the rig
are ignored (a subset of a studio's cameras needs no folder of its own; a log line lists them), every camera
of the rig must have files and all the same frame numbers, read in increasing order. Files and folders whose
names start with ``.`` are ignored; with the default pattern any other file in a camera's folder is an error.

Masks: images in mode ``1``, ``L``, ``I`` or ``I;16`` are read as they are, any other mode (RGB, RGBA,
palette) is converted to 8-bit grey first. A mask with at most two grey levels is binary: the higher of two
levels is the silhouette and the lower the background; an image of one level is all background if that level
is 0 and all silhouette otherwise. A mask with more levels (anti-aliased or soft masks) is thresholded at half
the range of its type: silhouette where the grey level is at least 128 (8-bit), 32768 (16-bit) or half its
maximum (32-bit); the first such file is logged. ``write_silhouette_folder`` writes 1-bit PNGs (black
background, white silhouette), atomically.
"""

import logging
import re
from pathlib import Path

import numpy as np
from PIL import Image, UnidentifiedImageError

from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path
from voxpose.voxels.cameras import Rig

log = logging.getLogger(__name__)

DEFAULT_PATTERN = "{camera}/{frame}.png"
_RAW_MODES = ("1", "L", "I", "I;16")
_GREY_HALF = {np.dtype(np.uint8): 128, np.dtype(np.uint16): 32768}
_logged_grey: set = set()


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


def pattern_regex(pattern: str):
    """The regular expression of a layout pattern (module docstring); a bad pattern is an error naming it."""
    for field in ("{camera}", "{frame}"):
        if pattern.count(field) != 1:
            raise VoxposeError(f"--pattern {pattern!r}: needs {field} exactly once (e.g. '{DEFAULT_PATTERN}')")
    parts = re.split(r"(\{camera\}|\{frame\}|\*|\?)", pattern)
    table = {"{camera}": r"(?P<camera>[^/]+?)", "{frame}": r"(?P<frame>\d+)", "*": r"[^/]*?", "?": r"[^/]"}
    return re.compile("".join(table.get(part, re.escape(part)) for part in parts), re.IGNORECASE)


def _layout(directory, rig: Rig, pattern: str | None = None):
    """Validate the layout (module docstring); return the sorted frame numbers and each camera's frame files."""
    directory = Path(directory)
    if not directory.is_dir():
        raise VoxposeError(f"{directory}: silhouette folder not found")
    regex = pattern_regex(pattern or DEFAULT_PATTERN)
    files = {name: {} for name in rig.names}
    others = set()
    for path in sorted(directory.rglob("*")):
        relative = path.relative_to(directory)
        if any(part.startswith(".") for part in relative.parts) or not path.is_file():
            continue
        match = regex.fullmatch(relative.as_posix())
        if match is None:
            if pattern is None and relative.parts[0] in files:
                raise VoxposeError(f"{path}: not a silhouette frame (expected files named <frame number>.png)")
            continue
        camera, number = match["camera"], int(match["frame"])
        if camera not in files:
            others.add(camera)
            continue
        if number in files[camera]:
            raise VoxposeError(f"{path}: frame {number} also stored as {files[camera][number].name}")
        files[camera][number] = path
    missing = [name for name in rig.names if not files[name]]
    if missing:
        raise VoxposeError(
            f"{directory}: no frames for camera(s) {', '.join(missing)} of rig {rig.name} matching "
            f"'{pattern or DEFAULT_PATTERN}' (the rig has {len(rig)} cameras: {', '.join(rig.names)})"
        )
    if others:
        log.info("silhouettes %s: ignoring camera(s) %s, not in rig %s", directory, ", ".join(sorted(others)),
                 rig.name)  # fmt: skip
    reference = rig.names[0]
    numbers = sorted(files[reference])
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
        half = _GREY_HALF.get(pixels.dtype, max(1, int(pixels.max()) // 2 + 1))
        if not _logged_grey:
            _logged_grey.add(path)
            log.info("%s: %d grey levels: silhouette where >= %d", path, len(levels), half)
        return pixels >= half
    if len(levels) == 1:
        return np.full(pixels.shape, levels[0] != 0)
    return pixels == levels[1]


def iter_silhouette_folder(directory, rig: Rig, pattern: str | None = None):
    """Frames (C, H, W) bool of a silhouette folder, one at a time; the layout is checked first."""
    numbers, files = _layout(directory, rig, pattern)
    height, width = rig.image_size

    def frames():
        for number in numbers:
            yield np.stack([read_mask(files[name][number], width, height) for name in rig.names])

    return frames()


def silhouette_frame_numbers(directory, rig: Rig, pattern: str | None = None) -> list:
    """The frame numbers (sorted) of a silhouette folder, after checking its layout."""
    return _layout(directory, rig, pattern)[0]
