"""``voxpose experiment-table``: one experiment's results, one row per (test set, method), as CSV and Markdown."""

from voxpose.cli.common import add_table_csv, write_table_meta

NAME = "experiment-table"
HELP = "an experiment's errors per test set and method (CSV + Markdown)"


def add_arguments(p):
    p.add_argument("--name", required=True, help="the experiment's name (the table's title)")
    p.add_argument(
        "--test-set", nargs=3, action="append", required=True, metavar=("SET", "MPPCA", "KMEANS"),
        help="a test set's name and the summary.json of its MPPCA and K-means runs (repeatable)",
    )  # fmt: skip
    add_table_csv(p)
    p.add_argument("--md", required=True)
    p.add_argument("--html", help="the table as a page for the report")


def run(args):
    from voxpose.errors import VoxposeError
    from voxpose.evaluation.tables import experiment_table, read_summary, write_table

    names = [name for name, _, _ in args.test_set]
    if len(set(names)) != len(names):
        raise VoxposeError(f"--test-set: a test set is named twice ({', '.join(names)})")
    sets = {name: (read_summary(mppca), read_summary(kmeans)) for name, mppca, kmeans in args.test_set}
    title = f"Experiment {args.name}: RMS error (degrees) and joint position error (mm) per test set"
    df = experiment_table(sets)
    write_table(df, args.csv, args.md, title)
    if args.html:
        from voxpose.evaluation import html

        html.write_page(args.html, title, html.table(df))
    write_table_meta(args)
