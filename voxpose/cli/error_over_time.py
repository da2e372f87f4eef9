"""``voxpose error-over-time``: the per-frame error along the test motions."""

from voxpose.cli.common import add_output, named_paths

NAME = "error-over-time"
HELP = "per-frame error along the test motions"


def add_arguments(p):
    p.add_argument("--predictions", action="append", required=True, help="NAME=predictions.h5 (repeatable)")
    add_output(p)


def run(args):
    from voxpose.evaluation import figures
    from voxpose.io.hdf5 import read_per_motion

    series = {}
    for title, path in named_paths(args.predictions, "--predictions"):
        motions, _ = read_per_motion(path, "predictions")
        series[title] = {name: p["frame_error_mvrvm"] for name, p in motions.items()}
    figures.save(figures.error_over_time(series), args.output, "png")
