"""``voxpose regress``: pose PCA (Eq. 1) and MVRVM (Section 3) on one experiment; predictions and Eq. 6 errors."""

import json

from voxpose.cli.common import parse_params

NAME = "regress"
HELP = "pose PCA + MVRVM on an experiment: predictions and errors"


def add_arguments(p):
    p.add_argument("features", help="per-frame features (HDF5) from `voxpose features`")
    p.add_argument("motions", nargs="+", help="motion files (HDF5) of the experiment's motions")
    p.add_argument("--train", required=True, help="comma-separated training motion names")
    p.add_argument("--test", required=True, help="comma-separated test motion names")
    p.add_argument("--params", required=True, help="JSON: the config's `regression` section")
    p.add_argument("--seed", type=int, default=0)
    for name in ("model", "predictions", "angles", "summary"):
        p.add_argument(f"--{name}", required=True, help=f"output: {name}")


def run(args):
    import pandas as pd

    from voxpose.evaluation.run import run
    from voxpose.io.atomic import atomic_path
    from voxpose.io.hdf5 import read_per_motion, write_arrays, write_per_motion
    from voxpose.motion import canon
    from voxpose.motion.data import read_motion
    from voxpose.regression.stored import regressor_arrays

    features, _ = read_per_motion(args.features, "features")
    motions = {m.name: m for m in map(read_motion, args.motions)}
    result = run(features, motions, args.train.split(","), args.test.split(","), parse_params(args.params), args.seed)
    write_arrays(args.model, "regressor", *regressor_arrays(result.pca, result.mvrvm))
    write_per_motion(args.predictions, "predictions", result.predictions, {"summary": result.summary})
    frames = []
    for name, p in result.predictions.items():
        df = pd.DataFrame(p["pred_mvrvm"], columns=canon.ANGLE_NAMES)
        df.insert(0, "frame", range(len(df)))
        df.insert(0, "motion", name)
        frames.append(df)
    with atomic_path(args.angles) as tmp:
        pd.concat(frames).to_csv(tmp, index=False, float_format="%.4f")
    with atomic_path(args.summary) as tmp:
        tmp.write_text(json.dumps(result.summary, indent=1))
