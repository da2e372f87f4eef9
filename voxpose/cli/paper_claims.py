"""``voxpose paper-claims``: the claims the paper draws from Tables 1 and 2, held or not on this run's data."""

from voxpose.cli.common import add_table_csv, write_table_meta
from voxpose.cli.table1 import add_bootstrap

NAME = "paper-claims"
HELP = "the paper's claims (MPPCA vs K-means, vs Agarwal & Triggs, five types) tested with paired comparisons"
RUNS = ("table1_mppca", "table1_kmeans", "table1_at_one", "table1_at_all", "table2_mppca", "table2_kmeans")


def add_arguments(p):
    p.add_argument(
        "--run",
        nargs=2,
        action="append",
        required=True,
        metavar=("NAME", "PREDICTIONS"),
        help=f"a run's predictions.h5; NAME one of {', '.join(RUNS)}",
    )
    p.add_argument("--data-set", required=True, help="what the motions are (shown beside every verdict)")
    add_bootstrap(p)
    add_table_csv(p)
    p.add_argument("--html", required=True)


def run(args):
    from voxpose.errors import VoxposeError
    from voxpose.evaluation import paper_claims, table_pages
    from voxpose.io.atomic import atomic_path

    runs = dict(args.run)
    unknown = sorted(set(runs) - set(RUNS))
    missing = sorted({"table1_mppca", "table1_kmeans", "table2_mppca"} - set(runs))
    if unknown or missing:
        raise VoxposeError(f"--run: unknown {unknown} / missing {missing} (known: {', '.join(RUNS)})")
    df = paper_claims.claims(runs, args.data_set, args.bootstrap, args.seed)
    with atomic_path(args.csv) as tmp:
        df.to_csv(tmp, index=False)
    table_pages.claims_page(df, paper_claims.overall(df), args.html, args.bootstrap)
    write_table_meta(args)
