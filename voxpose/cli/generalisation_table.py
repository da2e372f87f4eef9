"""``voxpose generalisation-table``: the subject-held-out results, one row per (held-out group, method), as CSV,
Markdown and a figure."""

from voxpose.cli.common import add_table_csv, list_of, parse_json, write_table_meta
from voxpose.cli.table1 import add_bootstrap

NAME = "generalisation-table"
HELP = "errors per held-out group and method (CSV + Markdown + figure)"


def add_arguments(p):
    p.add_argument(
        "--runs",
        required=True,
        help="JSON list of [group, MPPCA summary.json, K-means summary.json], or with the two runs' "
        "predictions.h5 after them (then with 95 %% intervals)",
    )
    add_bootstrap(p)
    add_table_csv(p)
    p.add_argument("--html", help="the table as a page for the report")
    p.add_argument("--md", required=True)
    p.add_argument("--png", required=True)


def run(args):
    from voxpose.errors import VoxposeError
    from voxpose.evaluation.figure_pages import generalisation_page
    from voxpose.evaluation.generalisation import generalisation_figure, generalisation_table, with_intervals
    from voxpose.evaluation.tables import read_summary, write_table

    entry = {"type": "array", "minItems": 3, "maxItems": 5, "items": {"type": "string"}}
    runs = parse_json(args.runs, "--runs", list_of(entry))
    if len({len(r) for r in runs}) != 1 or len(runs[0]) not in (3, 5):
        raise VoxposeError("--runs: every entry needs 3 items (group and two summaries) or 5 (and two predictions)")
    groups = [(name, read_summary(mppca), read_summary(kmeans)) for name, mppca, kmeans, *_ in runs]
    df = generalisation_table(groups)
    if len(runs[0]) == 5:
        df = with_intervals(df, {r[0]: (r[3], r[4]) for r in runs}, args.bootstrap, args.seed)
    write_table(df, args.csv, args.md, "Generalisation: each group held out in turn, RMS error (degrees) and "
                "joint position error (mm) on the held-out group")  # fmt: skip
    generalisation_figure(df, args.png)
    if args.html:
        generalisation_page(df, args.png, args.html)
    write_table_meta(args)
