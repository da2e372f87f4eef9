"""The two figures of the measured claims (issue 8): error against camera rig, error against degradation.

Runs arrive as JSON lists of objects naming a run summary (``summary.json`` of ``voxpose evaluate``):

- camera rigs: ``{"rig", "cameras", "series", "summary"}``; ``summary`` null where the series has no features
  on that rig (the A&T multi-view regressor on a rig with another number of cameras);
- robustness: ``{"kind", "level", "carving", "summary"}``, level 0 being the clean silhouettes.
"""

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from voxpose.evaluation.figures import FONT, finish_panels, label_panel
from voxpose.evaluation.tables import read_summary

LEVEL_TITLES = {
    "flip": "boundary pixels flipped (probability)",
    "morph": "erosion (-) / dilation (+), pixels",
    "limb": "limb segments missing in one view",
    "calibration": "rotation error of one camera (degrees)",
}


KIND_TITLES = {
    "flip": "Noisy silhouette boundaries",
    "morph": "Silhouettes too thin or too fat",
    "limb": "A limb missing in one view",
    "calibration": "One camera miscalibrated",
}


def _errors(path) -> dict:
    if path is None:
        return {"error (deg)": np.nan, "mean-pose baseline (deg)": np.nan, "test frames": 0, "gaps": np.nan}
    s = read_summary(path)
    return {
        "error (deg)": s["methods"]["mvrvm"]["full_body"],
        "heading error (deg)": s["methods"]["mvrvm"]["heading"],
        "mean-pose baseline (deg)": s["methods"]["mean_pose"]["full_body"],
        "test frames": s["test_frames"],
        "gaps": s["test_gaps"],
    }


def camera_table(runs) -> pd.DataFrame:
    """One row per (rig, series): the full-body error, its baselines and frame counts; NaN where undefined."""
    return pd.DataFrame([{k: r[k] for k in ("rig", "cameras", "series")} | _errors(r["summary"]) for r in runs])


def camera_figure(table: pd.DataFrame):
    """Grouped bars: error per rig for each series; "n/a" where a series cannot run on a rig."""
    rigs = list(dict.fromkeys(table["rig"]))
    series = list(dict.fromkeys(table["series"]))
    fig = Figure(figsize=(max(8.0, 1.7 * len(rigs) + 2), 5.0))
    ax = fig.subplots()
    width = 0.8 / len(series)
    x = np.arange(len(rigs))
    top = np.nanmax(table["error (deg)"].to_numpy(dtype=float)) if table["error (deg)"].notna().any() else 1.0
    for i, name in enumerate(series):
        rows = table[table["series"] == name].set_index("rig").reindex(rigs)
        values = rows["error (deg)"].to_numpy(dtype=float)
        pos = x + (i - (len(series) - 1) / 2) * width
        ax.bar(pos, np.nan_to_num(values), width, label=name, color=f"C{i}")
        for p, v, present in zip(pos, values, rows["cameras"].notna(), strict=True):
            if np.isnan(v) and present:
                ax.text(p, 0.02 * top, "n/a", ha="center", va="bottom", fontsize=FONT - 2, rotation=90)
    labels = [f"{r}\n({int(table[table['rig'] == r]['cameras'].iloc[0])} cameras)" for r in rigs]
    ax.set_xticks(x, labels, fontsize=FONT - 2)
    ax.tick_params(axis="y", labelsize=FONT - 1)
    ax.set_ylabel("full-body RMS error (deg, Eq. 6)", fontsize=FONT)
    baseline = table["mean-pose baseline (deg)"].dropna()
    if len(baseline):
        ax.axhline(baseline.iloc[0], color="0.5", ls="--", lw=1, label="mean training pose")
    ax.set_title("The regressor on other camera rigs: tested without retraining, and retrained", fontsize=FONT + 1)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=FONT - 1, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False)
    fig.tight_layout()
    return fig


def robustness_table(runs) -> pd.DataFrame:
    """One row per (kind, level, carving rule) with the full-body error and its baselines."""
    return pd.DataFrame([{k: r[k] for k in ("kind", "level", "carving")} | _errors(r["summary"]) for r in runs])


def robustness_figure(table: pd.DataFrame):
    """Error against degradation level, one panel per kind, one line per carving rule."""
    kinds = [k for k in LEVEL_TITLES if k in set(table["kind"])]
    n_cols = min(2, len(kinds))
    fig = Figure(figsize=(5.2 * n_cols, 4.0 * int(np.ceil(len(kinds) / n_cols)) + 0.6))
    axes = fig.subplots(int(np.ceil(len(kinds) / n_cols)), n_cols, squeeze=False, sharey=True)
    for ax, kind in zip(axes.flat, kinds, strict=False):
        rows = table[table["kind"] == kind]
        for i, (rule, part) in enumerate(rows.groupby("carving", sort=False)):
            part = part.sort_values("level")
            ax.plot(part["level"], part["error (deg)"], "o-", color=f"C{i}", label=f"carving: {rule}")
        clean = rows[rows["level"] == 0]["mean-pose baseline (deg)"]
        if len(clean):
            ax.axhline(clean.iloc[0], color="0.6", ls="--", lw=0.8, label="mean training pose")
        label_panel(ax, KIND_TITLES[kind], LEVEL_TITLES[kind], "full-body RMS error (deg, Eq. 6)")
    finish_panels(fig, axes, len(kinds), "Error on degraded silhouettes, by degradation and carving rule", ncol=3)
    return fig
