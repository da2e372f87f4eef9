"""What ``voxpose predict`` writes: the BVH, the CSV of angles and the prediction record, all or nothing.

* ``out.bvh``: the estimated motion on the model's output skeleton (``voxpose.motion.output_skeleton``), one BVH
  frame per input frame, ``Frame Time`` 1 / fps; gap frames as documented in ``voxpose.apply.predict``.
* ``out.csv``: columns ``frame`` (input frame number), ``valid`` (1: estimated, 0: gap) and the 42 angles
  ``motion.canon.ANGLE_NAMES`` in degrees; gap rows hold ``NaN``.
* ``out.h5`` (layout ``prediction``): the angles, valid flags, fitted root positions, frame numbers, true angles
  when known, the output skeleton and the carved voxels: everything ``voxpose render`` draws.

The three files are written to temporary names and renamed into place only once all are complete.
"""

import contextlib

import pandas as pd

from voxpose.apply.predict import Prediction, bvh_channels
from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path
from voxpose.io.bvh import write_bvh
from voxpose.io.hdf5 import read_groups, write_groups
from voxpose.motion import canon
from voxpose.motion.output_skeleton import OutputSkeleton
from voxpose.voxels.sequence import voxel_arrays, voxels_from_arrays

LAYOUT = "prediction"
BVH_PRECISION = 9  # significant digits: angles re-read to 1e-6 degrees


def angle_table(prediction: Prediction) -> pd.DataFrame:
    df = pd.DataFrame(prediction.angles, columns=canon.ANGLE_NAMES)
    df.insert(0, "valid", prediction.valid.astype(int))
    df.insert(0, "frame", prediction.frames)
    return df


def write_outputs(prediction: Prediction, skeleton: OutputSkeleton, bvh_path, csv_path, record_path,
                  meta: dict | None = None) -> None:  # fmt: skip
    """Write the BVH, the CSV and the record (module docstring); on any error none of them."""
    angles, root = bvh_channels(prediction)
    bvh = skeleton.bvh(angles, root, 1.0 / prediction.fps)
    arrays = {"angles": prediction.angles, "valid": prediction.valid, "root": prediction.root,
              "frames": prediction.frames}  # fmt: skip
    if prediction.true_angles is not None:
        arrays["true_angles"] = prediction.true_angles
    groups = {
        "prediction": (arrays, {"fps": prediction.fps, "smooth": prediction.smooth} | (meta or {})),
        "skeleton": ({"offsets": skeleton.offsets, "end_lengths": skeleton.end_lengths}, {}),
        "voxels": voxel_arrays(prediction.voxels),
    }
    with contextlib.ExitStack() as stack:
        tmp_csv, tmp_record = (stack.enter_context(atomic_path(p)) for p in (csv_path, record_path))
        angle_table(prediction).to_csv(tmp_csv, index=False, float_format="%.6f", na_rep="NaN")
        write_groups(tmp_record, LAYOUT, groups, {"bvh": str(bvh_path)})
        write_bvh(bvh, bvh_path, precision=BVH_PRECISION)  # last: the CSV and record are renamed after it


def read_record(path) -> tuple[Prediction, OutputSkeleton, dict]:
    """-> (prediction, output skeleton, meta) of a record written by ``write_outputs``."""
    groups, _ = read_groups(path, LAYOUT)
    try:
        return _from_groups(groups)
    except KeyError as err:
        raise VoxposeError(f"{path}: damaged prediction file (missing {err})") from None


def _from_groups(groups):
    arrays, meta = groups["prediction"]
    prediction = Prediction(
        angles=arrays["angles"],
        valid=arrays["valid"].astype(bool),
        root=arrays["root"],
        voxels=voxels_from_arrays(*groups["voxels"]),
        frames=arrays["frames"],
        fps=float(meta["fps"]),
        true_angles=arrays.get("true_angles"),
        smooth=float(meta["smooth"]),
    )
    skeleton = OutputSkeleton(**groups["skeleton"][0])
    return prediction, skeleton, meta
