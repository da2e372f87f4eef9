"""Table 1 and Table 2 of Section 6, from run summaries, with the paper's numbers beside ours.

Errors are in degrees: the mean over the 42 angles (or over a joint's 3 angles) of the RMS over the test
frames of the wrapped absolute difference (Eq. 6 and its footnote; see ``voxpose.evaluation.metrics``).
"""

import json

import pandas as pd

from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path

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
        with open(path) as f:
            return json.load(f)
    except (OSError, json.JSONDecodeError) as err:
        raise VoxposeError(f"{path}: cannot read run summary ({err})") from None


def table1(ours: dict, kmeans: dict, agarwal_triggs: dict | None = None) -> pd.DataFrame:
    """Rows: our approach (MPPCA + MVRVM), K-means + MVRVM, Agarwal & Triggs; measured and paper values.

    ``agarwal_triggs``: optional {row label: summary} of measured Agarwal & Triggs-style runs
    (``voxpose.features.silhouette``), placed after the row the paper quotes.
    """
    rows = []

    def measured(label, summary):
        m = summary["methods"]["mvrvm"]
        row = {"method": label, "source": "voxpose (measured)"}
        row |= {col: m[key] for key, col in TABLE1_COLUMNS.items()}
        row["mean-pose baseline (full body)"] = summary["methods"]["mean_pose"]["full_body"]
        row["joint position error (mm)"] = m["position_mm"]
        row["test frames"] = summary["test_frames"]
        return row

    def paper(label, key, source):
        row = {"method": label, "source": source}
        return row | {col: PAPER_TABLE1[key][k] for k, col in TABLE1_COLUMNS.items()} | {"test frames": 418}

    rows.append(measured("Our approach (MPPCA + MVRVM)", ours))
    rows.append(paper("Our approach (MPPCA + MVRVM)", "ours", "paper"))
    rows.append(measured("Our approach (K-means + MVRVM)", kmeans))
    rows.append(paper("Our approach (K-means + MVRVM)", "kmeans", "paper"))
    rows.append(paper("Agarwal & Triggs [1]", "agarwal_triggs", "quoted by the paper"))
    for label, summary in (agarwal_triggs or {}).items():
        rows.append(measured(label, summary))
    return pd.DataFrame(rows)


def table2(summary: dict) -> pd.DataFrame:
    """Error per motion type of one regressor trained on all types, with model size, beside the paper's."""
    per_kind = summary["methods"]["mvrvm"]["per_kind"]
    measured = {"source": "voxpose (measured)"}
    paper = {"source": "paper"}
    for kind, col in TABLE2_COLUMNS.items():
        measured[col] = per_kind[kind]["full_body"] if kind in per_kind else float("nan")
        paper[col] = PAPER_TABLE2[kind]
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
