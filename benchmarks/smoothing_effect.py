"""What temporal smoothing (``voxpose predict --smooth``) does to the test error of a workflow run.

For each ``predictions.h5`` given (from ``voxpose evaluate``: per test motion the MVRVM's per-frame estimates,
their validity and the true angles), the estimates are smoothed over time with ``predict.smooth_angles`` for
each Gaussian sigma (frames) and the full-body error (mean over the 42 angles of the RMS over frames, as in
Tables 1-2) is recomputed over the same valid frames. Sigma 0 is the paper's setting and reproduces the run.

    .venv/bin/python benchmarks/smoothing_effect.py results/runs/*/*/*/mppca-*/sets/*/predictions.h5 \
        [--sigmas 0 0.5 1 2 3 5]
"""

import argparse
from pathlib import Path

import numpy as np

from voxpose.apply.predict import smooth_angles
from voxpose.evaluation import metrics
from voxpose.io.hdf5 import read_per_motion


def errors(path, sigmas) -> dict:
    motions, _ = read_per_motion(path, "predictions")
    out = {}
    for sigma in sigmas:
        true, pred = [], []
        for p in motions.values():
            valid = p["valid"].astype(bool)
            true.append(p["true"][valid])
            pred.append(smooth_angles(p["pred_mvrvm"], valid, sigma)[valid])
        out[sigma] = metrics.full_body_error(np.concatenate(true), np.concatenate(pred))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("predictions", nargs="+", help="predictions.h5 files of workflow runs")
    parser.add_argument("--sigmas", type=float, nargs="+", default=[0, 0.5, 1, 2, 3, 5], help="sigmas (frames)")
    args = parser.parse_args()
    print("full-body error (degrees) of the MVRVM estimates after Gaussian smoothing over time, sigma in frames")
    print(f"{'run (folder of predictions.h5)':<60} " + " ".join(f"{s:>7g}" for s in args.sigmas))
    for path in args.predictions:
        row = errors(path, args.sigmas)
        label = str(Path(path).parent).removeprefix("results/runs/")
        print(f"{label[-60:]:<60} " + " ".join(f"{row[s]:7.3f}" for s in args.sigmas))


if __name__ == "__main__":
    main()
