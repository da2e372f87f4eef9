"""``voxpose silhouettes``: per-camera videos or image folders and the empty scene -> PNG mask folders for
``carve`` and ``predict`` (background subtraction, ``voxpose.voxels.segmentation``)."""

import logging

from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

NAME = "silhouettes"
HELP = "per-camera videos or image folders + empty scene -> silhouette PNG folders (background subtraction)"


def add_arguments(p):
    from voxpose.voxels.segmentation import Segmentation

    d = Segmentation()
    p.add_argument("recording", help="folder with a video <camera>.mp4 or an image folder per camera")
    p.add_argument("--background", required=True, help="the same for the empty scene (median of its first frames)")
    p.add_argument("--rig", required=True, help="rig calibration file: its cameras and image size")
    p.add_argument("--pattern", help="image layout of both folders (default '{camera}/*{frame}.*'; "
                   "voxpose/voxels/recordings.py)")  # fmt: skip
    p.add_argument("--chroma", type=float, default=d.chroma, help=f"colour distortion threshold (default {d.chroma})")
    p.add_argument("--brighter", type=float, default=d.brighter,
                   help=f"foreground if brighter than the background by this fraction (default {d.brighter})")
    p.add_argument("--shadow", type=float, default=d.shadow,
                   help=f"darkest relative brightness taken as shadow (default {d.shadow})")
    p.add_argument("--close", type=int, default=d.close, help=f"closing radius in pixels (default {d.close})")
    p.add_argument("--open", type=int, default=d.open, help=f"opening radius in pixels (default {d.open})")
    p.add_argument("--min-area", type=float, default=d.min_area,
                   help=f"keep components of at least this fraction of the largest's area, 0: all "
                   f"(default {d.min_area})")
    p.add_argument("--preview", help="also write a contact sheet (PNG) of a few frames with their masks")
    p.add_argument("-o", "--output", required=True, help="silhouette folder: <output>/<camera>/<frame:06d>.png")


def run(args):
    from pathlib import Path

    from voxpose.voxels.cameras import load_rig
    from voxpose.voxels.contact_sheet import MAX_ROWS, contact_sheet
    from voxpose.voxels.recordings import recording
    from voxpose.voxels.segmentation import Segmentation, median_background
    from voxpose.voxels.silhouettes import write_silhouette_folder

    seg = Segmentation(chroma=args.chroma, brighter=args.brighter, shadow=args.shadow, close=args.close,
                       open=args.open, min_area=args.min_area)  # fmt: skip
    rig = load_rig(args.rig)
    out = Path(args.output)
    if out.exists() and any(out.iterdir()):
        raise VoxposeError(f"-o {out}: the silhouette folder exists and is not empty")
    _, background_frames = recording(args.background, rig, args.pattern)
    background = median_background(images for _, images in background_frames)
    numbers, frames = recording(args.recording, rig, args.pattern)
    preview_every = max(1, len(numbers) // MAX_ROWS) if numbers else 10
    rows, n = [], 0
    for n, (number, images) in enumerate(frames, start=1):
        masks = [seg.mask(image, back) for image, back in zip(images, background, strict=True)]
        write_silhouette_folder([masks], rig, out, first_frame=number)
        if args.preview and (n - 1) % preview_every == 0 and len(rows) < MAX_ROWS:
            rows.append((number, images, masks))
    if n == 0:
        raise VoxposeError(f"{args.recording}: no frames")
    if args.preview:
        contact_sheet(rows, args.preview)
        log.info("silhouettes: contact sheet of frames %s -> %s", [r[0] for r in rows], args.preview)
    log.info("silhouettes: %d frames x %d cameras -> %s", n, len(rig), out)
