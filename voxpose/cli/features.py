"""``voxpose features``: descriptors -> one feature vector per frame (Eq. 5, or the K-means histogram)."""

import logging

from voxpose.cli.common import add_output

log = logging.getLogger("voxpose")

NAME = "features"
HELP = "descriptors -> one feature vector per frame (Eq. 5 or K-means)"


def add_arguments(p):
    p.add_argument("model", help="feature model (HDF5) from `voxpose fit-features`")
    p.add_argument("descriptors", nargs="+", help="descriptor files (HDF5), one per motion")
    add_output(p)


def run(args):
    from voxpose.descriptors.file import read_descriptor_file
    from voxpose.features.model import FeatureModel
    from voxpose.io.hdf5 import write_per_motion

    model = FeatureModel.load(args.model).compiled()  # thousands of frames: repays numba's start-up
    motions, novelty = {}, {}
    for path in args.descriptors:
        frames, _, meta, h0 = read_descriptor_file(path)
        out = model.frame_features(frames, h0, meta["params"]["n_a"], meta["motion"])
        motions[meta["motion"]] = {"features": out.features, "counts": out.counts}
        if out.h0 is not None:  # body-frame descriptors: the regressor works relative to it (descriptors.body_frame)
            motions[meta["motion"]]["reference_heading"] = out.h0
        novelty[meta["motion"]] = out.novelty
        if out.scores is not None:
            motions[meta["motion"]]["novelty"] = out.scores
        log.info("features %s: %d frames, %d gaps", meta["motion"], len(frames), int((out.counts == 0).sum()))
    meta = {"method": model.method, "model": model.meta}
    if "novelty" in model.meta:
        meta["novelty_by_motion"] = novelty
    write_per_motion(args.output, "features", motions, meta)
