"""``voxpose table2``: Table 2 (Section 6, one regressor for five motion types) from a run summary."""

from voxpose.cli.common import add_table_csv, write_table_meta

NAME = "table2"
HELP = "Table 2 from a run summary (CSV + Markdown)"


def add_arguments(p):
    p.add_argument("--summary", required=True, help="summary.json of the five-type regressor")
    add_table_csv(p)
    p.add_argument("--md", required=True)


def run(args):
    from voxpose.evaluation.tables import read_summary, table2, write_table

    df = table2(read_summary(args.summary))
    write_table(df, args.csv, args.md, "Table 2: one regressor for five motion types, RMS error (degrees)")
    write_table_meta(args)
