"""``voxpose silhouette-features``: 2D shape contexts -> the Agarwal & Triggs soft histogram per frame."""

from voxpose.cli.common import add_output

NAME = "silhouette-features"
HELP = "shape contexts -> A&T soft histograms per frame"


def add_arguments(p):
    p.add_argument("model", help="codebook (HDF5) from `voxpose fit-silhouette-features`")
    p.add_argument("contexts", nargs="+", help="shape-context files (HDF5), one per motion")
    add_output(p)


def run(args):
    from voxpose.descriptors.file import read_contours
    from voxpose.features.model import FeatureModel
    from voxpose.features.silhouette import silhouette_features
    from voxpose.io.hdf5 import write_per_motion

    model = FeatureModel.load(args.model)
    motions = {}
    for path in args.contexts:
        contexts, offsets, meta = read_contours(path)
        features, counts = silhouette_features(model, contexts, offsets, meta["n_cameras"])
        motions[meta["motion"]] = {"features": features, "counts": counts}
    write_per_motion(args.output, "features", motions, {"method": "agarwal-triggs", "model": model.meta})
