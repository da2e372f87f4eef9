"""``voxpose fit-features``: MPPCA (or the K-means baseline) fitted on training descriptors (Section 5)."""

from voxpose.cli.common import add_output, parse_params, seed
from voxpose.config_schema import section

NAME = "fit-features"
HELP = "fit MPPCA or K-means on training descriptors"


def add_arguments(p):
    p.add_argument("descriptors", nargs="+", help="descriptor files (HDF5) of the training motions")
    p.add_argument("--method", required=True, choices=["mppca", "kmeans"])
    p.add_argument("--params", required=True, help="JSON: the config's `features` section")
    p.add_argument("--seed", type=seed, default=0)
    add_output(p)


def run(args):
    from voxpose.features.model import FeatureModel
    from voxpose.features.training_set import read_training_set

    params = parse_params(args.params, schema=section("features"))
    training = read_training_set(args.descriptors, params.get("fit_subsample"), args.seed)
    model = FeatureModel.fit_rows(args.method, training.rows, training.n_rows, params, args.seed)
    model = model.with_novelty_range(training.frames)
    model.save(args.output)
