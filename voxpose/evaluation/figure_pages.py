"""Figure 4 and the measured claims' figures as report pages: the figure, a caption that states what the numbers
say, and the table behind it (issue 20: every table on the page, not only as a CSV download).

The captions are written from the tables, so their numbers are the CSV files' numbers.
"""

import numpy as np
import pandas as pd

from voxpose.evaluation import html
from voxpose.evaluation.figures import PAPER_CHOICE, SWEEP_TITLES
from voxpose.evaluation.generalisation import METHOD_LABELS

_ERROR = "error (deg)"
_BASELINE = "mean-pose baseline (deg)"


def _page(path, title: str, png, caption: str, table: pd.DataFrame) -> None:
    shown = table.astype(object).where(table.notna(), "")
    html.write_page(path, title, html.image(png) + html.caption(caption) + html.table(shown))


def _same(a, b) -> bool:
    return str(a) == str(b) or (not isinstance(a, str) and not isinstance(b, str) and np.isclose(float(a), float(b)))


def figure4_caption(table: pd.DataFrame) -> str:
    """What Figure 4 shows, its frames, and per sweep our best setting against the paper's choice."""
    first = table.iloc[0]
    parts = []
    for sweep in [s for s in SWEEP_TITLES if s in set(table["sweep"])]:
        rows = table[table["sweep"] == sweep]
        best = rows.loc[rows["validation error (deg)"].idxmin()]
        chosen = [r for _, r in rows.iterrows() if _same(r["value"], PAPER_CHOICE[sweep])]
        paper = f", the paper's choice {chosen[0]['validation error (deg)']:.2f}" if chosen else ""
        parts.append(f"{SWEEP_TITLES[sweep]}: best {best['value']} at {best['validation error (deg)']:.2f}{paper}")
    return (
        "Validation error (Eq. 6: per angle the RMS over the validation frames, then the mean over the 42 angles) of "
        "MPPCA features + MVRVM when one parameter of the 3D shape context or of the MPPCA is swept and the others "
        f"stay at the paper's choices (R_max = h/3, N_r = 4, 5 x 10 bins, K = 200); {int(first['training frames'])} "
        f"training and {int(first['validation frames'])} validation frames. The dashed line is the mean training "
        f"pose on the same frames ({first[_BASELINE]:.2f}): a setting above it predicts worse than no regression. "
        + "; ".join(parts) + "."
    )


def figure4_page(table: pd.DataFrame, png, path) -> None:
    _page(path, "Figure 4: validation error against the descriptor and feature parameters", png,
          figure4_caption(table), table)  # fmt: skip


def camera_caption(table: pd.DataFrame) -> str:
    """What the camera-rig figure shows and where the regressor trained on one rig does worst."""
    measured = table[table[_ERROR].notna()]
    trained = measured[measured["series"].str.contains("not retrained")]
    text = (
        "Full-body error (Eq. 6, degrees) on the test motions carved from each camera rig: the regressor trained on "
        "the default rig applied without retraining, a regressor retrained on each rig, and the Agarwal & "
        "Triggs-style regressor on the concatenated views (n/a where a rig has another number of cameras). "
        f"The dashed line is the mean training pose ({measured[_BASELINE].iloc[0]:.2f})."
    )
    if len(trained):
        worst, best = trained.loc[trained[_ERROR].idxmax()], trained.loc[trained[_ERROR].idxmin()]
        text += (f" Without retraining the error ranges from {best[_ERROR]:.2f} ({best['rig']}) to "
                 f"{worst[_ERROR]:.2f} ({worst['rig']}, {int(worst['cameras'])} cameras).")  # fmt: skip
    return text


def camera_page(table: pd.DataFrame, png, path) -> None:
    _page(path, "The regressor on other camera rigs", png, camera_caption(table), table)


def robustness_caption(table: pd.DataFrame) -> str:
    """What the robustness figure shows and, per degradation, the error at its strongest level."""
    parts = []
    for (kind, rule), rows in table.groupby(["kind", "carving"], sort=False):
        clean, worst = rows[rows["level"] == 0], rows.loc[rows["level"].abs().idxmax()]
        if len(clean):
            parts.append(f"{kind} ({rule}): {clean[_ERROR].iloc[0]:.2f} clean, {worst[_ERROR]:.2f} at level "
                         f"{worst['level']:g}")  # fmt: skip
    return (
        "Full-body error (Eq. 6, degrees) of the regressor trained on clean silhouettes, tested on the test motions "
        "carved from degraded silhouettes (boundary pixels flipped, eroded or dilated masks, a limb missing in one "
        "view, one camera's rotation wrong), carved with each rule in the table (a voxel kept when inside at least "
        f"that many views). The dashed line is the mean training pose ({table[_BASELINE].iloc[0]:.2f}). "
        + "; ".join(parts) + "."
    )


def robustness_page(table: pd.DataFrame, png, path) -> None:
    _page(path, "Error on degraded silhouettes", png, robustness_caption(table), table)


def generalisation_caption(table: pd.DataFrame) -> str:
    """What the subject-held-out figure shows and, per group, MPPCA + MVRVM against the mean training pose."""
    error = table.set_index(["held_out", "method"])
    groups = list(dict.fromkeys(table["held_out"]))
    parts = [f"{g} {error.loc[(g, 'mvrvm'), 'full_body']:.1f} against {error.loc[(g, 'mean_pose'), 'full_body']:.1f} "
             f"({error.loc[(g, 'mvrvm'), 'full_body'] / error.loc[(g, 'mean_pose'), 'full_body']:.2f} of it; "
             f"heading {error.loc[(g, 'mvrvm'), 'heading']:.1f})" for g in groups]  # fmt: skip
    return (
        "Subject-held-out evaluation: each group of motions (on real data a performer) is held out in turn, every "
        "method is trained on the rest of the pool and tested on the group. Full-body error (Eq. 6: per angle the "
        "RMS over the group's frames, then the mean over the 42 angles; beside it over the angles that move in "
        "the group's frames, their count in brackets) with its 95 % bootstrap interval (test motions, then "
        "frames), heading error (degrees) and mean joint position error (mm). The mean training pose is what "
        "a regressor must beat: a method generalises to unseen people only where it is clearly below it. "
        "MPPCA + MVRVM per held-out group: " + "; ".join(parts) + "."
    )


def generalisation_page(table: pd.DataFrame, png, path) -> None:
    """The figure, the caption and the table with methods in words and intervals under the values."""
    has_ci = "full_body_low" in table
    shown = pd.DataFrame({
        "held out": table["held_out"],
        "method": [METHOD_LABELS.get(m, m) for m in table["method"]],
        "test frames": table["frames"].astype(int),
        "training frames": table["train_frames"].astype(int),
        "full body, 42 angles": [
            html.with_interval(r["full_body"], r["full_body_low"], r["full_body_high"]) if has_ci
            else html.cell(r["full_body"]) for _, r in table.iterrows()],
        "full body, varying angles": [f"{r['full_body_varying']:.1f} ({int(r['varying_angles'])})"
                                      if "varying_angles" in r else "" for _, r in table.iterrows()],
        "heading": table["heading"],
        "left shoulder": table["left_shoulder"],
        "right hip": table["right_hip"],
        "MPJPE (mm)": table["mpjpe_mm"].round().astype(int),
    })  # fmt: skip
    rows = ["ours" if m == "mvrvm" else "" for m in table["method"]]
    html.write_page(path, "Generalisation: each group held out in turn", html.image(png)
                    + html.caption(generalisation_caption(table))
                    + html.table(shown, rows, raw_columns=("full body, 42 angles", "full body, varying angles")))
