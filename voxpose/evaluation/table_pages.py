"""Table 1 and Table 2 as the report shows them: each measured row with its 95 % interval, the paper's row under
it and the difference (ours - paper), the full body over 42 and over the varying angles side by side.

Built from the tables' DataFrames (``voxpose.evaluation.tables``), the same numbers as the CSV files.
"""

import pandas as pd

from voxpose.evaluation import html
from voxpose.evaluation.tables import FULL_VARYING, MEAN_POSE, MEAN_POSE_VARYING, TABLE1_COLUMNS, TABLE2_COLUMNS

_ERRORS = ["full body", FULL_VARYING, *list(TABLE1_COLUMNS.values())[1:]]
# the paper's row each measured row is compared with
_PAPER_OF = {"Agarwal & Triggs-style": "Agarwal & Triggs [1]"}


def _shown(row, col) -> str:
    value = row.get(col, float("nan"))
    if value != value:
        return ""
    low = row.get(f"{col} low", float("nan"))
    return html.with_interval(value, low, row[f"{col} high"]) if low == low else html.cell(float(value))


def table1_rows(df: pd.DataFrame) -> tuple[pd.DataFrame, list]:
    """Display rows of Table 1 (method, source, errors with intervals, mean pose, frames) and their CSS classes."""
    paper = {r["method"]: r for _, r in df[df["source"] != "voxpose (measured)"].iterrows()}
    rows, classes = [], []
    for _, r in df.iterrows():
        if r["source"] != "voxpose (measured)":
            continue
        varying = r.get("varying angles", float("nan"))
        head = {"method": r["method"], "source": "voxpose"}
        cells = {
            c
            if c != FULL_VARYING
            else f"full body, {int(varying) if varying == varying else '?'} varying angles": _shown(r, c)
            for c in _ERRORS
        }
        mean = f"{r[MEAN_POSE]:.1f}" + (f" / {r[MEAN_POSE_VARYING]:.1f}" if MEAN_POSE_VARYING in r else "")
        rows.append(head | cells | {"mean pose (42 / varying)": mean, "test frames": str(int(r["test frames"]))})
        classes.append("ours")
        key = next((v for k, v in _PAPER_OF.items() if r["method"].startswith(k)), r["method"])
        if key in paper:
            p = paper[key]
            label = "paper" if p["source"] == "paper" else "quoted by the paper"
            values = list(cells)
            rows.append(
                {"method": key, "source": label}
                | {
                    c: html.cell(float(p[c])) if c in p else ""
                    for c in ["full body", *list(TABLE1_COLUMNS.values())[1:]]
                }
                | {values[1]: "", "test frames": "418"}
            )
            classes.append("paper")
            diff = {c: html.cell(float(r[c] - p[c])) for c in ["full body", *list(TABLE1_COLUMNS.values())[1:]]}
            rows.append({"method": "", "source": "difference (voxpose - paper)"} | diff | {values[1]: ""})
            classes.append("diff")
    out = pd.DataFrame(rows).astype(object)
    out = out.where(out.notna(), "")
    return out, classes


def table2_rows(df: pd.DataFrame) -> pd.DataFrame:
    """Display rows of Table 2: one per motion type (voxpose with interval, paper, difference, mean pose, frames),
    then the five types together."""
    ours = df[df["source"] == "voxpose (measured)"].iloc[0]
    paper = df[df["source"] == "paper"].iloc[0]
    rows = []
    for col in TABLE2_COLUMNS.values():
        rows.append(
            {
                "motion type": col,
                "voxpose": _shown(ours, col),
                "paper": html.cell(float(paper[col])),
                "difference (voxpose - paper)": html.cell(float(ours[col] - paper[col])),
                "mean pose": html.cell(float(ours.get(f"{col} mean pose", float("nan")))),
                "test frames": html.cell(int(ours[f"{col} frames"])) if f"{col} frames" in ours else "",
            }
        )
    if "full body" in ours:
        varying = int(ours["varying angles"])
        for col, label in (
            ("full body", "all five types, 42 angles"),
            (FULL_VARYING, f"all five types, {varying} varying angles"),
        ):
            mean = ours[MEAN_POSE if col == "full body" else MEAN_POSE_VARYING]
            rows.append(
                {
                    "motion type": label,
                    "voxpose": _shown(ours, col),
                    "paper": "",
                    "difference (voxpose - paper)": "",
                    "mean pose": html.cell(float(mean)),
                    "test frames": html.cell(int(ours["test frames"])),
                }
            )
    return pd.DataFrame(rows)


def model_rows(df: pd.DataFrame) -> pd.DataFrame:
    """Table 2's model: relevance vectors, training frames, pose dimensions, test frames; voxpose and paper."""
    cols = ["source", "relevance vectors", "training frames", "pose dims", "test frames"]
    return df[cols].astype({c: int for c in cols[1:]})


def table1_page(df: pd.DataFrame, path, caption: str) -> None:
    rows, classes = table1_rows(df)
    raw = [c for c in rows.columns if c not in ("method", "source")]
    html.write_page(
        path,
        "Table 1: RMS joint-angle error (degrees) on the held-out spiral walk",
        html.table(rows, classes, raw) + html.caption(caption),
    )


def table2_page(df: pd.DataFrame, path, caption: str) -> None:
    rows = table2_rows(df)
    body = html.table(rows, None, [c for c in rows.columns if c != "motion type"]) + html.table(model_rows(df))
    html.write_page(
        path, "Table 2: one regressor for five motion types, RMS error (degrees)", body + html.caption(caption)
    )


def _row(df, method):
    return df[(df["method"] == method) & (df["source"] == "voxpose (measured)")].iloc[0]


def table1_caption(df: pd.DataFrame, n_boot: int) -> str:
    """What Table 1 shows, on which frames, and what its numbers say."""
    ours = df[df["source"] == "voxpose (measured)"].iloc[0]
    varying = int(ours.get("varying angles", 42))
    text = (
        f"Each method's regressor was trained without the test motion and tested on its {int(ours['test frames'])}"
        f" frames (the paper: 418 frames of spiral walking). Errors are Eq. 6: for each angle the RMS over the"
        f" test frames of the wrapped difference, averaged over the paper's 42 angles ('full body') and over"
        f" the {varying} angles whose true value moves in the test frames; an angle that never moves is"
        f" predicted exactly and would lower the 42-angle mean. Brackets: 95 % bootstrap intervals ({n_boot}"
        f" replicates, test motions resampled, then their frames; with one test motion the frames' correlation"
        f" in time makes them too narrow). Under each measured row, the paper's numbers and the difference."
        f" 'Mean pose' predicts the mean training pose for every frame: a regressor is useful only below it."
        f" Here MPPCA + MVRVM gives {ours['full body']:.1f} over 42 angles ({ours.get(FULL_VARYING, float('nan')):.1f}"
        f" over {varying}) against {ours[MEAN_POSE]:.1f} for the mean pose; the paper reports 5.2."
    )
    return text


def table2_caption(df: pd.DataFrame, n_boot: int) -> str:
    """What Table 2 shows, on which frames, and what its numbers say."""
    ours = df[df["source"] == "voxpose (measured)"].iloc[0]
    worst = max(TABLE2_COLUMNS.values(), key=lambda c: ours[c] if ours[c] == ours[c] else -1)
    text = (
        f"One MVRVM regressor trained on all five motion types at once ({int(ours['training frames'])} training"
        f" frames, {int(ours['relevance vectors'])} relevance vectors, {int(ours['pose dims'])}-d pose space; the"
        f" paper: 1744, 418, 8-d) tested on held-out motions of each type ({int(ours['test frames'])} frames;"
        f" the paper: 1411). Per type: Eq. 6 over 42 angles with its 95 % bootstrap interval ({n_boot}"
        f" replicates: test motions, then frames), the paper's number, the difference and the mean training"
        f" pose's error on the same frames. The hardest type here is {worst} ({ours[worst]:.1f})."
    )
    return text


def claims_rows(df: pd.DataFrame) -> tuple[pd.DataFrame, dict]:
    """Display rows of the claims: each comparison with its interval, p-values and verdict (and the verdicts'
    CSS classes)."""
    rows = pd.DataFrame(
        {
            "claim": [c if i == 0 or c != df["claim"].iloc[i - 1] else "" for i, c in enumerate(df["claim"])],
            "test set": df["test set"],
            "comparison (A vs B)": df["comparison"],
            "frames": df["test frames"].astype(int),
            "error A": df["error A"],
            "error B": df["error B"],
            "A - B [95 %]": [
                html.with_interval(d, lo, hi)
                for d, lo, hi in zip(df["difference A - B"], df["difference low"], df["difference high"], strict=True)
            ],
            "p (bootstrap)": [f"{p:.3g}" if p > 0 else "< 0.001" for p in df["p (paired bootstrap)"]],
            "p (Wilcoxon)": [f"{p:.2g}" for p in df["p (Wilcoxon, per frame)"]],
            "verdict": df["verdict"],
        }
    )
    return rows, {"verdict": [v.replace(" ", "") for v in df["verdict"]]}


def claims_caption(df: pd.DataFrame, n_boot: int) -> str:
    data = df["data set"].iloc[0] if len(df) else ""
    return (
        f"Data set: {data}. Each row compares method A with method B on the same test frames by the"
        f" full-body error (Eq. 6, 42 angles). 'A - B' is the difference with its 95 % interval from a paired"
        f" bootstrap ({n_boot} replicates: test motions, then frames, the same draws for both methods); p"
        f" (bootstrap) is its two-sided p-value and p (Wilcoxon) a signed-rank test on the per-frame errors."
        f" Verdict: held (A lower, the whole interval below zero), reversed (the interval above zero: B is"
        f" better on this data), not shown (the interval contains zero). The verdicts hold for this data set"
        f" only: run with bvh_dir for the real motion capture."
    )


def claims_page(df: pd.DataFrame, summary: pd.DataFrame, path, n_boot: int) -> None:
    rows, classes = claims_rows(df)
    verdicts = summary.rename(columns={"comparisons": "comparisons"})
    body = (
        html.table(verdicts, cell_classes={"verdict": [v.replace(" ", "") for v in summary["verdict"]]})
        + html.table(rows, raw_columns=["A - B [95 %]"], cell_classes=classes)
        + html.caption(claims_caption(df, n_boot))
    )
    html.write_page(path, "The paper's claims, tested on this run's data", body)
