"""The report's first page: Table 1, Table 2 and Figure 4 with the paper beside ours, the claims' verdicts and
the run (data set, configuration hash, wall time, software versions)."""

import pandas as pd

from voxpose.evaluation import html, run_info, table_pages
from voxpose.evaluation.figures import PAPER_CHOICE, SWEEP_TITLES
from voxpose.provenance import provenance


def figure4_rows(f4: pd.DataFrame) -> pd.DataFrame:
    """Per sweep: the paper's choice, our error there, our best setting and its error, the mean pose's error."""
    rows = []
    for sweep, title in SWEEP_TITLES.items():
        s = f4[f4["sweep"] == sweep]
        if s.empty:
            continue
        values = [str(v) for v in s["value"]]
        at = [str(v) == str(PAPER_CHOICE[sweep]) or _close(v, PAPER_CHOICE[sweep]) for v in s["value"]]
        best = s["validation error (deg)"].idxmin()
        rows.append(
            {
                "parameter": title,
                "paper's choice": _label(sweep, PAPER_CHOICE[sweep]),
                "voxpose at the paper's choice": html.cell(float(s["validation error (deg)"][at].iloc[0]))
                if any(at)
                else "not swept",
                "voxpose best": f"{_label(sweep, s['value'][best])}: {s['validation error (deg)'][best]:.2f}",
                "range over the sweep": f"{s['validation error (deg)'].min():.2f} - "
                f"{s['validation error (deg)'].max():.2f} ({len(values)} settings)",
                "mean pose": html.cell(float(s["mean-pose baseline (deg)"].mean())),
            }
        )
    return pd.DataFrame(rows)


def _close(value, choice) -> bool:
    try:
        return abs(float(value) - float(choice)) < 1e-3
    except (TypeError, ValueError):
        return False


def _label(sweep, value) -> str:
    return f"{float(value):.3f} h_sub" if sweep == "r_max" else str(value)


def _run_table(config_hash: str, data_set: str, log_dir, repo) -> pd.DataFrame:
    seconds = run_info.wall_time_s(log_dir)
    made = provenance(config_hash, repo)
    rows = {
        "data set": data_set,
        "configuration hash (SHA-256 of the config, sorted keys)": made["config_hash"],
        "commit": made["git_commit"],
        "wall time (first job's log to this page)": f"{seconds / 60:.1f} min" if seconds == seconds else "unknown",
    }
    rows |= {"version: voxpose": made["voxpose"], "version: python": made["python"]}
    rows |= {f"version: {k}": v for k, v in made["packages"].items()}
    return pd.DataFrame({"": list(rows), "value": list(rows.values())})


def summary_page(
    path,
    *,
    table1: pd.DataFrame,
    table2: pd.DataFrame,
    figure4: pd.DataFrame,
    figure4_png,
    claims: pd.DataFrame,
    verdicts: pd.DataFrame,
    config_hash: str,
    data_set: str,
    log_dir,
    repo,
    n_boot: int,
) -> None:
    t1, classes = table_pages.table1_rows(table1)
    t2 = table_pages.table2_rows(table2)
    f4 = figure4_rows(figure4)
    body = [
        html.caption(
            "voxpose reproduces Sun, Bray, Thayananthan, Yuan & Torr, 'Regression-Based Human Motion Capture"
            " From Voxel Data' (BMVC 2006). Errors in degrees (Eq. 6); brackets: 95 % bootstrap intervals."
            " The other pages of this report hold every table and figure with its caption and CSV."
        ),
        "<h2>Table 1: held-out spiral walk</h2>",
        html.table(t1, classes, [c for c in t1.columns if c not in ("method", "source")]),
        html.caption(table_pages.table1_caption(table1, n_boot)),
        "<h2>Table 2: one regressor for five motion types</h2>",
        html.table(t2, None, [c for c in t2.columns if c != "motion type"]),
        html.table(table_pages.model_rows(table2)),
        "<h2>Figure 4: cross-validation of the free parameters</h2>",
        html.table(f4),
        html.image(figure4_png),
        "<h2>The paper's claims on this data</h2>",
        html.table(verdicts, cell_classes={"verdict": [v.replace(" ", "") for v in verdicts["verdict"]]}),
        html.caption(table_pages.claims_caption(claims, n_boot)),
        "<h2>This run</h2>",
        html.table(_run_table(config_hash, data_set, log_dir, repo)),
    ]
    html.write_page(path, "Summary: the paper's tables and Figure 4, ours beside the paper's", "\n".join(body))
