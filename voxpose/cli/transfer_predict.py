"""``voxpose transfer-predict``: a trained regressor applied, without retraining, to features of another rig."""

import json
import logging

from voxpose.cli.common import add_output, parse_params

log = logging.getLogger("voxpose")

NAME = "transfer-predict"
HELP = "apply a trained regressor to other features: errors without retraining"


def add_arguments(p):
    p.add_argument("features", help="per-frame features (HDF5) of the test motions")
    p.add_argument("motions", nargs="+", help="motion files (HDF5) of the test motions")
    p.add_argument("--regressor", required=True, help="regressor (HDF5) from `voxpose regress`")
    p.add_argument("--test", required=True, help="comma-separated test motion names")
    p.add_argument("--params", required=True, help="JSON: the config's `regression` section")
    add_output(p)


def run(args):
    from voxpose.evaluation.run import evaluate, stored_predictors
    from voxpose.io.atomic import atomic_path
    from voxpose.io.hdf5 import read_arrays, read_per_motion
    from voxpose.motion.data import read_motion

    features, meta = read_per_motion(args.features, "features")
    motions = {m.name: m for m in map(read_motion, args.motions)}
    arrays, reg_meta = read_arrays(args.regressor, "regressor")
    predict = stored_predictors(arrays, reg_meta, parse_params(args.params).get("heading", "vector"))
    _, summary = evaluate(predict, features, motions, args.test.split(","))
    summary |= {"test": args.test.split(","), "regressor": args.regressor, "features": meta}
    m = summary["methods"]["mvrvm"]
    log.info("predict: %d test frames (%d gaps): full body %.2f deg, heading %.2f", summary["test_frames"],
             summary["test_gaps"], m["full_body"], m["heading"])  # fmt: skip
    with atomic_path(args.output) as tmp:
        tmp.write_text(json.dumps(summary, indent=1))
