"""``voxpose figure4``: Figure 4 (the cross-validation sweeps of Section 6) from the runs' summaries."""

from voxpose.cli.common import add_table_csv, list_of, parse_json, row, write_table_meta

NAME = "figure4"
HELP = "Figure 4 from the cross-validation sweep summaries"


def add_arguments(p):
    p.add_argument("--runs", required=True, help="JSON list of [sweep, value, summary.json]")
    p.add_argument("--png", required=True)
    p.add_argument("--pdf", required=True)
    p.add_argument("--html", help="the figure, its caption and its table as a page for the report")
    add_table_csv(p)


def run(args):
    from voxpose.evaluation import figures
    from voxpose.io.atomic import atomic_path

    runs = parse_json(args.runs, "--runs", list_of(row("string", ["number", "string"], "string")))
    table = figures.figure4_table(runs)
    with atomic_path(args.csv) as tmp:
        table.to_csv(tmp, index=False)
    fig = figures.figure4(table)
    figures.save(fig, args.png, "png")
    figures.save(fig, args.pdf, "pdf")
    if args.html:
        from voxpose.evaluation.figure_pages import figure4_page

        figure4_page(table, args.png, args.html)
    write_table_meta(args)
