"""``voxpose evaluate``: a fitted regressor on one test set: per-frame predictions and the Eq. 6 errors.

With the fit's baselines, every method of the fit is scored (MVRVM, mean pose, nearest neighbour, kernel ridge);
with a regressor file alone (features from another rig or degraded silhouettes, no retraining), the MVRVM
and the training mean pose.
"""

import json
import logging

from voxpose.cli.common import add_output, parse_params
from voxpose.config_schema import section

log = logging.getLogger("voxpose")

NAME = "evaluate"
HELP = "score a fitted regressor on test features: predictions and errors"


def add_arguments(p):
    p.add_argument("features", help="per-frame features (HDF5) of the test motions")
    p.add_argument("motions", nargs="+", help="motion files (HDF5) of the test motions")
    p.add_argument("--regressor", required=True, help="regressor (HDF5) from `voxpose regress`")
    p.add_argument("--baselines", help="baselines (HDF5) from `voxpose regress`")
    p.add_argument("--fit", help="the fit's summary (JSON) from `voxpose regress`, copied into the summary")
    p.add_argument("--test", required=True, help="comma-separated test motion names")
    p.add_argument("--params", required=True, help="JSON: the config's `regression` section")
    p.add_argument("--predictions", help="output: per-frame predictions and errors (HDF5)")
    p.add_argument("--angles", help="output: the MVRVM's predicted angles per frame (CSV)")
    add_output(p)


def run(args):
    from voxpose.evaluation.angles_csv import write_angles
    from voxpose.evaluation.run import Fit
    from voxpose.io.atomic import atomic_path
    from voxpose.io.hdf5 import read_per_motion, write_per_motion
    from voxpose.motion.data import read_motion

    heading = parse_params(args.params, schema=section("regression")).get("heading", "vector")
    fitted = Fit.load(args.regressor, args.baselines, args.fit, heading=heading)
    features, meta = read_per_motion(args.features, "features")
    motions = {m.name: m for m in map(read_motion, args.motions)}
    predictions, summary = fitted.test(features, motions, args.test.split(","))
    summary |= {"regressor": args.regressor, "features": meta}
    if args.predictions:
        write_per_motion(args.predictions, "predictions", predictions, {"summary": summary})
    if args.angles:
        write_angles(predictions, args.angles)
    with atomic_path(args.output) as tmp:
        tmp.write_text(json.dumps(summary, indent=1))
