"""The MVRVM's predicted angles of every test frame as CSV (``voxpose evaluate --angles``).

Written with the standard library's ``csv``, not pandas: every ``voxpose evaluate`` job writes one, and pandas
would add 0.15 s of import to each of them. The format is pandas' ``to_csv(index=False, float_format="%.4f")``:
a header line, values with 4 decimals, an empty field for NaN (gaps), ``\\n`` line ends.
"""

import csv
import math

from voxpose.io.atomic import atomic_path
from voxpose.motion import canon


def write_angles(predictions: dict, path) -> None:
    """Rows ``motion, frame, <42 angles>`` (degrees; empty at gaps) of ``predictions[motion]["pred_mvrvm"]``."""
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerow(["motion", "frame", *canon.ANGLE_NAMES])
        for name, p in predictions.items():
            for frame, row in enumerate(p["pred_mvrvm"]):
                out.writerow([name, frame, *("" if math.isnan(v) else f"{v:.4f}" for v in row.tolist())])
