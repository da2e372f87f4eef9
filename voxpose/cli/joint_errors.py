"""``voxpose joint-errors``: bar chart of the error per joint of one or more runs."""

from voxpose.cli.common import add_output, named_paths

NAME = "joint-errors"
HELP = "bar chart of the error per joint"


def add_arguments(p):
    p.add_argument("--summary", action="append", required=True, help="NAME=summary.json (repeatable)")
    add_output(p)


def run(args):
    from voxpose.evaluation import figures

    figures.save(
        figures.joint_errors(figures.summaries_from(named_paths(args.summary, "--summary"))), args.output, "png"
    )
