"""Per-frame cost of the claims stages (issue 8) at the default sizes, to extrapolate their share of the default DAG.

Prints milliseconds per frame of: carving a degraded sequence (each kind) from the default 6-camera rig, carving
from the 12-camera rig, and the 2D shape contexts of all 6 views at 200 contour points. Run:
``python benchmarks/bench_claims.py [frames]``.
"""

import sys
import tempfile
import time
from pathlib import Path

from voxpose.features.silhouette import render_contexts
from voxpose.io.bvh import write_bvh
from voxpose.motion.generate import generate_motion
from voxpose.motion.load import load_motion
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.degrade import Degradation, voxelize_degraded

CONTOUR = {"n_points": 200, "n_r": 5, "n_theta": 12, "r_inner": 0.125, "r_outer": 2.0}


def main(n_frames: int = 20) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        write_bvh(generate_motion("walk", seed=0, n_frames=n_frames), Path(tmp) / "walk_bench.bvh")
        motion = load_motion(Path(tmp) / "walk_bench.bvh")
    for rig in (circular_rig(), circular_rig(n=12)):
        for kind, level in (("none", 0), ("flip", 0.5), ("morph", -2), ("limb", 3), ("calibration", 1.0)):
            if len(rig) == 12 and kind != "none":
                continue
            start = time.perf_counter()
            voxelize_degraded(motion, rig, Degradation(kind, level, 0), n_basis=200, progress_every=0)
            ms = 1000 * (time.perf_counter() - start) / n_frames
            print(f"carve {len(rig):2d} cameras, {kind:11s}: {ms:6.1f} ms/frame")
    start = time.perf_counter()
    render_contexts(motion, circular_rig(), CONTOUR)
    print(f"2D shape contexts, 6 views x 200 points: {1000 * (time.perf_counter() - start) / n_frames:6.1f} ms/frame")


if __name__ == "__main__":
    main(*map(int, sys.argv[1:]))
