"""``voxpose readme-tables``: the README's result tables, generated from ``results/tables``."""

NAME = "readme-tables"
HELP = "the README's result tables from results/tables (print, or rewrite the README's generated block)"


def add_arguments(p):
    p.add_argument("--tables", default="results/tables", help="folder with table1.csv, table2.csv, claims.csv")
    p.add_argument("--readme", help="rewrite this README's generated block in place (default: print the tables)")
    p.add_argument("--block", default="", metavar="NAME",
                   help="the README block to rewrite: none for the default run's, e.g. 'real' for the real-data run's")


def run(args):
    from pathlib import Path

    from voxpose.errors import VoxposeError
    from voxpose.evaluation.readme_tables import markdown, replace_block
    from voxpose.io.atomic import atomic_path

    text = markdown(args.tables)
    if not args.readme:
        print(text)
        return
    try:
        readme = Path(args.readme).read_text()
    except OSError as err:
        raise VoxposeError(f"{args.readme}: cannot read ({err})") from None
    with atomic_path(args.readme) as tmp:
        tmp.write_text(replace_block(readme, text, args.readme, args.block))
