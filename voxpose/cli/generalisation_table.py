"""``voxpose generalisation-table``: the subject-held-out results, one row per (held-out group, method), as CSV,
Markdown and a figure."""

from voxpose.cli.common import add_table_csv, list_of, parse_json, row, write_table_meta

NAME = "generalisation-table"
HELP = "errors per held-out group and method (CSV + Markdown + figure)"


def add_arguments(p):
    p.add_argument("--runs", required=True, help="JSON list of [group, MPPCA summary.json, K-means summary.json]")
    add_table_csv(p)
    p.add_argument("--md", required=True)
    p.add_argument("--png", required=True)


def run(args):
    from voxpose.evaluation.generalisation import generalisation_figure, generalisation_table
    from voxpose.evaluation.tables import read_summary, write_table

    runs = parse_json(args.runs, "--runs", list_of(row("string", "string", "string")))
    groups = [(name, read_summary(mppca), read_summary(kmeans)) for name, mppca, kmeans in runs]
    df = generalisation_table(groups)
    write_table(df, args.csv, args.md, "Generalisation: each group held out in turn, RMS error (degrees) and "
                "joint position error (mm) on the held-out group")  # fmt: skip
    generalisation_figure(df, args.png)
    write_table_meta(args)
