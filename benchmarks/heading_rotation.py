"""Does the estimated pose depend on which way the world's axes point? (issue 18, item 4)

Rotating the whole world about the vertical, the cameras and the subject together, changes nothing a camera
sees; only the voxel grid and the world-aligned descriptors (Section 4) turn with it. A pose estimator that
holds should then change the heading by the rotation and leave the 39 other angles alone. This script turns
the motion and the rig's cameras by the same angles (``voxpose.apply.world_rotation``), carves and predicts
each with a trained model, and prints, per angle, the heading change minus the rotation and the RMS change of the 39
angles below the root against the unrotated prediction; then the same for the world moved by a fraction of a
voxel (``shift_response``: the carving's own noise, which a turn off the grid's axes also meets).

    python benchmarks/heading_rotation.py MODEL.h5 MOTION.bvh [--configfile config/quick.yaml]
        [--degrees 0 45 90 141 180 270] [--frames 60]

The rig is the config's ``rig`` section (the one the model was trained on).

Measured on the embedded default's Table 1 model (exported from its run), the first 40 frames of
results/bvh/generated/spiral_gen_03.bvh, turns 45 / 90 / 141 / 180 / 270 deg:
``descriptor.frame: world``: heading change minus turn 19.9 / 47.0 / 31.1 / 21.6 / 20.6 deg RMS (max 152), the 39
angles 5.6 / 6.3 / 4.9 / 4.2 / 6.1 deg RMS; half-voxel shifts of the world: heading 13.8 / 19.3, 39 angles 2.7 / 2.5;
``body``: heading 1.2 / 0 / 1.1 / 0 / 0 deg RMS (max 2.8), the 39 angles 1.5 / 0 / 1.6 / 0 / 0 deg RMS (the issue's
thresholds: 5 and 2); half-voxel shifts: 39 angles 1.6 / 1.8, heading 1.6 / 27.6 (one frame's sense flipped).
"""

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np
import yaml

from voxpose.apply.model_file import load_model
from voxpose.apply.world_rotation import rotation_response, shift_response
from voxpose.motion.load import load_motion
from voxpose.voxels.cameras import rig_from_config


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("model")
    p.add_argument("bvh")
    p.add_argument("--configfile", default="config/config.yaml")
    p.add_argument("--degrees", type=float, nargs="+", default=[0, 45, 90, 141, 180, 270])
    p.add_argument("--frames", type=int, default=60, help="the first N frames of the motion")
    args = p.parse_args()
    model = load_model(args.model)
    cfg = yaml.safe_load(Path(args.configfile).read_text())
    motion = load_motion(args.bvh)
    n = args.frames
    motion = replace(motion, positions=motion.positions[:n], rotations=motion.rotations[:n],
                     angles=motion.angles[:n], ends=motion.ends[:n])  # fmt: skip
    rig, proportions = rig_from_config(cfg["rig"]), cfg.get("voxels", {}).get("proportions")
    rows = rotation_response(model, motion, rig, args.degrees, proportions)
    print(f"{'turn':>6} {'heading change - turn: mean':>28} {'RMS':>6} {'max':>6} {'39 angles RMS':>14} "
          f"{'root tilt RMS':>14} {'heading error RMS':>18}")  # fmt: skip
    for r in rows:
        print(f"{r['degrees']:6.0f} {r['heading_mean']:28.1f} {r['heading_rms']:6.1f} {r['heading_max']:6.1f} "
              f"{r['body_rms']:14.2f} {r['tilt_rms']:14.2f} {r['heading_error']:18.1f}")  # fmt: skip
    voxel = model.voxels["l_res_fraction"] * motion.height
    for shift in ((0.5, 0.0, 0.3), (0.25, 0.0, -0.4)):
        r = shift_response(model, motion, rig, voxel * np.array(shift), proportions)
        print(f"world moved by {shift} voxels: heading change RMS {r['heading_rms']:.1f} (max {r['heading_max']:.1f}), "
              f"39 angles RMS change {r['body_rms']:.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
