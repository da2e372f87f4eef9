"""``voxpose camera-figure`` and ``voxpose robustness-figure``: the measured claims' figures and tables.

One module for both: they differ only in the table and drawing functions of ``voxpose.evaluation.claims_figures``.
"""

from voxpose.cli.common import add_table_csv, list_of, parse_json, record, write_table_meta


def add_arguments(p):
    p.add_argument("--runs", required=True, help="JSON list of runs (see voxpose/evaluation/claims_figures.py)")
    p.add_argument("--png", required=True)
    p.add_argument("--html", help="the figure, its caption and its table as a page for the report")
    add_table_csv(p)


def _write(args, which: str) -> None:
    from voxpose.evaluation import claims_figures, figure_pages, figures
    from voxpose.io.atomic import atomic_path

    table_of, draw, page, keys = {
        "cameras": (claims_figures.camera_table, claims_figures.camera_figure, figure_pages.camera_page,
                    ("rig", "cameras", "series")),
        "robustness": (claims_figures.robustness_table, claims_figures.robustness_figure,
                       figure_pages.robustness_page, ("kind", "level", "carving")),
    }[which]  # fmt: skip
    table = table_of(parse_json(args.runs, "--runs", list_of(record(*keys, "summary"))))
    with atomic_path(args.csv) as tmp:
        table.to_csv(tmp, index=False)
    figures.save(draw(table), args.png, "png")
    if args.html:
        page(table, args.png, args.html)
    write_table_meta(args)


def run_cameras(args):
    _write(args, "cameras")


def run_robustness(args):
    _write(args, "robustness")
