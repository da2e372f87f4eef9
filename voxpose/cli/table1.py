"""``voxpose table1``: Table 1 (Section 6) from the run summaries, our rows beside the paper's (CSV + Markdown)."""

from voxpose.cli.common import add_table_csv, write_table_meta

NAME = "table1"
HELP = "Table 1 from run summaries (CSV + Markdown)"


def add_arguments(p):
    p.add_argument("--ours", required=True, help="summary.json of MPPCA + MVRVM")
    p.add_argument("--kmeans", required=True, help="summary.json of K-means + MVRVM")
    p.add_argument("--at-one", help="summary.json of the Agarwal & Triggs-style run on one camera")
    p.add_argument("--at-all", help="summary.json of the Agarwal & Triggs-style run on all cameras")
    add_table_csv(p)
    p.add_argument("--md", required=True)


def run(args):
    from voxpose.evaluation.tables import AT_ALL_LABEL, AT_ONE_LABEL, read_summary, table1, write_table

    at = {label: read_summary(path) for label, path in ((AT_ONE_LABEL, args.at_one), (AT_ALL_LABEL, args.at_all))
          if path}  # fmt: skip
    df = table1(read_summary(args.ours), read_summary(args.kmeans), at)
    write_table(df, args.csv, args.md, "Table 1: RMS error (degrees) on the held-out spiral walk")
    write_table_meta(args)
