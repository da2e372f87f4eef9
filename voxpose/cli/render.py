"""``voxpose render``: an animated GIF of a prediction: voxels with the estimated (and true) skeleton."""

import logging
from pathlib import Path

from voxpose.cli.common import check_suffix, positive_integer, positive_number
from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

NAME = "render"
HELP = "animated GIF of a prediction: voxels with estimated (and true) skeleton"


def add_arguments(p):
    p.add_argument("record", help="prediction record (HDF5) from `voxpose predict`")
    p.add_argument("--truth", help="true motion: a motion file (HDF5) from `voxpose motion`, or a BVH file")
    p.add_argument("--every", type=positive_integer, default=1, help="draw every n-th frame (default 1)")
    p.add_argument("--fps", type=positive_number, help="playback rate (default: the prediction's frame rate)")
    p.add_argument("-o", "--output", required=True, help="animated GIF")


def run(args):
    from voxpose.apply.animation import render_gif
    from voxpose.apply.outputs import read_record

    check_suffix(args.output, "-o", ".gif")
    prediction, skeleton, _ = read_record(args.record)
    if args.truth:
        prediction.true_angles = _truth_angles(args.truth, len(prediction.valid))
    n = render_gif(prediction, skeleton.offsets, args.output, every=args.every, fps=args.fps)
    log.info("render: %d frames -> %s", n, args.output)


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
