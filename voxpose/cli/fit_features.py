"""``voxpose fit-features``: MPPCA (or the K-means baseline) fitted on training descriptors (Section 5)."""

import logging

from voxpose.cli.common import add_output, parse_params, seed
from voxpose.config_schema import section
from voxpose.features.fit_keys import FIT_KEYS

log = logging.getLogger("voxpose")

NAME = "fit-features"
HELP = "fit MPPCA or K-means on training descriptors"


def add_arguments(p):
    p.add_argument("descriptors", nargs="+", help="descriptor files (HDF5) of the training motions")
    p.add_argument("--method", required=True, choices=list(FIT_KEYS))
    p.add_argument("--params", required=True, help="JSON: the config's `features` section (its method's keys suffice)")
    p.add_argument("--seed", type=seed, default=0)
    p.add_argument("--motions", nargs="+", default=None,
                   help="motion files (HDF5) of the training motions, in the descriptors' order: with body-frame "
                        "descriptors and heading_sense: density, frames facing away from their true heading are "
                        "turned about before the fit")  # fmt: skip
    add_output(p)


def run(args):
    from voxpose.errors import VoxposeError
    from voxpose.features.model import FeatureModel
    from voxpose.features.training_set import read_training_set, training_turns

    params = parse_params(args.params, schema=section("features", required=FIT_KEYS[args.method]))
    turns, n_a = None, 0
    if params.get("heading_sense", "shape") == "density":
        if args.motions is None:
            raise VoxposeError("fit-features: heading_sense: density needs the training motions' files (--motions)")
        turns, n_a = training_turns(args.descriptors, args.motions)
    training = read_training_set(args.descriptors, params.get("fit_subsample"), args.seed, turns=turns, n_a=n_a)
    model = FeatureModel.fit_rows(args.method, training.rows, training.n_rows, params, args.seed)
    model = model.with_novelty_range(training.frames)
    if turns is not None:
        turned = int(sum(t.sum() for t in turns))
        model.meta = model.meta | {"turned_training_frames": turned}
        log.info("heading sense: %d of %d training frames turned about to their true heading before the fit",
                 turned, training.n_frames)  # fmt: skip
    model.save(args.output)
