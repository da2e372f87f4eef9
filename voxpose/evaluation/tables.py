"""Table 1 and Table 2 of Section 6, from run summaries, with the paper's numbers beside ours.

Errors are in degrees: the mean over the 42 angles (or over a joint's 3 angles) of the RMS over the test
frames of the wrapped absolute difference (Eq. 6 and its footnote; see ``voxpose.evaluation.metrics``). Every
measured error carries its 95 % bootstrap interval (``<column> low`` / ``<column> high``), and the full body is
also given over the angles that vary in the test data (``voxpose.evaluation.uncertainty``): an angle that never
moves is predicted exactly and lowers the mean over 42.
"""

import json

import numpy as np
import pandas as pd

from voxpose.errors import VoxposeError
from voxpose.evaluation import uncertainty
from voxpose.io.atomic import atomic_path
from voxpose.motion import canon

# Table 1 of the paper: RMS error over 418 frames of spiral walking.
PAPER_TABLE1 = {
    "ours": {"full_body": 5.2, "heading": 8.8, "left_shoulder": 6.3, "right_hip": 3.2},
    "kmeans": {"full_body": 5.4, "heading": 12.0, "left_shoulder": 6.5, "right_hip": 3.8},
    "agarwal_triggs": {"full_body": 6.0, "heading": 17.0, "left_shoulder": 7.5, "right_hip": 4.2},
}
# Table 2 of the paper: one regressor for five motion types; 418 relevance vectors of 1744, 8-d pose space.
PAPER_TABLE2 = {"walk": 2.5, "drunk": 5.0, "spiral": 5.3, "jog": 5.6, "jump": 4.9}
PAPER_TABLE2_MODEL = {"relevance_vectors": 418, "training_frames": 1744, "pose_dims": 8, "test_frames": 1411}
TABLE2_COLUMNS = {
    "walk": "regular walking",
    "drunk": "drunken walking",
    "spiral": "spiral walking",
    "jog": "jogging",
    "jump": "jump",
}
OURS_LABEL = "Our approach (MPPCA + MVRVM)"
KMEANS_LABEL = "Our approach (K-means + MVRVM)"
MEAN_POSE_LABEL = "Mean training pose (baseline)"
ALL_ANGLES = np.arange(canon.N_ANGLES)
AT_ONE_LABEL = "Agarwal & Triggs-style, 1 camera (2D shape contexts + K-means + MVRVM)"
AT_ALL_LABEL = "Agarwal & Triggs-style, all cameras concatenated (2D shape contexts + K-means + MVRVM)"
TABLE1_COLUMNS = {
    "full_body": "full body",
    "heading": "body heading angle",
    "left_shoulder": "left shoulder",
    "right_hip": "right hip",
}


def read_summary(path) -> dict:
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError) as err:  # ValueError: JSONDecodeError, UnicodeDecodeError (not a JSON file)
        raise VoxposeError(f"{path}: cannot read run summary ({err})") from None


FULL_VARYING = "full body, varying angles"
MEAN_POSE = "mean-pose baseline (full body)"
MEAN_POSE_VARYING = "mean-pose baseline (varying angles)"


def interval_columns(frames, n_boot: int, seed: int, prefix: str = "") -> dict:
    """The error columns of one method's test frames, each with its 95 % interval: full body over the 42 angles
    and over the varying ones (with their count), heading, left shoulder, right hip."""
    keep = uncertainty.varying(frames)
    selections = {"full_body": np.arange(canon.N_ANGLES), "varying": keep} | uncertainty.COLUMNS
    names = TABLE1_COLUMNS | {"varying": FULL_VARYING}
    out = {}
    for key, angles in selections.items():
        value, low, high = uncertainty.estimate(frames, angles, n_boot, seed)
        out |= {f"{prefix}{names[key]}": value, f"{prefix}{names[key]} low": low, f"{prefix}{names[key]} high": high}
    out["varying angles"] = int(keep.sum())
    return out


def read_csv(path) -> pd.DataFrame:
    """A table written by ``write_table``; a missing or unreadable file is a one-line error naming it."""
    try:
        return pd.read_csv(path)
    except (OSError, ValueError) as err:
        raise VoxposeError(f"{path}: cannot read table ({err})") from None


def table1(ours: dict, kmeans: dict, agarwal_triggs: dict | None = None, frames: dict | None = None,
           n_boot: int = 1000, seed: int = 0) -> pd.DataFrame:  # fmt: skip
    """Rows: our approach (MPPCA + MVRVM), K-means + MVRVM, Agarwal & Triggs; measured and paper values.

    ``agarwal_triggs``: optional {row label: summary} of measured Agarwal & Triggs-style runs
    (``voxpose.features.silhouette``), placed after the row the paper quotes. ``frames``: {row label:
    (the MVRVM's ``uncertainty.FrameErrors``, the mean pose's)} for the intervals and the varying-angle columns.
    """
    rows = []

    def measured(label, summary, method="mvrvm"):
        m = summary["methods"][method]
        row = {"method": label, "source": "voxpose (measured)"}
        row |= {col: m[key] for key, col in TABLE1_COLUMNS.items()}
        if frames and label in frames:
            errors, mean_pose = frames[label]
            row |= interval_columns(errors, n_boot, seed)
            row[MEAN_POSE_VARYING] = uncertainty.estimate(mean_pose, uncertainty.varying(mean_pose), 1, seed)[0]
        row[MEAN_POSE] = summary["methods"]["mean_pose"]["full_body"]
        row["joint position error (mm)"] = m["position_mm"]
        row["test frames"] = summary["test_frames"]
        return row

    def paper(label, key, source):
        row = {"method": label, "source": source}
        return row | {col: PAPER_TABLE1[key][k] for k, col in TABLE1_COLUMNS.items()} | {"test frames": 418}

    rows.append(measured(OURS_LABEL, ours))
    rows.append(paper(OURS_LABEL, "ours", "paper"))
    rows.append(measured(KMEANS_LABEL, kmeans))
    rows.append(paper(KMEANS_LABEL, "kmeans", "paper"))
    rows.append(paper("Agarwal & Triggs [1]", "agarwal_triggs", "quoted by the paper"))
    for label, summary in (agarwal_triggs or {}).items():
        rows.append(measured(label, summary))
    if frames and MEAN_POSE_LABEL in frames:
        rows.append(measured(MEAN_POSE_LABEL, ours, "mean_pose"))
    return pd.DataFrame(rows)


def table2(summary: dict, frames=None, n_boot: int = 1000, seed: int = 0) -> pd.DataFrame:
    """Error per motion type of one regressor trained on all types, with model size, beside the paper's.

    ``frames``: (the MVRVM's ``uncertainty.FrameErrors``, the mean pose's) for each type's interval and mean
    pose, and the full body over all types (42 and varying angles)."""
    per_kind = summary["methods"]["mvrvm"]["per_kind"]
    measured = {"source": "voxpose (measured)"}
    paper = {"source": "paper"}
    for kind, col in TABLE2_COLUMNS.items():
        measured[col] = per_kind[kind]["full_body"] if kind in per_kind else float("nan")
        paper[col] = PAPER_TABLE2[kind]
        if frames is not None:
            mvrvm, mean_pose = (f.of_kind(kind) for f in frames)
            _, measured[f"{col} low"], measured[f"{col} high"] = uncertainty.estimate(mvrvm, ALL_ANGLES, n_boot, seed)
            measured[f"{col} mean pose"] = uncertainty.estimate(mean_pose, ALL_ANGLES, 1, seed)[0]
            measured[f"{col} frames"] = sum(len(d) for d in mvrvm.diff)
    if frames is not None:
        columns = interval_columns(frames[0], n_boot, seed)
        keep = [f"{c}{end}" for c in ("full body", FULL_VARYING) for end in ("", " low", " high")]
        measured |= {k: columns[k] for k in [*keep, "varying angles"]}
        measured[MEAN_POSE] = summary["methods"]["mean_pose"]["full_body"]
        measured[MEAN_POSE_VARYING] = uncertainty.estimate(frames[1], uncertainty.varying(frames[1]), 1, seed)[0]
    measured |= {
        "relevance vectors": summary["n_relevance"],
        "training frames": summary["train_frames"],
        "pose dims": summary["pose_dims"],
        "test frames": summary["test_frames"],
    }
    paper |= {
        "relevance vectors": PAPER_TABLE2_MODEL["relevance_vectors"],
        "training frames": PAPER_TABLE2_MODEL["training_frames"],
        "pose dims": PAPER_TABLE2_MODEL["pose_dims"],
        "test frames": PAPER_TABLE2_MODEL["test_frames"],
    }
    return pd.DataFrame([measured, paper])


# The per-experiment table: one row per (test set, method). ``mvrvm`` is the paper's pipeline (MPPCA features,
# Eq. 5, and the MVRVM); ``kmeans`` the K-means histogram with the MVRVM; the other three are the baselines of
# the MPPCA run (``voxpose.evaluation.run``): the same features, another regressor.
EXPERIMENT_METHODS = ("mvrvm", "kmeans", "nearest_neighbour", "kernel_ridge", "mean_pose")


def experiment_table(test_sets: dict) -> pd.DataFrame:
    """``test_sets``: set name -> (MPPCA summary, K-means summary). Columns: test_set, method, frames, full_body,
    heading, left_shoulder, right_hip (degrees, Eq. 6), mpjpe_mm (mean joint position error, millimetres)."""
    rows = []
    for name, (mppca, kmeans) in test_sets.items():
        for method in EXPERIMENT_METHODS:
            summary, key = (kmeans, "mvrvm") if method == "kmeans" else (mppca, method)
            e = summary["methods"][key]
            rows.append({"test_set": name, "method": method, "frames": summary["test_frames"],
                         "full_body": e["full_body"], "heading": e["heading"], "left_shoulder": e["left_shoulder"],
                         "right_hip": e["right_hip"], "mpjpe_mm": e["position_mm"]})  # fmt: skip
    return pd.DataFrame(rows)


def write_table(df: pd.DataFrame, csv_path, md_path, title: str) -> None:
    """CSV (full precision) and Markdown (one decimal) side by side, both written atomically."""
    with atomic_path(csv_path) as tmp:
        df.to_csv(tmp, index=False)
    lines = [f"# {title}", "", _markdown(df), ""]
    with atomic_path(md_path) as tmp:
        tmp.write_text("\n".join(lines))


def _markdown(df: pd.DataFrame) -> str:
    def cell(v):
        if isinstance(v, float):
            return "" if v != v else f"{v:.1f}"
        return str(v)

    header = "| " + " | ".join(df.columns) + " |"
    rule = "|" + "|".join("---" for _ in df.columns) + "|"
    body = ["| " + " | ".join(cell(v) for v in row) + " |" for row in df.itertuples(index=False)]
    return "\n".join([header, rule, *body])
