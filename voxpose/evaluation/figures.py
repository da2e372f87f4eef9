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


def figure4(table: pd.DataFrame):
    """Error against each swept parameter, one panel per sweep, the paper's choice marked."""
    sweeps = [s for s in SWEEP_TITLES if s in set(table["sweep"])]
    fig = Figure(figsize=(4 * len(sweeps), 3.4))
    axes = fig.subplots(1, len(sweeps), squeeze=False)
    for ax, sweep in zip(axes[0], sweeps, strict=True):
        rows = table[table["sweep"] == sweep]
        labels = [str(v) for v in rows["value"]]
        x = np.arange(len(rows)) if sweep == "ne_na" else rows["value"].astype(float).to_numpy()
        ax.plot(x, rows["validation error (deg)"], "o-", color="C0", label="MPPCA + MVRVM")
        ax.plot(x, rows["mean-pose baseline (deg)"], "--", color="0.6", label="mean pose")
        choice = PAPER_CHOICE[sweep]
        if sweep == "ne_na":
            ax.set_xticks(x, labels)
            choice = labels.index(choice) if choice in labels else None
        if choice is not None:
            ax.axvline(choice, color="C3", lw=0.8, ls=":", label="paper's choice")
        ax.set_xlabel(SWEEP_TITLES[sweep])
        ax.set_ylabel("validation RMS error (deg)")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    return fig


def joint_errors(summaries: dict):
    """Bar chart of the error per joint (mean of its 3 angles) for each experiment."""
    fig = Figure(figsize=(10, 3.6))
    ax = fig.subplots()
    width = 0.8 / max(1, len(summaries))
    x = np.arange(canon.N_JOINTS)
    for i, (name, summary) in enumerate(summaries.items()):
        per_joint = summary["methods"]["mvrvm"]["per_joint"]
        ax.bar(x + i * width, [per_joint[j] for j in canon.JOINTS], width, label=name)
    ax.set_xticks(x + width * (len(summaries) - 1) / 2, canon.JOINTS, rotation=45, ha="right")
    ax.set_ylabel("RMS error (deg)")
    ax.legend()
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
        ax.set_title(title)
        ax.set_xlabel("frame")
        ax.set_ylabel("error (deg)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=3)
    fig.tight_layout()
    return fig


def summaries_from(pairs) -> dict:
    """``[(name, path), ...]`` -> {name: summary}."""
    return {name: read_summary(path) for name, path in pairs}
