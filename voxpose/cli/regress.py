"""``voxpose regress``: pose PCA (Eq. 1), MVRVM (Section 3) and the baselines fitted on one training set."""

from voxpose.cli.common import parse_params, seed
from voxpose.config_schema import section

NAME = "regress"
HELP = "fit pose PCA + MVRVM (and the baselines) on training features"


def add_arguments(p):
    p.add_argument("features", help="per-frame features (HDF5) of the training motions, from `voxpose features`")
    p.add_argument("motions", nargs="+", help="motion files (HDF5) of the training motions")
    p.add_argument("--train", required=True, help="comma-separated training motion names")
    p.add_argument("--params", required=True, help="JSON: the config's `regression` section")
    p.add_argument("--seed", type=seed, default=0)
    p.add_argument("--regressor", required=True, help="output: pose PCA and MVRVM (HDF5)")
    p.add_argument("--baselines", required=True, help="output: mean pose, nearest neighbour, kernel ridge (HDF5)")
    p.add_argument("--fit", required=True, help="output: what the fit measured (JSON)")


def run(args):
    from voxpose.evaluation.run import fit
    from voxpose.io.hdf5 import read_per_motion
    from voxpose.motion.data import read_motion

    params = parse_params(args.params, schema=section("regression"))
    features, _ = read_per_motion(args.features, "features")
    motions = {m.name: m for m in map(read_motion, args.motions)}
    fitted = fit(features, motions, args.train.split(","), params, args.seed)
    fitted.save(args.regressor, args.baselines, args.fit)
