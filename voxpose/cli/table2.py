"""``voxpose table2``: Table 2 (Section 6, one regressor for five motion types) from a run."""

from voxpose.cli.common import add_table_csv, write_table_meta
from voxpose.cli.table1 import add_bootstrap, add_run

NAME = "table2"
HELP = "Table 2 from a run (CSV + Markdown + HTML), with bootstrap intervals"


def add_arguments(p):
    add_run(p, "--run", "the five-type regressor")
    add_bootstrap(p)
    add_table_csv(p)
    p.add_argument("--md", required=True)
    p.add_argument("--html", help="the table as a page for the report")


def run(args):
    from voxpose.evaluation import table_pages
    from voxpose.evaluation.tables import read_summary, table2, write_table
    from voxpose.evaluation.uncertainty import read_test_frames

    summary, predictions = args.run
    frames = (read_test_frames(predictions), read_test_frames(predictions, "mean_pose"))
    df = table2(read_summary(summary), frames, args.bootstrap, args.seed)
    write_table(df, args.csv, args.md, "Table 2: one regressor for five motion types, RMS error (degrees)")
    if args.html:
        table_pages.table2_page(df, args.html, table_pages.table2_caption(df, args.bootstrap))
    write_table_meta(args)
