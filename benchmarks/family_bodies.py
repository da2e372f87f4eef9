"""Print, per skeleton family, the body model drawn on the raw joints and on the anatomical landmarks.

    python benchmarks/family_bodies.py [--bvh DIR] [--library DIR] [--generated N] [--frames N]

Issue 18 item 1: the same person should get the same body on every skeleton family. Per family (CMU, Bandai,
the library's ReActIdle rig with the config's joint map, the generated set), as means over files: the standing
height h, the hip and shoulder half-widths and the pelvis centre -> neck distance (fractions of h) of the raw
joints and of the landmarks (``voxpose.voxels.landmarks``), the landmark scale factors, and the occupied voxels
per frame at h/60 of the body drawn both ways (``--frames`` evenly spaced frames per file).

Measured (2026-11-27, shared ``bvh`` folder and the library's ReActIdle takes, 10 generated files, defaults):

    family     files    h m   hip / h         shoulder / h    pelvis->neck / h   k hip, shoulder, neck   voxels/frame
    bandai        25  1.571   0.041 -> 0.051  0.064 -> 0.130  0.273 -> 0.275    1.239 2.020 1.004       2747 -> 2906
    cmu           17  1.485   0.064 -> 0.051  0.126 -> 0.130  0.228 -> 0.251    0.804 1.032 1.102       2550 -> 2909
    reactidle      4  1.333   0.069 -> 0.051  0.110 -> 0.130  0.337 -> 0.277    0.734 1.181 0.823       3249 -> 2964
    generated     10  1.785   0.051 -> 0.051  0.130 -> 0.130  0.288 -> 0.288    1.000 1.000 1.000       3011 -> 3011

The families' voxel counts per frame spread 2550-3249 (27 %) on the raw joints and 2906-3011 (3.6 %) on the
landmarks. CMU's pelvis -> neck stays short (0.251 h): its pelvis centre -> head top distance is short too.
"""

import argparse
import tempfile
from collections import defaultdict
from pathlib import Path

import numpy as np
from end_angles import SHARED, family_of, generated_files, settings

from voxpose.motion import canon
from voxpose.motion.load import load_motion
from voxpose.voxels import body
from voxpose.voxels.landmarks import anatomical_points, landmark_scales
from voxpose.voxels.occupancy import occupied_voxels

_I = canon.INDEX


def proportions(joints, height) -> dict:
    """Median hip and shoulder half-widths and pelvis centre -> neck distance, fractions of the height."""
    pelvis = 0.5 * (joints[:, _I["lhip"]] + joints[:, _I["rhip"]])

    def median(a, b, factor=1.0):
        return factor * float(np.median(np.linalg.norm(a - b, axis=-1))) / height

    return {
        "hip": median(joints[:, _I["lhip"]], joints[:, _I["rhip"]], 0.5),
        "shoulder": median(joints[:, _I["lshoulder"]], joints[:, _I["rshoulder"]], 0.5),
        "trunk": median(joints[:, _I["neck"]], pelvis),
    }


def voxel_counts(motion, frames: int, raw: bool) -> float:
    """Mean occupied voxels per frame at h/60 over ``frames`` evenly spaced frames."""
    keep = np.unique(np.linspace(0, motion.n_frames - 1, frames).astype(int))
    arrays = {k: getattr(motion, k)[keep] for k in ("positions", "rotations", "ends")} | {"height": motion.height}
    landmarks = body.anatomical_points
    if raw:
        body.anatomical_points = lambda positions, ends, height, label: (positions, ends)
    try:
        frame, _ = occupied_voxels(body.body_ellipsoids(arrays), motion.height / 60.0)
    finally:
        body.anatomical_points = landmarks
    return len(frame) / len(keep)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bvh", type=Path, default=SHARED / "bvh")
    parser.add_argument("--library", type=Path, default=SHARED / "bvh-library")
    parser.add_argument("--generated", type=int, default=10)
    parser.add_argument("--frames", type=int, default=20)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        paths = sorted(args.bvh.glob("*.bvh")) + sorted(args.library.glob("idle_reactidle_*.bvh"))
        paths += generated_files(args.generated, Path(tmp))
        rows = defaultdict(lambda: defaultdict(list))
        for path in paths:
            motion = load_motion(path, **settings(path.stem))
            row = rows[family_of(path.stem)]
            row["height"].append(motion.height)
            joints, _ = anatomical_points(motion.positions, motion.ends, motion.height)
            for label, points in (("raw", motion.positions), ("landmarks", joints)):
                for key, value in proportions(points, motion.height).items():
                    row[label, key].append(value)
            for key, value in landmark_scales(motion.positions, motion.ends, motion.height).items():
                row["k", key].append(value)
            row["voxels raw"].append(voxel_counts(motion, args.frames, raw=True))
            row["voxels landmarks"].append(voxel_counts(motion, args.frames, raw=False))
    print(
        f"{'family':10s} {'files':>5s} {'h m':>6s}   half-widths / h (hip, shoulder), pelvis->neck / h;"
        " raw -> landmarks   k (hip, shoulder, neck)   voxels/frame raw -> landmarks"
    )
    for family, row in rows.items():
        m = {key: float(np.mean(values)) for key, values in row.items()}
        print(
            f"{family:10s} {len(row['height']):5d} {m['height']:6.3f}   "
            f"hip {m['raw', 'hip']:.3f} -> {m['landmarks', 'hip']:.3f}  "
            f"shoulder {m['raw', 'shoulder']:.3f} -> {m['landmarks', 'shoulder']:.3f}  "
            f"trunk {m['raw', 'trunk']:.3f} -> {m['landmarks', 'trunk']:.3f}   "
            f"k {m['k', 'hip']:.3f} {m['k', 'shoulder']:.3f} {m['k', 'neck']:.3f}   "
            f"{m['voxels raw']:.0f} -> {m['voxels landmarks']:.0f}"
        )


if __name__ == "__main__":
    main()
