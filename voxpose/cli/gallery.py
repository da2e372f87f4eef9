"""``voxpose gallery``: a Figure 5-style gallery of voxels with the estimated and true skeletons."""

from voxpose.cli.common import add_output, positive_integer

NAME = "gallery"
HELP = "Figure 5-style gallery: voxels with estimated and true skeletons"


def add_arguments(p):
    p.add_argument("predictions", help="predictions (HDF5) from `voxpose regress`")
    p.add_argument("voxels", nargs="+", help="voxel files (HDF5) of the test motions")
    p.add_argument("--per-kind", type=positive_integer, default=3, help="frames shown per motion type")
    add_output(p)


def run(args):
    from voxpose.evaluation import figures
    from voxpose.evaluation.gallery import gallery
    from voxpose.io.hdf5 import read_per_motion
    from voxpose.voxels.sequence import read_voxels

    predictions, _ = read_per_motion(args.predictions, "predictions")
    voxels = {}
    for path in args.voxels:
        seq, meta, _ = read_voxels(path)
        voxels[meta["motion"]] = (seq, meta)
    figures.save(gallery(predictions, voxels, per_kind=args.per_kind), args.output, "png")
