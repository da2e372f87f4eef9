"""The generalisation table and figure from planted run summaries."""

import json

import pandas as pd
import pytest
from PIL import Image

from voxpose.cli.main import main
from voxpose.errors import VoxposeError
from voxpose.evaluation.generalisation import generalisation_table

ANGLES = ("full_body", "heading", "left_shoulder", "right_hip", "position_mm")


def summary(test_frames, train_frames, **methods) -> dict:
    """A run summary with the given errors per method: (full_body, heading, left_shoulder, right_hip, mm)."""
    return {"test_frames": test_frames, "train_frames": train_frames,
            "methods": {m: dict(zip(ANGLES, values, strict=True)) for m, values in methods.items()}}  # fmt: skip


def planted():
    a = summary(120, 300, mvrvm=(5, 10, 6, 4, 50), nearest_neighbour=(7, 12, 8, 5, 70),
                kernel_ridge=(6, 11, 7, 4.5, 60), mean_pose=(9, 90, 12, 6, 120))  # fmt: skip
    a_km = summary(120, 300, mvrvm=(5.5, 20, 6.5, 4.2, 55))
    b = summary(80, 340, mvrvm=(11, 40, 13, 8, 130), nearest_neighbour=(12, 45, 14, 9, 140),
                kernel_ridge=(10.5, 35, 12, 7, 125), mean_pose=(10, 80, 13, 7, 128))  # fmt: skip
    b_km = summary(80, 340, mvrvm=(12.5, 50, 14, 9, 150))
    return [("s1", a, a_km), ("bandai2", b, b_km)]


EXPECTED = [
    ("s1", "mvrvm", 120, 300, 5, 10, 6, 4, 50),
    ("s1", "kmeans", 120, 300, 5.5, 20, 6.5, 4.2, 55),
    ("s1", "nearest_neighbour", 120, 300, 7, 12, 8, 5, 70),
    ("s1", "kernel_ridge", 120, 300, 6, 11, 7, 4.5, 60),
    ("s1", "mean_pose", 120, 300, 9, 90, 12, 6, 120),
    ("bandai2", "mvrvm", 80, 340, 11, 40, 13, 8, 130),
    ("bandai2", "kmeans", 80, 340, 12.5, 50, 14, 9, 150),
    ("bandai2", "nearest_neighbour", 80, 340, 12, 45, 14, 9, 140),
    ("bandai2", "kernel_ridge", 80, 340, 10.5, 35, 12, 7, 125),
    ("bandai2", "mean_pose", 80, 340, 10, 80, 13, 7, 128),
]
COLUMNS = ["held_out", "method", "frames", "train_frames", "full_body", "heading", "left_shoulder", "right_hip",
           "mpjpe_mm"]  # fmt: skip


def test_planted_summaries_give_exactly_one_row_per_group_and_method():
    df = generalisation_table(planted())
    assert list(df.columns) == COLUMNS
    assert [tuple(r) for r in df.itertuples(index=False)] == EXPECTED


def test_a_group_named_twice_is_refused():
    a = planted()[0]
    with pytest.raises(VoxposeError, match=r"^--runs: a group is named twice \(s1, s1\)$"):
        generalisation_table([a, a])


def test_the_command_writes_the_table_markdown_and_a_readable_figure(tmp_path):
    runs = []
    for name, mppca, kmeans in planted():
        for tag, s in (("mppca", mppca), ("kmeans", kmeans)):
            (tmp_path / f"{name}_{tag}.json").write_text(json.dumps(s))
        runs.append([name, str(tmp_path / f"{name}_mppca.json"), str(tmp_path / f"{name}_kmeans.json")])
    args = ["generalisation-table", "--runs", json.dumps(runs)]
    out = {k: tmp_path / f"generalisation.{k}" for k in ("csv", "md", "png")}
    assert main([*args, "--csv", str(out["csv"]), "--md", str(out["md"]), "--png", str(out["png"])]) == 0
    expected = pd.DataFrame(EXPECTED, columns=COLUMNS)
    pd.testing.assert_frame_equal(pd.read_csv(out["csv"]), expected, check_dtype=False)
    md = out["md"].read_text()
    assert "| bandai2 | kernel_ridge | 80 | 340 | 10.5 | 35 | 12.0 | 7.0 | 125 |" in md
    width, height = Image.open(out["png"]).size
    assert 600 <= width <= 1300 and 300 <= height < width  # two groups: a small figure, not a page-wide one
