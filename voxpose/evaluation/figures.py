"""Figure 4 (cross-validation sweeps), per-joint error bars and errors over time, drawn with matplotlib.

Every figure is written atomically as PNG (and PDF where the paper has the figure). Figures are
``matplotlib.figure.Figure`` objects, not pyplot's: no global state and no backend to choose, as ``savefig``
picks the writer for the file format.
"""

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from voxpose.evaluation.tables import read_summary
from voxpose.io.atomic import atomic_path
from voxpose.motion import canon

# The paper's choices (Section 6, Figure 4 caption).
PAPER_CHOICE = {"r_max": 1 / 3, "n_r": 4, "ne_na": "5x10", "n_components": 200}
SWEEP_TITLES = {
    "r_max": "support radius R_max (fraction of h_sub)",
    "n_r": "radial divisions N_r",
    "ne_na": "elevation x azimuth divisions",
    "n_components": "MPPCA components K",
}


JOINT_WORDS = {"root": "pelvis (root)", "neck": "neck", "lshoulder": "left shoulder", "lelbow": "left elbow",
               "lwrist": "left wrist", "rshoulder": "right shoulder", "relbow": "right elbow", "rwrist": "right wrist",
               "lhip": "left hip", "lknee": "left knee", "lankle": "left ankle", "rhip": "right hip",
               "rknee": "right knee", "rankle": "right ankle"}  # fmt: skip


# No creation date or software version in the files: the same config gives the same bytes.
_METADATA = {"png": {"Software": None}, "pdf": {"CreationDate": None, "Producer": None, "Creator": None}}


def save(fig, path, fmt: str) -> None:
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=fmt, dpi=120, bbox_inches="tight", metadata=_METADATA.get(fmt))


def figure4_table(runs) -> pd.DataFrame:
    """One row per sweep point: sweep, value, validation error of MVRVM and of the mean pose, model size."""
    rows = []
    for label, value, path in runs:
        s = read_summary(path)
        rows.append(
            {
                "sweep": label,
                "value": value,
                "validation error (deg)": s["methods"]["mvrvm"]["full_body"],
                "mean-pose baseline (deg)": s["methods"]["mean_pose"]["full_body"],
                "relevance vectors": s["n_relevance"],
                "training frames": s["train_frames"],
                "validation frames": s["test_frames"],
            }
        )
    return pd.DataFrame(rows)


# What the paper's text says about each sweep (Section 6), printed in its panel.
PAPER_STATEMENT = {
    "r_max": "paper: best 0.5-0.6 m, about h/3",
    "n_r": "paper: N_r = 4 best once R_max = h/3",
    "ne_na": "paper: 5 x 10 balances accuracy and cost",
    "n_components": "paper: curve flattens around K = 200",
}
FONT = 12  # points: at 120 dpi and the report's width, no text under 10 px


def figure4(table: pd.DataFrame):
    """Error against each swept parameter, one panel per sweep (two by two): ours, the mean training pose, the
    paper's choice (dotted line) and its text's statement, our best setting (star)."""
    sweeps = [s for s in SWEEP_TITLES if s in set(table["sweep"])]
    n_cols = min(2, len(sweeps))
    n_rows = int(np.ceil(len(sweeps) / n_cols))
    fig = Figure(figsize=(5.2 * n_cols, 4.0 * n_rows))
    axes = fig.subplots(n_rows, n_cols, squeeze=False)
    for ax, sweep in zip(axes.flat, sweeps, strict=False):
        rows = table[table["sweep"] == sweep]
        labels = [str(v) for v in rows["value"]]
        x = np.arange(len(rows)) if sweep == "ne_na" else rows["value"].astype(float).to_numpy()
        error = rows["validation error (deg)"].to_numpy()
        ax.plot(x, error, "o-", color="C0", label="voxpose: MPPCA + MVRVM")
        ax.plot(x, rows["mean-pose baseline (deg)"], "--", color="0.5", label="voxpose: mean training pose")
        best = int(np.argmin(error))
        ax.plot(x[best], error[best], "*", color="C1", ms=15, label="voxpose: best setting", zorder=5)
        choice = PAPER_CHOICE[sweep]
        if sweep == "ne_na":
            ax.set_xticks(x, labels)
            choice = labels.index(choice) if choice in labels else None
        if choice is not None:
            ax.axvline(choice, color="C3", lw=1.5, ls=":", label="paper's choice")
        ax.text(0.02, 0.97, PAPER_STATEMENT[sweep], transform=ax.transAxes, va="top", fontsize=FONT - 1, color="C3",
                bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.85})
        label_panel(ax, SWEEP_TITLES[sweep][0].upper() + SWEEP_TITLES[sweep][1:], SWEEP_TITLES[sweep],
                    "validation error (deg, Eq. 6)")
        ax.margins(y=0.25)
    finish_panels(fig, axes, len(sweeps), "Figure 4: validation error against the descriptor and feature parameters",
                  ncol=4)
    return fig


def label_panel(ax, title: str, xlabel: str, ylabel: str) -> None:
    """A panel's title, axis labels, tick labels and grid in the report's font sizes (readable at its width)."""
    ax.set_title(title, fontsize=FONT + 1)
    ax.set_xlabel(xlabel, fontsize=FONT)
    ax.set_ylabel(ylabel, fontsize=FONT)
    ax.tick_params(labelsize=FONT - 1)
    ax.grid(alpha=0.3)


def finish_panels(fig, axes, used: int, title: str, ncol: int) -> None:
    """Hide the grid's unused panels, put the first panel's legend under the grid and the title above it."""
    for ax in axes.flat[used:]:
        ax.set_axis_off()
    handles, names = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, names, loc="lower center", ncol=ncol, fontsize=FONT - 1, frameon=False)
    fig.suptitle(title, fontsize=FONT + 2)
    fig.tight_layout(rect=(0, 0.06, 1, 1))


def joint_errors(summaries: dict):
    """Bar chart of the error per joint (mean of its 3 angles) for each experiment."""
    fig = Figure(figsize=(10, 4.2))
    ax = fig.subplots()
    width = 0.8 / max(1, len(summaries))
    x = np.arange(canon.N_JOINTS)
    for i, (name, summary) in enumerate(summaries.items()):
        per_joint = summary["methods"]["mvrvm"]["per_joint"]
        ax.bar(x + i * width, [per_joint[j] for j in canon.JOINTS], width, label=name)
    ax.set_xticks(x + width * (len(summaries) - 1) / 2, [JOINT_WORDS[j] for j in canon.JOINTS], rotation=40,
                  ha="right", fontsize=FONT - 1)  # fmt: skip
    ax.set_ylabel("RMS error (deg, mean of 3 angles)", fontsize=FONT)
    ax.set_title("Error per joint of MPPCA + MVRVM", fontsize=FONT + 1)
    ax.tick_params(axis="y", labelsize=FONT - 1)
    ax.legend(fontsize=FONT - 1)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig


def error_over_time(series: dict):
    """Per-frame Eq. 6 error along each test motion; ``series``: panel title -> {motion: (F,) errors}."""
    fig = Figure(figsize=(10, 2.8 * len(series)))
    axes = fig.subplots(len(series), 1, squeeze=False)
    for ax, (title, motions) in zip(axes[:, 0], series.items(), strict=True):
        for name, err in motions.items():
            ax.plot(np.arange(len(err)), err, lw=0.9, label=name)
        ax.set_title(f"Per-frame error (Eq. 6) of MPPCA + MVRVM along each test motion: {title}", fontsize=FONT)
        ax.set_xlabel("frame", fontsize=FONT)
        ax.set_ylabel("error (deg)", fontsize=FONT)
        ax.tick_params(labelsize=FONT - 1)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=FONT - 2, ncol=5)
    fig.tight_layout()
    return fig


def summaries_from(pairs) -> dict:
    """``[(name, path), ...]`` -> {name: summary}."""
    return {name: read_summary(path) for name, path in pairs}
