"""``voxpose report-summary``: the report's first page (Tables 1 and 2, Figure 4, the claims, the run)."""

import os

from voxpose.cli.common import CONFIG_HASH_VARIABLE, positive_integer

NAME = "report-summary"
HELP = "the report's summary page: the paper's tables and Figure 4 beside ours, claims, configuration, versions"


def add_arguments(p):
    for name in ("table1", "table2", "figure4", "claims"):
        p.add_argument(f"--{name}", required=True, help=f"{name}.csv")
    p.add_argument("--figure4-png", required=True)
    p.add_argument("--config-hash", default=os.environ.get(CONFIG_HASH_VARIABLE),
                   help=f"the run's configuration hash (default: ${CONFIG_HASH_VARIABLE}, the workflow's)")
    p.add_argument("--data-set", required=True, help="what the motions are")
    p.add_argument("--logs", default="results/logs", help="the job logs (the wall time starts at the oldest)")
    p.add_argument("--bootstrap", type=positive_integer, default=1000, help="replicates the tables' intervals used")
    p.add_argument("-o", "--output", required=True, help="summary.html")


def run(args):
    from pathlib import Path

    import pandas as pd

    from voxpose.evaluation.paper_claims import overall
    from voxpose.evaluation.summary_page import summary_page
    from voxpose.evaluation.tables import read_csv

    claims = read_csv(args.claims)
    summary_page(
        args.output,
        table1=read_csv(args.table1),
        table2=read_csv(args.table2),
        figure4=read_csv(args.figure4),
        figure4_png=args.figure4_png,
        claims=claims,
        verdicts=overall(claims) if len(claims) else pd.DataFrame(),
        config_hash=args.config_hash,
        data_set=args.data_set,
        log_dir=args.logs,
        repo=Path.cwd(),
        n_boot=args.bootstrap,
    )
