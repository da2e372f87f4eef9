"""``voxpose table1``: Table 1 (Section 6) from the runs, our rows beside the paper's (CSV, Markdown and HTML)."""

from voxpose.cli.common import add_table_csv, positive_integer, seed, write_table_meta

NAME = "table1"
HELP = "Table 1 from runs (CSV + Markdown + HTML), with bootstrap intervals"


def add_run(p, flag: str, what: str, required: bool = True):
    p.add_argument(
        flag,
        nargs=2,
        metavar=("SUMMARY", "PREDICTIONS"),
        required=required,
        help=f"summary.json and predictions.h5 of {what}",
    )


def add_bootstrap(p):
    p.add_argument("--bootstrap", type=positive_integer, default=1000,
                   help="bootstrap replicates of the 95 %% intervals")
    p.add_argument("--seed", type=seed, default=0, help="seed of the bootstrap (the config's seed)")


def add_arguments(p):
    add_run(p, "--ours", "MPPCA + MVRVM")
    add_run(p, "--kmeans", "K-means + MVRVM")
    add_run(p, "--at-one", "the Agarwal & Triggs-style run on one camera", required=False)
    add_run(p, "--at-all", "the Agarwal & Triggs-style run on all cameras", required=False)
    add_bootstrap(p)
    add_table_csv(p)
    p.add_argument("--md", required=True)
    p.add_argument("--html", help="the table as a page for the report")


def run(args):
    from voxpose.evaluation import table_pages
    from voxpose.evaluation.tables import (
        AT_ALL_LABEL,
        AT_ONE_LABEL,
        KMEANS_LABEL,
        MEAN_POSE_LABEL,
        OURS_LABEL,
        read_summary,
        table1,
        write_table,
    )
    from voxpose.evaluation.uncertainty import read_test_frames

    runs = {OURS_LABEL: args.ours, KMEANS_LABEL: args.kmeans, AT_ONE_LABEL: args.at_one, AT_ALL_LABEL: args.at_all}
    runs = {label: paths for label, paths in runs.items() if paths}
    frames = {label: (read_test_frames(p), read_test_frames(p, "mean_pose")) for label, (_, p) in runs.items()}
    frames[MEAN_POSE_LABEL] = (frames[OURS_LABEL][1], frames[OURS_LABEL][1])
    summaries = {label: read_summary(s) for label, (s, _) in runs.items()}
    at = {label: summaries[label] for label in (AT_ONE_LABEL, AT_ALL_LABEL) if label in summaries}
    df = table1(summaries[OURS_LABEL], summaries[KMEANS_LABEL], at, frames, args.bootstrap, args.seed)
    write_table(df, args.csv, args.md, "Table 1: RMS error (degrees) on the held-out spiral walk")
    if args.html:
        table_pages.table1_page(df, args.html, table_pages.table1_caption(df, args.bootstrap))
    write_table_meta(args)
