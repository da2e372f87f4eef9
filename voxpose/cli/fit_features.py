"""``voxpose fit-features``: MPPCA (or the K-means baseline) fitted on training descriptors (Section 5)."""

from voxpose.cli.common import add_output, parse_params

NAME = "fit-features"
HELP = "fit MPPCA or K-means on training descriptors"


def add_arguments(p):
    p.add_argument("descriptors", nargs="+", help="descriptor files (HDF5) of the training motions")
    p.add_argument("--method", required=True, choices=["mppca", "kmeans"])
    p.add_argument("--params", required=True, help="JSON: the config's `features` section")
    p.add_argument("--seed", type=int, default=0)
    add_output(p)


def run(args):
    import numpy as np

    from voxpose.descriptors.file import read_descriptors
    from voxpose.features.model import FeatureModel

    frames = [d for path in args.descriptors for d in read_descriptors(path)[0]]
    rows = np.concatenate([d for d in frames if len(d)])
    model = FeatureModel.fit(args.method, rows, parse_params(args.params), args.seed).with_novelty_range(frames)
    model.save(args.output)
