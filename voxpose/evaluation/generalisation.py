"""The subject-held-out table and figure: each group (a performer) held out in turn, one row per (group, method).

Each held-out group is an ordinary workflow run (``voxpose.workflow_config.resolve_generalisation``); this module
only collects the runs' summaries, with the rows and columns of the per-experiment table
(``voxpose.evaluation.tables.experiment_table``).
"""

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from voxpose.errors import VoxposeError
from voxpose.evaluation import uncertainty
from voxpose.evaluation.figures import save
from voxpose.evaluation.tables import ALL_ANGLES, EXPERIMENT_METHODS, experiment_table

METHOD_LABELS = {
    "mvrvm": "MPPCA + MVRVM",
    "kmeans": "K-means + MVRVM",
    "nearest_neighbour": "nearest neighbour",
    "kernel_ridge": "kernel ridge",
    "mean_pose": "mean training pose",
}
COLOURS = {"mvrvm": "#1f77b4", "kmeans": "#ff7f0e", "nearest_neighbour": "#2ca02c", "kernel_ridge": "#9467bd",
           "mean_pose": "#7f7f7f"}  # fmt: skip
# Figures are saved at 120 dpi (figures.save): a 12 pt label is 20 px, still 13 px when the report scales the
# figure (at most 10 in, 1200 px) down to 800 px.
FONT_PT = 12


def generalisation_table(groups: list) -> pd.DataFrame:
    """``groups``: (held-out group, MPPCA summary, K-means summary) in order. Columns: held_out, method, frames
    (test frames: the group's), train_frames, full_body, heading, left_shoulder, right_hip (degrees, Eq. 6),
    mpjpe_mm."""
    by_group = {name: (mppca, kmeans) for name, mppca, kmeans in groups}
    if len(by_group) != len(groups):
        raise VoxposeError(f"--runs: a group is named twice ({', '.join(g[0] for g in groups)})")
    df = experiment_table(by_group).rename(columns={"test_set": "held_out"})
    df.insert(3, "train_frames", [by_group[g][0]["train_frames"] for g in df["held_out"]])
    return df


def with_intervals(df: pd.DataFrame, predictions: dict, n_boot: int, seed: int) -> pd.DataFrame:
    """``df`` with each row's full-body 95 % bootstrap interval (test motions, then frames) and its full body over
    the angles that vary in the held-out group; ``predictions``: group -> (MPPCA predictions.h5, K-means's)."""
    low, high, varying, count = [], [], [], []
    for group, method in zip(df["held_out"], df["method"], strict=True):
        mppca, kmeans = predictions[group]
        frames = uncertainty.read_test_frames(kmeans, "mvrvm") if method == "kmeans" else \
            uncertainty.read_test_frames(mppca, method)
        _, lo, hi = uncertainty.estimate(frames, ALL_ANGLES, n_boot, seed)
        keep = uncertainty.varying(frames)
        low.append(lo)
        high.append(hi)
        varying.append(uncertainty.estimate(frames, keep, 1, seed)[0])
        count.append(int(keep.sum()))
    at = list(df.columns).index("full_body") + 1
    out = df.copy()
    for offset, (name, values) in enumerate((("full_body_low", low), ("full_body_high", high),
                                             ("full_body_varying", varying), ("varying_angles", count))):
        out.insert(at + offset, name, values)
    return out


def generalisation_figure(df: pd.DataFrame, path) -> None:
    """Full-body error per held-out group (x) and method (bars), the mean training pose in grey (and as a dashed
    line across its group, to read the other bars against)."""
    groups = list(dict.fromkeys(df["held_out"]))
    error = df.set_index(["held_out", "method"])["full_body"]
    frames = df.groupby("held_out", sort=False)["frames"].first()
    width = 0.8 / len(EXPERIMENT_METHODS)
    fig = Figure(figsize=(min(10.0, max(7.0, 3.0 + 0.9 * len(groups))), 4.8))
    ax = fig.subplots()
    x = np.arange(len(groups))
    for i, method in enumerate(EXPERIMENT_METHODS):
        ax.bar(x + (i - (len(EXPERIMENT_METHODS) - 1) / 2) * width, [error[(g, method)] for g in groups], width,
               label=METHOD_LABELS[method], color=COLOURS[method])  # fmt: skip
    ax.hlines([error[(g, "mean_pose")] for g in groups], x - 0.45, x + 0.45, colors="black",
              linestyles="dashed", linewidth=1.2, label="mean-pose level", zorder=3)  # fmt: skip
    ax.set_xticks(x, [f"{g}\nn={frames[g]}" for g in groups], fontsize=FONT_PT)
    ax.tick_params(axis="y", labelsize=FONT_PT)
    ax.set_xlabel("held-out group (n: its test frames)", fontsize=FONT_PT)
    ax.set_ylabel("full-body error (deg, Eq. 6)", fontsize=FONT_PT)
    below = sum(error[(g, "mvrvm")] < error[(g, "mean_pose")] for g in groups)
    ax.set_title(f"Each group tested by a regressor trained without it\nMPPCA + MVRVM below the mean pose on {below} "
                 f"of {len(groups)} groups", fontsize=FONT_PT)  # fmt: skip
    ax.legend(fontsize=FONT_PT - 1, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.22), frameon=False)
    ax.grid(axis="y", alpha=0.3)
    save(fig, path, "png")
