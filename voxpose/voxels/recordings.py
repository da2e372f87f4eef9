"""Camera recordings on disk: per camera a folder of images or a video file, read frame by frame (RGB).

Layout under a root folder, for every camera of the rig: a video ``{root}/{camera}.<ext>`` (``.mp4 .avi .mov
.mkv .webm .mpg``; frames numbered 0, 1, ... in decoding order), or images matched by a pattern (default
``{camera}/*{frame}.*``: a folder per camera, the frame number the last digits of each file name, as in
``img_000123.jpg``; syntax of ``voxpose.voxels.silhouettes``). Images are read with Pillow; videos need the
optional extra ``voxpose[video]`` (imageio with its ffmpeg plugin), whose absence is a one-line error saying
so. Every camera must have the same frame numbers; frames come in increasing number.
"""

from pathlib import Path

import numpy as np
from PIL import Image, UnidentifiedImageError

from voxpose.errors import VoxposeError
from voxpose.voxels.silhouettes import pattern_regex

VIDEO_SUFFIXES = (".mp4", ".avi", ".mov", ".mkv", ".webm", ".mpg")
DEFAULT_PATTERN = "{camera}/*{frame}.*"


def read_image(path, size=None) -> np.ndarray:
    """(H, W, 3) float64 RGB of an image file; ``size`` (W, H) checked when given."""
    try:
        with Image.open(path) as image:
            if size is not None and image.size != tuple(size):
                raise VoxposeError(f"{path}: image is {image.size[0]}x{image.size[1]}, the camera's is "
                                   f"{size[0]}x{size[1]}")  # fmt: skip
            return np.asarray(image.convert("RGB"), dtype=float)
    except (OSError, UnidentifiedImageError) as err:
        raise VoxposeError(f"{path}: cannot read image ({err})") from None


def _video(path):
    try:
        import imageio.v3 as iio
    except ImportError:
        raise VoxposeError(f"{path}: reading videos needs the optional extra: pip install 'voxpose[video]'") from None
    try:
        for frame in iio.imiter(path):
            yield np.asarray(frame, dtype=float)[..., :3]
    except (OSError, ValueError, RuntimeError) as err:
        raise VoxposeError(f"{path}: cannot decode video ({err})") from None


def _camera_images(root: Path, camera: str, regex) -> dict:
    files = {}
    for path in sorted(root.rglob("*")):
        relative = path.relative_to(root)
        if any(part.startswith(".") for part in relative.parts) or not path.is_file():
            continue
        match = regex.fullmatch(relative.as_posix())
        if match and match["camera"] == camera:
            number = int(match["frame"])
            if number in files:
                raise VoxposeError(f"{path}: frame {number} also stored as {files[number].name}")
            files[number] = path
    return files


def recording(root, rig, pattern: str | None = None):
    """-> (frame numbers, iterator of (number, (C, H, W, 3) float64 frames)) of a recording (module docstring)."""
    root = Path(root)
    if not root.is_dir():
        raise VoxposeError(f"{root}: recording folder not found")
    regex = pattern_regex(pattern or DEFAULT_PATTERN)
    height, width = rig.image_size
    sources = {}
    for name in rig.names:
        videos = [root / f"{name}{s}" for s in VIDEO_SUFFIXES if (root / f"{name}{s}").is_file()]
        sources[name] = videos[0] if videos else _camera_images(root, name, regex)
        if not videos and not sources[name]:
            raise VoxposeError(f"{root}: no video {name}.mp4 (or {', '.join(VIDEO_SUFFIXES[1:])}) and no images "
                               f"matching '{pattern or DEFAULT_PATTERN}' for camera {name}")  # fmt: skip
    image_numbers = [sorted(s) for s in sources.values() if isinstance(s, dict)]
    if any(n != image_numbers[0] for n in image_numbers):
        raise VoxposeError(f"{root}: the cameras' image folders hold different frame numbers")
    numbers = image_numbers[0] if image_numbers else None

    def frames():
        streams = {name: _video(s) for name, s in sources.items() if not isinstance(s, dict)}
        index = 0
        while True:
            if numbers is not None and index >= len(numbers):
                return
            number = numbers[index] if numbers is not None else index
            images = []
            for name in rig.names:
                source = sources[name]
                if isinstance(source, dict):
                    images.append(read_image(source[number], (width, height)))
                    continue
                image = next(streams[name], None)
                if image is None:
                    if numbers is None and name == rig.names[0]:
                        return
                    raise VoxposeError(f"{source}: ends at frame {index}, before the other cameras")
                if image.shape[:2] != (height, width):
                    raise VoxposeError(f"{source}: frames are {image.shape[1]}x{image.shape[0]}, the camera's "
                                       f"are {width}x{height}")  # fmt: skip
                images.append(image)
            yield number, np.stack(images)
            index += 1

    return numbers, frames()
