"""The two figures of the measured claims (issue 8): error against camera rig, error against degradation.

Runs arrive as JSON lists of objects naming a run summary (``summary.json`` of ``voxpose evaluate``):

- camera rigs: ``{"rig", "cameras", "series", "summary"}``; ``summary`` null where the series has no features
  on that rig (the A&T multi-view regressor on a rig with another number of cameras);
- robustness: ``{"kind", "level", "carving", "summary"}``, level 0 being the clean silhouettes.
"""

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from voxpose.evaluation.tables import read_summary

LEVEL_TITLES = {
    "flip": "boundary pixels flipped (probability)",
    "morph": "erosion (-) / dilation (+), pixels",
    "limb": "limb segments missing in one view",
    "calibration": "rotation error of one camera (degrees)",
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
    fig = Figure(figsize=(1.6 * len(rigs) + 2, 3.8))
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
                ax.text(p, 0.02 * top, "n/a", ha="center", va="bottom", fontsize=7, rotation=90)
    labels = [f"{r}\n({int(table[table['rig'] == r]['cameras'].iloc[0])} cams)" for r in rigs]
    ax.set_xticks(x, labels, fontsize=8)
    ax.set_ylabel("full-body RMS error (deg)")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=2, frameon=False)
    fig.tight_layout()
    return fig


def robustness_table(runs) -> pd.DataFrame:
    """One row per (kind, level, carving rule) with the full-body error and its baselines."""
    return pd.DataFrame([{k: r[k] for k in ("kind", "level", "carving")} | _errors(r["summary"]) for r in runs])


def robustness_figure(table: pd.DataFrame):
    """Error against degradation level, one panel per kind, one line per carving rule."""
    kinds = [k for k in LEVEL_TITLES if k in set(table["kind"])]
    fig = Figure(figsize=(3.6 * len(kinds), 3.3))
    axes = fig.subplots(1, len(kinds), squeeze=False, sharey=True)
    for ax, kind in zip(axes[0], kinds, strict=True):
        rows = table[table["kind"] == kind]
        for i, (rule, part) in enumerate(rows.groupby("carving", sort=False)):
            part = part.sort_values("level")
            ax.plot(part["level"], part["error (deg)"], "o-", color=f"C{i}", label=f"carving: {rule}")
        clean = rows[rows["level"] == 0]["mean-pose baseline (deg)"]
        if len(clean):
            ax.axhline(clean.iloc[0], color="0.6", ls="--", lw=0.8, label="mean pose")
        ax.set_xlabel(LEVEL_TITLES[kind])
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("full-body RMS error (deg)")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    return fig
