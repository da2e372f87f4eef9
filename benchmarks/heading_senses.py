"""Print, per motion, the frames whose body-frame heading faces the wrong way: the hull's cue against the sense
the feature model chose (``features.heading_sense: density``).

    python benchmarks/heading_senses.py RESULTS FEATURE_SET.h5 [FEATURE_SET.h5 ...]

``RESULTS`` is a run's ``results`` folder; each ``FEATURE_SET`` one of its
``features/<train>/<rig>/<desc>/<feat>/sets/<set>.h5`` files. A frame faces the wrong way when its reference
heading lies more than 90 degrees from the true heading (``motions/<motion>.h5``); the cue's heading is the one
stored with the descriptors (``descriptors/<rig>/<desc>/<motion>.h5``), the chosen one the feature set's.

Measured (2026-11-27, c13a236) on the cross-family check of issue 18: ``bvh_dir`` the shared ``bvh`` folder
and two ``bvh_experiments``, ``bandai_to_cmu`` (train on the Bandai Namco walks, turning and irregular walks,
test on the CMU walks and irregular walks) and ``cmu_to_bandai`` (the reverse); the test sets' totals:

    test frames        cue wrong   chosen wrong: MPPCA (K = 200)   K-means (K = 200)
    CMU   2252               512                               0                   0
    Bandai 5738             1460                              10                  72
"""

import sys
from pathlib import Path

import numpy as np

from voxpose.descriptors.file import descriptor_headings
from voxpose.features.heading_sense import true_turns
from voxpose.io.hdf5 import read_per_motion
from voxpose.motion import canon
from voxpose.motion.data import read_motion

HEADING = canon.ANGLE_NAMES.index("root_y")


def main(results: Path, sets: list[Path]) -> None:
    for path in sets:
        rig, desc = path.parts[-5], path.parts[-4]
        motions, _ = read_per_motion(path, "features")
        print(f"\n{path}")
        print(f"{'motion':55s} {'frames':>7s} {'cue wrong':>10s} {'chosen wrong':>13s}")
        totals = np.zeros(3, dtype=int)
        for name, arrays in sorted(motions.items()):
            if "reference_heading" not in arrays:
                print(f"{name}: world-frame descriptors, no heading to choose")
                continue
            truth = read_motion(results / "motions" / f"{name}.h5").angles[:, HEADING]
            cue = descriptor_headings(results / "descriptors" / rig / desc / f"{name}.h5")[0]
            carved = arrays["counts"] > 0
            row = np.array([carved.sum(), true_turns(cue, truth)[carved].sum(),
                            true_turns(arrays["reference_heading"], truth)[carved].sum()])  # fmt: skip
            totals += row
            print(f"{name:55s} {row[0]:7d} {row[1]:10d} {row[2]:13d}")
        print(f"{'all':55s} {totals[0]:7d} {totals[1]:10d} {totals[2]:13d}")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(Path(sys.argv[1]), [Path(p) for p in sys.argv[2:]])
