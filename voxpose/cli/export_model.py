"""``voxpose export-model``: a trained pipeline bundled into one model file (``voxpose.apply.model_file``)."""

import logging

from voxpose.cli.common import parse_params, seed
from voxpose.config_schema import section
from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

NAME = "export-model"
HELP = "bundle a trained pipeline into one model file (HDF5)"


def add_arguments(p):
    p.add_argument("--feature-model", required=True, help="feature model (HDF5) from `voxpose fit-features`")
    p.add_argument("--regressor", required=True, help="regressor (HDF5) from `voxpose regress`")
    p.add_argument("--summary", required=True, help="summary.json of the same run (kept as provenance)")
    p.add_argument("--motions", nargs="+", required=True, help="motion files (HDF5) of the training motions")
    p.add_argument("--voxels", required=True, help="JSON: the config's `voxels` section")
    p.add_argument("--descriptor", required=True, help="JSON: the config's `descriptor` section")
    p.add_argument("--regression", required=True, help="JSON: the config's `regression` section")
    p.add_argument("--seed", type=seed, required=True, help="master seed (the basis voxels' seed)")
    p.add_argument("--name", default="", help="label kept in the model's provenance (experiment/rig/...)")
    p.add_argument("-o", "--output", required=True, help="model file (HDF5)")


def run(args):
    from voxpose import __version__
    from voxpose.apply.model_file import PoseModel, save_model, voxel_settings
    from voxpose.evaluation.tables import read_summary
    from voxpose.features.model import FeatureModel
    from voxpose.io.hdf5 import read_arrays
    from voxpose.motion.data import read_motion
    from voxpose.motion.output_skeleton import OutputSkeleton
    from voxpose.regression.stored import regressor_from_arrays

    voxels = parse_params(args.voxels, "--voxels", section("voxels", required=False))
    descriptor = parse_params(args.descriptor, "--descriptor", section("descriptor", required=False))
    regression = parse_params(args.regression, "--regression", section("regression"))
    motions = [read_motion(p) for p in args.motions]
    pca, mvrvm = regressor_from_arrays(*read_arrays(args.regressor, "regressor"))
    summary = read_summary(args.summary)
    train = sorted(m.name for m in motions)
    if sorted(summary["train"]) != train:
        raise VoxposeError(f"--motions: {', '.join(train)} are not the training motions of {args.summary}")
    fps = {m.fps for m in motions}
    if len(fps) != 1:
        raise VoxposeError(f"--motions: the training motions have different frame rates {sorted(fps)}")
    model = PoseModel(
        voxels=voxel_settings(voxels, args.seed),
        descriptor=descriptor,
        features=FeatureModel.load(args.feature_model),
        pca=pca,
        mvrvm=mvrvm,
        heading=regression.get("heading", "vector"),
        skeleton=OutputSkeleton.from_motions(motions),
        fps=fps.pop(),
        provenance={"name": args.name, "train": train, "test": summary["test"], "voxpose": __version__,
                    "test_errors": {m: {k: v for k, v in e.items() if not isinstance(v, dict)}
                                    for m, e in summary["methods"].items()}},
    )  # fmt: skip
    save_model(args.output, model)
    log.info("model %s: %s features, M = %d, %d relevance vectors -> %s", args.name, model.features.method,
             pca.n_components_, len(mvrvm.relevance_), args.output)  # fmt: skip
