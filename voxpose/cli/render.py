"""``voxpose render``: a prediction drawn through a rig camera or a virtual one: voxels with the estimated (and
true) skeleton, as PNG per frame, GIF or MP4 (``voxpose.apply.animation``)."""

import logging
from pathlib import Path

from voxpose.cli.common import finite_number, positive_integer, positive_number
from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

NAME = "render"
HELP = "a prediction seen by a rig camera or from an azimuth/elevation: PNG per frame, GIF or MP4"


def add_arguments(p):
    p.add_argument("record", help="prediction record (HDF5) from `voxpose predict`")
    p.add_argument("--truth", help="true motion: a motion file (HDF5) from `voxpose motion`, or a BVH file")
    p.add_argument("--rig", help="rig calibration file, with --camera: draw through that camera")
    p.add_argument("--camera", help="name of the rig camera to draw through")
    p.add_argument("--image", help="the camera's images underneath, a path with {frame} (the frame number), e.g. "
                   "'frames/cam0/{frame}.png'; needs --camera")  # fmt: skip
    p.add_argument("--azimuth", type=finite_number, default=30.0,
                   help="virtual view: degrees around the vertical from +Z towards +X (default 30)")
    p.add_argument("--elevation", type=finite_number, default=15.0,
                   help="virtual view: degrees above horizontal (default 15)")
    p.add_argument("--every", type=positive_integer, default=1, help="draw every n-th frame (default 1)")
    p.add_argument("--fps", type=positive_number, help="playback rate (default: the prediction's frame rate)")
    p.add_argument("-o", "--output", required=True,
                   help="animated .gif, .mp4 (needs voxpose[video]) or PNG files: a path with {frame}")


def _check(args):
    out = str(args.output)
    if "{frame}" not in out and Path(out).suffix.lower() not in (".gif", ".mp4"):
        raise VoxposeError(f"-o {out}: render writes .gif, .mp4 or PNG files named by a path holding {{frame}}")
    if "{frame}" in out and Path(out).suffix.lower() != ".png":
        raise VoxposeError(f"-o {out}: per-frame pictures are PNG files (.png)")
    if bool(args.rig) != bool(args.camera):
        raise VoxposeError("--rig and --camera come together (the camera to draw through)")
    if args.image and not args.camera:
        raise VoxposeError("--image needs --rig and --camera (the camera that took the images)")
    if args.image and "{frame}" not in args.image:
        raise VoxposeError(f"--image {args.image}: the path must hold {{frame}} (the frame number)")


def run(args):
    import numpy as np

    from voxpose.apply.animation import draw_frames, orbit_camera, write_pictures
    from voxpose.apply.outputs import read_record

    _check(args)
    prediction, skeleton, _ = read_record(args.record)
    if args.truth:
        prediction.true_angles = _truth_angles(args.truth, len(prediction.valid))
    images = None
    if args.camera:
        from voxpose.voxels.cameras import load_rig

        rig = load_rig(args.rig)
        if args.camera not in rig.names:
            raise VoxposeError(f"--camera {args.camera}: not a camera of {args.rig} ({', '.join(rig.names)})")
        camera = rig[rig.names.index(args.camera)]
        if args.image:
            images = _images(args.image, camera)
    else:
        seq = prediction.voxels
        occupied = seq.ijk[: seq.offsets[-1]]
        if not len(occupied):
            raise VoxposeError(f"{args.record}: every frame is empty; nothing to draw")
        centre = (occupied + 0.5).mean(axis=0) * seq.l_res
        extent = max(float(np.ptp(seq.frame(f)[0], axis=0).max() + 1) for f in np.flatnonzero(~seq.empty)) * seq.l_res
        camera = orbit_camera(centre, extent, args.azimuth, args.elevation)
    frames = draw_frames(prediction, skeleton, camera, every=args.every, images=images)
    n = write_pictures(frames, args.output, (args.fps or prediction.fps) / args.every)
    log.info("render: %d frames -> %s", n, args.output)


def _images(pattern, camera):
    from voxpose.voxels.recordings import read_image

    def image(number):
        path = pattern.replace("{frame}", str(number))
        if not Path(path).is_file():
            padded = pattern.replace("{frame}", f"{number:06d}")
            if not Path(padded).is_file():
                raise VoxposeError(f"--image: no image {path} (nor {padded}) for frame {number}")
            path = padded
        return read_image(path, (camera.width, camera.height)).astype("uint8")

    return image


def _truth_angles(path, n_frames):
    if Path(path).suffix.lower() == ".bvh":
        from voxpose.motion.load import load_motion

        angles = load_motion(path).angles
    else:
        from voxpose.motion.data import read_motion

        angles = read_motion(path).angles
    if len(angles) != n_frames:
        raise VoxposeError(f"--truth {path}: {len(angles)} frames, the prediction has {n_frames}")
    return angles
