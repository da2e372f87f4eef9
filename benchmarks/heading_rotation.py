"""Does the estimated pose depend on which way the world's axes point? (issue 18, item 4)

Rotating the whole world about the vertical, the cameras and the subject together, changes nothing a camera
sees; only the voxel grid and the world-aligned descriptors (Section 4) turn with it. A pose estimator that
holds should then change the heading by the rotation and leave the 39 other angles alone. This script turns
the motion (``motion.derive.turned``) and the rig's cameras by the same angles, carves and predicts each with
a trained model, and prints, per angle, the heading change minus the rotation and the RMS change of the 39
angles below the root against the unrotated prediction.

    python benchmarks/heading_rotation.py MODEL.h5 MOTION.bvh [--configfile config/quick.yaml]
        [--degrees 0 45 90 141 180 270] [--frames 60]

The rig is the config's ``rig`` section (the one the model was trained on).
"""

import argparse
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import yaml

from voxpose.apply.model_file import load_model
from voxpose.apply.predict import predict_voxels
from voxpose.evaluation.metrics import angle_differences
from voxpose.io.bvh import read_bvh, write_bvh
from voxpose.motion import canon
from voxpose.motion.derive import turned
from voxpose.motion.load import load_motion
from voxpose.motion.rotations import axis_rotation
from voxpose.voxels.cameras import Rig, rig_from_config
from voxpose.voxels.voxelize import voxelize_motion


def rotated_rig(rig: Rig, degrees: float) -> Rig:
    """The rig with every camera turned by ``degrees`` about the vertical through the origin."""
    yaw = axis_rotation("Y", degrees)
    return Rig(rig.name, [replace(cam, R=cam.R @ yaw.T) for cam in rig.cameras])


def predict_turned(model, bvh, rig, degrees, tmp: Path):
    path = tmp / f"turn{degrees:g}.bvh"
    write_bvh(turned(bvh, degrees=degrees), path)
    motion = load_motion(path)
    v = model.voxels
    seq = voxelize_motion(motion, rotated_rig(rig, degrees), l_res_fraction=v["l_res_fraction"],
                          min_views=v["min_views"], n_basis=v["n_basis"], seed=v["seed"])  # fmt: skip
    return predict_voxels(model, seq).angles


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("model")
    p.add_argument("bvh")
    p.add_argument("--configfile", default="config/config.yaml")
    p.add_argument("--degrees", type=float, nargs="+", default=[0, 45, 90, 141, 180, 270])
    p.add_argument("--frames", type=int, default=60, help="the first N frames of the motion")
    args = p.parse_args()
    model = load_model(args.model)
    rig = rig_from_config(yaml.safe_load(Path(args.configfile).read_text())["rig"])
    bvh = read_bvh(args.bvh)
    bvh = replace(bvh, motion=bvh.motion[: args.frames])
    heading = canon.ANGLE_NAMES.index("root_y")
    body = [i for i, name in enumerate(canon.ANGLE_NAMES) if not name.startswith("root_")]
    with tempfile.TemporaryDirectory() as tmp:
        base = predict_turned(model, bvh, rig, 0.0, Path(tmp))
        print(f"{'rotation':>9} {'heading change - rotation (mean, max abs)':>42} {'39 angles RMS change':>21}")
        for degrees in args.degrees:
            angles = predict_turned(model, bvh, rig, degrees, Path(tmp))
            off = np.mod(angles[:, heading] - base[:, heading] - degrees + 180.0, 360.0) - 180.0
            change = angle_differences(base[:, body], angles[:, body])
            print(f"{degrees:9.0f} {off.mean():20.1f} {np.abs(off).max():21.1f} "
                  f"{np.sqrt(np.mean(change**2)):21.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
